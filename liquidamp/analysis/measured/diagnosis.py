"""Residual diagnosis: trace what a calibrated model misses to a catalogue effect, add it.

The loop (what the paper did by hand in Sec. IV.C, where the residual
pointed to friction and then to friction that changes gradually near zero
velocity):

1. Calibrate the model (:func:`liquidamp.analysis.measured.calibration.calibrate`).
2. Stop if the calibration residual is noise: NRMSE below
   ``noise_factor`` (1.5) times the noise floor estimated from the records
   (:func:`liquidamp.analysis.measured.record_quality.noise_floor`).
3. Screen every applicable candidate effect by a score test: the model is
   run once with the effect at a probe strength scaled to the record; the
   change of force is the effect's signature s.  With J the Jacobian of the
   calibrated fit, the part of s that the fitted parameters cannot mimic is
   s_perp = s - J J^+ s (J without the columns of parameters held at a bound
   by the residual: the fit cannot move them), and the linearized drop of the residual sum of
   squares from adding the effect is (s_perp . r)^2 / |s_perp|^2 (a
   Lagrange-multiplier test).  A signature that would need a negative
   strength scores zero.  Simple signatures (correlation of the residual
   with sign(v), a, a constant, the dead-band indicator and the low-pressure
   phases) are reported too.
4. Refit the ``top`` candidates with everything free, starting from the
   linearized strength (cavitation: from the probe's vapour pressure, a
   threshold); when none of these refits brings the calibration
   residual down to ``structure_factor`` times the noise floor, refit also the
   next candidate if its score is within a factor ``score_ratio`` (3) of the best
   (the score test is local: where the calibrated model sits in another basin of
   the c1/c2 trade-off, an effect whose signature overlaps a free parameter's,
   such as leakage and c1, can score below a rival and still fit far better once
   the parameters move).  When a refit still leaves a residual above
   ``structure_factor`` times the noise floor, the candidate is refitted once
   more from the physics start of the original multipliers and the better
   fit is kept (the continuation can stay in a local minimum of the c1/c2
   trade-off).  A fit that stops on its evaluation budget (the baseline or a
   refit) is continued once before it is scored or judged; fits that still
   did not converge are listed in ``warnings`` and in the JSON
   (``converged``, ``not_converged``).
5. Accept the best refit only if it reduces the held-out (validation)
   NRMSE by more than ``rel_threshold`` (10 %) relative AND lowers the
   calibration BIC by more than ``bic_threshold`` (10, "very strong"
   evidence on Kass and Raftery's scale).  If the runner-up also passes and
   its validation NRMSE lies within ``tie_tolerance`` (10 %) of the best's,
   the step records a tie with both sets of evidence and adds the tied
   candidate with the lowest BIC (parsimony: Coulomb friction over a
   smooth friction whose fitted pre-sliding stiffness is huge).
6. Repeat from 2 with the effect included, at most ``max_steps`` times.

When the loop ends with the residual above ``structure_factor`` (2) times
the noise floor, the diagnosis says that structure remains that no candidate
explains (``Diagnosis.unexplained``), listing the residual's harmonics of the
excitation that stand out from their noise level.

Effects records cannot tell apart in this model family are listed in
:data:`CONFOUNDED` with the reason; when such an effect is added, the step
carries the evidence (``Step.confounded``: the partner multipliers before and
after, their correlation with the effect's parameter, the validation NRMSE
of the partner alone and with the effect) and ``warnings`` reports the tie
instead of choosing silently.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C.
.. [2] R. E. Kass, A. E. Raftery, "Bayes factors", JASA 90(430), 1995.
.. [3] C. R. Rao, "Large sample tests of statistical hypotheses concerning
   several parameters...", Proc. Camb. Phil. Soc. 44, 1948 (score test).
"""

from __future__ import annotations

import math
import warnings as _warnings
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.measured.calibration import (
    FIT_OPTIONS,
    CalibrationResult,
    FitSpec,
    calibrate,
    check_records,
    predict,
)
from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.analysis.measured.record_quality import noise_floor
from liquidamp.device.effects import EFFECTS, Effect, with_effects
from liquidamp.errors import (
    ConvergenceError,
    LiquidampError,
    LiquidampWarning,
    ParameterError,
    check_choice,
)
from liquidamp.options import resolve_options

