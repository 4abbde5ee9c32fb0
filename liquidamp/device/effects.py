"""Add-on effects: what a device model may lack, as real model components.

Each effect is a frozen, validated dataclass whose fields are its parameters
(SI, keys as below).  :func:`with_effects` composes any number of them with
ANY :class:`~liquidamp.device.models.DeviceModel` and returns a new
DeviceModel with the same interface: extra states are appended (with names
and units), and ``rhs``, ``fluid_force``, ``initial_state``,
``state_scales``, ``pressures`` and ``mass`` are composed.  The composed
``fluid_force`` holds every effect force, so ``DeviceModel.force`` (which
adds ``params.friction_N`` sign(v)) keeps its meaning.

======================  =====================================  =================================
name                    parameters                             states added
======================  =====================================  =================================
``coulomb_friction``    force_N                                none: F += F_c sign(v)
``smooth_friction``     force_N, stiffness_N_per_m,            z_friction [-] (LuGre bristle
                        stribeck_velocity_m_per_s,             state without bristle damping:
                        static_ratio                           Dahl when static_ratio = 1)
``force_offset``        offset_N                               none: F += offset (load-cell bias)
``moving_mass``         mass_kg                                none: F += m a
``series_compliance``   stiffness_N_per_m                      y_piston [m]
``freeplay``            gap_m                                  y_fp [m] (play operator)
``leakage``             coefficient_m3_per_s_Pa                none: bypass mass flow
``cavitation``          vapour_pressure_Pa                     Vc1, Vc2 [m^3] (vapour cavities)
======================  =====================================  =================================

Composition order is canonical whatever order the effects are given in:
fluid effects (leakage, then cavitation) act on the chamber equations
innermost; the kinematic effects (series compliance, then freeplay) turn the
measured rod stroke into the piston stroke the fluid sees; the force effects
(friction, mass, offset) act on the measured (rod) stroke and add to the
load-cell force outermost.  Force effects therefore use the rod velocity and
acceleration, which is exact without a kinematic effect and a first-order
approximation with one.

The per-effect right-hand sides are plain scalar Python (``math`` module)
so that a compiled engine can mirror them.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C (friction |F_f| = 30 N,
   gradual transitions near zero velocity, Fig. 4 pre-sliding and Stribeck).
.. [2] C. Canudas de Wit, H. Olsson, K. J. Astrom, P. Lischinsky, "A new
   model for control of systems with friction", IEEE TAC 40(3), 1995 (LuGre).
.. [3] P. R. Dahl, "Solid friction damping of mechanical vibrations", AIAA J.
   14(12), 1976.
.. [4] H. E. Merritt, Hydraulic Control Systems, Wiley, 1967 (laminar
   leakage, Ch. 3; cavitation and air release).
.. [5] M. A. Krasnosel'skii, A. V. Pokrovskii, Systems with Hysteresis,
   Springer, 1989 (the play operator used for freeplay).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device.fluid import bulk_modulus_gholizadeh
from liquidamp.device.models import DeviceModel
from liquidamp.errors import ParameterError, check_choice, check_finite, check_nonnegative

__all__ = [
    "Effect",
    "CoulombFriction",
    "SmoothFriction",
    "ForceOffset",
    "MovingMass",
    "SeriesCompliance",
    "Freeplay",
    "Leakage",
    "Cavitation",
    "EFFECTS",
    "effect_names",
    "make_effect",
    "with_effects",
]


# ---------------------------------------------------------------------------
# scalar physics kernels (plain Python, math module only)


def lugre_rate(v: float, z: float, force: float, stiffness: float, v_s: float,
               static_ratio: float) -> float:
    """dz/dt of the normalized LuGre bristle state z = F_fr / F_c [1/s].

    ``dz/dt = (sigma0 / F_c) (v - |v| z / g(v))``, ``g = 1 + (r - 1)
    exp(-(v / v_s)^2)``: steady sliding gives F_fr = F_c g(v) sign(v), the
    Stribeck curve; at reversal the force changes over a pre-sliding
    displacement of about F_c / sigma0 instead of jumping.  Zero force gives 0.
    """
    if force <= 0.0:
        return 0.0
    g = 1.0 + (static_ratio - 1.0) * math.exp(-(v / v_s) ** 2)
    return stiffness / force * (v - abs(v) * z / g)


def play_rate(y: float, y_fp: float, v: float, gap: float) -> float:
    """Rate of the driven side of a dead band of half-width ``gap`` [m/s].

    The play operator: the driven side stays put while the rod crosses the
    gap and follows the rod once in contact, ``dy_fp/dt = v s``, with the
    contact switch ``s = clip((e sign(v) - gap) / delta + 1, 0, 1)``,
    ``e = y - y_fp`` and a smoothing width ``delta = 0.05 gap + 1e-7 m``
    (keeps the right-hand side continuous; e sign(v) settles at the gap).
    """
    delta = 0.05 * gap + 1.0e-7
    e = y - y_fp
    if v > 0.0:
        s = (e - gap) / delta + 1.0
    elif v < 0.0:
        s = (-e - gap) / delta + 1.0
    else:
        return 0.0
    if s <= 0.0:
        return 0.0
    if s >= 1.0:
        return v
    return v * s


def compliance_rate(v: float, k: float, g0: float, g1: float) -> float:
    """Piston velocity behind a series spring k [m/s].

    The massless piston balances the spring: k (y - y_p) = F_fluid.
    Differentiating, k (v - v_p) = dF/dt = g0 + g1 v_p, with g0, g1 the
    fluid force rate at v_p = 0 and its slope in v_p (the chamber equations
    are affine in the piston velocity).  An infinite k returns v.
    """
    if math.isinf(k):
        return v
    return (k * v - g0) / (k + g1)


def chamber_bulk(p: float, X0: float, B_l: float, p0: float, n: float, B_const: float,
                 uses_law: bool) -> float:
    """Bulk modulus of a chamber [Pa]: eq. (2) at p (floored at 1 Pa) or a constant."""
    if not uses_law:
        return B_const
    return bulk_modulus_gholizadeh(max(p, 1.0), B_l, X0, p0, n)


def cavity_width(p_v: float) -> float:
    """Pressure width of the regularised cavity switch [Pa]: 0.05 p_v + 500 Pa."""
    return 0.05 * p_v + 500.0


def _smoothstep(s: float) -> float:
    if s <= 0.0:
        return 0.0
    if s >= 1.0:
        return 1.0
    return s * s * (3.0 - 2.0 * s)


def cavity_rates(p: float, dp_base: float, Vc: float, V: float, B: float,
                 p_v: float) -> tuple[float, float]:
    """(dp/dt, dVc/dt) of one chamber with a vapour cavity Vc [Pa/s, m^3/s].

    The chamber's compression rate (volume per second) is w = dp_base V / B.
    A share sigma of it goes to the cavity, dVc/dt = -sigma w, the rest to
    the pressure, dp/dt = (1 - sigma) dp_base.  Regularised complementarity
    over a small pressure width delta = :func:`cavity_width` (p_v): while the
    chamber expands (w < 0), sigma rises smoothly from 0 at p = p_v + delta to
    1 at p = p_v, so the pressure settles onto p_v from above and the cavity
    takes the volume change; while it is compressed (w > 0), sigma = S(Vc /
    V_delta), V_delta = V delta / B the volume that delta would compress, so
    the cavity refills first and the pressure rises once it has closed (S the
    C1 smoothstep).  Both rates carry the factor w, so the right-hand side
    is continuous where the motion reverses, and Vc never turns negative.
    The hard switch (delta -> 0) made LSODA run out of steps.
    """
    w = dp_base * V / B
    delta = cavity_width(p_v)
    if w < 0.0:
        sigma = _smoothstep((p_v + delta - p) / delta)
    else:
        sigma = _smoothstep(max(Vc, 0.0) * B / (V * delta))
    return (1.0 - sigma) * dp_base, -sigma * w


# ---------------------------------------------------------------------------
# effect classes


@dataclass(frozen=True)
class Effect:
    """Base class of the add-on effects.

    Class attributes: ``name`` (registry key), ``units`` (parameter key ->
    unit), ``fit_keys`` (parameters a calibration varies by default),
    ``bounds`` (key -> (low, high) for fitting), ``needs_pressures`` (only for
    models with chamber pressures), ``order`` (canonical composition rank),
    ``stroke_driven`` (the effect acts on the load-cell force only and its own
    states, ``state_names``, obey ODEs driven by the measured stroke alone,
    :meth:`stroke_state_rate`: the fluid states do not see it, so a run can
    take the fluid states from the compiled engine and integrate these apart).
    """

    name: ClassVar[str] = ""
    units: ClassVar[dict] = {}
    fit_keys: ClassVar[tuple] = ()
    bounds: ClassVar[dict] = {}
    needs_pressures: ClassVar[bool] = False
    order: ClassVar[int] = 0
    description: ClassVar[str] = ""
    stroke_driven: ClassVar[bool] = False
    state_names: ClassVar[tuple] = ()

    def stroke_state_rate(self, u, z) -> list:
        """Rates of the effect's own states under the measured stroke ``u = (y, v, a)``.

        Only for ``stroke_driven`` effects with states.
        """
        raise NotImplementedError(f"effect {self.name!r} has no stroke-driven states")

    @property
    def parameters(self) -> dict[str, float]:
        """Parameter values by key (SI)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    def replace(self, **changes) -> Effect:
        """Validated copy with ``changes`` applied; unknown keys raise ParameterError."""
        for key in changes:
            check_choice(f"{self.name} parameter", key, self.parameters)
        return dataclasses.replace(self, **changes)

    def apply(self, model: DeviceModel) -> DeviceModel:  # pragma: no cover - abstract
        raise NotImplementedError

    def __str__(self) -> str:
        pars = ", ".join(f"{k}={v:.4g}" for k, v in self.parameters.items())
        return f"{self.name}({pars})"


