"""Compile what a long command will need later in a second process, while it works.

Numba compiles on one core, and a first run of the demo is mostly
compiling (about 40 s of CPU).  The work splits into families used one after
the other (the case study's base-model integrators, the diagnosis's
integrators with effects, the lag section's rotor kernel and two-frequency
harmonic balance): :class:`Warmer` starts ``python -m liquidamp._warm`` on
the later families (when a core is idle: :func:`spare_core`), which compiles
them into numba's on-disk cache while the command compiles and runs the
earlier ones; numba loads a kernel from the
cache when it is first called, so the command then finds it ready.  A marker
file per family says when it is done; :meth:`Warmer.wait` waits for it rather
than compiling the same code twice.  If the helper fails or is not started
(the cache already holds the kernels), the command compiles as before: the
results do not depend on it.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["Warmer", "FAMILIES", "warm", "spare_core"]

#: Family -> (words for the progress line, kernel files whose cache entries it writes).
FAMILIES = {
    "effects": ("the time integrators with add-on effects",
                ("coupled/_kernels.py", "integrate-")),
    "lag": ("the rotor kernel and the two-frequency harmonic balance",
            ("coupled/_rotor_kernel.py", "rotor_integrate-")),
}

_ROOT = Path(__file__).resolve().parents[1]


def _cached(family: str) -> bool:
    """Whether numba's cache already holds the family's main kernel (then no helper)."""
    from liquidamp._numba_cache import cache_dir

    rel, prefix = FAMILIES[family][1]
    src = _ROOT / "liquidamp" / rel
    where = cache_dir(src)
    return bool(where and any(where.glob(f"{src.stem}.{prefix}*.nbi")))


def warm(family: str) -> None:
    """Run a small case of ``family`` (compiling its kernels as the command will call them)."""
    if family == "effects":
        from liquidamp.analysis.measured.diagnosis import bundled_records
        from liquidamp.analysis.measured.record_model import simulate_record
        from liquidamp.analysis.measured.records import read_record
        from liquidamp.device.effects import SmoothFriction, with_effects
        from liquidamp.device.models import get_model
        from liquidamp.device.presets import preset
        from liquidamp.options import resolve_options

        rec = read_record(bundled_records()["demo_3Hz_3mm"]).trimmed(1.0)
        model = with_effects(get_model("full"), SmoothFriction(20.0))
        simulate_record(model, preset("paper_calibrated"), rec,
                        options=resolve_options(None, "fit"))
    elif family == "lag":
        from liquidamp.analysis.stability.lag_sweep import lag_damping_sweep
        from liquidamp.examples.forward_flight_lag_damping import (
            MATCH_AMPLITUDE,
            OMEGA,
            devices,
        )

        blade, devs, _ = devices(names=("paper_calibrated",))
        lag_damping_sweep(blade, OMEGA, devs, (0.0,), lag_amplitudes=(MATCH_AMPLITUDE,))
    else:
        raise KeyError(family)


def spare_core() -> bool:
    """Whether a core is idle (1-minute load average below the core count minus one).

    On a busy machine a second process only competes with the first for the
    same cores (and adds its own imports), so the helper is started only
    when a core would otherwise idle.
    """
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):  # pragma: no cover - no load average here
        return True
    return load < (os.cpu_count() or 1) - 1.0


class Warmer:
    """A helper process compiling ``families`` into the cache; ``wait`` and ``stop`` it.

    Examples
    --------
    >>> w = Warmer([])          # nothing to compile: no process
    >>> w.wait("lag") is None and w.stop() is None
    True
    """

    def __init__(self, families, *, start: bool = True):
        self.families = [f for f in families if f in FAMILIES]
        self.process = None
        self.marks = None
        todo = ([f for f in self.families if not _cached(f)]
                if start and self.families and spare_core() else [])
        if todo:
            self.marks = tempfile.TemporaryDirectory(prefix="liquidamp-warm-")
            env = dict(os.environ)
            env["PYTHONPATH"] = str(_ROOT) + (os.pathsep + env["PYTHONPATH"]
                                              if env.get("PYTHONPATH") else "")
            self.process = subprocess.Popen(
                [sys.executable, "-m", "liquidamp._warm", self.marks.name, *todo],
                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL, env=env)
        self.todo = todo

    def wait(self, family: str, progress=None, timeout: float = 600.0) -> None:
        """Until the helper has compiled ``family`` (or has stopped); tell ``progress``."""
        if self.process is None or family not in self.todo:
            return
        mark = Path(self.marks.name) / f"{family}.done"
        told = False
        t_end = time.monotonic() + timeout
        while not mark.exists() and self.process.poll() is None and time.monotonic() < t_end:
            if not told and progress is not None:
                progress(f"waiting for {FAMILIES[family][0]} (compiling in a second "
                         "process, once; cached) ...")
                told = True
            time.sleep(0.1)

    def stop(self) -> None:
        """End the helper process (if still running) and remove its markers."""
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:  # pragma: no cover - a stuck helper
                self.process.kill()
                self.process.wait()
        if self.marks is not None:
            self.marks.cleanup()
            self.marks = None


def main(argv: list[str]) -> int:
    """``python -m liquidamp._warm DIR FAMILY...``: warm each family, mark it done in DIR."""
    marks, families = Path(argv[0]), argv[1:]
    for family in families:
        try:
            warm(family)
        except Exception:  # noqa: BLE001 - the command compiles it itself then
            pass
        (marks / f"{family}.done").write_text("done")
    return 0


if __name__ == "__main__":  # pragma: no cover - the helper process
    sys.exit(main(sys.argv[1:]))
