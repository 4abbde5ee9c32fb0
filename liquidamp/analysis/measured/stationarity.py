"""Does a record's force drift from cycle to cycle?  A simple trend test (diagnosis input).

A device that warms by its own dissipation (or a rig that creeps) changes its force from
cycle to cycle: no stationary model fits such a record to its noise, and the scatter of the
force at the same phase, which the diagnosis takes as its noise floor, grows with the drift.
:func:`cycle_drift` fits, to every whole stroke cycle of a periodic record, the force's mean
and its first harmonic at the stroke frequency (least squares on 1 and the first five
harmonics), then a straight
line through each of the two per-cycle series against time.  The drift over the record is
the line's rise over the record's span, its standard error from the scatter of the cycles
about the line.  The drift is reported as non-stationary when it is both

* significant: |drift| > ``t_min`` (5) standard errors, and
* large enough to matter: the force error a linear drift of the first-harmonic amplitude
  (or of the mean) by Delta leaves in a model fitted to the middle of the record, RMS
  |Delta| / sqrt(24) (|Delta| / sqrt(12) for the mean), exceeds ``noise_ratio`` (2) times the
  per-sample force noise sigma.  sigma is estimated from the same scatter of the cycles about
  the trend (an amplitude from n samples has standard error sigma sqrt(2 / n)), so the drift
  does not inflate it.

This is the small replaceable test of issue 19 item 3; a record-quality check that states
non-stationarity itself (``DataQuality.non_stationary`` or ``.drift``) takes precedence in
:func:`liquidamp.analysis.measured.diagnosis.diagnose`.

References
----------
.. [1] J. S. Bendat, A. G. Piersol, Random Data, 4th ed., Wiley, 2010, Sec. 10.4
   (tests for stationarity: trend of short-segment statistics).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Drift", "cycle_drift"]


@dataclass(frozen=True)
class Drift:
    """Cycle-to-cycle trend of one record's force (:func:`cycle_drift`).

    Attributes
    ----------
    source : str
        The record's label.
    cycles : int
        Whole cycles used [-].
    amplitude : float
        Mean first-harmonic force amplitude [N].
    amplitude_change, mean_change : float
        Rise of the first-harmonic amplitude and of the mean force over the record [N].
    amplitude_t, mean_t : float
        Each change over its standard error [-].
    noise_std : float
        Per-sample force noise estimated from the cycles' scatter about the trend [N].
    non_stationary : bool
        Significant and large enough to matter (module docstring).
    """

    source: str
    cycles: int
    amplitude: float
    amplitude_change: float
    mean_change: float
    amplitude_t: float
    mean_t: float
    noise_std: float
    non_stationary: bool

    @property
    def relative_change(self) -> float:
        """amplitude_change / amplitude [-]."""
        return self.amplitude_change / self.amplitude if self.amplitude > 0 else 0.0

    def describe(self) -> str:
        """One phrase, e.g. ``"a.csv: first-harmonic force -18.7 % over 30 cycles"``."""
        return (f"{self.source}: first-harmonic force {self.relative_change:+.1%} "
                f"({self.amplitude_change:+.3g} N), mean force {self.mean_change:+.3g} N over "
                f"{self.cycles} cycles")

    def as_dict(self) -> dict:
        """JSON-ready."""
        return {"record": self.source, "cycles": self.cycles,
                "amplitude [N]": self.amplitude,
                "amplitude_change [N]": self.amplitude_change,
                "relative_amplitude_change": self.relative_change,
                "mean_change [N]": self.mean_change, "amplitude_t": self.amplitude_t,
                "mean_t": self.mean_t, "noise_std [N]": self.noise_std,
                "non_stationary": self.non_stationary}


def _trend(tc, x, span):
    """Rise of a straight line through (tc, x) over ``span`` [s], and its standard error."""
    A = np.column_stack([np.ones_like(tc), tc - tc.mean()])
    coef, *_ = np.linalg.lstsq(A, x, rcond=None)
    res = x - A @ coef
    dof = max(tc.size - 2, 1)
    s2 = float(res @ res) / dof
    sxx = float(np.sum((tc - tc.mean()) ** 2))
    se = math.sqrt(s2 / sxx) * span if sxx > 0 else math.inf
    return float(coef[1]) * span, se, math.sqrt(s2)


def cycle_drift(record, *, t_min: float = 5.0, noise_ratio: float = 2.0) -> Drift | None:
    """Trend of the force's mean and first harmonic over the whole cycles of a record.

    Parameters
    ----------
    record : Record
        A record as read (not averaged).
    t_min : float
        Least |change| / standard error to call a drift significant [-].
    noise_ratio : float
        Least drift error RMS over the per-sample noise to call it relevant [-].

    Returns
    -------
    Drift or None
        None when the stroke is not periodic or fewer than 4 whole cycles are recorded.

    Examples
    --------
    A force whose amplitude falls by 10 % over 20 cycles, with 1 % noise:

    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 10, 0.005)
    >>> rng = np.random.default_rng(1)
    >>> F = 100 * (1 - 0.01 * t) * np.cos(2 * np.pi * 2 * t) + rng.normal(0, 1, t.size)
    >>> d = cycle_drift(Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 2 * t), F))
    >>> d.non_stationary, round(d.relative_change, 2)
    (True, -0.1)
    >>> F0 = 100 * np.cos(2 * np.pi * 2 * t) + rng.normal(0, 1, t.size)
    >>> cycle_drift(Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 2 * t), F0)).non_stationary
    False
    """
    shape = getattr(record, "shape", None)
    if shape is not None and not getattr(shape, "periodic", True):
        return None
    f = float(record.frequency)
    t = np.asarray(record.time, float)
    F = np.asarray(record.force, float)
    if not (f > 0 and t.size > 8):
        return None
    T = 1.0 / f
    n_cyc = int(math.floor((t[-1] - t[0]) / T + 1e-9))
    if n_cyc < 4:
        return None
    amps, means, tcs, counts = [], [], [], []
    w = 2 * math.pi * f
    for i in range(n_cyc):
        m = (t >= t[0] + i * T) & (t < t[0] + (i + 1) * T)
        if m.sum() < 6:
            return None
        tt = t[m]
        # the higher harmonics fitted too, so that a cycle not sampled on a whole number of
        # samples does not leak them into the first harmonic from cycle to cycle
        cols = [np.ones_like(tt)]
        for h in range(1, max(1, min(5, (tt.size - 1) // 4)) + 1):
            cols += [np.cos(h * w * tt), np.sin(h * w * tt)]
        c, *_ = np.linalg.lstsq(np.column_stack(cols), F[m], rcond=None)
        means.append(c[0])
        amps.append(math.hypot(c[1], c[2]))
        tcs.append(tt.mean())
        counts.append(int(m.sum()))
    tc, amps, means = np.array(tcs), np.array(amps), np.array(means)
    span = float(t[-1] - t[0])
    da, se_a, s_a = _trend(tc, amps, span)
    dm, se_m, s_m = _trend(tc, means, span)
    n = float(np.mean(counts))
    # an amplitude from n samples: sigma sqrt(2 / n); a mean: sigma / sqrt(n)
    sigma = max(min(s_a * math.sqrt(n / 2.0), s_m * math.sqrt(n)), 1e-300)
    t_a = abs(da) / se_a if se_a > 0 else math.inf
    t_m = abs(dm) / se_m if se_m > 0 else math.inf
    big_a = t_a > t_min and abs(da) / math.sqrt(24.0) > noise_ratio * sigma
    big_m = t_m > t_min and abs(dm) / math.sqrt(12.0) > noise_ratio * sigma
    return Drift(getattr(record, "label", ""), n_cyc, float(amps.mean()), da, dm,
                 float(t_a), float(t_m), float(sigma), bool(big_a or big_m))
