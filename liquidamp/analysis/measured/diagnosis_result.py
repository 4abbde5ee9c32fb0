"""What :func:`~liquidamp.analysis.measured.diagnosis.diagnose` returns: steps and the verdict.

:class:`Diagnosis` holds the baseline, the steps, the final fit, the evidence of the last
round, the reference models fitted on the same split
(:mod:`~liquidamp.analysis.measured.reference_models`) and the cycle drift of every record
(:mod:`~liquidamp.analysis.measured.stationarity`).  Its :meth:`Diagnosis.summary` leads
with what a user must know first: a non-stationary record, a residual that no candidate
explains, a physics model that does not beat the line F = c v + k y + F0 (or the dyno's
two-slope force-velocity map) on held-out records; then the held-out NRMSE record by
record, the pooled figure beside it.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from liquidamp.analysis.measured.calibration_result import CalibrationResult
from liquidamp.analysis.measured.reference_models import comparison
from liquidamp.analysis.measured.selection import Verdict, judge, sample_count

__all__ = ["Step", "Diagnosis", "heldout_per_record"]


def heldout_per_record(result: CalibrationResult) -> dict:
    """Record label -> held-out NRMSE of a calibrated model [-] (its validation records)."""
    return {e.label: e.nrmse for e in result.record_errors if e.role == "validation"}


def judge_fits(current: CalibrationResult, new: CalibrationResult, sel) -> Verdict:
    """The selection rule ``sel`` on fit ``new`` against the model held ``current``.

    :func:`~liquidamp.analysis.measured.selection.judge` on their calibration residuals
    [N], the parameters ``new`` frees beyond ``current``, each held-out record of
    ``current`` (NRMSE [-], record by record), ``sel``'s BIC threshold and validation
    tolerance, and the samples counted as ``sel.sample_count`` says on ``new``'s records
    (:func:`~liquidamp.analysis.measured.selection.sample_count`): the one comparison of
    two fits every stage of the diagnosis makes (a round's refits, the profile restart, a
    device credited with a refit's fall, an alternative class start).

    Parameters
    ----------
    current, new : CalibrationResult
        The model held and the one judged (same calibration and validation records).
    sel : SelectionRule
        ``bic_threshold``, ``validation_tolerance``, ``sample_count``.

    Returns
    -------
    Verdict
    """
    now, then = heldout_per_record(current), heldout_per_record(new)
    return judge(current.residuals("calibration"), new.residuals("calibration"),
                 len(new.varying) - len(current.varying), [now[k] for k in now],
                 [then[k] for k in now], bic_threshold=sel.bic_threshold,
                 validation_tolerance=sel.validation_tolerance,
                 n_eff=sample_count(new.calibration, new.residuals("calibration"),
                                    sel.sample_count))


@dataclass(frozen=True)
class Step:
    """One accepted addition (an effect, or a device step: a device parameter freed, or a
    refit's device kept without an effect whose force the noise hides, ``note`` saying
    why: :mod:`~liquidamp.analysis.measured.diagnosis_credit`)."""

    effect: str
    parameters: dict
    nrmse_calibration: float
    nrmse_validation: float | None
    candidates: tuple
    tie: tuple = ()
    result: CalibrationResult | None = field(default=None, repr=False)
    confounded: dict = field(default_factory=dict)
    profile: dict = field(default_factory=dict)
    note: str = ""

    def fitted_parameters(self) -> dict:
        """The step's parameters its refit varied (all of them where the refit is not
        kept): a measured temperature leaves a heat capacity at its default, which is not
        a finding."""
        if self.result is None:
            return dict(self.parameters)
        vary = set(self.result.varying)
        out = {k: v for k, v in self.parameters.items()
               if k in vary or f"{self.effect}.{k}" in vary}
        return out or dict(self.parameters)

    def as_dict(self) -> dict:
        """JSON-ready step (``fitted``: the names of the parameters the refit varied;
        ``fit``: whether the refit converged; ``confounded``: evidence that a fitted
        device parameter mimics the effect, see ``CONFOUNDED``; ``heldout_records``:
        held-out NRMSE per record; ``profile``: the profile of a freed parameter the
        records hardly determine, :class:`~.profile.Profile`, empty when none)."""
        fit = ({"converged": self.result.converged, "status": self.result.status,
                "message": self.result.message, "nfev": self.result.nfev}
               if self.result is not None else {})
        per = heldout_per_record(self.result) if self.result is not None else {}
        return {"effect": self.effect, "parameters": self.parameters,
                "fitted": list(self.fitted_parameters()),
                "nrmse": {"calibration": self.nrmse_calibration,
                          "validation": self.nrmse_validation},
                "heldout_records": per,
                "fit": fit, "tie": list(self.tie), "confounded": self.confounded,
                "profile": self.profile, "note": self.note,
                "evidence": [c.as_dict() for c in self.candidates]}


@dataclass(frozen=True, eq=False)
class Diagnosis:
    """Result of :func:`~liquidamp.analysis.measured.diagnosis.diagnose`.

    Attributes
    ----------
    baseline : CalibrationResult
        The calibrated model as given.
    steps : tuple of Step
        Effects added, in order.
    final : CalibrationResult
        The last calibrated model.
    noise_nrmse : float
        Noise floor of the (conditioned) calibration records, as an NRMSE [-].
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
    conditioning : tuple of Conditioning
        What was done to each record before fitting (calibration, then validation).
    noise_floors : tuple of NoiseFloor
        The noise floor of each conditioned calibration record.
    heldout_floors : dict
        Record label -> noise floor NRMSE of each held-out record as conditioned [-]: the
        floors the selection rule judged the held-out records by, about the least held-out
        NRMSE a model can reach there; the summary reads each held-out NRMSE against it.
    nrmse_raw : dict
        ``{"calibration": ..., "validation": ...}``: the final model against the records
        as given (empty when the conditioning changed nothing).
    references : dict
        ``{"line": ReferenceFit, "two_slope": ReferenceFit}`` fitted on the same split.
    drifts : tuple of Drift
        Cycle-to-cycle drift of each periodic record as read.
    non_stationary : str
        Non-empty when a record's force drifts (what and how much).
    options : DiagnoseOptions or None
        The options the diagnosis ran with.
    holdout : str
        How the held-out records were obtained ('' when given).
    device_steps : tuple of Step
        Device parameters the preset held fixed that the rule freed before the effects
        (e.g. ``inertance``: the channel inertance S_t); not effects.
    device_evidence : tuple of Candidate
        The evidence of every device parameter tried.
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
    conditioning: tuple = ()
    noise_floors: tuple = ()
    heldout_floors: dict = field(default_factory=dict)
    nrmse_raw: dict = field(default_factory=dict)
    references: dict = field(default_factory=dict)
    drifts: tuple = ()
    non_stationary: str = ""
    options: object = None
    holdout: str = ""
    device_steps: tuple = ()
    device_evidence: tuple = ()

    @property
    def added(self) -> tuple[str, ...]:
        """Names of the effects added."""
        return tuple(s.effect for s in self.steps)

    @property
    def heldout(self) -> dict:
        """Record label -> held-out NRMSE of the final model [-]."""
        return heldout_per_record(self.final)

    @property
    def without_input(self) -> dict | None:
        """The best fit that does not read the records' control input, beside a model that
        does (the field-controlled device class, issue #20): class, input, NRMSE; None
        where the model reads no input."""
        return (self.baseline.start or {}).get("without_input")

    @property
    def loses_to_line(self) -> str:
        """Where the final physics model does not beat the line held out ('' otherwise)."""
        return comparison(self.heldout, self.references)

    @property
    def loses_to_map(self) -> str:
        """Where the final physics model does not beat the dyno's two-slope force-velocity
        map held out ('' otherwise)."""
        return comparison(self.heldout, self.references, name="two_slope")

    @property
    def device_at_bound(self) -> str:
        """The final model's device multipliers held at a bound of the fit, with their
        values ('' when none) [-]."""
        at = self.final.at_bounds()
        floor = set(self.air_free)
        return ", ".join(f"{n} x{self.final.values[n]:.3g} ({side})" for n, side in at.items()
                         if self.final.spec[n].kind == "multiplier" and n not in floor)

    @property
    def air_free(self) -> tuple[str, ...]:
        """The final model's air ratios at their physical floor
        (:func:`~liquidamp.analysis.measured.fit_spec.air_floor`): chambers without air, to
        within its share of their compliance."""
        from liquidamp.analysis.measured.fit_spec import AIR_RATIOS, air_floor

        fin = self.final
        floor = air_floor(fin.start_params)
        return tuple(n for n, side in fin.at_bounds().items()
                     if n in AIR_RATIOS and side == "lower"
                     and fin.spec[n].min * getattr(fin.start_params, n)
                     <= floor * (1.0 + 1e-6))

    def summary(self) -> str:
        """Lines: the verdict first (a force read negated, non-stationary, unexplained, loses
        to the line; then the effects added and the held-out NRMSE per record, each with its
        ratio to the record's own noise floor (``heldout_floors``; a ratio near 1: the
        record is predicted to its noise), pooled beside), then the reference models held
        out, then why the loop stopped."""
        first = []
        negated = self.baseline.force_negated()
        if negated:
            first.append("FORCE NEGATED: " + negated)
        drifting = [e.name for e in self.final.effects if not e.stationary]
        if self.non_stationary and drifting:
            first.append("NON-STATIONARY: the records drift (" + self.non_stationary + "); "
                         "followed by " + ", ".join(drifting) + ", a drifting model marched "
                         "over each whole record")
        elif self.non_stationary:
            first.append("NON-STATIONARY: the residual is non-stationary (" +
                         self.non_stationary + "); no stationary effect explains a drift, "
                         "and no effect with a parameter at a bound is kept")
        if self.unexplained:
            first.append("UNEXPLAINED: " + self.unexplained.split(": ", 1)[0])
        lose = self.loses_to_line
        if lose:
            first.append("LOSES TO THE LINE: " + lose)
        lose_map = self.loses_to_map
        if lose_map:
            first.append("LOSES TO THE TWO-SLOPE MAP: " + lose_map)
        floors = self.heldout_floors
        per = ", ".join(f"{k} {v:.3g}" + (f" ({v / floors[k]:.2g} x its noise floor)"
                                           if floors.get(k) else "")
                        for k, v in self.heldout.items())
        pooled = self.final.nrmse_validation
        base = heldout_per_record(self.baseline)
        added = (", ".join(f"{s.effect} ({_short(s.fitted_parameters())})"
                           for s in self.steps)
                 or "nothing")
        fy = next((e for e in self.final.effects if e.name == "field_yield"), None)
        if self.baseline.device_class == "field" and fy is not None:
            # the field class starts with the yield on the input: it is found first
            first.append(f"field_yield on the {fy.input} first (the field-controlled class: "
                         f"{_short(fy.parameters)})")
        freed = [s for s in self.device_steps if not s.note]
        if freed:
            added += "; device parameters freed: " + ", ".join(
                f"{s.effect} ({_short(s.parameters)})" for s in freed)
        for s in self.device_steps:
            if s.note:  # a refit's device kept without its negligible effect
                added += f"; device refined: {s.note}"
        first.append(f"added {added}: held-out NRMSE per record {per}"
                     + (f" (pooled {pooled:.3g})" if pooled is not None else "")
                     + "; before: " + ", ".join(f"{k} {v:.3g}" for k, v in base.items()))
        if self.air_free:
            from liquidamp.analysis.measured.fit_spec import AIR_COMPLIANCE_SHARE

            first.append("no air: " + ", ".join(self.air_free) + " at the physical floor "
                         f"(air under {AIR_COMPLIANCE_SHARE:.0%} of the chamber's compliance "
                         "at p0: a degassed chamber)")
        held = self.device_at_bound
        if held:
            first.append("device parameters at a bound: " + held + " (their values are the "
                         "bounds', not the records'; an effect added beside them may stand in "
                         "for what the bound holds back)")
        loose = [s.profile["description"] for s in self.steps
                 if s.profile and (s.profile["open_low"] or s.profile["open_high"])]
        if loose:
            first.append("not determined by the calibration records: " + "; ".join(loose))
        lines = ["; ".join(first)]
        wi = self.without_input
        if wi:
            how = wi.get("model") or f"the best fit ({wi['class']} start)"
            lines.append(f"without the {wi['input']} input: {how}, held out " + ", ".join(
                             f"{k} {v:.3g}" for k, v in wi["validation_records"].items())
                         + f" (pooled {wi['nrmse_validation']:.3g}, calibration "
                         f"{wi['nrmse_calibration']:.3g})")
        if self.references:
            lines.append("reference models held out: " + "; ".join(
                f"{name} " + ", ".join(f"{lab} {v:.3g}" for lab, v in ref.validation)
                for name, ref in self.references.items()))
        lines.append(f"stopped: {self.stop_reason}; noise floor NRMSE {self.noise_nrmse:.3g}")
        if self.holdout:
            lines.append(f"held out: {self.holdout}")
        return "\n".join(lines)

    def bic_samples(self) -> dict:
        """How the selection rule counts samples in the BIC, with each calibration record's
        count (JSON ``"bic_samples"``)."""
        from liquidamp.analysis.measured.selection import bandwidth_samples

        how = getattr(getattr(self.options, "selection", None), "sample_count", "bandwidth")
        text = {"bandwidth": "min(N, 2 B T + 1) per record: the independent values a force "
                "kept to a bandwidth B [Hz] (the conditioning's harmonics kept x the stroke "
                "frequency) holds over the span T [s] fitted (sampling theorem; an averaged "
                "cycle counts 2 H + 1)",
                "correlation": "N / tau per record, tau the integrated autocorrelation time "
                "of the refit's residual (Geyer's initial monotone sequence)",
                "samples": "N, every sample"}[how]
        return {"method": how, "how": text,
                "records": {r.label: {"samples": int(r.time.size),
                                      "bandwidth_count": bandwidth_samples(r)}
                            for r in self.final.calibration}}

    def as_dict(self) -> dict:
        """JSON: summary, baseline, steps, final, reference models, drift."""
        def block(res):
            d = res.as_dict()
            return {"parameters": res.parameters_dict(),
                    "nrmse": {"calibration": res.nrmse_calibration,
                              "validation": res.nrmse_validation},
                    "heldout_records": heldout_per_record(res),
                    "fit": d["fit"], "summary": d["summary"], "start": d["start"],
                    "parameter_flags": d["parameter_flags"], "records": d["records"],
                    "plausibility": d["plausibility"], "device_class": d["device_class"],
                    "fit_warnings": d["warnings"]}
        fits = ([("baseline", self.baseline)]
                + [(f"device: {s.effect}", s.result) for s in self.device_steps]
                + [(f"step {i + 1}: + {s.effect}", s.result)
                   for i, s in enumerate(self.steps) if s.result is not None])
        not_conv = [{"fit": lab, "status": r.status, "message": r.message, "nfev": r.nfev}
                    for lab, r in fits if not r.converged]
        return {"summary": self.summary(), "heldout": self.heldout,
                "heldout_noise_floors": self.heldout_floors,
                "baseline": block(self.baseline),
                "device_refinement": {"kept": [s.as_dict() for s in self.device_steps],
                                      "tried": [c.as_dict() for c in self.device_evidence]},
                "steps": [s.as_dict() for s in self.steps],
                "final": block(self.final), "converged": not not_conv,
                "not_converged": not_conv, "noise_floor_nrmse": self.noise_nrmse,
                "noise_floors": [{"record": c.source, "force_std [N]": f.force_std,
                                  "rate_force_std [N]": f.rate_force_std,
                                  "nrmse": f.nrmse, "method": f.method,
                                  "harmonics": f.harmonics,
                                  "drift_std [N]": getattr(f, "drift_std", 0.0),
                                  "drift_nrmse": getattr(f, "drift_nrmse", 0.0),
                                  "nonstationary": bool(getattr(f, "drift", None) is not None
                                                        and f.drift.nonstationary)}
                                 for c, f in zip(self.conditioning[:len(self.noise_floors)],
                                                 self.noise_floors, strict=True)],
                "conditioning": [c.as_dict() for c in self.conditioning],
                "data_quality": [q.as_dict() for q in self.baseline.data_quality],
                "nrmse_raw": dict(self.nrmse_raw),
                "reference_models": {k: v.as_dict() for k, v in self.references.items()},
                "physics_loses_to_line": self.loses_to_line,
                "physics_loses_to_two_slope": self.loses_to_map,
                "without_input": self.without_input,
                "bic_samples": self.bic_samples(),
                "drift": [d.as_dict() for d in self.drifts],
                "non_stationary": self.non_stationary, "holdout": self.holdout,
                "options": self.options.as_dict() if self.options is not None else None,
                "signatures": self.signatures, "stop_reason": self.stop_reason,
                "unexplained": self.unexplained, "warnings": list(self.warnings),
                "last_round": [c.as_dict() for c in self.last_candidates]}


def _short(parameters: dict) -> str:
    return ", ".join(f"{k} {v:.3g}" for k, v in list(parameters.items())[:3]
                     if isinstance(v, (int, float)))
