"""Add-on effects: what a device model may lack, as real model components.

Each effect is a frozen, validated dataclass whose fields are its parameters
(SI, keys as below) and whose class attributes are its metadata (units,
bounds, states, the compiled slot its parameters go to, how it enters a
linear or describing-function model).  Its physics is written once, in
:mod:`liquidamp.device.kernels`, and runs on both engines.
:func:`with_effects` composes any number of them with any
:class:`~liquidamp.device.models.DeviceModel` and returns a new DeviceModel
with the same interface: extra states are appended (with names and units),
and the model's ``effects`` tuple tells every consumer what it holds.  The
composed ``fluid_force`` holds every effect force, so ``DeviceModel.force``
(which adds ``params.friction_N`` sign(v)) keeps its meaning.

======================  =====================================  =================================
name                    parameters                             states added
======================  =====================================  =================================
``coulomb_friction``    force_N; location (rod | piston)       none: F += F_c sign(v)
``smooth_friction``     force_N, stiffness_N_per_m,            z_friction [-] (LuGre bristle
                        stribeck_velocity_m_per_s,             state without bristle damping:
                        static_ratio; location (rod | piston)  Dahl when static_ratio = 1)
``force_offset``        offset_N                               none: F += offset (load-cell bias)
``moving_mass``         mass_kg                                none: F += m a
``series_compliance``   stiffness_N_per_m                      y_piston [m]
``freeplay``            gap_m                                  y_fp [m] (play operator)
``floating_freeplay``   gap_m, contact_stiffness_N_per_m       y_piston [m] (the dead band
                                                               before a free piston: a series
                                                               contact engaged past the band)
``leakage``             coefficient_m3_per_s_Pa                none: bypass mass flow
``cavitation``          vapour_pressure_Pa                     Vc1, Vc2 [m^3] (vapour cavities)
``rotating_frame``      rotor_speed_rad_per_s,                 none: centrifugal pressure rise
                        mounting_radius_m, axis_angle_rad      dp_c on every flow path and the
                                                               force; rest state on the rotor
``relief_valve``        cracking_pressure_Pa,                  none: second path beside the
                        conductance_m3_per_s_Pa                channel above p_r (dashpot types:
                                                               exact force saturation)
``asymmetric_loss``     rebound_ratio                          none: loss coefficients x r in
                                                               rebound
``bypass_groove``       depth, centre_m, half_width_m          none: loss coefficients x
                                                               1 - d exp(-((y - y_c)/w)^2)
                                                               (softer over a band of stroke)
``elastomer``           parallel_stiffness_N_per_m,            F_elastomer [N] (k0 parallel to
                        branch_stiffness_N_per_m,              k1 in series with c1: standard
                        branch_damping_N_s_per_m               linear solid on the rod)
``end_stops``           stiffness_N_per_m, clearance_m,        none: contact beyond centre +/-
                        damping_N_s_per_m, centre_m            clearance (C1 onset)
``gas_charge``          rod_area_m2, charge_pressure_Pa,       none: preload p_c A_r and gas
                        gas_volume_m3, polytropic_index,       spring (polytropic, absolute
                        stroke_offset_m, ambient_pressure_Pa   stroke); chamber level + p_g(y)
``digressive_valve``    compression_cracking_Pa,               none: relief_valve's path with a
                        compression_conductance_m3_per_s_Pa,   cracking pressure and conductance
                        rebound_cracking_Pa,                   per flow direction (a knee per
                        rebound_conductance_m3_per_s_Pa        direction)
``field_yield``         yield_pressure_Pa,                     u_field [V or A] (field lag of
                        yield_pressure_per_input,              the measured voltage or current;
                        lag_rate_per_s,                        Bingham-like yield drop in the
                        smoothing_flow_kg_per_s; input         channel's momentum balance)
``self_heating``        heat_capacity_J_per_K,                 T_fluid [K]: warmed by the
                        conductance_W_per_K, beta_per_K,       dissipated power; c1 x mu(T)/
                        c2_exponent, ambient/reference/        mu(T_ref), c2 x its power
                        initial_temperature_K, law_a, law_b;   gamma2 (exponential, water or
                        law (exponential | water | walther)    Walther law)
======================  =====================================  =================================

Composition order is canonical whatever order the effects are given in
(``order``, innermost first): the fluid effects act on the chamber equations
innermost (asymmetric_loss 3 and bypass_groove 4 on the channel's coefficients, leakage 5,
field_yield 6 on the
channel's momentum balance, and
relief_valve or digressive_valve 7 as paths beside the channel, rotating_frame 8 driving every
flow path, cavitation 10 on the pressure rates, so that it sees the rotating
frame's lowered inboard pressures); the kinematic effects (series_compliance
20, then freeplay 30) turn the measured rod stroke into the piston stroke the
fluid sees; the force effects (smooth_friction 35, coulomb_friction 40, elastomer 42, moving_mass
45, end_stops 47, gas_charge 48, force_offset 50) act on the measured (rod) stroke and add
to the load-cell force outermost, except friction at ``location="piston"``,
which sits behind the kinematic effects with the fluid.  Force effects
therefore use the rod velocity and acceleration, which is exact without a
kinematic effect and a first-order approximation with one.  On the
stateless dashpot-type bases (``dashpot``, ``dashpot_inerter``,
``viscous``) the flow effects relief_valve and asymmetric_loss act as the
exact force laws they imply.

Diagnosis: every effect states a probe (:meth:`Effect.probe`), so each is a
candidate of :func:`liquidamp.analysis.measured.diagnosis.diagnose`; the
four of issue #12 (relief_valve, asymmetric_loss, elastomer, end_stops) are
screened only when named (``Effect.screened`` False): a relief valve whose
cracking pressure falls towards zero is a laminar bypass, and on the leakage
record of the diagnosis tests it out-scores ``leakage`` (whose linear
signature the free c1 absorbs) and is refitted to p_r = 2 kPa, G = 1.97e-11
m^3/(s Pa) against the hidden 2e-11; likewise an elastomer's springs trade
with the air.

Composition fields: a field declared with :func:`dataclasses.field` metadata
``composition`` (the allowed words) says where an effect sits rather than how
strong it is: ``location`` of the two friction effects, ``"rod"`` (default:
on the measured stroke, outermost) or ``"piston"`` (behind the kinematic
effects, in series with a dead band like the fluid: the chain rod -> dead
band -> friction element), and ``drives`` of ``freeplay``, ``"piston"``
(default: the fluid and the friction at the piston behind the dead band) or
``"friction"`` (only the friction at the piston: a friction element behind its
own play, the fluid on the rod).  It is part of the model, not a fitted parameter:
:attr:`Effect.parameters` (and so fits, bounds and fit keys) holds the
numbers only, :meth:`Effect.as_dict` both (device files, JSON, synthetic
recipes), and ``str(effect)``, :func:`make_effect`, device files and the
command line's ``--effect coulomb_friction:force_N=100,location=piston``
accept it.  A diagnosis that wants "freeplay in series with the existing
friction" composes ``Freeplay(g)`` with the friction it already has
re-placed: ``friction.replace(location="piston")``.

Modules: this module is the public face (the registry :data:`EFFECTS`,
:func:`make_effect`, :func:`with_effects`) and re-exports every effect; the
:class:`~liquidamp.device.effects_base.Effect` base is in
:mod:`liquidamp.device.effects_base` and the effects by family in
:mod:`~liquidamp.device.effects_force` (coulomb_friction, smooth_friction,
force_offset, moving_mass, elastomer, end_stops),
:mod:`~liquidamp.device.effects_kinematic` (series_compliance, freeplay),
:mod:`~liquidamp.device.effects_fluid` (leakage, relief_valve,
asymmetric_loss, cavitation), :mod:`~liquidamp.device.effects_operating`
(rotating_frame), :mod:`~liquidamp.device.effects_position` (bypass_groove) and
:mod:`~liquidamp.device.effects_damper` (gas_charge,
digressive_valve: what real dampers have, issue #20) and
:mod:`~liquidamp.device.effects_field` (field_yield, which reads a measured input channel:
how is documented on the :class:`~liquidamp.device.effects_base.Effect` base).

The scalar laws (:func:`lugre_rate`, :func:`play_rate`,
:func:`compliance_rate`, :func:`cavity_rates`) are the compiled ones of
:mod:`liquidamp.device.kernels`, re-exported here; they can be called from
Python with floats.

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
.. [6] A. Gelb, W. E. Vander Velde, Multiple-Input Describing Functions and
   Nonlinear System Design, McGraw-Hill, 1968 (saturation and dead-zone
   describing functions: relief valve, end stops).
.. [7] C. Zener, Elasticity and Anelasticity of Metals, Univ. of Chicago
   Press, 1948 (standard linear solid: elastomer).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from liquidamp.device.effects_base import (
    Effect,
    piston_stroke_index,
)
from liquidamp.device.effects_damper import DigressiveValve, GasCharge
from liquidamp.device.effects_field import FieldYield
from liquidamp.device.effects_fluid import (
    AsymmetricLoss,
    Cavitation,
    Leakage,
    ReliefValve,
    saturation_damping,
)
from liquidamp.device.effects_force import (
    CoulombFriction,
    Elastomer,
    EndStops,
    ForceOffset,
    MovingMass,
    SlipWeakening,
    SmoothFriction,
)
from liquidamp.device.effects_kinematic import FloatingFreeplay, Freeplay, SeriesCompliance
from liquidamp.device.effects_operating import RotatingFrame
from liquidamp.device.effects_position import BypassGroove
from liquidamp.device.effects_thermal import SelfHeating
from liquidamp.device.kernels import (
    cavity_rates,
    cavity_width,
    compliance_rate,
    lugre_rate,
    play_rate,
)
from liquidamp.device.models import BASES, DeviceModel
from liquidamp.device.rotating import least_pressures
from liquidamp.errors import ParameterError, check_choice

__all__ = [
    "Effect",
    "CoulombFriction",
    "SmoothFriction",
    "SlipWeakening",
    "ForceOffset",
    "MovingMass",
    "SeriesCompliance",
    "Freeplay",
    "FloatingFreeplay",
    "Leakage",
    "Cavitation",
    "ReliefValve",
    "AsymmetricLoss",
    "BypassGroove",
    "Elastomer",
    "EndStops",
    "saturation_damping",
    "RotatingFrame",
    "GasCharge",
    "DigressiveValve",
    "FieldYield",
    "SelfHeating",
    "EFFECTS",
    "effect_names",
    "make_effect",
    "with_effects",
    "on_absolute_stroke",
    "chambers_on_absolute_stroke",
    "with_stroke_offset",
    "least_pressures",
    "lugre_rate",
    "play_rate",
    "compliance_rate",
    "cavity_rates",
    "cavity_width",
]



EFFECTS: dict[str, type[Effect]] = {
    cls.name: cls
    for cls in (CoulombFriction, SmoothFriction, ForceOffset, MovingMass, SeriesCompliance,
                Freeplay, Leakage, Cavitation, ReliefValve, AsymmetricLoss, Elastomer, EndStops,
                RotatingFrame, GasCharge, DigressiveValve, FieldYield,
                SelfHeating, BypassGroove, SlipWeakening, FloatingFreeplay)
}
"""Registry: effect name -> class."""


def effect_names() -> tuple[str, ...]:
    """Names of the catalogue effects.

    Examples
    --------
    >>> effect_names()
    ('coulomb_friction', 'smooth_friction', 'force_offset', 'moving_mass', \
'series_compliance', 'freeplay', 'leakage', 'cavitation', 'relief_valve', 'asymmetric_loss', \
'elastomer', 'end_stops', 'rotating_frame', 'gas_charge', 'digressive_valve', \
'field_yield', 'self_heating', 'bypass_groove', 'slip_weakening', 'floating_freeplay')
    """
    return tuple(EFFECTS)


def make_effect(name: str, **parameters) -> Effect:
    """Build the catalogue effect ``name`` with ``parameters`` (SI, keys as documented).

    Examples
    --------
    >>> make_effect("freeplay", gap_m=1e-4).parameters
    {'gap_m': 0.0001}
    >>> make_effect("coulomb_friction", force_N=30, location="piston").location
    'piston'
    >>> make_effect("coulomb_friction", location="seal")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: coulomb_friction location must be one of 'rod', \
