"""Cold-start cases of ``liquidamp bench``: what a new user waits for on a fresh install.

Each figure is the wall time of a fresh process (:func:`subprocess.run`
timed with :func:`time.perf_counter`, interpreter start-up included), the
code under test first on ``sys.path``:

``import_seconds``
    ``python -c "import liquidamp"`` (median of several runs).
``help_seconds``
    ``python -m liquidamp --help`` (median).
``argument_error_seconds``
    ``python -m liquidamp simulate --preset no_such_preset`` (an argument
    value error; exit code 2; median).
``demo_first_run_seconds``
    ``python -m liquidamp demo --quiet --out TMP`` with an empty numba cache
    (``NUMBA_CACHE_DIR`` a new temporary directory): every kernel the demo
    needs is compiled (one run: it takes about a minute), with the CPU
    seconds it used and the load average before it;
``demo_warm_seconds``
    the same demo again in a fresh process reusing the cache just written
    (one run).

The demo cases run only without ``quick``; the load average is recorded
because the wall times on a shared two-core machine depend on it.  The
first calls of the compiled routes (:data:`FIRST_CALL_CODE`) are measured
here too.
"""

from __future__ import annotations

import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["cold_start", "fresh_process", "first_call", "FIRST_CALL_CODE"]

#: The directory that holds the ``liquidamp`` package being measured.
_ROOT = str(Path(__file__).resolve().parents[2])


def _env(extra: dict | None = None) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = _ROOT + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH")
                                 else "")
    env.update(extra or {})
    return env


