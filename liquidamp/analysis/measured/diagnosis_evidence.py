"""Evidence for the residual diagnosis: signatures, score test, confounded pairs.

What :func:`liquidamp.analysis.measured.diagnosis.diagnose` weighs before it refits a
candidate (steps 3 and 5 of its algorithm): :func:`signatures` (correlations of the
calibration residual with simple effect signatures), the score test of one candidate
(:func:`score`: the model run once with the effect at a probe strength, the part of its
signature the fitted parameters cannot mimic, the linearized drop of the residual sum of
squares), the :class:`Candidate` record of that evidence, and :data:`CONFOUNDED`, the pairs
of effects and device parameters a record may not separate, with the evidence gathered when
such an effect is added.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C.
.. [2] C. R. Rao, "Large sample tests of statistical hypotheses concerning
   several parameters...", Proc. Camb. Phil. Soc. 44, 1948 (score test).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.measured.calibration import (
    FIT_OPTIONS,
    CalibrationResult,
    predict,
)
from liquidamp.analysis.measured.candidates import (
    COMPOSITES,
    DEVICE_REFINEMENTS,
    REDUCTIONS,
    applicable,
    candidate_change,
    free_columns,
    probe_effect,
)
from liquidamp.analysis.measured.record_model import NOT_PERIODIC, simulate_record
from liquidamp.device.effects import EFFECTS
from liquidamp.errors import LiquidampError

__all__ = ["Candidate", "CONFOUNDED", "COMPOSITES", "DEVICE_REFINEMENTS", "REDUCTIONS",
           "signatures", "score", "probe_effect",
           "candidate_change", "applicable", "confounding", "confounding_warnings",
           "harmonic_structure"]

CONFOUNDED = {
    ("series_compliance", "inv_gamma"): "a series spring and the air in the chambers are both "
    "springs in series with the channel; with the air ratios free only the pressure dependence "
    "of the air's stiffness separates them, which is weak at small strokes",
    ("leakage", "c1"): "a laminar bypass and the channel's laminar loss are both conductances "
    "between the chambers; with c1 free only the channel's inertance and quadratic loss, which "
    "the bypass skips, separate them",
    ("moving_mass", "S_t"): "a moving mass (F += m a) and the channel inertance b_L = rho_l "
    "S_t A_p^2 both give a force in phase with the acceleration while the air spring is stiff; "
    "S_t is not among the paper's fitted multipliers, so a wrong S_t is absorbed by the mass "
    "(damper preset, 1/10 of paper_initial's S_t, diagnosed from paper_initial: mass fitted at "
    "twice its value)",
    ("cavitation", "inv_gamma"): "a vapour cavity and a little more entrained air both soften "
    "the low-pressure chamber; the force waveforms can be nearly identical",
    ("elastomer", "inv_gamma"): "the elastomer's branch (a spring in series with a dashpot) "
    "and the fluid (the air spring in series with the channel's losses) are both Maxwell "
    "elements; only the parallel spring is the elastomer's own, so its branch trades with "
    "the air ratios and losses unless the records span its relaxation frequency",
}
"""Pairs an experiment may not separate, and why."""


@dataclass(frozen=True)
class Candidate:
    """Evidence for one candidate effect at one step.

    Attributes
    ----------
    effect : str
        Catalogue name.
    score : float
        Linearized relative drop of the calibration RSS (score test) [-].
    signature_correlation : float
        Correlation of the residual with the effect's signature [-].
    estimate : dict
        Linearized strength (parameter key -> value, SI).
    refitted : bool
        Whether the candidate was refitted.
    nrmse_calibration, nrmse_validation : float or None
        After the refit [-].
    relative_reduction : float or None
        Relative drop of the validation NRMSE against the current model [-].
    delta_bic : float or None
        Calibration BIC change counted with ``n_effective`` samples (negative favours
        the effect; module doc, step 5).
    n_effective : float or None
        Effective number of independent calibration samples of the refit's residual [-].
    parameters : dict
        Fitted effect parameters (SI) after the refit.
    accepted : bool
        Passed the selection rule (module doc, step 5).
    note : str
        Why not applicable, what happened in the refit, or which test it failed.
    validation_records : dict
        Held-out NRMSE of the refit per record (label -> NRMSE [-]).
    """

    effect: str
    score: float
    signature_correlation: float
    estimate: dict
    refitted: bool = False
    nrmse_calibration: float | None = None
    nrmse_validation: float | None = None
    relative_reduction: float | None = None
    delta_bic: float | None = None
    n_effective: float | None = None
    parameters: dict = field(default_factory=dict)
    accepted: bool = False
    note: str = ""
    validation_records: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """JSON-ready evidence."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


# ---------------------------------------------------------------------------
# evidence


def _corr(a, b) -> float:
    a = a - a.mean()
    b = b - b.mean()
    den = math.sqrt(float(a @ a) * float(b @ b))
    return float(a @ b / den) if den > 0 else 0.0


