"""Residual diagnosis: trace what a calibrated model misses to a catalogue effect, add it.

The loop (what the paper did by hand in Sec. IV.C, where the residual
pointed to friction and then to friction that changes gradually near zero
velocity):

0. Condition the records
   (:func:`liquidamp.analysis.measured.conditioning.condition`): an optional
   zero-phase force low-pass (``force_cutoff``), then anti-alias filtering and
   decimation to keep ``harmonics`` (30) harmonics of the stroke frequency
   (a 200 Hz record of a 3 Hz stroke is left as it is; a 1 kHz record of a
   0.5 Hz stroke is decimated 27x), then, for a periodic stroke over at least
   four whole cycles, the average of the cycles (least squares on the average
   is least squares on every cycle for a model at its periodic steady state,
   at the cost of one simulated cycle).  The model's force is conditioned
   exactly as the record's.  Every NRMSE below is on the conditioned
   records; what the conditioning removed is reported per record, and the
   final model's NRMSE on the records as given (``nrmse_raw``).
1. Calibrate the model (:func:`liquidamp.analysis.measured.calibration.calibrate`).
2. Stop if the calibration residual is noise: NRMSE at most ``noise_factor``
   (1.5) times the noise floor, the force error that no model driven by the
   recorded stroke can avoid (:func:`liquidamp.analysis.measured.record_quality.noise_floor`:
   the cycle-to-cycle scatter of the conditioned force at the same phase, and the
   scatter of the recorded stroke rate times the device's equivalent damping; for
   an averaged record, divided by about the square root of the cycles averaged).
3. Screen every applicable candidate (by default every catalogue effect with fitted
   parameters and every composite, :func:`default_candidates`) by a score test: the model is
   run once with the effect at a probe strength scaled to the record; the
   change of force is the effect's signature s.  With J the Jacobian of the
   calibrated fit, the part of s that the fitted parameters cannot mimic is
   s_perp = s - J J^+ s (J without the columns of parameters held at a bound
   by the residual: the fit cannot move them), and the linearized drop of the
   residual sum of squares from adding the effect is (s_perp . r)^2 / |s_perp|^2 (a
   Lagrange-multiplier test).  A signature that would need a negative
   strength scores zero; so does a candidate whose model at the probe reaches no periodic
   orbit on a calibration record (the record simulation returns its last marched cycle,
   flagged: vapour cavities that settle over hundreds of cycles), whose force then follows
   where the march started rather than the parameters, so that neither its signature nor a
   fit of it is evidence; it is not refitted.  Simple signatures (correlation of the residual
   with sign(v), a, a constant, the dead-band indicator and the low-pressure
   phases) are reported too.
4. Refit also, in every round and whatever its score, each device parameter the preset
   holds fixed (:data:`~.candidates.DEVICE_REFINEMENTS`: the channel inertance S_t, and the
   chambers' pressure level p0 where the residual keeps a preload consistent with a gas
   charge; by default,
   or when named among ``candidates``); it
   competes with the effects under the same rule, and when chosen it is recorded as the
   device's own parameter (``Diagnosis.device_steps``), not an effect.
   Refit the ``top`` candidates with everything free (only those whose linearized
   evidence pays their BIC penalty: N_eff ln(1 - score) + k ln N_eff < 0, N_eff of the
   current residual, k the effect's fitted parameters), starting
   from the linearized strength (cavitation: from the probe's vapour pressure, a
   threshold); when none of these refits brings the calibration
   residual down to ``structure_factor`` times the noise floor and each held-out record
   to as many times its own (a model at the calibration noise that misses a held-out
   record is a wrong one the calibration cannot show), refit also the
   next candidate if its score is within a factor ``score_ratio`` (3) of the best
   (the score test is local: where the calibrated model sits in another basin of
   the c1/c2 trade-off, an effect whose signature overlaps a free parameter's,
   such as leakage and c1, can score below a rival and still fit far better once
   the parameters move).  A queued candidate that is a limit of another (``REDUCTIONS``)
   is refitted before it (nested hypotheses from the smallest up).  Once a refit leaves the
   residual at the noise (``noise_factor`` times the floor), later candidates of the round
   freeing more parameters are not refitted (parsimony: at the noise they could only tie,
   and the BIC charges their extra parameters), nor those freeing as many where that refit
   predicts every held-out record to its own noise too.  When no refit of the round
   brings the residual down to ``structure_factor`` times the noise floor, each is
   refitted once more from the physics start of the original multipliers and the better
   fit is kept (the continuation can stay in a local minimum of the c1/c2 trade-off).
   Where no device refinement alone passes the rule (item 5) but one alone
   lowers the calibration BIC by more than ``bic_threshold`` (the records feel it), each
   restart, and each simpler model refitted as a reduction, is also continued with that
   refinement's multipliers freed beside the effect, kept where it then reaches
   ``structure_factor`` times the noise floor, fits better and loses no held-out record
   (an effect and a device parameter can each fail alone and explain the records
   together: an elastomer on a channel 15 % off the preset's); a step so chosen records
   the freed device parameter in ``Diagnosis.device_steps`` too.
   A fit that stops on its evaluation budget (the baseline or a
   refit) is continued once before it is scored or judged; fits that still
   did not converge are listed in ``warnings`` and in the JSON
   (``converged``, ``not_converged``).
5. Keep a refit only when all hold (:class:`~.diagnosis_options.SelectionRule`):

   * held out, record by record: no held-out record's NRMSE rises by more than
     ``validation_tolerance`` (2 %, relative), and together they fall by more than it
     (the geometric mean of the per-record ratios at most 0.98): an effect is kept only
     if it predicts data it was not fitted to better;
   * the calibration BIC, counted with an honest number of samples, falls by more than
     ``bic_threshold`` (10, "very strong" evidence on Kass and Raftery's scale):
     delta BIC = N ln(RSS_new / RSS_now) + (k_new - k_now) ln N < -10, N the independent
     values the kept band of each record can hold, min(N_i, 2 B_i T_i + 1) summed over
     records (B_i the force bandwidth the conditioning kept, T_i the span fitted:
     :func:`~liquidamp.analysis.measured.selection.bandwidth_samples`; an averaged cycle
     of 30 harmonics counts 61 whatever its sampling rate; ``sample_count="correlation"``
     uses N_i / tau_i of the residual instead);
   * no parameter the candidate frees ends at a bound (there its value is the bound's,
     not the data's).  A candidate rejected so has the records asking for a limit of its
     model: the simpler candidates it contains as limits (``REDUCTIONS``: a digressive valve
     cracking at its least pressure is a relief valve cracking at none, a laminar bypass)
     are refitted from their own probes, if they were not, and judged by the same rule (the
     richer refit reaching the limit would otherwise "explain" the round first).

   Among the refits kept the best held out (lowest geometric mean ratio) is added; the
   others within ``tie_tolerance`` (10 %) of it are reported as tied with their evidence.
   An effect whose own force at its fitted value the noise hides (chi2 of that force below
   the rule's 10 + k ln N) did not earn its refit's fall, the base's escape from a local
   minimum did: it is not kept, and the refit's device without it, continued, becomes the
   current model as a device step (``restart``, :mod:`~.diagnosis_credit`).
   Without validation records the last of several calibration records is held out, or the
   second half of the whole cycles of one periodic record (``Diagnosis.holdout``).
   A parameter the added effect frees with a standard error above its value (a flat valley:
   an elastomer's parallel spring against its branch's relaxation time) is profiled, the fit
   restarted from the profile's minimum where it still passes the rule, and its 95 %
   profile interval reported (:mod:`~liquidamp.analysis.measured.profile`, ``Step.profile``).
6. Repeat from 2 with the effect included, at most ``max_steps`` times.
7. Where the loop ends above the noise level, the class choice's runner-up start (where it
   continued one) and the fluid family's other starts (the device as given where the fluid
   start was sized for its force alone; the family's channels beyond the fit's reach,
   :func:`~liquidamp.analysis.measured.class_revisit.fluid_alternatives`) are diagnosed too,
   in turn; each final model replaces the one held only where it passes the rule of 5
   against it (:mod:`~liquidamp.analysis.measured.class_revisit`).

Broadband records and records with a control input: :func:`~.diagnosis_options.broadband`,
:func:`~liquidamp.analysis.measured.device_class.calibrate_by_class`.

Besides the catalogue effects, :data:`COMPOSITES` lists candidates that change how
effects compose or behave (:mod:`liquidamp.analysis.measured.candidates`):
``"backlash"`` adds freeplay and moves the friction already in the model behind it (a
dead band in series with the friction, as in a friction damper whose band slips only once
the play is taken up); ``"friction_asymmetry"`` frees the friction's reverse-to-forward
level ratio; ``"friction_transition"`` the smooth friction's transition exponent (a
sharp, elastic-plastic slip).  Every candidate is one
:class:`~liquidamp.analysis.measured.candidates.Change` -- the candidate model at a probe,
the parameters it frees, the one the score test estimates -- so a composite is screened,
refitted and judged like an effect, with the parameters it frees counted in delta BIC.

Beside the physics model the line F = c v + k y + F0 and the two-slope force-velocity
map per direction are fitted on the same split
(:mod:`~liquidamp.analysis.measured.reference_models`); where the physics model does not
beat the line on a held-out record, the first line of :meth:`Diagnosis.summary` says so.
The force of every periodic record as read is tested for a drift from cycle to cycle
(:func:`~liquidamp.analysis.measured.stationarity.cycle_drift`, the one drift test); a
drifting record is reported first as non-stationary, its drift is kept out of its noise
floor, it is not averaged (the baseline fitted on its averaged cycles is continued on it as
it runs) and it proposes ``self_heating``, marched over each whole record (as does a record
with a measured temperature, which then drives the viscosity law).

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
.. [4] C. J. Geyer, "Practical Markov chain Monte Carlo", Stat. Sci. 7(4), 1992
   (the autocorrelation time behind N_eff).
"""