def _compose(model: DeviceModel, effect: Effect, **changes) -> DeviceModel:
    name = f"{model.name}+{effect.name}"
    desc = f"{model.description}; with {effect}"
    return dataclasses.replace(model, name=name, description=desc, jacobian=None,
                               effects=model.effects + (effect,), **changes)


def _force_only(model: DeviceModel, effect: Effect, extra, *, uses_acceleration=False):
    base_force = model.fluid_force

    def fluid_force(t, x, u, p):
        return base_force(t, x, u, p) + extra(u)

    return _compose(model, effect, fluid_force=fluid_force,
                    uses_acceleration=model.uses_acceleration or uses_acceleration)


@dataclass(frozen=True)
class CoulombFriction(Effect):
    """Coulomb seal friction F += F_c sign(v) (the paper's |F_f|, Sec. IV.C).

    Parameters
    ----------
    force_N : float
        Friction force level F_c >= 0 [N] (paper: 30 N).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> m = with_effects(get_model("dashpot"), CoulombFriction(30.0))
    >>> from liquidamp.device import preset
    >>> float(m.force(0.0, np.zeros(0), (0.0, 0.01, 0.0), preset("reference")) - 0.01 *
    ...       preset("reference").c_L)
    30.0
    """

    force_N: float = 0.0
    name: ClassVar[str] = "coulomb_friction"
    stroke_driven: ClassVar[bool] = True
    units: ClassVar[dict] = {"force_N": "N"}
    fit_keys: ClassVar[tuple] = ("force_N",)
    bounds: ClassVar[dict] = {"force_N": (1e-2, 1e4)}
    order: ClassVar[int] = 40
    description: ClassVar[str] = "Coulomb seal friction F_c sign(v)"

    def __post_init__(self):
        check_nonnegative("coulomb_friction force_N", self.force_N, "N")

    def apply(self, model):
        fc = self.force_N
        return _force_only(model, self, lambda u: fc * np.sign(u[1]))


