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

Local minima (least squares on the air ratios and loss coefficients has
them: a start away from the paper's multipliers can stall at ten times the
noise floor): the default start is taken from physics.  The
record's first harmonic gives the dynamic stiffness K*; the linear model of
the device, a spring k_D in series with the channel (dashpot c and inertance
b_L, eq. 16 with inertia), is solved for k_D and c given b_L; k_D is mapped
to a common multiplier on both air ratios through eq. (2), and c to a common
multiplier on c1 and c2 through the describing function of the quadratic
loss, c_eq = A_p^2 (c1 + 8 c2 Q / (3 pi)).  That start, the specification's
own start and their geometric mean are each evaluated once and the fit
starts from the best; the result reports all three.

Standard errors and correlations come from the Jacobian at the optimum
scaled by the residual variance, s^2 (J^T J)^-1 with s^2 = RSS / (N - p).
They assume independent residuals; model error is correlated in time, so
read them as lower bounds.

Data quality comes first: every record is checked by
:func:`liquidamp.analysis.measured.record_quality.check_record` before any model run.  A
record whose force shows no first harmonic above the noise, or whose stroke
reaches the chamber end, is refused; isolated spikes (a Hampel filter) in the
displacement are refused (the stroke drives the model), and in the force
either refused (default) or, with ``outliers="drop"``, left out of the
residual and of every error measure and listed in ``CalibrationResult.dropped``.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C and Table 2.
.. [2] M. Newville et al., LMFIT, doi:10.5281/zenodo.11813 (parameters
   kept apart from the model).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from liquidamp.analysis.measured.calibration_result import CalibrationResult, RecordError
from liquidamp.analysis.measured.fit_spec import PAPER_FOUR, FitSpec, Parameter, check_spec_uses
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.analysis.measured.record_quality import DataQuality, check_record
from liquidamp.analysis.measured.records import Record
from liquidamp.device.effects import EFFECTS, Effect, with_effects
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
           "predict", "physics_start", "check_records", "FIT_OPTIONS", "PAPER_FOUR"]


FIT_OPTIONS = PRESETS["fit"]
"""Solver options for fitting, the ``"fit"`` preset of :data:`liquidamp.options.PRESETS`:
looser than the defaults (rtol 1e-6); the compiled engine (used for the models it supports, see
:func:`liquidamp.analysis.measured.record_model.simulate_record`), with RODAS4 throughout: the
least-squares Jacobians are finite differences of the simulated force, and at
rtol 1e-6 RODAS4's global error is several times smaller than Dormand-Prince's
(|K*| error 2.2e-7 against 1.3e-6 for the reference design at 3 Hz, 3 mm); with
Dormand-Prince the diagnosis of the bundled demo record took 13x longer and
added freeplay and leakage beside the true smooth friction."""

def build(base_params: DeviceParams, effects: tuple[Effect, ...], spec: FitSpec,
          values: dict) -> tuple[DeviceParams, tuple[Effect, ...]]:
    """Parameters and effects for fit ``values`` (name -> value); inputs untouched.

    Multipliers apply through :meth:`DeviceParams.scaled`: on ``c1``, ``c2``,
    ``S_t`` they scale the loss/inertance factor (or the explicit value), on
    ``mu``, ``l_t``, ``A_t`` the geometry the derived coefficients follow.
    """
    check_spec_uses(base_params, spec)
    mult = {p.name: values.get(p.name, p.value) for p in spec.parameters
            if p.kind == "multiplier"}
    params = base_params.scaled(**mult) if mult else base_params
    by_name = {e.name: e for e in effects}
    for name in spec.effect_names():
        if name not in by_name:
            by_name[name] = EFFECTS[name]()
    changes: dict[str, dict] = {}
    for p in spec.parameters:
        if p.kind == "effect":
            eff, key = p.name.split(".", 1)
            changes.setdefault(eff, {})[key] = values.get(p.name, p.value)
    out = []
    for name, e in by_name.items():
        out.append(e.replace(**changes[name]) if name in changes else e)
    return params, tuple(out)