def signatures(result: CalibrationResult) -> dict:
    """Correlations of the calibration residual with simple effect signatures [-].

    sign(v) (Coulomb friction), a (a moving mass), a constant (the share of
    the residual's RMS in its mean: a load-cell offset), the dead-band
    indicator sign(v) * exp(-|y - y_reversal| / (0.05 Y)) (freeplay and
    pre-sliding after each reversal), and the low-pressure phases
    (where the lower chamber pressure is within 20 % of its minimum).
    """
    recs = result.calibration
    r = np.concatenate(result.residuals("calibration"))
    v = np.concatenate([rec.velocity for rec in recs])
    a = np.concatenate([rec.acceleration for rec in recs])
    dead = []
    for rec in recs:
        y = rec.smoothed - rec.offset
        rev = np.where(rec.velocity > 0, y.min(), y.max())
        dead.append(np.sign(rec.velocity) * np.exp(-np.abs(y - rev) / (0.05 * rec.amplitude)))
    out = {"sign(v)": _corr(r, np.sign(v)), "acceleration": _corr(r, a),
           "constant": float(r.mean() / max(np.sqrt(np.mean(r * r)), 1e-300)),
           "dead band": _corr(r, np.concatenate(dead))}
    m = result.device_model
    if m.pressures is not None:
        low = []
        for rec in recs:
            resp = simulate_record(m, result.params, rec, options=FIT_OPTIONS)
            pl = np.minimum(resp.p1, resp.p2)
            span = max(float(np.ptp(pl)), 1e-9)
            low.append(((pl - pl.min()) < 0.2 * span).astype(float))
        out["low pressure"] = _corr(np.abs(r), np.concatenate(low))
    return out


def score(name: str, result: CalibrationResult, options, preroll: int, *,
          route: str = "auto"):
    """Score test of one candidate against a calibrated model.

    Parameters
    ----------
    name : str
        Catalogue effect or composite candidate (:data:`COMPOSITES`).
    result : CalibrationResult
        The current calibrated model.
    options : SolverOptions
        Solver options of the probe run.
    preroll : int
        Pre-roll passes of the probe run.
    route : str
        Route of the probe run to each record's periodic orbit
        (:func:`~liquidamp.analysis.measured.record_model.simulate_record`;
        ``"no_shooting"``: a probe the march does not bring to its orbit is not scored,
        as one whose shooting fails, without the Newton shooting's runs).

    Returns
    -------
    (Candidate, Change)
        The evidence (linearized relative drop of the calibration RSS, correlation with the
        residual, linearized value of the lead parameter) and the change it was computed
        with (:func:`~.candidates.candidate_change`).  A candidate whose probe model
        reaches no periodic orbit on a calibration record
        (:data:`~liquidamp.analysis.measured.record_model.NOT_PERIODIC`) scores 0, with a
        note saying so (its force follows where the march started, not the parameters).
    """
    change = candidate_change(name, result)
    resp = []
    try:
        Fp = predict(result.model, change.params or result.params, change.effects,
                     result.calibration, options=options, preroll=preroll, responses=resp,
                     route=route)
    except LiquidampError as exc:
        return Candidate(name, 0.0, 0.0, {}, note=f"probe run failed: {exc}"), change
    off = [w for r in resp if r.solver_stats.get("route") == NOT_PERIODIC for w in r.warnings]
    if off:
        # its force follows where the march started, not the parameters alone: neither the
        # signature nor a least-squares fit of it is evidence (a refit ends above its start)
        return Candidate(name, 0.0, 0.0, {}, note="not scored: the model with it reaches no "
                         "periodic orbit on the calibration records (" + "; ".join(off)
                         + ")"), change
    meas = np.concatenate([r.force for r in result.calibration])
    scale = float(np.sqrt(np.mean((meas - meas.mean()) ** 2))) * math.sqrt(meas.size)
    r = (np.concatenate(result.predictions_calibration) - meas) / scale
    s = (np.concatenate(Fp) - np.concatenate(result.predictions_calibration)) / scale
    J, P = _free_projector(result, r)
    s_perp = s - J @ (P @ s) if J.size else s
    ss = float(s_perp @ s_perp)
    rss = float(r @ r)
    if ss <= 1e-30 * max(float(s @ s), 1e-300):
        return Candidate(name, 0.0, _corr(r, s), {}, note="signature fully mimicked by the "
                         "fitted parameters"), change
    beta = -float(s_perp @ r) / ss
    drop = (float(s_perp @ r) ** 2 / ss) / rss if rss > 0 else 0.0
    ok = beta > 0 or change.signed
    eff, key = change.lead
    label = key if eff in (change.added, "device") else f"{eff}.{key}"
    est = {label: change.estimate(beta)} if ok else {}
    note = "" if ok else "the residual asks for a negative strength"
    return Candidate(name, drop if ok else 0.0, -_corr(r, s), est, note=note), change


_PROJECTOR: list = []


