"""Bench case ``stiffness_1um`` of :func:`liquidamp.analysis.bench.run_bench` (issue #21).

Every preset's 1 um first-harmonic K* at 7 frequencies 0.5-20 Hz
(:func:`~liquidamp.analysis.response.stiffness.nonlinear_stiffness`, default options):
the wall time, the points present, which route reached them
(:func:`liquidamp.coupled.periodic.periodic_state`: march or shooting) and the largest
departure from the equivalent linearization at the stroke amplitude.  Measured before
the route (march alone, 400 cycles): 7 of 56 points missing (inerter 0.5, 1 Hz; spring 1,
4 Hz; damper 0.5, 1 Hz; device_b 0.5 Hz).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

__all__ = ["case_stiffness_1um", "FREQUENCIES"]

#: Frequencies of the case [Hz] (the seven points that failed before are among them).
FREQUENCIES = (0.5, 1.0, 2.0, 4.0, 7.0, 12.0, 20.0)


def case_stiffness_1um(quick: bool, repeats: int) -> dict:
    """Run the case (module docstring); ``repeats`` timed sweeps after one warm-up.

    Examples
    --------
    >>> r = case_stiffness_1um(True, 1)
    >>> r["points_present"] == r["points"] == 56, r["max_error_vs_equivalent"] < 1e-3
    (True, True)
    """
    from liquidamp.analysis.response.equivalent import equivalent_linearization
    from liquidamp.analysis.response.linear import linearize
    from liquidamp.analysis.response.stiffness import nonlinear_stiffness
    from liquidamp.device import preset, preset_names
    from liquidamp.errors import LiquidampWarning

    names = preset_names()
    Y = 1e-6

    def sweep():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", LiquidampWarning)
            return [nonlinear_stiffness(preset(n), FREQUENCIES, [Y], on_error="skip")
                    for n in names]

    sweep()  # compile or load the cached kernels
    times = []
    for _ in range(max(int(repeats), 1)):
        t = time.perf_counter()
        runs = sweep()
        times.append(time.perf_counter() - t)
    present = sum(int(np.isfinite(r.value).sum()) for r in runs)
    worst = 0.0
    for n, r in zip(names, runs, strict=True):
        p = preset(n)
        kind = "inertial_2state" if p.S_t > 0 else "single_state"
        for j, f in enumerate(FREQUENCIES):
            K = r.value[0, j]
            if not np.isfinite(K):
                continue
            c_eq = equivalent_linearization(p.replace(friction_N=0.0), f, Y, kind,
                                            bulk="rest").c_eq
            K_eq = linearize("full", p.replace(c1=c_eq, c2=0.0)).frequency_response([f])[0]
            worst = max(worst, abs(K / K_eq - 1.0))
    return {
        "description": "nonlinear_stiffness of every preset at 1 um, 7 frequencies 0.5-20 Hz "
                       "(march, then shooting where the march stalls)",
        "seconds": float(np.median(times)),
        "repeats": len(times),
        "points": len(names) * len(FREQUENCIES),
        "points_present": present,
        "points_missing_before": 7,
        "max_error_vs_equivalent": float(worst) if math.isfinite(worst) else None,
    }
