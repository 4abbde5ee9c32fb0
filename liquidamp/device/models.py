"""The device model family: eq. (10) of Titurus (2018) and every reduction (11)-(20).

Every variant is a :class:`DeviceModel`: data (base equation, family, state
names and units, limits of validity, effects) whose right-hand side,
Jacobian and force are the compiled functions of
:mod:`liquidamp.device.kernels` -- the one copy of the physics that both
engines run -- as pure functions of ``(t, x, u, params)``,
where ``x`` is the state vector, ``u = (y, v, a)`` the piston stroke [m],
stroke rate [m/s] and stroke acceleration [m/s^2], and ``params`` a
:class:`~liquidamp.device.params.DeviceParams`.  Nothing about a call is
kept on the object (the packed arrays of a model and a parameter set are
memoized read-only).  :data:`REGISTRY` maps each name to its model so that one contract
test runs over all of them.

Sign conventions: V1 = V01 - A_p y, V2 = V02 + A_p y; m12 > 0 flows from
chamber 1 to chamber 2; the load-cell force is F = A_p (p1 - p2) plus Coulomb
friction |F_f| sign(v) when ``params.friction_N`` > 0.

====================  ==========  ==============================================
name                  equation    states
====================  ==========  ==============================================
``full``              (10)        p1, rho1, p2, rho2, m12
``no_inertia``        (11)        p1, rho1, p2, rho2
``constant_bulk``     (13)        p1, p2
``volumetric``        (14)        p1, p2   (does not conserve mass: drifts)
``single_state``      (15)        dp
``inertial``          (17)        p1, p2, m12
``inertial_2state``   (18)        dp, q12
``maxwell``           (16) lin.   F
``dashpot``           (19) c_L    none
``spring``            (16) B/V    none
``dashpot_inerter``   (19)        none
``inerter``           (20)        none
====================  ==========  ==============================================

References
----------
.. [1] B. Titurus, "Generalized Liquid-Based Damping Device for Passive
   Vibration Control", AIAA J. 56(10), 4134-4145, 2018.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, check_choice

__all__ = ["DeviceModel", "FAMILIES", "REGISTRY", "BASES", "VISCOUS", "ViscousParams",
           "get_model", "model_names"]

#: Model families: what a model's states are, which decides which effects apply.
FAMILIES = {
    "chamber": "chamber pressures and densities as states (eqs. 10, 11)",
    "pressure": "chamber pressures as states, densities explicit (eqs. 13, 14, 17)",
    "differential": "differential pressure (and channel flow) only (eqs. 15, 18)",
    "linear": "linear Maxwell unit (eq. 16)",
    "ideal": "stateless ideal element (eqs. 16, 19, 20)",
}


@dataclass(frozen=True, eq=False)
class DeviceModel:
    """One variant of the device model family, possibly with add-on effects.

    A model is data: its base equation (``base``), its family, its states
    and its effects.  Its right-hand side, Jacobian and force are the
    compiled functions of :mod:`liquidamp.device.kernels`, evaluated on the
    packed arrays of :meth:`packed`; both engines use them, so there is one
    copy of the physics.  Models compare by identity.

    Attributes
    ----------
    name : str
        Registry name; for a composed model the base name and the effect
        names joined by ``+`` (a label only: nothing parses it).
    base : str
        Registry name of the base equation (a key of
        :data:`liquidamp.device.kernels.MODEL_IDS`).
    family : str
        One of :data:`FAMILIES`.
    equation : str
        Equation number(s) in Titurus (2018).
    description : str
        One line on what the variant keeps and drops.
    state_names : tuple of str
        Names of the states, in order (base states, then effect states).
    state_units : tuple of str
        Unit of each state.
    limits : str
        Limits of validity.
    initial_state : callable
        ``initial_state(params, y0) -> x0`` at rest with stroke ``y0`` [m].
    state_scales : callable
        ``state_scales(params) -> array`` of magnitudes used for absolute
        tolerances and finite-difference steps.
    pressures : callable or None
        ``pressures(x, u, params) -> (p1, p2)`` [Pa] where chamber pressures
        are states (vectorized; a diagnostic).
    mass : callable or None
        ``mass(x, u, params) -> total fluid mass`` [kg] where defined
        (vectorized; a diagnostic).
    conserves_mass : bool
        True where the total mass is an exact invariant.
    uses_acceleration : bool
        True where the force depends on the stroke acceleration.
    requires : tuple of str
        Parameters that must be > 0 for this variant (:meth:`check_params`).
    uses_bulk_law : bool
        True where the chamber bulk modulus follows ``params.bulk_law``
        (eq. 2 is singular at p = 0, so the run stops at the pressure floor);
        the constant-bulk reductions can pass through zero pressure, which
        the run reports as a warning.
    effects : tuple of Effect
        Add-on effects composed into this model by
        :func:`liquidamp.device.effects.with_effects`, in composition order
        (empty for a registered model).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> m, p = get_model("maxwell"), preset("reference")
    >>> x = np.array([10.0])
    >>> bool(np.isclose(m.rhs(0.0, x, (0.0, 0.01, 0.0), p)[0], p.k_D * 0.01 - 10.0 / p.T_D))
    True
    """

    name: str
    base: str
    family: str
    equation: str
    description: str
    state_names: tuple[str, ...]
    state_units: tuple[str, ...]
    limits: str
    initial_state: Callable[[DeviceParams, float], np.ndarray]
    state_scales: Callable[[DeviceParams], np.ndarray]
    pressures: Callable | None = None
    mass: Callable | None = None
    conserves_mass: bool = False
    uses_acceleration: bool = False
    requires: tuple[str, ...] = field(default=())
    uses_bulk_law: bool = False
    effects: tuple = field(default=())

    def __post_init__(self) -> None:
        check_choice("model base", self.base, K.MODEL_IDS)
        check_choice("model family", self.family, FAMILIES)
        object.__setattr__(self, "_spec", self._build_spec())
        wanted = {c for e in self.effects for c in getattr(e, "input_channels", ())}
        object.__setattr__(self, "_inputs", tuple(c for c in K.CHANNELS if c in wanted))

    # -------------------------------------------------------- packing
    @property
    def n_states(self) -> int:
        """Number of states."""
        return len(self.state_names)

    @property
    def n_base_states(self) -> int:
        """Number of states of the base equation (the effect states follow)."""
        return K.BASE_STATES[K.MODEL_IDS[self.base]]

    @property
    def analytic_jacobian(self) -> bool:
        """True where the Jacobian is analytic (otherwise central differences)."""
        return bool(self._spec[K.S_ANALYTIC])

    def effect(self, name: str):
        """The composed effect called ``name``, or None."""
        for e in self.effects:
            if e.name == name:
                return e
        return None

    def _build_spec(self) -> np.ndarray:
        spec = np.full(K.N_SPEC, -1, dtype=np.int64)
        spec[K.S_MID] = K.MODEL_IDS[self.base]
        spec[K.S_N] = self.n_states
        spec[K.S_NB] = self.n_base_states
        for slot in (K.S_LEAK, K.S_COUL, K.S_MASS, K.S_OFF, K.S_CPIST, K.S_ZPIST,
                     K.S_RELIEF, K.S_ASYM, K.S_STOP, K.S_GAS):  # flags; state indices stay -1
            spec[slot] = 0
        i = self.n_base_states
        for e in self.effects:
            if e.state_names:
                spec[e.slot] = i
                i += len(e.state_names)
            else:
                spec[e.slot] = 1
            for slot, value in e.spec_flags().items():
                spec[slot] = value
        if i != self.n_states:
            raise ParameterError(
                f"model {self.name!r}: {self.n_states} state names for {i} states")
        names = self.state_names
        if "p1" in names[:self.n_base_states]:
            spec[K.S_I1], spec[K.S_I2] = names.index("p1"), names.index("p2")
        fd = spec[K.S_ICAV] >= 0 or spec[K.S_IC] >= 0 or spec[K.S_IFP] >= 0 or (
            spec[K.S_LEAK] and self.base not in ("full", "no_inertia")) or spec[K.S_RELIEF] \
            or spec[K.S_ROT] > 0 or spec[K.S_TH] >= 0 or spec[K.S_IW] >= 0
        spec[K.S_ANALYTIC] = 0 if fd else 1
        spec[K.S_EFFECTS] = len(self.effects)
        return spec

    def packed(self, params) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The arrays the compiled physics runs on: ``(spec, prm, ep)``.

        ``spec`` describes the composition, ``prm`` the parameters
        (:func:`liquidamp.device.kernels.pack_params`), ``ep`` the effect
        parameters and the state scales (see :mod:`liquidamp.device.kernels`).
        ``spec`` and ``ep`` are read-only (shared between calls); ``prm`` is
        a fresh writable copy, as the compiled laws make their own modified
        copies of it (direction-dependent losses), so that one compiled
        signature serves both.
        """
        spec, prm, ep = _packed(self, params)
        return spec, prm.copy(), ep

    @property
    def input_channels(self) -> tuple[str, ...]:
        """Measured channels the model reads (its effects' ``input_channels``, slot order)."""
        return self._inputs

    def _with_inputs(self, prm, u, rates=None):
        """Write the channel values ``u[3]`` (and ``rates[2]``) into ``prm``'s channel slots;
        refuse a model that reads channels without them (Effect docstring)."""
        if not self._inputs:
            return
        if len(u) < 4 or u[3] is None:
            check_input_channels(self, (), "a drive u = (y, v, a) without channel values (an "
                                 "analytic stroke or a coupled host)")
        prm[K.P_CH:K.P_CH + K.N_CH] = np.asarray(u[3], float).reshape(K.N_CH)
        if rates is not None and len(rates) > 2 and rates[2] is not None:
            prm[K.P_CHD:K.P_CHD + K.N_CH] = np.asarray(rates[2], float).reshape(K.N_CH)

    # -------------------------------------------------------- physics
    def rhs(self, t, x, u, params) -> np.ndarray:
        """dx/dt at state ``x`` under the rod stroke ``u = (y, v, a)`` [state units / s]
        (``u = (y, v, a, c)`` with the input channel values ``c`` for a model that reads
        measured channels: :class:`~liquidamp.device.effects_base.Effect`)."""
        spec, prm, ep = self.packed(params)
        self._with_inputs(prm, u)
        out = np.empty(self.n_states)
        if out.size:
            K.model_rhs(spec, np.array(x, dtype=float), float(u[0]), float(u[1]), prm, ep, out)
        return out

    def jacobian(self, t, x, u, params) -> np.ndarray:
        """d rhs / dx, shape (n, n): analytic or central differences (:attr:`analytic_jacobian`)."""
        spec, prm, ep = self.packed(params)
        self._with_inputs(prm, u)
        J = np.zeros((self.n_states, self.n_states))
        if J.size:
            K.model_jac(spec, np.array(x, dtype=float), float(u[0]), float(u[1]), prm, ep, J)
        return J

    def rhs_t(self, t, x, u, rates, params) -> np.ndarray:
        """d rhs / dt at fixed x through the stroke, ``rates = (dy/dt, dv/dt)`` (and the
        channel rates ``dc/dt`` third where the model reads channels)."""
        spec, prm, ep = self.packed(params)
        self._with_inputs(prm, u, rates)
        out = np.zeros(self.n_states)
        if out.size:
            K.model_rhs_t(spec, np.array(x, dtype=float), float(u[0]), float(u[1]),
                          float(rates[0]), float(rates[1]), prm, ep, out)
        return out

    def _force(self, x, u, params, with_friction: bool):
        spec, prm, ep = self.packed(params)
        X = np.asarray(x, dtype=float)
        y, v = np.asarray(u[0], float), np.asarray(u[1], float)
        a = np.asarray(u[2], float) if len(u) > 2 else np.zeros(())
        n = self.n_states
        shape = np.broadcast_shapes(y.shape, v.shape, a.shape, X.shape[1:])
        N = math.prod(shape)
        X2 = X.reshape(n, -1) if X.size else np.zeros((n, 1))
        # writable contiguous copies where needed: one compiled signature for every call
        X2 = np.require(np.broadcast_to(X2, (n, N)), float, "CW")
        Y, V, A = (np.require(np.broadcast_to(q, shape).reshape(-1), float, "CW")
                   for q in (y, v, a))
        out = np.empty(N)
        if self._inputs and len(u) > 3 and u[3] is not None:
            # the channel values per sample (rows in slot order) into the channel slots
            C = np.require(np.broadcast_to(np.asarray(u[3], float).reshape(K.N_CH, -1),
                                           (K.N_CH, N)), float, "CW")
            K.force_series_inputs(spec, X2, Y, V, A, C, prm, ep, with_friction, out)
        elif self.effects:
            K.force_series(spec, X2, Y, V, A, prm, ep, with_friction, out)
        else:
            K.base_force_series(int(spec[K.S_MID]), X2, Y, V, A, prm, with_friction, out)
        return np.float64(out[0]) if shape == () else out.reshape(shape)

    def fluid_force(self, t, x, u, params):
        """Load-cell force without the parameter set's friction ``friction_N`` [N] (vectorized).

        The fluid force at the piston stroke plus every effect force; ``x``
        of shape (n,) or (n, N) with ``u`` of scalars or arrays of length N.
        """
        return self._force(x, u, params, False)

    def force(self, t, x, u, params):
        """Load-cell force F = :meth:`fluid_force` + ``friction_N`` sign(v) [N] (vectorized)."""
        return self._force(x, u, params, True)

    def check_params(self, params: DeviceParams) -> None:
        """Raise ParameterError if ``params`` lies outside this variant's domain.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> get_model("full").check_params(preset("reference").replace(S_t=0.0))
        Traceback (most recent call last):
        ...
        liquidamp.errors.ParameterError: model 'full' (eq. (10)) needs S_t > 0 [1/m], got 0; \
use 'no_inertia' (eq. 11) for a channel without inertance
        """
        hints = {"S_t": "; use 'no_inertia' (eq. 11) for a channel without inertance",
                 "c1": "; the linear models need a laminar loss"}
        units = {"S_t": "1/m", "c1": "kg m^-4 s^-1"}
        for key in self.requires:
            value = getattr(params, key)
            if not value > 0.0:
                raise ParameterError(
                    f"model {self.name!r} (eq. {self.equation}) needs {key} > 0 "
                    f"[{units.get(key, '-')}], got {value:g}{hints.get(key, '')}"
                )