'piston', got 'seal'
    >>> make_effect("coulomb_friction", force_N="30")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: coulomb_friction force_N must be a number (SI), got '30' \
(str)
    >>> make_effect("stiction")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown effect 'stiction'; valid: coulomb_friction, \
smooth_friction, force_offset, moving_mass, series_compliance, freeplay, leakage, cavitation, \
relief_valve, asymmetric_loss, elastomer, end_stops, rotating_frame, gas_charge, \
digressive_valve, field_yield, self_heating, bypass_groove, slip_weakening, floating_freeplay
    """
    check_choice("effect", name, EFFECTS)
    cls = EFFECTS[name]
    comp = cls.composition_keys()
    keys = list(cls.parameter_keys()) + list(comp)
    for key in parameters:
        check_choice(f"{name} parameter", key, keys)
    values = {}
    for k, v in parameters.items():
        if k in comp:
            if not isinstance(v, str):
                raise ParameterError(f"{name} {k} must be one of "
                                     f"{', '.join(map(repr, comp[k]))}, got {v!r}")
            values[k] = v
        else:
            if isinstance(v, (str, bytes, bool)):  # never converted silently
                raise ParameterError(f"{name} {k} must be a number (SI), got {v!r} "
                                     f"({type(v).__name__})")
            try:
                values[k] = float(v)
            except (TypeError, ValueError):
                raise ParameterError(f"{name} {k} must be a number (SI), got {v!r}") from None
    return cls(**values)


def _diagnostic(fn, n_base: int, ip):
    """A base model's vectorized ``pressures``/``mass`` on the composed state and stroke."""
    if fn is None:
        return None

    def composed(x, u, p):
        y = u[0] if ip is None else x[ip]
        return fn(x[:n_base], (y,) + tuple(u[1:]), p)

    return composed