def predict(model, params: DeviceParams, effects, records, *, options=None,
            preroll: int = 1) -> list[np.ndarray]:
    """Model force [N] for each record (driven by its stroke)."""
    m = with_effects(get_model(model), *effects)
    opts = resolve_options(options, "fit")
    return [simulate_record(m, params, r, options=opts, preroll=preroll).force for r in records]


def check_records(records, params: DeviceParams | None = None, *, outliers: str = "raise",
                  what: str = "calibrate") -> tuple[tuple[DataQuality, ...], tuple]:
    """Check records before a fit; raise on what cannot be fitted honestly.

    Parameters
    ----------
    records : sequence of Record
        Every record of the fit (calibration and validation).
    params : DeviceParams, optional
        Device whose chamber end bounds the stroke.
    outliers : {'raise', 'drop'}
        Force spikes: refuse (default) or return them to be left out.
    what : str
        Name of the caller in the messages.

    Returns
    -------
    (tuple of DataQuality, tuple of (label, Outlier))
        The checks and the force samples to drop (empty unless ``'drop'``).

    Raises
    ------
    DataFileError
        A record holds no force response above its noise, a stroke past the
        chamber end, a displacement spike, or (``outliers='raise'``) a force
        spike; the record, the line and the values are named.
    """
    check_choice("outliers", outliers, ("raise", "drop"))
    records = tuple(records)
    qs = tuple(check_record(r, params) for r in records)
    problems = [p for q in qs for p in q.problems]
    if problems:
        raise DataFileError(f"{what}: " + "; ".join(problems))
    disp = [(q, o) for q in qs for o in q.outliers if o.column == "displacement"]
    if disp:
        raise DataFileError(
            f"{what}: {len(disp)} displacement spike(s) (Hampel filter, check_record): "
            + _listed([f"{q.source}, {o.describe()}" for q, o in disp])
            + "; the recorded stroke drives the model, so these samples cannot be dropped: "
            "correct or remove them in the file")
    force = [(r.label, o) for r, q in zip(records, qs, strict=True) for o in q.outliers
             if o.column == "force"]
    if force and outliers == "raise":
        raise DataFileError(
            f"{what}: {len(force)} force outlier(s) (Hampel filter, check_record): "
            + _listed([f"{q.source}, {o.describe()}" for q in qs for o in q.outliers
                       if o.column == "force"])
            + "; correct the file, or pass outliers='drop' to leave these samples out of the "
            "fit and the error measures (the result lists them)")
    return qs, tuple(force)


def _listed(items: list[str], first: int = 5) -> str:
    """The first ``first`` items joined by '; ', then how many more there are."""
    more = len(items) - first
    return "; ".join(items[:first]) + (f"; and {more} more" if more > 0 else "")


# ---------------------------------------------------------------------------
# physics start


def _harmonic(t, s, f):
    w = 2 * math.pi * f * (t - t[0])
    A = np.column_stack((np.sin(w), np.cos(w), np.ones_like(w)))
    (a, b, _), *_ = np.linalg.lstsq(A, s, rcond=None)
    return complex(a, b)


def linear_fit(record: Record, b_L: float) -> tuple[float, float]:
    """k_D [N/m] and c [N s/m] of a spring in series with (dashpot c + inerter b_L).

    Solved from the record's first-harmonic dynamic stiffness
    K* = F1 / Y1: 1/K = 1/k_D + 1/Z, Z = i w c - w^2 b_L.
    """
    K = _harmonic(record.time, record.force, record.frequency) / _harmonic(
        record.time, record.displacement, record.frequency)
    w = 2 * math.pi * record.frequency
    W = 1.0 / K
    beta = w * w * b_L
    disc = 1.0 - 4.0 * beta * beta * W.imag ** 2
    u = (-1.0 + math.sqrt(disc)) / (2.0 * beta) if (beta > 0 and disc > 0) else 0.0
    s = W.real - u
    k_D = 1.0 / s if s > 0 else math.inf
    c = -W.imag / (w * (u * u + W.imag ** 2))
    return k_D, c


