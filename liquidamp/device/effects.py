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
``leakage``             coefficient_m3_per_s_Pa                none: bypass mass flow
``cavitation``          vapour_pressure_Pa                     Vc1, Vc2 [m^3] (vapour cavities)

Composition order is canonical whatever order the effects are given in:
fluid effects (leakage, the rotating frame, then cavitation) act on the chamber
equations innermost (cavitation sees the rotating frame's lowered inboard
pressures); the kinematic effects (series compliance, then freeplay) turn the
measured rod stroke into the piston stroke the fluid sees; the force effects
(friction, mass, offset) act on the measured (rod) stroke and add to the
load-cell force outermost.  Force effects therefore use the rod velocity and
acceleration, which is exact without a kinematic effect and a first-order
approximation with one.
``rotating_frame``      rotor_speed_rad_per_s,                 none: centrifugal pressure rise
                        mounting_radius_m, axis_angle_rad      dp_c on every flow path and the
                                                               force; rest state on the rotor
=======
``relief_valve``        cracking_pressure_Pa,                  none: second path beside the
                        conductance_m3_per_s_Pa                channel above p_r (dashpot types:
                                                               exact force saturation)
``asymmetric_loss``     rebound_ratio                          none: loss coefficients x r in
                                                               rebound
``elastomer``           parallel_stiffness_N_per_m,            F_elastomer [N] (k0 parallel to
                        branch_stiffness_N_per_m,              k1 in series with c1: standard
                        branch_damping_N_s_per_m               linear solid on the rod)
``end_stops``           stiffness_N_per_m, clearance_m,        none: contact beyond centre +/-
                        damping_N_s_per_m, centre_m            clearance (C1 onset)
======================  =====================================  =================================

Composition order is canonical whatever order the effects are given in
(``order``, innermost first): the fluid effects act on the chamber equations
innermost (asymmetric_loss 3 on the channel's coefficients, leakage 5 and
relief_valve 7 as paths beside the channel, rotating_frame 8 driving every
flow path, cavitation 10 on the pressure rates, so that it sees the rotating
frame's lowered inboard pressures); the kinematic effects (series_compliance
20, then freeplay 30) turn the measured rod stroke into the piston stroke the fluid sees; the force
effects (smooth_friction 35, coulomb_friction 40, elastomer 42, moving_mass
45, end_stops 47, force_offset 50) act on the measured (rod) stroke and add
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
band -> friction element).  It is part of the model, not a fitted parameter:
:attr:`Effect.parameters` (and so fits, bounds and fit keys) holds the
numbers only, :meth:`Effect.as_dict` both (device files, JSON, synthetic
recipes), and ``str(effect)``, :func:`make_effect`, device files and the
command line's ``--effect coulomb_friction:force_N=100,location=piston``
accept it.  A diagnosis that wants "freeplay in series with the existing
friction" composes ``Freeplay(g)`` with the friction it already has
re-placed: ``friction.replace(location="piston")``.

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
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.kernels import (
    cavity_rates,
    cavity_width,
    compliance_rate,
    lugre_rate,
    play_rate,
)
from liquidamp.device.models import BASES, DeviceModel
from liquidamp.device.rotating import ROTATING_BASES, heads, least_pressures, rest_state
from liquidamp.errors import (
    ParameterError,
    check_choice,
    check_finite,
    check_nonnegative,
    check_positive,
)

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
    "ReliefValve",
    "AsymmetricLoss",
    "Elastomer",
    "EndStops",
    "saturation_damping",
    "RotatingFrame",
    "EFFECTS",
    "effect_names",
    "make_effect",
    "with_effects",
    "least_pressures",
    "lugre_rate",
    "play_rate",
    "compliance_rate",
    "cavity_rates",
    "cavity_width",
]


# ---------------------------------------------------------------------------
# effect classes

#: Field metadata key of a composition field (a choice of where the effect sits; not a
#: fitted parameter): the allowed values.
_COMPOSITION = "composition"

#: Where a friction effect sits: on the rod (the measured stroke), or at the piston
#: behind the kinematic effects (in series with a dead band, like the fluid).
LOCATIONS = ("rod", "piston")


def _location_field():
    return dataclasses.field(default="rod", metadata={_COMPOSITION: LOCATIONS})


#: Allowed reverse-to-forward level ratio of a direction-dependent friction [-].
REVERSE_RATIO_BOUNDS = (0.1, 10.0)


def _check_reverse_ratio(effect) -> None:
    q = check_finite(f"{effect.name} reverse_ratio", effect.reverse_ratio, "-")
    lo, hi = REVERSE_RATIO_BOUNDS
    if not lo <= q <= hi:
        raise ParameterError(f"{effect.name} reverse_ratio must be in [{lo:g}, {hi:g}] [-] "
                             f"(reverse-to-forward friction level), got {q:g}")


def _check_location(effect, effects) -> None:
    if effect.location != "piston":
        return
    if any(e.name == "series_compliance" for e in effects):
        raise ParameterError(
            f"effect {effect.name!r} at location 'piston' cannot sit behind "
            "series_compliance: a massless piston between a spring and dry friction is a "
            "stick-slip element without a rate while it sticks; put the friction at "
            "location 'rod' or drop series_compliance")


