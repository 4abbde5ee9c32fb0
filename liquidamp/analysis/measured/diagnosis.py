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
3. Screen every applicable candidate effect by a score test: the model is
   run once with the effect at a probe strength scaled to the record; the
   change of force is the effect's signature s.  With J the Jacobian of the
   calibrated fit, the part of s that the fitted parameters cannot mimic is
   s_perp = s - J J^+ s (J without the columns of parameters held at a bound
   by the residual: the fit cannot move them), and the linearized drop of the
   residual sum of squares from adding the effect is (s_perp . r)^2 / |s_perp|^2 (a
   Lagrange-multiplier test).  A signature that would need a negative
   strength scores zero.  Simple signatures (correlation of the residual
   with sign(v), a, a constant, the dead-band indicator and the low-pressure
   phases) are reported too.
4. Refit the ``top`` candidates with everything free (only those whose linearized
   evidence pays their BIC penalty: N_eff ln(1 - score) + k ln N_eff < 0, N_eff of the
   current residual, k the effect's fitted parameters), starting
   from the linearized strength (cavitation: from the probe's vapour pressure, a
   threshold); when none of these refits brings the calibration
   residual down to ``structure_factor`` times the noise floor, refit also the
   next candidate if its score is within a factor ``score_ratio`` (3) of the best
   (the score test is local: where the calibrated model sits in another basin of
   the c1/c2 trade-off, an effect whose signature overlaps a free parameter's,
   such as leakage and c1, can score below a rival and still fit far better once
   the parameters move).  When no refit of the round brings the residual down to
   ``structure_factor`` times the noise floor, each is refitted once
   more from the physics start of the original multipliers and the better
   fit is kept (the continuation can stay in a local minimum of the c1/c2
   trade-off).  A fit that stops on its evaluation budget (the baseline or a
   refit) is continued once before it is scored or judged; fits that still
   did not converge are listed in ``warnings`` and in the JSON
   (``converged``, ``not_converged``).
5. Accept a refit when both hold:

   * the calibration BIC, counted with the effective number of independent
     samples, falls by more than ``bic_threshold`` (10, "very strong" evidence
     on Kass and Raftery's scale):
     delta BIC = N_eff ln(RSS_new / RSS_now) + (k_new - k_now) ln N_eff < -10,
     N_eff = sum N_i / tau_i with tau_i the integrated autocorrelation time of
     the refit's residual on record i
     (:mod:`liquidamp.analysis.measured.selection`: a densely sampled residual is
     correlated, so N samples are not N independent observations);
   * the held-out (validation) NRMSE does not get worse by more than
     ``validation_tolerance`` (2 %) relative.

   Of the accepted refits the one with the lowest validation NRMSE is added;
   if others lie within ``tie_tolerance`` (10 %) of it, the step records a tie
   with every set of evidence and adds the tied candidate with the fewest
   parameters, unless one with more lowers delta BIC by more than
   ``bic_threshold`` further (parsimony: Coulomb friction over a smooth friction
   whose fitted pre-sliding stiffness is huge; the extra parameter needs the
   evidence an effect of its own would need); among equals the lowest delta BIC.
6. Repeat from 2 with the effect included, at most ``max_steps`` times.

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

import math
import warnings as _warnings
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.measured.calibration import (
    CalibrationResult,
    FitSpec,
    calibrate,
    with_progress,
)
from liquidamp.analysis.measured.checks import check_records, drop_outliers, keep_outliers
from liquidamp.analysis.measured.conditioning import HARMONICS, condition
from liquidamp.analysis.measured.diagnosis_evidence import (
    COMPOSITES,
    CONFOUNDED,
    Candidate,
    applicable,
    confounding,
    confounding_warnings,
    harmonic_structure,
    score,
    signatures,
)
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.analysis.measured.record_quality import noise_floor
from liquidamp.analysis.measured.selection import effective_samples, judge
from liquidamp.device.effects import EFFECTS
from liquidamp.errors import (
    ConvergenceError,
    LiquidampWarning,
    ParameterError,
    check_choice,
)
from liquidamp.options import resolve_options

__all__ = ["Candidate", "Step", "Diagnosis", "diagnose", "CONFOUNDED", "COMPOSITES",
           "signatures", "demo_loop", "bundled_records"]

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
    nrmse_raw : dict
        ``{"calibration": ..., "validation": ...}``: the final model against the records
        as given (empty when the conditioning changed nothing).
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
    nrmse_raw: dict = field(default_factory=dict)

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
                "noise_floors": [{"record": c.source, "force_std [N]": f.force_std,
                                  "rate_force_std [N]": f.rate_force_std,
                                  "nrmse": f.nrmse, "method": f.method,
                                  "harmonics": f.harmonics,
                                  "drift_std [N]": f.drift_std,
                                  "drift_nrmse": f.drift_nrmse,
                                  "nonstationary": bool(f.drift is not None
                                                        and f.drift.nonstationary)}
                                 for c, f in zip(self.conditioning[:len(self.noise_floors)],
                                                 self.noise_floors, strict=True)],
                "conditioning": [c.as_dict() for c in self.conditioning],
                "data_quality": [q.as_dict() for q in self.baseline.data_quality],
                "nrmse_raw": dict(self.nrmse_raw),
                "signatures": self.signatures, "stop_reason": self.stop_reason,
                "unexplained": self.unexplained, "warnings": list(self.warnings),
                "last_round": [c.as_dict() for c in self.last_candidates]}


def _refit(cand, change, current, validation, options, preroll, max_nfev, tol, sizing):
    """Fit the model the candidate proposes, from the current optimum and its estimate.

    ``change`` is the candidate's :class:`~.candidates.Change`: the effects of the candidate
    model and the parameters it frees; the lead starts at the score test's estimate, the
    other freed parameters at their probe values, kept inside their bounds (a decade in
    from wide catalogue bounds, a tenth of the log-range from narrow ones)."""
    effects = list(change.effects)
    spec = FitSpec(current.spec.parameters)
    for name, key in change.free:
        i = next(i for i, e in enumerate(effects) if e.name == name)
        v = getattr(effects[i], key)
        label = key if name == change.added else f"{name}.{key}"
        if (name, key) == change.lead and cand.effect != "cavitation":
            # cavitation's lead is a threshold, not a strength: the linearized value can
            # fall below the lowest chamber pressure, where the effect is inactive and the
            # fit has no gradient
            v = cand.estimate.get(label, v)
        lo, hi = type(effects[i]).bounds[key]
        if lo > 0:
            m = 10.0 if hi / lo >= 1e4 else (hi / lo) ** 0.1
            v = min(max(abs(v), lo * m), hi / m)
        effects[i] = effects[i].replace(**{key: v})
        spec = spec.with_effect(effects[i], keys=(key,))
    res = calibrate(current.calibration, model=current.model, params=current.start_params,
                    effects=tuple(effects), spec=spec, validate=validation,
                    options=options, start="spec", max_nfev=max_nfev, preroll=preroll,
                    tol=tol, warn=False, sizing=sizing)
    if res.status == "max_nfev":
        res = _converge(res, validation, options, preroll, max_nfev, tol, sizing)
    return res


def _restart(res, current, validation, options, preroll, max_nfev, tol, start0, sizing,
             validation_tolerance):
    """Refit from the physics start of the original multipliers; the better of the two fits.

    The continuation from the previous optimum may sit in a local minimum of the loss
    coefficients (the c1/c2 trade-off: least squares on the air ratios and loss
    coefficients has local minima).  The restart is kept where it fits the calibration
    records better and does not lose on the held-out ones by more than
    ``validation_tolerance`` (relative): two optima of one model that differ there differ in
    what the calibration record cannot tell apart (on the friction-damper records a
    restart into strong fluid losses fits the 0.5 Hz loop 3 % better and the 1 and 0.25 Hz
    loops 40 % worse, the losses standing in for friction at one rate only).
    """
    spec2 = res.spec.with_values(start0)
    try:
        res2 = calibrate(current.calibration, model=current.model,
                         params=current.start_params, effects=res.effects,
                         spec=spec2, validate=validation, options=options, start="physics",
                         max_nfev=max_nfev, preroll=preroll, tol=tol, warn=False,
                         sizing=sizing)
        if res2.status == "max_nfev":
            res2 = _converge(res2, validation, options, preroll, max_nfev, tol, sizing)
    except ConvergenceError:
        return res
    if res2.cost >= res.cost:
        return res
    if (res.nrmse_validation is not None
            and res2.nrmse_validation > (1.0 + validation_tolerance) * res.nrmse_validation):
        return res
    return res2


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


@with_progress
def diagnose(calibration, validation, *, model="full", params=None, effects=(),
             candidates=None, spec: FitSpec | None = None, options=None, max_steps: int = 3,
             top: int = 2, bic_threshold: float = 10.0, validation_tolerance: float = 0.02,
             tie_tolerance: float = 0.10, noise_factor: float = 1.5,
             structure_factor: float = 2.0, score_ratio: float = 3.0, max_nfev: int = 60,
             preroll: int = 1, tol: float = 1e-5, force_cutoff: float | None = None,
             decimate="auto", harmonics: float = HARMONICS, average="auto",
             sizing: str = "auto", outliers: str = "refuse",
             baseline: CalibrationResult | None = None) -> Diagnosis:
    """Calibrate, then add catalogue effects the evidence asks for (module doc).

    Parameters
    ----------
    calibration, validation : sequence of Record
        Records to fit and held-out records to judge by (at least one each).
    model, params, effects, spec, options, preroll
        As for :func:`~liquidamp.analysis.measured.calibration.calibrate` (default:
        ``full`` from ``paper_initial`` with the paper's four multipliers free).
    candidates : sequence of str, optional
        Effects to consider (default: the catalogue effects with ``screened`` set
        and fitted parameters, ``fit_keys``, and the composite candidates of
        :data:`COMPOSITES`, e.g. ``"backlash"``: freeplay in series with the friction
        already in the model, ``"friction_asymmetry"``; the others, e.g.
        ``relief_valve``, only when named here; operating conditions such as
        ``rotating_frame`` are given, not diagnosed).
    max_steps : int
        Largest number of effects added.
    top : int
        Candidates refitted per step at least (the best scores).
    score_ratio : float
        When the ``top`` refits leave the residual structured, the next candidate is
        refitted too if its score is at least 1/``score_ratio`` of the best
        (module doc, step 4).
    bic_threshold : float
        Least fall of the effective-sample BIC for an effect to be added [-] (step 5).
    validation_tolerance : float
        Largest relative rise of the held-out NRMSE an added effect may cause [-].
    tie_tolerance, noise_factor, structure_factor : float
        Decision thresholds (module doc).
    progress : callable, optional
        Called as ``progress(1)`` after every model evaluation of every fit
        (keyword only; :func:`~liquidamp.analysis.measured.calibration.with_progress`).
    max_nfev : int
        Evaluation budget of each fit.
    tol : float
        Fit tolerance (ftol = xtol of least squares).
    force_cutoff : float, optional
        Cut-off of the zero-phase force filter applied to every record [Hz] (default:
        none); see :func:`~liquidamp.analysis.measured.conditioning.condition`.
    decimate : 'auto' or int
        Decimation factor of every record (``'auto'``: keep ``harmonics`` harmonics of
        each record's stroke frequency; 1: none).
    harmonics : float
        Harmonics of the stroke frequency kept by ``decimate='auto'`` [-].
    average : 'auto', True or False
        Average the whole cycles of each record into one (``'auto'``: a periodic stroke
        over at least four whole cycles).
    sizing : {'auto', 'preset', 'data'}
        The device the baseline calibration starts from, as for
        :func:`~liquidamp.analysis.measured.calibration.calibrate`; each refit starts
        from the baseline's device, sized again only where calibrate's ``'auto'`` rule
        finds the model with the candidate far from the records.
    outliers : {'refuse', 'drop', 'keep'}
        Spikes in the records as read (:func:`~liquidamp.analysis.measured.checks.check_records`):
        refuse the records (default), drop the force spikes before conditioning
        (:func:`~liquidamp.analysis.measured.checks.drop_outliers`), or keep them.
    baseline : CalibrationResult, optional
        A calibration already done on the records it holds (``baseline.calibration``);
        those records and ``validation`` are used as they are (no conditioning: condition
        them before calibrating).

    Returns
    -------
    Diagnosis

    Raises
    ------
    DataFileError
        Before any model run, as :func:`~liquidamp.analysis.measured.calibration.check_records`:
        a record with no force response above its noise, a stroke past the
        chamber end (``params.stroke_limit``), or a spike in the force or the
        displacement (every record, count and file line named at once; force spikes
        pass with ``outliers='drop'`` or ``'keep'``, displacement spikes with
        ``'keep'``).
    ParameterError
        Bad conditioning options (as :func:`~.conditioning.condition`).

    Warns
    -----
    LiquidampWarning
        With each of ``Diagnosis.warnings``.
    """
    calibration, validation = tuple(calibration), tuple(validation)
    if not validation:
        raise ParameterError("diagnose needs held-out validation records (--validate)")
    for name, v, lo in (("bic_threshold", bic_threshold, 0.0),
                        ("validation_tolerance", validation_tolerance, 0.0)):
        if not (math.isfinite(v) and v >= lo):
            raise ParameterError(f"diagnose: {name} must be a finite number >= {lo:g}, "
                                 f"got {v!r}")
    if params is None:
        from liquidamp.device import preset

        check_params = preset("paper_initial")
    else:
        check_params = params
    # before any model run: noise-only records, spikes (a 30 mm displacement spike made
    # the integration crawl for minutes) and a stroke past the chamber end are refused
    quality, _ = check_records(calibration + validation, check_params, what="diagnose",
                               outliers=outliers)
    if outliers != "refuse" and baseline is None:  # before any conditioning
        nc = len(calibration)
        how = drop_outliers if outliers == "drop" else keep_outliers
        fixed = [how(r, q) for r, q in zip(calibration + validation, quality, strict=True)]
        calibration, validation = tuple(fixed[:nc]), tuple(fixed[nc:])
    names = (tuple(n for n, c in EFFECTS.items() if c.screened and c.fit_keys)
             if candidates is None
             else tuple(candidates))
    if candidates is None:
        names += tuple(COMPOSITES)
    for n in names:
        check_choice("candidate effect", n, {**EFFECTS, **COMPOSITES})
        if n not in COMPOSITES and not EFFECTS[n].fit_keys:
            raise ParameterError(
                f"candidate effect {n!r} has no fitted parameters (an operating condition): "
                "give it with effects=, not as a candidate")
    options = resolve_options(options, "fit")
    raw = (calibration, validation)
    if baseline is None:
        conds = [condition(r, force_cutoff=force_cutoff, decimate=decimate,
                           harmonics=harmonics, average=average)
                 for r in calibration + validation]
        nc = len(calibration)
        calibration = tuple(r for r, _ in conds[:nc])
        validation = tuple(r for r, _ in conds[nc:])
        conditioning = tuple(c for _, c in conds)
        baseline = calibrate(calibration, model=model, params=params, effects=effects,
                             spec=spec, validate=validation, options=options,
                             max_nfev=max_nfev, preroll=preroll, tol=tol, warn=False,
                             sizing=sizing, outliers=outliers)
    else:
        calibration = baseline.calibration
        conditioning = tuple(r.meta.get("conditioning")
                             or condition(r, decimate=1, average=False)[1]
                             for r in calibration + validation)
        raw = (calibration, validation)
    warnings = []
    if baseline.status == "max_nfev":
        # score candidates only against a converged model: a fit stopped on its budget
        # leaves structure that a candidate would "explain" spuriously
        # continued from where it stopped: its device (sized or not) is kept unless far
        baseline = _converge(baseline, validation, options, preroll, max_nfev, tol,
                             "preset" if sizing == "preset" else "auto")
    if not baseline.converged:
        warnings.append(f"NOT CONVERGED: baseline calibration ({baseline.status}): "
                        f"{baseline.message}")
    meas = np.concatenate([r.force for r in calibration])
    den = float(np.sqrt(np.mean((meas - meas.mean()) ** 2)))
    # the floor of each record as conditioned (an averaged cycle: the scatter over its cycles)
    floors = tuple(c.noise if c.noise is not None else noise_floor(r)
                   for c, r in zip(conditioning, calibration, strict=False))
    noise_std = float(np.sqrt(sum(f.std ** 2 * r.time.size
                                  for f, r in zip(floors, calibration, strict=True))
                              / meas.size))
    noise_nrmse = noise_std / den
    sig = signatures(baseline)
    spec0 = baseline.spec if spec is None else spec
    start0 = {p.name: (spec0[p.name].value if p.name in spec0.names else 1.0)
              for p in baseline.spec.parameters if p.kind == "multiplier"}
    if spec is None:
        start0 = dict.fromkeys(start0, 1.0)
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
        round_ = []
        probes = {}
        for n in names:
            if n in present:
                continue
            why = applicable(n, current)
            if why:
                round_.append(Candidate(n, 0.0, 0.0, {}, note=f"not applicable: {why}"))
                continue
            cand, probe = score(n, current, options, preroll)
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
        # candidate pruning: a candidate whose linearized evidence does not even pay its
        # BIC penalty is not refitted (its note says so)
        n_now, _ = effective_samples(current.residuals("calibration"))
        for cand in queue + extra:
            lin = _linear_delta_bic(cand, probes[cand.effect], n_now)
            if lin > 0:
                i = ranked.index(cand)
                ranked[i] = _with(cand, note=(
                    f"not refitted: its score {cand.score:.3g} over N_eff {n_now:.4g} "
                    f"predicts delta BIC {lin:+.3g}, not even its penalty"))
        queue = [c for c in queue if _linear_delta_bic(c, probes[c.effect], n_now) <= 0]
        extra = [c for c in extra if _linear_delta_bic(c, probes[c.effect], n_now) <= 0]
        level = structure_factor * noise_nrmse
        while queue:
            for cand in queue:
                try:
                    refits[cand.effect] = _refit(cand, probes[cand.effect], current,
                                                 validation, options, preroll, max_nfev, tol,
                                                 "auto")
                except (ConvergenceError, ParameterError) as exc:
                    i = ranked.index(cand)
                    ranked[i] = _with(cand, refitted=True, note=f"refit failed: {exc}")
            # a refit that leaves the residual structured is tried once more from the
            # physics start, unless another candidate of the round already explains it
            for cand in queue:
                if cand.effect in refits and not _explained(refits, level):
                    refits[cand.effect] = _restart(refits[cand.effect], current, validation,
                                                   options, preroll, max_nfev, tol, start0,
                                                   "auto", validation_tolerance)
            queue, extra = ([], []) if _explained(refits, level) else (extra, [])
        for cand in [c for c in ranked if c.effect in refits]:
            res = refits[cand.effect]
            v = judge(current.residuals("calibration"), res.residuals("calibration"),
                      len(res.varying) - len(current.varying), current.nrmse_validation,
                      res.nrmse_validation, bic_threshold=bic_threshold,
                      validation_tolerance=validation_tolerance)
            why = ([f"refit: {res.message}"] if not res.converged else []) + list(v.reasons)
            ranked[ranked.index(cand)] = _with(
                cand, refitted=True, nrmse_calibration=res.nrmse_calibration,
                nrmse_validation=res.nrmse_validation, relative_reduction=v.relative_reduction,
                delta_bic=v.delta_bic, n_effective=v.n_effective, accepted=v.accepted,
                note="; ".join(why),
                parameters=probes[cand.effect].parameters(res))
        last_round = tuple(ranked)
        passed = sorted([c for c in ranked if c.accepted], key=lambda c: c.nrmse_validation)
        if not passed:
            best = min((c for c in ranked if c.refitted and c.delta_bic is not None),
                       key=lambda c: c.delta_bic, default=None)
            stop = ("no candidate passes the selection rule (delta BIC with N_eff < "
                    f"-{bic_threshold:g} and held-out NRMSE not worse by more than "
                    f"{validation_tolerance:.0%})"
                    + (f"; best: {best.effect}, delta BIC {best.delta_bic:.4g} (N_eff "
                       f"{best.n_effective:.4g}), validation NRMSE change "
                       f"{-best.relative_reduction:+.1%}" if best else "")
                    + (f"; best score: {scored[0].effect} {scored[0].score:.3g}, linearized "
                       f"delta BIC "
                       f"{_linear_delta_bic(scored[0], probes[scored[0].effect], n_now):+.3g}"
                       ", not refitted" if scored and not best else ""))
            break
        tied = [c for c in passed
                if c.nrmse_validation <= (1 + tie_tolerance) * passed[0].nrmse_validation]
        chosen = _parsimonious(tied, refits, bic_threshold)
        tie = ()
        if len(tied) > 1:
            tie = tuple(c.effect for c in tied)
            warnings.append(
                "tie: " + " and ".join(
                    f"{c.effect} (validation NRMSE {c.nrmse_validation:.4g}, dBIC "
                    f"{c.delta_bic:.4g})" for c in tied)
                + f" explain the residual about equally (validation NRMSE within "
                f"{tie_tolerance:.0%}); {chosen.effect} was added (fewest parameters unless "
                f"more lower delta BIC by over {bic_threshold:g})")
        res = refits[chosen.effect]
        if not res.converged:
            warnings.append(f"NOT CONVERGED: fit with {chosen.effect} ({res.status}): "
                            f"{res.message}")
        warnings += confounding_warnings(chosen.effect, current, res)
        steps.append(Step(chosen.effect, chosen.parameters, res.nrmse_calibration,
                          res.nrmse_validation, tuple(ranked), tie, res,
                          confounding(chosen.effect, current, res)))
        current = res
        last_round = ()
    unexplained = ""
    if current.nrmse_calibration > structure_factor * noise_nrmse:
        # said whenever the residual stays well above the noise floor, with the
        # excitation harmonics that stand out when there are any
        h = harmonic_structure(current, noise_std)
        unexplained = ("residual keeps structure that no candidate explains "
                       f"(calibration NRMSE {current.nrmse_calibration:.3g} vs noise floor "
                       f"{noise_nrmse:.3g}, more than {structure_factor:g} x): "
                       + (h or "no single harmonic of the excitation stands out (broadband "
                          "or non-periodic misfit)"))
    raw_nrmse = {}
    if any(c.changed for c in conditioning):
        m = current.device_model
        raw_nrmse = {role: nrmse([simulate_record(m, current.params, r, options=options,
                                                  preroll=preroll).force for r in recs],
                                 [r.force for r in recs])
                     for role, recs in zip(("calibration", "validation"), raw, strict=True)}
    for w in warnings:
        _warnings.warn(f"diagnose: {w}", LiquidampWarning, stacklevel=2)
    return Diagnosis(baseline=baseline, steps=tuple(steps), final=current,
                     noise_nrmse=noise_nrmse, signatures=sig, stop_reason=stop,
                     unexplained=unexplained, warnings=tuple(warnings),
                     last_candidates=last_round, conditioning=conditioning,
                     noise_floors=floors, nrmse_raw=raw_nrmse)


def _parsimonious(tied: list, refits: dict, bic_threshold: float) -> Candidate:
    """The tied candidate to add: the fewest parameters, unless one with more lowers the
    effective-sample BIC by more than ``bic_threshold`` below it (its extra parameters need
    the same evidence as an effect of their own); the lowest delta BIC among equals."""
    def size(c):
        return len(refits[c.effect].varying)

    order = sorted(tied, key=lambda c: (size(c), c.delta_bic))
    chosen = order[0]
    for c in order[1:]:
        if size(c) > size(chosen) and c.delta_bic < chosen.delta_bic - bic_threshold:
            chosen = c
    return chosen


def _linear_delta_bic(cand: Candidate, change, n_eff: float) -> float:
    """delta BIC the score test predicts: N_eff ln(1 - score) + k ln N_eff (k parameters
    the candidate frees)."""
    k = len(change.free)
    return n_eff * math.log(max(1.0 - cand.score, 1e-300)) + k * math.log(n_eff)


def _explained(refits: dict, level: float) -> bool:
    """Whether a refit of the round brought the calibration NRMSE down to ``level``."""
    return any(r.nrmse_calibration <= level for r in refits.values())


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
