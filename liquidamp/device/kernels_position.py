"""Compiled laws of the position-dependent channel losses (``bypass_groove``): the loss
scale over the stroke and its contribution to the time derivative of the right-hand side.
Part of :mod:`liquidamp.device.kernels` (the public face, which re-exports every name).

A bypass groove cut into the pressure tube (or a tapered metering pin) opens a second
path around the piston over a band of the stroke: the channel's loss coefficients are
multiplied there by s(y) = 1 - d phi((y + y_0 - y_c) / w), phi(xi) = exp(-xi^2), depth
0 <= d < 1, centre y_c [m] and half-width w [m] (the 1/e half-width) on the absolute stroke
(y_0 the absolute stroke of the model's zero).  Every loss of the
base equations is a multiple of s (the volumetric c1, c2, the mass-flow g1, g2, the
Maxwell time T_D = c1 / B, the dashpot c_L and the viscous c, c2), so the right-hand side
at fixed stroke is the base one with the scaled coefficients; s does not depend on the
states, so the analytic Jacobian is the base one at the scaled coefficients, and the
time derivative along the stroke gains (d rhs / d ln s) (s'(y) / s) dy/dt
(:func:`groove_rate_terms`).

References
----------
.. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5
   (position-sensitive damping: bypass grooves, tapered metering pins).
"""

from __future__ import annotations

import math

from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.device.kernels_laws import bulk, loss_flow_dp, r_const
from liquidamp.device.kernels_layout import (
    E_GC,
    E_GD,
    E_GW,
    E_GY0,
    M_CONSTANT_BULK,
    M_FULL,
    M_INERTIAL,
    M_INERTIAL_2STATE,
    M_MAXWELL,
    M_NO_INERTIA,
    M_SINGLE_STATE,
    M_VOLUMETRIC,
    P_AP,
    P_B01,
    P_B02,
    P_C1,
    P_C2,
    P_G1,
    P_G2,
    P_LT,
    P_ST,
    P_TD,
    P_V01,
    P_V02,
    P_X01,
    P_X02,
)

drop_stale(__file__)  # before any kernel of this module loads from the cache


@njit(cache=True, error_model="numpy")
def groove_scale(y, depth, centre, half_width):
    """Loss scale of a bypass groove at piston stroke y and its slope: (s [-], ds/dy [1/m]).

    s(y) = 1 - d exp(-xi^2), xi = (y - y_c) / w: smooth (C-infinity), so that the
    stiff steppers keep their order across the groove's edges and the analytic Jacobian
    and time derivative hold everywhere; s >= 1 - d > 0.

    Examples
    --------
    >>> s, ds = groove_scale(0.001, 0.4, 0.001, 0.002)   # at the centre: 1 - d, flat
    >>> round(s, 12), ds
    (0.6, 0.0)
    >>> s, ds = groove_scale(0.003, 0.4, 0.001, 0.002)   # one half-width off: 1 - d / e
    >>> round(s, 12) == round(1 - 0.4 / math.e, 12), round(ds, 6) == round(400 / math.e, 6)
    (True, True)
    """
    xi = (y - centre) / half_width
    phi = math.exp(-xi * xi)
    return 1.0 - depth * phi, 2.0 * depth * xi * phi / half_width


@njit(cache=True, error_model="numpy")
def groove_ep_scale(y, ep):
    """:func:`groove_scale` at the absolute stroke y + ``ep[E_GY0]`` with the parameters of
    the effect slots ``E_GD``, ``E_GC``, ``E_GW`` (the groove is cut at a fixed place in the
    tube; the model's y is about the record's mean stroke)."""
    return groove_scale(y + ep[E_GY0], ep[E_GD], ep[E_GC], ep[E_GW])


@njit(cache=True, error_model="numpy")
def groove_rate_terms(mid, x, y, v, q, kL, rate, out):
    """Add (d rhs / d ln s) ``rate`` to ``out``: the groove's part of d rhs / dt [state/s^2].

    ``q`` is the packed parameter vector at the scaled loss coefficients (the base's own
    right-hand side at fixed stroke), ``rate`` = (s'(y) / s) dy/dt [1/s], ``kL`` the
    leakage conductance (unscaled: the groove acts on the channel only).  The loss enters
    each base as a multiple of s: where the channel flow is a state (``full``,
    ``inertial``, ``inertial_2state``) its momentum balance loses s (k1 m + k2 m|m|), so
    d/d ln s is minus the scaled loss; where the flow follows the pressure difference,
    s (k1 q + k2 q|q|) = dp gives dq / d ln s = -dp dq/d(dp); on ``maxwell``
    dF/dt = k_D v - F / (s T_D) gives +F / (s T_D).  Stateless bases have no states.
    """
    if rate == 0.0:
        return
    Ap = q[P_AP]
    V1 = q[P_V01] - Ap * y
    V2 = q[P_V02] + Ap * y
    if mid == M_FULL:
        m = x[4]
        out[4] -= (q[P_G1] * m + q[P_G2] * m * abs(m)) / q[P_ST] * rate
    elif mid == M_INERTIAL:
        m = x[2]
        out[2] -= (q[P_G1] * m + q[P_G2] * m * abs(m)) / q[P_ST] * rate
    elif mid == M_INERTIAL_2STATE:
        f = x[1]
        out[1] -= (q[P_C1] * f + q[P_C2] * f * abs(f)) / q[P_LT] * rate
    elif mid == M_MAXWELL:
        out[0] += x[0] / q[P_TD] * rate
    elif mid == M_NO_INERTIA:
        dp = x[0] - x[2]
        dm = -dp * loss_flow_dp(dp, q[P_G1], q[P_G2]) * rate
        B1 = bulk(x[0], q[P_X01], q)
        B2 = bulk(x[2], q[P_X02], q)
        out[0] -= B1 / (V1 * x[1]) * dm
        out[1] -= dm / V1
        out[2] += B2 / (V2 * x[3]) * dm
        out[3] += dm / V2
    elif mid == M_CONSTANT_BULK:
        dp = x[0] - x[1]
        dm = -dp * loss_flow_dp(dp, q[P_G1], q[P_G2]) * rate
        B1, B2 = q[P_B01], q[P_B02]
        out[0] -= B1 / (V1 * r_const(x[0], B1, q)) * dm
        out[1] += B2 / (V2 * r_const(x[1], B2, q)) * dm
    elif mid == M_VOLUMETRIC:
        dp = x[0] - x[1]
        dq = -dp * loss_flow_dp(dp, q[P_C1], q[P_C2]) * rate
        out[0] -= q[P_B01] / V1 * dq
        out[1] += q[P_B02] / V2 * dq
    elif mid == M_SINGLE_STATE:
        dq = -x[0] * loss_flow_dp(x[0], q[P_C1], q[P_C2]) * rate
        out[0] -= (q[P_B01] / V1 + q[P_B02] / V2) * dq