@dataclass(frozen=True)
class Effect:
    """Base class of the add-on effects.

    Class attributes (metadata): ``name`` (registry key), ``units``
    (parameter key -> unit), ``fit_keys`` (parameters a calibration varies by
    default), ``bounds`` (key -> (low, high) for fitting), ``needs_pressures``
    (only for models with chamber pressure states), ``order`` (canonical
    composition rank), ``state_names`` / ``state_units`` (states the effect
    appends), ``slot`` (where the compiled composition records it:
    a ``liquidamp.device.kernels.S_*`` index), ``kind`` (``"force"``: adds
    to the load-cell force only, driven by the measured stroke;
    ``"kinematic"``: sits between the measured stroke and the piston;
    ``"fluid"``: acts on the chamber equations).
    """

    name: ClassVar[str] = ""
    units: ClassVar[dict] = {}
    fit_keys: ClassVar[tuple] = ()
    bounds: ClassVar[dict] = {}
    needs_pressures: ClassVar[bool] = False
    order: ClassVar[int] = 0
    description: ClassVar[str] = ""
    state_names: ClassVar[tuple] = ()
    state_units: ClassVar[tuple] = ()
    slot: ClassVar[int] = -1
    kind: ClassVar[str] = "force"
    uses_acceleration: ClassVar[bool] = False
    #: True where the effect's force is linear (affine) in the stroke: its describing
    #: function is then its exact element at any amplitude, also at rest.
    linear: ClassVar[bool] = False
    #: True where a diagnosis screens the effect when no candidates are named; the
    #: others are candidates on request (``diagnose(..., candidates=...)``).
    screened: ClassVar[bool] = True

    @classmethod
    def parameter_keys(cls) -> tuple[str, ...]:
        """Keys of the numeric (fittable) parameters, SI.

        Examples
        --------
        >>> CoulombFriction.parameter_keys(), CoulombFriction.composition_keys()
        (('force_N', 'reverse_ratio'), {'location': ('rod', 'piston')})
        """
        return tuple(f.name for f in dataclasses.fields(cls) if _COMPOSITION not in f.metadata)

    @classmethod
    def composition_keys(cls) -> dict[str, tuple[str, ...]]:
        """Composition fields (key -> allowed values): where the effect sits, never fitted."""
        return {f.name: f.metadata[_COMPOSITION] for f in dataclasses.fields(cls)
                if _COMPOSITION in f.metadata}

    @property
    def parameters(self) -> dict[str, float]:
        """Numeric parameter values by key (SI): what a fit may vary."""
        return {k: getattr(self, k) for k in self.parameter_keys()}

    @property
    def composition(self) -> dict[str, str]:
        """Composition choices by key (e.g. ``location``): part of the model, not fitted."""
        return {k: getattr(self, k) for k in self.composition_keys()}

    def as_dict(self) -> dict:
        """Parameters and composition choices: what rebuilds the effect (device files, JSON).

        Examples
        --------
        >>> e = make_effect("coulomb_friction", force_N=100.0, location="piston")
        >>> e.as_dict()
        {'force_N': 100.0, 'reverse_ratio': 1.0, 'location': 'piston'}
        >>> str(e)
        'coulomb_friction(force_N=100, reverse_ratio=1, location=piston)'
        >>> make_effect(**{"name": "coulomb_friction", **e.as_dict()}) == e
        True
        """
        return {**self.parameters, **self.composition}

    def replace(self, **changes) -> Effect:
        """Validated copy with ``changes`` applied; unknown keys raise ParameterError."""
        for key in changes:
            check_choice(f"{self.name} parameter", key, self.as_dict())
        return dataclasses.replace(self, **changes)

    def _check_composition(self) -> None:
        for key, allowed in self.composition_keys().items():
            value = getattr(self, key)
            if value not in allowed:
                raise ParameterError(f"{self.name} {key} must be one of "
                                     f"{', '.join(map(repr, allowed))}, got {value!r}")

    @classmethod
    def probe(cls, force_amplitude_N: float, amplitude_m: float, omega: float, params
              ) -> Effect:
        """The effect at a small probe strength for a record (the diagnosis's score test).

        Parameters
        ----------
        force_amplitude_N : float
            Amplitude of the measured force [N].
        amplitude_m, omega : float
            Stroke amplitude [m] and angular frequency [rad/s] of the records.
        params : DeviceParams or ViscousParams
            The calibrated parameters.

        Raises
        ------
        ParameterError
            For an effect that states no probe.
        """
        raise ParameterError(f"no probe for effect {cls.name!r}")

    def spec_flags(self) -> dict[int, int]:
        """Extra composition slots (``kernels.S_*`` -> value) beyond :attr:`slot`."""
        return {}

    def check_with(self, effects: tuple) -> None:
        """Raise ParameterError if the effect cannot be composed with the other ``effects``."""

    def pack(self, ep: np.ndarray) -> None:  # pragma: no cover - abstract
        """Write the parameters into their slots of the compiled effect vector ``ep``."""
        raise NotImplementedError

    def check(self, model: DeviceModel) -> None:
        """Raise ParameterError if the effect cannot be composed with ``model``."""
        if self.needs_pressures and "p1" not in model.state_names[:model.n_base_states]:
            raise ParameterError(
                f"effect {self.name!r} needs a model with chamber pressure states p1, p2; "
                f"model {model.name!r} has states ({', '.join(model.state_names) or 'none'}); "
                "use 'full', 'no_inertia', 'constant_bulk', 'volumetric' or 'inertial'")

    #: Why the effect has no small-signal model at rest (None: the linearization of the
    #: composed equations at rest holds it exactly).
    small_signal_reason: ClassVar[str | None] = None
    #: Why the effect has no describing function in parallel with the fluid (None: it has).
    describing_reason: ClassVar[str | None] = (
        "it changes the fluid equations, so its first harmonic is not a force in parallel "
        "with the fluid's")

    def check_small_signal(self, params) -> None:
        """Raise ParameterError if the linearization at rest cannot represent the effect."""
        if self.small_signal_reason is not None:
            raise ParameterError(
                f"effect {self.name!r} has no small-signal model at rest: "
                f"{self.small_signal_reason}; give an amplitude and a frequency for an "
                "equivalent linearization, or use the time domain")

    def describing_function(self, amplitude_m: float, omega: float, params, model=None
                            ) -> tuple[float, float, float]:
        """Equivalent parallel element of the effect at y = Y sin(w t) (first harmonic).

        Parameters
        ----------
        amplitude_m : float
            Stroke amplitude Y > 0 [m].
        omega : float
            Angular frequency w > 0 [rad/s].
        params : DeviceParams or ViscousParams
            Device parameters.
        model : DeviceModel, optional
            The composed model (effects whose first harmonic depends on the
            base equation need it).

        Returns
        -------
        (k, c, b) : tuple of float
            Stiffness [N/m], damping [N s/m] and inertance [kg] in parallel
            with the fluid force whose first harmonic equals the effect's:
            its dynamic stiffness is k + i w c - w^2 b.

        Raises
        ------
        ParameterError
            Where the effect does not act as a force in parallel (naming why).
        """
        raise ParameterError(
            f"effect {self.name!r} has no equivalent linearization in parallel with the "
            f"fluid: {self.describing_reason}; use the time domain "
            "(liquidamp.analysis.response.stiffness.nonlinear_stiffness)")

    def initial_state(self, params, y0: float) -> np.ndarray:
        """Initial values of the effect's states at rest with rod stroke ``y0`` [m]."""
        return np.zeros(len(self.state_names))

    def rest_base_state(self, model: DeviceModel, params, y0: float,
                        x_base: np.ndarray) -> np.ndarray:
        """The base model's states at rest with the effect (default: ``x_base`` unchanged).

        ``model`` is the bare base model, ``x_base`` its rest state at rod
        stroke ``y0`` [m] as the effects before this one left it.
        """
        return x_base

    def state_scales(self, params) -> np.ndarray:
        """Magnitudes of the effect's states (tolerances, difference increments)."""
        return np.ones(len(self.state_names))

    def __str__(self) -> str:
        pars = [f"{k}={v:.4g}" for k, v in self.parameters.items()]
        pars += [f"{k}={v}" for k, v in self.composition.items()]
        return f"{self.name}({', '.join(pars)})"