from __future__ import annotations

import dataclasses
import warnings as _warnings

import numpy as np

from liquidamp.analysis.measured.calibration import (
    CalibrationResult,
    FitSpec,
    calibrate,
    with_progress,
)
from liquidamp.analysis.measured.checks import check_records, drop_outliers, keep_outliers
from liquidamp.analysis.measured.class_revisit import revisit_starts
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.diagnosis_credit import RESTART, credit
from liquidamp.analysis.measured.diagnosis_evidence import (
    COMPOSITES,
    CONFOUNDED,
    DEVICE_REFINEMENTS,
    REDUCTIONS,
    Candidate,
    applicable,
    confounding,
    confounding_warnings,
    harmonic_structure,
    score,
    signatures,
)
from liquidamp.analysis.measured.diagnosis_fits import (
    _converge,
    _device_round,
    _joint_multipliers,
    _profile_step,
    _refit,
    _restart,
)
from liquidamp.analysis.measured.diagnosis_options import (
    BROADBAND_TOP,
    Budget,
    ConditioningOptions,
    DiagnoseOptions,
    SelectionRule,
    broadband,
    march_options,
)
from liquidamp.analysis.measured.diagnosis_result import Diagnosis, Step
from liquidamp.analysis.measured.diagnosis_select import (
    _at_noise,
    _bounded_reductions,
    _explained,
    _held_back,
    _judge_round,
    _linear_delta_bic,
    _n_free,
    _no_pass,
    _reduce,
    _select,
    _simplest_first,
    _with,
)
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.analysis.measured.record_quality import noise_floor
from liquidamp.analysis.measured.reference_models import reference_models
from liquidamp.analysis.measured.selection import sample_count
from liquidamp.analysis.measured.stationarity import cycle_drift
from liquidamp.device.effects import EFFECTS
from liquidamp.errors import (
    LiquidampError,
    LiquidampWarning,
    ParameterError,
    check_choice,
)

