"""The refits of the residual diagnosis: a candidate's fit, its restart, a continued fit, and
the profile restart of a chosen effect's parameter the records hardly determine.

Helpers of :func:`liquidamp.analysis.measured.diagnosis.diagnose` (stage "fit"): each calls
:func:`~liquidamp.analysis.measured.calibration.calibrate` on the records the diagnosis holds.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C.
"""

from __future__ import annotations

import dataclasses

from liquidamp.analysis.measured.calibration import FitSpec, calibrate
from liquidamp.analysis.measured.candidates import DEVICE_REFINEMENTS
from liquidamp.analysis.measured.diagnosis_evidence import Candidate
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record, judge_fits
from liquidamp.analysis.measured.fit_spec import Parameter
from liquidamp.analysis.measured.profile import profile_restart, undetermined_parameter
from liquidamp.errors import LiquidampError

__all__: list = []


def _refit(cand, change, current, validation, options, preroll, max_nfev, tol, sizing):
    """Fit the model the candidate proposes, from the current optimum and its estimate.

    ``change`` is the candidate's :class:`~.candidates.Change`: the effects of the candidate
    model and the parameters it frees; the lead starts at the score test's estimate, the
    other freed parameters at their probe values, kept inside their bounds (a decade in
    from wide catalogue bounds, a tenth of the log-range from narrow ones, 5 % of the range
    from linear ones)."""
    effects = list(change.effects)
    spec = FitSpec(current.spec.parameters)
    if change.added == "gas_charge":
        # a gas-charged device's chambers sit at the charge (on_absolute_stroke): its charge,
        # freed, is the level; the filling pressure's multiplier is held.  On records at one
        # stroke frequency the gas rate and the channel's inertance are one in-phase
        # stiffness (k_g - w^2 rho_l S_t A_p^2): the inertance is held where the fit without
        # the gas put it, and the held-out records judge the rate
        held = {"p0"} | ({"S_t"} if len({round(r.frequency, 6) for r in current.calibration})
                         == 1 else set())
        spec = FitSpec(tuple(p.replace(vary=False) if p.name in held else p
                             for p in spec.parameters))
    for name, key in change.free:
        i = next(i for i, e in enumerate(effects) if e.name == name)
        v = getattr(effects[i], key)
        label = key if name == change.added else f"{name}.{key}"
        if (name, key) == change.lead and cand.effect != "cavitation":
            # cavitation's lead is a threshold, not a strength: the linearized value can
            # fall below the lowest chamber pressure, where the effect is inactive and the
            # fit has no gradient
            v = cand.estimate.get(label, v)
            if change.added == "gas_charge" and key == "rod_area_m2" and v > 0:
                # the gas keeps the probe's travel V_g / A_r (its rate then follows the
                # estimated preload as the probe's did)
                effects[i] = effects[i].replace(
                    gas_volume_m3=effects[i].gas_volume_m3 * v / effects[i].rod_area_m2)
        lo, hi = type(effects[i]).bounds[key]
        if lo > 0:
            m = 10.0 if hi / lo >= 1e4 else (hi / lo) ** 0.1
            v = min(max(abs(v), lo * m), hi / m)
        else:  # a linear parameter (a depth, a signed offset): 5 % of its range inside
            v = min(max(v, lo + 0.05 * (hi - lo)), hi - 0.05 * (hi - lo))
        effects[i] = effects[i].replace(**{key: v})
        spec = spec.with_effect(effects[i], keys=(key,))
    for name in change.multipliers:
        # a device multiplier freed (its start: the score test's estimate, inside the bounds
        # of the other multipliers)
        lo, hi = _multiplier_bounds(spec, name, change)
        v = min(max(float(cand.estimate.get(name, change.probe)), lo * 1.5), hi / 1.5)
        spec = _free_multiplier(spec, name, change, v)
    res = calibrate(current.calibration, model=current.model,
                    params=change.start or current.start_params,
                    effects=tuple(effects), spec=spec, validate=validation,
                    options=options, start="spec", max_nfev=max_nfev, preroll=preroll,
                    tol=tol, warn=False, sizing=sizing)
    if res.status == "max_nfev":
        res = _converge(res, validation, options, preroll, max_nfev, tol, sizing)
    return res


def _multiplier_bounds(spec, name, change) -> tuple[float, float]:
    """Bounds of the device multiplier ``name``: those ``change`` states for it, else the
    spec's other multipliers'."""
    lo, hi = next(((p.min, p.max) for p in spec.parameters if p.kind == "multiplier"),
                  (0.05, 20.0))
    return next(((a, b) for n, a, b in getattr(change, "bounds", ()) if n == name), (lo, hi))