@dataclass(frozen=True)
class CoulombFriction(Effect):
    """Coulomb seal friction F += F_c sign(v) (the paper's |F_f|, Sec. IV.C).

    At ``location="piston"`` the friction element sits behind the kinematic
    effects, in series with a dead band (``freeplay``) like the fluid: the
    kinematic chain rod -> dead band -> friction element of a friction
    damper with backlash.  The contact is massless: inside the gap no force
    is transmitted and the element stays put; in contact it moves with the
    rod and transmits F_c sign(v), so F = F_c sign(v) C with C the dead
    band's C1 contact factor (:func:`~liquidamp.device.kernels.play_contact`,
    0 in the gap, 1 in contact).  Under y = A sin(w t) with A > g the loop
    is flat while the rod crosses the gap 2g after each reversal and the
    energy dissipated per cycle is 2 F_c (2A - 2g).  Without freeplay the
    piston moves with the rod and both locations agree.  Not behind
    ``series_compliance`` (a stick-slip element: ParameterError).

    A band or seal that grips harder one way slides at F_c forward (v > 0)
    and q F_c in reverse (``reverse_ratio`` q,
    :func:`~liquidamp.device.kernels.friction_level`): the loop's levels
    +F_c / -q F_c, whose mean (1 - q) F_c / 2 acts only while sliding, not
    inside a dead band as a ``force_offset`` would.

    Parameters
    ----------
    force_N : float
        Friction force level F_c >= 0 [N] (paper: 30 N), forward (v > 0).
    reverse_ratio : float
        Reverse-to-forward level ratio q in [0.1, 10] [-] (1: symmetric).
    location : {"rod", "piston"}
        Where the friction sits (a composition choice, not fitted).

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
    reverse_ratio: float = 1.0
    location: str = _location_field()
    name: ClassVar[str] = "coulomb_friction"
    units: ClassVar[dict] = {"force_N": "N", "reverse_ratio": "-"}
    fit_keys: ClassVar[tuple] = ("force_N",)
    bounds: ClassVar[dict] = {"force_N": (1e-2, 1e4), "reverse_ratio": REVERSE_RATIO_BOUNDS}
    order: ClassVar[int] = 40
    description: ClassVar[str] = "Coulomb seal friction F_c sign(v)"
    slot: ClassVar[int] = K.S_COUL

    def __post_init__(self):
        check_nonnegative("coulomb_friction force_N", self.force_N, "N")
        _check_reverse_ratio(self)
        self._check_composition()

    def spec_flags(self):
        return {K.S_CPIST: int(self.location == "piston")}

    def check_with(self, effects):
        _check_location(self, effects)

    small_signal_reason: ClassVar[str | None] = (
        "Coulomb friction sticks at rest (infinite slope of sign(v))")
    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_CF], ep[K.E_CRQ] = self.force_N, self.reverse_ratio

    def describing_function(self, amplitude_m, omega, params, model=None):
        """Equivalent damping 2 (1 + q) F_c / (pi w Y) [N s/m] (no stiffness, no inertance).

        The first harmonic of the square wave +F_c / -q F_c; its mean
        (1 - q) F_c / 2 is not part of a describing function.

        Examples
        --------
        >>> k, c, b = CoulombFriction(30.0).describing_function(1e-3, 2 * math.pi, None)
        >>> round(c * 2 * math.pi * 1e-3 * math.pi / 4, 12)   # = F_c
        30.0
        >>> k, c2, b = CoulombFriction(30.0, 0.5).describing_function(1e-3, 2 * math.pi, None)
        >>> round(c2 / c, 12)   # (1 + q) / 2
        0.75
        """
        Y, w = _check_harmonic(amplitude_m, omega)
        return 0.0, 2.0 * (1.0 + self.reverse_ratio) * self.force_N / (math.pi * w * Y), 0.0


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
    units: ClassVar[dict] = {"offset_N": "N"}
    fit_keys: ClassVar[tuple] = ("offset_N",)
    bounds: ClassVar[dict] = {"offset_N": (-1e4, 1e4)}
    order: ClassVar[int] = 50
    description: ClassVar[str] = "constant load-cell bias"
    slot: ClassVar[int] = K.S_OFF
    linear: ClassVar[bool] = True

    def __post_init__(self):
        check_finite("force_offset offset_N", self.offset_N, "N")

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_OFF] = self.offset_N

    def describing_function(self, amplitude_m, omega, params, model=None):
        """A constant force has no first harmonic: (0, 0, 0)."""
        _check_harmonic(amplitude_m, omega)
        return 0.0, 0.0, 0.0


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
    units: ClassVar[dict] = {"mass_kg": "kg"}
    fit_keys: ClassVar[tuple] = ("mass_kg",)
    bounds: ClassVar[dict] = {"mass_kg": (1e-3, 1e3)}
    order: ClassVar[int] = 45
    description: ClassVar[str] = "piston and rod inertia m a"
    slot: ClassVar[int] = K.S_MASS
    uses_acceleration: ClassVar[bool] = True
    linear: ClassVar[bool] = True

    def __post_init__(self):
        check_nonnegative("moving_mass mass_kg", self.mass_kg, "kg")

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_MASS] = self.mass_kg

    def describing_function(self, amplitude_m, omega, params, model=None):
        """An inertance m [kg] in parallel (exact: F = m a is linear)."""
        _check_harmonic(amplitude_m, omega)
        return 0.0, 0.0, self.mass_kg


@dataclass(frozen=True)
class SmoothFriction(Effect):
    """Seal friction with pre-sliding and Stribeck behaviour (LuGre without bristle damping).

    F += F_c z with dz/dt = (sigma0 / F_c)(v - |v| z / g(v)),
    g(v) = 1 + (r - 1) exp(-(v / v_s)^2) (:func:`lugre_rate`).  Around each
    reversal the force changes gradually over a pre-sliding stroke of about
    F_c / sigma0 (the gradual transitions of Figs. 5-6 and the pre-slide
    stage of Fig. 4); with r > 1 the sliding force falls from r F_c to F_c
    as |v| passes v_s (the Stribeck region of Fig. 4).  sigma0 -> infinity
    with r = 1 is Coulomb friction.  Extra state ``z_friction`` [-],
    starting at 0, driven by the measured rod velocity.

    At ``location="piston"`` the seal sits behind a dead band (``freeplay``):
    the bristles are driven by the piston velocity (the dead band's output
    rate) and the load cell reads the bristle force F_c z, which the
    massless piston can only pass through the contact.  Derived rather than
    scaled: when the rod backs off, the loaded bristles keep the piston
    pressed against it (its elastic spring-back, a stroke of at most about
    F_c / sigma0) until their force has gone, and only then does the gap
    open (:func:`~liquidamp.device.kernels.piston_contact`); inside the gap
    the piston and its bristles stay put, unloaded (the force there is below
    about 1 % of F_c, the regularisation ``Z_HOLD``).  The freeplay state
    ``y_fp`` is the piston position including that spring-back.  Not behind
    ``series_compliance`` (ParameterError).

    The transition exponent n (Bouc-Wen's) shapes the pre-sliding: n = 1
    is the exponential approach above; a large n keeps the bristle stiff
    (slope sigma0) up to the sliding level and then slips sharply, the
    elastic-plastic (Jenkins) element of a clamped band.

    Direction-dependent level (``reverse_ratio`` q): F = F_c z for z >= 0
    and q F_c z for z < 0 (:func:`~liquidamp.device.kernels.friction_level`),
    sliding at +r F_c ... F_c forward and -q F_c in reverse, and zero where
    the bristles are unloaded (inside a dead band).

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
    reverse_ratio : float
        Reverse-to-forward level ratio q in [0.1, 10] [-] (1: symmetric).
    transition_exponent : float
        Pre-sliding transition exponent n in [1, 20] [-] (1: LuGre/Dahl).
    location : {"rod", "piston"}
        Where the seal sits (a composition choice, not fitted).
    """

    force_N: float = 0.0
    stiffness_N_per_m: float = 1.0e5
    stribeck_velocity_m_per_s: float = 0.005
    static_ratio: float = 1.0
    reverse_ratio: float = 1.0
    transition_exponent: float = 1.0
    location: str = _location_field()
    name: ClassVar[str] = "smooth_friction"
    units: ClassVar[dict] = {"force_N": "N", "stiffness_N_per_m": "N/m",
                             "stribeck_velocity_m_per_s": "m/s", "static_ratio": "-",
                             "reverse_ratio": "-", "transition_exponent": "-"}
    fit_keys: ClassVar[tuple] = ("force_N", "stiffness_N_per_m")
    bounds: ClassVar[dict] = {"force_N": (1e-2, 1e4), "stiffness_N_per_m": (1e2, 1e9),
                              "stribeck_velocity_m_per_s": (1e-5, 1.0),
                              "static_ratio": (1.0, 5.0), "reverse_ratio": REVERSE_RATIO_BOUNDS,
                              "transition_exponent": (1.0, 20.0)}
    order: ClassVar[int] = 35
    description: ClassVar[str] = "LuGre/Dahl friction: gradual reversal, Stribeck"
    state_names: ClassVar[tuple] = ("z_friction",)
    state_units: ClassVar[tuple] = ("-",)
    slot: ClassVar[int] = K.S_IZ

    def __post_init__(self):
        check_nonnegative("smooth_friction force_N", self.force_N, "N")
        for key, unit in (("stiffness_N_per_m", "N/m"), ("stribeck_velocity_m_per_s", "m/s")):
            v = check_finite(f"smooth_friction {key}", getattr(self, key), unit)
            if not v > 0:
                raise ParameterError(f"smooth_friction {key} must be > 0 [{unit}], got {v:g}")
        r = check_finite("smooth_friction static_ratio", self.static_ratio, "-")
        if r < 1.0:
            raise ParameterError(f"smooth_friction static_ratio must be >= 1 [-], got {r:g}")
        _check_reverse_ratio(self)
        n = check_finite("smooth_friction transition_exponent", self.transition_exponent, "-")
        if not 1.0 <= n <= 20.0:
            raise ParameterError("smooth_friction transition_exponent must be in [1, 20] [-] "
                                 f"(1: LuGre/Dahl, large: elastic-plastic), got {n:g}")
        self._check_composition()

    def spec_flags(self):
        return {K.S_ZPIST: int(self.location == "piston")}

    def check_with(self, effects):
        _check_location(self, effects)

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_SFC], ep[K.E_SIG] = self.force_N, self.stiffness_N_per_m
        ep[K.E_VS], ep[K.E_SR] = self.stribeck_velocity_m_per_s, self.static_ratio
        ep[K.E_FRQ], ep[K.E_FEX] = self.reverse_ratio, self.transition_exponent

    def describing_function(self, amplitude_m, omega, params, model=None):
        """Equivalent (k, c, 0) from the first harmonic of F_c z on its periodic orbit.

        The bristle state is driven by the stroke alone, so its describing
        function is exact: z is integrated (Radau, rtol 1e-10) over cycles
        of y = Y sin(w t) until one period repeats to 1e-9, and
        k + i w c = F1 / Y.  Large amplitudes tend to Coulomb's
        (0, 4 F_c / (pi w Y)); small ones to the bristle spring (sigma0, 0).

        Examples
        --------
        >>> f = SmoothFriction(30.0, 1e7)
        >>> k, c, b = f.describing_function(1e-3, 2 * math.pi, None)
        >>> c_coulomb = CoulombFriction(30.0).describing_function(1e-3, 2 * math.pi, None)[1]
        >>> bool(abs(c / c_coulomb - 1) < 0.01), bool(0 < k < 0.05 * 1e7)
        (True, True)
        """
        from scipy.integrate import solve_ivp

        Y, w = _check_harmonic(amplitude_m, omega)
        if self.force_N == 0.0:
            return 0.0, 0.0, 0.0
        args = (self.force_N, self.stiffness_N_per_m, self.stribeck_velocity_m_per_s,
                self.static_ratio, self.transition_exponent)
        T = 2.0 * math.pi / w
        N = 512
        z0 = 0.0
        for _ in range(50):
            sol = solve_ivp(lambda t, z: [lugre_rate(Y * w * math.cos(w * t), z[0], *args)],
                            (0.0, T), [z0], method="Radau", rtol=1e-10, atol=1e-12,
                            t_eval=np.arange(N + 1) * (T / N), max_step=T / 64)
            z = sol.y[0]
            if abs(z[-1] - z0) < 1e-9:
                break
            z0 = z[-1]
        level = np.where(z[:N] >= 0.0, z[:N], self.reverse_ratio * z[:N])
        F1 = 2.0 / N * np.sum(self.force_N * level * np.exp(-1j * w * sol.t[:N]))
        K = 1j * F1 / Y  # y = Y sin(w t) = Im(Y e^{iwt}): K = F1 / (-i Y)
        return float(K.real), float(K.imag / w), 0.0


@dataclass(frozen=True)
class Elastomer(Effect):
    """Elastomer branch in parallel on the rod: the standard linear solid.

    A spring k0 in parallel with a spring k1 in series with a dashpot c1
    (a Zener / standard linear solid, e.g. an elastomeric lead-lag element
    beside the fluid device), acting on the measured rod stroke:
    F += k0 y + F_e, dF_e/dt = k1 v - F_e / tau, tau = c1 / k1
    (:func:`~liquidamp.device.kernels.elastomer_rate`).  One state
    ``F_elastomer`` [N], 0 at rest.  Linear, so its small-signal model and
    its describing function are exact and equal:

    K(i w) = k0 + k1 i w tau / (1 + i w tau).

    Parameters
    ----------
    parallel_stiffness_N_per_m : float
        k0 >= 0 [N/m].
    branch_stiffness_N_per_m : float
        k1 >= 0 [N/m].
    branch_damping_N_s_per_m : float
        c1 > 0 [N s/m].

    References
    ----------
    .. [1] C. Zener, Elasticity and Anelasticity of Metals, Univ. of Chicago
       Press, 1948 (the standard linear solid).
    .. [2] D. L. Kunz, "Nonlinear analysis of helicopter ground resonance",
       Nonlinear Dyn. 2002 (elastomeric lag dampers).

    Examples
    --------
    >>> e = Elastomer(1e5, 4e5, 4e5 / (2 * math.pi * 3.0))   # w tau = 1 at 3 Hz
    >>> k, c, b = e.describing_function(1e-3, 2 * math.pi * 3.0, None)
    >>> round(k), round(c * 2 * math.pi * 3.0)               # k0 + k1/2, k1/2
    (300000, 200000)
    """

    parallel_stiffness_N_per_m: float = 0.0
    branch_stiffness_N_per_m: float = 0.0
    branch_damping_N_s_per_m: float = 1.0
    name: ClassVar[str] = "elastomer"
    units: ClassVar[dict] = {"parallel_stiffness_N_per_m": "N/m",
                             "branch_stiffness_N_per_m": "N/m",
                             "branch_damping_N_s_per_m": "N s/m"}
    fit_keys: ClassVar[tuple] = ("branch_stiffness_N_per_m", "branch_damping_N_s_per_m",
                                 "parallel_stiffness_N_per_m")
    bounds: ClassVar[dict] = {"parallel_stiffness_N_per_m": (1.0, 1e9),
                              "branch_stiffness_N_per_m": (1.0, 1e9),
                              "branch_damping_N_s_per_m": (1e-2, 1e8)}
    order: ClassVar[int] = 42
    description: ClassVar[str] = "parallel elastomer (standard linear solid) on the rod"
    state_names: ClassVar[tuple] = ("F_elastomer",)
    state_units: ClassVar[tuple] = ("N",)
    slot: ClassVar[int] = K.S_IEL
    linear: ClassVar[bool] = True
    screened: ClassVar[bool] = False  # a candidate on request (see the module notes)

    def __post_init__(self):
        check_nonnegative("elastomer parallel_stiffness_N_per_m",
                          self.parallel_stiffness_N_per_m, "N/m")
        check_nonnegative("elastomer branch_stiffness_N_per_m",
                          self.branch_stiffness_N_per_m, "N/m")
        check_positive("elastomer branch_damping_N_s_per_m", self.branch_damping_N_s_per_m,
                       "N s/m")

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_K0] = self.parallel_stiffness_N_per_m
        ep[K.E_K1] = self.branch_stiffness_N_per_m
        ep[K.E_C1E] = self.branch_damping_N_s_per_m

    def state_scales(self, params):
        return np.array([max(self.branch_stiffness_N_per_m * 1e-4, 1.0)])

    def stiffness(self, omega: float) -> complex:
        """K(i w) = k0 + k1 i w tau / (1 + i w tau) [N/m] at w [rad/s]."""
        k1, c1 = self.branch_stiffness_N_per_m, self.branch_damping_N_s_per_m
        iwc = 1j * float(omega) * c1
        branch = 0j if k1 == 0.0 else k1 * iwc / (k1 + iwc)
        return self.parallel_stiffness_N_per_m + branch

    def describing_function(self, amplitude_m, omega, params, model=None):
        """Exact (linear): (Re K, Im K / w, 0)."""
        _, w = _check_harmonic(amplitude_m, omega)
        K_ = self.stiffness(w)
        return float(K_.real), float(K_.imag / w), 0.0

    @classmethod
    def probe(cls, force_amplitude_N, amplitude_m, omega, params):
        """A branch of 5 % of the record's force amplitude at w tau = 1, k0 = k1 / 2."""
        k1 = 0.05 * force_amplitude_N / amplitude_m
        return cls(0.5 * k1, k1, k1 / omega)


def _contact_fraction(rho: float) -> float:
    """First-harmonic share of one one-sided stop with threshold rho = a / Y [-]."""
    if rho >= 1.0:
        return 0.0
    if rho <= -1.0:
        return 1.0
    return (0.5 * math.pi - math.asin(rho) - rho * math.sqrt(1.0 - rho * rho)) / math.pi


@dataclass(frozen=True)
class EndStops(Effect):
    """Stiff end stops: contact when the rod stroke leaves centre +/- clearance.

    F += sign(u) (k (|u| - clearance) + c v) beyond the clearance,
    u = y - centre, nothing inside; the onset is C1 over a width
    w = 0.01 clearance + 1e-7 m (:func:`~liquidamp.device.kernels.stop_force`:
    the elastic force is exact beyond it).  The elastic part is a force of
    the stroke alone, so it does no net work over a cycle; the damping is
    Kelvin-Voigt.  Describing function (exact up to the onset width): with
    rho_+ = (clearance + centre) / Y, rho_- = (clearance - centre) / Y and
    n(rho) = (pi/2 - arcsin rho - rho sqrt(1 - rho^2)) / pi per stop
    (0 for rho >= 1, 1 for rho <= -1), (k, c) = (k_s, c_s) (n(rho_+) + n(rho_-));
    a centre off zero also gives a mean force, which has no first harmonic.

    Parameters
    ----------
    stiffness_N_per_m : float
        Contact stiffness k >= 0 [N/m].
    clearance_m : float
        Free stroke on either side of the centre >= 0 [m].
    damping_N_s_per_m : float
        Contact damping c >= 0 [N s/m].
    centre_m : float
        Stroke at the middle of the free travel [m].

    References
    ----------
    .. [1] A. Gelb, W. E. Vander Velde, Multiple-Input Describing Functions
       and Nonlinear System Design, McGraw-Hill, 1968 (dead zone).

    Examples
    --------
    >>> k, c, b = EndStops(1e6, 1e-3).describing_function(2e-3, 10.0, None)
    >>> round(k / 1e6, 6)          # 1 - (2/pi)(pi/6 + sqrt(3)/4)
    0.391002
    """

    stiffness_N_per_m: float = 0.0
    clearance_m: float = 1.0e-2
    damping_N_s_per_m: float = 0.0
    centre_m: float = 0.0
    name: ClassVar[str] = "end_stops"
    units: ClassVar[dict] = {"stiffness_N_per_m": "N/m", "clearance_m": "m",
                             "damping_N_s_per_m": "N s/m", "centre_m": "m"}
    fit_keys: ClassVar[tuple] = ("stiffness_N_per_m", "clearance_m")
    bounds: ClassVar[dict] = {"stiffness_N_per_m": (1e2, 1e10), "clearance_m": (1e-6, 1e-1),
                              "damping_N_s_per_m": (1e-1, 1e6), "centre_m": (-1e-1, 1e-1)}
    order: ClassVar[int] = 47
    description: ClassVar[str] = "stiff contact beyond a clearance"
    slot: ClassVar[int] = K.S_STOP
    screened: ClassVar[bool] = False  # a candidate on request (see the module notes)

    def __post_init__(self):
        check_nonnegative("end_stops stiffness_N_per_m", self.stiffness_N_per_m, "N/m")
        check_nonnegative("end_stops clearance_m", self.clearance_m, "m")
        check_nonnegative("end_stops damping_N_s_per_m", self.damping_N_s_per_m, "N s/m")
        check_finite("end_stops centre_m", self.centre_m, "m")

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_KS], ep[K.E_CS] = self.stiffness_N_per_m, self.damping_N_s_per_m
        ep[K.E_CLR], ep[K.E_CTR] = self.clearance_m, self.centre_m

    def describing_function(self, amplitude_m, omega, params, model=None):
        """(k_s N, c_s N, 0), N = n(rho_+) + n(rho_-) (class docstring)."""
        Y, _ = _check_harmonic(amplitude_m, omega)
        N = (_contact_fraction((self.clearance_m + self.centre_m) / Y)
             + _contact_fraction((self.clearance_m - self.centre_m) / Y))
        return self.stiffness_N_per_m * N, self.damping_N_s_per_m * N, 0.0

    @classmethod
    def probe(cls, force_amplitude_N, amplitude_m, omega, params):
        """Stops at 90 % of the stroke, 5 x the record's force over the stroke."""
        return cls(5.0 * force_amplitude_N / amplitude_m, 0.9 * amplitude_m)


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
    state_names: ClassVar[tuple] = ("y_piston",)
    state_units: ClassVar[tuple] = ("m",)
    slot: ClassVar[int] = K.S_IC
    kind: ClassVar[str] = "kinematic"

    def __post_init__(self):
        k = float(self.stiffness_N_per_m)
        if not k > 0 or math.isnan(k):
            raise ParameterError(
                f"series_compliance stiffness_N_per_m must be > 0 [N/m] (inf: rigid), got {k:g}")

    def check(self, model):
        if model.n_base_states == 0 or model.uses_acceleration:
            raise ParameterError(
                f"effect {self.name!r} needs a model whose force is carried by its states; "
                f"model {model.name!r} has {model.n_base_states} states"
                + (" and uses the acceleration" if model.uses_acceleration else "")
                + "; for a dashpot behind a spring use 'maxwell'")

    describing_reason: ClassVar[str | None] = (
        "a spring in series with the fluid; its equivalent is 1/(1/K_fluid + 1/k), not a "
        "parallel element")

    def pack(self, ep):
        ep[K.E_KC] = float(self.stiffness_N_per_m)

    def initial_state(self, params, y0):
        return np.array([y0])

    def state_scales(self, params):
        return np.array([1e-4])


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
    state_names: ClassVar[tuple] = ("y_fp",)
    state_units: ClassVar[tuple] = ("m",)
    slot: ClassVar[int] = K.S_IFP
    kind: ClassVar[str] = "kinematic"

    def __post_init__(self):
        check_nonnegative("freeplay gap_m", self.gap_m, "m")

    small_signal_reason: ClassVar[str | None] = (
        "inside the dead band the piston does not move at all")
    describing_reason: ClassVar[str | None] = (
        "a dead band in series with the fluid")

    def pack(self, ep):
        ep[K.E_GAP] = self.gap_m

    def initial_state(self, params, y0):
        return np.array([y0])

    def state_scales(self, params):
        return np.array([1e-4])


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
    slot: ClassVar[int] = K.S_LEAK
    kind: ClassVar[str] = "fluid"

    def __post_init__(self):
        check_nonnegative("leakage coefficient_m3_per_s_Pa", self.coefficient_m3_per_s_Pa,
                          "m^3/(s Pa)")

    def pack(self, ep):
        ep[K.E_LEAK] = self.coefficient_m3_per_s_Pa


