"""The stroke datum: the record's zero as the mid-position, when the record is not centred.

A record's stroke drives a model about its mean (:mod:`~liquidamp.analysis.measured.record_model`:
the LVDT zero is taken as arbitrary, the mean stroke as the mid-position where the chambers
hold V01 and V02).  A test machine's LVDT is often zeroed at the device's mid-position
instead, and a test run about a mean stroke m away from it (a lag damper's steady lag
offset) then has chambers of V01 - A_p m and V02 + A_p m about its mean: each chamber's
stiffness changes by up to |m| / L (L = V0 / A_p, the chamber end), and so does the force.
On the double-rod reference device a mean of -10 mm (L = 25 mm) moves the force by 28 %
NRMSE.  The centred model follows part of it with unequal air ratios (a larger chamber is
softer, as one with more air), and the loop adds effects for the rest (a groove and a
digressive valve on sweep record R_mean_m10mm, runs/s11_combo, whose true effect is
leakage); freeing the chamber volumes within that loop does not help, because the effect
the records do hold is invisible until the chambers are right and the reverse.

So the record's zero as the datum is a START, diagnosed whole like the fluid family's other
starts (:func:`~liquidamp.analysis.measured.class_revisit.fluid_alternatives`), where the
loop from the centred start ends above the noise and the hypothesis could matter:
:func:`datum_start` gives the device with V01 - A_p m and V02 + A_p m (m the calibration
records' mean stroke as recorded) where |m| / L, the largest share of the force the datum
can move, exceeds the centred loop's calibration NRMSE, and where the chambers can hold the
stroke about that datum (|m| + the largest excursion below L; else the record's zero cannot
be the mid-position).  A centred record (|m| of micrometres) never proposes it.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eq. (10) (V1 = V01 - A_p y, V2 = V02 + A_p y).
"""

from __future__ import annotations

import numpy as np

__all__ = ["record_mean", "datum_start"]


def record_mean(records) -> float:
    """Mean stroke of ``records`` as recorded [m] (each record's ``offset``, weighted by its
    samples)."""
    recs = tuple(records)
    n = np.array([r.time.size for r in recs], float)
    return float(np.sum(n * np.array([r.offset for r in recs])) / n.sum())


def datum_start(params, records, residual: float):
    """The device ``params`` with its chambers about the records' mean stroke as the
    record's zero sets them, or None where that hypothesis cannot matter or cannot hold
    (module docstring).

    Parameters
    ----------
    params : DeviceParams
        The device given (V01, V02 at its mid-position).
    records : sequence of Record
        The calibration records as recorded (their ``offset``: mean stroke [m]).
    residual : float
        Calibration NRMSE the centred loop ended at [-].

    Returns
    -------
    DeviceParams or None
        ``params`` with V01 - A_p m and V02 + A_p m [m^3] (m the records' mean stroke [m]),
        named for it; None for a device without chambers, a centred record (|m| / L at most
        ``residual``) or a stroke the chambers cannot hold about the zero.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> rec = SimpleNamespace(time=np.zeros(100), offset=-0.010, displacement=np.full(100, -0.01))
    >>> q = datum_start(p, [rec], 0.009)
    >>> round(q.V01 / p.V01, 3), round(q.V02 / p.V02, 3)
    (1.4, 0.6)
    >>> datum_start(p, [SimpleNamespace(time=np.zeros(9), offset=2e-6,
    ...                                 displacement=np.zeros(9))], 0.009) is None
    True
    """
    if not hasattr(params, "V01") or params.A_p <= 0:
        return None
    m = record_mean(records)
    L = params.stroke_limit
    if abs(m) / L <= residual:
        return None
    reach = max(float(np.max(np.abs(r.displacement))) for r in records)  # about the zero
    if reach >= L:
        return None
    return params.replace(V01=params.V01 - params.A_p * m, V02=params.V02 + params.A_p * m,
                          name=f"{params.name or 'device'} about the record's zero "
                          f"(mean stroke {m * 1e3:.3g} mm)")
