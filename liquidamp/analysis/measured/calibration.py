"""Calibrate a device model against measured records by least squares on force.

The fit specification is kept apart from the model (lmfit-style, without
signature introspection): a :class:`FitSpec` is a tuple of
:class:`Parameter` objects, each naming either a :class:`DeviceParams`
field, varied as a multiplier on the starting parameter set (the paper's
alpha_j of Table 2), or an effect parameter ``"effect.key"`` (e.g.
``"coulomb_friction.force_N"``), varied as an absolute value.  Positive
quantities are fitted in log space, so a multiplier's bounds [0.05, 20] are
symmetric in the fit.
Both live in :mod:`liquidamp.analysis.measured.fit_spec`; the result,
:class:`CalibrationResult`, in :mod:`liquidamp.analysis.measured.calibration_result` (all three
are importable from here).

:func:`calibrate` fits several records at once and validates on others.
The residual is (model force - measured force) / RMS(measured - mean) over
the pooled calibration set, so the cost is NRMSE^2 / 2 with

    NRMSE = RMS(model force - measured force) / RMS(measured force - its mean)

pooled over all records of a set.  Every model run is driven by the
recorded stroke (:func:`liquidamp.analysis.measured.record_model.simulate_record`).

Where the fit starts (:mod:`liquidamp.analysis.measured.start`): from the
given device (``paper_initial`` by default) when the records are near it (its
RMS force within 4x of the measured and the stroke within half its chamber),
else from a similar device sized to the records (piston area, chamber volumes
and loss and inertance factors scaled so that its RMS force equals the
measured one with the stroke inside half the chamber; ``sizing`` chooses).
The multipliers and their bounds then apply to that device; the result states
which device and scale (``CalibrationResult.start``).

Which class of device (:mod:`liquidamp.analysis.measured.device_class`): where
the caller leaves the structure to the start (no ``spec``, ``start='physics'``,
``sizing`` not 'preset'), three structurally different starts are calibrated
cheaply -- that fluid device, a friction damper (smooth friction read off the
loop, little fluid) and a viscous damper with a force offset -- and the one
chosen on the data (effective-sample BIC on the calibration records, held-out
records as a veto) is continued; ``CalibrationResult.device_class`` and
``class_starts`` give every start's figures.  Geometry the records cannot
support is flagged in ``CalibrationResult.plausibility``
(:mod:`liquidamp.analysis.measured.plausibility`).

Local minima (least squares on the air ratios and loss coefficients has
them: a start away from the paper's multipliers can stall at ten times the
noise floor): the default start is taken from physics.  The
record's first harmonic gives the dynamic stiffness K*; the linear model of
the device, a spring k_D in series with the channel (dashpot c and inertance
b_L, eq. 16 with inertia), is solved for k_D and c given b_L; k_D is mapped
to a common multiplier on both air ratios through eq. (2), and c to a common
multiplier on c1 and c2 through the describing function of the quadratic
loss, c_eq = A_p^2 (c1 + 8 c2 Q / (3 pi)).  That start, the specification's
own start and their geometric mean are each evaluated once; from each that can be
used, one common factor on the air ratios and one on the losses are fitted (a 2-parameter
fit that finds the basin, cheap and well conditioned), and the full fit starts from the
best of those; the result reports all three (a sized device already
holds the physics start -- its air ratios and losses matched to K', K'' when
that fits the records better -- so only its start is evaluated).  When none can be used
(the model cannot be run there, or its NRMSE reaches 2.9, where a point that
cannot be run is penalized) :func:`calibrate` refuses with each start tried,
its parameters, NRMSE, predicted against measured peak force, the loop's loss
share (energy sign) and the likely cause: scale, sign or geometry.

Standard errors and correlations come from the Jacobian at the optimum
scaled by the residual variance, s^2 (J^T J)^-1 with s^2 = RSS / (N - p).
They assume independent residuals; model error is correlated in time, so
read them as lower bounds.

Data quality comes first: every record is checked by
:func:`liquidamp.analysis.measured.record_quality.check_record` before any model run.  A
record whose force shows no first harmonic above the noise, whose loop delivers
energy (a flipped force sign), whose sampling is too coarse for the velocity,
or whose stroke reaches the chamber end of the starting device, is refused;
isolated spikes, judged against each record's own local rates, in the displacement
are refused (the stroke drives the model), and in the force either refused
(default) or, with ``outliers="drop"``, left out of the residual and of every
error measure and listed in ``CalibrationResult.dropped`` (``outliers="keep"``
fits every spike as recorded).  The checks run on each record as read, never on the
samples a conditioning made (:func:`check_records`).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C and Table 2.
.. [2] M. Newville et al., LMFIT, doi:10.5281/zenodo.11813 (parameters
   kept apart from the model).
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from liquidamp.analysis.measured.calibration_result import (
    CalibrationResult,
    RecordError,
    parameter_flags,
)
from liquidamp.analysis.measured.checks import (
    OUTLIER_CHOICES,
    _listed,
    check_records,
    drop_outliers,
    dropped_outliers,
    keep_outliers,
)
from liquidamp.analysis.measured.device_class import DEVICE_CLASSES, calibrate_by_class
from liquidamp.analysis.measured.fit_objective import FitObjective, build, predict
from liquidamp.analysis.measured.fit_spec import (
    AIR_COMPLIANCE_SHARE,
    AIR_RATIOS,
    PAPER_FOUR,
    FitSpec,
    Parameter,
    air_floor_spec,
    check_spec_uses,
    scale_effect_bounds,
)
from liquidamp.analysis.measured.plausibility import plausibility_flags
from liquidamp.analysis.measured.progress import with_progress
from liquidamp.analysis.measured.record_model import nrmse
from liquidamp.analysis.measured.record_quality import as_read, check_record_stroke
from liquidamp.analysis.measured.records import Record
from liquidamp.analysis.measured.selection import correlation_inflation
from liquidamp.analysis.measured.start import (
    NEAR_FORCE_RATIO,
    NEAR_STROKE_SHARE,
    SIZING_CHOICES,
    Sizing,
    StartTrial,
    linear_fit,
    linear_stiffness,
    physics_factors,
    refusal_message,
    similar_device,
    similarity_factors,
    stroke_factor,
    stroke_share,
)
from liquidamp.device.effects import (
    EFFECTS,
    chambers_on_absolute_stroke,
    on_absolute_stroke,
    with_effects,
)
from liquidamp.device.models import get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import (
    ConvergenceError,
    DataFileError,
    LiquidampError,
    LiquidampWarning,
    ParameterError,
    PressureError,
    check_choice,
)
from liquidamp.options import PRESETS, SolverOptions, resolve_options

__all__ = ["Parameter", "FitSpec", "CalibrationResult", "RecordError", "calibrate",
           "predict", "physics_start", "check_records", "drop_outliers", "OUTLIER_CHOICES",
           "linear_fit", "FIT_OPTIONS",
           "PAPER_FOUR"]


FIT_OPTIONS = PRESETS["fit"]
"""Solver options for fitting, the ``"fit"`` preset of :data:`liquidamp.options.PRESETS`:
looser than the defaults (rtol 1e-6); the compiled engine (used for the models it supports, see
:func:`liquidamp.analysis.measured.record_model.simulate_record`), with RODAS4 throughout: the
least-squares Jacobians are finite differences of the simulated force, and at
rtol 1e-6 RODAS4's global error is several times smaller than Dormand-Prince's
(|K*| error 2.2e-7 against 1.3e-6 for the reference design at 3 Hz, 3 mm); with
Dormand-Prince the diagnosis of the bundled demo record took 13x longer and
added freeplay and leakage beside the true smooth friction."""


# ---------------------------------------------------------------------------
# physics start


def physics_start(records, base_params: DeviceParams, spec: FitSpec) -> dict:
    """Start values of the paper's multipliers read off the records' first harmonics.

    Returns a dict name -> multiplier for those of inv_gamma1/2 and c1/c2
    that ``spec`` varies (a common factor for each pair, their ratio kept
    from the spec's start).  See the module docstring.  For a record whose
    stroke is not periodic, K* at its dominant frequency comes from the
    linear regression of :func:`~liquidamp.analysis.measured.start.first_harmonic_stiffness`
    and the stroke amplitude is sqrt(2) x its RMS (``Record.stroke_scale``).
    """
    vals = {p.name: p.value for p in spec.parameters}
    p0 = build(base_params, (), FitSpec(tuple(p for p in spec.parameters
                                                if p.kind == "multiplier")), vals)[0]
    out = {}
    pair_g = [n for n in ("inv_gamma1", "inv_gamma2") if n in spec.varying]
    pair_c = [n for n in ("c1", "c2") if n in spec.varying]
    f_air, f_loss = physics_factors(records, p0, air=tuple(pair_g) or ("inv_gamma1",
                                                                       "inv_gamma2"))
    for pair, f in ((pair_g, f_air), (pair_c, f_loss)):
        if f is not None:
            for n in pair:
                out[n] = vals[n] * f
    for n, v in list(out.items()):
        p = spec[n]
        out[n] = min(max(v, p.min), p.max)
    return out


# ---------------------------------------------------------------------------
# the fit


def _pair_groups(var):
    names = [p.name for p in var]
    groups = []
    for pair in (("inv_gamma1", "inv_gamma2"), ("c1", "c2")):
        idx = [names.index(n) for n in pair if n in names and var[names.index(n)].log]
        if idx:
            groups.append(idx)
    return groups


def _keep_masks(records) -> list[np.ndarray]:
    """Per record: True where the sample is fitted (False at dropped outliers of a record
    whose samples are those read, not conditioned)."""
    masks = []
    for r in records:
        k = np.ones(r.time.size, bool)
        if r.meta.get("conditioning") is None:
            k[[o.index for o in r.meta.get("dropped", ())]] = False
        masks.append(k)
    return masks


def _nrmse_kept(preds, records, masks) -> float:
    return nrmse([p[k] for p, k in zip(preds, masks, strict=True)],
                 [r.force[k] for r, k in zip(records, masks, strict=True)])



# ---------------------------------------------------------------------------
# the starting device and the start trials


def _trial(obj: FitObjective, label: str, values: dict, forces=None,
           params: DeviceParams | None = None) -> StartTrial:
    """Run the objective's model at ``values`` once: a StartTrial (errors recorded).

    ``forces`` given: the trial of those forces (no run) on device ``params``."""
    F = forces
    if F is None:
        obj.nfev += 1  # a model evaluation (the fit's count includes its starts)
        try:
            _, _, F = obj.forces(values)
        except (PressureError, ConvergenceError, ParameterError) as exc:
            F = exc
    shown = {k: v for k, v in values.items() if k in obj.spec.varying}
    dev = (obj.base if params is None else params).name or "custom"
    return StartTrial.evaluate(label, shown, dev, F, obj.records, _split(obj.keep, obj.records))


def _split(keep, records):
    out, i = [], 0
    for r in records:
        out.append(keep[i:i + r.time.size])
        i += r.time.size
    return out


def _scaled_values(spec: FitSpec, values: dict, force: float, stroke: float) -> dict:
    """Effect-parameter values scaled with the similar device (by their unit)."""
    fac = similarity_factors(force, stroke)
    out = dict(values)
    for p in spec.parameters:
        if p.kind == "effect":
            eff, key = p.name.split(".", 1)
            out[p.name] = values[p.name] * fac.get(EFFECTS[eff].units.get(key, "-"), 1.0)
    return out


def _start_device(obj: FitObjective, records, validate, sizing: str) -> Sizing:
    """The device the fit starts from: the given one when the records are near it, else
    similar to it and sized to the records (module docstring of start).

    A similar device's force is exactly its factor times the original's (same pressures), so
    the sized candidates' trials are the runs of the unsized device scaled, not new runs."""
    base, effects = obj.base, obj.effects
    t0 = _trial(obj, f"preset {base.name}" if base.name else "given device", obj.fixed)
    ratio0 = 1.0 / t0.rms_ratio if t0.ran and t0.rms_ratio else None
    # a gas-charged device's chambers follow the absolute stroke (on_absolute_stroke)
    absolute = chambers_on_absolute_stroke(obj.model, effects)
    s = stroke_factor(records + validate, base, absolute)
    share = stroke_share(records + validate, base, absolute)
    if sizing == "preset":
        return Sizing(base, effects, False, rms_ratio=ratio0,
                      reason="sizing='preset': the device as given", trials=(t0,))
    near = s == 1.0 and ratio0 is not None and 1 / NEAR_FORCE_RATIO <= ratio0 <= NEAR_FORCE_RATIO
    if near and sizing == "auto":
        return Sizing(base, effects, False, rms_ratio=ratio0, trials=(t0,), reason=(
            f"near the records: measured RMS force {ratio0:.3g}x the device's (within "
            f"{NEAR_FORCE_RATIO:g}x), peak stroke {share:.0%} of its chamber length (at most "
            f"{NEAR_STROKE_SHARE:.0%})"))
    why = []
    if sizing == "data":
        why.append("sizing='data'")
    if not t0.ran:
        why.append(f"the device as given cannot be run under the records ({t0.error})")
    elif not 1 / NEAR_FORCE_RATIO <= ratio0 <= NEAR_FORCE_RATIO:
        why.append(f"measured RMS force {ratio0:.3g}x the device's (more than "
                   f"{NEAR_FORCE_RATIO:g}x off)")
    if s > 1.0:
        why.append(f"peak stroke {share:.0%} of its chamber length V0/A_p "
                   f"({base.stroke_limit * 1e3:.4g} mm; at most {NEAR_STROKE_SHARE:.0%})")

    def objective(p, e):
        o = FitObjective(obj.model, p, e, obj.spec, obj.records, obj.options, obj.preroll,
                       keep=_split(obj.keep, obj.records))
        o.nfev = obj.nfev  # one count of the model runs made to choose the start
        return o

    trials = [t0]
    t1, a = t0, ratio0
    if s > 1.0:
        p1, e1 = similar_device(base, effects, stroke=s)
        o1 = objective(p1, e1)
        t1 = _trial(o1, f"stroke x{s:.3g}", _scaled_values(obj.spec, obj.fixed, 1.0, s))
        obj.nfev = o1.nfev
        trials.append(t1)
        a = 1.0 / t1.rms_ratio if t1.ran and t1.rms_ratio else None
    how = "RMS force of one run"
    if a is None:  # the run failed: the linear model's |K*| at each record's stroke
        p1 = similar_device(base, effects, stroke=s)[0]
        pred = [abs(linear_stiffness(p1, r.frequency, r.stroke_scale)) * r.stroke_scale
                / math.sqrt(2) for r in records]
        a = obj.den / float(np.sqrt(np.mean(np.square(pred))))
        how = "first-harmonic |K*| of the linear model (the run failed)"
    a = float(a)
    vals = _scaled_values(obj.spec, obj.fixed, a, s)
    # candidate 1: the similar device (its force: a x the run above)
    p_sim, e_sim = similar_device(base, effects, force=a, stroke=s)
    f1 = t1.forces
    o_sim = objective(p_sim, e_sim)
    t_sim = _trial(o_sim, "similar device", vals, None if f1 is None else [a * f for f in f1])
    obj.nfev = o_sim.nfev
    trials.append(t_sim)
    cands = [(t_sim, p_sim, e_sim, a, None, None)]
    # candidate 2: its air ratios and losses matched to K', K'' (physics_factors), the force
    # level then corrected (exactly: a similar device of factor rho)
    f_air, f_loss = physics_factors(records, p_sim)
    mult = {**(dict.fromkeys(("inv_gamma1", "inv_gamma2"), f_air) if f_air else {}),
            **(dict.fromkeys(("c1", "c2"), f_loss) if f_loss else {})}
    def named(p, force, fa, fl):
        return p.replace(name=f"{base.name or 'device'} sized (force x{force:.4g}, stroke "
                         f"x{s:.4g}" + (f", air x{fa:.3g}" if fa else "")
                         + (f", losses x{fl:.3g}" if fl else "") + ")")

    p_sim = named(p_sim, a, None, None)
    if mult:
        p2 = named(p_sim.scaled(**mult), a, f_air, f_loss)
        o2 = objective(p2, e_sim)
        t2 = _trial(o2, "air and losses from K*", vals)
        obj.nfev = o2.nfev
        trials.append(t2)
        if t2.ran and t2.rms_ratio:
            rho = 1.0 / t2.rms_ratio
            p3, e3 = similar_device(p2, e_sim, force=rho)
            p3 = named(p3, a * rho, f_air, f_loss)
            vals3 = _scaled_values(obj.spec, vals, rho, 1.0)
            t3 = _trial(objective(p3, e3), "air and losses, level corrected", vals3,
                        [rho * f for f in t2.forces], params=p3)
            trials.append(t3)
            cands.append((t3, p3, e3, a * rho, f_air, f_loss))
    ran = [c for c in cands if c[0].ran]
    t_best, params, eff, a_best, fa, fl = min(ran, key=lambda c: c[0].nrmse) if ran else cands[0]
    name = params.name
    if mult:
        got = ", ".join(([f"air ratios x{f_air:.3g}"] if f_air else [])
                        + ([f"loss coefficients x{f_loss:.3g}"] if f_loss else []))
        how += (f"; {got} from the records' K', K'' "
                f"{'kept' if fa or fl else 'tried, not kept (a worse start)'}")
    trial = dataclasses.replace(t_best, label="sized", device=name)
    return Sizing(params, eff, True, force_scale=a_best, stroke_scale=s,
                  rms_ratio=ratio0, trials=tuple(trials) + (trial,), reason="; ".join(why)
                  + f"; force x{a_best:.4g} from the {how}; stroke x{s:.4g}",
                  air_factor=fa or 1.0, loss_factor=fl or 1.0)


def _with_stroke_limit(quality, records, params: DeviceParams, model=None):
    """The checks with the starting device's chamber end; a stroke past it (as read) is
    refused.  A gas-charged ``model`` holds its chambers on the absolute stroke: each record
    is checked on the device about its mean
    (:func:`~liquidamp.device.effects_damper.on_absolute_stroke`)."""
    def about(r):
        return params if model is None else on_absolute_stroke(model, params, r.offset)[1]

    problems = [p for r in records
                for p in check_record_stroke(as_read(r), about(r))]
    if problems:
        raise DataFileError("calibrate: " + "; ".join(problems))
    return tuple(dataclasses.replace(q, stroke_limit=float(params.stroke_limit))
                 for q in quality)


@with_progress


def calibrate(records, *, model="full", params: DeviceParams | None = None, effects=(),
              spec: FitSpec | None = None, validate=(), options: SolverOptions | None = None,
              start: str = "physics", max_nfev: int = 80, preroll: int = 1,
              tol: float = 1e-6, strict: bool = False,
              outliers: str = "refuse", warn: bool = True,
              sizing: str = "auto", device_class: str = "auto") -> CalibrationResult:
    """Fit ``spec`` to the calibration ``records``; report errors on ``validate`` too.

    Parameters
    ----------
    records : sequence of Record
        Calibration records (fitted together).
    model : str or DeviceModel
        Base device model (default ``full``, eq. 10).
    params : DeviceParams, optional
        Starting parameters the multipliers apply to (default preset
        ``paper_initial``).
    effects : sequence of Effect
        Effects in the model; those named in ``spec`` are fitted, the others
        held at their values.
    spec : FitSpec, optional
        What varies (default: the paper's four multipliers in [0.05, 20]
        and the default fit keys of ``effects``).
    validate : sequence of Record
        Held-out records.
    options : SolverOptions, optional
        Solver options of the model runs (default: the ``"fit"`` preset,
        :data:`FIT_OPTIONS`).
    start : {'physics', 'spec'}
        'physics': evaluate the physics start, the spec's start and their
        geometric mean, fit common air and loss factors from each and the full fit from
        the best of those; 'spec': fit from the spec's start.
    sizing : {'auto', 'preset', 'data'}
        The device the multipliers apply to (:mod:`~liquidamp.analysis.measured.start`):
        'auto' (default) ``params`` when the records are near it, else a
        similar device sized to the records; 'preset' always ``params`` (a
        stroke past its chamber end is refused); 'data' always the sized
        device.
    device_class : {'auto', 'fluid', 'friction', 'viscous', 'valved', 'field'}
        The start's device class (:mod:`~liquidamp.analysis.measured.device_class`):
        'auto' (default) calibrates the sized fluid device, a friction damper, a
        viscous damper with a force offset, a valved viscous damper (the two-slope map,
        :mod:`~liquidamp.analysis.measured.start_valved`) and, where every record carries a
        voltage or
        current channel, a field-controlled (MR/ER) device cheaply and continues the one
        chosen on the
        data, where the caller left the structure to the start (``spec`` None,
        ``start='physics'``, ``sizing`` not 'preset'; otherwise the fluid start alone);
        a class name starts from that class only.
    max_nfev : int
        Budget of model evaluations (each runs every calibration record).
    preroll : int
        Pre-roll passes of each run (records module).
    tol : float
        ftol = xtol of scipy.optimize.least_squares.
    strict : bool
        Raise ConvergenceError instead of returning a result with
        ``converged = False``.
    outliers : {'refuse', 'drop', 'keep'}
        Spikes found by :func:`check_records` in the records as read:
        ``'refuse'`` the records (default); ``'drop'`` the force spikes
        (:func:`drop_outliers`: replaced by the line between their neighbours
        before any conditioning, and left out of the residual and of every NRMSE
        where the record is fitted as read; listed in ``CalibrationResult.dropped``
        and in a warning; a displacement spike is still refused); ``'keep'``:
        fit every spike as recorded (a warning lists them).
    warn : bool
        Issue ``CalibrationResult.warnings`` as :class:`LiquidampWarning` (default;
        :func:`~liquidamp.analysis.measured.diagnosis.diagnose` reports its own).
    progress : callable, optional
        Called as ``progress(1)`` after every model evaluation (e.g. a tqdm
        bar's ``update``); keyword only (:func:`with_progress`).

    Returns
    -------
    CalibrationResult
        New objects; the inputs are not changed.

    Raises
    ------
    DataFileError
        Before any model run (:func:`check_records`): a record whose force's
        first harmonic is not distinguishable from its noise, whose loop
        delivers energy (the force or displacement sign flipped: the message
        names it), whose sampling leaves the velocity more than 10 % low, a
        stroke past the chamber end of the starting device, a displacement
        spike (unless ``outliers='keep'``), or a force spike with
        ``outliers='refuse'``; every record, problem and line is named at once.
    ConvergenceError
        If no start can be used (the message lists each start tried, its
        NRMSE, peak forces and energy sign, and the likely cause), or
        (``strict``) if the fit does not converge.

    Warns
    -----
    LiquidampWarning
        With the text of ``CalibrationResult.warnings`` (not converged,
        trial points that failed, dropped samples, noisy records).
    """
    from scipy.optimize import least_squares

    from liquidamp.device import preset

    records = tuple(records)
    validate = tuple(validate)
    if not records:
        raise ParameterError("calibrate needs at least one calibration record")
    for r in records + validate:
        if not isinstance(r, Record):
            raise ParameterError(f"calibrate takes Record objects, got {type(r).__name__}")
    base = preset("paper_initial") if params is None else params
    effects = tuple(effects)
    structure_open = spec is None  # the caller left the model's structure to the start
    if spec is None:
        spec = FitSpec.default(effects=effects)
    check_spec_uses(base, spec)
    check_choice("start", start, ("physics", "spec"))
    check_choice("sizing", sizing, SIZING_CHOICES)
    check_choice("device_class", device_class, ("auto",) + DEVICE_CLASSES)
    if structure_open and (device_class in ("friction", "viscous", "valved", "field") or (
            device_class == "auto" and start == "physics" and sizing != "preset")):
        res = calibrate_by_class(
            calibrate, records, validate, params=base, effects=effects, sizing=sizing,
            max_nfev=max_nfev, model=model, options=options, preroll=preroll, tol=tol,
            outliers=outliers,
            classes=DEVICE_CLASSES if device_class == "auto" else (device_class,))
        if strict and not res.converged:
            raise ConvergenceError(f"calibration did not converge: {res.message}")
        for w in res.warnings if warn else ():
            warnings.warn(f"calibrate: {w}", LiquidampWarning, stacklevel=2)
        return res
    # the chamber end bounds the stroke as read, about the record's mean; a gas-charged
    # device holds its chambers on the absolute stroke, so its reach is judged about each
    # record's own mean by _with_stroke_limit below (a profile refit of a gas charge whose
    # datum volume V01 is 1.5 cm^3 reaches 36 mm about a mean of -31 mm, 5 mm about 0)
    on_datum = sizing == "preset" and not chambers_on_absolute_stroke(get_model(model), effects)
    quality, found = check_records(records + validate, base if on_datum else None,
                                   outliers=outliers)
    if outliers != "refuse":  # dropped (the force) or kept, in every later check too
        how = drop_outliers if outliers == "drop" else keep_outliers
        nc = len(records)
        records = tuple(how(r, q) for r, q in zip(records, quality[:nc], strict=True))
        validate = tuple(how(r, q) for r, q in zip(validate, quality[nc:], strict=True))
    dropped = dropped_outliers(records + validate)
    for r in records + validate:
        if sum(1 for q in records + validate if q.label == r.label) > 1 and dropped:
            raise ParameterError(f"calibrate: two records share the label {r.label!r}; "
                                 "outliers='drop' needs distinct labels")
    keep_c = _keep_masks(records)
    keep_v = _keep_masks(validate)
    options = resolve_options(options, "fit")
    spec = scale_effect_bounds(spec, records)
    obj = FitObjective(model, base, effects, spec, records, options, preroll, keep=keep_c)
    if not obj.var:
        raise ParameterError("the fit specification varies nothing")
    sz = _start_device(obj, records, validate, sizing)
    if sz.sized:
        spec = spec.with_values(_scaled_values(spec, obj.fixed, sz.force_scale,
                                               sz.stroke_scale))
        runs = obj.nfev  # the model runs made to choose the start
        obj = FitObjective(model, sz.params, sz.effects, spec, records, options, preroll,
                         keep=keep_c)
        obj.nfev = runs
        trials = list(sz.trials)
        candidates = [trials[-1]]  # the sized device's trial (its values: obj.fixed)
    else:
        trials = [dataclasses.replace(sz.trials[0], label="spec")]
        candidates = list(trials)
    quality = _with_stroke_limit(quality, records + validate, sz.params,
                                 with_effects(get_model(model), *sz.effects))

    def x_of(values):
        return np.array([p.to_x(min(max(values[p.name], p.min), p.max)) for p in obj.var])

    if start == "physics" and not sz.sized:  # (a sized device holds the physics start)
        phys = {**obj.fixed, **physics_start(records, obj.base, spec)}
        mid = {k: math.sqrt(phys[k] * obj.fixed[k]) if spec[k].log else
               0.5 * (phys[k] + obj.fixed[k]) for k in obj.fixed}
        candidates += [_trial(obj, "physics", phys), _trial(obj, "geometric mean", mid)]
        trials += candidates[-2:]
    ok = [t for t in candidates if t.ran and t.nrmse < 2.9]
    if not ok:
        raise ConvergenceError(refusal_message(trials, records, sz))
    best = min(ok, key=lambda t: t.nrmse)
    lo, hi = zip(*(p.x_bounds() for p in obj.var), strict=True)
    lo, hi = np.array(lo), np.array(hi)
    x0 = np.clip(x_of(best.values), lo + 1e-12, hi - 1e-12)
    groups = _pair_groups(obj.var) if start == "physics" else []
    if groups:
        # stage 1: one common factor per pair (air ratios, loss coefficients), the
        # other parameters held: a well-conditioned 1-2 parameter fit that lands
        # in the right basin (the c1/c2 trade-off has local minima).  Run from every
        # usable start: the NRMSE at a start does not tell the basin it lies in (on a
        # 6 Hz, 1.5 mm record of the reference design the start nearest at 0.66 led to
        # a basin at 0.13, the geometric mean at 1.08 to one at 0.011), and the full
        # fit continues from the best stage-1 optimum
        G = np.zeros((len(obj.var), len(groups)))
        for j, idx in enumerate(groups):
            G[idx, j] = 1.0
        zb = 4.0 * np.ones(len(groups))
        landed = []
        for t in ok:
            xs = np.clip(x_of(t.values), lo + 1e-12, hi - 1e-12)
            s1 = least_squares(lambda z, xs=xs: obj(np.clip(xs + G @ z, lo, hi)),
                               np.zeros(len(groups)), bounds=(-zb, zb), method="trf",
                               diff_step=1e-3, ftol=1e-4, xtol=1e-4,
                               max_nfev=8 * len(groups) + 4, workers=obj.columns)
            landed.append((float(s1.cost), t, np.clip(xs + G @ s1.x, lo + 1e-12, hi - 1e-12)))
        _, best, x0 = min(landed, key=lambda c: c[0])
    sol = least_squares(obj, x0, bounds=(lo, hi), method="trf", diff_step=1e-3,
                        x_scale=1.0, ftol=tol, xtol=tol, gtol=tol * 1e-2,
                        max_nfev=max_nfev, workers=obj.columns)
    values = obj.values(sol.x)
    params_fit, effects_fit = build(obj.base, obj.effects, spec, values)
    pc = predict(model, params_fit, effects_fit, records, options=options, preroll=preroll)
    pv = predict(model, params_fit, effects_fit, validate, options=options,
                 preroll=preroll) if validate else []
    n = int(obj.keep.sum())
    k = len(obj.var)
    J = np.asarray(sol.jac, float)
    res = np.where(obj.keep, np.concatenate(pc) - obj.meas, 0.0) / obj.scale
    rss_scaled = float(res @ res)
    s2 = rss_scaled * n / max(n - k, 1)  # residual variance in units of 1/sqrt(N) scaling
    # residuals correlated in time (a filtered, decimated or averaged record; a misfit that
    # follows the stroke) carry less information than their count: the covariance is
    # inflated by N / N_eff, N_eff = sum N_i / tau_i with tau_i each record's integrated
    # autocorrelation time (selection.correlation_time; 1 for white residuals)
    sizes = np.cumsum([r.force.size for r in records])[:-1]
    inflation = correlation_inflation([r[k] for r, k in zip(np.split(res, sizes), np.split(
        np.asarray(obj.keep, bool), sizes), strict=True)])
    try:
        cov = np.linalg.pinv(J.T @ J) * s2 / n * inflation
    except np.linalg.LinAlgError:
        cov = np.full((k, k), np.nan)
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(sd, sd)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    stderr = {}
    for i, p in enumerate(obj.var):
        v = values[p.name]
        stderr[p.name] = float(v * sd[i]) if p.log else float(p.scale * sd[i])
    converged = sol.status > 0 and obj.failures < obj.nfev
    status = "converged" if sol.status > 0 else ("max_nfev" if sol.status == 0 else "failed")
    message = sol.message
    if status == "max_nfev":
        message = (f"not converged: stopped after {obj.nfev} model evaluations (max_nfev = "
                   f"{max_nfev}) before the tolerance {tol:g} was met")
    if obj.failures:
        message += f"; {obj.failures} trial point(s) could not be run ({obj.last_error})"
    if strict and not converged:
        raise ConvergenceError(f"calibration did not converge: {message}")
    errs = [RecordError.of(r, "calibration", nrmse(f[m], r.force[m]))
            for f, r, m in zip(pc, records, keep_c, strict=True)]
    errs += [RecordError.of(r, "validation", nrmse(f[m], r.force[m]))
             for f, r, m in zip(pv, validate, keep_v, strict=True)]
    rss = float(np.sum(np.where(obj.keep, np.concatenate(pc) - obj.meas, 0.0) ** 2))
    warns = []
    if not converged:
        warns.append(f"NOT CONVERGED ({status}): {message}")
    elif obj.failures:
        warns.append(f"{obj.failures} trial point(s) could not be run ({obj.last_error})")
    if dropped:
        warns.append(f"{len(dropped)} force outlier(s) dropped from the fit and the error "
                     "measures (replaced by the line between their neighbours before any "
                     "conditioning): "
                     + _listed([f"{lab}, {o.describe()}" for lab, o in dropped]))
    if outliers == "keep" and any(q.outliers for q in quality):
        kept = [(q.source, o) for q in quality for o in q.outliers]
        warns.append(f"{len(kept)} spike(s) kept in the fit as recorded (outliers='keep'): "
                     + _listed([f"{lab}, {o.describe()}" for lab, o in kept]))
    warns += [n for q in quality for n in q.notes]
    spec_fit = spec.with_values(values)
    flags = parameter_flags(spec_fit, tuple(p.name for p in obj.var), values, stderr, J,
                            params_fit)
    warns += flags.warnings()
    plaus = plausibility_flags(params_fit, effects_fit, records, force_scale=sz.force_scale,
                               at_bound=flags.at_bound)
    warns += [f"implausible: {f.message}" for f in plaus]
    if sz.sized:
        warns.append(f"started from a device sized to the records: {sz.params.name} "
                     f"({sz.reason})")
    aic = n * math.log(rss / n) + 2 * k
    bic = n * math.log(rss / n) + k * math.log(n)
    res = CalibrationResult(
        model=get_model(model).name, params=params_fit, start_params=obj.base,
        effects=effects_fit, spec=spec_fit, values={p.name: values[p.name] for p in obj.var},
        stderr=stderr, correlation=corr, varying=tuple(p.name for p in obj.var),
        nrmse_calibration=_nrmse_kept(pc, records, keep_c),
        nrmse_validation=_nrmse_kept(pv, validate, keep_v) if validate else None,
        record_errors=tuple(errs), converged=bool(converged), status=status,
        message=message, nfev=obj.nfev, cost=float(sol.cost), n_samples=n, aic=aic, bic=bic,
        starts=tuple((t.label, t.nrmse if t.ran else math.inf) for t in trials),
        calibration=records,
        validation=validate, predictions_calibration=tuple(pc),
        predictions_validation=tuple(pv), jacobian=J, data_quality=quality, dropped=dropped,
        warnings=tuple(warns), start={**sz.as_dict(), "chosen": best.label},
        start_trials=tuple(dataclasses.replace(t, forces=None) for t in trials), flags=flags,
        plausibility=plaus)
    # an air ratio held at its multiplier bound is continued to its physical floor
    res = _air_continued(res, lambda spec2: calibrate(
        records, model=model, params=res.start_params, effects=res.effects, spec=spec2,
        validate=validate, options=options, start="spec", max_nfev=max_nfev,
        preroll=preroll, tol=tol, strict=strict, outliers=outliers, warn=False,
        sizing="preset"))
    for w in res.warnings if warn else ():
        warnings.warn(f"calibrate: {w}", LiquidampWarning, stacklevel=2)
    return res


def _air_continued(res: CalibrationResult, refit) -> CalibrationResult:
    """The fit continued where it ended with an air ratio at a multiplier bound above the
    physical floor (:func:`~liquidamp.analysis.measured.fit_spec.air_floor`): ``refit(spec)``
    from the fitted values with that bound lowered to the floor; kept where its cost is
    lower, the start and the evaluations counted from the first fit, with a warning.

    An air ratio's physical range reaches 0; the multiplier bound 0.05 is the fit's, not the
    device's (a degassed device held at 0.05 x the start's air leaves its liquid stiffness
    to effects that compensate, and the losses and inertance follow it to their bounds)."""
    low = [n for n, side in res.at_bounds().items() if n in AIR_RATIOS and side == "lower"]
    spec2 = air_floor_spec(res.spec, res.start_params, names=tuple(low)) if low else None
    if spec2 is None:
        return res
    try:
        res2 = refit(spec2)
    except LiquidampError:  # the device with less air cannot be run: the bound's fit stands
        return res
    if not res2.cost < res.cost:
        return res
    said = ", ".join(f"{n} x{res.values[n]:.3g} -> x{res2.values[n]:.3g} ({n} "
                     f"{getattr(res2.params, n):.3g})" for n in low)
    note = (f"air ratio below its multiplier bound {min(res.spec[n].min for n in low):g}: "
            f"{said}; the fit continued to the physical floor (air carrying "
            f"{AIR_COMPLIANCE_SHARE:.0%} of the chamber compliance at p0), calibration NRMSE "
            f"{res.nrmse_calibration:.4g} -> {res2.nrmse_calibration:.4g}")
    return dataclasses.replace(res2, start=res.start, starts=res.starts,
                               start_trials=res.start_trials, nfev=res.nfev + res2.nfev,
                               warnings=res2.warnings + (note,))
