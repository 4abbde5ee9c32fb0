"""Stage "select" of the residual diagnosis: the selection rule on each refit, the
reductions to simpler candidates, the choice among those that pass, and why none did.

Helpers of :func:`liquidamp.analysis.measured.diagnosis.diagnose` (step 5 of its algorithm;
the rule itself is :func:`~liquidamp.analysis.measured.selection.judge`).

References
----------
.. [1] R. E. Kass, A. E. Raftery, "Bayes factors", JASA 90(430), 1995.
"""

from __future__ import annotations

import math
from dataclasses import replace

from liquidamp.analysis.measured.calibration import CalibrationResult
from liquidamp.analysis.measured.diagnosis_evidence import REDUCTIONS, Candidate
from liquidamp.analysis.measured.diagnosis_fits import _freeing, _refit
from liquidamp.analysis.measured.diagnosis_options import SelectionRule
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record, judge_fits
from liquidamp.errors import LiquidampError

__all__: list = []


def _freed_at_bound(res: CalibrationResult, change) -> list:
    """The parameters a candidate freed that end at a bound of the refit."""
    at = res.at_bounds()
    return ([f"{n}.{k} ({at[f'{n}.{k}']})" for n, k in change.free if f"{n}.{k}" in at]
            + [f"{n} ({at[n]})" for n in change.multipliers if n in at])


def _judge_round(ranked, refits, probes, current, sel: SelectionRule):
    """Stage "select", part 1: the selection rule on every refit (per held-out record, the
    honest sample count, no freed parameter at a bound)."""
    for cand in [c for c in ranked if c.effect in refits]:
        res = refits[cand.effect]
        v, new = judge_fits(current, res, sel), heldout_per_record(res)
        why = ([f"refit: {res.message}"] if not res.converged else []) + list(v.reasons)
        bound = _freed_at_bound(res, probes[cand.effect])
        if bound and sel.reject_at_bound:
            why.append("parameter at a bound (its value is the bound's, not the data's): "
                       + ", ".join(bound))
        ranked[ranked.index(cand)] = _with(
            cand, refitted=True, nrmse_calibration=res.nrmse_calibration,
            nrmse_validation=res.nrmse_validation, relative_reduction=v.relative_reduction,
            delta_bic=v.delta_bic, n_effective=v.n_effective,
            accepted=v.accepted and not (bound and sel.reject_at_bound),
            note="; ".join(why), validation_records=new,
            parameters=probes[cand.effect].parameters(res))
    return ranked


def _select(ranked, sel: SelectionRule):
    """Stage "select", part 2: the best held-out candidate that passed, and those tied with
    it (held-out geometric-mean ratio within ``tie_tolerance``)."""
    passed = sorted([c for c in ranked if c.accepted], key=lambda c: -c.relative_reduction)
    if not passed:
        return None, []
    best = 1.0 - passed[0].relative_reduction
    tied = [c for c in passed if 1.0 - c.relative_reduction <= (1 + sel.tie_tolerance) * best]
    return passed[0], tied