def check_input_channels(model, available, where: str) -> None:
    """Raise ParameterError, before any work, if ``model`` reads a channel ``available`` lacks.

    Parameters
    ----------
    model : DeviceModel
        The composed model.
    available : iterable of str
        Channels the drive carries (e.g. a record's ``channels``).
    where : str
        What drives the model, for the message (e.g. ``"record 'd10_cal'"``).

    Raises
    ------
    ParameterError
        Naming the effect, the channel it reads and the channels ``where`` carries.

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> check_input_channels(get_model("full"), (), "a harmonic stroke") is None
    True
    """
    have = tuple(available)
    for e in getattr(model, "effects", ()):
        for c in e.input_channels:
            if c not in have:
                raise ParameterError(
                    f"effect {e.name!r} reads the measured {c!r} channel, which {where} does "
                    f"not carry (channels there: {', '.join(have) or 'none'}); drive it with "
                    f"a record that has a {c} column "
                    "(liquidamp.analysis.measured.record_model.simulate_record), or leave "
                    "the effect out")


@functools.lru_cache(maxsize=256)
def _packed(model: DeviceModel, params) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    prm = K.pack_params(params)
    if prm[K.P_CV2] != 0.0:
        laws = [e.name for e in model.effects
                if e.name in ("relief_valve", "digressive_valve", "asymmetric_loss")]
        if laws:
            raise ParameterError(
                f"model {model.name!r}: {', '.join(laws)} on the viscous damper is written for "
                f"F = c v; its quadratic coefficient c2 = {params.c2!r} N s^2/m^2 must be 0 "
                "there (use a fluid model, e.g. 'single_state', for a quadratic loss with a "
                "relief valve or rebound ratio)")
    ep = np.zeros(K.N_EP + model.n_states)
    for e in model.effects:
        e.pack(ep)
    if model.n_states:
        ep[K.N_EP:] = np.asarray(model.state_scales(params), float)
    spec = model._spec
    for a in (spec, prm, ep):
        a.flags.writeable = False
    return spec, prm, ep


