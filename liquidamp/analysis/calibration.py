"""Calibrate a device model against measured records by least squares on force.

The fit specification is kept apart from the model (lmfit-style, without
signature introspection): a :class:`FitSpec` is a tuple of
:class:`Parameter` objects, each naming either a :class:`DeviceParams`
field, varied as a multiplier on the starting parameter set (the paper's
alpha_j of Table 2), or an effect parameter ``"effect.key"`` (e.g.
``"coulomb_friction.force_N"``), varied as an absolute value.  Positive
quantities are fitted in log space, so a multiplier's bounds [0.05, 20] are
symmetric in the fit.

:func:`calibrate` fits several records at once and validates on others.
The residual is (model force - measured force) / RMS(measured - mean) over
the pooled calibration set, so the cost is NRMSE^2 / 2 with

    NRMSE = RMS(model force - measured force) / RMS(measured force - its mean)

pooled over all records of a set.  Every model run is driven by the
recorded stroke (:func:`liquidamp.analysis.records.simulate_record`).

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
:func:`liquidamp.analysis.records.check_record` before any model run.  A
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

import dataclasses
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.records import DataQuality, Record, check_record, nrmse, simulate_record
from liquidamp.device.effects import EFFECTS, Effect, with_effects
from liquidamp.device.models import DeviceModel, get_model
from liquidamp.device.params import SCALABLE, DeviceParams
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
:func:`liquidamp.analysis.records.simulate_record`), with RODAS4 throughout: the
least-squares Jacobians are finite differences of the simulated force, and at
rtol 1e-6 RODAS4's global error is several times smaller than Dormand-Prince's
(|K*| error 2.2e-7 against 1.3e-6 for the reference design at 3 Hz, 3 mm); with
Dormand-Prince the diagnosis of the bundled demo record took 13x longer and
added freeplay and leakage beside the true smooth friction."""

PAPER_FOUR = ("inv_gamma1", "inv_gamma2", "c1", "c2")
"""The multipliers the paper calibrated (Table 2)."""


@dataclass(frozen=True)
class Parameter:
    """One fitted quantity.

    Parameters
    ----------
    name : str
        A scalable DeviceParams field (fitted as a multiplier on the
        starting parameters) or ``"effect.key"`` (absolute, SI).
    value : float
        Start value (multiplier [-] or the effect parameter in SI).
    min, max : float
        Bounds (same meaning as ``value``).
    vary : bool
        False holds the parameter at ``value``.
    log : bool
        Fit log(value) (needs min > 0).
    scale : float
        For linear parameters: the fit works on value / scale [unit of value].

    Examples
    --------
    >>> Parameter("c1", 1.0, 0.05, 20.0).kind
    'multiplier'
    >>> Parameter("c1", 30.0, 0.05, 20.0)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: parameter 'c1': start 30 outside its bounds [0.05, 20]
    """

    name: str
    value: float
    min: float
    max: float
    vary: bool = True
    log: bool = True
    scale: float = 1.0

    def __post_init__(self):
        if "." in self.name:
            eff, key = self.name.split(".", 1)
            check_choice("effect", eff, EFFECTS)
            keys = [f.name for f in dataclasses.fields(EFFECTS[eff])]
            check_choice(f"{eff} parameter", key, keys)
        else:
            check_choice("fitted device parameter", self.name, SCALABLE)
        for k in ("value", "min", "max", "scale"):
            v = float(getattr(self, k))
            if not math.isfinite(v):
                raise ParameterError(f"parameter {self.name!r}: {k} must be finite, got {v!r}")
            object.__setattr__(self, k, v)
        if not self.min < self.max:
            raise ParameterError(f"parameter {self.name!r}: min {self.min:g} must be < max "
                                 f"{self.max:g}")
        if not self.min <= self.value <= self.max:
            raise ParameterError(f"parameter {self.name!r}: start {self.value:g} outside its "
                                 f"bounds [{self.min:g}, {self.max:g}]")
        if self.log and not self.min > 0:
            raise ParameterError(f"parameter {self.name!r}: a log-parametrized bound must be "
                                 f"> 0, got min {self.min:g}")
        if not self.scale > 0:
            raise ParameterError(f"parameter {self.name!r}: scale must be > 0")

    @property
    def kind(self) -> str:
        """'multiplier' (DeviceParams field) or 'effect'."""
        return "effect" if "." in self.name else "multiplier"

    def to_x(self, value: float) -> float:
        """Internal fit coordinate."""
        return math.log(value) if self.log else value / self.scale

    def from_x(self, x: float) -> float:
        """Value from the internal coordinate."""
        return math.exp(x) if self.log else x * self.scale

    def x_bounds(self) -> tuple[float, float]:
        """Bounds in the internal coordinate."""
        return self.to_x(self.min), self.to_x(self.max)

    def replace(self, **changes) -> Parameter:
        """Validated copy."""
        return dataclasses.replace(self, **changes)