@dataclass(frozen=True)
class ForceOffset(Effect):
    """Load-cell bias: F += offset [N] (the paper removes it before the fit, Sec. IV.B).

    Parameters
    ----------
    offset_N : float
        Constant force added to the model's load-cell force [N] (any sign).
    """

    offset_N: float = 0.0
    name: ClassVar[str] = "force_offset"
    stroke_driven: ClassVar[bool] = True
    units: ClassVar[dict] = {"offset_N": "N"}
    fit_keys: ClassVar[tuple] = ("offset_N",)
    bounds: ClassVar[dict] = {"offset_N": (-1e4, 1e4)}
    order: ClassVar[int] = 50
    description: ClassVar[str] = "constant load-cell bias"

    def __post_init__(self):
        check_finite("force_offset offset_N", self.offset_N, "N")

    def apply(self, model):
        off = self.offset_N
        return _force_only(model, self, lambda u: off + 0.0 * np.asarray(u[1], float))


@dataclass(frozen=True)
class MovingMass(Effect):
    """Piston and rod inertia: F += m a (Sec. IV.C: about 1.8 N peak at 0.5 Hz).

    Parameters
    ----------
    mass_kg : float
        Moving mass m >= 0 [kg].
    """

    mass_kg: float = 0.0
    name: ClassVar[str] = "moving_mass"
    stroke_driven: ClassVar[bool] = True
    units: ClassVar[dict] = {"mass_kg": "kg"}
    fit_keys: ClassVar[tuple] = ("mass_kg",)
    bounds: ClassVar[dict] = {"mass_kg": (1e-3, 1e3)}
    order: ClassVar[int] = 45
    description: ClassVar[str] = "piston and rod inertia m a"

    def __post_init__(self):
        check_nonnegative("moving_mass mass_kg", self.mass_kg, "kg")

    def apply(self, model):
        m = self.mass_kg
        return _force_only(model, self, lambda u: m * np.asarray(u[2], float),
                           uses_acceleration=True)