# ---------------------------------------------------------------------------
# diagnostics (vectorized): volumes, pressures, mass


def _volumes(y, p: DeviceParams):
    return p.V01 - p.A_p * y, p.V02 + p.A_p * y


def _r(pr, B0: float, p: DeviceParams):
    """Explicit density of a constant-bulk chamber, r(p) = rho0 exp((p - p0)/B0)."""
    return p.rho0 * np.exp((pr - p.p0) / B0)


def _scales_full(p):
    return np.array([p.p0, p.rho0, p.p0, p.rho0, p.rho0 * p.A_p * 0.01])


def _mass_states(x, u, p):
    V1, V2 = _volumes(u[0], p)
    return x[1] * V1 + x[3] * V2


def _pressures_02(x, u, p):
    return x[0], x[2]


def _mass_cb(x, u, p):
    V1, V2 = _volumes(u[0], p)
    return _r(x[0], p.B01, p) * V1 + _r(x[1], p.B02, p) * V2


def _pressures_01(x, u, p):
    return x[0], x[1]


def _x0(*values):
    def initial(p: DeviceParams, y0: float = 0.0) -> np.ndarray:
        return np.array([getattr(p, v) if isinstance(v, str) else float(v) for v in values])

    return initial


def _scales(*values):
    def scales(p: DeviceParams) -> np.ndarray:
        out = []
        for v in values:
            if callable(v):
                out.append(v(p))
            else:
                out.append(getattr(p, v) if isinstance(v, str) else float(v))
        return np.array(out)

    return scales