def _reduce(chosen, tied, ranked, refits, probes, current, validation, options, bud, sel,
            joint=None):
    """Stage "select", part 3: a chosen candidate that contains a simpler one as a limit
    (:data:`~.candidates.REDUCTIONS`: a relief valve cracking near zero is a laminar bypass)
    gives way to it where the simpler one, refitted if it was not, passes the rule and ties
    on held-out data (within ``tie_tolerance``).  The chain is followed to its end, each
    link refitted from its own probe: the simplest that ties wins (a digressive valve whose
    cracking pressures sit near zero is a leak; the relief valve between them may not tie,
    its refit caught at a cracking pressure the records do not ask for)."""
    if chosen is None:
        return ranked, chosen, tied
    best = 1.0 - chosen.relative_reduction
    for simpler in _chain(chosen.effect):
        cand = next((c for c in ranked if c.effect == simpler), None)
        if cand is None or cand.note.startswith("not applicable"):
            break
        if simpler not in refits:
            if simpler not in probes:
                break
            res, failure = _refit_link(cand, probes[simpler], current, validation, options,
                                       bud, joint, sel)
            if res is None:
                ranked[ranked.index(cand)] = _with(cand, refitted=True,
                                                   note=f"refit failed: {failure}")
                break
            refits[simpler] = res
            ranked = _judge_round(ranked, {simpler: res}, probes, current, sel)
        cand = next(c for c in ranked if c.effect == simpler)
        tie = (1 + sel.tie_tolerance) * best
        warm = _at_the_limit(simpler, probes.get(simpler), refits.get(chosen.effect))
        if warm is not None and not (cand.accepted and 1.0 - cand.relative_reduction <= tie):
            # its own probe's refit stopped short of the limit the chosen one reached: the
            # simpler model refitted once more from the chosen fit's values of its own
            # effect (the limit, where the two models are one), kept where its calibration
            # cost is lower
            change, lead = warm
            res, _ = _refit_link(_with(cand, estimate={**cand.estimate, **lead}), change,
                                 current, validation, options, bud, joint, sel)
            if res is not None and res.cost < refits[simpler].cost:
                refits[simpler] = res
                ranked = _judge_round(ranked, {simpler: res}, probes, current, sel)
                cand = next(c for c in ranked if c.effect == simpler)
        if cand.accepted and 1.0 - cand.relative_reduction <= tie:
            i = ranked.index(cand)
            ranked[i] = _with(cand, note=(cand.note + "; " if cand.note else "") + (
                f"added instead of {chosen.effect}, which reduces to it and ties on held-out "
                "data"))
            tied = [ranked[i]] + [c for c in tied if c.effect != simpler]
            chosen = ranked[i]
    return ranked, chosen, tied


def _at_the_limit(simpler: str, probe, richer):
    """The simpler candidate's change with its effect at the richer refit's fitted values,
    and its lead there (``(change, {label: value})``), or None where the richer model does
    not hold an effect of that name (a relief valve's reduction, leakage, is another effect).

    Backlash at a closed dead band is its friction alone: the friction the backlash refit
    fitted is the simpler model's optimum at that limit, the start its own refit needs."""
    if probe is None or richer is None or probe.added != simpler:
        return None
    fitted = next((e for e in richer.effects if e.name == simpler), None)
    if fitted is None:
        return None
    mine = probe.effect(simpler)
    keys = [k for k in type(mine).fit_keys if hasattr(fitted, k)]
    if not keys:
        return None
    effects = tuple(e.replace(**{k: getattr(fitted, k) for k in keys}) if e.name == simpler
                    else e for e in probe.effects)
    _, key = probe.lead  # (effect, key)
    return replace(probe, effects=effects), {key: getattr(fitted, key)}


def _chain(effect: str):
    """The simpler candidates ``effect`` reduces to, in order (:data:`~.candidates.
    REDUCTIONS` followed to its end: digressive valve, relief valve, leakage)."""
    s = REDUCTIONS.get(effect)
    while s is not None:
        yield s
        s = REDUCTIONS.get(s)


def _simplest_first(wave, pool):
    """The candidates of a fit wave, each preceded by the simpler candidates it contains as
    limits (:data:`~.candidates.REDUCTIONS`) that the screen queued (``pool``: both waves),
    simplest first.

    Nested hypotheses are tested from the smallest up (forward selection): the richer one
    is refitted only where the simpler one leaves the residual above the noise (the quiet
    rule of :func:`~.diagnosis._fit_round`).  The score cannot order them itself: the
    simpler one's signature is the one a free base parameter absorbs (a leak against c1),
    so it scores below the richer one whose extra shape the base cannot absorb (see
    :func:`_bounded_reductions`).  200 Hz leakage bench record: the digressive valve
    (8 free parameters) ranked first and took 1.6 s of 3.4 s to end a tie with the leak
    queued after it.

    Examples
    --------
    >>> from liquidamp.analysis.measured.diagnosis_evidence import Candidate
    >>> c = {n: Candidate(n, s, 0.0, {}) for n, s in (("digressive_valve", 0.79),
    ...      ("relief_valve", 0.76), ("leakage", 0.71), ("elastomer", 0.3))}
    >>> wave = [c["digressive_valve"], c["elastomer"]]
    >>> [x.effect for x in _simplest_first(wave, wave + [c["leakage"]])]
    ['leakage', 'digressive_valve', 'elastomer']
    """
    queued = {c.effect: c for c in pool}
    out: list = []
    for cand in wave:
        for simpler in reversed(list(_chain(cand.effect))):
            if simpler in queued and queued[simpler] not in out:
                out.append(queued[simpler])
        if cand not in out:
            out.append(cand)
    return out


