"""The compiled stroke of the test-machine integrators: harmonic, two-frequency, recorded.

``kind`` 0: harmonic (``sp`` = amplitude, omega, offset, phase); 1: recorded
(samples ``st``, ``sy``, ``sv``, ``sa``, interpolated linearly, with the
sample times as break points the integrator never steps across); 2: two
frequencies (``sp`` = offset, then amplitude, omega, phase of each).  Part of
:mod:`liquidamp.coupled._kernels` (which re-exports every name).

Measured input channels (issue #20) travel with a recorded stroke: ``sa`` holds the
acceleration samples followed by one block of the same length per input channel slot
(``device.kernels.CHANNELS`` order, all ``N_CH`` of them), and :func:`channel_eval`
writes their linear interpolant and its slope at a stage time into the channel slots of
``prm`` (``P_CH``, ``P_CHD``), where the compiled laws read them; the sample times are
the break points for the channels as for the stroke.  A stroke without channels (any
analytic one, a recorded one whose ``sa`` holds the acceleration alone) writes nothing.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.device.kernels_layout import N_CH, P_CH, P_CHD

drop_stale(__file__)  # before any kernel of this module loads from the cache

__all__ = ["stroke_eval", "stroke_rate", "channel_eval"]


@njit(cache=True, error_model="numpy")
def _segment(st, t):
    """Index i of the sample interval [st[i], st[i+1]) holding t, st[0] <= t < st[-1]."""
    lo, hi = 0, st.size - 1
    while hi - lo > 1:
        mid = (lo + hi) >> 1
        if st[mid] <= t:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True, error_model="numpy")
def stroke_eval(kind, t, sp, st, sy, sv, sa):
    """Stroke (y [m], v [m/s], a [m/s^2]) at time t [s]."""
    if kind == 0:
        Y, w, off, ph = sp[0], sp[1], sp[2], sp[3]
        s = math.sin(w * t + ph)
        c = math.cos(w * t + ph)
        return off + Y * s, Y * w * c, -Y * w * w * s
    if kind == 2:
        y, v, a = sp[0], 0.0, 0.0
        for j in (1, 4):
            Y, w, ph = sp[j], sp[j + 1], sp[j + 2]
            s = math.sin(w * t + ph)
            c = math.cos(w * t + ph)
            y += Y * s
            v += Y * w * c
            a -= Y * w * w * s
        return y, v, a
    if kind == 3:  # Fourier series [offset, w, t0, K, s_1, c_1, ..., s_K, c_K]
        y, v, a = sp[0], 0.0, 0.0
        w, tau = sp[1], t - sp[2]
        for k in range(1, int(sp[3]) + 1):
            s_k, c_k = sp[2 + 2 * k], sp[3 + 2 * k]
            kw = k * w
            s = math.sin(kw * tau)
            c = math.cos(kw * tau)
            y += s_k * s + c_k * c
            v += kw * (s_k * c - c_k * s)
            a -= kw * kw * (s_k * s + c_k * c)
        return y, v, a
    n = st.size
    if t <= st[0]:
        return sy[0], sv[0], sa[0]
    if t >= st[n - 1]:
        return sy[n - 1], sv[n - 1], sa[n - 1]
    lo = _segment(st, t)
    hi = lo + 1
    w = (t - st[lo]) / (st[hi] - st[lo])
    return (sy[lo] + w * (sy[hi] - sy[lo]), sv[lo] + w * (sv[hi] - sv[lo]),
            sa[lo] + w * (sa[hi] - sa[lo]))


@njit(cache=True, error_model="numpy")
def stroke_rate(kind, t, sp, st, sy, sv, sa):
    """Time derivatives (dy/dt [m/s], dv/dt [m/s^2]) of the stroke as evaluated.

    Harmonic and two-frequency: (v, a) exactly.  Recorded: the slopes of the
    linear interpolant on the segment that starts at or before ``t`` (the
    integrator never steps across a sample time, so this is exact there).
    """
    if kind != 1:
        y, v, a = stroke_eval(kind, t, sp, st, sy, sv, sa)
        return v, a
    n = st.size
    if t < st[0] or t >= st[n - 1]:
        return 0.0, 0.0
    lo = _segment(st, t)
    hi = lo + 1
    d = st[hi] - st[lo]
    return (sy[hi] - sy[lo]) / d, (sv[hi] - sv[lo]) / d


@njit(cache=True, error_model="numpy")
def _next_break(kind, t, st, tiny):
    """First sample time of a recorded stroke after t + tiny (inf for analytic strokes)."""
    if kind != 1:
        return np.inf
    n = st.size
    if t + tiny >= st[n - 1]:
        return np.inf
    if t + tiny < st[0]:
        return st[0]
    return st[_segment(st, t + tiny) + 1]


@njit(cache=True, error_model="numpy")
def channel_eval(kind, t, st, sa, prm):
    """Write the measured input channels at time t [s] into ``prm`` (module docstring).

    Values (linear interpolation of the samples, end values held outside, as the stroke)
    into ``prm[P_CH + k]``, slopes of the segment that starts at or before ``t`` (0
    outside) into ``prm[P_CHD + k]``; nothing for a stroke without channels.
    """
    if kind != 1:
        return
    n = st.size
    if sa.size < (N_CH + 1) * n:
        return
    if t < st[0] or t >= st[n - 1]:
        j = 0 if t < st[0] else n - 1
        for k in range(N_CH):
            prm[P_CH + k] = sa[(k + 1) * n + j]
            prm[P_CHD + k] = 0.0
        return
    lo = _segment(st, t)
    hi = lo + 1
    d = st[hi] - st[lo]
    w = (t - st[lo]) / d
    for k in range(N_CH):
        a = sa[(k + 1) * n + lo]
        b = sa[(k + 1) * n + hi]
        prm[P_CH + k] = a + w * (b - a)
        prm[P_CHD + k] = (b - a) / d