def with_effects(model: DeviceModel, *effects: Effect) -> DeviceModel:
    """Return ``model`` with ``effects`` added: a new DeviceModel with the same interface.

    The effects are composed in the canonical order of the module docstring
    whatever order they are given in (with those ``model`` already holds);
    each name may appear once.  The result is data: its ``effects`` tuple
    and the compiled slots of :mod:`liquidamp.device.kernels` tell the
    engines and the analyses what it holds.

    Raises
    ------
    ParameterError
        A duplicate effect, something that is not an Effect, or an effect
        that does not apply to the model (e.g. one that needs chamber
        pressures on a model without them).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> m = with_effects(get_model("full"), Cavitation(2339.0), SmoothFriction(20.0))
    >>> m.name, m.state_names[5:]
    ('full+cavitation+smooth_friction', ('Vc1', 'Vc2', 'z_friction'))
    >>> [e.name for e in m.effects], m.base
    (['cavitation', 'smooth_friction'], 'full')
    >>> with_effects(get_model("single_state"), Leakage(1e-12))
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: effect 'leakage' needs a model with chamber pressure \
states p1, p2; model 'single_state' has states (dp); use 'full', 'no_inertia', \
'constant_bulk', 'volumetric' or 'inertial'
    """
    from liquidamp.device.models import get_model

    model = get_model(model)
    seen = {e.name for e in model.effects}
    for e in effects:
        if not isinstance(e, Effect):
            raise ParameterError(f"with_effects takes Effect objects, got {type(e).__name__}")
        if e.name in seen:
            raise ParameterError(f"effect {e.name!r} given twice")
        seen.add(e.name)
    if not effects:
        return model
    bare = BASES[model.base] if model.effects else model
    ordered = tuple(sorted(model.effects + tuple(effects), key=lambda e: e.order))
    for e in ordered:
        e.check(bare)
        e.check_with(ordered)
    nb = bare.n_states
    ip = piston_stroke_index(ordered, nb)
    base_x0, base_sc = bare.initial_state, bare.state_scales

    def initial_state(p, y0=0.0):
        xb = np.asarray(base_x0(p, y0), float)
        for e in ordered:
            xb = e.rest_base_state(bare, p, y0, xb)
        return np.concatenate([xb] + [e.initial_state(p, y0) for e in ordered])

    def state_scales(p):
        return np.concatenate([np.asarray(base_sc(p), float)]
                              + [e.state_scales(p) for e in ordered])

    return dataclasses.replace(
        bare,
        name="+".join((bare.name,) + tuple(e.name for e in ordered)),
        description=bare.description + "".join(f"; with {e}" for e in ordered),
        state_names=bare.state_names + sum((e.state_names for e in ordered), ()),
        state_units=bare.state_units + sum((e.state_units for e in ordered), ()),
        initial_state=initial_state,
        state_scales=state_scales,
        pressures=_diagnostic(bare.pressures, nb, ip),
        mass=_diagnostic(bare.mass, nb, ip),
        uses_acceleration=bare.uses_acceleration or any(e.uses_acceleration for e in ordered),
        effects=ordered,
    )