#: Stateless bases on which the flow effects act as a force law on the dashpot.
_DAMPERS = ("dashpot", "dashpot_inerter", "viscous")


def _damper(params, model) -> tuple[float, float]:
    """(c [N s/m], piston area [m^2]) of a stateless dashpot-type base (viscous: area 1)."""
    if model.base == "viscous":
        return float(params.c), 1.0
    return float(params.c_L), float(params.A_p)


def saturation_damping(c: float, c_open: float, force_r: float,
                       velocity_amplitude: float) -> float:
    """Equivalent damping of a relief-valve saturated dashpot at v = V cos(w t) [N s/m].

    The static law F(v) = sign(v) min(c |v|, F_r + c_o (|v| - F_r / c)) is
    c_o v plus (c - c_o) times a unit saturation at F_r / c, whose describing
    function is exact (Gelb and Vander Velde, 1968): with rho = F_r / (c V),

    c_eq = c_o + (c - c_o) (2 / pi) (arcsin(rho) + rho sqrt(1 - rho^2))

    for c V > F_r, and c otherwise.  (For a small second harmonic on top of
    a large motion the incremental damping is the time average of the slope,
    c_o + (c - c_o) (2 / pi) arcsin(rho), without the second term.)

    Parameters
    ----------
    c : float
        Damping below cracking > 0 [N s/m].
    c_open : float
        Slope above cracking, 0 <= c_open <= c [N s/m].
    force_r : float
        Cracking force F_r >= 0 [N].
    velocity_amplitude : float
        V > 0 [m/s].

    Returns
    -------
    float
        c_eq [N s/m]: the first harmonic of F is c_eq V cos(w t).

    Examples
    --------
    >>> saturation_damping(1e5, 1e4, 500.0, 0.004)     # below cracking: c
    100000.0
    >>> round(saturation_damping(1e5, 0.0, 0.0, 0.01), 12)   # Coulomb-like limit 0
    0.0
    """
    for name, v in (("c", c), ("c_open", c_open), ("force_r", force_r),
                    ("velocity_amplitude", velocity_amplitude)):
        check_nonnegative(f"saturation_damping {name}", v, "SI")
    if not c > 0 or not velocity_amplitude > 0 or c_open > c:
        raise ParameterError(f"saturation_damping needs c > 0, V > 0 and c_open <= c, got "
                             f"c = {c:g}, V = {velocity_amplitude:g}, c_open = {c_open:g}")
    rho = force_r / (c * velocity_amplitude)
    if rho >= 1.0:
        return float(c)
    return float(c_open + (c - c_open) * 2.0 / math.pi
                 * (math.asin(rho) + rho * math.sqrt(1.0 - rho * rho)))