def physics_start(records, base_params: DeviceParams, spec: FitSpec) -> dict:
    """Start values of the paper's multipliers read off the records' first harmonics.

    Returns a dict name -> multiplier for those of inv_gamma1/2 and c1/c2
    that ``spec`` varies (a common factor for each pair, their ratio kept
    from the spec's start).  See the module docstring.
    """
    from scipy.optimize import brentq

    vals = {p.name: p.value for p in spec.parameters}
    p0 = build(base_params, (), FitSpec(tuple(p for p in spec.parameters
                                                if p.kind == "multiplier")), vals)[0]
    kds, cs = [], []
    for r in records:
        k_D, c = linear_fit(r, p0.b_L if p0.S_t else 0.0)
        if math.isfinite(k_D) and k_D > 0 and c > 0:
            kds.append(k_D)
            cs.append((c, r))
    out = {}
    pair_g = [n for n in ("inv_gamma1", "inv_gamma2") if n in spec.varying]
    if kds and pair_g:
        target = float(np.exp(np.mean(np.log(kds))))

        def g(logf):
            f = math.exp(logf)
            return math.log(p0.scaled(**{n: f for n in pair_g}).k_D / target)
        try:
            lo, hi = math.log(0.01), math.log(100.0)
            f = math.exp(brentq(g, lo, hi)) if g(lo) * g(hi) < 0 else None
        except (ValueError, LiquidampError):
            f = None
        if f is not None:
            for n in pair_g:
                out[n] = vals[n] * f
    pair_c = [n for n in ("c1", "c2") if n in spec.varying]
    if cs and pair_c:
        fs = []
        for c, r in cs:
            w = 2 * math.pi * r.frequency
            Q = p0.A_p * w * r.amplitude
            ceq = p0.A_p ** 2 * (p0.c1 + 8.0 / (3.0 * math.pi) * p0.c2 * Q)
            fs.append(c / ceq)
        f = float(np.exp(np.mean(np.log(fs))))
        for n in pair_c:
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


def _keep_masks(records, dropped) -> list[np.ndarray]:
    """Per record: True where the sample is fitted (False at dropped outliers)."""
    masks = []
    for r in records:
        k = np.ones(r.time.size, bool)
        k[[o.index for lab, o in dropped if lab == r.label]] = False
        masks.append(k)
    return masks


def _nrmse_kept(preds, records, masks) -> float:
    return nrmse([p[k] for p, k in zip(preds, masks, strict=True)],
                 [r.force[k] for r, k in zip(records, masks, strict=True)])


class _Objective:
    def __init__(self, model, base_params, effects, spec, records, options, preroll,
                 keep=None):
        self.model = get_model(model)
        self.base, self.effects, self.spec = base_params, tuple(effects), spec
        self.records, self.options, self.preroll = tuple(records), options, preroll
        self.var = [p for p in spec.parameters if p.vary]
        self.fixed = {p.name: p.value for p in spec.parameters}
        meas = np.concatenate([r.force for r in self.records])
        self.meas = meas
        self.keep = (np.ones(meas.size, bool) if keep is None
                     else np.concatenate(keep).astype(bool))
        kept = meas[self.keep]
        self.den = float(np.sqrt(np.mean((kept - kept.mean()) ** 2)))
        if self.den == 0:
            raise ParameterError("calibration records hold a constant force")
        self.scale = self.den * math.sqrt(kept.size)
        self.nfev = 0
        self.failures = 0
        self.last_error = ""

    def values(self, x) -> dict:
        v = dict(self.fixed)
        for p, xi in zip(self.var, x, strict=True):
            v[p.name] = p.from_x(float(xi))
        return v

    def forces(self, values):
        params, effects = build(self.base, self.effects, self.spec, values)
        return params, effects, predict(self.model, params, effects, self.records,
                                        options=self.options, preroll=self.preroll)

    def __call__(self, x):
        self.nfev += 1
        try:
            _, _, F = self.forces(self.values(x))
        except (PressureError, ConvergenceError, ParameterError) as exc:
            self.failures += 1
            self.last_error = str(exc)
            return np.where(self.keep, 3.0 / math.sqrt(self.keep.sum()), 0.0)
        return np.where(self.keep, np.concatenate(F) - self.meas, 0.0) / self.scale


