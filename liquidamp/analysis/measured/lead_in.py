"""The lead-in before a record's first sample when the record is not periodic.

:func:`~liquidamp.analysis.measured.record_model.simulate_record` runs a record whose stroke
is not periodic from rest at the start of a lead-in, so that the model meets the first
sample in motion (its module docstring): :func:`lead_in` chooses the record's own motion
into its state nearest the first sample's (:func:`_analogue_lead_in`, a stroke of a few
sinusoids) or a ramp at the first sample's velocity (:func:`_ramp_lead_in`).

References
----------
.. [1] E. N. Lorenz, "Atmospheric predictability as revealed by naturally occurring
   analogues", J. Atmos. Sci. 26(4), 1969 (the method of analogues).
"""

from __future__ import annotations

import numpy as np

from liquidamp.structure.testmachine import RecordedStroke

__all__ = ["lead_in"]


def _analogue_lead_in(stroke, duration: float, period: float):
    """``stroke`` with a lead-in of ``duration`` [s] before its first sample: the record's own
    motion into the state most like its first sample's (the channels held at their first
    values).

    A record is cut from a running test: before its first sample the rod was moving as it
    moves in the record, and a device's pressures, flows and friction states carry that
    history (a fluid device's channel flow rings at its own frequency for tens of
    milliseconds after any jump in the motion's derivatives).  The lead-in is the stretch of
    the record that ends at the sample t* (at least ``duration`` after the first) whose
    stroke, rate and acceleration are nearest the first sample's (each scaled by its RMS
    over the record: the method of analogues), moved in time to end at the first sample;
    the remaining mismatch is added as the displacement c(s) = (b0 + b1 s + b2 s^2 / 2)
    exp(s / T) (s <= 0, T = ``period`` / 2 pi, b chosen so that c, c', c'' are the mismatch
    of stroke, rate and acceleration at s = 0) and differentiated with it: the lead-in is one
    motion that meets the first sample on its position, rate and acceleration, the
    correction on the motion's own time scale and gone a period before the first sample.
    A periodic stroke's analogue is the same phase a
    whole number of cycles later (its history exactly); a multi-tone stroke's the nearest
    return of its tones' phases.  Before, the lead-in was a ramp at the first sample's
    velocity no farther than the stroke's RMS (0.1 s on a 4 Hz + 1.3 Hz stroke): the true
    model then left 91 N at the first sample, 2 % NRMSE over the record, 5x its noise.

    Examples
    --------
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0.0, 2.0, 0.005)
    >>> s = Record.from_arrays(t, 1e-3 * np.sin(2 * np.pi * 4 * t + 1.0), 0 * t).stroke()
    >>> led = _analogue_lead_in(s, 0.3, 0.25)
    >>> t0 = float(s.time[0]) - 0.13  # before the first sample: the sine's own history
    >>> round(float(led(t0)[0]) * 1e3, 2), round(float(np.sin(8 * np.pi * t0 + 1.0)), 2)
    (-0.84, -0.85)
    """
    st, y, v, a = stroke.time, stroke.displacement, stroke.velocity, stroke.acceleration
    dt = float(st[1] - st[0])
    n = int(duration / dt)
    if n < 1 or n >= st.size:
        return stroke
    scale = [max(float(np.std(q)), 1e-300) for q in (y, v, a)]
    dist = sum(((q[n:] - q[0]) / sc) ** 2 for q, sc in zip((y, v, a), scale, strict=True))
    k = n + int(np.argmin(dist))
    seg = slice(k - n, k)
    tau = -dt * np.arange(n, 0, -1)
    # the mismatch as the displacement c(s) = Q(s) exp(s / T), Q quadratic in s with c, c', c''
    # = dy, dv, da at s = 0, T = period / (2 pi): it lives on the motion's own time scale and
    # is gone (exp(-2 pi)) a period before the first sample
    dy, dv, da = (float(q[0] - q[k]) for q in (y, v, a))
    T = period / (2.0 * np.pi)
    b0 = dy
    b1 = dv - dy / T
    b2 = da - 2.0 * b1 / T - b0 / (T * T)
    E = np.exp(tau / T)
    Q, Q1 = b0 + b1 * tau + 0.5 * b2 * tau * tau, b1 + b2 * tau
    parts = [y[seg] + Q * E, v[seg] + (Q1 + Q / T) * E,
             a[seg] + (b2 + 2.0 * Q1 / T + Q / (T * T)) * E]
    ch = {c: np.concatenate([np.full(n, q[0]), q]) for c, q in stroke.channels.items()}
    return RecordedStroke(np.concatenate([st[0] + tau, st]),
                          *(np.concatenate([p, q]) for p, q in zip(parts, (y, v, a),
                                                                   strict=True)),
                          channels=ch)