def _free_multiplier(spec, name, change, v):
    """``spec`` with the device multiplier ``name`` varying from ``v`` [-], in
    :func:`_multiplier_bounds`."""
    if name in spec.names:
        return FitSpec(tuple(p.replace(value=v, vary=True) if p.name == name else p
                             for p in spec.parameters))
    return FitSpec(spec.parameters + (Parameter(name, v, *_multiplier_bounds(spec, name,
                                                                             change)),))


def _device_round(current, validation, options, bud, names):
    """Stage "fit", device part: every device parameter the preset holds fixed
    (:data:`~.candidates.DEVICE_REFINEMENTS`: the channel inertance S_t) refitted freed,
    whatever its score (the score test is local and S_t moves far); it competes with the
    round's effects under the same rule, and when chosen it is the device's own parameter,
    not an effect (``Diagnosis.device_steps``).  Returns candidates, changes and refits."""
    cands, changes, refits = [], {}, {}
    for name, comp in DEVICE_REFINEMENTS.items():
        if name not in names or comp.applicable(current):
            continue
        change = comp.change(current)
        cand = Candidate(name, 0.0, 0.0, {}, note="device parameter freed (refitted always)")
        try:
            refits[name] = _refit(cand, change, current, validation, options, bud.preroll,
                                  bud.max_nfev, bud.tol, "auto")
            low = [n for n, _, _ in change.bounds
                   if refits[name].at_bounds().get(n) == "lower"]
            if low:  # an inertance the records cannot tell from none: held at its least
                change = dataclasses.replace(change, multipliers=tuple(
                    m for m in change.multipliers if m not in low))
                res = refits[name]
                held = tuple(Parameter(n, res.values[n], lo, hi, vary=False)
                             for n, lo, hi in change.bounds if n in low)
                current_held = dataclasses.replace(current, spec=FitSpec(
                    current.spec.parameters + held))
                refits[name] = _refit(cand, change, current_held, validation, options,
                                      bud.preroll, bud.max_nfev, bud.tol, "auto")
        except LiquidampError as exc:  # the candidate's model failed, not the loop
            cand = dataclasses.replace(cand, refitted=True, note=f"refit failed: {exc}")
        cands.append(cand)
        changes[name] = change
    return cands, changes, refits


def _restart(res, current, validation, options, preroll, max_nfev, tol, start0, sizing,
             validation_tolerance, joint=None):
    """Refit from the physics start and from the original multipliers; the best of the fits,
    then continued with the device refinements ``joint`` freed too (:func:`_freeing`).

    The continuation from the previous optimum may sit in a local minimum of the loss
    coefficients (the c1/c2 trade-off: least squares on the air ratios and loss
    coefficients has local minima).  The restart is kept where it fits the calibration
    records better and does not lose on any held-out record by more than
    ``validation_tolerance`` (relative): two optima of one model that differ there differ in
    what the calibration record cannot tell apart (on the friction-damper records a
    restart into strong fluid losses fits the 0.5 Hz loop 3 % better and the 1 and 0.25 Hz
    loops 40 % worse, the losses standing in for friction at one rate only).

    ``joint``: the :class:`Joint` of the device refinements applicable to ``current``
    (:data:`~.candidates.DEVICE_REFINEMENTS`: the channel inertance S_t that the preset
    holds), given where none alone passes the selection rule.
    """
    spec2 = res.spec.with_values(start0)
    tries = []
    # from the physics start (air and losses read off K', K'' of the records, which a strong
    # friction loop also feeds); and where the refit left a device multiplier at a bound
    # (a fluid fit without the effect pushed a loss coefficient there, and the continuation
    # stays: held by the bound, its gradient says nothing of the interior), also from the
    # original multipliers as they are, with the effects where the refit put them
    mult = {p.name for p in res.spec.parameters if p.kind == "multiplier"}
    pinned = bool(mult & set(res.at_bounds()))
    # a gas charge's refit starts from its datum device (Change.start), kept by the restart
    gas = any(e.name == "gas_charge" for e in res.effects)
    params0 = res.start_params if gas else current.start_params
    for how in ("physics", "spec") if pinned else ("physics",):
        try:
            r2 = calibrate(current.calibration, model=current.model,
                           params=params0, effects=res.effects,
                           spec=spec2, validate=validation, options=options, start=how,
                           max_nfev=max_nfev, preroll=preroll, tol=tol, warn=False,
                           sizing=sizing)
            if r2.status == "max_nfev":
                r2 = _converge(r2, validation, options, preroll, max_nfev, tol, sizing)
        except LiquidampError:  # this start's model or fit failed (as a refit's): the others
            continue
        tries.append(r2)
    if tries:
        res = _better(res, min(tries, key=lambda r: r.cost), validation_tolerance)
    return _freeing(res, joint, validation, options, preroll, max_nfev, tol, sizing,
                    validation_tolerance)