def _append_states(model, effect, names, units, extra_rhs, extra_x0, extra_scales,
                   *, force=None, inner_u=None, pressures=None, mass=None, **changes):
    """Compose a model with appended states.

    ``extra_rhs(t, x, u, p, dx_base, xe) -> list`` gives the derivatives of the
    extra states (and may modify dx_base in place); ``inner_u(x_extra, u) ->
    u'`` maps the measured stroke to the one the base model sees (vectorized
    when given arrays).
    """
    n = model.n_states
    base_rhs, base_force, base_x0, base_sc = (model.rhs, model.fluid_force, model.initial_state,
                                              model.state_scales)
    base_pr, base_mass = model.pressures, model.mass
    mapu = inner_u or (lambda xe, u: u)

    def rhs(t, x, u, p):
        xe = x[n:]
        up = mapu(xe, u)
        dx = np.array(base_rhs(t, x[:n], up, p), dtype=float)
        extra = extra_rhs(t, x, u, p, dx, xe, up)
        return np.concatenate((dx, extra))

    def fluid_force(t, x, u, p):
        up = mapu(x[n:], u)
        f = base_force(t, x[:n], up, p)
        return f if force is None else f + force(x, u, p)

    def initial_state(p, y0=0.0):
        return np.concatenate((np.asarray(base_x0(p, y0), float), extra_x0(p, y0)))

    def state_scales(p):
        return np.concatenate((np.asarray(base_sc(p), float), extra_scales(p)))

    new_pr = None
    if base_pr is not None:
        def new_pr(x, u, p):
            return base_pr(x[:n], mapu(x[n:], u), p)
    new_mass = mass
    if new_mass is None and base_mass is not None:
        def new_mass(x, u, p):
            return base_mass(x[:n], mapu(x[n:], u), p)
    return _compose(model, effect, state_names=model.state_names + tuple(names),
                    state_units=model.state_units + tuple(units), rhs=rhs,
                    fluid_force=fluid_force, initial_state=initial_state,
                    state_scales=state_scales, pressures=pressures or new_pr, mass=new_mass,
                    **changes)