@dataclass(frozen=True)
class ReliefValve(Effect):
    """Relief (blow-off) valve: a pressure-limited second flow path beside the channel.

    No flow below the cracking pressure p_r; above it the valve passes
    q_r = sign(dp) G (|dp| - p_r) [m^3/s] in parallel with the channel
    (:func:`~liquidamp.device.kernels.relief_flow`, C1 over a pressure width
    0.01 p_r + 1 Pa so that stiff steppers keep their order).  On the models
    with chamber pressures the mass flow rho_l q_r joins the chamber balances
    like leakage's (mass conserved exactly); on the differential models
    (eqs. 15, 18) d(dp)/dt loses B q_r, on ``maxwell`` dF/dt loses
    k_D q_r(F / A_p) / A_p.  On the stateless dashpot-type bases it is the
    exact static force saturation (no regularisation: no state)

    F(v) = sign(v) min(c |v|, F_r + c_o (|v| - F_r / c)),

    F_r = p_r A_p, c_o = 1 / (1 / c + G / A_p^2), c = c_L (``dashpot``; the
    dashpot part of ``dashpot_inerter``): the channel's laminar loss with
    the valve path in parallel above cracking.  The ``viscous`` base F = c v
    is read as a dashpot of unit piston area: cracking force F_r [N] =
    cracking_pressure_Pa x 1 m^2 and c_o = 1 / (1 / c + G x 1 m^-4), i.e. give
    the relief as a force with :meth:`from_force`.  Its describing function
    there is exact (:func:`saturation_damping`).  Closed at rest, so the
    small-signal model at rest holds it (it has no effect there).

    Parameters
    ----------
    cracking_pressure_Pa : float
        p_r >= 0 [Pa] (viscous base: the cracking force in N).
    conductance_m3_per_s_Pa : float
        G >= 0 [m^3/(s Pa)] (viscous base: m/(N s)); 0 keeps the valve shut.

    References
    ----------
    .. [1] H. E. Merritt, Hydraulic Control Systems, Wiley, 1967, Ch. 5
       (pressure-relief valves).
    .. [2] A. Gelb, W. E. Vander Velde, Multiple-Input Describing Functions
       and Nonlinear System Design, McGraw-Hill, 1968 (saturation).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> m = with_effects(get_model("dashpot"), ReliefValve(1e6, 1e-9))
    >>> F_r = 1e6 * p.A_p; v = 2 * F_r / p.c_L      # twice the cracking speed
    >>> c_o = 1 / (1 / p.c_L + 1e-9 / p.A_p**2)
    >>> bool(np.isclose(m.force(0.0, np.zeros(0), (0.0, v, 0.0), p), F_r + c_o * v / 2))
    True
    """

    cracking_pressure_Pa: float = 1.0e6
    conductance_m3_per_s_Pa: float = 0.0
    name: ClassVar[str] = "relief_valve"
    units: ClassVar[dict] = {"cracking_pressure_Pa": "Pa",
                             "conductance_m3_per_s_Pa": "m^3/(s Pa)"}
    fit_keys: ClassVar[tuple] = ("conductance_m3_per_s_Pa", "cracking_pressure_Pa")
    bounds: ClassVar[dict] = {"cracking_pressure_Pa": (1e2, 1e9),
                              "conductance_m3_per_s_Pa": (1e-15, 1e-1)}
    order: ClassVar[int] = 7
    description: ClassVar[str] = "pressure-limited bypass (blow-off valve)"
    slot: ClassVar[int] = K.S_RELIEF
    kind: ClassVar[str] = "fluid"
    screened: ClassVar[bool] = False  # a candidate on request (see the module notes)

    def __post_init__(self):
        check_nonnegative("relief_valve cracking_pressure_Pa", self.cracking_pressure_Pa, "Pa")
        check_nonnegative("relief_valve conductance_m3_per_s_Pa",
                          self.conductance_m3_per_s_Pa, "m^3/(s Pa)")

    @classmethod
    def from_force(cls, cracking_force_N: float, damping_N_s_per_m: float,
                   open_damping_N_s_per_m: float, area_m2: float = 1.0) -> ReliefValve:
        """The valve that saturates a dashpot c at F_r with slope c_o above it.

        p_r = F_r / A, G = A^2 (1 / c_o - 1 / c); A = 1 m^2 for the viscous
        base, A_p for ``dashpot``.

        Examples
        --------
        >>> r = ReliefValve.from_force(5000.0, 1e5, 2e4)
        >>> r.cracking_pressure_Pa, round(r.conductance_m3_per_s_Pa, 12)
        (5000.0, 4e-05)
        """
        c = check_positive("damping_N_s_per_m", damping_N_s_per_m, "N s/m")
        co = check_positive("open_damping_N_s_per_m", open_damping_N_s_per_m, "N s/m")
        A = check_positive("area_m2", area_m2, "m^2")
        if co > c:
            raise ParameterError(f"open_damping_N_s_per_m must be <= damping_N_s_per_m "
                                 f"({c:g} N s/m), got {co:g}")
        return cls(float(cracking_force_N) / A, A * A * (1.0 / co - 1.0 / c))

    @classmethod
    def probe(cls, force_amplitude_N, amplitude_m, omega, params):
        """Cracking at 70 % of the peak pressure difference, a path of 0.3 x the channel's
        conductance at the record's flow (F_a / A_p for the peak; the viscous base: A = 1).

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> r = ReliefValve.probe(1000.0, 0.003, 6 * math.pi, preset("reference"))
        >>> round(r.cracking_pressure_Pa * preset("reference").A_p, 6)
        700.0
        """
        if hasattr(params, "A_p"):
            A = params.A_p
            Q = A * omega * amplitude_m
            c = params.c1 + 8.0 / (3.0 * math.pi) * params.c2 * Q
        else:
            A, c = 1.0, float(params.c)
        return cls(0.7 * force_amplitude_N / A, 0.3 / max(c, 1e-300))

    def check(self, model):
        if model.base in ("spring", "inerter"):
            raise ParameterError(
                f"effect {self.name!r} needs a flow path: model {model.name!r} has none "
                "(use a model with chamber pressures, a differential or Maxwell model, "
                "'dashpot', 'dashpot_inerter' or 'viscous')")

    describing_reason: ClassVar[str | None] = (
        "on a model with chamber states the valve changes the fluid equations; only on "
        "'dashpot', 'dashpot_inerter' and 'viscous' is it an exact force law")

    def pack(self, ep):
        ep[K.E_PR] = self.cracking_pressure_Pa
        ep[K.E_GR] = self.conductance_m3_per_s_Pa

    def describing_function(self, amplitude_m, omega, params, model=None):
        """Exact on the dashpot-type bases: (0, c_eq - c, 0) (:func:`saturation_damping`).

        Examples
        --------
        >>> from liquidamp.device.models import VISCOUS, ViscousParams
        >>> m = with_effects(VISCOUS, ReliefValve.from_force(500.0, 1e5, 2e4))
        >>> k, dc, b = m.effects[0].describing_function(0.002, 5.0, ViscousParams(1e5), m)
        >>> round(1e5 + dc, 3) == round(saturation_damping(1e5, 2e4, 500.0, 0.01), 3)
        True
        """
        Y, w = _check_harmonic(amplitude_m, omega)
        if model is None or model.base not in _DAMPERS:
            return super().describing_function(amplitude_m, omega, params, model)
        c, area = _damper(params, model)
        if c == 0.0:
            return 0.0, 0.0, 0.0
        asym = model.effect("asymmetric_loss")
        F_r = self.cracking_pressure_Pa * area
        g = self.conductance_m3_per_s_Pa / area**2
        # each half cycle contributes half the first harmonic; with asymmetric_loss the
        # rebound half saturates the dashpot r c (its own describing function holds the
        # unsaturated average c (1 + r) / 2, this one the saturation on top)
        out = 0.0
        for ci in ((c,) if asym is None else (c, c * asym.rebound_ratio)):
            out += saturation_damping(ci, 1.0 / (1.0 / ci + g), F_r, w * Y) - ci
        return 0.0, out if asym is None else 0.5 * out, 0.0