__all__ = ["Candidate", "Step", "Diagnosis", "diagnose", "CONFOUNDED", "COMPOSITES",
           "DiagnoseOptions", "SelectionRule", "Budget", "ConditioningOptions",
           "default_candidates", "signatures", "bundled_records", "broadband"]


def default_candidates() -> tuple[str, ...]:
    """Every catalogue effect with fitted parameters, then every composite (the default
    screen; operating conditions such as ``rotating_frame`` are given, not diagnosed)."""
    return tuple(n for n, c in EFFECTS.items() if c.fit_keys) + tuple(COMPOSITES)


def _candidate_names(candidates) -> tuple:
    names = default_candidates() if candidates is None else tuple(candidates)
    for n in names:
        check_choice("candidate effect", n, {**EFFECTS, **COMPOSITES, **DEVICE_REFINEMENTS})
        if n in DEVICE_REFINEMENTS:
            continue
        if n not in COMPOSITES and not EFFECTS[n].fit_keys:
            raise ParameterError(
                f"candidate effect {n!r} has no fitted parameters (an operating condition): "
                "give it with effects=, not as a candidate")
    return names


def _stationarity(records) -> tuple[list, str]:
    """Stage "check": the drift test of every record as read (the one test,
    :func:`~liquidamp.analysis.measured.drift.record_drift`, which the record-quality checks
    and the noise floor read too; None where it cannot test), and the sentence that says
    which records drift (empty when none)."""
    drifts = [cycle_drift(r) for r in records]
    said = [d.describe() for d in drifts if d is not None and d.non_stationary]
    return drifts, "; ".join(said)


def _holdout(calibration) -> tuple[tuple, tuple, str]:
    """Held-out records where none were given: the last of several records, else the second
    half of the whole cycles of a periodic record of at least 6 cycles."""
    if len(calibration) >= 2:
        return (calibration[:-1], calibration[-1:],
                f"no validation records given: {calibration[-1].label} held out")
    r = calibration[0]
    if not (r.periodic and r.cycles >= 6.0):
        raise ParameterError(
            "diagnose needs held-out records: give validation records (--validate), two "
            "calibration records (the last is held out) or one periodic record of at least 6 "
            f"whole cycles (its second half is held out); got one record of {r.cycles:.3g} "
            "cycles")
    half = int(r.cycles) // 2
    i = int(np.searchsorted(r.time, r.time[0] + half * r.period))
    from liquidamp.analysis.measured.records import Record

    def part(sl, tag):
        # each half keeps the file's own lines, the measured channels and what the reading
        # did (a force read negated)
        return Record.from_arrays(r.time[sl], r.displacement[sl], r.force[sl],
                                  window=r.window, order=r.order, source=r.source + tag,
                                  lines=[r.line(j) for j in range(r.time.size)[sl]],
                                  channels={k: v[sl] for k, v in r.channels.items()},
                                  meta={k: v for k, v in r.meta.items()
                                        if k in ("force_sign",)})

    return ((part(slice(0, i), ""),), (part(slice(i, None), " (second half)"),),
            f"no validation records given: the second half of {r.label} ({half} cycles "
            "from its middle on) held out")