@dataclass(frozen=True)
class SmoothFriction(Effect):
    """Seal friction with pre-sliding and Stribeck behaviour (LuGre without bristle damping).

    F += F_c z with dz/dt = (sigma0 / F_c)(v - |v| z / g(v)),
    g(v) = 1 + (r - 1) exp(-(v / v_s)^2).  Around each reversal the force
    changes gradually over a pre-sliding stroke of about F_c / sigma0 (the
    gradual transitions of Figs. 5-6 and the pre-slide stage of Fig. 4); with
    r > 1 the sliding force falls from r F_c to F_c as |v| passes v_s (the
    Stribeck region of Fig. 4).  sigma0 -> infinity with r = 1 is Coulomb
    friction.  Extra state ``z_friction`` [-], starting at 0.

    Parameters
    ----------
    force_N : float
        Sliding (Coulomb) level F_c >= 0 [N].
    stiffness_N_per_m : float
        Bristle (pre-sliding) stiffness sigma0 > 0 [N/m].
    stribeck_velocity_m_per_s : float
        Stribeck velocity v_s > 0 [m/s].
    static_ratio : float
        Static-to-sliding force ratio r >= 1 [-] (1: no Stribeck dip, Dahl-like).
    """

    force_N: float = 0.0
    stiffness_N_per_m: float = 1.0e5
    stribeck_velocity_m_per_s: float = 0.005
    static_ratio: float = 1.0
    name: ClassVar[str] = "smooth_friction"
    units: ClassVar[dict] = {"force_N": "N", "stiffness_N_per_m": "N/m",
                             "stribeck_velocity_m_per_s": "m/s", "static_ratio": "-"}
    fit_keys: ClassVar[tuple] = ("force_N", "stiffness_N_per_m")
    bounds: ClassVar[dict] = {"force_N": (1e-2, 1e4), "stiffness_N_per_m": (1e2, 1e9),
                              "stribeck_velocity_m_per_s": (1e-5, 1.0),
                              "static_ratio": (1.0, 5.0)}
    order: ClassVar[int] = 35
    description: ClassVar[str] = "LuGre/Dahl friction: gradual reversal, Stribeck"
    stroke_driven: ClassVar[bool] = True
    state_names: ClassVar[tuple] = ("z_friction",)

    def __post_init__(self):
        check_nonnegative("smooth_friction force_N", self.force_N, "N")
        for key, unit in (("stiffness_N_per_m", "N/m"), ("stribeck_velocity_m_per_s", "m/s")):
            v = check_finite(f"smooth_friction {key}", getattr(self, key), unit)
            if not v > 0:
                raise ParameterError(f"smooth_friction {key} must be > 0 [{unit}], got {v:g}")
        r = check_finite("smooth_friction static_ratio", self.static_ratio, "-")
        if r < 1.0:
            raise ParameterError(f"smooth_friction static_ratio must be >= 1 [-], got {r:g}")

    def stroke_state_rate(self, u, z) -> list:
        """[dz/dt] of :func:`lugre_rate` at the rod velocity ``u[1]`` [1/s]."""
        return [lugre_rate(float(u[1]), float(z[0]), self.force_N, self.stiffness_N_per_m,
                           self.stribeck_velocity_m_per_s, self.static_ratio)]

    def apply(self, model):
        fc = self.force_N
        n = model.n_states

        def extra(t, x, u, p, dx, xe, up):
            return self.stroke_state_rate(u, xe)

        return _append_states(model, self, self.state_names, ("-",), extra,
                              lambda p, y0: np.zeros(1), lambda p: np.ones(1),
                              force=lambda x, u, p: fc * x[n])


def _piston_index(model: DeviceModel):
    for name in ("y_piston", "y_fp"):
        if name in model.state_names:
            return model.state_names.index(name)
    return None


def _check_linear_force(model: DeviceModel, effect: Effect) -> None:
    if model.n_states == 0 or model.uses_acceleration:
        raise ParameterError(
            f"effect {effect.name!r} needs a model whose force is carried by its states; "
            f"model {model.name!r} has {model.n_states} states"
            + (" and uses the acceleration" if model.uses_acceleration else "")
            + "; for a dashpot behind a spring use 'maxwell'")