@dataclass(frozen=True)
class AsymmetricLoss(Effect):
    """Direction-dependent losses: rebound unlike compression.

    The channel's loss coefficients are multiplied by the rebound ratio r
    while the flow runs from chamber 2 to chamber 1 (rebound; compression,
    y increasing, drives it from 1 to 2): c1, c2 (volumetric models), g1, g2
    (mass-flow models), T_D = c1 / B (``maxwell``), c_L (``dashpot``,
    ``dashpot_inerter``) and the viscous c, where the direction is the
    channel flow's sign (a state, or the pressure difference it follows;
    :func:`~liquidamp.device.kernels.flow_direction`) or the piston
    velocity's on the stateless bases.  The force stays continuous (every
    loss vanishes at zero flow); the ratio is piecewise constant, so the
    analytic Jacobian holds off zero flow.  A relief valve's path is not
    scaled.  On the stateless bases F = c v (compression), r c v (rebound):
    the first harmonic's damping is the average c (1 + r) / 2 and the
    energy of the rebound half cycle is r times the compression half's.

    Parameters
    ----------
    rebound_ratio : float
        r > 0 [-]: rebound loss / compression loss (1: symmetric).

    References
    ----------
    .. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007,
       Ch. 1 and 5 (bump and rebound damping).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> m = with_effects(get_model("dashpot"), AsymmetricLoss(2.5))
    >>> u = (np.zeros(2), np.array([0.01, -0.01]), np.zeros(2))
    >>> [round(float(f / (0.01 * p.c_L)), 12) for f in m.force(0.0, np.zeros((0, 2)), u, p)]
    [1.0, -2.5]
    """

    rebound_ratio: float = 1.0
    name: ClassVar[str] = "asymmetric_loss"
    units: ClassVar[dict] = {"rebound_ratio": "-"}
    fit_keys: ClassVar[tuple] = ("rebound_ratio",)
    bounds: ClassVar[dict] = {"rebound_ratio": (0.05, 20.0)}
    order: ClassVar[int] = 3
    description: ClassVar[str] = "rebound losses r times the compression losses"
    slot: ClassVar[int] = K.S_ASYM
    kind: ClassVar[str] = "fluid"
    screened: ClassVar[bool] = False  # a candidate on request (see the module notes)

    def __post_init__(self):
        r = check_finite("asymmetric_loss rebound_ratio", self.rebound_ratio, "-")
        if not r > 0:
            raise ParameterError(f"asymmetric_loss rebound_ratio must be > 0 [-], got {r:g}")

    def check(self, model):
        if model.base in ("spring", "inerter"):
            raise ParameterError(
                f"effect {self.name!r} needs a loss: model {model.name!r} has none")

    def check_small_signal(self, params) -> None:
        """The slope of the loss jumps at zero flow unless the ratio is 1."""
        if self.rebound_ratio != 1.0:
            raise ParameterError(
                f"effect {self.name!r} has no small-signal model at rest: the loss slope "
                f"jumps by the rebound ratio {self.rebound_ratio:g} at zero flow; give an "
                "amplitude and a frequency for an equivalent linearization, or use the time "
                "domain")

    describing_reason: ClassVar[str | None] = (
        "on a model with chamber states it changes the fluid equations; only on 'dashpot', "
        "'dashpot_inerter' and 'viscous' is it an exact force law")

    def pack(self, ep):
        ep[K.E_RR] = self.rebound_ratio

    @classmethod
    def probe(cls, force_amplitude_N, amplitude_m, omega, params):
        """Rebound losses 20 % above compression's."""
        return cls(1.2)

    def describing_function(self, amplitude_m, omega, params, model=None):
        """Exact on the dashpot-type bases: (0, c (r - 1) / 2, 0) (the average damping).

        Examples
        --------
        >>> from liquidamp.device.models import VISCOUS, ViscousParams
        >>> m = with_effects(VISCOUS, AsymmetricLoss(3.0))
        >>> m.effects[0].describing_function(1e-3, 10.0, ViscousParams(100.0), m)
        (0.0, 100.0, 0.0)
        """
        _check_harmonic(amplitude_m, omega)
        if model is None or model.base not in _DAMPERS:
            return super().describing_function(amplitude_m, omega, params, model)
        c = _damper(params, model)[0]
        return 0.0, 0.5 * c * (self.rebound_ratio - 1.0), 0.0


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
    state_names: ClassVar[tuple] = ("Vc1", "Vc2")
    state_units: ClassVar[tuple] = ("m^3", "m^3")
    slot: ClassVar[int] = K.S_ICAV
    kind: ClassVar[str] = "fluid"

    def __post_init__(self):
        v = check_finite("cavitation vapour_pressure_Pa", self.vapour_pressure_Pa, "Pa")
        if not v > 0:
            raise ParameterError(f"cavitation vapour_pressure_Pa must be > 0 [Pa], got {v:g}")

    describing_reason: ClassVar[str | None] = (
        "cavities open on part of the cycle and change the chamber stiffness")

    def pack(self, ep):
        ep[K.E_PV] = self.vapour_pressure_Pa

    def check_small_signal(self, params) -> None:
        """At rest the cavities are closed (p0 above p_v plus the switch width): no effect."""
        if params.p0 <= self.vapour_pressure_Pa + cavity_width(self.vapour_pressure_Pa):
            raise ParameterError(
                f"effect 'cavitation' has no small-signal model at rest: the filling pressure "
                f"p0 = {params.p0:g} Pa is within the cavity switch "
                f"(p_v = {self.vapour_pressure_Pa:g} Pa + "
                f"{cavity_width(self.vapour_pressure_Pa):g} Pa)")

    def state_scales(self, params):
        return np.full(2, params.A_p * 1e-4)


