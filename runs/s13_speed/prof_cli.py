"""Profile a ``liquidamp`` command for at most SECONDS, keeping the profile if it is cut.

``PYTHONPATH=. python runs/s13_speed/prof_cli.py SECONDS OUT.prof diagnose CAL --validate VAL
--json OUT.json``: runs ``python -m liquidamp ARGS`` in-process under cProfile; after
SECONDS the run is interrupted and the profile so far written (``timeout`` would lose it).
"""

import cProfile
import signal
import sys
import time


class _Cut(BaseException):
    pass


def _alarm(signum, frame):
    raise _Cut()


if __name__ == "__main__":
    seconds, out, args = int(sys.argv[1]), sys.argv[2], sys.argv[3:]
    from liquidamp.cli import main

    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(seconds)
    prof = cProfile.Profile()
    t0 = time.perf_counter()
    rc = "cut"
    prof.enable()
    try:
        rc = main(args)
    except _Cut:
        pass
    except SystemExit as exc:
        rc = exc.code
    finally:
        prof.disable()
        prof.dump_stats(out)
    print(f"prof_cli: rc {rc} wall {time.perf_counter() - t0:.1f} s", file=sys.stderr)