@dataclasses.dataclass(frozen=True)
class Joint:
    """What :func:`_freeing` frees beside a candidate, and what it must reach.

    Attributes
    ----------
    multipliers : dict
        Device multiplier name -> :class:`Parameter` (varying, in its bounds, from 1: the
        preset's value; only multipliers the current fit does not hold, the others it
        fits or holds already).
    level : float
        Calibration NRMSE the continued fit must reach to be kept [-]: the structure level
        (``structure_factor`` x the noise floor) that the round's first fits missed.
    """

    multipliers: dict
    level: float


def _joint_multipliers(current, changes, level: float) -> Joint | None:
    """The :class:`Joint` of the device refinements ``changes`` (their multipliers that
    ``current`` does not hold), or None where they free none."""
    out = {}
    for change in changes:
        for name in change.multipliers:
            if name not in current.spec.names and name not in out:
                out[name] = Parameter(name, 1.0,
                                      *_multiplier_bounds(current.spec, name, change))
    return Joint(out, float(level)) if out else None


def _better(res, res2, validation_tolerance):
    """``res2`` where it fits the calibration records better than ``res`` and loses on no
    held-out record by more than ``validation_tolerance`` (relative), else ``res``."""
    if res2.cost >= res.cost:
        return res
    a, b = heldout_per_record(res), heldout_per_record(res2)
    if any(b[k] > (1.0 + validation_tolerance) * a[k] for k in a if k in b):
        return res  # worse on a held-out record: judged record by record
    return res2


def _freeing(res, joint: Joint | None, validation, options, preroll, max_nfev, tol, sizing,
             validation_tolerance):
    """The fit ``res`` continued from where it arrived with the device multipliers of
    ``joint`` (those ``res``'s spec holds, varying or held, are left as they are) varying
    beside its own parameters; kept where it reaches ``joint.level`` and is the better of
    the two (:func:`_better`), else ``res``.  Only a continuation that explains what the
    round's fits left unexplained replaces a refit: one that merely fits a little better
    would tip a round between poor candidates by the device's freedom (independent record
    d03: a series spring with S_t freed, 7 x the noise, 0.34 held out, passed an elastomer
    at 0.37 and led the loop away from the start that reaches 0.012).

    A device refinement (the channel inertance S_t) competes alone in every round
    (:func:`_device_round`), but an effect and a device parameter can each fail
    alone and explain the residual together: an elastomer on a device whose channel
    inertance is 15 % off the preset's (independent-simulator record R_elastomer40: the
    elastomer with S_t held fits the calibration at 5 x the noise floor and the held-out
    record at 0.10, its branch a dashpot; with S_t freed beside it at the noise, held out
    0.010 to 0.035), and greedily neither is ever added.  Every candidate of such a round
    is judged with the same freedom: its restart (:func:`_restart`) and the simpler models
    a richer one reduces to (:func:`~.diagnosis_select._refit_link`)."""
    if joint is None:
        return res
    # a multiplier the refit's spec holds stays held: held by design (a gas charge's refit
    # holds the filling pressure, its chambers sit at the charge) or by an earlier round (an
    # inertance the records could not tell from none)
    freed = {n: p for n, p in joint.multipliers.items() if n not in res.spec.names}
    if not freed:
        return res
    spec = FitSpec(res.spec.with_values(res.values).parameters
                   + tuple(p.replace(vary=True) for p in freed.values()))
    try:
        r = calibrate(res.calibration, model=res.model, params=res.start_params,
                      effects=res.effects, spec=spec, validate=validation, options=options,
                      start="spec", max_nfev=max_nfev, preroll=preroll, tol=tol, warn=False,
                      sizing=sizing)
        if r.status == "max_nfev":
            r = _converge(r, validation, options, preroll, max_nfev, tol, sizing)
    except LiquidampError:  # the model with the device freed failed: the fit as it was
        return res
    return _better(res, r, validation_tolerance) if r.nrmse_calibration <= joint.level else res


def _converge(result, validation, options, preroll, max_nfev, tol, sizing):
    """Continue a fit that stopped on its evaluation budget from where it stopped.

    The refits (and their continuations) run calibrate's own rule for their start
    (``sizing="auto"``): from the baseline's device, sized again only where the model with
    the candidate is far from the records (RMS force more than 4x off, or the stroke past
    half the chamber); ``sizing`` of :func:`diagnose` chooses the baseline's start."""
    return calibrate(result.calibration, model=result.model, params=result.start_params,
                     effects=result.effects, spec=result.spec, validate=validation,
                     options=options, start="spec", max_nfev=max_nfev, preroll=preroll,
                     tol=tol, warn=False, sizing=sizing)