@dataclass(frozen=True)
class RotatingFrame(Effect):
    """The device on a rotor: the centrifugal field along its axis.

    A lag damper turning with the rotor at Omega, its mid-point (the piston
    at zero stroke) at the radius r_m and its axis (chamber 1 -> chamber 2)
    at the angle theta to the radial direction in the plane of rotation.
    With the head h(s) = r_m cos(theta) s + s^2/2 along the axis (s from
    the mid-point; the integral of r dr projected on the axis) and h_i its
    mean over chamber i (chamber 1 on [-L1, -y], chamber 2 on [-y, L2],
    L_i = V0i / A_p, y the piston stroke), the centrifugal pressure rise
    from chamber 1's lumped pressure to chamber 2's ([1]_, rigid-body
    rotation) is

        Delta p_c(y) = rho_l Omega^2 (h_2 - h_1)
                     = rho_l Omega^2 [r_m cos(theta) (L1 + L2)/2
                       + (L2^2 - L1^2)/6 - (L1 + L2) y / 6],

    i.e. rho_l Omega^2 r_m L cos(theta) for equal chambers of length L at
    zero stroke.  It enters (kernel :func:`~liquidamp.device.kernels.rotating_heads`):

    - the channel momentum equation (eq. 10 of [2]_, ``full``, ``inertial``,
      ``inertial_2state``): S_t dm12/dt = p1 - p2 + Delta p_c - g1 m12 -
      g2 m12 |m12| (the Coriolis force is normal to the flow);
    - the loss relation of the reductions without inertia (``no_inertia``,
      ``constant_bulk``, ``volumetric``, ``single_state``) and the leakage
      bypass: the flow is driven by dp + Delta p_c;
    - the load-cell force: F = A_p (p1 - p2 + Delta p_c) (both piston faces
      at one point, so F = 0 at rest);
    - the cavitation effect: its switch acts on each chamber's
      innermost-point pressure (:meth:`inboard_pressures`), so a cavity
      opens at the inboard end and holds it at p_v;
    - the rest state: sealed and unpressurized, the device keeps its filling
      mass, and at rest p2 - p1 = Delta p_c: the outboard chamber rises, the
      inboard one falls (:func:`~liquidamp.device.rotating.rest_state`), so a
      run on the rotor starts at rest.

    The models without chamber pressures or channel flow (``maxwell``, the
    ideal elements, ``viscous``) refuse it: the rotation acts through the
    mean chamber pressures, which they do not hold.  Zero speed is the bare
    model exactly.  A tangential axis (theta = pi/2) leaves a symmetric
    device's rest state unchanged; only the stroke term of Delta p_c
    remains, a stiffness change of A_p dDelta p_c/dy = -A_p rho_l Omega^2
    (L1 + L2)/6 in the fluid's flow path (a few N/m).  Rotor speed and
    radius are operating conditions, not fitted (no ``fit_keys``).  For a
    device on the ground-resonance host, use the host's rotor speed.  The
    derivation, assumptions and limits are in :mod:`liquidamp.device.rotating`.

    Parameters
    ----------
    rotor_speed_rad_per_s : float
        Rotor speed Omega >= 0 [rad/s].
    mounting_radius_m : float
        Distance r_m >= 0 from the shaft to the device mid-point [m].
    axis_angle_rad : float
        Angle theta between the device axis (chamber 1 -> chamber 2) and the
        radial direction, in the plane of rotation [rad]: 0 = chamber 2
        outboard, pi = chamber 1 outboard, pi/2 = tangential.

    References
    ----------
    .. [1] F. M. White, Fluid Mechanics, 7th ed., McGraw-Hill, 2011, Sec. 2.9.
    .. [2] B. Titurus, AIAA J. 56(10), 2018, eqs. (6), (10)-(18).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> p = preset("reference")                       # L1 = L2 = V0/A_p = 25 mm
    >>> rf = RotatingFrame(26.18, 0.3, 0.0)           # 250 rpm, 0.3 m, radial
    >>> dp_c = rf.pressure_rise(p)                    # rho_l Omega^2 r_m L
    >>> round(dp_c, 1), round(dp_c / (p.rho_l * 26.18**2 * 0.3 * p.V01 / p.A_p), 12)
    (5131.3, 1.0)
    >>> m = with_effects(get_model("full"), rf)
    >>> x = m.initial_state(p, 0.0)                   # at rest on the rotor
    >>> round(float(x[2] - x[0]), 1), [round(float(q)) for q in (x[0], x[2])]
    (5131.3, [98812, 103944])
    >>> abs(float(m.force(0.0, x, (0.0, 0.0, 0.0), p))) < 1e-9   # both faces pushed alike
    True
    >>> [round(q) for q in rf.inboard_pressures(x[0], x[2], p)]   # innermost points
    [96389, 101307]
    """

    rotor_speed_rad_per_s: float = 0.0
    mounting_radius_m: float = 0.0
    axis_angle_rad: float = 0.0
    name: ClassVar[str] = "rotating_frame"
    units: ClassVar[dict] = {"rotor_speed_rad_per_s": "rad/s", "mounting_radius_m": "m",
                             "axis_angle_rad": "rad"}
    fit_keys: ClassVar[tuple] = ()
    bounds: ClassVar[dict] = {}
    order: ClassVar[int] = 8
    description: ClassVar[str] = "centrifugal field of a device turning with a rotor"
    slot: ClassVar[int] = K.S_ROT
    kind: ClassVar[str] = "fluid"

    def __post_init__(self):
        check_nonnegative("rotating_frame rotor_speed_rad_per_s", self.rotor_speed_rad_per_s,
                          "rad/s")
        check_nonnegative("rotating_frame mounting_radius_m", self.mounting_radius_m, "m")
        check_finite("rotating_frame axis_angle_rad", self.axis_angle_rad, "rad")

    describing_reason: ClassVar[str | None] = (
        "it moves the mean chamber pressures and with them the air's bulk modulus")

    def check(self, model):
        if model.base not in ROTATING_BASES:
            raise ParameterError(
                f"effect {self.name!r} needs a model with chamber pressures or channel flow; "
                f"model {model.name!r} ({model.family}) has states "
                f"({', '.join(model.state_names) or 'none'}): the centrifugal field acts "
                "through the mean chamber pressures (bulk modulus, cavitation margin), which "
                "it does not hold, and in its assumptions it would be a constant pressure "
                "offset that leaves the force unchanged; use one of "
                f"{', '.join(ROTATING_BASES)}")

    def pack(self, ep):
        ep[K.E_OMEGA] = self.rotor_speed_rad_per_s
        ep[K.E_RM] = self.mounting_radius_m
        ep[K.E_COSA] = math.cos(self.axis_angle_rad)

    def _ep(self) -> np.ndarray:
        ep = np.zeros(K.N_EP)
        self.pack(ep)
        return ep

    def pressure_rise(self, params, stroke=0.0):
        """Centrifugal pressure rise Delta p_c from chamber 1 to chamber 2 [Pa] (vectorized).

        Parameters
        ----------
        params : DeviceParams
            Device (chamber lengths V0i / A_p, liquid density rho_l).
        stroke : float or array
            Piston stroke y [m].

        Returns
        -------
        float or ndarray
            rho_l Omega^2 (h_2 - h_1) at each stroke [Pa].
        """
        return _shaped(heads(params, self._ep(), stroke)[0], stroke)

    def inboard_pressures(self, p1, p2, params, stroke=0.0):
        """Pressure at each chamber's innermost point [Pa]: the cavitation margin (vectorized).

        The chambers' lumped pressures (the model's p1, p2, volume means)
        lowered by the centrifugal head between the chamber's mean and its
        point nearest the shaft, p_i + rho_l Omega^2 (min h - h_i): the
        inboard end, unless the axis passes its point nearest the shaft
        inside the chamber (nearly tangential axes).  Compare it with the
        vapour pressure.

        Parameters
        ----------
        p1, p2 : float or array
            Lumped chamber pressures [Pa] (e.g. ``response.p1``, ``response.p2``).
        params : DeviceParams
            Device.
        stroke : float or array
            Piston stroke y [m] (the rod stroke without kinematic effects).

        Returns
        -------
        (p1_in, p2_in) : floats or ndarrays
            Least pressure in chamber 1 and chamber 2 [Pa].
        """
        _, o1, o2 = heads(params, self._ep(), stroke)
        return (_shaped(np.asarray(p1, float) + o1, p1, stroke),
                _shaped(np.asarray(p2, float) + o2, p2, stroke))

    def rest_base_state(self, model, params, y0, x_base):
        """The static equilibrium on the rotor (:func:`~liquidamp.device.rotating.rest_state`)."""
        if self.rotor_speed_rad_per_s == 0.0:
            return x_base
        dp_c = float(self.pressure_rise(params, y0))
        return rest_state(model.base, params, y0, dp_c, x_base)


