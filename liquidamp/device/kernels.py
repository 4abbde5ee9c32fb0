"""The device physics, written once: every model of the family and every add-on effect.

This module holds the right-hand side, the Jacobian, the time derivative
along the stroke and the load-cell force of each model of Titurus (2018),
eqs. (10)-(20), and of each add-on effect, as numba-compiled functions on
plain float arrays.  Both engines call these same functions: the compiled
integrators of :mod:`liquidamp.coupled.fast` from inside their loops, the
scipy reference engine through :class:`~liquidamp.device.models.DeviceModel`'s
methods (``rhs``, ``jacobian``, ``force``).  There is no second copy of the
physics; independent checks come from closed forms, limits between models,
conservation laws, finite differences and a different integrator (scipy's
Radau) on the same equations.

A composed model travels as three arrays, built by
:meth:`~liquidamp.device.models.DeviceModel.packed`:

``spec`` (int64, ``S_*`` slots)
    the base model id (``M_*``), the state count, the base state count, the
    state index of each effect's states (-1: absent), the flags of the
    stateless effects and whether the analytic Jacobian applies;
``prm`` (float64, ``P_*`` slots)
    the device parameters (:func:`pack_params`);
``ep`` (float64, ``E_*`` slots, then one scale per state)
    the effect parameters and the state scales that size the
    finite-difference increments.

Composition (the order of :mod:`liquidamp.device.effects`): the kinematic
effects turn the measured rod stroke into the piston stroke the fluid sees
(freeplay outermost, then series compliance); the fluid effects act on the
chamber equations (direction-dependent loss coefficients ``S_ASYM``,
:func:`loss_params`; leakage and the relief valve ``S_RELIEF`` as second
flow paths, :func:`relief_flow`; cavitation on the pressure rates); on the
stateless dashpot-type bases the relief valve and the rebound ratio are
the exact force law :func:`relief_force`; smooth friction's bristle state
is driven by the rod velocity, or by the piston's behind a dead band (``S_ZPIST``: friction at
the piston, :func:`piston_contact`); the force effects add to the load-cell
force (Coulomb friction at the piston through the dead band's contact
factor, ``S_CPIST``; the elastomer branch ``S_IEL``, :func:`elastomer_rate`;
end stops ``S_STOP``, :func:`stop_force`).

The Jacobian is analytic for every base model, with leakage on ``full`` and
``no_inertia``, with smooth friction, the elastomer and direction-dependent
losses; compositions with cavitation, series compliance, freeplay, a relief
valve or leakage on the reductions use central differences of the same
compiled right-hand side (exact to about 1e-10 relative, which the
Rosenbrock stepper's error control absorbs).

References
----------
.. [1] B. Titurus, "Generalized Liquid-Based Damping Device for Passive
   Vibration Control", AIAA J. 56(10), 4134-4145, 2018, eqs. (2), (5),
   (10)-(20).
.. [2] C. Canudas de Wit et al., "A new model for control of systems with
   friction", IEEE TAC 40(3), 1995 (LuGre bristle state).
.. [3] M. A. Krasnosel'skii, A. V. Pokrovskii, Systems with Hysteresis,
   Springer, 1989 (play operator).
.. [4] H. E. Merritt, Hydraulic Control Systems, Wiley, 1967 (leakage,
   cavitation).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "MODEL_IDS", "BASE_STATES", "N_PRM", "N_SPEC", "N_EP", "pack_params",
    "bulk", "bulk_and_dp", "loss_flow", "loss_flow_dp",
    "lugre_rate", "play_contact", "piston_contact", "play_rate", "compliance_rate",
    "cavity_width", "cavity_rates", "c1_ramp", "relief_flow", "relief_force",
    "flow_direction", "loss_params", "elastomer_rate", "stop_force",
    "rotating_heads", "rotating_slope", "rotating_offset_slopes",
    "model_rhs", "model_jac", "model_rhs_t", "model_force", "friction_level", "force_series",
    "base_force_series",
]

#: Fast-math flags of the pure arithmetic kernels: reciprocal and contraction only
#: (no assumption of finite values, so NaN/inf checks keep working).
_FM = {"arcp", "contract"}

# ---------------------------------------------------------------- model ids
M_FULL = 0
M_NO_INERTIA = 1
M_CONSTANT_BULK = 2
M_VOLUMETRIC = 3
M_SINGLE_STATE = 4
M_INERTIAL = 5
M_INERTIAL_2STATE = 6
M_MAXWELL = 7
M_DASHPOT = 8
M_SPRING = 9
M_DASHPOT_INERTER = 10
M_INERTER = 11
M_VISCOUS = 12

#: Base equation name -> compiled id.
MODEL_IDS = {
    "full": M_FULL,
    "no_inertia": M_NO_INERTIA,
    "constant_bulk": M_CONSTANT_BULK,
    "volumetric": M_VOLUMETRIC,
    "single_state": M_SINGLE_STATE,
    "inertial": M_INERTIAL,
    "inertial_2state": M_INERTIAL_2STATE,
    "maxwell": M_MAXWELL,
    "dashpot": M_DASHPOT,
    "spring": M_SPRING,
    "dashpot_inerter": M_DASHPOT_INERTER,
    "inerter": M_INERTER,
    "viscous": M_VISCOUS,
}
#: Compiled id -> number of base states.
BASE_STATES = {0: 5, 1: 4, 2: 2, 3: 2, 4: 1, 5: 3, 6: 2, 7: 1, 8: 0, 9: 0, 10: 0, 11: 0, 12: 0}

# ------------------------------------------------------- parameter vector
P_AP, P_V01, P_V02, P_BL, P_X01, P_X02, P_P0, P_N, P_RHO0 = range(9)
P_G1, P_G2, P_C1, P_C2, P_ST, P_LT, P_B01, P_B02, P_KD, P_TD = range(9, 19)
P_CONSTB, P_FRIC, P_CV, P_CL, P_BLM = 19, 20, 21, 22, 23
#: Quadratic coefficient c2 [N s^2/m^2] of the viscous damper F = c v + c2 v|v|.
P_CV2 = 24
N_PRM = 25

# ------------------------------------------------------------ composition
S_MID, S_N, S_NB, S_ICAV, S_IC, S_IFP, S_IZ = range(7)
S_LEAK, S_COUL, S_MASS, S_OFF, S_ANALYTIC, S_I1, S_I2, S_EFFECTS = range(7, 15)
#: Composition flags of issue #12 (slots 15-20): friction behind the kinematic effects
#: (Coulomb, smooth), relief valve, direction-dependent losses, the elastomer branch's
#: state index, end stops.
S_CPIST, S_ZPIST, S_RELIEF, S_ASYM, S_IEL, S_STOP = range(15, 21)
#: Rotating frame (centrifugal field along the device axis): 1 when composed, else -1.
S_ROT = 21
N_SPEC = 22

E_LEAK, E_PV, E_KC, E_GAP, E_SFC, E_SIG, E_VS, E_SR, E_CF, E_MASS, E_OFF = range(11)
E_PR, E_GR = 11, 12  # relief valve: cracking pressure [Pa], conductance [m^3/(s Pa)]
E_RR = 13  # direction-dependent losses: rebound ratio [-]
E_K0, E_K1, E_C1E = 14, 15, 16  # elastomer: k0, k1 [N/m], c1 [N s/m]
E_KS, E_CS, E_CLR, E_CTR = 17, 18, 19, 20  # end stops: k [N/m], c [N s/m], clearance, centre [m]
#: Direction-dependent friction: reverse-to-forward level ratio of smooth friction (slot 21)
#: and of Coulomb friction (slot 22) [-] (:func:`friction_level`).
E_FRQ, E_CRQ = 21, 22
#: Rotating frame: rotor speed [rad/s], radius of the device mid-point [m], cos(axis angle) [-].
E_OMEGA, E_RM, E_COSA = 23, 24, 25
#: Smooth friction's transition exponent n [-] (:func:`lugre_rate`).
E_FEX = 26
#: The effect slots; the state scales follow from ``ep[N_EP]`` on.
N_EP = 27


def pack_params(params) -> np.ndarray:
    """Packed parameter vector (``P_*`` order) of a parameter set.

    Parameters
    ----------
    params : DeviceParams or ViscousParams
        Device parameters (SI); a ViscousParams fills only the damping
        coefficients ``c`` (slot ``P_CV``) and ``c2`` (slot ``P_CV2``).

    Returns
    -------
    ndarray
        Shape (N_PRM,).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> v = pack_params(preset("reference"))
    >>> v.shape, bool(v[P_AP] == preset("reference").A_p)
    ((25,), True)
    """
    v = np.zeros(N_PRM)
    if not hasattr(params, "A_p"):  # the viscous damper F = c v + c2 v|v|
        v[P_CV] = float(params.c)
        v[P_CV2] = float(getattr(params, "c2", 0.0))
        v[P_FRIC] = float(getattr(params, "friction_N", 0.0))
        return v
    p = params
    v[P_AP], v[P_V01], v[P_V02], v[P_BL] = p.A_p, p.V01, p.V02, p.B_l
    v[P_X01], v[P_X02], v[P_P0], v[P_N] = p.X01, p.X02, p.p0, p.n
    v[P_RHO0], v[P_G1], v[P_G2] = p.rho0, p.g1, p.g2
    v[P_C1], v[P_C2], v[P_ST], v[P_LT] = p.c1, p.c2, p.S_t, p.L_t
    v[P_B01], v[P_B02], v[P_KD] = p.B01, p.B02, p.k_D
    v[P_TD] = p.T_D if p.c1 > 0.0 else np.inf
    v[P_CONSTB] = 1.0 if p.bulk_law == "constant" else 0.0
    v[P_FRIC] = p.friction_N
    v[P_CL], v[P_BLM] = p.c_L, p.b_L
    return v


# ------------------------------------------------------------------ fluid laws
@njit(cache=True, error_model="numpy", fastmath=_FM)
def bulk(p, X0, prm):
    """Bulk modulus of eq. (2) under the parameter set's law; p floored at 1 Pa [Pa].

    The floor only keeps trial states of an implicit stepper finite: a run
    stops at the pressure floor long before a pressure gets there.
    """
    if prm[P_CONSTB] != 0.0:
        p = prm[P_P0]
    if p < 1.0:
        p = 1.0
    B_l, n = prm[P_BL], prm[P_N]
    r = (prm[P_P0] / p) ** (1.0 / n)
    return B_l * (1.0 - X0 + X0 * r) / (1.0 - X0 + B_l * X0 * r / (n * p))


@njit(cache=True, error_model="numpy", fastmath=_FM)
def bulk_and_dp(p, X0, prm):
    """Bulk modulus of eq. (2) [Pa] and its slope dB/dp [-] (0 for the constant law)."""
    if prm[P_CONSTB] != 0.0 or p < 1.0:
        return bulk(p, X0, prm), 0.0
    B_l, n, p0 = prm[P_BL], prm[P_N], prm[P_P0]
    r = (p0 / p) ** (1.0 / n)
    num = 1.0 - X0 + X0 * r
    den = 1.0 - X0 + B_l * X0 * r / (n * p)
    dr = -r / (n * p)
    dnum = X0 * dr
    dden = B_l * X0 / n * (dr / p - r / (p * p))
    return B_l * num / den, B_l * (dnum * den - num * dden) / (den * den)


@njit(cache=True, error_model="numpy", fastmath=_FM)
def loss_flow(dp, k1, k2):
    """Analytic inverse of eq. (5), dp = k1 q + k2 q|q|, cancellation-free [flow unit]."""
    if dp == 0.0:
        return 0.0
    return 2.0 * dp / (k1 + math.sqrt(k1 * k1 + 4.0 * k2 * abs(dp)))


@njit(cache=True, error_model="numpy", fastmath=_FM)
def loss_flow_dp(dp, k1, k2):
    """d(flow)/d(dp) of :func:`loss_flow` [flow unit / Pa]."""
    return 1.0 / max(math.sqrt(k1 * k1 + 4.0 * k2 * abs(dp)), 1e-300)


@njit(cache=True, error_model="numpy", fastmath=_FM)
def r_const(p, B0, prm):
    """Density of a constant-bulk chamber r(p) = rho0 exp((p - p0)/B0) [kg/m^3]."""
    return prm[P_RHO0] * math.exp((p - prm[P_P0]) / B0)


# ------------------------------------------------------------ effect laws
@njit(cache=True, error_model="numpy")
def _stribeck(v, v_s, static_ratio):
    return 1.0 + (static_ratio - 1.0) * math.exp(-(v / v_s) ** 2)


@njit(cache=True, error_model="numpy")
def lugre_rate(v, z, force, stiffness, v_s, static_ratio, exponent=1.0):
    """dz/dt of the normalized LuGre bristle state z = F_fr / F_c [1/s].

    ``dz/dt = (sigma0 / F_c) (v - |v| h)``, ``h = (z / g) |z / g|^(n - 1)``,
    ``g = 1 + (r - 1) exp(-(v / v_s)^2)``: steady sliding gives
    F_fr = F_c g(v) sign(v), the Stribeck curve; at reversal the force
    changes over a pre-sliding displacement of about F_c / sigma0 instead
    of jumping.  The transition exponent n >= 1 shapes that change as in
    the Bouc-Wen law: n = 1 is LuGre's (and Dahl's) exponential approach;
    a large n keeps the bristle stiff (slope sigma0) until the force is
    near its sliding level and then slips sharply, the elastic-plastic
    (Jenkins) element.  Zero force gives 0.

    Examples
    --------
    >>> lugre_rate(0.01, 1.0, 30.0, 1e5, 0.005, 1.0)   # steady sliding: z = 1 holds
    0.0
    >>> lugre_rate(0.01, 0.5, 30.0, 1e5, 0.005, 1.0, 8.0) > lugre_rate(0.01, 0.5, 30.0, 1e5,
    ...                                                                 0.005, 1.0)
    True
    """
    if force <= 0.0:
        return 0.0
    s = z / _stribeck(v, v_s, static_ratio)
    h = s if exponent == 1.0 else s * abs(s) ** (exponent - 1.0)
    return stiffness / force * (v - abs(v) * h)


@njit(cache=True, error_model="numpy")
def _smoothstep(s):
    if s <= 0.0:
        return 0.0
    if s >= 1.0:
        return 1.0
    return s * s * (3.0 - 2.0 * s)


@njit(cache=True, error_model="numpy")
def play_contact(e, v, gap):
    """Contact factor of the dead band's driven side, 0 in the gap and 1 in contact [-].

    ``S(s)``, ``s = (e sign(v) - gap) / delta + 1`` with ``e = y - y_fp`` and
    the smoothing width ``delta = 0.05 gap + 1e-7 m`` (:func:`play_rate`); 0
    at v = 0.

    Examples
    --------
    >>> play_contact(0.0, 0.1, 1e-3), play_contact(1e-3, 0.1, 1e-3)
    (0.0, 1.0)
    """
    delta = 0.05 * gap + 1.0e-7
    if v > 0.0:
        s = (e - gap) / delta + 1.0
    elif v < 0.0:
        s = (-e - gap) / delta + 1.0
    else:
        return 0.0
    return _smoothstep(s)


#: Width of the bristle contact's switch in units of the pre-sliding stroke F_c / sigma0
#: [-] (:func:`piston_contact`): the bristle force left in the gap is of this order.
Z_HOLD = 0.01


@njit(cache=True, error_model="numpy")
def piston_contact(e, z, lam, gap):
    """Contact factor of a dead band in series with LuGre bristles (friction at the piston) [-].

    The driven side (the piston with its seal) is massless, so the bristle
    force F_c z must pass through the contact.  The dead band and the
    bristle spring are in series between the rod and the bristle root
    ``w = y_fp - lam z`` (``lam = F_c / sigma0`` [m], the pre-sliding
    stroke): the contact is closed while |y - w| = |e + lam z| exceeds the
    gap, i.e. while the rod pushes into it or the loaded bristles press the
    piston against a rod that backs off (the elastic spring-back of the
    pre-sliding deflection); it opens when their force has gone.
    ``C = S((|e + lam z| - gap) / delta_c + 1)``, S the C1 smoothstep,
    ``delta_c = min(0.05 gap + 1e-7 m, Z_HOLD lam)``: the bristle force left
    in the gap is of order ``Z_HOLD`` F_c (:data:`Z_HOLD` = 0.01).  The
    piston then moves at C v and the bristles are driven by it.

    Examples
    --------
    >>> piston_contact(1e-3, 0.5, 1e-4, 1e-3)   # loaded bristles: held (any direction)
    1.0
    >>> piston_contact(0.5e-3, 0.0, 1e-4, 1e-3)  # unloaded, inside the gap: open
    0.0
    """
    delta = min(0.05 * gap + 1.0e-7, Z_HOLD * lam)
    return _smoothstep((abs(e + lam * z) - gap) / delta + 1.0)


@njit(cache=True, error_model="numpy")
def play_rate(y, y_fp, v, gap):
    """Rate of the driven side of a dead band of half-width ``gap`` [m/s].

    The play operator: the driven side stays put while the rod crosses the
    gap and follows the rod once in contact, ``dy_fp/dt = v S(s)``, with
    ``s = (e sign(v) - gap) / delta + 1``, ``e = y - y_fp``, a smoothing
    width ``delta = 0.05 gap + 1e-7 m`` and the C1 smoothstep
    ``S(s) = s^2 (3 - 2 s)`` on [0, 1] (0 below, 1 above): the right-hand
    side and its Jacobian stay continuous, so that the stiff stepper keeps
    its order through each contact (a clipped ramp took RODAS4 ten times the
    steps); e sign(v) settles within delta of the gap.

    Examples
    --------
    >>> play_rate(0.0, 0.0, 0.1, 1e-3)     # inside the gap: the driven side stays
    0.0
    >>> play_rate(1e-3, 0.0, 0.1, 1e-3)    # in contact: it follows the rod
    0.1
    """
    return v * play_contact(y - y_fp, v, gap)


@njit(cache=True, error_model="numpy")
def compliance_rate(v, k, g0, g1):
    """Piston velocity behind a series spring k [m/s].

    The massless piston balances the spring: k (y - y_p) = F_fluid.
    Differentiating, k (v - v_p) = dF/dt = g0 + g1 v_p, with g0, g1 the
    fluid force rate at v_p = 0 and its slope in v_p (the chamber equations
    are affine in the piston velocity).  An infinite k returns v.

    Examples
    --------
    >>> compliance_rate(0.1, math.inf, 5.0, 2.0)
    0.1
    >>> compliance_rate(0.1, 1e6, 0.0, 1e6)     # equal springs share the stroke
    0.05
    """
    if math.isinf(k):
        return v
    return (k * v - g0) / (k + g1)


@njit(cache=True, error_model="numpy")
def cavity_width(p_v):
    """Pressure width of the regularised cavity switch [Pa]: 0.05 p_v + 500 Pa.

    Examples
    --------
    >>> cavity_width(2339.0)
    616.95
    """
    return 0.05 * p_v + 500.0


@njit(cache=True, error_model="numpy")
def cavity_rates(p, dp_base, Vc, V, B, p_v):
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

    Examples
    --------
    >>> cavity_rates(1e5, -1e6, 0.0, 1e-4, 1e8, 2339.0)   # far above p_v: no cavity
    (-1000000.0, -0.0)
    """
    w = dp_base * V / B
    delta = cavity_width(p_v)
    if w < 0.0:
        sigma = _smoothstep((p_v + delta - p) / delta)
    else:
        sigma = _smoothstep(max(Vc, 0.0) * B / (V * delta))
    return (1.0 - sigma) * dp_base, -sigma * w