__all__ = ["Candidate", "Step", "Diagnosis", "diagnose", "CONFOUNDED", "signatures", "demo_loop",
           "bundled_records"]

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
        Calibration BIC change (negative favours the effect).
    parameters : dict
        Fitted effect parameters (SI) after the refit.
    accepted : bool
        Passed both thresholds.
    note : str
        Why not applicable, or what happened in the refit.
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
    parameters: dict = field(default_factory=dict)
    accepted: bool = False
    note: str = ""

    def as_dict(self) -> dict:
        """JSON-ready evidence."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


@dataclass(frozen=True)
class Step:
    """One accepted addition."""

    effect: str
    parameters: dict
    nrmse_calibration: float
    nrmse_validation: float | None
    candidates: tuple
    tie: tuple = ()
    result: CalibrationResult | None = field(default=None, repr=False)
    confounded: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """JSON-ready step (``fit``: whether the refit converged; ``confounded``: evidence
        that a fitted device parameter mimics the effect, see :data:`CONFOUNDED`)."""
        fit = ({"converged": self.result.converged, "status": self.result.status,
                "message": self.result.message, "nfev": self.result.nfev}
               if self.result is not None else {})
        return {"effect": self.effect, "parameters": self.parameters,
                "nrmse": {"calibration": self.nrmse_calibration,
                          "validation": self.nrmse_validation},
                "fit": fit, "tie": list(self.tie), "confounded": self.confounded,
                "evidence": [c.as_dict() for c in self.candidates]}


@dataclass(frozen=True, eq=False)
class Diagnosis:
    """Result of :func:`diagnose`.

    Attributes
    ----------
    baseline : CalibrationResult
        The calibrated model as given.
    steps : tuple of Step
        Effects added, in order.
    final : CalibrationResult
        The last calibrated model.
    noise_nrmse : float
        Noise floor of the calibration records, as an NRMSE [-].
    signatures : dict
        Simple residual signatures of the baseline (name -> correlation).
    stop_reason : str
        Why the loop stopped.
    unexplained : str
        Non-empty when structure remains that no candidate explains.
    warnings : tuple of str
        Ties, non-converged fits.
    last_candidates : tuple of Candidate
        Evidence of the final, rejected round.
    """

    baseline: CalibrationResult
    steps: tuple
    final: CalibrationResult
    noise_nrmse: float
    signatures: dict
    stop_reason: str
    unexplained: str
    warnings: tuple
    last_candidates: tuple

    @property
    def added(self) -> tuple[str, ...]:
        """Names of the effects added."""
        return tuple(s.effect for s in self.steps)

    def as_dict(self) -> dict:
        """JSON: baseline, steps, final (see the diagnose command)."""
        def block(res):
            d = res.as_dict()
            return {"parameters": res.parameters_dict(),
                    "nrmse": {"calibration": res.nrmse_calibration,
                              "validation": res.nrmse_validation},
                    "fit": d["fit"], "summary": d["summary"], "start": d["start"],
                    "parameter_flags": d["parameter_flags"], "records": d["records"],
                    "fit_warnings": d["warnings"]}
        fits = [("baseline", self.baseline)] + [(f"step {i + 1}: + {s.effect}", s.result)
                                                 for i, s in enumerate(self.steps)
                                                 if s.result is not None]
        not_conv = [{"fit": lab, "status": r.status, "message": r.message, "nfev": r.nfev}
                    for lab, r in fits if not r.converged]
        return {"baseline": block(self.baseline), "steps": [s.as_dict() for s in self.steps],
                "final": block(self.final), "converged": not not_conv,
                "not_converged": not_conv, "noise_floor_nrmse": self.noise_nrmse,
                "signatures": self.signatures, "stop_reason": self.stop_reason,
                "unexplained": self.unexplained, "warnings": list(self.warnings),
                "last_round": [c.as_dict() for c in self.last_candidates]}


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


def _probe(name: str, result: CalibrationResult) -> Effect:
    """The effect at a probe strength scaled to the records and the calibrated model."""
    recs = result.calibration
    F = np.concatenate([r.force for r in recs])
    Fa = math.sqrt(2.0) * float(np.sqrt(np.mean((F - F.mean()) ** 2)))
    Y = float(np.mean([r.amplitude for r in recs]))
    w = 2 * math.pi * float(np.mean([r.frequency for r in recs]))
    p = result.params
    cls = EFFECTS[name]
    if name == "coulomb_friction":
        return cls(force_N=0.05 * Fa)
    if name == "smooth_friction":
        return cls(force_N=0.05 * Fa, stiffness_N_per_m=0.05 * Fa / (0.05 * Y))
    if name == "force_offset":
        return cls(offset_N=0.02 * Fa)
    if name == "moving_mass":
        return cls(mass_kg=0.05 * Fa / (w * w * Y))
    if name == "series_compliance":
        return cls(stiffness_N_per_m=10.0 * Fa / Y)
    if name == "freeplay":
        return cls(gap_m=0.03 * Y)
    if name == "leakage":
        Q = p.A_p * w * Y
        return cls(coefficient_m3_per_s_Pa=0.3 / (p.c1 + 8.0 / (3.0 * math.pi) * p.c2 * Q))
    if name == "cavitation":
        resp = simulate_record(result.device_model, p, recs[0], options=FIT_OPTIONS)
        pmin = float(min(resp.p1.min(), resp.p2.min()))
        return cls(vapour_pressure_Pa=max(pmin + 0.3 * (p.p0 - pmin), 1.0))
    return cls.probe(Fa, Y, w, p)  # the other catalogue effects state their own probe


def _free_columns(result, r, tol: float = 1e-3):
    """Jacobian columns of the fitted parameters that can still move to mimic an effect.

    A parameter held at a bound by the residual (within ``tol`` of it in the fit
    coordinate, with the descent direction -J^T r pointing out of the bounds) is
    effectively fixed at the constrained optimum (Kuhn-Tucker): the fit cannot move it
    to absorb an effect's signature, so its column must not be projected out of the
    signature.  Otherwise a parameter stuck at its bound in the direction the missing
    effect pulls it (c1 at its lower bound for a bypass leak) hides the effect from the
    score test.
    """
    J = result.jacobian
    if not J.size:
        return J
    g = J.T @ r
    keep = []
    for i, name in enumerate(result.varying):
        p = result.spec[name]
        lo, hi = p.x_bounds()
        x = p.to_x(result.values[name])
        pinned = (x - lo < tol and g[i] > 0) or (hi - x < tol and g[i] < 0)
        if not pinned:
            keep.append(i)
    return J[:, keep]


def _score(name, result, options, preroll):
    """Score test of one candidate: (Candidate, probe effect)."""
    probe = _probe(name, result)
    try:
        Fp = predict(result.model, result.params, result.effects + (probe,),
                     result.calibration, options=options, preroll=preroll)
    except LiquidampError as exc:
        return Candidate(name, 0.0, 0.0, {}, note=f"probe run failed: {exc}"), probe
    meas = np.concatenate([r.force for r in result.calibration])
    scale = float(np.sqrt(np.mean((meas - meas.mean()) ** 2))) * math.sqrt(meas.size)
    r = (np.concatenate(result.predictions_calibration) - meas) / scale
    s = (np.concatenate(Fp) - np.concatenate(result.predictions_calibration)) / scale
    J = _free_columns(result, r)
    s_perp = s - J @ (np.linalg.pinv(J) @ s) if J.size else s
    ss = float(s_perp @ s_perp)
    rss = float(r @ r)
    if ss <= 1e-30 * max(float(s @ s), 1e-300):
        return Candidate(name, 0.0, _corr(r, s), {}, note="signature fully mimicked by the "
                         "fitted parameters"), probe
    beta = -float(s_perp @ r) / ss
    score = (float(s_perp @ r) ** 2 / ss) / rss if rss > 0 else 0.0
    key = probe.fit_keys[0]
    signed_ok = beta > 0 or name == "force_offset"
    est = {key: getattr(probe, key) * beta} if signed_ok else {}
    note = "" if signed_ok else "the residual asks for a negative strength"
    return Candidate(name, score if signed_ok else 0.0, -_corr(r, s), est, note=note), probe


def _applicable(name, model) -> str:
    try:
        with_effects(model, EFFECTS[name]())
    except ParameterError as exc:
        return str(exc)
    return ""


def _refit(cand, probe, current, validation, options, preroll, max_nfev, tol, restart=None):
    cls = EFFECTS[cand.effect]
    start = {}
    for key in cls.fit_keys:
        v = cand.estimate.get(key, getattr(probe, key))
        if cand.effect == "cavitation":
            # a threshold, not a strength: the linearized value can fall below the lowest
            # chamber pressure, where the effect is inactive and the fit has no gradient
            v = getattr(probe, key)
        lo, hi = cls.bounds[key]
        if lo > 0:
            v = min(max(abs(v), lo * 10), hi / 10)
        start[key] = v
    effect = probe.replace(**start)
    spec = FitSpec(current.spec.parameters).with_effect(effect)
    res = calibrate(current.calibration, model=current.model, params=current.start_params,
                    effects=current.effects + (effect,), spec=spec, validate=validation,
                    options=options, start="spec", max_nfev=max_nfev, preroll=preroll,
                    tol=tol, warn=False)
    if restart is not None and res.nrmse_calibration > restart[1]:
        # residual still structured: the continuation from the previous optimum may sit in a
        # local minimum of the loss coefficients (the c1/c2 trade-off: least squares on the
        # air ratios and loss coefficients has local minima); refit
        # from the physics start of the original multipliers too and keep the better fit
        spec2 = spec.with_values(restart[0])
        try:
            res2 = calibrate(current.calibration, model=current.model,
                             params=current.start_params, effects=current.effects + (effect,),
                             spec=spec2, validate=validation, options=options,
                             start="physics", max_nfev=max_nfev, preroll=preroll, tol=tol,
                             warn=False)
        except ConvergenceError:
            return res
        if res2.cost < res.cost:
            return res2
    return res


def _converge(result, validation, options, preroll, max_nfev, tol):
    """Continue a fit that stopped on its evaluation budget from where it stopped."""
    return calibrate(result.calibration, model=result.model, params=result.start_params,
                     effects=result.effects, spec=result.spec, validate=validation,
                     options=options, start="spec", max_nfev=max_nfev, preroll=preroll,
                     tol=tol, warn=False)


_PARTNERS = {"inv_gamma": ("inv_gamma1", "inv_gamma2"), "c1": ("c1",), "S_t": ("S_t",)}


def _confounding(effect: str, before: CalibrationResult, after: CalibrationResult) -> dict:
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


def _harmonic_structure(result: CalibrationResult, noise_std: float) -> str:
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


def diagnose(calibration, validation, *, model="full", params=None, effects=(),
             candidates=None, spec: FitSpec | None = None, options=None, max_steps: int = 3,
             top: int = 2, rel_threshold: float = 0.10, bic_threshold: float = 10.0,
             tie_tolerance: float = 0.10, noise_factor: float = 1.5,
             structure_factor: float = 2.0, score_ratio: float = 3.0, max_nfev: int = 60,
             preroll: int = 1, tol: float = 1e-5,
             baseline: CalibrationResult | None = None) -> Diagnosis:
    """Calibrate, then add catalogue effects while the held-out error improves (module doc).

    Parameters
    ----------
    calibration, validation : sequence of Record
        Records to fit and held-out records to judge by (at least one each).
    model, params, effects, spec, options, preroll
        As for :func:`~liquidamp.analysis.measured.calibration.calibrate` (default:
        ``full`` from ``paper_initial`` with the paper's four multipliers free).
    candidates : sequence of str, optional
        Effects to consider (default: the catalogue effects with ``screened`` set
        and fitted parameters, ``fit_keys``; the others, e.g. ``relief_valve``,
        only when named here; operating conditions such as ``rotating_frame`` are
        given, not diagnosed).
    max_steps : int
        Largest number of effects added.
    top : int
        Candidates refitted per step at least (the best scores).
    score_ratio : float
        When the ``top`` refits leave the residual structured, the next candidate is
        refitted too if its score is at least 1/``score_ratio`` of the best
        (module doc, step 4).
    rel_threshold, bic_threshold, tie_tolerance, noise_factor, structure_factor : float
        Decision thresholds (module doc).
    max_nfev : int
        Evaluation budget of each fit.
    tol : float
        Fit tolerance (ftol = xtol of least squares).
    baseline : CalibrationResult, optional
        A calibration already done for the same inputs.

    Returns
    -------
    Diagnosis

    Raises
    ------
    DataFileError
        Before any model run, as :func:`~liquidamp.analysis.measured.calibration.check_records`:
        a record with no force response above its noise, a stroke past the
        chamber end (``params.stroke_limit``), or a spike in the force or the
        displacement (record and line named).  Drop force spikes with
        ``calibrate(..., outliers="drop")`` and pass that result as ``baseline``
        only after correcting the file: the diagnosis scores effects on the
        whole record.

    Warns
    -----
    LiquidampWarning
        With each of ``Diagnosis.warnings``.
    """
    calibration, validation = tuple(calibration), tuple(validation)
    if not validation:
        raise ParameterError("diagnose needs held-out validation records (--validate)")
    if params is None:
        from liquidamp.device import preset

        check_params = preset("paper_initial")
    else:
        check_params = params
    # before any model run: noise-only records, spikes (a 30 mm displacement spike made
    # the integration crawl for minutes) and a stroke past the chamber end are refused
    check_records(calibration + validation, check_params, what="diagnose")
    names = (tuple(n for n, c in EFFECTS.items() if c.screened and c.fit_keys)
             if candidates is None
             else tuple(candidates))
    for n in names:
        check_choice("candidate effect", n, EFFECTS)
        if not EFFECTS[n].fit_keys:
            raise ParameterError(
                f"candidate effect {n!r} has no fitted parameters (an operating condition): "
                "give it with effects=, not as a candidate")
    options = resolve_options(options, "fit")
    if baseline is None:
        baseline = calibrate(calibration, model=model, params=params, effects=effects,
                             spec=spec, validate=validation, options=options,
                             max_nfev=max_nfev, preroll=preroll, tol=tol, warn=False)
    warnings = []
    if baseline.status == "max_nfev":
        # score candidates only against a converged model: a fit stopped on its budget
        # leaves structure that a candidate would "explain" spuriously
        baseline = _converge(baseline, validation, options, preroll, max_nfev, tol)
    if not baseline.converged:
        warnings.append(f"NOT CONVERGED: baseline calibration ({baseline.status}): "
                        f"{baseline.message}")
    meas = np.concatenate([r.force for r in calibration])
    den = float(np.sqrt(np.mean((meas - meas.mean()) ** 2)))
    floors = [noise_floor(r) for r in calibration]
    noise_std = float(np.sqrt(np.mean([f.force_std ** 2 for f in floors])))
    noise_nrmse = noise_std / den
    sig = signatures(baseline)
    spec0 = baseline.spec if spec is None else spec
    start0 = {p.name: (spec0[p.name].value if p.name in spec0.names else 1.0)
              for p in baseline.spec.parameters if p.kind == "multiplier"}
    if spec is None:
        start0 = dict.fromkeys(start0, 1.0)
    restart = (start0, structure_factor * noise_nrmse)
    current = baseline
    steps = []
    stop = f"max_steps = {max_steps} reached"
    last_round: tuple = ()
    for _ in range(max_steps):
        if current.nrmse_calibration <= noise_factor * noise_nrmse:
            stop = (f"residual is noise: calibration NRMSE {current.nrmse_calibration:.4g} <= "
                    f"{noise_factor:g} x noise floor {noise_nrmse:.4g}")
            break
        present = {e.name for e in current.effects}
        dm = current.device_model
        round_ = []
        probes = {}
        for n in names:
            if n in present:
                continue
            why = _applicable(n, dm)
            if why:
                round_.append(Candidate(n, 0.0, 0.0, {}, note=f"not applicable: {why}"))
                continue
            cand, probe = _score(n, current, options, preroll)
            probes[n] = probe
            round_.append(cand)
        ranked = sorted(round_, key=lambda c: -c.score)
        refits = {}
        scored = [c for c in ranked if c.score > 0]
        # the score test is local: at a calibrated model that sits in another basin of the
        # c1/c2 trade-off, an effect whose signature overlaps a free parameter's can score
        # below a rival and still fit far better once the parameters move; so when the
        # ``top`` refits leave the calibration residual structured (above
        # ``structure_factor`` x the noise floor), the next candidate is refitted too if
        # it scores within ``score_ratio`` of the best
        extra = [c for c in scored[top:top + 1] if c.score * score_ratio >= scored[0].score]
        queue = scored[:top]
        while queue:
            for cand in queue:
                try:
                    res = _refit(cand, probes[cand.effect], current, validation, options,
                                 preroll, max_nfev, tol, restart)
                    if res.status == "max_nfev":
                        res = _converge(res, validation, options, preroll, max_nfev, tol)
                except (ConvergenceError, ParameterError) as exc:
                    i = ranked.index(cand)
                    ranked[i] = _with(cand, refitted=True, note=f"refit failed: {exc}")
                    continue
                rel = 1.0 - res.nrmse_validation / current.nrmse_validation
                dbic = res.bic - current.bic
                acc = bool(rel > rel_threshold and dbic < -bic_threshold)
                note = "" if res.converged else f"refit: {res.message}"
                i = ranked.index(cand)
                ranked[i] = _with(cand, refitted=True,
                                  nrmse_calibration=res.nrmse_calibration,
                                  nrmse_validation=res.nrmse_validation,
                                  relative_reduction=rel, delta_bic=dbic, accepted=acc,
                                  note=note, parameters=next(e.parameters for e in res.effects
                                                             if e.name == cand.effect))
                refits[cand.effect] = res
            explained = any(r.nrmse_calibration <= structure_factor * noise_nrmse
                            for r in refits.values())
            queue, extra = ([], []) if explained else (extra, [])
        last_round = tuple(ranked)
        passed = sorted([c for c in ranked if c.accepted], key=lambda c: c.nrmse_validation)
        if not passed:
            best = next((c for c in ranked if c.refitted), None)
            stop = ("no candidate improves the held-out error meaningfully"
                    + (f" (best: {best.effect}, validation NRMSE change "
                       f"{-(best.relative_reduction or 0):+.1%}, dBIC "
                       f"{best.delta_bic if best.delta_bic is not None else float('nan'):.3g})"
                       if best else ""))
            break
        tied = [c for c in passed
                if c.nrmse_validation <= (1 + tie_tolerance) * passed[0].nrmse_validation]
        chosen = min(tied, key=lambda c: c.delta_bic)  # parsimony among the tied
        tie = ()
        if len(tied) > 1:
            tie = tuple(c.effect for c in tied)
            warnings.append(
                "tie: " + " and ".join(
                    f"{c.effect} (validation NRMSE {c.nrmse_validation:.4g}, dBIC "
                    f"{c.delta_bic:.4g})" for c in tied)
                + f" explain the residual about equally (validation NRMSE within "
                f"{tie_tolerance:.0%}); {chosen.effect} was added (lowest BIC)")
        res = refits[chosen.effect]
        if not res.converged:
            warnings.append(f"NOT CONVERGED: fit with {chosen.effect} ({res.status}): "
                            f"{res.message}")
        conf = _confounding(chosen.effect, current, res)
        for partner, ev in conf.items():
            if not ev["partner_fitted"]:
                warnings.append(
                    f"confounded: {chosen.effect} with {partner} (held fixed): {ev['reason']}; "
                    f"if {partner} is wrong, the {chosen.effect} parameter absorbs its error")
                continue
            moved = ", ".join(f"{n} {ev['multipliers_before'][n]:.3g} -> "
                              f"{ev['multipliers_after'][n]:.3g}"
                              for n in ev["multipliers_before"])
            cc = ", ".join(f"{n} {c:+.2f}" for n, c in ev["correlation_with_effect"].items())
            # a tie only where the effect does not clearly beat its partner on held-out data
            separated = (ev["validation_nrmse_with_effect"]
                         <= 0.5 * ev["validation_nrmse_partner_only"])
            verdict = (f"separated: {chosen.effect} and {partner} (fitted) can mimic each "
                       "other, but the held-out records tell them apart"
                       if separated else
                       f"tie: {chosen.effect} and {partner} (fitted) may explain the residual "
                       "about equally")
            warnings.append(
                f"{verdict}: {ev['reason']}; evidence: validation NRMSE "
                f"{ev['validation_nrmse_partner_only']:.4g} with {partner} alone, "
                f"{ev['validation_nrmse_with_effect']:.4g} with {chosen.effect}; "
                f"{moved}; correlation with the effect's parameter: {cc or 'n/a'}")
        steps.append(Step(chosen.effect, chosen.parameters, res.nrmse_calibration,
                          res.nrmse_validation, tuple(ranked), tie, res, conf))
        current = res
        last_round = ()
    unexplained = ""
    if current.nrmse_calibration > structure_factor * noise_nrmse:
        # said whenever the residual stays well above the noise floor, with the
        # excitation harmonics that stand out when there are any
        h = _harmonic_structure(current, noise_std)
        unexplained = ("residual keeps structure that no candidate explains "
                       f"(calibration NRMSE {current.nrmse_calibration:.3g} vs noise floor "
                       f"{noise_nrmse:.3g}, more than {structure_factor:g} x): "
                       + (h or "no single harmonic of the excitation stands out (broadband "
                          "or non-periodic misfit)"))
    for w in warnings:
        _warnings.warn(f"diagnose: {w}", LiquidampWarning, stacklevel=2)
    return Diagnosis(baseline=baseline, steps=tuple(steps), final=current,
                     noise_nrmse=noise_nrmse, signatures=sig, stop_reason=stop,
                     unexplained=unexplained, warnings=tuple(warnings),
                     last_candidates=last_round)


def _with(c: Candidate, **changes) -> Candidate:
    from dataclasses import replace

    return replace(c, **changes)


def bundled_records() -> dict:
    """Paths of the bundled synthetic records (liquidamp/analysis/measured/data, see its README)."""
    from pathlib import Path

    data = Path(__file__).parent / "data"
    return {p.stem: p for p in sorted(data.glob("*.csv"))}


def demo_loop(out_dir, *, cycles: float = 3.0, top: int = 1) -> dict:
    """Calibrate and diagnose the bundled records end to end; write JSON and an HTML report.

    Calibrates on ``demo_3Hz_3mm`` and validates on ``demo_4Hz_2mm``
    (synthetic: the paper's calibrated device with smooth friction, see
    ``liquidamp/analysis/measured/data/README.md``), each trimmed to its first
    ``cycles`` cycles to keep the run short.

    Returns
    -------
    dict
        ``added`` (effects), ``nrmse`` before/after on both sets, the truth's
        effects, ``report`` (index.html path), ``json`` path, ``seconds``.
    """
    import json
    import time
    from pathlib import Path

    from liquidamp.analysis.measured.records import read_record
    from liquidamp.analysis.reports.report_calibration import write_report

    t0 = time.perf_counter()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = bundled_records()
    cal = read_record(files["demo_3Hz_3mm"]).trimmed(cycles)
    val = read_record(files["demo_4Hz_2mm"]).trimmed(cycles)
    d = diagnose([cal], [val], top=top, max_nfev=40)
    (out / "diagnosis.json").write_text(json.dumps(d.as_dict(), indent=2, default=float))
    report = write_report(out / "report", diagnosis=d, title="liquidamp demo: calibrate and "
                          "diagnose the bundled records")
    truth = json.loads(files["demo_3Hz_3mm"].with_suffix(".json").read_text())["effects"]
    return {
        "added": list(d.added),
        "parameters": [s.parameters for s in d.steps],
        "truth_effects": truth,
        "nrmse": {"baseline": {"calibration": d.baseline.nrmse_calibration,
                               "validation": d.baseline.nrmse_validation},
                  "final": {"calibration": d.final.nrmse_calibration,
                            "validation": d.final.nrmse_validation}},
        "stop_reason": d.stop_reason,
        "warnings": list(d.warnings),
        "report": str(report),
        "json": str(out / "diagnosis.json"),
        "seconds": time.perf_counter() - t0,
    }