def calibrate(records, *, model="full", params: DeviceParams | None = None, effects=(),
              spec: FitSpec | None = None, validate=(), options: SolverOptions | None = None,
              start: str = "physics", max_nfev: int = 80, preroll: int = 1,
              tol: float = 1e-6, strict: bool = False,
              outliers: str = "raise", warn: bool = True) -> CalibrationResult:
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
        geometric mean, fit from the best; 'spec': fit from the spec's start.
    max_nfev : int
        Budget of model evaluations (each runs every calibration record).
    preroll : int
        Pre-roll passes of each run (records module).
    tol : float
        ftol = xtol of scipy.optimize.least_squares.
    strict : bool
        Raise ConvergenceError instead of returning a result with
        ``converged = False``.
    outliers : {'raise', 'drop'}
        Isolated force spikes found by
        :func:`~liquidamp.analysis.measured.record_quality.check_record`:
        refuse the records (default) or leave those samples out of the
        residual and of every NRMSE, listed in ``CalibrationResult.dropped``
        and in a warning.
    warn : bool
        Issue ``CalibrationResult.warnings`` as :class:`LiquidampWarning` (default;
        :func:`~liquidamp.analysis.measured.diagnosis.diagnose` reports its own).

    Returns
    -------
    CalibrationResult
        New objects; the inputs are not changed.

    Raises
    ------
    DataFileError
        Before any model run (:func:`check_records`): a record whose force's
        first harmonic is not distinguishable from its noise, a stroke past
        the chamber end (``params.stroke_limit``), a displacement spike, or a
        force spike with ``outliers='raise'``; the record and line are named.
    ConvergenceError
        If the model cannot be run at the start, or (``strict``) if the fit
        does not converge.

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
    if spec is None:
        spec = FitSpec.default(effects=effects)
    check_spec_uses(base, spec)
    check_choice("start", start, ("physics", "spec"))
    quality, dropped = check_records(records + validate, base, outliers=outliers)
    for r in records + validate:
        if sum(1 for q in records + validate if q.label == r.label) > 1 and dropped:
            raise ParameterError(f"calibrate: two records share the label {r.label!r}; "
                                 "outliers='drop' needs distinct labels")
    keep_c = _keep_masks(records, dropped)
    keep_v = _keep_masks(validate, dropped)
    options = resolve_options(options, "fit")
    obj = _Objective(model, base, effects, spec, records, options, preroll, keep=keep_c)
    if not obj.var:
        raise ParameterError("the fit specification varies nothing")

    def x_of(values):
        return np.array([p.to_x(min(max(values[p.name], p.min), p.max)) for p in obj.var])

    starts = [("spec", dict(obj.fixed))]
    if start == "physics":
        phys = {**obj.fixed, **physics_start(records, base, spec)}
        mid = {k: math.sqrt(phys[k] * obj.fixed[k]) if spec[k].log else
               0.5 * (phys[k] + obj.fixed[k]) for k in obj.fixed}
        starts += [("physics", phys), ("geometric mean", mid)]
    evaluated = []
    for label, vals in starts:
        r = obj(x_of(vals))
        evaluated.append((label, float(np.sqrt(np.sum(r * r))), vals))
    ok = [e for e in evaluated if e[1] < 2.9]
    if not ok:
        raise ConvergenceError(
            "calibration: the model cannot be run at any start (" + obj.last_error + ")")
    best = min(ok, key=lambda e: e[1])
    lo, hi = zip(*(p.x_bounds() for p in obj.var), strict=True)
    lo, hi = np.array(lo), np.array(hi)
    x0 = np.clip(x_of(best[2]), lo + 1e-12, hi - 1e-12)
    groups = _pair_groups(obj.var) if start == "physics" else []
    if groups:
        # stage 1: one common factor per pair (air ratios, loss coefficients), the
        # other parameters held: a well-conditioned 1-2 parameter fit that lands
        # in the right basin (the c1/c2 trade-off has local minima)
        G = np.zeros((len(obj.var), len(groups)))
        for j, idx in enumerate(groups):
            G[idx, j] = 1.0

        def reduced(z):
            return obj(np.clip(x0 + G @ z, lo, hi))

        zb = 4.0 * np.ones(len(groups))
        s1 = least_squares(reduced, np.zeros(len(groups)), bounds=(-zb, zb), method="trf",
                           diff_step=1e-3, ftol=1e-4, xtol=1e-4, max_nfev=8 * len(groups) + 4)
        x0 = np.clip(x0 + G @ s1.x, lo + 1e-12, hi - 1e-12)
    sol = least_squares(obj, x0, bounds=(lo, hi), method="trf", diff_step=1e-3,
                        x_scale=1.0, ftol=tol, xtol=tol, gtol=tol * 1e-2,
                        max_nfev=max_nfev)
    values = obj.values(sol.x)
    params_fit, effects_fit = build(base, effects, spec, values)
    pc = predict(model, params_fit, effects_fit, records, options=options, preroll=preroll)
    pv = predict(model, params_fit, effects_fit, validate, options=options,
                 preroll=preroll) if validate else []
    n = int(obj.keep.sum())
    k = len(obj.var)
    J = np.asarray(sol.jac, float)
    res = np.where(obj.keep, np.concatenate(pc) - obj.meas, 0.0) / obj.scale
    rss_scaled = float(res @ res)
    s2 = rss_scaled * n / max(n - k, 1)  # residual variance in units of 1/sqrt(N) scaling
    try:
        cov = np.linalg.pinv(J.T @ J) * s2 / n
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
    errs = [RecordError(r.label, "calibration", nrmse(f[m], r.force[m]), r.frequency,
                        r.amplitude) for f, r, m in zip(pc, records, keep_c, strict=True)]
    errs += [RecordError(r.label, "validation", nrmse(f[m], r.force[m]), r.frequency,
                         r.amplitude) for f, r, m in zip(pv, validate, keep_v, strict=True)]
    rss = float(np.sum(np.where(obj.keep, np.concatenate(pc) - obj.meas, 0.0) ** 2))
    warns = []
    if not converged:
        warns.append(f"NOT CONVERGED ({status}): {message}")
    elif obj.failures:
        warns.append(f"{obj.failures} trial point(s) could not be run ({obj.last_error})")
    if dropped:
        warns.append(f"{len(dropped)} force outlier(s) dropped from the fit and the error "
                     "measures: " + _listed([f"{lab}, {o.describe()}" for lab, o in dropped]))
    warns += [n for q in quality for n in q.notes]
    at = {}
    for p in obj.var:
        lo_i, hi_i = p.x_bounds()
        x = p.to_x(values[p.name])
        if x - lo_i <= 1e-3 * (hi_i - lo_i) or hi_i - x <= 1e-3 * (hi_i - lo_i):
            at[p.name] = (values[p.name], p.min if x - lo_i <= 1e-3 * (hi_i - lo_i)
                          else p.max)
    if at:
        warns.append("parameter(s) at a bound (their standard errors are not meaningful): "
                     + ", ".join(f"{nm} = {v:.4g} (bound {b:g})" for nm, (v, b) in at.items()))
    for w in warns if warn else ():
        warnings.warn(f"calibrate: {w}", LiquidampWarning, stacklevel=2)
    aic = n * math.log(rss / n) + 2 * k
    bic = n * math.log(rss / n) + k * math.log(n)
    return CalibrationResult(
        model=get_model(model).name, params=params_fit, start_params=base,
        effects=effects_fit, spec=spec.with_values(values), values={p.name: values[p.name]
                                                                    for p in obj.var},
        stderr=stderr, correlation=corr, varying=tuple(p.name for p in obj.var),
        nrmse_calibration=_nrmse_kept(pc, records, keep_c),
        nrmse_validation=_nrmse_kept(pv, validate, keep_v) if validate else None,
        record_errors=tuple(errs), converged=bool(converged), status=status,
        message=message, nfev=obj.nfev, cost=float(sol.cost), n_samples=n, aic=aic, bic=bic,
        starts=tuple((lab, v) for lab, v, _ in evaluated), calibration=records,
        validation=validate, predictions_calibration=tuple(pc),
        predictions_validation=tuple(pv), jacobian=J, data_quality=quality, dropped=dropped,
        warnings=tuple(warns))