def _timed(argv: list[str], env: dict | None = None, timeout: float = 900.0) -> dict:
    """Wall and CPU seconds of a fresh process running ``argv``; its exit code."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run(argv, capture_output=True, text=True, env=_env(env), cwd=_ROOT,
                         timeout=timeout, check=False)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"seconds": wall, "cpu_seconds": cpu, "returncode": out.returncode,
            "stderr_tail": out.stderr.strip().splitlines()[-1:] if out.returncode else []}


def _median(argv: list[str], runs: int) -> dict:
    times = [_timed(argv) for _ in range(runs)]
    return {"seconds": statistics.median(t["seconds"] for t in times), "runs": runs,
            "returncode": times[-1]["returncode"]}


def cold_start(quick: bool = False, runs: int | None = None, progress=None) -> dict:
    """Fresh-process start-up figures; the demo's first (empty cache) and warm runs.

    Parameters
    ----------
    quick : bool
        Import, ``--help`` and argument-error times only (one run each).
    runs : int, optional
        Runs of each short case (default 5, 1 when quick).
    progress : callable, optional
        ``progress(text)`` before each case.

    Returns
    -------
    dict
        ``import_seconds``, ``help_seconds``, ``argument_error_seconds`` (medians),
        and without ``quick`` ``demo_first_run_seconds``, ``demo_first_run_cpu_seconds``,
        ``demo_warm_seconds``, ``load_average_before_demo``.
    """
    runs = runs or (1 if quick else 5)
    py = sys.executable
    say = progress or (lambda text: None)
    out = {"description": "fresh processes, wall seconds (interpreter start-up included), "
                          "medians of the short cases; the demo once with an empty numba "
                          "cache and once reusing it",
           "cpu_count": os.cpu_count()}
    say("cold start: import")
    out["import_seconds"] = _median([py, "-c", "import liquidamp"], runs)["seconds"]
    say("cold start: --help")
    out["help_seconds"] = _median([py, "-m", "liquidamp", "--help"], runs)["seconds"]
    say("cold start: argument error")
    err = _median([py, "-m", "liquidamp", "simulate", "--preset", "no_such_preset"], runs)
    out["argument_error_seconds"] = err["seconds"]
    out["argument_error_exit_code"] = err["returncode"]
    out["runs"] = runs
    if quick:
        out["demo_note"] = "demo first run not measured (--quick)"
        return out
    with tempfile.TemporaryDirectory(prefix="liquidamp-numba-") as cache, \
            tempfile.TemporaryDirectory(prefix="liquidamp-demo-") as where:
        env = {"NUMBA_CACHE_DIR": cache}
        argv = [py, "-m", "liquidamp", "demo", "--quiet", "--force", "--out", where]
        out["load_average_before_demo"] = list(os.getloadavg())
        say("cold start: demo with an empty compile cache (about a minute)")
        cold = _timed(argv, env)
        say("cold start: demo again, cache reused")
        warm = _timed(argv, env)
    out.update({"demo_first_run_seconds": cold["seconds"],
                "demo_first_run_cpu_seconds": cold["cpu_seconds"],
                "demo_first_run_exit_code": cold["returncode"],
                "demo_warm_seconds": warm["seconds"],
                "demo_warm_cpu_seconds": warm["cpu_seconds"]})
    if cold["returncode"]:
        out["demo_error"] = cold["stderr_tail"]
    return out


# ------------------------------------------------------------ first calls
FIRST_CALL_CODE = {
    "stability_map": "from liquidamp.analysis.bench_maps import _warm; _warm(64)",
    "steady_state_loop": "from liquidamp.analysis.bench import _fast_steady as f; f()",
    "coupled_rotor": ("from liquidamp.analysis.bench import _coupled_setup; "
                      "from liquidamp.coupled.fast_rotor import simulate_rotor; r, d, _ = "
                      "_coupled_setup(); simulate_rotor(r, 27.2, d, 0.1, {'zeta_1': 1e-3})"),
    "dual_frequency": "from liquidamp.analysis.bench import _dual_frequency as f; f()",
    "calibration": ("import tempfile; from liquidamp.analysis.bench import _records, "
                    "_as_record_objects; "
                    "from liquidamp.analysis.measured.calibration import calibrate; "
                    "from liquidamp.device import preset; d = tempfile.mkdtemp(); "
                    "calibrate(_as_record_objects(_records(True), d), "
                    "params=preset('reference'), max_nfev=1)"),
}


def fresh_process(code: str, env_extra: dict | None = None) -> dict:
    """Run ``code`` in a fresh interpreter; time the imports and the first call."""
    script = (
        "import time, json\n"
        "t0 = time.perf_counter()\n"
        "import liquidamp.coupled.testrig, liquidamp.analysis.bench\n"
        "t1 = time.perf_counter()\n"
        f"{code}\n"
        "t2 = time.perf_counter()\n"
        "print(json.dumps({'import_seconds': t1 - t0, 'first_call_seconds': t2 - t1}))\n"
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         env=_env(env_extra), cwd=_ROOT, timeout=600, check=False)
    if out.returncode != 0:
        return {"error": out.stderr.strip().splitlines()[-1] if out.stderr else "failed"}
    return json.loads(out.stdout.strip().splitlines()[-1])


def first_call(cold: bool) -> dict:
    """Compilation with an empty numba cache, then a second fresh process reusing it."""
    code = FIRST_CALL_CODE["steady_state_loop"]
    if not cold:
        warm = fresh_process(code)
        return {"cold_cache": None, "note": "cold-cache compilation not measured (--quick)",
                "cached_seconds": warm.get("first_call_seconds"),
                "cached_import_seconds": warm.get("import_seconds")}
    with tempfile.TemporaryDirectory(prefix="liquidamp-numba-") as d:
        env = {"NUMBA_CACHE_DIR": d}
        cold_run = fresh_process(code, env)
        warm = fresh_process(code, env)
    with tempfile.TemporaryDirectory(prefix="liquidamp-numba-") as d:
        both = fresh_process("from liquidamp.coupled.fast import warm_up; warm_up()",
                              {"NUMBA_CACHE_DIR": d})
    return {
        "description": "steady_state_loop's first call in a fresh process: with an empty "
                       "numba cache (compilation included), then again in a second fresh "
                       "process reusing the cache just written; "
                       "both_kernels_cold_cache_seconds: fast.warm_up() with an empty cache, "
                       "which compiles the kernel with RODAS4 as well (what a first call on a "
                       "stiff working point pays)",
        "cold_cache_seconds": cold_run.get("first_call_seconds"),
        "cached_seconds": warm.get("first_call_seconds"),
        "import_seconds": warm.get("import_seconds"),
        "both_kernels_cold_cache_seconds": both.get("first_call_seconds"),
    }
