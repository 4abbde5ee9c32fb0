"""Spikes in a record, judged against the record's own local rates.

:func:`find_spikes` finds the samples that leave both their neighbours and come back by
more than the signal's own sample-to-sample changes around them (and its noise, and 2 % of
its range); :class:`Outlier` names one, with the line of the file it was read from.
:func:`~liquidamp.analysis.measured.record_quality.check_record` runs it on the force and
the displacement of a record as read.

References
----------
.. [1] R. K. Pearson, "Outliers in process modeling and identification", IEEE Trans.
   Control Syst. Technol. 10(1), 2002.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Outlier", "find_spikes", "SPIKE_LOCAL", "SPIKE_NOISE", "SPIKE_FLOOR",
           "SPIKE_WIDTH", "SPIKE_RUN"]


@dataclass(frozen=True)
class Outlier:
    """One sample that stands out of its neighbours (:func:`check_record`).

    Attributes
    ----------
    column : str
        ``"force"`` or ``"displacement"``.
    index : int
        Sample index in the record.
    line : int
        Line of the source file (header = line 1).
    time : float
        Sample time [s].
    value : float
        Recorded value [N] or [m].
    expected : float
        The line between the samples just outside its run (:func:`find_spikes`) [N] or [m].
    """

    column: str
    index: int
    line: int
    time: float
    value: float
    expected: float

    def describe(self) -> str:
        """'line L (t = ... s): force 5e+04 N where its neighbours give 312 N'."""
        unit, k = ("N", 1.0) if self.column == "force" else ("mm", 1e3)
        return (f"line {self.line} (t = {self.time:.6g} s): {self.column} {self.value * k:.6g} "
                f"{unit} where its neighbours give {self.expected * k:.6g} {unit}")


#: A spike departs from both its outer neighbours by more than this many times the record's
#: own local rate: the largest sample-to-sample change around it (:func:`find_spikes`) [-].
SPIKE_LOCAL = 3.0
#: ... and by more than this many robust standard deviations of the sample noise [-].
SPIKE_NOISE = 10.0
#: ... and by more than this share of the signal's half range (0.5th to 99.5th percentile) [-].
SPIKE_FLOOR = 0.02
#: Neighbouring sample-to-sample changes on each side that set the local rate [samples].
SPIKE_WIDTH = 5
#: Longest run of adjacent samples taken for one spike [samples].
SPIKE_RUN = 3


def find_spikes(x, *, k_local: float = SPIKE_LOCAL, k_noise: float = SPIKE_NOISE,
                floor: float = SPIKE_FLOOR, width: int = SPIKE_WIDTH,
                run: int = SPIKE_RUN) -> tuple[np.ndarray, np.ndarray]:
    """Isolated spikes of a signal judged against its own local rates: (indices, expected).

    A run of 1 to ``run`` adjacent samples is a spike when every sample of it lies
    beyond both samples just outside it, on the same side, by a height h that exceeds

    * ``k_local`` times the local rate L: the largest of the ``width`` sample-to-sample
      changes on each side of the run (not the run's own) and of the change across the
      run (from the sample before it to the sample after it);
    * ``k_noise`` robust standard deviations of the sample noise (1.4826 x the median
      absolute deviation of the second differences over sqrt(6), their variance for
      white noise being 6 sigma^2);
    * ``floor`` times the signal's half range (its 0.5th to 99.5th percentile).

    So a sample that leaves its neighbours and comes back is a spike, while a step (a
    friction reversal, an MR fluid's yield step: the samples lie between their
    neighbours, or the change across the run is the step itself) and a kink or a
    reversal (a departure of at most the local rate x one sample) are not, however fast
    the stroke.  The test reads the samples as they are, no smooth part is removed
    first, so it holds for periodic, tapered and broadband records alike.  Two passes:
    the spikes of the first are replaced by the line between their outer neighbours
    (``expected``) before the second, so that a spike does not hide a second one nearby.

    Parameters
    ----------
    x : array
        The signal as recorded.
    k_local, k_noise, floor : float
        Thresholds (above) [-].
    width : int
        Sample-to-sample changes on each side that set the local rate [samples].
    run : int
        Longest run of adjacent samples taken for one spike [samples].

    Returns
    -------
    (ndarray of int, ndarray)
        Indices of the spike samples, and for each the value on the line between the
        samples just outside its run.

    References
    ----------
    .. [1] R. K. Pearson, "Outliers in process modeling and identification", IEEE
       Trans. Control Syst. Technol. 10(1), 2002 (local, data-driven outlier scales).

    Examples
    --------
    >>> t = np.arange(0, 1.0, 1e-3)
    >>> y = 0.003 * np.abs(np.sin(2 * np.pi * 3 * t))     # kinks at every reversal
    >>> find_spikes(y)[0].size
    0
    >>> y[550] = 0.03                                      # one 30 mm sample
    >>> idx, expected = find_spikes(y)
    >>> idx.tolist(), round(float(expected[0]) * 1e3, 2)
    ([550], 2.43)
    """
    from numpy.lib.stride_tricks import sliding_window_view as windows

    x = np.array(x, dtype=float)
    n = x.size
    found = np.zeros(n, bool)
    expected = np.zeros(n)
    if n < 2 * width + run + 2:
        return np.flatnonzero(found), expected[found]
    lo_q, hi_q = np.percentile(x, [0.5, 99.5])
    d2 = np.diff(x, 2)
    sigma = 1.4826 * float(np.median(np.abs(d2 - np.median(d2)))) / math.sqrt(6.0)
    level = max(k_noise * sigma, floor * 0.5 * float(hi_q - lo_q))
    for _ in range(2):
        ad = np.abs(np.diff(x))
        pad = np.concatenate((np.zeros(width), ad, np.zeros(width)))
        near = windows(pad, width).max(axis=1)  # near[j] = max |d[j - width : j]|
        new = np.zeros(n, bool)
        for m in range(1, run + 1):
            i = np.arange(1, n - m)
            inner = windows(x, m)[i]
            before, after = x[i - 1], x[i + m]
            up = inner.min(axis=1) - np.maximum(before, after)
            down = np.minimum(before, after) - inner.max(axis=1)
            h = np.maximum(up, down)
            rate = np.maximum.reduce((near[i - 1], near[i + m + width],
                                      np.abs(after - before)))
            hit = np.flatnonzero((h > k_local * rate) & (h > level))
            for j in hit:
                k = int(i[j])
                if new[k:k + m].any() or found[k:k + m].any():
                    continue
                new[k:k + m] = True
                expected[k:k + m] = before[j] + (after[j] - before[j]) * (
                    np.arange(1, m + 1) / (m + 1))
        if not new.any():
            break
        found |= new
        x[new] = expected[new]
    return np.flatnonzero(found), expected[found]
