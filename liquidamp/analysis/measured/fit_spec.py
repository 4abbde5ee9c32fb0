"""What a calibration varies: fit parameters and the fit specification (lmfit-style).

A :class:`FitSpec` is a tuple of :class:`Parameter` objects, each naming either a
:class:`~liquidamp.device.params.DeviceParams` field, varied as a multiplier [-] on the
starting parameter set (the paper's alpha_j of Table 2), or an effect parameter
``"effect.key"`` (e.g. ``"coulomb_friction.force_N"``), varied as an absolute value [SI].
Positive quantities are fitted in log space.  The fit itself is
:func:`liquidamp.analysis.measured.calibration.calibrate`.

Bounds scale with the records.  A multiplier's bounds ([0.05, 20] by
default) are relative to the device the fit starts from, which is sized to
the records when they are far from the given device
(:mod:`liquidamp.analysis.measured.start`); a fit that ends with an air ratio at its
lower bound is continued with that bound at the air ratio's physical floor
(:func:`air_floor`: a degassed chamber).  An effect parameter's catalogue
bounds (``Effect.bounds``, written for the paper's 1 kN, 3 mm device) are
replaced by bounds relative to the records' scales
(:func:`scale_effect_bounds`): with F_s and Y_s the largest half peak-to-peak
force and stroke, K_s = F_s / Y_s and M_s = K_s / w^2 (w the stroke
frequency),

=============  ==========================  ===================================
unit           bounds                      e.g. for F_s = 12 kN, Y_s = 13 mm
=============  ==========================  ===================================
N (> 0)        [1e-6 F_s, 2 F_s]           friction up to 24 kN (not 10 kN)
N (signed)     [-2 F_s, 2 F_s]             a load-cell offset
N/m            [1e-3 K_s, 1e5 K_s]         pre-sliding or series stiffness
kg             [1e-5 M_s, 10 M_s]          moving mass
m              [1e-3 Y_s, Y_s]             a dead band no wider than the stroke
=============  ==========================  ===================================

A length (a dead band, an end stop's clearance, a groove's half-width, a slip distance) of
less than 1e-3 Y_s is below what a record resolves: after a reversal the stroke moves
Y_s (w t)^2 / 2, which within one sample of a record of 100 samples a cycle
(w dt = 2 pi / 100) is 2e-3 Y_s, a dead band of half-width 1e-3 Y_s crossed in a sample
(the conditioning keeps tens of samples a cycle).  Its force is then that of the band
closed (backlash's is its friction alone, a reduction the selection rule tries), while a
fit driven toward a band of nanometres crosses it in microseconds and costs every
simulation thousands of steps (a backlash refit on a 3 kHz record: over 15 minutes with
the floor at 1e-5 Y_s, 30 s at 1e-3 Y_s).

Other units (velocities, ratios, leakage coefficients, pressures) keep the
catalogue's bounds.  A signed length (a groove's centre) keeps its bounds and is fitted in
units of Y_s (its difference steps then resolve the stroke).  Bounds a caller set
(different from the catalogue's) are kept.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C and Table 2.
.. [2] M. Newville et al., LMFIT, doi:10.5281/zenodo.11813 (parameters
   kept apart from the model).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from liquidamp.device.effects import EFFECTS
from liquidamp.device.params import SCALABLE, DeviceParams
from liquidamp.errors import (
    ParameterError,
    check_choice,
)

__all__ = ["Parameter", "FitSpec", "PAPER_FOUR", "check_spec_uses", "record_scales",
           "effect_bounds", "scale_effect_bounds", "AIR_RATIOS", "AIR_COMPLIANCE_SHARE",
           "air_floor", "air_floor_spec"]

#: The air ratios 1/gamma of the two chambers (DeviceParams fields).
AIR_RATIOS = ("inv_gamma1", "inv_gamma2")
#: Share of a chamber's compliance at the filling pressure the air carries at the air
#: ratio's physical floor (:func:`air_floor`) [-].
AIR_COMPLIANCE_SHARE = 0.01


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
            check_choice(f"{eff} parameter", key, EFFECTS[eff].parameter_keys())
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

    def with_effect(self, effect, start: dict | None = None, keys=None) -> FitSpec:
        """Add the effect's parameters ``keys`` (default: its fit keys; start: the effect's
        values or ``start``).

        Examples
        --------
        >>> from liquidamp.device.effects import make_effect
        >>> f = make_effect("smooth_friction", force_N=10.0)
        >>> FitSpec(()).with_effect(f, keys=("reverse_ratio",))["smooth_friction.reverse_ratio"]
        Parameter(name='smooth_friction.reverse_ratio', value=1.0, min=0.1, max=10.0, \
vary=True, log=True, scale=1.0)
        """
        if isinstance(effect, str):
            check_choice("effect", effect, EFFECTS)
            effect = EFFECTS[effect]()
        start = dict(start or {})
        new = list(self.parameters)
        keys = effect.fit_keys if keys is None else tuple(keys)
        for key in keys:
            check_choice(f"{effect.name} fitted parameter", key, tuple(effect.bounds))
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


def record_scales(records) -> dict:
    """Force, stroke, stiffness and mass scales of ``records`` (module docstring), SI.

    Returns
    -------
    dict
        ``{"N": F_s, "m": Y_s, "N/m": K_s, "kg": M_s}``: the largest half
        peak-to-peak force [N] and stroke [m] over the records, K_s = F_s / Y_s [N/m] and
        M_s = K_s / w^2 [kg] with w the lowest stroke frequency [rad/s].

    Examples
    --------
    >>> import numpy as np
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 2.0, 0.005)
    >>> r = Record.from_arrays(t, 0.003 * np.sin(6 * np.pi * t), 600 * np.cos(6 * np.pi * t))
    >>> {k: float(f"{v:.3g}") for k, v in record_scales([r]).items()}
    {'N': 600.0, 'm': 0.003, 'N/m': 200000.0, 'kg': 563.0}
    """
    import numpy as np

    records = tuple(records)
    if not records:
        raise ParameterError("record_scales needs at least one record")
    F_s = max(0.5 * float(np.ptp(r.force)) for r in records)
    Y_s = max(0.5 * float(np.ptp(r.displacement)) for r in records)
    w = 2 * math.pi * min(r.frequency for r in records)
    K_s = F_s / Y_s
    return {"N": F_s, "m": Y_s, "N/m": K_s, "kg": K_s / (w * w)}


def air_floor(params: DeviceParams) -> float:
    """The least air ratio 1/gamma a fit needs to reach: the air a liquid-only chamber holds
    to within :data:`AIR_COMPLIANCE_SHARE` of its compliance [-].

    An air ratio's physical range reaches 0 (a degassed chamber; the paper's inerter
    design holds 1/gamma ~ 1e-5).  In the Gholizadeh mixture (eq. 2) at the filling
    pressure p0 the air's compliance X0 / (n p0) and the liquid's (1 - X0) / B_l are equal
    at X0 = n p0 / B_l; at the share ``s`` of the chamber's compliance the air ratio is
    1/gamma = s n p0 / B_l (X0 << 1).  Below it the air changes the chamber stiffness at p0
    by less than ``s``: the multiplier bound [0.05, 20] of a fit (relative to the start's
    air, 0.1 on ``paper_initial``: 0.005 absolute, air carrying 98 % of the compliance) is
    then no physical limit, and a fit held there leaves a liquid-only device to effects
    that compensate (:func:`air_floor_spec`; calibrate continues such a fit to the floor).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> f"{air_floor(preset('paper_initial')):.3g}"  # 0.01 x 1.35 x 101325 Pa / 1.5513 GPa
    '8.82e-07'
    """
    return AIR_COMPLIANCE_SHARE * params.n * params.p0 / params.B_l


def air_floor_spec(spec, params: DeviceParams, names=AIR_RATIOS):
    """``spec`` with the lower bound of each air-ratio multiplier in ``names`` lowered to
    the physical floor (:func:`air_floor`) relative to ``params`` (the device the
    multipliers apply to); None where no bound is above the floor [-].

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> s = air_floor_spec(FitSpec.default(), preset("paper_initial"))
    >>> f"{s['inv_gamma1'].min:.3g}", s['c1'].min
    ('8.82e-06', 0.05)
    """
    floor = air_floor(params)
    out, changed = [], False
    for p in spec.parameters:
        start = getattr(params, p.name, 0.0) if p.name in names else 0.0
        if p.log and start > 0.0 and p.min * start > floor * (1.0 + 1e-9):
            p = p.replace(min=floor / start)
            changed = True
        out.append(p)
    return FitSpec(tuple(out)) if changed else None


_BOUND_RULES = {"N/m": (1e-3, 1e5), "kg": (1e-5, 10.0), "m": (1e-3, 1.0)}


def effect_bounds(effect: str, key: str, scales: dict) -> tuple[float, float]:
    """Bounds of effect parameter ``effect.key`` for records of ``scales``
    (:func:`record_scales`; module docstring's table), SI.

    Examples
    --------
    >>> effect_bounds("coulomb_friction", "force_N", {"N": 12e3, "m": 0.0127, "N/m": 9.4e5,
    ...                                               "kg": 9.6e4})
    (0.012, 24000.0)
    >>> effect_bounds("leakage", "coefficient_m3_per_s_Pa", {"N": 1.0, "m": 1.0, "N/m": 1.0,
    ...                                                      "kg": 1.0})
    (1e-16, 1e-07)
    """
    check_choice("effect", effect, EFFECTS)
    cls = EFFECTS[effect]
    check_choice(f"{effect} parameter", key, tuple(cls.bounds))
    lo, hi = cls.bounds[key]
    unit = cls.units.get(key, "-")
    if unit == "N":
        F_s = scales["N"]
        return (1e-6 * F_s, 2.0 * F_s) if lo > 0 else (-2.0 * F_s, 2.0 * F_s)
    if unit in _BOUND_RULES and lo > 0:
        a, b = _BOUND_RULES[unit]
        return a * scales[unit], b * scales[unit]
    return float(lo), float(hi)


def scale_effect_bounds(spec: FitSpec, records) -> FitSpec:
    """``spec`` with its effect parameters' catalogue bounds scaled to ``records``.

    A parameter whose bounds differ from its effect's catalogue bounds (set by
    the caller) is kept; the others get :func:`effect_bounds`, widened to hold
    their start value.
    """
    scales = None
    out = []
    for p in spec.parameters:
        if p.kind != "effect":
            out.append(p)
            continue
        eff, key = p.name.split(".", 1)
        if tuple(EFFECTS[eff].bounds.get(key, ())) != (p.min, p.max):
            out.append(p)
            continue
        scales = scales or record_scales(records)
        lo, hi = effect_bounds(eff, key, scales)
        lo, hi = min(lo, p.value), max(hi, p.value)
        if p.log:
            lo = max(lo, 1e-300)
        elif EFFECTS[eff].units.get(key) == "m":  # a signed length (a groove's centre):
            p = p.replace(scale=scales["m"])      # fitted in units of the records' stroke
        out.append(p.replace(min=lo, max=hi) if lo < hi else p)
    return FitSpec(tuple(out))