@njit(cache=True, error_model="numpy")
def _head_mean(a, b, rc):
    """Mean over the axis interval [a, b] of the head h(s) = rc s + s^2/2 [m^2]."""
    return 0.5 * rc * (a + b) + (a * a + a * b + b * b) / 6.0


@njit(cache=True, error_model="numpy")
def _head_min(a, b, rc):
    """Least head h(s) = rc s + s^2/2 on [a, b]: at the point nearest the shaft [m^2]."""
    s = min(max(-rc, a), b)
    return rc * s + 0.5 * s * s


@njit(cache=True, error_model="numpy")
def rotating_heads(y, prm, ep):
    """(dp_c, o1, o2) of the rotating frame at piston stroke y [m]: pressures [Pa].

    Axis coordinate s from the device mid-point (the piston at zero stroke,
    at radius r_m) towards chamber 2; the axis makes the angle theta with
    the radial direction, so a point at s is at radius
    r(s)^2 = r_m^2 + 2 r_m cos(theta) s + s^2 and the centrifugal potential
    per unit mass is -Omega^2 r^2 / 2.  Chamber 1 spans [-L1, -y], chamber
    2 [-y, L2] (L_i = V0i / A_p).  With the head h(s) = r_m cos(theta) s +
    s^2/2 (the integral of the radius projected on the axis, r . e ds) and
    its volume mean h_i over chamber i, for the liquid density rho_l:

    - ``dp_c = rho_l Omega^2 (h_2 - h_1)``: the centrifugal pressure rise
      from the lumped (volume-mean) pressure of chamber 1 to that of chamber
      2 along any path (the field is conservative, so the channel's route
      does not enter), = rho_l Omega^2 r_m cos(theta) (L1 + L2)/2 + rho_l
      Omega^2 ((L2^2 - L1^2)/3 - (L1 + L2) y/3)/2;
    - ``o_i = rho_l Omega^2 (min h over chamber i - h_i) <= 0``: the
      pressure at the chamber's innermost point (its inboard end) minus its
      lumped pressure.

    Examples
    --------
    >>> prm = np.zeros(N_PRM); ep = np.zeros(N_EP)
    >>> prm[P_AP], prm[P_V01], prm[P_V02], prm[P_RHO0] = 1e-3, 2e-5, 2e-5, 1000.0
    >>> ep[E_OMEGA], ep[E_RM], ep[E_COSA] = 10.0, 0.5, 1.0
    >>> [round(float(q), 9) for q in rotating_heads(0.0, prm, ep)]   # 1000 * 100 * 0.5 * 0.02
    [1000.0, -486.666666667, -506.666666667]
    """
    k = prm[P_RHO0] * ep[E_OMEGA] * ep[E_OMEGA]
    rc = ep[E_RM] * ep[E_COSA]
    L1 = prm[P_V01] / prm[P_AP]
    L2 = prm[P_V02] / prm[P_AP]
    h1 = _head_mean(-L1, -y, rc)
    h2 = _head_mean(-y, L2, rc)
    return k * (h2 - h1), k * (_head_min(-L1, -y, rc) - h1), k * (_head_min(-y, L2, rc) - h2)