def _flow_scale(p):
    return p.A_p * 0.01  # 10 mm/s of piston speed [m^3/s]


def _dp_scale(p):
    return 1.0e5  # 1 bar


_IDEAL_LIMITS = "linear ideal element; no compressibility or flow nonlinearity"

REGISTRY: dict[str, DeviceModel] = {
    m.name: m
    for m in (
        DeviceModel(
            name="full",
            base="full",
            family="chamber",
            equation="(10)",
            description="5-state nonlinear model: pressure-dependent bulk modulus, densities, "
            "channel inertance and linear-quadratic losses",
            state_names=("p1", "rho1", "p2", "rho2", "m12"),
            state_units=("Pa", "kg/m^3", "Pa", "kg/m^3", "kg/s"),
            limits="lumped channel flow (frequencies well below the line's first acoustic mode); "
            "chamber pressures > 0 (no cavitation unless the effect is added); |y| < V0/A_p",
            initial_state=_x0("p0", "rho0", "p0", "rho0", 0.0),
            state_scales=_scales_full,
            pressures=_pressures_02,
            mass=_mass_states,
            conserves_mass=True,
            requires=("S_t",),
            uses_bulk_law=True,
        ),
        DeviceModel(
            name="no_inertia",
            base="no_inertia",
            family="chamber",
            equation="(11)",
            description="eq. (10) with S_t = 0: m12 from the analytic inverse of eq. (5)",
            state_names=("p1", "rho1", "p2", "rho2"),
            state_units=("Pa", "kg/m^3", "Pa", "kg/m^3"),
            limits="channel inertance negligible: b_L omega << c_eq A_p^2; pressures > 0",
            initial_state=_x0("p0", "rho0", "p0", "rho0"),
            state_scales=_scales("p0", "rho0", "p0", "rho0"),
            pressures=_pressures_02,
            mass=_mass_states,
            conserves_mass=True,
            uses_bulk_law=True,
        ),
        DeviceModel(
            name="constant_bulk",
            base="constant_bulk",
            family="pressure",
            equation="(13)",
            description="eq. (11) with constant bulk moduli B_i = B_i(p0); explicit densities "
            "r_i(p) keep the mass conserved",
            state_names=("p1", "p2"),
            state_units=("Pa", "Pa"),
            limits="pressure swings small against the scale on which B(p) changes (air-rich "
            "chambers stiffen strongly with pressure); no channel inertia",
            initial_state=_x0("p0", "p0"),
            state_scales=_scales("p0", "p0"),
            pressures=_pressures_01,
            mass=_mass_cb,
            conserves_mass=True,
        ),
        DeviceModel(
            name="volumetric",
            base="volumetric",
            family="pressure",
            equation="(14)",
            description="volumetric flow balance of each chamber; kept to show its "
            "non-physical drift (mass is not conserved)",
            state_names=("p1", "p2"),
            state_units=("Pa", "Pa"),
            limits="not physical: total mass drifts by (r2 - r1) q12 per unit time, so mean "
            "pressures drift; use constant_bulk (eq. 13) instead",
            initial_state=_x0("p0", "p0"),
            state_scales=_scales("p0", "p0"),
            pressures=_pressures_01,
            mass=_mass_cb,
            conserves_mass=False,
        ),
        DeviceModel(
            name="single_state",
            base="single_state",
            family="differential",
            equation="(15)",
            description="differential pressure only: d(dp)/dt = (B1/V1 + B2/V2)(A_p v - q12); "
            "eq. (16) is its small-stroke form",
            state_names=("dp",),
            state_units=("Pa",),
            limits="constant bulk moduli; mean pressure not tracked (no cavitation check); "
            "no channel inertia",
            initial_state=_x0(0.0),
            state_scales=_scales(_dp_scale),
        ),
        DeviceModel(
            name="inertial",
            base="inertial",
            family="pressure",
            equation="(17)",
            description="constant bulk moduli with channel inertance: p1, p2, m12",
            state_names=("p1", "p2", "m12"),
            state_units=("Pa", "Pa", "kg/s"),
            limits="constant bulk moduli (small pressure swings); pressures > 0",
            initial_state=_x0("p0", "p0", 0.0),
            state_scales=_scales("p0", "p0", lambda p: p.rho0 * _flow_scale(p)),
            pressures=_pressures_01,
            mass=_mass_cb,
            conserves_mass=True,
            requires=("S_t",),
        ),
        DeviceModel(
            name="inertial_2state",
            base="inertial_2state",
            family="differential",
            equation="(18)",
            description="differential pressure and volumetric channel flow: "
            "B^-1 d(dp)/dt = A_p v - q, L_t dq/dt = dp - c1 q - c2 q|q|",
            state_names=("dp", "q12"),
            state_units=("Pa", "m^3/s"),
            limits="constant bulk moduli, r1 = r2 (differential view only); mean pressure "
            "not tracked",
            initial_state=_x0(0.0, 0.0),
            state_scales=_scales(_dp_scale, _flow_scale),
            requires=("S_t",),
        ),
        DeviceModel(
            name="maxwell",
            base="maxwell",
            family="linear",
            equation="(16), linear laminar",
            description="Maxwell unit dF/dt + F/T_D = k_D v, k_D = A_p^2 (B1/V01 + B2/V02), "
            "T_D = c1/(B1/V01 + B2/V02)",
            state_names=("F",),
            state_units=("N",),
            limits="small strokes, laminar loss only (c2 ignored), no inertia",
            initial_state=_x0(0.0),
            state_scales=_scales(lambda p: p.k_D * 1e-3),
            requires=("c1",),
        ),
        DeviceModel(
            name="dashpot",
            base="dashpot",
            family="ideal",
            equation="(16) with B -> inf",
            description="viscous dashpot F = c_L v, c_L = c1 A_p^2",
            state_names=(),
            state_units=(),
            limits=_IDEAL_LIMITS,
            initial_state=_x0(),
            state_scales=_scales(),
            requires=("c1",),
        ),
        DeviceModel(
            name="spring",
            base="spring",
            family="ideal",
            equation="(16) with c1 -> inf (closed channel)",
            description="linear spring F = k_D y",
            state_names=(),
            state_units=(),
            limits=_IDEAL_LIMITS,
            initial_state=_x0(),
            state_scales=_scales(),
        ),
        DeviceModel(
            name="dashpot_inerter",
            base="dashpot_inerter",
            family="ideal",
            equation="(19)",
            description="dashpot and inerter in parallel, F = c_L v + b_L a",
            state_names=(),
            state_units=(),
            limits=_IDEAL_LIMITS,
            initial_state=_x0(),
            state_scales=_scales(),
            uses_acceleration=True,
        ),
        DeviceModel(
            name="inerter",
            base="inerter",
            family="ideal",
            equation="(20)",
            description="ideal inerter F = b_L a, b_L = rho_l S_t A_p^2",
            state_names=(),
            state_units=(),
            limits=_IDEAL_LIMITS,
            initial_state=_x0(),
            state_scales=_scales(),
            uses_acceleration=True,
        ),
    )
}


