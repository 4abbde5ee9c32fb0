"""How the device class is chosen among the starts' cheap calibrations.

:func:`choose_start` judges the starts of
:func:`~liquidamp.analysis.measured.device_class.calibrate_by_class` on the data: the
held-out records first (a start that another beats on the pooled held-out records by
more than :data:`HELD_OUT_TOLERANCE`, while not worse on any record and not paying for it
with parameters the calibration records do not support, is out), then the
Bayesian information criterion on the calibration records with an honest sample count
(:func:`~liquidamp.analysis.measured.selection.effective_samples`), graded by Kass and
Raftery's evidence scale (:data:`BIC_POSITIVE`, :data:`BIC_STRONG`).  Each start's outcome
is kept as a :class:`StartOutcome` for the JSON and the report.

References
----------
R. E. Kass and A. E. Raftery, "Bayes factors", J. Am. Stat. Assoc. 90(430), 773-795, 1995.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.selection import effective_samples
from liquidamp.errors import ConvergenceError, ParameterError

__all__ = ["HELD_OUT_TOLERANCE", "BIC_STRONG", "BIC_POSITIVE", "DEFAULT_CLASS",
           "StartOutcome", "choose_start"]

#: Largest relative excess of a start's pooled held-out NRMSE over the best start's [-].
HELD_OUT_TOLERANCE = 0.05
#: BIC difference that is strong evidence on the calibration records (Kass and Raftery's
#: "very strong", as the diagnosis's ``bic_threshold``) [-].
BIC_STRONG = 10.0
#: BIC difference that is positive evidence (Kass and Raftery): another class replaces the
#: fluid start only beyond it (or better held-out) [-].
BIC_POSITIVE = 2.0
#: The family's own start.
DEFAULT_CLASS = "fluid"


# ---------------------------------------------------------------------------
# the choice


@dataclass(frozen=True)
class StartOutcome:
    """One start's cheap calibration and how :func:`choose_start` judged it.

    Attributes
    ----------
    name : str
        ``"fluid"``, ``"friction"`` or ``"viscous"`` (or any label).
    reason : str
        What the start was read off.
    nrmse_calibration, nrmse_validation : float or None
        Pooled NRMSE [-] (None: the start could not be calibrated).
    validation_records : dict
        Record label -> held-out NRMSE [-].
    k : int
        Varied parameters.
    bic : float or None
        N_eff ln RSS + k ln N_eff on the calibration records [-].
    admissible : bool
        Not dominated by another start (:func:`choose_start`).
    chosen : bool
    nfev : int
        Model evaluations of its cheap calibration.
    error : str
        Why it could not be calibrated ('' when it was).
    continued : bool
        Its fit was continued with the full budget (its figures are the continued
        fit's).
    sized : bool
        Its device was sized to the records (a similar device, not the one given).
    """

    name: str
    reason: str
    nrmse_calibration: float | None = None
    nrmse_validation: float | None = None
    validation_records: dict = dataclasses.field(default_factory=dict)
    k: int = 0
    bic: float | None = None
    admissible: bool = True
    chosen: bool = False
    nfev: int = 0
    error: str = ""
    continued: bool = False
    sized: bool = False

    def describe(self) -> str:
        """'friction: calibration 0.21, validation 0.25 (chosen)'."""
        if self.nrmse_calibration is None:
            return f"{self.name}: failed ({self.error})"
        nv = ("" if self.nrmse_validation is None
              else f", validation {self.nrmse_validation:.3g}")
        tag = " (chosen)" if self.chosen else ("" if self.admissible
                                               else " (dominated)")
        cheap = "" if self.continued else " after the cheap fit"
        return f"{self.name}: calibration {self.nrmse_calibration:.3g}{nv}{cheap}{tag}"

    def as_dict(self) -> dict:
        """JSON-ready."""
        return dataclasses.asdict(self)


def _dominates(b, a, tolerance: float) -> bool:
    """Fit ``b`` predicts the held-out records better than ``a`` by more than ``tolerance``
    (pooled) and is not worse by more than it on any record, calibration or held-out."""
    if a.nrmse_validation is None or b.nrmse_validation is None:
        return False
    ea = {(e.role, e.label): e.nrmse for e in a.record_errors}
    eb = {(e.role, e.label): e.nrmse for e in b.record_errors}
    return (b.nrmse_validation * (1 + tolerance) < a.nrmse_validation
            and all(eb[k] <= (1 + tolerance) * v for k, v in ea.items() if k in eb))


def choose_start(fits: dict, tolerance: float = HELD_OUT_TOLERANCE,
                 reasons: dict | None = None, eligible=None) -> tuple[str, tuple, str]:
    """The start to continue among calibrations of the same records (module docstring).

    Among the eligible fits that no other dominates (better on the pooled held-out
    records by more than ``tolerance``, not worse by more than ``tolerance`` on any
    record, calibration or held-out, and an effective-sample BIC not higher by
    :data:`BIC_POSITIVE` or more: its parameters paid for), the lowest effective-sample
    BIC on the calibration records leads.  A fit better held-out than the leader by more
    than ``tolerance`` wins instead where the leader's BIC is lower by less than
    :data:`BIC_STRONG` (the calibration records hold no strong evidence; the best held-out
    of those wins);
    where it is lower by more, the records disagree, the leader stays and the returned
    note says so.  A choice of another class than :data:`DEFAULT_CLASS` (the fluid start,
    when it is eligible and not dominated) gives way to the fluid start where it predicts
    the held-out records worse than the fluid start (at all), or where its BIC is lower
    than the fluid start's by less than :data:`BIC_POSITIVE` (2, no positive evidence)
    and it does not predict the held-out records better by more than ``tolerance``.

    Parameters
    ----------
    fits : dict
        Name -> :class:`~liquidamp.analysis.measured.calibration_result.CalibrationResult`
        (same calibration and validation records), or the exception its fit raised.
    tolerance : float
        Relative tolerance on the NRMSE [-] (``math.inf``: the calibration BIC alone).
    reasons : dict, optional
        Name -> what the start was read off (copied into the outcomes).
    eligible : collection of str, optional
        The names that may win (default: every fit); the others are judged and reported
        only.

    Returns
    -------
    (str, tuple of StartOutcome, str)
        The chosen name, every start's outcome and a note ('' or where the records
        disagree).

    Raises
    ------
    ConvergenceError
        When no start could be calibrated (every error named).
    ParameterError
        A negative or NaN ``tolerance``, or no eligible fit.
    """
    if math.isnan(tolerance) or tolerance < 0:
        raise ParameterError(f"choose_start: tolerance must be a number >= 0 [-], "
                             f"got {tolerance!r}")
    reasons = reasons or {}
    ok = {n: r for n, r in fits.items() if not isinstance(r, BaseException)}
    if not ok:
        raise ConvergenceError("calibration: no start could be calibrated: " + "; ".join(
            f"{n}: {e}" for n, e in fits.items()))
    can = [n for n in ok if eligible is None or n in eligible]
    if not can:
        raise ParameterError(f"choose_start: no eligible fit among {sorted(ok)} "
                             f"(eligible: {sorted(eligible)})")
    res = {n: r.residuals("calibration") for n, r in ok.items()}
    n_eff = min(effective_samples(v)[0] for v in res.values())
    bic = {n: n_eff * math.log(max(sum(float(np.sum(x * x)) for x in v), 1e-300))
           + len(ok[n].varying) * math.log(n_eff) for n, v in res.items()}
    # b dominates a only where it is at least as good on the calibration records as the
    # choice measures them, its parameters paid for (BIC not higher by BIC_POSITIVE or
    # more): a start with more parameters that matches another there only within the
    # tolerance has not earned the exclusion of the simpler one
    dominated = {n: any(_dominates(ok[m], ok[n], tolerance)
                        and bic[m] - bic[n] < BIC_POSITIVE for m in can if m != n)
                 for n in ok}
    free = [n for n in can if not dominated[n]]
    leader = min(free, key=lambda n: bic[n])
    r0 = ok[leader]
    better = [m for m in free if m != leader and r0.nrmse_validation is not None
              and ok[m].nrmse_validation * (1 + tolerance) < r0.nrmse_validation]
    weak = [m for m in better if bic[m] - bic[leader] < BIC_STRONG]
    chosen, note = leader, ""
    if weak:  # the calibration records do not hold strong evidence: the held-out decide
        chosen = min(weak, key=lambda n: ok[n].nrmse_validation)
        note = (f"the held-out records decide: the {chosen} start predicts them better "
                f"({ok[chosen].nrmse_validation:.3g} against {r0.nrmse_validation:.3g}) and "
                f"the {leader} start's lower effective-sample BIC on the calibration records "
                f"is not strong evidence ({bic[chosen] - bic[leader]:.3g} < {BIC_STRONG:g})")
    elif better:
        m = min(better, key=lambda n: ok[n].nrmse_validation)
        note = (f"the records disagree: the {m} start predicts the held-out records better "
                f"({ok[m].nrmse_validation:.3g} against {r0.nrmse_validation:.3g}) but the "
                f"{leader} start fits the calibration records better ({r0.nrmse_calibration:.3g} "
                f"against {ok[m].nrmse_calibration:.3g}) with strong evidence (effective-"
                f"sample BIC {bic[leader]:.4g} against {bic[m]:.4g}, more than {BIC_STRONG:g} "
                "lower)")
    if chosen != DEFAULT_CLASS and DEFAULT_CLASS in free:
        f, c = ok[DEFAULT_CLASS], ok[chosen]
        worse = (c.nrmse_validation is not None
                 and c.nrmse_validation > f.nrmse_validation)
        weak_bic = bic[DEFAULT_CLASS] - bic[chosen] < BIC_POSITIVE and not (
            c.nrmse_validation is not None
            and c.nrmse_validation * (1 + tolerance) < f.nrmse_validation)
        if worse or weak_bic:  # the family's own start gives way on evidence only
            note = (f"the {chosen} start " + (
                f"predicts the held-out records worse than the {DEFAULT_CLASS} start "
                f"({c.nrmse_validation:.3g} against {f.nrmse_validation:.3g})" if worse else
                f"has no positive evidence over the {DEFAULT_CLASS} start (BIC lower by "
                f"{bic[DEFAULT_CLASS] - bic[chosen]:.3g} < {BIC_POSITIVE:g}, held-out not "
                f"better by {tolerance:.0%})") + f": the {DEFAULT_CLASS} start is kept")
            chosen = DEFAULT_CLASS
    out = []
    for n, r in fits.items():
        if isinstance(r, BaseException):
            out.append(StartOutcome(n, reasons.get(n, ""), admissible=False,
                                    error=f"{type(r).__name__}: {r}"))
            continue
        out.append(StartOutcome(
            n, reasons.get(n, ""), r.nrmse_calibration, r.nrmse_validation,
            {e.label: e.nrmse for e in r.record_errors if e.role == "validation"},
            len(r.varying), bic[n], not dominated[n], n == chosen, r.nfev))
    return chosen, tuple(out), note