@njit(cache=True, error_model="numpy")
def rotating_offset_slopes(y, prm, ep):
    """(do1/dy, do2/dy) of the inboard offsets of :func:`rotating_heads` [Pa/m].

    The chambers' means and, where the least head sits at the piston face,
    their least heads move with the piston: at fixed lumped pressures the
    inboard-end pressures change at (do_i/dy) v.
    """
    k = prm[P_RHO0] * ep[E_OMEGA] * ep[E_OMEGA]
    rc = ep[E_RM] * ep[E_COSA]
    L1 = prm[P_V01] / prm[P_AP]
    L2 = prm[P_V02] / prm[P_AP]
    d1 = rc / 2.0 - (L1 + 2.0 * y) / 6.0  # -d(mean head)/dy, chamber 1 on [-L1, -y]
    d2 = rc / 2.0 + (L2 - 2.0 * y) / 6.0  # chamber 2 on [-y, L2]
    if -rc > -y:  # chamber 1's least head at its piston face s = -y
        d1 -= rc - y
    if -rc < -y:  # chamber 2's least head at its piston face
        d2 -= rc - y
    return k * d1, k * d2


@njit(cache=True, error_model="numpy")
def rotating_slope(prm, ep):
    """d(dp_c)/dy of :func:`rotating_heads`: -rho_l Omega^2 (L1 + L2)/6 [Pa/m].

    The lumped points move with the piston while their separation stays
    (L1 + L2)/2; only the s^2/2 part of the head sees the shift.
    """
    return -prm[P_RHO0] * ep[E_OMEGA] * ep[E_OMEGA] * (prm[P_V01] + prm[P_V02]) / (
        6.0 * prm[P_AP])