def _shaped(value, *inputs):
    """A float where every input is scalar, else the array."""
    if all(np.ndim(q) == 0 for q in inputs):
        return float(value)
    return value


def _check_harmonic(amplitude_m, omega) -> tuple[float, float]:
    Y, w = float(amplitude_m), float(omega)
    if not (math.isfinite(Y) and Y > 0):
        raise ParameterError(f"amplitude must be finite and > 0 [m], got {amplitude_m!r}")
    if not (math.isfinite(w) and w > 0):
        raise ParameterError(f"omega must be finite and > 0 [rad/s], got {omega!r}")
    return Y, w


EFFECTS: dict[str, type[Effect]] = {
    cls.name: cls
    for cls in (CoulombFriction, SmoothFriction, ForceOffset, MovingMass, SeriesCompliance,
                Freeplay, Leakage, Cavitation, ReliefValve, AsymmetricLoss, Elastomer, EndStops,
                RotatingFrame)
}
"""Registry: effect name -> class."""


def effect_names() -> tuple[str, ...]:
    """Names of the catalogue effects.

    Examples
    --------
    >>> effect_names()
    ('coulomb_friction', 'smooth_friction', 'force_offset', 'moving_mass', \
'series_compliance', 'freeplay', 'leakage', 'cavitation', 'relief_valve', 'asymmetric_loss', \
'elastomer', 'end_stops', 'rotating_frame')
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
relief_valve, asymmetric_loss, elastomer, end_stops, rotating_frame
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


def _piston_stroke(model_effects, n_base: int):
    """Index of the state that holds the piston stroke (innermost kinematic effect), or None."""
    i = n_base
    index = {}
    for e in model_effects:
        index[e.name] = i
        i += len(e.state_names)
    for name in ("series_compliance", "freeplay"):
        if name in index:
            return index[name]
    return None


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
    ip = _piston_stroke(ordered, nb)
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