def _prepare(calibration, validation, model, params, effects, spec, options, config,
             baseline, drifts=None):
    """Stages "condition", "start" and "fit": the conditioned records, what was done, the
    records as given, and the baseline calibration."""
    bud = config.budget
    raw = (calibration, validation)
    if baseline is None:
        kw = config.conditioning.keywords()
        conds = [condition(r, **kw) for r in calibration + validation]
        nc = len(calibration)
        calibration = tuple(r for r, _ in conds[:nc])
        validation = tuple(r for r, _ in conds[nc:])
        conditioning = tuple(c for _, c in conds)
        baseline = calibrate(calibration, model=model, params=params, effects=effects,
                             spec=spec, validate=validation, options=options,
                             max_nfev=bud.max_nfev, preroll=bud.preroll, tol=bud.tol,
                             warn=False, sizing=config.sizing, outliers=config.outliers)
        drifts = drifts or [None] * len(conds)
        if kw.get("average", "auto") == "auto" and any(
                d is not None and d.non_stationary and c.cycles_averaged > 1
                for d, (_, c) in zip(drifts, conds, strict=True)):
            # a drifting record is not averaged over its cycles (they differ by the drift,
            # which a drifting model follows over the whole record): the stationary baseline
            # fitted on the averages (least squares on every cycle, the same optimum) is
            # continued on the records as they run
            conds = [condition(r, **{**kw, "average": False})
                     if d is not None and d.non_stationary else rc
                     for r, d, rc in zip(raw[0] + raw[1], drifts, conds, strict=True)]
            calibration = tuple(r for r, _ in conds[:nc])
            validation = tuple(r for r, _ in conds[nc:])
            conditioning = tuple(c for _, c in conds)
            averaged = baseline
            baseline = calibrate(calibration, model=baseline.model,
                                 params=baseline.start_params, effects=baseline.effects,
                                 spec=baseline.spec, validate=validation, options=options,
                                 start="spec", max_nfev=bud.max_nfev, preroll=bud.preroll,
                                 tol=bud.tol, warn=False, sizing="auto",
                                 outliers=config.outliers)
            # the class choice was made on the averages: its starts (and the runner-up a
            # revisit diagnoses) are the averaged baseline's
            baseline = dataclasses.replace(baseline, device_class=averaged.device_class,
                                           class_starts=averaged.class_starts)
    else:
        calibration = baseline.calibration
        conditioning = tuple(r.meta.get("conditioning")
                             or condition(r, decimate=1, average=False)[1]
                             for r in calibration + validation)
        raw = (calibration, validation)
    if baseline.status == "max_nfev":
        # score candidates only against a converged model: a fit stopped on its budget
        # leaves structure that a candidate would "explain" spuriously
        prior = baseline
        baseline = _converge(baseline, validation, options, bud.preroll, bud.max_nfev,
                             bud.tol, "preset" if config.sizing == "preset" else "auto")
        kept = {k: v for k, v in (prior.start or {}).items()  # the class, the fit without
                if k in ("without_input", "device_class", "device_class_rule", "classes")}
        baseline = dataclasses.replace(baseline, start={**(baseline.start or {}), **kept},
                                       device_class=prior.device_class,
                                       class_starts=prior.class_starts)
    return calibration, validation, conditioning, raw, baseline


def _noise(calibration, conditioning, validation) -> tuple[tuple, float, float, dict]:
    """The noise floor of each conditioned calibration record, the pooled force noise [N],
    its NRMSE and each held-out record's floor NRMSE (by label); the floor of a record whose
    cycles drift is the scatter about the drift
    (:func:`~liquidamp.analysis.measured.record_quality.noise_floor` removes it, once)."""
    meas = np.concatenate([r.force for r in calibration])
    den = float(np.sqrt(np.mean((meas - meas.mean()) ** 2)))
    floors = tuple(c.noise if c.noise is not None else noise_floor(r)
                   for c, r in zip(conditioning, calibration, strict=False))
    stds = [f.std for f in floors]
    noise_std = float(np.sqrt(sum(s ** 2 * r.time.size
                                  for s, r in zip(stds, calibration, strict=True))
                              / meas.size))
    held = {r.label: (c.noise if c.noise is not None else noise_floor(r)).nrmse
            for c, r in zip(conditioning[len(calibration):], validation, strict=True)}
    return floors, noise_std, noise_std / den, held