@njit(cache=True, error_model="numpy")
def c1_ramp(u, w):
    """C1 ramp: 0 for u <= 0, u for u >= w, u^2 (2w - u) / w^2 between [unit of u].

    Exact beyond the width w (its slope rises from 0 to at most 4/3 and is 1
    at w), so that closed forms hold past the onset while stiff steppers
    keep their order through it.

    Examples
    --------
    >>> c1_ramp(-1.0, 0.1), c1_ramp(0.05, 0.1), c1_ramp(2.0, 0.1)
    (0.0, 0.0375, 2.0)
    """
    if u <= 0.0:
        return 0.0
    if u >= w:
        return u
    return u * u * (2.0 * w - u) / (w * w)


@njit(cache=True, error_model="numpy")
def relief_flow(dp, p_r, G):
    """Volumetric flow through a relief (blow-off) valve [m^3/s] at pressure difference dp.

    ``q = sign(dp) G R(|dp| - p_r)``: closed below the cracking pressure p_r
    [Pa], then a conductance G [m^3/(s Pa)]; R the :func:`c1_ramp` over the
    width ``0.01 p_r + 1 Pa``.

    Examples
    --------
    >>> relief_flow(1e6, 2e6, 1e-9), relief_flow(-3e6, 2e6, 1e-9)
    (0.0, -0.001)
    """
    q = G * c1_ramp(abs(dp) - p_r, 0.01 * p_r + 1.0)
    return q if dp >= 0.0 else -q


@njit(cache=True, error_model="numpy")
def relief_force(v, c, F_r, g):
    """Force of a dashpot c [N s/m] with a relief valve, exact static law [N].

    ``F = sign(v) min(c |v|, F_r + c_o (|v| - F_r / c))``, ``c_o = c / (1 +
    c g)``: the channel carries the flow up to the cracking force F_r =
    p_r A [N]; above it the valve's path (``g = G / A^2`` [m/(N s)]) opens
    in parallel and the slope falls to c_o.  No regularisation (no state).

    Examples
    --------
    >>> relief_force(0.01, 1e5, 500.0, 0.0)      # below cracking: c v
    1000.0
    >>> relief_force(-0.01, 1e5, 500.0, 4e-5)    # above: 500 + 2e4 (0.01 - 0.005)
    -600.0
    """
    a = abs(v)
    f = c * a
    if f > F_r:
        f = F_r + c / (1.0 + c * g) * (a - F_r / c)
    return f if v >= 0.0 else -f


# --------------------------------------------------------------- base models
@njit(cache=True, error_model="numpy", fastmath=_FM)
def base_rhs(mid, x, y, v, prm, kL, dpc, out):
    """dx/dt of base model ``mid`` at piston stroke (y [m], v [m/s]), into ``out``.

    ``kL`` is a laminar leakage conductance [m^3/(s Pa)] in parallel with the
    channel (mass flow rho_l kL (p1 - p2 + dpc)); 0 for none.  ``dpc`` is a
    body-force pressure rise from chamber 1 to chamber 2 [Pa] (the rotating
    frame, :func:`rotating_heads`; 0 for none): every flow path (channel
    momentum, loss relation, leakage) is driven by p1 - p2 + dpc.
    Stateless models write nothing.
    """
    Ap = prm[P_AP]
    V1 = prm[P_V01] - Ap * y
    V2 = prm[P_V02] + Ap * y
    mL = 0.0
    if mid == M_FULL or mid == M_NO_INERTIA:
        p1, r1, p2, r2 = x[0], x[1], x[2], x[3]
        dp = p1 - p2 + dpc
        if mid == M_FULL:
            m = x[4]
        else:
            m = loss_flow(dp, prm[P_G1], prm[P_G2])
        mt = m + prm[P_RHO0] * kL * dp
        B1 = bulk(p1, prm[P_X01], prm)
        B2 = bulk(p2, prm[P_X02], prm)
        out[0] = B1 / V1 * (Ap * v - mt / r1)
        out[1] = (r1 * Ap * v - mt) / V1
        out[2] = B2 / V2 * (-Ap * v + mt / r2)
        out[3] = (-r2 * Ap * v + mt) / V2
        if mid == M_FULL:
            out[4] = (dp - prm[P_G1] * m - prm[P_G2] * m * abs(m)) / prm[P_ST]
        return
    if mid == M_CONSTANT_BULK or mid == M_VOLUMETRIC or mid == M_INERTIAL:
        p1, p2 = x[0], x[1]
        dp = p1 - p2 + dpc
        B1, B2 = prm[P_B01], prm[P_B02]
        r1 = r_const(p1, B1, prm)
        r2 = r_const(p2, B2, prm)
        if kL != 0.0:
            mL = prm[P_RHO0] * kL * dp
        if mid == M_VOLUMETRIC:
            q = loss_flow(dp, prm[P_C1], prm[P_C2])
            out[0] = B1 / V1 * (Ap * v - q - mL / r1)
            out[1] = B2 / V2 * (-Ap * v + q + mL / r2)
            return
        if mid == M_INERTIAL:
            m = x[2]
            out[2] = (dp - prm[P_G1] * m - prm[P_G2] * m * abs(m)) / prm[P_ST]
        else:
            m = loss_flow(dp, prm[P_G1], prm[P_G2])
        out[0] = B1 / V1 * (Ap * v - (m + mL) / r1)
        out[1] = B2 / V2 * (-Ap * v + (m + mL) / r2)
        return
    if mid == M_SINGLE_STATE:
        q = loss_flow(x[0] + dpc, prm[P_C1], prm[P_C2])
        out[0] = (prm[P_B01] / V1 + prm[P_B02] / V2) * (Ap * v - q)
    elif mid == M_INERTIAL_2STATE:
        q = x[1]
        B = prm[P_B01] / V1 + prm[P_B02] / V2
        out[0] = B * (Ap * v - q)
        out[1] = (x[0] + dpc - prm[P_C1] * q - prm[P_C2] * q * abs(q)) / prm[P_LT]
    elif mid == M_MAXWELL:
        out[0] = prm[P_KD] * v - x[0] / prm[P_TD]


#: :func:`base_rhs` inlined into the explicit stepper, where it is most of the work per
#: step (elsewhere it is called, which keeps the compile time down).
base_rhs_inline = njit(cache=True, error_model="numpy", fastmath=_FM,
                       inline="always")(base_rhs.py_func)