def _ramp_lead_in(stroke, duration: float):
    """``stroke`` with a lead-in before its first sample: the first sample approached at its
    own velocity v0 (y = y0 - v0 s, s before t0; the channels held at their first values)
    over ``duration`` [s] or over the time that moves the rod by the stroke's RMS about its
    mean, whichever is shorter, on the stroke's sample spacing; so that a model started
    from rest meets the first sample in steady flow at v0 (its yield, friction and pressure
    drops on the side the motion sets), not from rest at a finite velocity."""
    st, y = stroke.time, stroke.displacement
    v0 = float(stroke.velocity[0])
    reach = float(np.sqrt(np.mean((y - y.mean()) ** 2)))
    span = min(duration, reach / abs(v0)) if v0 != 0.0 else duration
    dt = float(st[1] - st[0])
    n = int(span / dt)
    if n < 1:
        return stroke
    s = dt * np.arange(n, 0, -1)
    ch = {c: np.concatenate([np.full(n, v[0]), v]) for c, v in stroke.channels.items()}
    return RecordedStroke(np.concatenate([st[0] - s, st]),
                          np.concatenate([y[0] - v0 * s, y]),
                          np.concatenate([np.full(n, v0), stroke.velocity]),
                          np.concatenate([np.zeros(n), stroke.acceleration]), channels=ch)


def lead_in(stroke, share: float, longest: float, period: float, analogue: bool = True):
    """``stroke`` with a lead-in before its first sample, so that a model started from rest
    meets the first sample in motion (module docstring).

    A stroke of a few sinusoids (``analogue``:
    :func:`~liquidamp.analysis.measured.tones.tone_fit` explains it) was moving before the
    record as it moves in it; where the record beyond a lead-in of
    ``share`` of its span (at least one ``period`` [s] of its frequency, at most ``longest``
    [s]) still holds a whole period, the lead-in is the record's own motion into its state
    nearest the first sample's (:func:`_analogue_lead_in`; the remaining mismatch then fades
    on the motion's own time scale and the search spans every phase of it).  Otherwise (a
    tapered stroke, which started from rest; a broadband one; a record too short to hold a
    return of its state) a ramp at the first sample's velocity over ``share`` of the span
    (:func:`_ramp_lead_in`).

    Examples
    --------
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0.0, 4.0, 0.005)
    >>> s = Record.from_arrays(t, 1e-3 * np.sin(8 * np.pi * t), 0 * t).stroke()
    >>> led = lead_in(s, 0.1, 1.0, 0.25)  # a sine: its own history, 0.4 s
    >>> round(float(s.time[0] - led.time[0]), 3)
    0.4
    >>> ramp = lead_in(s, 0.1, 1.0, 0.25, analogue=False)  # the ramp, within the stroke's RMS
    >>> bool(s.time[0] - ramp.time[0] < 0.4)
    True
    """
    span = float(stroke.time[-1] - stroke.time[0])
    lead = min(share * span, longest)
    longer = min(max(lead, period), longest)
    if analogue and lead > 0.0 and span >= longer + period:
        return _analogue_lead_in(stroke, longer, period)
    return _ramp_lead_in(stroke, lead) if lead > 0.0 else stroke