def with_stroke_offset(model: DeviceModel, offset_m: float) -> DeviceModel:
    """``model`` with its absolute-stroke effects placed at ``offset_m`` (the others as they are).

    An effect whose force depends on where the rod is (``absolute_stroke``:
    ``gas_charge``) sees y + ``stroke_offset_m``; a record's stroke drives the
    chambers about its mean, so its mean stroke is given back here
    (:func:`~liquidamp.analysis.measured.record_model.simulate_record` calls this with
    :attr:`Record.offset`).  A model without such an effect is returned unchanged.

    Parameters
    ----------
    model : DeviceModel
        Any composed model.
    offset_m : float
        Absolute stroke at the model's y = 0 [m].

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> m = with_effects(get_model("dashpot"), GasCharge(1e-4, 1e6, 1e-4))
    >>> with_stroke_offset(m, 0.01).effect("gas_charge").stroke_offset_m
    0.01
    >>> with_stroke_offset(get_model("full"), 0.01).name
    'full'
    """
    from liquidamp.device.models import get_model
    from liquidamp.errors import check_finite

    model = get_model(model)
    off = check_finite("stroke offset", offset_m, "m")
    if not any(getattr(e, "absolute_stroke", False) for e in model.effects):
        return model
    effects = tuple(e.replace(stroke_offset_m=off) if getattr(e, "absolute_stroke", False)
                    else e for e in model.effects)
    return with_effects(BASES[model.base], *effects)