@njit(cache=True, error_model="numpy", fastmath=_FM)
def base_rhs_t(mid, x, y, v, yd, a, prm, kL, out):
    """Partial derivative d rhs / dt of base model ``mid`` at fixed x through the stroke.

    ``yd`` = dy/dt [m/s] and ``a`` = dv/dt [m/s^2] of the stroke as
    evaluated (the leakage flow does not depend on the stroke).
    """
    Ap = prm[P_AP]
    V1 = prm[P_V01] - Ap * y
    V2 = prm[P_V02] + Ap * y
    if mid == M_MAXWELL:
        out[0] = prm[P_KD] * a
        return
    if mid == M_SINGLE_STATE or mid == M_INERTIAL_2STATE:
        if mid == M_SINGLE_STATE:
            q = loss_flow(x[0], prm[P_C1], prm[P_C2])
        else:
            q = x[1]
            out[1] = 0.0
        B1, B2 = prm[P_B01], prm[P_B02]
        out[0] = (B1 / (V1 * V1) - B2 / (V2 * V2)) * Ap * yd * (Ap * v - q) + (
            B1 / V1 + B2 / V2) * Ap * a
        return
    if mid == M_FULL or mid == M_NO_INERTIA:
        p1, r1, p2, r2 = x[0], x[1], x[2], x[3]
        if mid == M_FULL:
            m = x[4]
            out[4] = 0.0
        else:
            m = loss_flow(p1 - p2, prm[P_G1], prm[P_G2])
        m = m + prm[P_RHO0] * kL * (p1 - p2)
        B1 = bulk(p1, prm[P_X01], prm)
        B2 = bulk(p2, prm[P_X02], prm)
        w1 = Ap * v - m / r1
        w2 = -Ap * v + m / r2
        out[0] = B1 / V1 * (Ap * yd / V1 * w1 + Ap * a)
        out[1] = (r1 * Ap * a + (r1 * Ap * v - m) / V1 * Ap * yd) / V1
        out[2] = B2 / V2 * (-Ap * yd / V2 * w2 - Ap * a)
        out[3] = (-r2 * Ap * a - (-r2 * Ap * v + m) / V2 * Ap * yd) / V2
        return
    if mid != M_CONSTANT_BULK and mid != M_VOLUMETRIC and mid != M_INERTIAL:
        return
    B1, B2 = prm[P_B01], prm[P_B02]
    r1 = r_const(x[0], B1, prm)
    r2 = r_const(x[1], B2, prm)
    mL = prm[P_RHO0] * kL * (x[0] - x[1])
    if mid == M_VOLUMETRIC:
        q = loss_flow(x[0] - x[1], prm[P_C1], prm[P_C2])
        w1 = Ap * v - q - mL / r1
        w2 = -Ap * v + q + mL / r2
    else:
        if mid == M_INERTIAL:
            m = x[2]
            out[2] = 0.0
        else:
            m = loss_flow(x[0] - x[1], prm[P_G1], prm[P_G2])
        w1 = Ap * v - (m + mL) / r1
        w2 = -Ap * v + (m + mL) / r2
    out[0] = B1 / V1 * (Ap * yd / V1 * w1 + Ap * a)
    out[1] = B2 / V2 * (-Ap * yd / V2 * w2 - Ap * a)


@njit(cache=True, error_model="numpy", fastmath=_FM)
def base_jac(mid, x, y, v, prm, kL, J):
    """Analytic Jacobian d rhs / dx of base model ``mid`` into ``J`` (its block zeroed here).

    Leakage (``kL``) is included for ``full`` and ``no_inertia``; the
    reductions with leakage use :func:`model_jac`'s differences.
    """
    nb = BASE_N[mid]
    for i in range(nb):
        for j in range(nb):
            J[i, j] = 0.0
    Ap = prm[P_AP]
    V1 = prm[P_V01] - Ap * y
    V2 = prm[P_V02] + Ap * y
    if mid == M_FULL or mid == M_NO_INERTIA:
        p1, r1, p2, r2 = x[0], x[1], x[2], x[3]
        dmL = prm[P_RHO0] * kL
        if mid == M_FULL:
            m = x[4]
            dm = dmL  # d(total flow)/dp1 = -d/dp2
        else:
            m = loss_flow(p1 - p2, prm[P_G1], prm[P_G2])
            dm = loss_flow_dp(p1 - p2, prm[P_G1], prm[P_G2]) + dmL
        mt = m + dmL * (p1 - p2)
        X1, X2 = prm[P_X01], prm[P_X02]
        B1, dB1 = bulk_and_dp(p1, X1, prm)
        B2, dB2 = bulk_and_dp(p2, X2, prm)
        J[0, 0] = dB1 / V1 * (Ap * v - mt / r1) - B1 / (V1 * r1) * dm
        J[0, 1] = B1 / V1 * mt / (r1 * r1)
        J[0, 2] = B1 / (V1 * r1) * dm
        J[1, 0] = -dm / V1
        J[1, 1] = Ap * v / V1
        J[1, 2] = dm / V1
        J[2, 0] = B2 / (V2 * r2) * dm
        J[2, 2] = dB2 / V2 * (-Ap * v + mt / r2) - B2 / (V2 * r2) * dm
        J[2, 3] = -B2 / V2 * mt / (r2 * r2)
        J[3, 0] = dm / V2
        J[3, 2] = -dm / V2
        J[3, 3] = -Ap * v / V2
        if mid == M_FULL:
            S = prm[P_ST]
            J[0, 4] = -B1 / (V1 * r1)
            J[1, 4] = -1.0 / V1
            J[2, 4] = B2 / (V2 * r2)
            J[3, 4] = 1.0 / V2
            J[4, 0] = 1.0 / S
            J[4, 2] = -1.0 / S
            J[4, 4] = -(prm[P_G1] + 2.0 * prm[P_G2] * abs(m)) / S
    elif mid == M_CONSTANT_BULK:
        p1, p2 = x[0], x[1]
        m = loss_flow(p1 - p2, prm[P_G1], prm[P_G2])
        dm = loss_flow_dp(p1 - p2, prm[P_G1], prm[P_G2])
        B1, B2 = prm[P_B01], prm[P_B02]
        r1, r2 = r_const(p1, B1, prm), r_const(p2, B2, prm)
        J[0, 0] = -B1 / (V1 * r1) * dm + m / (V1 * r1)
        J[0, 1] = B1 / (V1 * r1) * dm
        J[1, 0] = B2 / (V2 * r2) * dm
        J[1, 1] = -B2 / (V2 * r2) * dm - m / (V2 * r2)
    elif mid == M_VOLUMETRIC:
        dq = loss_flow_dp(x[0] - x[1], prm[P_C1], prm[P_C2])
        J[0, 0] = -prm[P_B01] / V1 * dq
        J[0, 1] = prm[P_B01] / V1 * dq
        J[1, 0] = prm[P_B02] / V2 * dq
        J[1, 1] = -prm[P_B02] / V2 * dq
    elif mid == M_SINGLE_STATE:
        dq = loss_flow_dp(x[0], prm[P_C1], prm[P_C2])
        J[0, 0] = -(prm[P_B01] / V1 + prm[P_B02] / V2) * dq
    elif mid == M_INERTIAL:
        p1, p2, m = x[0], x[1], x[2]
        B1, B2 = prm[P_B01], prm[P_B02]
        r1, r2 = r_const(p1, B1, prm), r_const(p2, B2, prm)
        S = prm[P_ST]
        J[0, 0] = m / (V1 * r1)
        J[0, 2] = -B1 / (V1 * r1)
        J[1, 1] = -m / (V2 * r2)
        J[1, 2] = B2 / (V2 * r2)
        J[2, 0] = 1.0 / S
        J[2, 1] = -1.0 / S
        J[2, 2] = -(prm[P_G1] + 2.0 * prm[P_G2] * abs(m)) / S
    elif mid == M_INERTIAL_2STATE:
        B = prm[P_B01] / V1 + prm[P_B02] / V2
        J[0, 1] = -B
        J[1, 0] = 1.0 / prm[P_LT]
        J[1, 1] = -(prm[P_C1] + 2.0 * prm[P_C2] * abs(x[1])) / prm[P_LT]
    elif mid == M_MAXWELL:
        J[0, 0] = -1.0 / prm[P_TD]


#: Number of base states by model id (a tuple, so that compiled code can index it).
BASE_N = tuple(BASE_STATES[i] for i in range(len(BASE_STATES)))


