"""Stage "select", who earned the fall: an effect whose own force the noise hides cannot have.

A refit frees the effect's parameters and every free device parameter at once, from the
current optimum.  Where the current model sits in a local minimum of the base parameters
(the c1/c2/air trade-off), the refit can escape it: the calibration residual falls and the
held-out records improve, whatever the effect.  The selection rule then credits the effect
with a fall that belongs to the device (independent-simulator sweep, session 12, Device B
with an elastomer: round 1 kept Coulomb friction at 1.1e-4 N, 0.00007 x the force noise,
because its refit took the calibration NRMSE 0.078 -> 0.0126; a moving mass held at its
lower bound reached the same 0.0126).

The test (statistics, the selection rule's own evidence level): the effect's force at its
fitted value, f = F(refit) - F(refit with the effect absent, every other parameter as
fitted), is compared with the noise.  Were f the whole of what the refit explained, the
fall of the residual sum of squares it could account for is |f|^2 over the records, in
units of the noise variance chi2_f = N_eff mean(f^2) / sigma^2 (N_eff the samples the rule
counts, sigma the pooled noise floor of the calibration records).  The rule asks of an
addition a fall of the BIC by ``bic_threshold`` plus its penalty k ln N_eff; where

    chi2_f < bic_threshold + k ln N_eff,

no data at this noise could tell the effect at its fitted size from its absence (its force
is below what the noise hides at the rule's evidence level): the improvement is the
device's.  The loop then takes the refit's device with the effect removed, continued to its
own optimum from the refit's values (a restart of the baseline from the better basin), as
its current model, judged against the current model by the same rule, and reports it as a
device refinement (``Diagnosis.device_steps``, named :data:`RESTART`); the next round screens
the candidates from there.  An effect is never kept at a size the noise hides.

References
----------
.. [1] R. E. Kass, A. E. Raftery, "Bayes factors", JASA 90(430), 1995.
.. [2] G. Schwarz, "Estimating the dimension of a model", Ann. Stat. 6(2), 1978.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from liquidamp.analysis.measured.calibration import FitSpec, calibrate
from liquidamp.analysis.measured.diagnosis_fits import _converge
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record, judge_fits
from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.analysis.measured.selection import sample_count
from liquidamp.device.effects import with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import LiquidampError

__all__ = ["RESTART", "EffectForce", "effect_force", "absent_model"]

#: Name of the device step that takes a refit's device without its negligible effect.
RESTART = "restart"


@dataclasses.dataclass(frozen=True)
class EffectForce:
    """An effect's own force at its fitted value, against the noise.

    Attributes
    ----------
    rms : float
        RMS over the calibration records of f = F(refit) - F(refit, effect absent) [N].
    chi2 : float
        N_eff mean(f^2) / sigma^2 [-]: the fall of the residual sum of squares, in noise
        variances, that f could account for at most.
    needed : float
        ``bic_threshold`` + k ln N_eff [-]: what the selection rule asks of the addition.
    noise : float
        sigma, the pooled noise floor of the calibration records [N].

    Examples
    --------
    A friction of 1e-4 N over 61 values (an averaged cycle of 30 harmonics) at 0.5 N of
    noise could explain 61 (1e-4 / 0.5)^2 = 2.4e-6 noise variances, against the 10 + ln 61
    a one-parameter addition must earn:

    >>> ef = EffectForce(1e-4, 61 * (1e-4 / 0.5) ** 2, 10 + math.log(61), 0.5)
    >>> ef.negligible, f"{ef.chi2:.2g}", f"{ef.needed:.3g}"
    (True, '2.4e-06', '14.1')
    """

    rms: float
    chi2: float
    needed: float
    noise: float

    @property
    def negligible(self) -> bool:
        """Whether the noise hides the effect at its fitted size (chi2 < needed)."""
        return self.chi2 < self.needed

    def describe(self, effect: str) -> str:
        """The sentence the diagnosis reports."""
        return (f"{effect}'s own force at its fitted value is {self.rms:.3g} N RMS "
                f"({self.rms / self.noise:.2g} x the noise floor {self.noise:.3g} N; "
                f"chi2 {self.chi2:.3g} against the {self.needed:.3g} the rule asks): "
                "below what the noise hides, so the refit's fall is the device's")


def absent_model(change, result, current):
    """The refit ``result``'s effects and fit spec with the candidate's effect absent
    (``(effects, spec)``), every other parameter at its fitted value; None where the
    candidate adds no effect it can remove (a device multiplier freed, a lead whose absence
    is not a value).

    A catalogue effect the current model did not hold is dropped with its fitted
    parameters; an effect it held whose lead the candidate frees (a rebound ratio, a dead
    band moved in front of a friction) gets the lead's value of absence, ``change.base``.
    """
    name, key = change.lead
    if name == "device":
        return None
    held = {e.name for e in current.effects}
    if change.added and change.added not in held:
        gone = change.added
        effects = tuple(e for e in result.effects if e.name != gone)
        drop = {p.name for p in result.spec.parameters if p.name.startswith(gone + ".")}
    elif math.isfinite(change.base) and any(e.name == name for e in result.effects):
        try:
            effects = tuple(e.replace(**{key: change.base}) if e.name == name else e
                            for e in result.effects)
        except (LiquidampError, ValueError):  # the absence is outside the effect's range
            return None
        drop = {f"{name}.{key}"}
    else:
        return None
    spec = FitSpec(tuple(p for p in result.spec.with_values(result.values).parameters
                         if p.name not in drop))
    return effects, spec


def effect_force(result, change, current, noise_nrmse, sel, options, preroll):
    """The candidate's own force at its fitted value against the noise
    (:class:`EffectForce`), or None where its effect cannot be removed
    (:func:`absent_model`) or the model without it fails.

    Parameters
    ----------
    result : CalibrationResult
        The candidate's refit.
    change : Change
        The candidate's change (:func:`~.candidates.candidate_change`).
    current : CalibrationResult
        The model the refit is judged against (k = the parameters the refit adds).
    noise_nrmse : float
        The calibration records' pooled noise floor as an NRMSE (the diagnosis' own) [-];
        sigma = noise_nrmse x RMS of the pooled measured force about its mean [N].
    sel : SelectionRule
        ``bic_threshold`` and ``sample_count`` of the rule.
    options, preroll
        As for :func:`~liquidamp.analysis.measured.record_model.simulate_record`.

    Returns
    -------
    EffectForce or None
    """
    absent = absent_model(change, result, current)
    if absent is None:
        return None
    recs = result.calibration
    with_ = with_effects(get_model(result.model), *result.effects)
    without = with_effects(get_model(result.model), *absent[0])
    try:
        f = np.concatenate([
            simulate_record(with_, result.params, r, options=options, preroll=preroll).force
            - simulate_record(without, result.params, r, options=options,
                              preroll=preroll).force for r in recs])
    except LiquidampError:
        return None
    meas = np.concatenate([r.force for r in recs])
    sigma = noise_nrmse * float(np.sqrt(np.mean((meas - meas.mean()) ** 2)))
    if not (np.all(np.isfinite(f)) and sigma > 0.0):
        return None
    n_eff = sample_count(recs, result.residuals("calibration"), sel.sample_count)
    k = len(result.varying) - len(current.varying)
    ms = float(np.mean(f ** 2))
    return EffectForce(math.sqrt(ms), n_eff * ms / sigma ** 2,
                       sel.bic_threshold + max(k, 1) * math.log(n_eff), sigma)


def device_without(result, change, current, validation, options, bud):
    """The refit's device with the candidate's effect removed, continued to its own optimum
    from the refit's values (None where it cannot be built or fitted)."""
    absent = absent_model(change, result, current)
    if absent is None:
        return None
    effects, spec = absent
    try:
        res = calibrate(current.calibration, model=current.model, params=result.start_params,
                        effects=effects, spec=spec, validate=validation, options=options,
                        start="spec", max_nfev=bud.max_nfev, preroll=bud.preroll,
                        tol=bud.tol, warn=False, sizing="auto")
        if res.status == "max_nfev":
            res = _converge(res, validation, options, bud.preroll, bud.max_nfev, bud.tol,
                            "auto")
    except LiquidampError:
        return None
    return res