def _screen(names, current, options, bud: Budget, sel: SelectionRule, route: str = "auto"):
    """Stage "screen": the score test of every applicable candidate (one model run each),
    ranked; the ones to refit (the ``top`` and, if needed, the next within ``score_ratio``)
    whose linearized evidence pays their BIC penalty.  ``route``: the probe runs' route to
    the periodic orbits (:func:`~.diagnosis_evidence.score`)."""
    present = {e.name for e in current.effects}
    round_, probes = [], {}
    for n in names:
        if n in present:
            continue
        why = applicable(n, current)
        if why:
            round_.append(Candidate(n, 0.0, 0.0, {}, note=f"not applicable: {why}"))
            continue
        cand, probe = score(n, current, options, bud.preroll, route=route)
        probes[n] = probe
        round_.append(cand)
    ranked = sorted(round_, key=lambda c: -c.score)
    scored = [c for c in ranked if c.score > 0]
    # the score test is local: at a calibrated model that sits in another basin of the
    # c1/c2 trade-off, an effect whose signature overlaps a free parameter's can score
    # below a rival and still fit far better once the parameters move
    extra = [c for c in scored[bud.top:bud.top + 1]
             if c.score * bud.score_ratio >= scored[0].score]
    queue = scored[:bud.top]
    if broadband(current.calibration):  # each refit marches every whole record: the best
        queue, extra = scored[:min(bud.top, BROADBAND_TOP)], []
    n_now = sample_count(current.calibration, current.residuals("calibration"),
                         sel.sample_count)
    keep = []
    for cand in queue + extra:
        lin = _linear_delta_bic(cand, probes[cand.effect], n_now)
        if lin > 0:
            ranked[ranked.index(cand)] = _with(cand, note=(
                f"not refitted: its score {cand.score:.3g} over {n_now:.4g} samples "
                f"predicts delta BIC {lin:+.3g}, not even its penalty"))
        else:
            keep.append(cand)
    queue = [c for c in queue if c in keep]
    extra = [c for c in extra if c in keep]
    return ranked, probes, scored, queue, extra, n_now


def _fit_round(ranked, probes, queue, extra, current, validation, options, bud, level,
               start0, sel, noise, joint=None, floors=None):
    """Stage "fit": refit the queued candidates (a second wave if the first leaves the
    residual above ``level``); where no refit of the round reaches ``level``, each is
    restarted once from the physics start (module doc, 4).

    The second wave's first fits come before any restart: both answer a round the first
    refits left unexplained (the score test is local), and a restart is a second fit of a
    candidate already fitted, the next candidate's refit a first fit of one the score
    could not rank (200 Hz series-compliance bench record: the compliance, third by score,
    reaches the noise at once; restarting the two above it first cost 3.5 of 9 s).

    Once a refit leaves the calibration residual at the noise (``noise``, the loop's own
    stop, noise_factor x the noise floor), a later candidate of the round that frees more
    parameters is not refitted: at the noise no data can tell it from the simpler one
    (its held-out NRMSE could at best tie, decided by the noise), and the BIC charges its
    extra parameters for the same residual (200 Hz Coulomb-friction bench record: the
    friction reached the noise in 0.3 s, the backlash refit after it took 7.7 s to end
    seven times above it).  One that frees as many is not refitted either where that refit
    also predicts every held-out record to its own noise (``floors``: held-out record label
    -> its noise floor NRMSE; noise_factor x it): it could at best tie on both
    (:func:`~.diagnosis_select._held_back`).  A round counts as explained (no second wave,
    no restart) only where a refit reaches ``level`` on the calibration records and
    structure_factor x its own floor on every held-out record: a refit at the calibration
    noise that leaves a held-out record far above its floor is a wrong model the calibration
    record cannot show."""
    refits, fitted, quiet, silent = {}, [], None, False
    for wave in (queue, extra):
        if wave is extra and (not fitted or _explained(refits, level, floors, sel)):
            break
        for cand in _simplest_first(wave, queue + extra):
            if cand.effect in refits:
                continue
            why = quiet and _held_back(quiet, _n_free(probes[quiet]), silent,
                                       _n_free(probes[cand.effect]))
            if why:
                ranked[ranked.index(cand)] = _with(cand, note=why)
                continue
            fitted.append(cand)
            try:
                refits[cand.effect] = _refit(cand, probes[cand.effect], current, validation,
                                             options, bud.preroll, bud.max_nfev, bud.tol,
                                             "auto")
            except LiquidampError as exc:  # e.g. a chamber at the pressure floor
                ranked[ranked.index(cand)] = _with(cand, refitted=True,
                                                   note=f"refit failed: {exc}")
                continue
            if refits[cand.effect].nrmse_calibration <= noise and (
                    quiet is None or _n_free(probes[cand.effect]) < _n_free(probes[quiet])):
                quiet = cand.effect
                silent = _at_noise(refits[quiet], floors, sel.noise_factor)
    restart = not broadband(current.calibration) and not _explained(refits, level, floors,
                                                                    sel)
    for cand in fitted if restart else []:  # no physics start for a broadband record
        if cand.effect in refits and not _explained(refits, level, floors, sel):
            refits[cand.effect] = _restart(refits[cand.effect], current, validation,
                                           options, bud.preroll, bud.max_nfev, bud.tol,
                                           start0, "auto", sel.validation_tolerance, joint)
    return refits, joint if restart else None


