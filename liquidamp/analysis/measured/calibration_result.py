"""The result of a calibration: fitted parameters, their errors, per-record errors, reports.

:class:`CalibrationResult` is returned by
:func:`liquidamp.analysis.measured.calibration.calibrate` (and by each step of
:func:`liquidamp.analysis.measured.diagnosis.diagnose`); :class:`RecordError` is the NRMSE
[-] of one record.  Standard errors and correlations come from the Jacobian at the optimum
scaled by the residual variance, s^2 (J^T J)^-1 with s^2 = RSS / (N - p); read them as lower
bounds (model error is correlated in time).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C and Table 2.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass, field
from pathlib import PurePath

import numpy as np

from liquidamp.analysis.measured.fit_spec import FitSpec
from liquidamp.device.effects import EFFECTS, with_effects
from liquidamp.device.models import DeviceModel, get_model
from liquidamp.device.params import SCALABLE, DeviceParams

__all__ = ["CalibrationResult", "RecordError", "ParameterFlags", "parameter_flags"]


@dataclass(frozen=True)
class RecordError:
    """Error of a calibrated model on one record.

    Attributes
    ----------
    label : str
        The record's label.
    role : str
        ``"calibration"`` or ``"validation"``.
    nrmse : float
        NRMSE on the record [-].
    frequency, amplitude : float or None
        Stroke frequency [Hz] and first-harmonic amplitude [m]; None when the
        stroke is not periodic (``stroke`` says what it is).
    periodic : bool
        Whether the stroke is periodic.
    stroke : str
        The stroke in words (:meth:`Record.describe
        <liquidamp.analysis.measured.records.Record.describe>`).
    """

    label: str
    role: str
    nrmse: float
    frequency: float | None
    amplitude: float | None
    periodic: bool = True
    stroke: str = ""

    @classmethod
    def of(cls, record, role: str, nrmse: float) -> RecordError:
        """The error on ``record``, its harmonic summary only where its stroke is periodic."""
        per = record.periodic
        return cls(record.label, role, float(nrmse), record.frequency if per else None,
                   record.amplitude if per else None, per, record.describe())


@dataclass(frozen=True)
class ParameterFlags:
    """Fitted parameters to distrust (:func:`parameter_flags`).

    Attributes
    ----------
    at_bound : dict
        name -> (value, bound, 'lower' or 'upper'): within 0.1 % of the range (in
        the fit coordinate) of a bound; its standard error is not meaningful.
    undetermined : dict
        name -> (value, standard error): standard error larger than |value|.
    unused : dict
        name -> reason: a device input the fitted parameters do not use
        (:meth:`DeviceParams.unused <liquidamp.device.params.DeviceParams.unused>`),
        or a varied parameter the model force does not depend on (a zero
        Jacobian column).
    """

    at_bound: dict = field(default_factory=dict)
    undetermined: dict = field(default_factory=dict)
    unused: dict = field(default_factory=dict)

    def __bool__(self) -> bool:
        return bool(self.at_bound or self.undetermined or self.unused)

    def warnings(self) -> list[str]:
        """One warning per kind of flag (the text of ``CalibrationResult.warnings``)."""
        out = []
        if self.at_bound:
            out.append("parameter(s) at a bound (their standard errors are not meaningful): "
                       + ", ".join(f"{n} = {v:.4g} (bound {b:g})"
                                   for n, (v, b, _) in self.at_bound.items()))
        if self.undetermined:
            out.append("parameter(s) not determined by the records (standard error larger "
                       "than the value): " + ", ".join(
                           f"{n} = {v:.4g} +/- {se:.3g}"
                           for n, (v, se) in self.undetermined.items()))
        if self.unused:
            out.append("parameter(s) the model does not use: " + "; ".join(
                f"{n} ({why})" for n, why in self.unused.items()))
        return out

    def short(self) -> str:
        """'at bound: c1 (upper); stderr > value: mu' ('' when nothing is flagged)."""
        parts = []
        if self.at_bound:
            parts.append("at bound: " + ", ".join(f"{n} ({side})" for n, (_, _, side)
                                                  in self.at_bound.items()))
        if self.undetermined:
            parts.append("stderr > value: " + ", ".join(self.undetermined))
        if self.unused:
            parts.append("unused: " + ", ".join(self.unused))
        return "; ".join(parts)

    def as_dict(self) -> dict:
        """JSON-ready."""
        return {"at_bound": {n: {"value": v, "bound": b, "side": side}
                             for n, (v, b, side) in self.at_bound.items()},
                "undetermined": {n: {"value": v, "stderr": se}
                                 for n, (v, se) in self.undetermined.items()},
                "unused": dict(self.unused)}


def parameter_flags(spec: FitSpec, varying, values: dict, stderr: dict, jacobian,
                    params: DeviceParams, tol: float = 1e-3) -> ParameterFlags:
    """Parameters at a bound, not determined, or unused, after a fit.

    Parameters
    ----------
    spec : FitSpec
        The specification (bounds).
    varying : sequence of str
        Varied parameter names, in the Jacobian's column order.
    values, stderr : dict
        Fitted values and standard errors (multipliers [-], effect parameters [SI]).
    jacobian : ndarray
        Jacobian of the scaled residual in the fit coordinates.
    params : DeviceParams
        The fitted device (its :meth:`~liquidamp.device.params.DeviceParams.unused`
        inputs are flagged).
    tol : float
        Distance to a bound as a share of the range in the fit coordinate [-].

    Returns
    -------
    ParameterFlags
    """
    at, und, unused = {}, {}, dict(params.unused())
    J = np.asarray(jacobian, float)
    norms = np.sqrt(np.sum(J * J, axis=0)) if J.size else np.zeros(len(varying))
    top = float(norms.max()) if norms.size else 0.0
    for i, name in enumerate(varying):
        p = spec[name]
        lo, hi = p.x_bounds()
        x = p.to_x(values[name])
        if x - lo <= tol * (hi - lo):
            at[name] = (values[name], p.min, "lower")
        elif hi - x <= tol * (hi - lo):
            at[name] = (values[name], p.max, "upper")
        se = stderr.get(name, math.nan)
        if i < norms.size and norms[i] <= 1e-9 * max(top, 1e-300):
            unused[name] = "the model force does not depend on it (zero Jacobian column)"
        elif name not in at and (not math.isfinite(se) or se > abs(values[name])):
            und[name] = (values[name], se)
    return ParameterFlags(at, und, unused)


#: Above this times the noise floor a fit's residual is called structured [-] (the
#: diagnosis's ``SelectionRule.structure_factor`` default: twice the error no model avoids).
STRUCTURE_FACTOR = 2.0


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
        Not converged, failed trial points, dropped samples, noisy records,
        parameters at a bound, not determined or unused, a sized start;
        also issued as :class:`~liquidamp.errors.LiquidampWarning`.
    start : dict
        The device the fit started from (:class:`Sizing
        <liquidamp.analysis.measured.start.Sizing>`: sized or not, force and
        stroke scale, why) and the start chosen.
    start_trials : tuple of StartTrial
        Every start evaluated, with its NRMSE, peak forces and energy sign.
    flags : ParameterFlags
        Parameters at a bound, not determined or unused.
    device_class : str
        The start class the fit continued (``"fluid"``, ``"friction"``,
        ``"viscous"``; :mod:`~liquidamp.analysis.measured.device_class`), '' when no
        class starts were compared.
    class_starts : tuple of StartOutcome
        Every class start's cheap calibration, its figures and whether it was chosen.
    plausibility : tuple of PlausibilityFlag
        Fitted geometry the records cannot support
        (:mod:`~liquidamp.analysis.measured.plausibility`); empty when none.

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
    start: dict = field(default_factory=dict)
    start_trials: tuple = ()
    flags: ParameterFlags = field(default_factory=ParameterFlags)
    device_class: str = ""
    class_starts: tuple = ()
    plausibility: tuple = ()

    @property
    def references(self) -> dict:
        """The reference models fitted on the same split: ``{"line": ReferenceFit,
        "two_slope": ReferenceFit}`` (:mod:`~liquidamp.analysis.measured.reference_models`:
        F = c v + k y + F0 and the two-slope force-velocity map per direction)."""
        from liquidamp.analysis.measured.reference_models import reference_models

        cached = self.__dict__.get("_references")
        if cached is None:
            cached = reference_models(self.calibration, self.validation)
            object.__setattr__(self, "_references", cached)
        return cached

    def heldout_records(self) -> dict:
        """Record label -> held-out NRMSE [-] (the validation records)."""
        return {e.label: e.nrmse for e in self.record_errors if e.role == "validation"}

    def versus_line(self) -> str:
        """Where the physics model does not beat the line F = c v + k y + F0 held out
        ('' where it does or nothing is held out)."""
        from liquidamp.analysis.measured.reference_models import comparison

        return comparison(self.heldout_records(), self.references) if self.validation else ""

    def versus_map(self) -> str:
        """Where the physics model does not beat the dyno's two-slope force-velocity map
        held out ('' where it does or nothing is held out)."""
        from liquidamp.analysis.measured.reference_models import comparison

        return (comparison(self.heldout_records(), self.references, name="two_slope")
                if self.validation else "")

    @functools.cached_property
    def noise_nrmse(self) -> float:
        """The calibration records' pooled noise floor as an NRMSE [-]: the force error a
        model driven by the recorded stroke cannot avoid
        (:func:`~liquidamp.analysis.measured.record_quality.noise_floor` of each record, or
        its conditioning's floor where it was averaged or decimated; pooled in quadrature
        over the samples, as the diagnosis pools it); nan without a record."""
        from liquidamp.analysis.measured.record_quality import noise_floor

        recs = tuple(self.calibration)
        if not recs:
            return math.nan
        meas = np.concatenate([np.asarray(r.force, float) for r in recs])
        den = float(np.sqrt(np.mean((meas - meas.mean()) ** 2)))
        var = 0.0
        for r in recs:
            nf = getattr(r.meta.get("conditioning"), "noise", None) or noise_floor(r)
            var += nf.std ** 2 * r.time.size
        return float(np.sqrt(var / meas.size)) / den if den > 0 else math.nan

    def above_noise(self, factor: float = STRUCTURE_FACTOR) -> str:
        """Where the fit leaves more than ``factor`` x the records' noise floor
        (:attr:`noise_nrmse`) on the calibration records: structure the model does not
        explain, whatever the optimizer's status ('' otherwise) [-]."""
        floor = self.noise_nrmse
        if not (math.isfinite(floor) and floor > 0.0
                and self.nrmse_calibration > factor * floor):
            return ""
        return (f"calibration NRMSE {self.nrmse_calibration:.3g} is "
                f"{self.nrmse_calibration / floor:.3g} x the records' noise floor {floor:.3g} "
                f"(more than {factor:g} x): the model leaves structure it cannot explain "
                "(`liquidamp diagnose` screens the effect catalogue)")

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
            if r.meta.get("conditioning") is None:  # indices of the record as read
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

    def force_negated(self) -> str:
        """The records read with their force negated, "" if none: ``"a.csv, b.csv (the
        loop as recorded delivers energy: read with the other sign convention)"``
        (:func:`~liquidamp.analysis.measured.checks.orient_force`)."""
        names = [PurePath(q.source).name for q in self.data_quality if q.force_negated]
        if not names:
            return ""
        return (", ".join(names) + " (the loop as recorded delivers energy, a damper's loop "
                "drawn backwards: read with the other sign convention, the force negated)")

    def summary(self) -> str:
        """One line: status, NRMSE (held out per record, pooled beside), the start device and
        scale, the flagged parameters; led by ``FORCE NEGATED: ...`` where a record's
        force was read negated (:meth:`force_negated`), then ``PHYSICS MODEL LOSES TO THE
        LINE: ...`` where the line F = c v + k y + F0 fitted on the same split predicts a
        held-out record at least as well, ``PHYSICS MODEL LOSES TO THE TWO-SLOPE MAP: ...``
        likewise for the dyno's two-slope force-velocity map, then by ``ABOVE THE NOISE:
        ...`` where the calibration NRMSE is more than :data:`STRUCTURE_FACTOR` x the
        records' noise floor (:meth:`above_noise`: a converged optimizer is not a model that
        explains the record).

        Examples of its content: ``converged (41 evaluations): NRMSE calibration
        0.0123, held out b 0.0231, c 0.0310 (pooled 0.0262); start physics from
        paper_initial sized (force x0.21, stroke x1.5); flags: at bound: c1 (upper)``.
        """
        per = self.heldout_records()
        nv = ("" if self.nrmse_validation is None
              else ", held out " + ", ".join(f"{k} {v:.4g}" for k, v in per.items())
              + (f" (pooled {self.nrmse_validation:.4g})" if len(per) > 1 else ""))
        lose = self.versus_line()
        dev = self.start_params.name or "custom"
        chosen = self.start.get("chosen", "")
        flags = self.flags.short()
        cls = ""
        if self.class_starts:
            others = [o.describe() for o in self.class_starts if not o.chosen]
            wi = self.start.get("without_input")
            if wi and wi.get("nrmse_validation") is not None:
                others.append(f"without the {wi['input']}: held out "
                              f"{wi['nrmse_validation']:.3g}")
            cls = f"; device class {self.device_class}" + (
                f" ({'; '.join(others)})" if others else "")
        implausible = "".join(f"; IMPLAUSIBLE: {f.message}" for f in self.plausibility)
        above = self.above_noise()
        lose_map = self.versus_map()
        negated = self.force_negated()
        return (("FORCE NEGATED: " + negated + "; " if negated else "")
                + ("PHYSICS MODEL LOSES TO THE LINE: " + lose + "; " if lose else "")
                + ("PHYSICS MODEL LOSES TO THE TWO-SLOPE MAP: " + lose_map + "; "
                   if lose_map else "")
                + ("ABOVE THE NOISE: " + above + "; " if above else "")
                + f"{self.status} ({self.nfev} evaluations): NRMSE calibration "
                f"{self.nrmse_calibration:.4g}{nv}; start {chosen + ' ' if chosen else ''}"
                f"from {dev}{cls}" + (f"; flags: {flags}" if flags else
                                      "; no parameter flagged") + implausible)

    def __str__(self) -> str:
        lines = [f"CalibrationResult: model {self.model!r} from "
                 f"{self.start_params.name or 'custom'} parameters",
                 f"  fit: {self.status} after {self.nfev} evaluations (cost {self.cost:.4g})",
                 f"  records: {len(self.calibration)} calibration, {len(self.validation)} "
                 f"validation, {self.n_samples} samples fitted",
                 f"  NRMSE: calibration {self.nrmse_calibration:.4g}"
                 + ("" if self.nrmse_validation is None
                    else f", validation {self.nrmse_validation:.4g}")]
        if self.start.get("sized"):
            lines.append(f"  start: sized to the records ({self.start.get('reason', '')})"[:200])
        if self.class_starts:
            lines.append(f"  device class: {self.device_class} ("
                         + "; ".join(o.describe() for o in self.class_starts) + ")")
        if self.flags:
            lines.append(f"  flags: {self.flags.short()}")
        for f in self.plausibility:
            lines.append(f"  IMPLAUSIBLE: {f.message}")
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
        if self.start:
            out.append(f"    start device       = {self.start_params.name or 'custom'} "
                       f"({'sized to the records' if self.start.get('sized') else 'as given'})")
            out.append(f"    start chosen       = {self.start.get('chosen', '')}")
        if self.class_starts:
            out.append(f"    device class       = {self.device_class}")
            out += [f"      {o.describe()}" + (f" -- {o.reason}" if o.reason else "")
                    for o in self.class_starts]
        if self.plausibility:
            out.append("[[Plausibility]]")
            out += [f"    {f.kind}: {f.message}" for f in self.plausibility]
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
            if p.name in self.flags.undetermined:
                flag += "  NOT DETERMINED (stderr > value)"
            if p.name in self.flags.unused:
                flag += "  UNUSED"
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
        from liquidamp.analysis.reports.report_calibration import plot_fit

        return plot_fit(self, role)

    def parameters_dict(self) -> dict:
        """JSON-ready parameters: multipliers, DeviceParams values, effects."""
        mult = {p.name: self.values.get(p.name, p.value) for p in self.spec.parameters
                if p.kind == "multiplier"}
        return {
            "model": self.model,
            "start_parameters": self.start_params.name or "custom",
            "multipliers": mult,
            "device": {k: getattr(self.params, k) for k in (*SCALABLE, "n")
                       if getattr(self.params, k) is not None},
            "effects": {e.name: e.as_dict() for e in self.effects},
            "stderr": dict(self.stderr),
        }

    def as_dict(self) -> dict:
        """JSON-ready summary (with ``data_quality``, ``dropped`` and ``warnings``)."""
        return {
            "data_quality": [q.as_dict() for q in self.data_quality],
            "dropped": [{"record": lab, **o.__dict__} for lab, o in self.dropped],
            "warnings": list(self.warnings),
            "at_bounds": self.at_bounds(),
            "parameter_flags": self.flags.as_dict(),
            "plausibility": [f.as_dict() for f in self.plausibility],
            "device_class": {"chosen": self.device_class,
                             "starts": [o.as_dict() for o in self.class_starts]},
            "summary": self.summary(),
            "noise_floor_nrmse": self.noise_nrmse,
            "above_noise": self.above_noise(),
            "start": dict(self.start),
            "parameters": self.parameters_dict(),
            "nrmse": {"calibration": self.nrmse_calibration,
                      "validation": self.nrmse_validation},
            "records": [dataclasses.asdict(e) for e in self.record_errors],
            "reference_models": {k: v.as_dict() for k, v in self.references.items()},
            "physics_loses_to_line": self.versus_line(),
            "physics_loses_to_two_slope": self.versus_map(),
            "correlation": {"names": list(self.varying),
                            "matrix": np.round(self.correlation, 4).tolist()},
            "fit": {"converged": self.converged, "status": self.status,
                    "message": self.message, "nfev": self.nfev, "cost": self.cost,
                    "n_samples": self.n_samples, "aic": self.aic, "bic": self.bic,
                    "starts": ([t.as_dict() for t in self.start_trials] if self.start_trials
                               else [{"start": s, "nrmse": v} for s, v in self.starts])},
        }


def _effect_unit(name: str) -> str:
    """Unit of fitted effect parameter ``effect.key``, from the effect's ``units``."""
    eff, key = name.split(".", 1)
    return f"[{EFFECTS[eff].units.get(key, '-')}]"