@njit(cache=True, error_model="numpy", fastmath=_FM)
def full_all(x, y, v, yd, a, prm, kL, f, J, ft):
    """:func:`base_rhs`, :func:`base_jac` (non-zero entries only) and :func:`base_rhs_t`
    of the full model (eq. 10) at one point, sharing the two bulk-modulus evaluations."""
    Ap = prm[P_AP]
    V1 = prm[P_V01] - Ap * y
    V2 = prm[P_V02] + Ap * y
    p1, r1, p2, r2, m = x[0], x[1], x[2], x[3], x[4]
    dm = prm[P_RHO0] * kL
    mt = m + dm * (p1 - p2)
    B1, dB1 = bulk_and_dp(p1, prm[P_X01], prm)
    B2, dB2 = bulk_and_dp(p2, prm[P_X02], prm)
    S = prm[P_ST]
    w1 = Ap * v - mt / r1
    w2 = -Ap * v + mt / r2
    f[0] = B1 / V1 * w1
    f[1] = (r1 * Ap * v - mt) / V1
    f[2] = B2 / V2 * w2
    f[3] = (-r2 * Ap * v + mt) / V2
    f[4] = (p1 - p2 - prm[P_G1] * m - prm[P_G2] * m * abs(m)) / S
    c1 = B1 / (V1 * r1)
    c2 = B2 / (V2 * r2)
    J[0, 0] = dB1 / V1 * w1 - c1 * dm
    J[0, 1] = B1 / V1 * mt / (r1 * r1)
    J[0, 2] = c1 * dm
    J[0, 4] = -c1
    J[1, 0] = -dm / V1
    J[1, 1] = Ap * v / V1
    J[1, 2] = dm / V1
    J[1, 4] = -1.0 / V1
    J[2, 0] = c2 * dm
    J[2, 2] = dB2 / V2 * w2 - c2 * dm
    J[2, 3] = -B2 / V2 * mt / (r2 * r2)
    J[2, 4] = c2
    J[3, 0] = dm / V2
    J[3, 2] = -dm / V2
    J[3, 3] = -Ap * v / V2
    J[3, 4] = 1.0 / V2
    J[4, 0] = 1.0 / S
    J[4, 2] = -1.0 / S
    J[4, 4] = -(prm[P_G1] + 2.0 * prm[P_G2] * abs(m)) / S
    ft[0] = B1 / V1 * (Ap * yd / V1 * w1 + Ap * a)
    ft[1] = (r1 * Ap * a + (r1 * Ap * v - mt) / V1 * Ap * yd) / V1
    ft[2] = B2 / V2 * (-Ap * yd / V2 * w2 - Ap * a)
    ft[3] = (-r2 * Ap * a - (-r2 * Ap * v + mt) / V2 * Ap * yd) / V2
    ft[4] = 0.0


@njit(cache=True, error_model="numpy")
def base_force(mid, x, y, v, a, prm):
    """Fluid force of base model ``mid`` [N] at piston stroke (y, v, a), no friction."""
    Ap = prm[P_AP]
    if mid == M_FULL or mid == M_NO_INERTIA:
        return Ap * (x[0] - x[2])
    if mid == M_CONSTANT_BULK or mid == M_VOLUMETRIC or mid == M_INERTIAL:
        return Ap * (x[0] - x[1])
    if mid == M_SINGLE_STATE or mid == M_INERTIAL_2STATE:
        return Ap * x[0]
    if mid == M_MAXWELL:
        return x[0]
    if mid == M_DASHPOT:
        return prm[P_CL] * v
    if mid == M_SPRING:
        return prm[P_KD] * y
    if mid == M_DASHPOT_INERTER:
        return prm[P_CL] * v + prm[P_BLM] * a
    if mid == M_INERTER:
        return prm[P_BLM] * a
    return prm[P_CV] * v + prm[P_CV2] * v * abs(v)  # viscous, linear and quadratic


@njit(cache=True, error_model="numpy")
def _state_force(mid, d, prm):
    """The state-linear part of the base force applied to a rate vector ``d`` [N/s]."""
    Ap = prm[P_AP]
    if mid == M_FULL or mid == M_NO_INERTIA:
        return Ap * (d[0] - d[2])
    if mid == M_CONSTANT_BULK or mid == M_VOLUMETRIC or mid == M_INERTIAL:
        return Ap * (d[0] - d[1])
    if mid == M_SINGLE_STATE or mid == M_INERTIAL_2STATE:
        return Ap * d[0]
    return d[0]


# -------------------------------------------------------- composed models
@njit(cache=True, error_model="numpy")
def flow_direction(mid, spec, x, v, dpc=0.0):
    """Sign of the channel flow (compression > 0, rebound < 0) of base ``mid`` [-].

    The channel mass flow where it is a state (``full``, ``inertial``), the
    volumetric flow (``inertial_2state``), the pressure difference it follows
    (``no_inertia``, ``constant_bulk``, ``volumetric``, ``single_state``),
    the Maxwell force, or the piston velocity ``v`` (stateless bases).
    """
    if mid == M_FULL:
        d = x[4]
    elif mid == M_INERTIAL or mid == M_INERTIAL_2STATE:
        d = x[2] if mid == M_INERTIAL else x[1]
    elif mid == M_NO_INERTIA or mid == M_CONSTANT_BULK or mid == M_VOLUMETRIC:
        d = x[spec[S_I1]] - x[spec[S_I2]] + dpc
    elif mid == M_SINGLE_STATE:
        d = x[0] + dpc
    elif mid == M_MAXWELL:
        d = x[0]
    else:
        d = v
    return 1.0 if d > 0.0 else (-1.0 if d < 0.0 else 0.0)


@njit(cache=True, error_model="numpy")
def loss_params(spec, x, v, prm, ep, dpc=0.0):
    """Copy of ``prm`` with the channel's loss coefficients of the flow's direction.

    In rebound (:func:`flow_direction` < 0) c1, c2, g1, g2, c_L, the viscous
    c and T_D (= c1 / B) are multiplied by the rebound ratio ``ep[E_RR]``;
    piecewise constant, so the analytic Jacobian stays exact off zero flow.
    """
    q = prm.copy()
    if flow_direction(spec[S_MID], spec, x, v, dpc) < 0.0:
        r = ep[E_RR]
        for k in (P_G1, P_G2, P_C1, P_C2, P_CL, P_CV, P_TD):
            q[k] = q[k] * r
    return q


@njit(cache=True, error_model="numpy")
def _relief_differential(mid, x, y, prm, ep, dpc, out):
    """The relief flow in the differential and linear models (eqs. 15, 16, 18)."""
    Ap = prm[P_AP]
    if mid == M_MAXWELL:  # dF/dt = A_p B (A_p v - q - q_r), k_D = A_p^2 B
        out[0] -= prm[P_KD] / Ap * relief_flow(x[0] / Ap, ep[E_PR], ep[E_GR])
    elif mid == M_SINGLE_STATE or mid == M_INERTIAL_2STATE:
        B = prm[P_B01] / (prm[P_V01] - Ap * y) + prm[P_B02] / (prm[P_V02] + Ap * y)
        out[0] -= B * relief_flow(x[0] + dpc, ep[E_PR], ep[E_GR])


@njit(cache=True, error_model="numpy")
def _damper_force(spec, v, prm, ep):
    """Force of a stateless dashpot-type base (dashpot, dashpot_inerter's dashpot, viscous)
    with the rebound ratio and the relief valve as an exact force saturation [N] (the
    viscous damper is read as a dashpot of unit piston area)."""
    if spec[S_MID] == M_VISCOUS:
        c, area = prm[P_CV], 1.0
    else:
        c, area = prm[P_CL], prm[P_AP]
    if spec[S_ASYM] != 0 and v < 0.0:
        c *= ep[E_RR]
    if spec[S_RELIEF] != 0 and c > 0.0:
        return relief_force(v, c, ep[E_PR] * area, ep[E_GR] / (area * area))
    return c * v