@with_progress
def diagnose(calibration, validation=(), *, model="full", params=None, effects=(),
             spec: FitSpec | None = None, options=None, config: DiagnoseOptions | None = None,
             baseline: CalibrationResult | None = None, **keywords) -> Diagnosis:
    """Calibrate, then add the catalogue effects the held-out records ask for (module doc).

    The stages: check the records as read (and their cycle drift), condition them, start
    and fit the baseline, then per step screen every candidate, refit the best, select by
    the rule, and report (with the reference models fitted on the same split).

    Parameters
    ----------
    calibration, validation : sequence of Record
        Records to fit and held-out records to judge by.  Without validation records the
        last of several calibration records is held out, or the second half of the whole
        cycles of one periodic record of at least 6 cycles (``Diagnosis.holdout`` says so).
    model, params, effects, spec, options
        As for :func:`~liquidamp.analysis.measured.calibration.calibrate` (default:
        ``full`` from ``paper_initial`` with the paper's four multipliers free);
        ``options`` are the solver options.
    config : DiagnoseOptions, optional
        Selection rule, budget, conditioning, candidates and start
        (:mod:`~liquidamp.analysis.measured.diagnosis_options`).  Default: every catalogue
        effect with fitted parameters and every composite is a candidate
        (:func:`default_candidates`).
    baseline : CalibrationResult, optional
        A calibration already done on the records it holds (``baseline.calibration``);
        those records and ``validation`` are used as they are (no conditioning).
    **keywords
        Flat options mapped onto ``config`` (:meth:`DiagnoseOptions.from_keywords`):
        ``candidates``, ``sizing``, ``max_steps``, ``top``, ``score_ratio``, ``max_nfev``,
        ``tol``, ``preroll``, ``bic_threshold``, ``validation_tolerance``,
        ``tie_tolerance``, ``noise_factor``, ``structure_factor``, ``sample_count``,
        ``reject_at_bound``, ``force_cutoff``, ``decimate``, ``harmonics``, ``average``,
        ``outliers``.  Unknown names raise.
    progress : callable, optional
        Called as ``progress(1)`` after every model evaluation of every fit
        (keyword only; :func:`~liquidamp.analysis.measured.calibration.with_progress`).

    Returns
    -------
    Diagnosis

    Raises
    ------
    DataFileError
        Before any model run, as :func:`~liquidamp.analysis.measured.checks.check_records`
        (every record, count and file line named at once; force spikes pass with
        ``outliers='drop'`` or ``'keep'``, displacement spikes with ``'keep'``).
    ParameterError
        Unknown or bad options, no held-out records and none can be held out.

    Warns
    -----
    LiquidampWarning
        With each of ``Diagnosis.warnings``.
    """
    config = DiagnoseOptions.from_keywords(config, **keywords)
    sel, bud = config.selection, config.budget
    calibration, validation = tuple(calibration), tuple(validation)
    if not calibration:
        raise ParameterError("diagnose needs at least one calibration record")
    names = _candidate_names(config.candidates)
    # the device's own parameters are tried by default, or when named among the candidates
    device_names = (tuple(DEVICE_REFINEMENTS) if config.candidates is None
                    else tuple(n for n in names if n in DEVICE_REFINEMENTS))
    names = tuple(n for n in names if n not in DEVICE_REFINEMENTS)
    options = march_options(options, calibration + validation)
    if params is None:
        from liquidamp.device import preset

        check_params = preset("paper_initial")
    else:
        check_params = params
    # stage "check", before any model run: noise-only records, spikes and a stroke past the
    # chamber end are refused (the chamber end only where the device keeps its chambers:
    # otherwise the start stretches them to the records' stroke); the cycle drift of every
    # record as read is measured
    quality, _ = check_records(calibration + validation,
                               check_params if config.sizing == "preset" else None,
                               what="diagnose",
                               outliers=config.outliers)
    if config.outliers != "refuse" and baseline is None:  # before any conditioning
        nc = len(calibration)
        how = drop_outliers if config.outliers == "drop" else keep_outliers
        fixed = [how(r, q) for r, q in zip(calibration + validation, quality, strict=True)]
        calibration, validation = tuple(fixed[:nc]), tuple(fixed[nc:])
    holdout = ""
    if not validation:
        if baseline is not None:
            raise ParameterError("diagnose with a baseline needs its validation records")
        calibration, validation, holdout = _holdout(calibration)
    drifts, non_stat = _stationarity(calibration + validation)
    # stages "condition", "start", "fit"; a drifting record is not averaged over its cycles
    # (they differ by the drift, which a drifting model follows over the whole record)
    calibration, validation, conditioning, raw, baseline = _prepare(
        calibration, validation, model, params, effects, spec, options, config, baseline,
        drifts)
    floors, noise_std, noise_nrmse, held = _noise(calibration, conditioning, validation)
    run = _loop(baseline, names, device_names, validation, options, config, spec,
                noise_nrmse, held)

    def fit(kw):  # an alternative start's baseline (stages "start", "fit")
        base2 = calibrate(calibration, model=model, validate=validation, options=options,
                          max_nfev=bud.max_nfev, preroll=bud.preroll, tol=bud.tol,
                          warn=False, outliers=config.outliers,
                          **{"params": params, "effects": effects, "spec": spec, **kw})
        if base2.status == "max_nfev":
            base2 = _converge(base2, validation, options, bud.preroll, bud.max_nfev,
                              bud.tol, "preset" if kw["sizing"] == "preset" else "auto")
        return base2

    run = revisit_starts(run, baseline, sel.noise_factor * noise_nrmse, check_params, config,
                         fit, lambda base, cfg: _loop(base, names, device_names, validation,
                                                      options, cfg, spec, noise_nrmse, held),
                         lambda base: _first_refits(base, names, device_names, validation,
                                                       options, bud, sel))
    baseline, steps, current = run["baseline"], run["steps"], run["current"]
    stop, last_round, device_steps = run["stop"], run["last_round"], run["device_steps"]
    device_evidence = run["device_evidence"]
    warnings = run["warnings"]
    if not baseline.converged:
        warnings.insert(0, f"NOT CONVERGED: baseline calibration ({baseline.status}): "
                        f"{baseline.message}")
    sig = signatures(baseline)
    # stage "report"
    unexplained = ""
    if current.nrmse_calibration > sel.structure_factor * noise_nrmse:
        h = harmonic_structure(current, noise_std)
        unexplained = ("residual keeps structure that no candidate explains "
                       f"(calibration NRMSE {current.nrmse_calibration:.3g} vs noise floor "
                       f"{noise_nrmse:.3g}, more than {sel.structure_factor:g} x): "
                       + (h or "no single harmonic of the excitation stands out (broadband "
                          "or non-periodic misfit)"))
    raw_nrmse = {}
    if any(c.changed for c in conditioning):
        m = current.device_model
        raw_nrmse = {role: nrmse([simulate_record(m, current.params, r, options=options,
                                                  preroll=bud.preroll).force for r in recs],
                                 [r.force for r in recs])
                     for role, recs in zip(("calibration", "validation"), raw, strict=True)}
    refs = reference_models(calibration, validation)
    for w in warnings:
        _warnings.warn(f"diagnose: {w}", LiquidampWarning, stacklevel=2)
    return Diagnosis(baseline=baseline, steps=tuple(steps), final=current,
                     noise_nrmse=noise_nrmse, signatures=sig, stop_reason=stop,
                     unexplained=unexplained, warnings=tuple(warnings),
                     last_candidates=last_round, conditioning=conditioning,
                     noise_floors=floors, heldout_floors=held, nrmse_raw=raw_nrmse,
                     references=refs,
                     drifts=tuple(d for d in drifts if d is not None),
                     non_stationary=non_stat, options=config, holdout=holdout,
                     device_steps=tuple(device_steps), device_evidence=device_evidence)