@dataclass(frozen=True)
class FitSpec:
    """What a calibration varies: a tuple of :class:`Parameter` (names unique).

    Examples
    --------
    >>> spec = FitSpec.default()
    >>> spec.names
    ('inv_gamma1', 'inv_gamma2', 'c1', 'c2')
    >>> FitSpec.default(vary=("c1",), effects=["coulomb_friction"]).varying
    ('c1', 'coulomb_friction.force_N')
    """

    parameters: tuple[Parameter, ...]

    def __post_init__(self):
        params = tuple(self.parameters)
        names = [p.name for p in params]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ParameterError(f"fit parameter(s) given twice: {', '.join(sorted(dup))}")
        for p in params:
            if not isinstance(p, Parameter):
                raise ParameterError("FitSpec holds Parameter objects")
        object.__setattr__(self, "parameters", params)

    @classmethod
    def default(cls, vary=PAPER_FOUR, effects=(), bounds=(0.05, 20.0)) -> FitSpec:
        """Multipliers ``vary`` (start 1, ``bounds``) and each effect's default fit keys.

        ``effects`` holds Effect objects (their values are the starts) or names
        (catalogue defaults).
        """
        pars = [Parameter(n, 1.0, *bounds) for n in vary]
        spec = cls(tuple(pars))
        for e in effects:
            spec = spec.with_effect(e)
        return spec

    def with_effect(self, effect, start: dict | None = None) -> FitSpec:
        """Add the effect's default fit keys (start: the effect's values or ``start``)."""
        if isinstance(effect, str):
            check_choice("effect", effect, EFFECTS)
            effect = EFFECTS[effect]()
        start = dict(start or {})
        new = list(self.parameters)
        for key in effect.fit_keys:
            lo, hi = effect.bounds[key]
            v = float(start.get(key, getattr(effect, key)))
            log = lo > 0
            if log:
                v = min(max(v, lo), hi) if math.isfinite(v) else hi
            scale = 1.0 if log else max(abs(v), 1.0)
            new.append(Parameter(f"{effect.name}.{key}", v, lo, hi, log=log, scale=scale))
        return FitSpec(tuple(new))

    @property
    def names(self) -> tuple[str, ...]:
        """All parameter names."""
        return tuple(p.name for p in self.parameters)

    @property
    def varying(self) -> tuple[str, ...]:
        """Names of the varied parameters."""
        return tuple(p.name for p in self.parameters if p.vary)

    def __getitem__(self, name: str) -> Parameter:
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(name)

    def with_values(self, values: dict) -> FitSpec:
        """Copy whose start values are ``values`` (clipped into the bounds)."""
        out = []
        for p in self.parameters:
            v = values.get(p.name, p.value)
            out.append(p.replace(value=min(max(float(v), p.min), p.max)))
        return FitSpec(tuple(out))

    def effect_names(self) -> tuple[str, ...]:
        """Effects named by the spec's parameters."""
        seen = []
        for p in self.parameters:
            if p.kind == "effect":
                e = p.name.split(".")[0]
                if e not in seen:
                    seen.append(e)
        return tuple(seen)


def check_spec_uses(base_params: DeviceParams, spec: FitSpec) -> None:
    """Raise ParameterError if ``spec`` varies (or scales) a field ``base_params`` does not use.

    A field listed by :meth:`DeviceParams.unused` (e.g. ``mu`` once ``c1`` is
    given explicitly) enters no answer: "fitting" it would return its start
    with standard error 0.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> check_spec_uses(preset("reference"), FitSpec.default(vary=("mu",)))
    >>> check_spec_uses(preset("reference").replace(c1=1e9), FitSpec.default(vary=("mu",)))
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: cannot fit 'mu': the starting parameters do not use it ...
    """
    unused = base_params.unused()
    for p in spec.parameters:
        if p.kind == "multiplier" and p.name in unused and (p.vary or p.value != 1.0):
            derived = [k for k in ("c1", "c2", "S_t") if k in base_params.explicit]
            instead = " or ".join(derived) or "another parameter"
            raise ParameterError(
                f"cannot fit {p.name!r}: the starting parameters do not use it "
                f"({unused[p.name]}); vary {instead} instead, or start from parameters "
                f"that derive {instead} from {p.name}")


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