@dataclass(frozen=True)
class ViscousParams:
    """Parameters of the viscous damper F = c v + c2 v|v| (linear and quadratic).

    Parameters
    ----------
    c : float
        Linear damping coefficient >= 0 [N s/m].
    c2 : float
        Quadratic damping coefficient >= 0 [N s^2/m^2] (default 0: the linear
        damper).  It has no small-signal part at rest (zero slope at v = 0);
        its describing function at y = Y sin(w t) is 8 c2 w Y / (3 pi) [N s/m].

    Examples
    --------
    >>> ViscousParams(65080.0).c
    65080.0
    >>> ViscousParams(0.0, c2=-1.0)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: viscous quadratic damping c2 must be >= 0 [N s^2/m^2], got -1
    """

    c: float
    c2: float = 0.0

    def __post_init__(self) -> None:
        from liquidamp.errors import check_nonnegative

        object.__setattr__(self, "c", check_nonnegative("viscous damping c", self.c, "N s/m"))
        object.__setattr__(self, "c2", check_nonnegative("viscous quadratic damping c2",
                                                         self.c2, "N s^2/m^2"))

    @property
    def friction_N(self) -> float:
        """No friction [N] (the DeviceModel interface asks for it)."""
        return 0.0

    def describing_damping(self, amplitude: float, omega: float) -> float:
        """Equivalent viscous damping c + 8 c2 w Y / (3 pi) at y = Y sin(w t) [N s/m].

        Parameters
        ----------
        amplitude : float
            Stroke amplitude Y >= 0 [m].
        omega : float
            Angular frequency w >= 0 [rad/s].

        Examples
        --------
        >>> round(ViscousParams(100.0, c2=3 * math.pi / 8).describing_damping(0.01, 100.0), 9)
        101.0
        """
        return self.c + 8.0 * self.c2 * omega * amplitude / (3.0 * math.pi)