def _loop(baseline, names, device_names, validation, options, config, spec,
          noise_nrmse, heldout_floors=None) -> dict:
    """Stages "screen", "fit" and "select" from one baseline, step after step (module doc,
    2-6); ``heldout_floors``: each held-out record's noise floor NRMSE by label.  Returns the
    loop's state: ``baseline``, ``steps``, ``current`` (the final fit), ``stop``,
    ``last_round``, ``device_steps``, ``device_evidence``, ``warnings``."""
    sel, bud = config.selection, config.budget
    warnings = []
    spec0 = baseline.spec if spec is None else spec
    start0 = {p.name: (spec0[p.name].value if p.name in spec0.names else 1.0)
              for p in baseline.spec.parameters if p.kind == "multiplier"}
    if spec is None:
        start0 = dict.fromkeys(start0, 1.0)
    current, steps, last_round = baseline, [], ()
    stop = f"max_steps = {bud.max_steps} reached"
    level = sel.structure_factor * noise_nrmse
    device_steps, device_evidence, restarts = [], (), 0
    while len(steps) < bud.max_steps:
        if current.nrmse_calibration <= sel.noise_factor * noise_nrmse:
            stop = (f"residual is noise: calibration NRMSE {current.nrmse_calibration:.4g} <= "
                    f"{sel.noise_factor:g} x noise floor {noise_nrmse:.4g}")
            break
        # stage "screen"
        ranked, probes, scored, queue, extra, n_now = _screen(names, current, options, bud,
                                                              sel)
        # stage "fit": the device refinements first; where none alone passes the rule, the
        # effects' restarts free beside the effect those the calibration records feel (alone
        # they lower its BIC by more than the threshold: diagnosis_fits._freeing)
        dev, dev_changes, dev_refits = _device_round(current, validation, options, bud,
                                                     device_names)
        alone = _judge_round(list(dev), dev_refits, dev_changes, current, sel)
        joint = {} if any(c.accepted for c in alone) else {
            c.effect: dev_changes[c.effect] for c in alone
            if c.delta_bic is not None and c.delta_bic < -sel.bic_threshold}
        refits, beside = _fit_round(ranked, probes, queue, extra, current, validation,
                                    options, bud, level, start0, sel,
                                    sel.noise_factor * noise_nrmse,
                                    _joint_multipliers(current, joint.values(), level),
                                    heldout_floors)
        ranked += dev
        probes.update(dev_changes)
        refits.update(dev_refits)
        # stage "select"
        ranked = _judge_round(ranked, refits, probes, current, sel)
        ranked = _bounded_reductions(ranked, refits, probes, current, validation, options,
                                     bud, sel, beside, sel.noise_factor * noise_nrmse)
        chosen, tied = _select(ranked, sel)
        ranked, chosen, tied = _reduce(chosen, tied, ranked, refits, probes, current,
                                       validation, options, bud, sel, beside)
        # an effect whose own force the noise hides did not earn the fall: the device did
        chosen, tied, ranked, restart = credit(
            chosen, tied, ranked, refits, probes, current, validation, options, bud, sel,
            noise_nrmse, _select)
        last_round = tuple(ranked)
        device_evidence = tuple(c for c in ranked if c.effect in DEVICE_REFINEMENTS)
        if restart is not None and restarts < bud.max_steps:
            res, cand = restart
            restarts += 1
            device_steps.append(Step(RESTART, cand.parameters, res.nrmse_calibration,
                                     res.nrmse_validation, tuple(ranked) + (cand,), (), res,
                                     {}, {}, cand.note))
            warnings.append(f"device refined: {cand.note}")
            current, last_round = res, ()
            continue
        if chosen is None:
            stop = _no_pass(ranked, scored, probes, n_now, sel)
            break
        tie = ()
        if len(tied) > 1:
            tie = tuple(c.effect for c in tied)
            warnings.append(
                "tie: " + " and ".join(
                    f"{c.effect} (validation NRMSE {c.nrmse_validation:.4g}, dBIC "
                    f"{c.delta_bic:.4g})" for c in tied)
                + f" explain the residual about equally (held-out NRMSE within "
                f"{sel.tie_tolerance:.0%}); {chosen.effect} was added ("
                + ("the best held out" if chosen.effect not in REDUCTIONS.values()
                   or "added instead" not in chosen.note else
                   "the simpler model the best one reduces to") + ")")
        res = refits[chosen.effect]
        if chosen.effect in DEVICE_REFINEMENTS:
            # the device's own parameter, not an effect: it does not count as a step
            device_steps.append(Step(chosen.effect, chosen.parameters, res.nrmse_calibration,
                                     res.nrmse_validation, tuple(ranked), tie, res, {}))
            current, last_round = res, ()
            continue
        claimed = set()
        for name, change in sorted(joint.items(), key=lambda kv: -len(kv[1].multipliers)):
            # a restart that freed device refinements beside the effect: the device's own
            # parameters, recorded as such (as where one is chosen alone), each once (the
            # pressure level frees the inertance with it)
            new = {m for m in change.multipliers if m in res.varying
                   and m not in current.varying} - claimed
            if new:
                claimed |= set(change.multipliers)
                device_steps.append(Step(name, change.parameters(res), res.nrmse_calibration,
                                         res.nrmse_validation, tuple(ranked), (), res, {}))
        res, chosen, prof = _profile_step(res, chosen, probes, current, validation, options,
                                          bud, sel, warnings)
        if not res.converged:
            warnings.append(f"NOT CONVERGED: fit with {chosen.effect} ({res.status}): "
                            f"{res.message}")
        warnings += confounding_warnings(chosen.effect, current, res)
        steps.append(Step(chosen.effect, chosen.parameters, res.nrmse_calibration,
                          res.nrmse_validation, tuple(ranked), tie, res,
                          confounding(chosen.effect, current, res),
                          prof.as_dict() if prof is not None else {}))
        current = res
        last_round = ()
    return {"baseline": baseline, "steps": steps, "current": current, "stop": stop,
            "last_round": last_round, "device_steps": device_steps,
            "device_evidence": device_evidence, "warnings": warnings}


