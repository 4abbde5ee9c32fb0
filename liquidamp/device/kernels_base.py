"""The compiled base models of the family (Titurus 2018, eqs. (10)-(20)): right-hand side,
Jacobian, time derivative along the stroke and load-cell force of each base equation.
Part of :mod:`liquidamp.device.kernels` (the public face, which re-exports every name;
references there).
"""

from __future__ import annotations

from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.device.kernels_laws import (
    _sign,
    bulk,
    bulk_and_dp,
    loss_flow,
    loss_flow_dp,
    r_const,
)
from liquidamp.device.kernels_layout import (
    _FM,
    BASE_STATES,
    M_CONSTANT_BULK,
    M_DASHPOT,
    M_DASHPOT_INERTER,
    M_FULL,
    M_INERTER,
    M_INERTIAL,
    M_INERTIAL_2STATE,
    M_MAXWELL,
    M_NO_INERTIA,
    M_SINGLE_STATE,
    M_SPRING,
    M_VOLUMETRIC,
    P_AP,
    P_B01,
    P_B02,
    P_BLM,
    P_C1,
    P_C2,
    P_CL,
    P_CV,
    P_CV2,
    P_FRIC,
    P_G1,
    P_G2,
    P_KD,
    P_LT,
    P_RHO0,
    P_ST,
    P_TD,
    P_V01,
    P_V02,
    P_X01,
    P_X02,
)

drop_stale(__file__)  # before any kernel of this module loads from the cache


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
def state_force(mid, d, prm):
    """The state-linear part of the base force applied to a rate vector ``d`` [N/s]."""
    Ap = prm[P_AP]
    if mid == M_FULL or mid == M_NO_INERTIA:
        return Ap * (d[0] - d[2])
    if mid == M_CONSTANT_BULK or mid == M_VOLUMETRIC or mid == M_INERTIAL:
        return Ap * (d[0] - d[1])
    if mid == M_SINGLE_STATE or mid == M_INERTIAL_2STATE:
        return Ap * d[0]
    return d[0]


@njit(cache=True, error_model="numpy", nogil=True)
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