@dataclass(frozen=True)
class RecordError:
    """Error of a calibrated model on one record."""

    label: str
    role: str
    nrmse: float
    frequency: float
    amplitude: float


@dataclass(frozen=True, eq=False)
class CalibrationResult:
    """Named, immutable result of :func:`calibrate`.

    Attributes
    ----------
    model : str
        Base model name (effects listed apart).
    params : DeviceParams
        Calibrated device parameters.
    start_params : DeviceParams
        The parameters the multipliers apply to.
    effects : tuple of Effect
        Calibrated effects.
    spec : FitSpec
        The specification with the fitted values as its values.
    values, stderr : dict
        Fitted value and standard error of each varied parameter (multiplier
        [-] or effect parameter [SI]).
    correlation : ndarray
        Correlation matrix of the varied parameters (order of ``varying``).
    varying : tuple of str
        Names of the varied parameters.
    nrmse_calibration, nrmse_validation : float, float or None
        Pooled NRMSE on each set [-].
    record_errors : tuple of RecordError
        NRMSE on every record.
    converged : bool
        True if least squares met its tolerance (status > 0).
    status : str
        'converged', 'max_nfev' (stopped on the evaluation budget: not
        converged) or 'failed'.
    message : str
        What the optimizer reported.
    nfev, cost : int, float
        Model evaluations of the fit; final cost = NRMSE^2 / 2.
    n_samples : int
        Calibration samples N.
    aic, bic : float
        N ln(RSS/N) + 2 k and + k ln N on the calibration set (k varied parameters).
    starts : tuple of (str, float)
        The starts evaluated and their calibration NRMSE.
    calibration, validation : tuple of Record
    predictions_calibration, predictions_validation : tuple of ndarray
        Model force on each record [N].
    jacobian : ndarray
        Jacobian of the scaled residual in the fit coordinates at the optimum.
    data_quality : tuple of DataQuality
        The check of every record (calibration, then validation).
    dropped : tuple of (str, Outlier)
        Force samples left out of the fit and the error measures
        (``outliers="drop"``), with their record's label.
    warnings : tuple of str
        Not converged, failed trial points, dropped samples, noisy records;
        also issued as :class:`~liquidamp.errors.LiquidampWarning`.

    Printing the result gives a short summary; :meth:`fit_report` the
    parameters with their errors and correlations; :meth:`plot` a figure.
    """

    model: str
    params: DeviceParams
    start_params: DeviceParams
    effects: tuple
    spec: FitSpec
    values: dict
    stderr: dict
    correlation: np.ndarray
    varying: tuple
    nrmse_calibration: float
    nrmse_validation: float | None
    record_errors: tuple
    converged: bool
    status: str
    message: str
    nfev: int
    cost: float
    n_samples: int
    aic: float
    bic: float
    starts: tuple
    calibration: tuple
    validation: tuple
    predictions_calibration: tuple
    predictions_validation: tuple
    jacobian: np.ndarray = field(repr=False)
    data_quality: tuple = ()
    dropped: tuple = ()
    warnings: tuple = ()

    @property
    def device_model(self) -> DeviceModel:
        """The calibrated model with its effects."""
        return with_effects(get_model(self.model), *self.effects)

    def residuals(self, role: str = "calibration") -> list[np.ndarray]:
        """Model minus measured force on each record of a set [N] (0 at dropped samples)."""
        recs = self.calibration if role == "calibration" else self.validation
        preds = (self.predictions_calibration if role == "calibration"
                 else self.predictions_validation)
        out = []
        for p, r in zip(preds, recs, strict=True):
            res = p - r.force
            idx = [o.index for lab, o in self.dropped if lab == r.label]
            res[idx] = 0.0
            out.append(res)
        return out

    def __repr__(self) -> str:
        nv = ("" if self.nrmse_validation is None
              else f", validation {self.nrmse_validation:.4g}")
        vals = ", ".join(f"{k}={v:.4g}" for k, v in self.values.items())
        extra = f", {len(self.warnings)} warning(s)" if self.warnings else ""
        return (f"<CalibrationResult {self.model}: {self.status}, NRMSE calibration "
                f"{self.nrmse_calibration:.4g}{nv}; {vals}{extra}>")

    def __str__(self) -> str:
        lines = [f"CalibrationResult: model {self.model!r} from "
                 f"{self.start_params.name or 'custom'} parameters",
                 f"  fit: {self.status} after {self.nfev} evaluations (cost {self.cost:.4g})",
                 f"  records: {len(self.calibration)} calibration, {len(self.validation)} "
                 f"validation, {self.n_samples} samples fitted",
                 f"  NRMSE: calibration {self.nrmse_calibration:.4g}"
                 + ("" if self.nrmse_validation is None
                    else f", validation {self.nrmse_validation:.4g}")]
        for k, v in self.values.items():
            lines.append(f"  {k:<34s} {v:12.5g} +/- {self.stderr.get(k, math.nan):.2g}")
        if self.effects:
            lines.append("  effects: " + ", ".join(e.name for e in self.effects))
        for w in self.warnings[:5]:
            lines.append("  warning: " + (w if len(w) < 200 else w[:197] + "..."))
        if len(self.warnings) > 5:
            lines.append(f"  ... {len(self.warnings) - 5} more warning(s)")
        lines.append("  (fit_report() for errors and correlations, plot() for a figure)")
        return "\n".join(lines)

    def fit_report(self, min_correl: float = 0.5) -> str:
        """lmfit-style text report of the fit.

        Values with units, standard errors and relative errors, the
        correlations whose magnitude exceeds ``min_correl``, and a flag on
        every parameter within 0.1 % (of its range in the fit coordinate) of
        a bound: its standard error is then not meaningful.  Multipliers are
        dimensionless factors on the starting parameters (Table 2's alpha_j);
        effect parameters are in SI with the unit in their key.

        Parameters
        ----------
        min_correl : float
            Smallest |correlation| listed [-] (default 0.5, as lmfit's 0.1
            would list nearly every pair of this model family).

        Returns
        -------
        str
        """
        out = ["[[Fit Statistics]]",
               f"    model              = {self.model}"
               + (f" + {', '.join(e.name for e in self.effects)}" if self.effects else ""),
               f"    status             = {self.status} ({self.message})",
               f"    function evals     = {self.nfev}",
               f"    data points        = {self.n_samples}",
               f"    variables          = {len(self.varying)}",
               f"    NRMSE calibration  = {self.nrmse_calibration:.6g}"]
        if self.nrmse_validation is not None:
            out.append(f"    NRMSE validation   = {self.nrmse_validation:.6g}")
        out += [f"    Akaike info crit   = {self.aic:.6g}",
                f"    Bayesian info crit = {self.bic:.6g}"]
        if self.dropped:
            out.append(f"    dropped samples    = {len(self.dropped)} (force outliers)")
        out.append("[[Variables]]")
        at_bound = self.at_bounds()
        for p in self.spec.parameters:
            v = self.values.get(p.name, p.value)
            unit = "[-] multiplier" if p.kind == "multiplier" else _effect_unit(p.name)
            if not p.vary:
                out.append(f"    {p.name + ':':<36s} {v:.6g} {unit} (fixed)")
                continue
            se = self.stderr.get(p.name, math.nan)
            rel = f"({abs(se / v):.2%})" if v != 0 and math.isfinite(se) else "(n/a)"
            flag = f"  AT {at_bound[p.name].upper()} BOUND" if p.name in at_bound else ""
            out.append(f"    {p.name + ':':<36s} {v:.6g} +/- {se:.3g} {rel} {unit} "
                       f"(bounds [{p.min:g}, {p.max:g}]){flag}")
        pairs = []
        names = list(self.varying)
        for i in range(len(names)):
            for j in range(i + 1, len(names)):
                c = float(self.correlation[i, j])
                if abs(c) > min_correl:
                    pairs.append((abs(c), names[i], names[j], c))
        out.append(f"[[Correlations]] (unreported correlations are < {min_correl:.3f})")
        for _, a, b, c in sorted(pairs, reverse=True):
            out.append(f"    C({a}, {b}) = {c:+.4f}")
        if not pairs:
            out.append("    none")
        if self.warnings:
            out.append("[[Warnings]]")
            out += [f"    {w}" for w in self.warnings]
        return "\n".join(out)

    def at_bounds(self, tol: float = 1e-3) -> dict:
        """Varied parameters within ``tol`` of a bound (fraction of the range in the fit
        coordinate): name -> 'lower' or 'upper'."""
        out = {}
        for name in self.varying:
            p = self.spec[name]
            lo, hi = p.x_bounds()
            x = p.to_x(self.values[name])
            if x - lo <= tol * (hi - lo):
                out[name] = "lower"
            elif hi - x <= tol * (hi - lo):
                out[name] = "upper"
        return out

    def plot(self, role: str = "calibration"):
        """Measured and fitted force over time and force-displacement loops of every record.

        Parameters
        ----------
        role : {'calibration', 'validation'}
            Which set of records.

        Returns
        -------
        matplotlib.figure.Figure
            One row per record: force [N] against time [s] (measured, model,
            dropped samples marked) and force against displacement [mm].
        """
        from liquidamp.analysis.report_calibration import plot_fit

        return plot_fit(self, role)

    def parameters_dict(self) -> dict:
        """JSON-ready parameters: multipliers, DeviceParams values, effects."""
        mult = {p.name: self.values.get(p.name, p.value) for p in self.spec.parameters
                if p.kind == "multiplier"}
        return {
            "model": self.model,
            "start_parameters": self.start_params.name or "custom",
            "multipliers": mult,
            "device": {k: getattr(self.params, k) for k in SCALABLE
                       if getattr(self.params, k) is not None},
            "effects": {e.name: e.parameters for e in self.effects},
            "stderr": dict(self.stderr),
        }

    def as_dict(self) -> dict:
        """JSON-ready summary (with ``data_quality``, ``dropped`` and ``warnings``)."""
        return {
            "data_quality": [q.as_dict() for q in self.data_quality],
            "dropped": [{"record": lab, **o.__dict__} for lab, o in self.dropped],
            "warnings": list(self.warnings),
            "at_bounds": self.at_bounds(),
            "parameters": self.parameters_dict(),
            "nrmse": {"calibration": self.nrmse_calibration,
                      "validation": self.nrmse_validation},
            "records": [dataclasses.asdict(e) for e in self.record_errors],
            "correlation": {"names": list(self.varying),
                            "matrix": np.round(self.correlation, 4).tolist()},
            "fit": {"converged": self.converged, "status": self.status,
                    "message": self.message, "nfev": self.nfev, "cost": self.cost,
                    "n_samples": self.n_samples, "aic": self.aic, "bic": self.bic,
                    "starts": [{"start": s, "nrmse": v} for s, v in self.starts]},
        }