@dataclass(frozen=True)
class SeriesCompliance(Effect):
    """Rig or attachment elasticity k between the measured stroke and the piston.

    The piston position ``y_piston`` is a state.  The piston is massless, so
    the spring carries the fluid force, k (y - y_piston) = F_fluid; the
    piston velocity follows from the time derivative of that balance, which
    is affine in it because the chamber equations are (see
    :func:`compliance_rate`).  The fluid model sees the piston stroke; the
    load cell reads the spring force.  Needs a model whose force is a linear
    function of its states (every model with pressure states and
    ``maxwell``); k = inf reproduces the bare model.  Like air in the
    chambers it is a spring in series with the channel, so at small strokes
    it trades against the air ratios (only the pressure dependence of the
    air's stiffness tells them apart).

    Parameters
    ----------
    stiffness_N_per_m : float
        Series stiffness k > 0 [N/m] (math.inf: rigid).
    """

    stiffness_N_per_m: float = math.inf
    name: ClassVar[str] = "series_compliance"
    units: ClassVar[dict] = {"stiffness_N_per_m": "N/m"}
    fit_keys: ClassVar[tuple] = ("stiffness_N_per_m",)
    bounds: ClassVar[dict] = {"stiffness_N_per_m": (1e3, 1e10)}
    order: ClassVar[int] = 20
    description: ClassVar[str] = "spring in series between stroke and piston"

    def __post_init__(self):
        k = float(self.stiffness_N_per_m)
        if not k > 0 or math.isnan(k):
            raise ParameterError(
                f"series_compliance stiffness_N_per_m must be > 0 [N/m] (inf: rigid), got {k:g}")

    def apply(self, model):
        _check_linear_force(model, self)
        k = float(self.stiffness_N_per_m)
        n = model.n_states
        base_rhs, base_force = model.rhs, model.fluid_force

        def inner_u(xe, u):
            return (xe[0], u[1], u[2])  # v replaced in rhs; force depends on states only

        def rhs(t, x, u, p):
            xb = x[:n]
            yp = float(x[n])
            a = u[2]
            d0 = np.asarray(base_rhs(t, xb, (yp, 0.0, a), p), float)
            if math.isinf(k):
                vp = float(u[1])
                dx = np.asarray(base_rhs(t, xb, (yp, vp, a), p), float)
            else:
                d1 = np.asarray(base_rhs(t, xb, (yp, 1.0, a), p), float)
                g0 = float(base_force(t, d0, u, p))
                g1 = float(base_force(t, d1, u, p)) - g0
                vp = compliance_rate(float(u[1]), k, g0, g1)
                dx = d0 + vp * (d1 - d0)
            return np.concatenate((dx, [vp]))

        composed = _append_states(model, self, ("y_piston",), ("m",), lambda *a: [0.0],
                                  lambda p, y0: np.array([y0]),
                                  lambda p: np.array([1e-4]), inner_u=inner_u)
        return dataclasses.replace(composed, rhs=rhs)


@dataclass(frozen=True)
class Freeplay(Effect):
    """Dead band of half-width ``gap_m`` in the attachment (play operator).

    The driven side ``y_fp`` (a state) stays put while the rod crosses the
    gap and follows it once in contact (:func:`play_rate`); the piston is
    assumed held by its seals while in the gap, so the fluid keeps relaxing
    through the channel there.  The fluid model sees ``y_fp``.  gap 0
    reproduces the bare model.

    Parameters
    ----------
    gap_m : float
        Half-width of the dead band >= 0 [m].
    """

    gap_m: float = 0.0
    name: ClassVar[str] = "freeplay"
    units: ClassVar[dict] = {"gap_m": "m"}
    fit_keys: ClassVar[tuple] = ("gap_m",)
    bounds: ClassVar[dict] = {"gap_m": (1e-7, 1e-2)}
    order: ClassVar[int] = 30
    description: ClassVar[str] = "dead band in the attachment"

    def __post_init__(self):
        check_nonnegative("freeplay gap_m", self.gap_m, "m")

    def apply(self, model):
        g = self.gap_m

        def switch(e, v):
            delta = 0.05 * g + 1.0e-7
            s = (np.sign(v) * e - g) / delta + 1.0
            return np.where(v == 0.0, 0.0, np.clip(s, 0.0, 1.0))

        def inner_u(xe, u):
            if np.ndim(u[0]):
                vp = u[1] * switch(u[0] - xe[0], u[1])
                return (xe[0], vp, u[2])
            rate = play_rate(float(u[0]), float(xe[0]), float(u[1]), g)
            return (xe[0], rate, u[2])

        def extra(t, x, u, p, dx, xe, up):
            return [up[1]]

        return _append_states(model, self, ("y_fp",), ("m",), extra,
                              lambda p, y0: np.array([y0]), lambda p: np.array([1e-4]),
                              inner_u=inner_u)


def _chamber_indices(model: DeviceModel, effect: Effect):
    if model.pressures is None or "p1" not in model.state_names:
        raise ParameterError(
            f"effect {effect.name!r} needs a model with chamber pressure states p1, p2; "
            f"model {model.name!r} has states ({', '.join(model.state_names) or 'none'}); use "
            "'full', 'no_inertia', 'constant_bulk', 'volumetric' or 'inertial'")
    names = model.state_names
    i1, i2 = names.index("p1"), names.index("p2")
    r1 = names.index("rho1") if "rho1" in names else None
    r2 = names.index("rho2") if "rho2" in names else None
    return i1, i2, r1, r2