def _profiled(res, change, validation, options, preroll, max_nfev, tol, validation_tolerance):
    """The chosen candidate's fit after a profile restart over its least determined freed
    parameter (:func:`~liquidamp.analysis.measured.profile.profile_restart`), and the
    profile (None where every freed parameter is determined: standard error below its value).

    A freed parameter whose linearized standard error exceeds its value sits on a nearly
    flat valley of the objective (it trades with other fitted parameters: an elastomer's
    parallel spring with its Maxwell branch's relaxation time), where the fit stops wherever
    it arrives.  The profile finds the valley's minimum and the interval the records allow;
    the fit restarted from that minimum is kept where its calibration cost is lower and, as
    :func:`_restart` judges two optima of one model, no held-out record is worse by more
    than ``validation_tolerance`` (relative)."""
    name = undetermined_parameter(res, [f"{n}.{k}" for n, k in change.free])
    if not name:
        return res, None

    def fit(spec):
        r = calibrate(res.calibration, model=res.model, params=res.start_params,
                      effects=res.effects, spec=spec, validate=validation, options=options,
                      start="spec", max_nfev=max_nfev, preroll=preroll, tol=tol, warn=False,
                      sizing="preset")
        if r.status == "max_nfev":
            r = _converge(r, validation, options, preroll, max_nfev, tol, "preset")
        return r

    res2, prof = profile_restart(res, name, fit)
    if res2 is res:
        return res, prof
    a, b = heldout_per_record(res), heldout_per_record(res2)
    if any(b[k] > (1.0 + validation_tolerance) * a[k] for k in a if k in b):
        return res, dataclasses.replace(prof, restarted=False)
    return res2, prof


def _profile_step(res, chosen, probes, current, validation, options, bud, sel, warnings):
    """Stage "select", part 4: the chosen effect's fit after the profile restart over its
    least determined freed parameter (:func:`_profiled`), kept only where it still passes the
    selection rule against ``current``; the candidate's parameters follow it, and
    ``warnings`` (a list) gains the profile's report.  Returns the fit, the candidate and the
    profile (None: nothing undetermined, or the profile failed).

    The profile refines a fit the rule has already accepted: where one of its refits fails
    (a library error: a chamber at the pressure floor, a record the profile's device cannot
    take), the accepted fit stands and ``warnings`` says why it was not profiled, rather than
    the whole diagnosis stopping (a gas charge's profile refit once refused a vehicle-damper
    record and ended the diagnosis with exit code 2; ``runs/s14_lead``)."""
    try:
        res, chosen, prof = _profile_judged(res, chosen, probes, current, validation,
                                            options, bud, sel)
    except LiquidampError as exc:
        warnings.append(f"not profiled: {chosen.effect}'s fit kept where it stopped (its "
                        f"profile failed: {exc})")
        return res, chosen, None
    if prof is not None:
        warnings.append(_profile_warning(chosen.effect, prof))
    return res, chosen, prof


def _profile_judged(res, chosen, probes, current, validation, options, bud, sel):
    res2, prof = _profiled(res, probes[chosen.effect], validation, options, bud.preroll,
                           bud.max_nfev, bud.tol, sel.validation_tolerance)
    if prof is None or res2 is res:
        return res, chosen, prof
    v, new = judge_fits(current, res2, sel), heldout_per_record(res2)
    if not v.accepted:
        return res, chosen, dataclasses.replace(prof, restarted=False)
    chosen = dataclasses.replace(chosen, parameters=probes[chosen.effect].parameters(res2),
                   nrmse_calibration=res2.nrmse_calibration,
                   nrmse_validation=res2.nrmse_validation,
                   relative_reduction=v.relative_reduction, delta_bic=v.delta_bic,
                   validation_records=new)
    return res2, chosen, prof


def _profile_warning(effect: str, prof) -> str:
    """The sentence that reports a profiled parameter of an added effect."""
    what = ("the fit restarted from the profile's minimum" if prof.restarted else
            "the fit kept where it stopped (the restart from the profile's minimum did not "
            "lower the calibration cost, or lost on a held-out record)")
    honest = ("" if prof.determined else
              "; the calibration records do not determine it: read the value as the "
              "least-squares point of a flat valley, not a measurement")
    return (f"profiled: {effect}'s {prof.name.split('.', 1)[-1]} had a standard error above "
            f"its value; {prof.describe()}; {what}{honest}")