@njit(cache=True, error_model="numpy")
def _fluid_rhs(spec, x, y, v, prm, ep, out):
    """Base model with the fluid effects (leakage, rotating frame, cavitation) at piston
    stroke (y, v)."""
    mid = spec[S_MID]
    kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
    dpc = 0.0
    o1 = 0.0
    o2 = 0.0
    if spec[S_ROT] > 0:
        dpc, o1, o2 = rotating_heads(y, prm, ep)
    i1 = spec[S_I1]
    if spec[S_RELIEF] != 0 and i1 >= 0:  # a second path beside the channel, driven like
        dp = x[i1] - x[spec[S_I2]] + dpc  # it: its secant conductance joins the leakage's
        if dp != 0.0:
            kL += relief_flow(dp, ep[E_PR], ep[E_GR]) / dp
    if spec[S_ASYM] != 0:
        base_rhs(mid, x, y, v, loss_params(spec, x, v, prm, ep, dpc), kL, dpc, out)
    else:
        base_rhs(mid, x, y, v, prm, kL, dpc, out)
    if spec[S_RELIEF] != 0 and i1 < 0:
        _relief_differential(mid, x, y, prm, ep, dpc, out)
    ic = spec[S_ICAV]
    if ic >= 0:
        i2 = spec[S_I2]
        Ap = prm[P_AP]
        V1 = prm[P_V01] - Ap * y
        V2 = prm[P_V02] + Ap * y
        if mid == M_FULL or mid == M_NO_INERTIA:
            B1 = bulk(x[i1], prm[P_X01], prm)
            B2 = bulk(x[i2], prm[P_X02], prm)
        else:
            B1, B2 = prm[P_B01], prm[P_B02]
        pv = ep[E_PV]
        # the cavity opens where the pressure is least: in a rotating frame the inboard end,
        # whose pressure p_i + o_i(y) changes at dp_i/dt + (do_i/dy) v; the switch acts on it
        s1 = 0.0
        s2 = 0.0
        if spec[S_ROT] > 0:
            s1, s2 = rotating_offset_slopes(y, prm, ep)
            s1 *= v
            s2 *= v
        dp1, dc1 = cavity_rates(x[i1] + o1, out[i1] + s1, x[ic], V1, B1, pv)
        dp2, dc2 = cavity_rates(x[i2] + o2, out[i2] + s2, x[ic + 1], V2, B2, pv)
        out[i1] = dp1 - s1
        out[i2] = dp2 - s2
        out[ic] = dc1
        out[ic + 1] = dc2


@njit(cache=True, error_model="numpy")
def elastomer_rate(v, F, k1, c1):
    """dF/dt of the elastomer's Maxwell branch (spring k1 in series with dashpot c1) [N/s].

    ``dF/dt = k1 v - (k1 / c1) F`` (tau = c1 / k1); with the parallel
    spring k0 the branch is the standard linear solid,
    K(i w) = k0 + k1 i w tau / (1 + i w tau).

    Examples
    --------
    >>> elastomer_rate(0.01, 50.0, 1e5, 1e3)
    -4000.0
    """
    return k1 * v - k1 / c1 * F


@njit(cache=True, error_model="numpy")
def stop_force(y, v, k, c, clearance, centre):
    """Force of a pair of end stops on the rod [N] (0 inside the clearance).

    ``F = sign(u) (k R(|u| - clearance) + c v S((|u| - clearance) / w))``,
    ``u = y - centre``, R the :func:`c1_ramp` and S the C1 smoothstep over
    the onset width ``w = 0.01 clearance + 1e-7 m``: exactly
    k (|u| - clearance) sign(u) beyond the width; the damping is
    Kelvin-Voigt (it may pull briefly while the contact separates).

    Examples
    --------
    >>> stop_force(0.5e-3, 0.0, 1e6, 0.0, 1e-3, 0.0), stop_force(-2e-3, 0.0, 1e6, 0.0, 1e-3, 0.0)
    (0.0, -1000.0)
    """
    u = y - centre
    pen = abs(u) - clearance
    if pen <= 0.0:
        return 0.0
    w = 0.01 * clearance + 1.0e-7
    f = k * c1_ramp(pen, w) * (1.0 if u > 0.0 else -1.0)
    if c != 0.0:
        f += c * v * _smoothstep(pen / w)
    return f


@njit(cache=True, error_model="numpy")
def _fp_contact(spec, x, y, v, ep):
    """Contact factor of the freeplay (needs ``spec[S_IFP] >= 0``) [-].

    :func:`play_contact`, or :func:`piston_contact` where smooth friction
    sits behind the dead band (its loaded bristles hold the contact).
    """
    e = y - x[spec[S_IFP]]
    if spec[S_ZPIST] != 0 and spec[S_IZ] >= 0:
        return piston_contact(e, x[spec[S_IZ]], ep[E_SFC] / ep[E_SIG], ep[E_GAP])
    return play_contact(e, v, ep[E_GAP])


@njit(cache=True, error_model="numpy", fastmath=_FM)
def model_rhs(spec, x, y, v, prm, ep, out):
    """dx/dt of a composed model at the measured rod stroke (y [m], v [m/s]), into ``out``.

    Freeplay (``y_fp``) and series compliance (``y_piston``) map the rod
    stroke to the piston stroke; the fluid sees the piston; smooth
    friction's bristle state follows the rod velocity, or the piston's
    behind a dead band (``spec[S_ZPIST]``: friction at the piston).
    """
    if (spec[S_N] == spec[S_NB] and spec[S_LEAK] == 0 and spec[S_RELIEF] == 0
            and spec[S_ASYM] == 0 and spec[S_ROT] <= 0):
        base_rhs_inline(spec[S_MID], x, y, v, prm, 0.0, 0.0, out)
        return
    yi = y
    vi = v
    ifp = spec[S_IFP]
    iz = spec[S_IZ]
    if ifp >= 0:
        r = v * _fp_contact(spec, x, y, v, ep)
        out[ifp] = r
        yi = x[ifp]
        vi = r
    icp = spec[S_IC]
    if icp >= 0:
        yp = x[icp]
        k = ep[E_KC]
        if math.isinf(k):
            _fluid_rhs(spec, x, yp, vi, prm, ep, out)
            out[icp] = vi
        else:
            n_in = icp  # the fluid block (base and cavities) precedes y_piston
            d1 = np.empty(n_in)
            _fluid_rhs(spec, x, yp, 1.0, prm, ep, d1)
            _fluid_rhs(spec, x, yp, 0.0, prm, ep, out)
            mid = spec[S_MID]
            g0 = _state_force(mid, out, prm)
            g1 = _state_force(mid, d1, prm) - g0
            if spec[S_ROT] > 0:  # the force's centrifugal term A_p dp_c(y_piston)
                g1 += prm[P_AP] * rotating_slope(prm, ep)
            vp = compliance_rate(vi, k, g0, g1)
            for i in range(n_in):
                out[i] = out[i] + vp * (d1[i] - out[i])
            out[icp] = vp
    else:
        _fluid_rhs(spec, x, yi, vi, prm, ep, out)
    if iz >= 0:  # the bristles move with the rod, or with the piston behind the dead band
        vz = vi if spec[S_ZPIST] != 0 else v
        out[iz] = lugre_rate(vz, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                             ep[E_FEX])
    iel = spec[S_IEL]
    if iel >= 0:
        out[iel] = elastomer_rate(v, x[iel], ep[E_K1], ep[E_C1E])


@njit(cache=True, error_model="numpy")
def _lugre_dz_dv(v, z, force, stiffness, v_s, r, n):
    """(d/dz, d/dv) of :func:`lugre_rate` [1/s, 1/m]."""
    if force <= 0.0:
        return 0.0, 0.0
    g = _stribeck(v, v_s, r)
    dg = (r - 1.0) * math.exp(-(v / v_s) ** 2) * (-2.0 * v / (v_s * v_s))
    sgn = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    c = stiffness / force
    s = z / g
    a = 1.0 if n == 1.0 else abs(s) ** (n - 1.0)  # |s|^(n-1)
    # h = s |s|^(n-1): dh/dz = n a / g, dh/dv = -n a s dg / g
    return -c * abs(v) * n * a / g, c * (1.0 - sgn * s * a + abs(v) * n * a * s * dg / g)