def credit(chosen, tied, ranked, refits, probes, current, validation, options, bud, sel,
           noise_nrmse, select):
    """Stage "select", part 5: the chosen candidate checked for a force the noise hides
    (module doc).  Returns ``(chosen, tied, ranked, restart)``: where the chosen effect's
    force is negligible it is marked not accepted (its note says why) and the next passing
    candidate is checked in turn; ``restart`` is ``(fit, candidate)``, the first negligible
    refit's device without its effect, continued, where it passes the selection rule
    against ``current`` (the loop takes it as a device step), else None.  ``select`` is the
    round's choice among the accepted (:func:`~.diagnosis_select._select`)."""
    restart = None
    while chosen is not None:
        change = probes.get(chosen.effect)
        res = refits.get(chosen.effect)
        ef = (effect_force(res, change, current, noise_nrmse, sel, options, bud.preroll)
              if change is not None and res is not None else None)
        if ef is None or not ef.negligible:
            break
        i = ranked.index(chosen)
        ranked[i] = dataclasses.replace(
            chosen, accepted=False, note="; ".join(x for x in (chosen.note, "not kept: "
                                                                 + ef.describe(chosen.effect))
                                                   if x))
        if restart is None:
            dev = device_without(res, change, current, validation, options, bud)
            if dev is not None:
                v, new = judge_fits(current, dev, sel), heldout_per_record(dev)
                if v.accepted:
                    cand = dataclasses.replace(
                        ranked[i], effect=RESTART, accepted=True, refitted=True,
                        nrmse_calibration=dev.nrmse_calibration,
                        nrmse_validation=dev.nrmse_validation,
                        relative_reduction=v.relative_reduction, delta_bic=v.delta_bic,
                        n_effective=v.n_effective, validation_records=new,
                        parameters=_multipliers(dev),
                        note=(f"the base refitted from the {chosen.effect} refit's device, "
                              f"without it (calibration NRMSE {current.nrmse_calibration:.3g}"
                              f" -> {dev.nrmse_calibration:.3g}): "
                              + ef.describe(chosen.effect)))
                    restart = (dev, cand)
                    return None, [], ranked, restart
        chosen, tied = select(ranked, sel)
    return chosen, tied, ranked, restart


def _multipliers(res) -> dict:
    """The fitted device multipliers of a calibration [-]."""
    return {p.name: res.values[p.name] for p in res.spec.parameters
            if p.kind == "multiplier" and p.name in res.values}
