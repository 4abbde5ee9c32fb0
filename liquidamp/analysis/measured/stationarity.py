"""Does a record's force drift from cycle to cycle?  The diagnosis's name for the one test.

There is one drift test, :func:`~liquidamp.analysis.measured.drift.record_drift` (the trend of
each whole cycle's first-harmonic force amplitude and mean against the cycle-to-cycle
scatter, a Student t test at ``alpha`` = 1e-3 and a change of at least 1 % of the amplitude;
broadband records by windows), whose :class:`~liquidamp.analysis.measured.drift.Drift` the
record-quality checks, the noise floor and the diagnosis all read.  Before issue #19's
cleanup a second, simpler test lived here (a 5-standard-error trend whose error RMS exceeded
twice the noise); :func:`cycle_drift` keeps its name and its ``None`` for a record it cannot
test, and returns the one test's verdict.

References
----------
.. [1] J. S. Bendat, A. G. Piersol, Random Data, 4th ed., Wiley, 2010, Sec. 10.4.
"""

from __future__ import annotations

from liquidamp.analysis.measured.drift import Drift, record_drift

__all__ = ["Drift", "cycle_drift"]


def cycle_drift(record) -> Drift | None:
    """The drift test of ``record`` (:func:`~liquidamp.analysis.measured.drift.record_drift`),
    or None where it cannot be tested (a tapered stroke, too few whole cycles or windows).

    Examples
    --------
    A force whose amplitude falls by 10 % over 20 cycles, with 1 % noise:

    >>> import numpy as np
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
    d = record_drift(record)
    return d if d.tested else None
