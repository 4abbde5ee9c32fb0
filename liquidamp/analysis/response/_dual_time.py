"""Time-domain routes of :mod:`liquidamp.analysis.response.dual_frequency`.

Private module.  A run on the engine of the options under a
:class:`~liquidamp.structure.testmachine.TwoFrequencyStroke`: the periodic
steady state over the common period and the exact DFT of the force where
the frequencies are commensurate; otherwise a march from rest in windows
and Hann-weighted least squares (module notes of
:mod:`~liquidamp.analysis.response.dual_frequency`).
"""

from __future__ import annotations

import math

import numpy as np

from liquidamp.errors import ConvergenceError
from liquidamp.structure.testmachine import TwoFrequencyStroke

__all__ = ["time_route"]


def _dft(F, t, f: float) -> complex:
    """a + i b of F ~ a sin(2 pi f t) + b cos(2 pi f t) over whole periods of samples."""
    w = 2.0 * math.pi * f
    return complex(2.0 * np.mean(F * np.sin(w * t)) + 2j * np.mean(F * np.cos(w * t)))


def _lsq(t, F, stroke: TwoFrequencyStroke, span: float):
    """First harmonics at f1 and f2 by Hann-weighted least squares over one window.

    Regressors: a constant and the tones k f1 + l f2 (0 <= k <= 4, |l| <= 4, lowest order
    first) that lie more than 2 / span from every tone already taken, f1 and f2 first;
    the Hann weight makes the tones left out leak little.
    """
    f1, f2 = stroke.frequency1, stroke.frequency2
    freqs = [f1, f2]
    res = 2.0 / span  # tones closer than this cannot be told apart over the window
    combos = sorted(((k, m) for k in range(5) for m in range(-4, 5)),
                    key=lambda km: (abs(km[0]) + abs(km[1]), km))
    for k, m in combos:
        f = k * f1 + m * f2
        if f > res and all(abs(f - g) > res for g in freqs):
            freqs.append(f)
    cols = [np.ones_like(t)]
    for f in freqs:
        cols += [np.sin(2 * math.pi * f * t), np.cos(2 * math.pi * f * t)]
    wt = np.sqrt(np.sin(math.pi * (t - t[0]) / span) ** 2)[:, None]
    c, *_ = np.linalg.lstsq(np.stack(cols, axis=1) * wt, F * wt[:, 0], rcond=None)
    return complex(c[1], c[2]), complex(c[3], c[4])


def time_route(model, params, stroke: TwoFrequencyStroke, options, tol: float) -> dict:
    """The fields of a DualFrequencyStiffness by the time domain (``method="time"``)."""
    from liquidamp.coupled.engines import TestRig, engine_for
    from liquidamp.coupled.testrig import steady_state

    A1, A2, f1, f2 = stroke.amplitude1, stroke.amplitude2, stroke.frequency1, stroke.frequency2
    Y2 = A2 * np.exp(1j * stroke.phase2)
    ratio = stroke.ratio
    pmin = None
    warn = ()
    if ratio is not None:
        a, b = ratio
        T = stroke.period
        S = max(options.samples_per_period, 128 * max(a, b))
        if model.n_states == 0:
            t = np.arange(S) * (T / S)
            y, v, acc = stroke(t)
            F = np.asarray(model.force(t, np.zeros((0, S)), (y, v, acc), params), float)
            cycles, residual, msg = 1, 0.0, "stateless model: force sampled over the common period"
        else:
            r = steady_state(model, params, stroke, options=options.replace(samples_per_period=S))
            t, F = r.time, r.force
            cycles, residual, msg, pmin, warn = (r.cycles, r.residual, r.message,
                                                 r.min_pressure, r.warnings)
        K_lag = _dft(F, t, f2) / Y2
        K_rev = _dft(F, t, f1) / A1 if A1 > 0.0 else None
        return dict(method="time_periodic", K_lag=K_lag, K_rev=K_rev, grid=None,
                    harmonics=None, residual=float(residual), converged=True,
                    iterations=cycles, samples=S, min_pressure=pmin,
                    message=(f"periodic steady state over the common period {T:.6g} s "
                             f"(f1/f2 = {a}/{b}), {S} samples: {msg}"), warnings=tuple(warn))
    # incommensurate: march windows, least squares, until two windows agree
    span = 20.0 / min(f1, f2)
    S = int(32 * span * max(f1, f2))
    t_win = np.arange(S) * (span / S)
    if model.n_states == 0:
        y, v, acc = stroke(t_win)
        F = np.asarray(model.force(t_win, np.zeros((0, S)), (y, v, acc), params), float)
        F_rev, F_lag = _lsq(t_win, F, stroke, span)
        return dict(method="time_window", K_lag=F_lag / Y2,
                    K_rev=F_rev / A1 if A1 > 0.0 else None, grid=None, harmonics=None,
                    residual=0.0, converged=True, iterations=1, samples=S,
                    message=f"stateless model: least squares over {span:.4g} s")
    from liquidamp.coupled.fast import step_period

    rig = TestRig(model, params, stroke)
    engine = engine_for(rig, options)
    x = model.initial_state(params, float(stroke(0.0)[0]))
    prev = None
    change = math.inf
    h_max = options.max_step_fraction * step_period(stroke)
    for k in range(options.max_cycles):
        t0 = k * span
        te = np.append(t0 + t_win, t0 + span)
        X = engine.march(rig, x, t0, t0 + span, te, options, h_max, {})
        x = X[:, -1]
        tt = te[:-1]
        F = np.asarray(model.force(tt, X[:, :-1], stroke(tt), params), float)
        F_rev, F_lag = _lsq(tt, F, stroke, span)
        K_lag = F_lag / Y2
        if prev is not None:
            change = abs(K_lag - prev) / abs(K_lag)
            if change < tol and k >= 2:
                if model.pressures is not None:
                    p1, p2 = model.pressures(X, stroke(te), params)
                    pmin = float(min(np.min(p1), np.min(p2)))
                return dict(method="time_window", K_lag=K_lag,
                            K_rev=F_rev / A1 if A1 > 0.0 else None, grid=None,
                            harmonics=None, residual=change, converged=True,
                            iterations=k + 1, samples=S, min_pressure=pmin,
                            message=(f"march of {k + 1} windows of {span:.4g} s, first "
                                     f"harmonics by least squares; last change of K_lag "
                                     f"{change:.1e}"))
        prev = K_lag
    raise ConvergenceError(
        f"model {model.name!r}: K_lag did not settle over {options.max_cycles} windows of "
        f"{span:.4g} s under {stroke.describe()}: last relative change {change:.2e} (allowed "
        f"{tol:g}); raise max_cycles or tol")