def _effect_unit(name: str) -> str:
    key = name.split(".", 1)[1]
    for suffix, unit in (("_N_per_m", "[N/m]"), ("_m3_per_s_Pa", "[m^3/(s Pa)]"),
                         ("_Pa", "[Pa]"), ("_N", "[N]"), ("_kg", "[kg]"), ("_m", "[m]"),
                         ("_s", "[s]")):
        if key.endswith(suffix):
            return unit
    return "[SI]"


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
            + "; ".join(f"{q.source}, {o.describe()}" for q, o in disp)
            + "; the recorded stroke drives the model, so these samples cannot be dropped: "
            "correct or remove them in the file")
    force = [(r.label, o) for r, q in zip(records, qs, strict=True) for o in q.outliers
             if o.column == "force"]
    if force and outliers == "raise":
        raise DataFileError(
            f"{what}: {len(force)} force outlier(s) (Hampel filter, check_record): "
            + "; ".join(f"{q.source}, {o.describe()}" for q in qs for o in q.outliers
                        if o.column == "force")
            + "; correct the file, or pass outliers='drop' to leave these samples out of the "
            "fit and the error measures (the result lists them)")
    return qs, tuple(force)


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
        Isolated force spikes found by :func:`~liquidamp.analysis.records.check_record`:
        refuse the records (default) or leave those samples out of the
        residual and of every NRMSE, listed in ``CalibrationResult.dropped``
        and in a warning.
    warn : bool
        Issue ``CalibrationResult.warnings`` as :class:`LiquidampWarning` (default;
        :func:`~liquidamp.analysis.diagnosis.diagnose` reports its own).

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
                     "measures: " + "; ".join(f"{lab}, {o.describe()}" for lab, o in dropped))
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