#: The viscous damper F = c v + c2 v|v| [N] as a stateless device model (parameters:
#: ViscousParams).
VISCOUS = DeviceModel(
    name="viscous",
    base="viscous",
    family="ideal",
    equation="-",
    description="viscous damper F = c v + c2 v|v| (the host's own lag damper as a device; "
    "c2 = 0: linear)",
    state_names=(),
    state_units=(),
    limits="ideal element; the quadratic part has no small-signal stiffness at rest",
    initial_state=lambda p, y0=0.0: np.zeros(0),
    state_scales=lambda p: np.zeros(0),
)

#: Every base equation by name: the paper's family (:data:`REGISTRY`) and the viscous damper.
BASES: dict[str, DeviceModel] = {**REGISTRY, "viscous": VISCOUS}


def model_names() -> tuple[str, ...]:
    """Names of the registered device models.

    Examples
    --------
    >>> model_names()[:3]
    ('full', 'no_inertia', 'constant_bulk')
    """
    return tuple(REGISTRY)


def get_model(name: str | DeviceModel) -> DeviceModel:
    """Return the registered model ``name`` (a DeviceModel passes through).

    Raises
    ------
    ParameterError
        For an unknown name; the message lists the valid names.

    Examples
    --------
    >>> get_model("inertial_2state").state_names
    ('dp', 'q12')
    >>> get_model("ful")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown model 'ful'; valid: full, no_inertia, \
constant_bulk, volumetric, single_state, inertial, inertial_2state, maxwell, dashpot, spring, \
dashpot_inerter, inerter
    """
    if isinstance(name, DeviceModel):
        return name
    check_choice("model", name, REGISTRY)
    return REGISTRY[name]