def _n_free(change) -> int:
    """Parameters a candidate's refit frees beyond the current fit's (effect keys and device
    multipliers)."""
    return len(change.free) + len(change.multipliers)


def _at_noise(result, floors, factor: float) -> bool:
    """Whether ``result`` predicts every held-out record within ``factor`` x its noise floor
    (``floors``: record label -> the record's noise floor NRMSE; None or empty: not known,
    False)."""
    if not floors:
        return False
    got = heldout_per_record(result)
    return bool(got) and all(label in floors and v <= factor * floors[label]
                             for label, v in got.items())


def _explained(refits: dict, level: float, floors=None, sel=None) -> bool:
    """Whether a refit of the round brought the calibration NRMSE down to ``level`` and
    every held-out record to ``sel.structure_factor`` x its floor (``floors``: label ->
    noise floor NRMSE [-]; None or empty: the held-out records not judged).

    R_leakage3 (``runs/s12_indep``, a leak 24 x the force noise): Coulomb friction reached
    the level on the calibration record (0.0049 against 0.0054) and held the held-out one
    at 0.051, 27 x its floor; the round was taken as explained, the leak (its score 0.07,
    its signature absorbed by c1) never refitted, and a relief valve followed (held out
    0.031).  Judged on both, the round goes on: the leak is added first, held out 0.0017.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> from liquidamp.analysis.measured.diagnosis_options import SelectionRule
    >>> r = NS(nrmse_calibration=0.004, record_errors=(
    ...     NS(role="validation", label="val", nrmse=0.051),))
    >>> _explained({"c": r}, 0.0054), _explained({"c": r}, 0.0054, {"val": 0.0019},
    ...                                          SelectionRule())
    (True, False)
    """
    return any(r.nrmse_calibration <= level and (
        not floors or _at_noise(r, floors, sel.structure_factor))
        for r in refits.values())


def _held_back(quiet: str, n_quiet: int, silent: bool, n_free: int) -> str:
    """Why a candidate freeing ``n_free`` parameters is not refitted once the refit of
    ``quiet`` (``n_quiet`` free) leaves the calibration residual at the noise ('' where it
    is refitted).

    Freeing more, it could at best tie on the residual and the BIC would charge its extra
    parameters.  Freeing as many, it could at best tie on the residual and the BIC; where
    ``quiet`` predicts every held-out record to its noise too (``silent``), it could at best
    tie there as well: every comparison the rule makes would be decided by the noise
    (200 Hz elastomer bench record: the elastomer at the noise on both records, backlash,
    as many parameters, took 0.9 s of 3.1 s to end 60 x above it).  Freeing fewer, it is
    refitted: the BIC may prefer it at a residual a little above the noise.

    Examples
    --------
    >>> _held_back("elastomer", 7, True, 7)[:57]
    'not refitted: elastomer already leaves the residual at th'
    >>> _held_back("elastomer", 7, False, 7), _held_back("elastomer", 7, True, 6)
    ('', '')
    """
    if n_free > n_quiet:
        return (f"not refitted: {quiet} already leaves the residual at the noise with fewer "
                f"free parameters ({n_quiet} against {n_free})")
    if n_free == n_quiet and silent:
        return (f"not refitted: {quiet} already leaves the residual at the noise, and every "
                f"held-out record at its own, with as many free parameters ({n_free})")
    return ""


def _refit_link(cand, probe, current, validation, options, bud, joint, sel):
    """One reduction refitted from its own probe: ``(result, None)``, or ``(None, why)``
    where the fit could not be made.  ``joint``: the device multipliers the round's
    restarts freed beside each candidate (:class:`~.diagnosis_fits.Joint`,
    :func:`~.diagnosis_fits._freeing`), freed for it too: every candidate of the round is
    judged with the same freedom."""
    try:
        res = _refit(cand, probe, current, validation, options, bud.preroll, bud.max_nfev,
                     bud.tol, "auto")
    except LiquidampError as exc:  # the reduction's model failed
        return None, str(exc)
    return _freeing(res, joint, validation, options, bud.preroll, bud.max_nfev, bud.tol,
                    "auto", sel.validation_tolerance), None