@dataclass(frozen=True)
class Leakage(Effect):
    """Laminar bypass past the piston: mass flow m_L = rho_l k (p1 - p2) from chamber 1 to 2.

    Added to the chamber equations as a second path in parallel with the
    channel: with density states (eqs. 10-11) dp_i/dt -/+= B_i/V_i m_L/rho_i
    and drho_i/dt -/+= m_L/V_i; with explicit constant-bulk densities
    (eqs. 13, 14, 17) dp_i/dt -/+= B0i/V_i m_L/r_i(p_i).  Either way the total
    mass is conserved exactly.  Needs chamber pressure states.  At small
    strokes it trades against c1 (both are laminar conductances); only the
    channel's inertance and quadratic loss, which the bypass skips, tell
    them apart.

    Parameters
    ----------
    coefficient_m3_per_s_Pa : float
        Volumetric leakage conductance k >= 0 [m^3/(s Pa)].
    """

    coefficient_m3_per_s_Pa: float = 0.0
    name: ClassVar[str] = "leakage"
    units: ClassVar[dict] = {"coefficient_m3_per_s_Pa": "m^3/(s Pa)"}
    fit_keys: ClassVar[tuple] = ("coefficient_m3_per_s_Pa",)
    bounds: ClassVar[dict] = {"coefficient_m3_per_s_Pa": (1e-16, 1e-7)}
    needs_pressures: ClassVar[bool] = True
    order: ClassVar[int] = 5
    description: ClassVar[str] = "laminar bypass past the piston"

    def __post_init__(self):
        check_nonnegative("leakage coefficient_m3_per_s_Pa", self.coefficient_m3_per_s_Pa,
                          "m^3/(s Pa)")

    def apply(self, model):
        i1, i2, r1i, r2i = _chamber_indices(model, self)
        kL = self.coefficient_m3_per_s_Pa
        iy = _piston_index(model)
        law = model.uses_bulk_law
        base_rhs = model.rhs

        def rhs(t, x, u, p):
            dx = np.array(base_rhs(t, x, u, p), dtype=float)
            p1, p2 = float(x[i1]), float(x[i2])
            y = float(x[iy]) if iy is not None else float(u[0])
            V1, V2 = p.V01 - p.A_p * y, p.V02 + p.A_p * y
            mL = p.rho_l * kL * (p1 - p2)
            B1 = chamber_bulk(p1, p.X01, p.B_l, p.p0, p.n, p.B01, law)
            B2 = chamber_bulk(p2, p.X02, p.B_l, p.p0, p.n, p.B02, law)
            if r1i is not None:
                d1, d2 = float(x[r1i]), float(x[r2i])
                dx[r1i] -= mL / V1
                dx[r2i] += mL / V2
            else:
                d1 = p.rho0 * math.exp((p1 - p.p0) / B1)
                d2 = p.rho0 * math.exp((p2 - p.p0) / B2)
            dx[i1] -= B1 / V1 * mL / d1
            dx[i2] += B2 / V2 * mL / d2
            return dx

        return _compose(model, self, rhs=rhs)