def _first_refits(base, names, device_names, validation, options, bud, sel):
    """The fits a round from ``base`` makes first: the score test's queue and its second
    wave, each refitted once without the restart from the physics start, and the device
    refinement (the channel inertance freed, :func:`_device_round`): (name, fit) pairs,
    yielded one at a time (the screen stops at the first that does not miss), the ones
    whose model failed left out (the screen of an alternative start,
    :func:`~.class_revisit.screened`).

    The screen's score tests run their probes without the Newton shooting
    (``route="no_shooting"``): a probe the march does not bring to its periodic orbit is
    not scored, as one whose shooting fails is.  The screen is reached only where the
    start's baseline already misses every held-out record, and it only ranks candidates
    for refits made without restarts; a probe model whose march stalls (contraction 0.98 a
    cycle or slower) is one whose refit marches no better.  On the reference design with
    end stops (tests/analysis/measured/test_class_alternatives.py) the inerter design's
    freeplay probe spent 12 shooting iterations, 118 one-period runs at rtol down to
    1e-10 (45 s idle, 2/3 of the whole diagnosis), to end not scored all the same."""
    _, probes, _, queue, extra, _ = _screen(names, base, options, bud, sel,
                                            route="no_shooting")
    for c in queue + extra:
        try:
            fit = _refit(c, probes[c.effect], base, validation, options, bud.preroll,
                         bud.max_nfev, bud.tol, "auto")
        except LiquidampError:  # the candidate's model failed, not the screen
            continue
        yield c.effect, fit
    yield from _device_round(base, validation, options, bud, device_names)[2].items()


def bundled_records() -> dict:
    """Paths of the bundled synthetic records (liquidamp/analysis/measured/data, see its README)."""
    from pathlib import Path

    data = Path(__file__).parent / "data"
    return {p.stem: p for p in sorted(data.glob("*.csv"))}