def _bounded_reductions(ranked, refits, probes, current, validation, options, bud, sel,
                        joint=None, noise=0.0):
    """Stage "select", part 1b: the simpler candidates a refit contains as limits
    (:data:`~.candidates.REDUCTIONS`, followed to the end: a digressive valve cracking at
    its least pressure is a relief valve cracking at none, a laminar bypass) not refitted yet
    are refitted from their own probes and judged by the same rule, where the refit passed
    the rule or was rejected for a freed parameter at a bound.

    Rejected at a bound, the records ask for a limit of its model (a richer refit that
    reaches the limit "explains" the round before the simpler one is tried).  Passed, the
    simpler model is in the running too, and the score test cannot rank it: its signature
    is the one a free base parameter absorbs (a leak against c1), so it scores far below the
    richer one whose extra shape the base cannot absorb.  Independent record R_leakage40
    (``runs/s14_lead``, leak 39 x the force noise): the leak scored 0.048 against the relief
    valve's 0.94, a series spring won round 1 (held out 0.026) and the leak came second;
    refitted as the passing relief valve's reduction it is added first, coefficient -0.7 %,
    held out 0.0756 -> 0.0017, and nothing else.

    Where a refit of the round already leaves the calibration residual at the noise
    (``noise``, the loop's stop), a refit that ended above it gives no reduction: the
    simpler model is a limit of it, so its calibration residual cannot come below that refit's
    (200 Hz elastomer bench record: the elastomer at the noise, backlash 60 x above it with
    its gap at a bound, whose friction alone took 0.46 s of 3.3 s to end higher still)."""
    explained = _explained(refits, noise)  # on the calibration records alone
    todo = {}
    for c in ranked:
        if explained and c.effect in refits and refits[c.effect].nrmse_calibration > noise:
            continue
        if c.effect in refits and (c.accepted or _freed_at_bound(refits[c.effect],
                                                                 probes[c.effect])):
            for s in _chain(c.effect):
                if s in todo:
                    break
                todo[s] = c.effect
    new = {}
    for s, richer in todo.items():
        i = next((i for i, c in enumerate(ranked) if c.effect == s), None)
        if s in refits or s not in probes or i is None:
            continue
        why = f"refitted: {richer}, which reduces to it, ended with a parameter at a bound"
        res, failure = _refit_link(ranked[i], probes[s], current, validation, options, bud,
                                   joint, sel)
        if res is None:
            why += f"; refit failed: {failure}"
        else:
            new[s] = res
        ranked[i] = _with(ranked[i], refitted=True, note=why)
    refits.update(new)
    ranked = _judge_round(ranked, new, probes, current, sel)
    return [_with(c, note="; ".join(x for x in (f"{todo[c.effect]}'s reduction (it ended with "
                                                 "a parameter at a bound)", c.note) if x))
            if c.effect in new else c for c in ranked]


def _no_pass(ranked, scored, probes, n_now, sel: SelectionRule) -> str:
    best = min((c for c in ranked if c.refitted and c.delta_bic is not None),
               key=lambda c: c.delta_bic, default=None)
    return ("no candidate passes the selection rule (held out: no record worse by more than "
            f"{sel.validation_tolerance:.0%} and better together by more than it; delta BIC "
            f"over the {sel.sample_count} sample count < -{sel.bic_threshold:g}; no freed "
            "parameter at a bound)"
            + (f"; best: {best.effect}, delta BIC {best.delta_bic:.4g} (N {best.n_effective:.4g}"
               f"), held-out change {-best.relative_reduction:+.1%}"
               + (f" ({best.note})" if best.note else "") if best else "")
            + (f"; best score: {scored[0].effect} {scored[0].score:.3g}, linearized "
               f"delta BIC {_linear_delta_bic(scored[0], probes[scored[0].effect], n_now):+.3g}"
               ", not refitted" if scored and not best else ""))


def _linear_delta_bic(cand: Candidate, change, n_eff: float) -> float:
    """delta BIC the score test predicts: N_eff ln(1 - score) + k ln N_eff (k freed)."""
    return n_eff * math.log(max(1.0 - cand.score, 1e-300)) + len(change.free) * math.log(n_eff)


def _with(c: Candidate, **changes) -> Candidate:
    return replace(c, **changes)
