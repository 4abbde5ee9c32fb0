"""The device model family: eq. (10) of Titurus (2018) and every reduction (11)-(20).

Every variant is a :class:`DeviceModel`: data (name, equation, state names
and units, limits of validity) plus pure functions of ``(t, x, u, params)``,
where ``x`` is the state vector, ``u = (y, v, a)`` the piston stroke [m],
stroke rate [m/s] and stroke acceleration [m/s^2], and ``params`` a
:class:`~liquidamp.device.params.DeviceParams`.  Nothing is cached between
calls.  :data:`REGISTRY` maps each name to its model so that one contract
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

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from liquidamp.device.fluid import (
    bulk_modulus_gholizadeh,
    bulk_modulus_gholizadeh_dp,
    loss_flow,
    loss_flow_dp,
)
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, check_choice

__all__ = ["DeviceModel", "REGISTRY", "get_model", "model_names"]

Rhs = Callable[[float, np.ndarray, tuple, DeviceParams], np.ndarray]


@dataclass(frozen=True)
class DeviceModel:
    """One variant of the device model family.

    Attributes
    ----------
    name : str
        Registry name.
    equation : str
        Equation number(s) in Titurus (2018).
    description : str
        One line on what the variant keeps and drops.
    state_names : tuple of str
        Names of the states, in order.
    state_units : tuple of str
        Unit of each state.
    limits : str
        Limits of validity.
    rhs : callable
        ``rhs(t, x, u, params) -> dx/dt`` (array of len(state_names)).
    fluid_force : callable
        ``fluid_force(t, x, u, params) -> F`` without friction [N]; accepts
        ``x`` of shape (n_states, N) and ``u`` of arrays for vectorized use.
    initial_state : callable
        ``initial_state(params, y0) -> x0`` at rest with stroke ``y0`` [m].
    state_scales : callable
        ``state_scales(params) -> array`` of magnitudes used for absolute
        tolerances and finite-difference steps.
    jacobian : callable or None
        Analytic ``d rhs / d x``; None means finite differences.
    pressures : callable or None
        ``pressures(x, u, params) -> (p1, p2)`` [Pa] where chamber pressures
        are states.
    mass : callable or None
        ``mass(x, u, params) -> total fluid mass`` [kg] where defined.
    conserves_mass : bool
        True where the total mass is an exact invariant.
    uses_acceleration : bool
        True where the force depends on the stroke acceleration.
    requires : tuple of str
        Parameters that must be > 0 for this variant (checked by
        :meth:`check_params`).
    uses_bulk_law : bool
        True where the chamber bulk modulus follows ``params.bulk_law``
        (eq. 2 is singular at p = 0, so the run stops at the pressure floor);
        the constant-bulk reductions can pass through zero pressure, which
        the run reports as a warning.
    effects : tuple of Effect
        Add-on effects composed into this model by
        :func:`liquidamp.device.effects.with_effects`, in composition order
        (empty for a registered model).
    """

    name: str
    equation: str
    description: str
    state_names: tuple[str, ...]
    state_units: tuple[str, ...]
    limits: str
    rhs: Rhs
    fluid_force: Callable
    initial_state: Callable[[DeviceParams, float], np.ndarray]
    state_scales: Callable[[DeviceParams], np.ndarray]
    jacobian: Rhs | None = None
    pressures: Callable | None = None
    mass: Callable | None = None
    conserves_mass: bool = False
    uses_acceleration: bool = False
    requires: tuple[str, ...] = field(default=())
    uses_bulk_law: bool = False
    effects: tuple = field(default=())

    @property
    def n_states(self) -> int:
        """Number of states."""
        return len(self.state_names)

    def force(self, t, x, u, params: DeviceParams):
        """Load-cell force F = fluid force + |F_f| sign(v) [N] (vectorized)."""
        f = self.fluid_force(t, x, u, params)
        if params.friction_N > 0.0:
            f = f + params.friction_N * np.sign(u[1])
        return f

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


# ---------------------------------------------------------------------------
# shared pieces


def _volumes(y, p: DeviceParams):
    return p.V01 - p.A_p * y, p.V02 + p.A_p * y


def _bulk(pr: float, X0: float, p: DeviceParams) -> float:
    """Chamber bulk modulus under the parameter set's law; floors p at 1 Pa.

    The floor only keeps trial states of an implicit solver finite: the
    simulation stops with PressureError long before a pressure gets there.
    """
    if p.bulk_law == "constant":
        pr = p.p0
    return bulk_modulus_gholizadeh(max(pr, 1.0), p.B_l, X0, p.p0, p.n)


def _bulk_dp(pr: float, X0: float, p: DeviceParams) -> float:
    if p.bulk_law == "constant" or pr < 1.0:
        return 0.0
    return bulk_modulus_gholizadeh_dp(pr, p.B_l, X0, p.p0, p.n)


def _r(pr, B0: float, p: DeviceParams):
    """Explicit density of a constant-bulk chamber, r(p) = rho0 exp((p - p0)/B0)."""
    return p.rho0 * np.exp((pr - p.p0) / B0)


def _dp_force(t, x, u, p):
    return p.A_p * (x[0] - x[2])


def _scales_full(p):
    return np.array([p.p0, p.rho0, p.p0, p.rho0, p.rho0 * p.A_p * 0.01])


# ---------------------------------------------------------------------------
# eq. (10): full 5-state model


def _full_rhs(t, x, u, p):
    p1, r1, p2, r2, m = x
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    B1, B2 = _bulk(p1, p.X01, p), _bulk(p2, p.X02, p)
    w1 = p.A_p * v - m / r1
    w2 = -p.A_p * v + m / r2
    return np.array([
        B1 / V1 * w1,
        (r1 * p.A_p * v - m) / V1,
        B2 / V2 * w2,
        (-r2 * p.A_p * v + m) / V2,
        (p1 - p2 - p.g1 * m - p.g2 * m * abs(m)) / p.S_t,
    ])


def _full_jac(t, x, u, p):
    p1, r1, p2, r2, m = x
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    B1, B2 = _bulk(p1, p.X01, p), _bulk(p2, p.X02, p)
    J = np.zeros((5, 5))
    J[0, 0] = _bulk_dp(p1, p.X01, p) / V1 * (p.A_p * v - m / r1)
    J[0, 1] = B1 / V1 * m / r1**2
    J[0, 4] = -B1 / (V1 * r1)
    J[1, 1] = p.A_p * v / V1
    J[1, 4] = -1.0 / V1
    J[2, 2] = _bulk_dp(p2, p.X02, p) / V2 * (-p.A_p * v + m / r2)
    J[2, 3] = -B2 / V2 * m / r2**2
    J[2, 4] = B2 / (V2 * r2)
    J[3, 3] = -p.A_p * v / V2
    J[3, 4] = 1.0 / V2
    J[4, 0] = 1.0 / p.S_t
    J[4, 2] = -1.0 / p.S_t
    J[4, 4] = -(p.g1 + 2.0 * p.g2 * abs(m)) / p.S_t
    return J


def _mass_states(x, u, p):
    V1, V2 = _volumes(u[0], p)
    return x[1] * V1 + x[3] * V2


def _pressures_02(x, u, p):
    return x[0], x[2]


# ---------------------------------------------------------------------------
# eq. (11): no channel inertia, m12 from the analytic inverse of eq. (5)


def _noi_rhs(t, x, u, p):
    p1, r1, p2, r2 = x
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    m = loss_flow(p1 - p2, p.g1, p.g2)
    B1, B2 = _bulk(p1, p.X01, p), _bulk(p2, p.X02, p)
    return np.array([
        B1 / V1 * (p.A_p * v - m / r1),
        (r1 * p.A_p * v - m) / V1,
        B2 / V2 * (-p.A_p * v + m / r2),
        (-r2 * p.A_p * v + m) / V2,
    ])


def _noi_jac(t, x, u, p):
    p1, r1, p2, r2 = x
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    m = loss_flow(p1 - p2, p.g1, p.g2)
    dm = loss_flow_dp(p1 - p2, p.g1, p.g2)  # dm/dp1 = dm, dm/dp2 = -dm
    B1, B2 = _bulk(p1, p.X01, p), _bulk(p2, p.X02, p)
    J = np.zeros((4, 4))
    J[0, 0] = _bulk_dp(p1, p.X01, p) / V1 * (p.A_p * v - m / r1) - B1 / (V1 * r1) * dm
    J[0, 1] = B1 / V1 * m / r1**2
    J[0, 2] = B1 / (V1 * r1) * dm
    J[1, 0] = -dm / V1
    J[1, 1] = p.A_p * v / V1
    J[1, 2] = dm / V1
    J[2, 0] = B2 / (V2 * r2) * dm
    J[2, 2] = _bulk_dp(p2, p.X02, p) / V2 * (-p.A_p * v + m / r2) - B2 / (V2 * r2) * dm
    J[2, 3] = -B2 / V2 * m / r2**2
    J[3, 0] = dm / V2
    J[3, 2] = -dm / V2
    J[3, 3] = -p.A_p * v / V2
    return J


# ---------------------------------------------------------------------------
# eq. (13) and (14): constant bulk modulus, pressures only


def _cb_rhs(t, x, u, p):
    p1, p2 = x
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    m = loss_flow(p1 - p2, p.g1, p.g2)
    B1, B2 = p.B01, p.B02
    return np.array([
        B1 / V1 * (p.A_p * v - m / _r(p1, B1, p)),
        B2 / V2 * (-p.A_p * v + m / _r(p2, B2, p)),
    ])


def _vol_rhs(t, x, u, p):
    p1, p2 = x
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    q = loss_flow(p1 - p2, p.c1, p.c2)
    return np.array([
        p.B01 / V1 * (p.A_p * v - q),
        p.B02 / V2 * (-p.A_p * v + q),
    ])


def _mass_cb(x, u, p):
    V1, V2 = _volumes(u[0], p)
    return _r(x[0], p.B01, p) * V1 + _r(x[1], p.B02, p) * V2


def _pressures_01(x, u, p):
    return x[0], x[1]


def _force_01(t, x, u, p):
    return p.A_p * (x[0] - x[1])


# ---------------------------------------------------------------------------
# eq. (15): single differential-pressure state; eq. (16) linear = Maxwell


def _ss_rhs(t, x, u, p):
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    q = loss_flow(x[0], p.c1, p.c2)
    return np.array([(p.B01 / V1 + p.B02 / V2) * (p.A_p * v - q)])


def _force_dp0(t, x, u, p):
    return p.A_p * x[0]


def _maxwell_rhs(t, x, u, p):
    return np.array([p.k_D * u[1] - x[0] / p.T_D])


def _maxwell_jac(t, x, u, p):
    return np.array([[-1.0 / p.T_D]])


def _force_state0(t, x, u, p):
    return x[0]


# ---------------------------------------------------------------------------
# eq. (17) and (18): inertial models with constant bulk modulus


def _in_rhs(t, x, u, p):
    p1, p2, m = x
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    B1, B2 = p.B01, p.B02
    return np.array([
        B1 / V1 * (p.A_p * v - m / _r(p1, B1, p)),
        B2 / V2 * (-p.A_p * v + m / _r(p2, B2, p)),
        (p1 - p2 - p.g1 * m - p.g2 * m * abs(m)) / p.S_t,
    ])


def _in_mass(x, u, p):
    return _mass_cb(x, u, p)


def _i2_rhs(t, x, u, p):
    dp, q = x
    y, v = u[0], u[1]
    V1, V2 = _volumes(y, p)
    B = p.B01 / V1 + p.B02 / V2
    return np.array([
        B * (p.A_p * v - q),
        (dp - p.c1 * q - p.c2 * q * abs(q)) / p.L_t,
    ])


def _i2_jac(t, x, u, p):
    y = u[0]
    V1, V2 = _volumes(y, p)
    B = p.B01 / V1 + p.B02 / V2
    return np.array([[0.0, -B], [1.0 / p.L_t, -(p.c1 + 2.0 * p.c2 * abs(x[1])) / p.L_t]])


# ---------------------------------------------------------------------------
# ideal elements (no states)


def _no_rhs(t, x, u, p):
    return np.zeros(0)


def _dashpot_force(t, x, u, p):
    return p.c_L * u[1]


def _spring_force(t, x, u, p):
    return p.k_D * u[0]


def _di_force(t, x, u, p):
    return p.c_L * u[1] + p.b_L * u[2]


def _inerter_force(t, x, u, p):
    return p.b_L * u[2]


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
            equation="(10)",
            description="5-state nonlinear model: pressure-dependent bulk modulus, densities, "
            "channel inertance and linear-quadratic losses",
            state_names=("p1", "rho1", "p2", "rho2", "m12"),
            state_units=("Pa", "kg/m^3", "Pa", "kg/m^3", "kg/s"),
            limits="lumped channel flow (frequencies well below the line's first acoustic mode); "
            "chamber pressures > 0 (no cavitation unless the effect is added); |y| < V0/A_p",
            rhs=_full_rhs,
            jacobian=_full_jac,
            fluid_force=_dp_force,
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
            equation="(11)",
            description="eq. (10) with S_t = 0: m12 from the analytic inverse of eq. (5)",
            state_names=("p1", "rho1", "p2", "rho2"),
            state_units=("Pa", "kg/m^3", "Pa", "kg/m^3"),
            limits="channel inertance negligible: b_L omega << c_eq A_p^2; pressures > 0",
            rhs=_noi_rhs,
            jacobian=_noi_jac,
            fluid_force=_dp_force,
            initial_state=_x0("p0", "rho0", "p0", "rho0"),
            state_scales=_scales("p0", "rho0", "p0", "rho0"),
            pressures=_pressures_02,
            mass=_mass_states,
            conserves_mass=True,
            uses_bulk_law=True,
        ),
        DeviceModel(
            name="constant_bulk",
            equation="(13)",
            description="eq. (11) with constant bulk moduli B_i = B_i(p0); explicit densities "
            "r_i(p) keep the mass conserved",
            state_names=("p1", "p2"),
            state_units=("Pa", "Pa"),
            limits="pressure swings small against the scale on which B(p) changes (air-rich "
            "chambers stiffen strongly with pressure); no channel inertia",
            rhs=_cb_rhs,
            fluid_force=_force_01,
            initial_state=_x0("p0", "p0"),
            state_scales=_scales("p0", "p0"),
            pressures=_pressures_01,
            mass=_mass_cb,
            conserves_mass=True,
        ),
        DeviceModel(
            name="volumetric",
            equation="(14)",
            description="volumetric flow balance of each chamber; kept to show its "
            "non-physical drift (mass is not conserved)",
            state_names=("p1", "p2"),
            state_units=("Pa", "Pa"),
            limits="not physical: total mass drifts by (r2 - r1) q12 per unit time, so mean "
            "pressures drift; use constant_bulk (eq. 13) instead",
            rhs=_vol_rhs,
            fluid_force=_force_01,
            initial_state=_x0("p0", "p0"),
            state_scales=_scales("p0", "p0"),
            pressures=_pressures_01,
            mass=_mass_cb,
            conserves_mass=False,
        ),
        DeviceModel(
            name="single_state",
            equation="(15)",
            description="differential pressure only: d(dp)/dt = (B1/V1 + B2/V2)(A_p v - q12); "
            "eq. (16) is its small-stroke form",
            state_names=("dp",),
            state_units=("Pa",),
            limits="constant bulk moduli; mean pressure not tracked (no cavitation check); "
            "no channel inertia",
            rhs=_ss_rhs,
            fluid_force=_force_dp0,
            initial_state=_x0(0.0),
            state_scales=_scales(_dp_scale),
        ),
        DeviceModel(
            name="inertial",
            equation="(17)",
            description="constant bulk moduli with channel inertance: p1, p2, m12",
            state_names=("p1", "p2", "m12"),
            state_units=("Pa", "Pa", "kg/s"),
            limits="constant bulk moduli (small pressure swings); pressures > 0",
            rhs=_in_rhs,
            fluid_force=_force_01,
            initial_state=_x0("p0", "p0", 0.0),
            state_scales=_scales("p0", "p0", lambda p: p.rho0 * _flow_scale(p)),
            pressures=_pressures_01,
            mass=_in_mass,
            conserves_mass=True,
            requires=("S_t",),
        ),
        DeviceModel(
            name="inertial_2state",
            equation="(18)",
            description="differential pressure and volumetric channel flow: "
            "B^-1 d(dp)/dt = A_p v - q, L_t dq/dt = dp - c1 q - c2 q|q|",
            state_names=("dp", "q12"),
            state_units=("Pa", "m^3/s"),
            limits="constant bulk moduli, r1 = r2 (differential view only); mean pressure "
            "not tracked",
            rhs=_i2_rhs,
            jacobian=_i2_jac,
            fluid_force=_force_dp0,
            initial_state=_x0(0.0, 0.0),
            state_scales=_scales(_dp_scale, _flow_scale),
            requires=("S_t",),
        ),
        DeviceModel(
            name="maxwell",
            equation="(16), linear laminar",
            description="Maxwell unit dF/dt + F/T_D = k_D v, k_D = A_p^2 (B1/V01 + B2/V02), "
            "T_D = c1/(B1/V01 + B2/V02)",
            state_names=("F",),
            state_units=("N",),
            limits="small strokes, laminar loss only (c2 ignored), no inertia",
            rhs=_maxwell_rhs,
            jacobian=_maxwell_jac,
            fluid_force=_force_state0,
            initial_state=_x0(0.0),
            state_scales=_scales(lambda p: p.k_D * 1e-3),
            requires=("c1",),
        ),
        DeviceModel(
            name="dashpot",
            equation="(16) with B -> inf",
            description="viscous dashpot F = c_L v, c_L = c1 A_p^2",
            state_names=(),
            state_units=(),
            limits=_IDEAL_LIMITS,
            rhs=_no_rhs,
            fluid_force=_dashpot_force,
            initial_state=_x0(),
            state_scales=_scales(),
            requires=("c1",),
        ),
        DeviceModel(
            name="spring",
            equation="(16) with c1 -> inf (closed channel)",
            description="linear spring F = k_D y",
            state_names=(),
            state_units=(),
            limits=_IDEAL_LIMITS,
            rhs=_no_rhs,
            fluid_force=_spring_force,
            initial_state=_x0(),
            state_scales=_scales(),
        ),
        DeviceModel(
            name="dashpot_inerter",
            equation="(19)",
            description="dashpot and inerter in parallel, F = c_L v + b_L a",
            state_names=(),
            state_units=(),
            limits=_IDEAL_LIMITS,
            rhs=_no_rhs,
            fluid_force=_di_force,
            initial_state=_x0(),
            state_scales=_scales(),
            uses_acceleration=True,
        ),
        DeviceModel(
            name="inerter",
            equation="(20)",
            description="ideal inerter F = b_L a, b_L = rho_l S_t A_p^2",
            state_names=(),
            state_units=(),
            limits=_IDEAL_LIMITS,
            rhs=_no_rhs,
            fluid_force=_inerter_force,
            initial_state=_x0(),
            state_scales=_scales(),
            uses_acceleration=True,
        ),
    )
}


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