@njit(cache=True, error_model="numpy")
def _fd_step(x_j, scale):
    return 2.0e-6 * max(abs(x_j), scale)


@njit(cache=True, error_model="numpy")
def model_jac(spec, x, y, v, prm, ep, J):
    """Jacobian d rhs / dx of a composed model into ``J[:n, :n]`` (zeroed here).

    Analytic where ``spec[S_ANALYTIC]``; otherwise central differences of
    :func:`model_rhs` with increments 2e-6 max(|x_j|, scale_j).
    """
    n = spec[S_N]
    for i in range(n):
        for j in range(n):
            J[i, j] = 0.0
    if spec[S_ANALYTIC] != 0:
        kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
        if spec[S_ASYM] != 0:
            base_jac(spec[S_MID], x, y, v, loss_params(spec, x, v, prm, ep), kL, J)
        else:
            base_jac(spec[S_MID], x, y, v, prm, kL, J)
        iz = spec[S_IZ]
        if iz >= 0:
            J[iz, iz] = _lugre_dz_dv(v, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                                     ep[E_FEX])[0]
        iel = spec[S_IEL]
        if iel >= 0:
            J[iel, iel] = -ep[E_K1] / ep[E_C1E]
        return
    xp = x.copy()
    fp = np.empty(n)
    fm = np.empty(n)
    for j in range(n):
        h = _fd_step(x[j], ep[N_EP + j])
        xp[j] = x[j] + h
        model_rhs(spec, xp, y, v, prm, ep, fp)
        xp[j] = x[j] - h
        model_rhs(spec, xp, y, v, prm, ep, fm)
        xp[j] = x[j]
        for i in range(n):
            J[i, j] = (fp[i] - fm[i]) / (2.0 * h)


@njit(cache=True, error_model="numpy")
def model_rhs_t(spec, x, y, v, yd, vd, prm, ep, out):
    """d rhs / dt at fixed x through the stroke (dy/dt = yd [m/s], dv/dt = vd [m/s^2]).

    Analytic where ``spec[S_ANALYTIC]``; otherwise a central difference along
    the stroke over +/- 1e-7 s.
    """
    n = spec[S_N]
    if spec[S_ANALYTIC] != 0:
        kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
        if spec[S_ASYM] != 0:
            base_rhs_t(spec[S_MID], x, y, v, yd, vd, loss_params(spec, x, v, prm, ep), kL, out)
        else:
            base_rhs_t(spec[S_MID], x, y, v, yd, vd, prm, kL, out)
        iz = spec[S_IZ]
        if iz >= 0:
            out[iz] = _lugre_dz_dv(v, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                                   ep[E_FEX])[1] * vd
        iel = spec[S_IEL]
        if iel >= 0:
            out[iel] = ep[E_K1] * vd
        return
    dt = 1.0e-7
    fm = np.empty(n)
    model_rhs(spec, x, y + dt * yd, v + dt * vd, prm, ep, out)
    model_rhs(spec, x, y - dt * yd, v - dt * vd, prm, ep, fm)
    for i in range(n):
        out[i] = (out[i] - fm[i]) / (2.0 * dt)


@njit(cache=True, error_model="numpy")
def _sign(v):
    return 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)


@njit(cache=True, error_model="numpy")
def friction_level(z, reverse_ratio):
    """Friction force per unit level of a direction-dependent friction [-].

    ``z`` for z >= 0 and ``reverse_ratio z`` for z < 0: the bristle state
    z (smooth friction, force F_c z) or sign(v) (Coulomb, F_c sign(v)).  A
    band or seal that grips harder one way slides at F_c forward and
    q F_c in reverse (q = ``reverse_ratio`` > 0); unlike a constant
    offset, the force is still zero where the friction is unloaded (inside
    a dead band, at rest).  Continuous in z (with a kink at z = 0 where
    q != 1).

    Examples
    --------
    >>> friction_level(0.5, 0.8), friction_level(-0.5, 0.8), friction_level(0.0, 0.8)
    (0.5, -0.4, 0.0)
    """
    return z if z >= 0.0 else reverse_ratio * z


@njit(cache=True, error_model="numpy")
def model_force(spec, x, y, v, a, prm, ep, with_friction):
    """Load-cell force of a composed model [N] at the rod stroke (y, v, a).

    The fluid force at the piston stroke plus the effect forces (Coulomb
    friction behind a dead band, ``spec[S_CPIST]``: F_c sign(v) C, C the
    dead band's contact factor, 0 in the gap); with
    ``with_friction`` also the parameter set's Coulomb friction
    ``friction_N sign(v)`` (:attr:`DeviceParams.friction_N`).
    """
    mid = spec[S_MID]
    yi = y
    vi = v
    ifp = spec[S_IFP]
    cfp = 1.0  # contact factor of the dead band (1: no freeplay)
    if ifp >= 0:
        cfp = _fp_contact(spec, x, y, v, ep)
        vi = v * cfp
        yi = x[ifp]
    if spec[S_IC] >= 0:
        yi = x[spec[S_IC]]
    if (spec[S_RELIEF] != 0 or spec[S_ASYM] != 0) and (
            mid == M_DASHPOT or mid == M_DASHPOT_INERTER or mid == M_VISCOUS):
        f = _damper_force(spec, vi, prm, ep)
        if mid == M_DASHPOT_INERTER:
            f += prm[P_BLM] * a
    else:
        f = base_force(mid, x, yi, vi, a, prm)
        if spec[S_ROT] > 0:  # piston faces: A_p (p1 - p2 + dp_c) (rotating_heads)
            f += prm[P_AP] * rotating_heads(yi, prm, ep)[0]
    iz = spec[S_IZ]
    if iz >= 0:
        f += ep[E_SFC] * friction_level(x[iz], ep[E_FRQ])
    if spec[S_COUL] != 0:
        # at the piston the dead band passes the friction force only in contact
        f += ep[E_CF] * friction_level(_sign(v), ep[E_CRQ]) * (
            cfp if spec[S_CPIST] != 0 else 1.0)
    iel = spec[S_IEL]
    if iel >= 0:  # the elastomer on the rod: k0 y plus its Maxwell branch
        f += ep[E_K0] * y + x[iel]
    if spec[S_STOP] != 0:
        f += stop_force(y, v, ep[E_KS], ep[E_CS], ep[E_CLR], ep[E_CTR])
    if spec[S_MASS] != 0:
        f += ep[E_MASS] * a
    if spec[S_OFF] != 0:
        f += ep[E_OFF]
    if with_friction and prm[P_FRIC] > 0.0:
        f += prm[P_FRIC] * _sign(v)
    return f


@njit(cache=True, error_model="numpy")
def force_series(spec, X, Y, V, A, prm, ep, with_friction, out):
    """:func:`model_force` over samples: X (n, N) states, Y, V, A (N,) strokes; into ``out``."""
    for k in range(out.size):
        out[k] = model_force(spec, X[:, k], Y[k], V[k], A[k], prm, ep, with_friction)


@njit(cache=True, error_model="numpy")
def base_force_series(mid, X, Y, V, A, prm, with_friction, out):
    """:func:`base_force` (+ the set's friction) over samples, for a model without effects.

    The same values as :func:`force_series` there; kept apart so that a bare
    model's first call does not compile the composition.
    """
    fr = prm[P_FRIC] if with_friction else 0.0
    for k in range(out.size):
        f = base_force(mid, X[:, k], Y[k], V[k], A[k], prm)
        if fr > 0.0:
            f += fr * _sign(V[k])
        out[k] = f