def _free_projector(result: CalibrationResult, r):
    """The free Jacobian columns of ``result`` (:func:`~.candidates.free_columns`) and their
    pseudo-inverse, computed once per calibrated model: every candidate of a screen is
    projected on the same columns (the last model's kept)."""
    if _PROJECTOR and _PROJECTOR[0] is result:
        return _PROJECTOR[1], _PROJECTOR[2]
    J = free_columns(result, r)
    P = np.linalg.pinv(J) if J.size else J
    _PROJECTOR[:] = [result, J, P]
    return J, P


_PARTNERS = {"inv_gamma": ("inv_gamma1", "inv_gamma2"), "c1": ("c1",), "S_t": ("S_t",)}


def confounding(effect: str, before: CalibrationResult, after: CalibrationResult) -> dict:
    """Evidence that a fitted device parameter mimics ``effect`` (CONFOUNDED pairs).

    For each pair listed in :data:`CONFOUNDED`: the partner multipliers before and
    after the effect was added (how far the fit moved them to make room), the
    correlation of the effect's parameter with them in the refit, and the validation
    NRMSE of the partner alone (the model before) and with the effect.
    """
    out = {}
    for (eff, partner), why in CONFOUNDED.items():
        if eff != effect:
            continue
        names = [n for n in _PARTNERS.get(partner, (partner,)) if n in after.varying]
        keys = [f"{effect}.{k}" for k in EFFECTS[effect].fit_keys if
                f"{effect}.{k}" in after.varying]
        corr = {}
        for k in keys:
            i = after.varying.index(k)
            for n in names:
                corr[n] = float(after.correlation[i, after.varying.index(n)])
        out[partner] = {
            "reason": why,
            "partner_fitted": bool(names),
            "multipliers_before": {n: before.values.get(n) for n in names},
            "multipliers_after": {n: after.values.get(n) for n in names},
            "correlation_with_effect": corr,
            "validation_nrmse_partner_only": before.nrmse_validation,
            "validation_nrmse_with_effect": after.nrmse_validation,
        }
    return out


def harmonic_structure(result: CalibrationResult, noise_std: float) -> str:
    """The residual's harmonics of the excitation (1-10) above 10x their noise level [N].

    ``noise_std`` is the residual noise per sample [N]; a harmonic amplitude's noise
    level is noise_std sqrt(2 / N).  Returns '' when none stands out.
    """
    parts = []
    for rec, res in zip(result.calibration, result.residuals("calibration"), strict=True):
        t = rec.time - rec.time[0]
        w = 2 * math.pi * rec.frequency
        amps = []
        for k in range(1, 11):
            if k * rec.frequency > 0.4 * rec.sampling_rate:
                break
            A = np.column_stack((np.sin(k * w * t), np.cos(k * w * t)))
            c, *_ = np.linalg.lstsq(A, res - res.mean(), rcond=None)
            amps.append(float(np.hypot(*c)))
        level = noise_std * math.sqrt(2.0 / t.size)
        big = [(k + 1, a) for k, a in enumerate(amps) if a > 10.0 * level]
        if big:
            parts.append(f"{rec.label}: residual harmonics " + ", ".join(
                f"{k}x: {a:.3g} N" for k, a in big) + f" (noise level {level:.2g} N)")
    return "; ".join(parts)


def _multiplier(value) -> str:
    """A partner's multiplier [-] as text: 'held' where the model did not fit it (None).

    >>> _multiplier(1.234567), _multiplier(None)
    ('1.23', 'held')
    """
    return "held" if value is None else f"{value:.3g}"


def confounding_warnings(effect: str, before: CalibrationResult,
                         after: CalibrationResult) -> list[str]:
    """The warnings of :func:`confounding`'s evidence: a tie, or separated by held-out data."""
    out = []
    for partner, ev in confounding(effect, before, after).items():
        if not ev["partner_fitted"]:
            out.append(
                f"confounded: {effect} with {partner} (held fixed): {ev['reason']}; "
                f"if {partner} is wrong, the {effect} parameter absorbs its error")
            continue
        # a partner the model before held (None: not among its fitted parameters) and the
        # refit freed beside the effect (a device refinement), as held
        moved = ", ".join(f"{n} {_multiplier(ev['multipliers_before'][n])} -> "
                          f"{_multiplier(ev['multipliers_after'][n])}"
                          for n in ev["multipliers_before"])
        cc = ", ".join(f"{n} {c:+.2f}" for n, c in ev["correlation_with_effect"].items())
        # a tie only where the effect does not clearly beat its partner on held-out data
        separated = (ev["validation_nrmse_with_effect"]
                     <= 0.5 * ev["validation_nrmse_partner_only"])
        verdict = (f"separated: {effect} and {partner} (fitted) can mimic each "
                   "other, but the held-out records tell them apart"
                   if separated else
                   f"tie: {effect} and {partner} (fitted) may explain the residual "
                   "about equally")
        out.append(
            f"{verdict}: {ev['reason']}; evidence: validation NRMSE "
            f"{ev['validation_nrmse_partner_only']:.4g} with {partner} alone, "
            f"{ev['validation_nrmse_with_effect']:.4g} with {effect}; "
            f"{moved}; correlation with the effect's parameter: {cc or 'n/a'}")
    return out