def chambers_on_absolute_stroke(model: DeviceModel, effects=()) -> bool:
    """Whether ``model`` (with ``effects`` added) holds its chambers on the absolute
    stroke: a ``gas_charge`` on a model with chamber pressures (:func:`on_absolute_stroke`
    then moves V01, V02 and p0; a device without chambers keeps them).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> gas = GasCharge(4.5e-5, 6.894757e5, 2.4e-6, 1.25)
    >>> chambers_on_absolute_stroke(get_model("full"), (gas,))
    True
    >>> chambers_on_absolute_stroke(get_model("dashpot"), (gas,))
    False
    """
    return model.pressures is not None and any(
        e.name == "gas_charge" for e in (*model.effects, *effects))


def on_absolute_stroke(model, params, offset_m: float):
    """The model and device a record read about ``offset_m`` runs on: absolute stroke kept.

    A record's stroke drives a model about its mean (the LVDT zero of a centred record is
    arbitrary).  A model with an effect on the absolute stroke (``gas_charge``) declares
    the record's zero the stroke datum, so everything that depends on where the rod is
    follows it:

    * the effect sees y + ``offset_m`` (:func:`with_stroke_offset`);
    * a gas-charged device's chambers hold V01 and V02 at the datum, so about the
      record's mean they hold V01 - A_p offset and V02 + A_p offset (the chamber end
      V0 / A_p is then reached ``|offset|`` sooner);
    * a gas-charged damper's liquid sits at its gas pressure (the accumulator sets the
      pressure level of a monotube or twin-tube damper: Dixon, Sec. 5.9): the chambers
      are filled at p0 = p_c + p_a, the charge's absolute pressure at the datum, and the
      air ratios 1/gamma are those at that level.

    With the level set by the filling, a cavity switch beside the charge would count the
    charge twice (the compiled law adds p_g(y) to the states for it), so a cavitation
    effect is refused here naming why.  A model without an absolute-stroke effect, or one
    without chambers (``dashpot``, ``viscous``), keeps ``params`` as given.

    Parameters
    ----------
    model : DeviceModel
        Any composed model.
    params : DeviceParams
        The device, V01 and V02 at the stroke datum.
    offset_m : float
        The record's mean stroke [m] (:attr:`Record.offset`).

    Returns
    -------
    (DeviceModel, DeviceParams)

    Raises
    ------
    ParameterError
        If the model holds ``cavitation`` beside a gas charge on chambers, or the
        offset empties a chamber (|offset| >= V0 / A_p).

    References
    ----------
    .. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Sec. 5.9.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.effects import with_effects
    >>> from liquidamp.device.models import get_model
    >>> m = with_effects(get_model("full"), GasCharge(4.5e-5, 6.894757e5, 2.4e-6, 1.25))
    >>> p = preset("reference").replace(V01=6e-5, V02=6e-5)
    >>> m2, p2 = on_absolute_stroke(m, p, -0.031)
    >>> m2.effect("gas_charge").stroke_offset_m, round(p2.p0), round(p2.V01 * 1e6, 3)
    (-0.031, 790801, 81.426)
    """
    model = with_stroke_offset(model, offset_m)
    if not chambers_on_absolute_stroke(model):
        return model, params
    gas = [e for e in model.effects if e.name == "gas_charge"]
    if any(e.name == "cavitation" for e in model.effects):
        raise ParameterError(
            "a record on the absolute stroke fills a gas-charged device at its charge "
            "pressure; 'cavitation' beside 'gas_charge' would count the charge twice "
            "(fit one or the other)")
    g, off, A = gas[0], float(offset_m), params.A_p
    V1, V2 = params.V01 - A * off, params.V02 + A * off
    if min(V1, V2) <= 0.0:
        raise ParameterError(
            f"record mean stroke {off:.4g} m empties a chamber of the gas-charged device "
            f"(V01 {params.V01:.4g} m^3, V02 {params.V02:.4g} m^3 at the datum, A_p "
            f"{A:.4g} m^2): |offset| must be < {min(params.V01, params.V02) / A:.4g} m")
    return model, params.replace(V01=V1, V02=V2,
                                 p0=g.charge_pressure_Pa + g.ambient_pressure_Pa)