@dataclass(frozen=True)
class Cavitation(Effect):
    """Vapour cavities: a chamber's pressure cannot fall below p_v.

    One cavity-volume state per chamber (``Vc1``, ``Vc2`` [m^3], starting at
    0).  When a chamber's pressure reaches p_v while it still expands, the
    pressure is held at p_v and the cavity opens and takes the volume
    change; the pressure rises again only after the cavity has refilled
    (:func:`cavity_rates`: a regularised switch over a pressure width of
    0.05 p_v + 500 Pa, :func:`cavity_width`, so that the equations stay
    integrable).  Mass is untouched (vapour mass neglected), so a
    mass-conserving model stays so.  Needs chamber pressure states.  In this
    model family a little more entrained air (a softer low-pressure
    chamber) can mimic a cavity closely: report ties.

    Parameters
    ----------
    vapour_pressure_Pa : float
        p_v > 0 [Pa] (water at 20 C: 2339 Pa; dissolved-air release makes
        the effective value higher).
    """

    vapour_pressure_Pa: float = 2339.0
    name: ClassVar[str] = "cavitation"
    units: ClassVar[dict] = {"vapour_pressure_Pa": "Pa"}
    fit_keys: ClassVar[tuple] = ("vapour_pressure_Pa",)
    bounds: ClassVar[dict] = {"vapour_pressure_Pa": (1.0, 5e5)}
    needs_pressures: ClassVar[bool] = True
    order: ClassVar[int] = 10
    description: ClassVar[str] = "pressure held at p_v while a vapour cavity is open"

    def __post_init__(self):
        v = check_finite("cavitation vapour_pressure_Pa", self.vapour_pressure_Pa, "Pa")
        if not v > 0:
            raise ParameterError(f"cavitation vapour_pressure_Pa must be > 0 [Pa], got {v:g}")

    def apply(self, model):
        i1, i2, _, _ = _chamber_indices(model, self)
        pv = self.vapour_pressure_Pa
        iy = _piston_index(model)
        law = model.uses_bulk_law

        def extra(t, x, u, p, dx, xe, up):
            p1, p2 = float(x[i1]), float(x[i2])
            y = float(x[iy]) if iy is not None else float(u[0])
            V1, V2 = p.V01 - p.A_p * y, p.V02 + p.A_p * y
            B1 = chamber_bulk(p1, p.X01, p.B_l, p.p0, p.n, p.B01, law)
            B2 = chamber_bulk(p2, p.X02, p.B_l, p.p0, p.n, p.B02, law)
            dp1, dc1 = cavity_rates(p1, float(dx[i1]), float(xe[0]), V1, B1, pv)
            dp2, dc2 = cavity_rates(p2, float(dx[i2]), float(xe[1]), V2, B2, pv)
            dx[i1], dx[i2] = dp1, dp2
            return [dc1, dc2]

        return _append_states(model, self, ("Vc1", "Vc2"), ("m^3", "m^3"), extra,
                              lambda p, y0: np.zeros(2),
                              lambda p: np.full(2, p.A_p * 1e-4))


EFFECTS: dict[str, type[Effect]] = {
    cls.name: cls
    for cls in (CoulombFriction, SmoothFriction, ForceOffset, MovingMass, SeriesCompliance,
                Freeplay, Leakage, Cavitation)
}
"""Registry: effect name -> class."""


def effect_names() -> tuple[str, ...]:
    """Names of the catalogue effects.

    Examples
    --------
    >>> effect_names()
    ('coulomb_friction', 'smooth_friction', 'force_offset', 'moving_mass', \
'series_compliance', 'freeplay', 'leakage', 'cavitation')
    """
    return tuple(EFFECTS)


def make_effect(name: str, **parameters) -> Effect:
    """Build the catalogue effect ``name`` with ``parameters`` (SI, keys as documented).

    Examples
    --------
    >>> make_effect("freeplay", gap_m=1e-4).parameters
    {'gap_m': 0.0001}
    >>> make_effect("stiction")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown effect 'stiction'; valid: coulomb_friction, \
smooth_friction, force_offset, moving_mass, series_compliance, freeplay, leakage, cavitation
    """
    check_choice("effect", name, EFFECTS)
    cls = EFFECTS[name]
    keys = [f.name for f in dataclasses.fields(cls)]
    for key in parameters:
        check_choice(f"{name} parameter", key, keys)
    return cls(**{k: float(v) for k, v in parameters.items()})


def with_effects(model: DeviceModel, *effects: Effect) -> DeviceModel:
    """Return ``model`` with ``effects`` added: a new DeviceModel with the same interface.

    The effects are composed in the canonical order of the module docstring
    whatever order they are given in; each name may appear once.

    Raises
    ------
    ParameterError
        A duplicate effect, something that is not an Effect, or an effect
        that needs chamber pressures on a model without them.

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> m = with_effects(get_model("full"), Cavitation(2339.0), SmoothFriction(20.0))
    >>> m.name, m.state_names[5:]
    ('full+cavitation+smooth_friction', ('Vc1', 'Vc2', 'z_friction'))
    >>> with_effects(get_model("single_state"), Leakage(1e-12))
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: effect 'leakage' needs a model with chamber pressure \
states p1, p2; model 'single_state' has states (dp); use 'full', 'no_inertia', \
'constant_bulk', 'volumetric' or 'inertial'
    """
    from liquidamp.device.models import get_model

    model = get_model(model)
    seen = set()
    for e in effects:
        if not isinstance(e, Effect):
            raise ParameterError(f"with_effects takes Effect objects, got {type(e).__name__}")
        if e.name in seen:
            raise ParameterError(f"effect {e.name!r} given twice")
        seen.add(e.name)
    for e in sorted(effects, key=lambda e: e.order):
        model = e.apply(model)
    return model
