"""The compiled laws of self-heating (issue #20 item 5): the viscosity's temperature law, the
loss coefficients at the fluid's temperature and the power the flow paths dissipate.

Part of the device physics of :mod:`liquidamp.device.kernels` (the composed model
:func:`~liquidamp.device.kernels_model.model_rhs` calls them where ``spec[S_TH] >= 0``);
the effect is :class:`~liquidamp.device.effects_thermal.SelfHeating`.

Viscosity laws (``ep[E_TLAW]``), as the ratio mu(T) / mu(T_ref) [-], T in kelvin:

* ``0`` exponential (Reynolds): exp(-beta (T - T_ref)), beta = ``ep[E_TBETA]`` [1/K];
* ``1`` water, Vogel's fit mu = A 10^(B / (T - C)) (A = 2.414e-5 Pa s, B = 247.8 K,
  C = 140 K; within 2.5 % of the IAPWS values from 0 to 370 C), ``ep[E_TA]`` = B ln 10,
  ``ep[E_TB]`` = C;
* ``2`` Walther / ASTM D341 for mineral oil: log10 log10(nu + 0.7) = A - B log10 T (nu in
  mm^2/s), ``ep[E_TA]`` = A, ``ep[E_TB]`` = B (the kinematic viscosity's ratio; the density's
  change, about 0.07 %/K, is neglected).

References
----------
.. [1] O. Reynolds, "On the theory of lubrication", Phil. Trans. R. Soc. 177, 1886
   (exponential law).
.. [2] C. J. Seeton, "Viscosity-temperature correlation for liquids", Tribology Letters
   22(1), 2006 (Vogel's water fit; Walther's equation).
.. [3] ASTM D341-20, Standard Practice for Viscosity-Temperature Equations and Charts for
   Liquid Petroleum or Hydrocarbon Products.
"""

from __future__ import annotations

import math

from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.device.kernels_laws import loss_flow
from liquidamp.device.kernels_layout import (
    _FM,
    E_TA,
    E_TB,
    E_TBETA,
    E_TG2,
    E_TLAW,
    E_TREF,
    E_TSRC,
    M_CONSTANT_BULK,
    M_DASHPOT,
    M_DASHPOT_INERTER,
    M_FULL,
    M_INERTIAL,
    M_INERTIAL_2STATE,
    M_MAXWELL,
    M_NO_INERTIA,
    M_SINGLE_STATE,
    M_VISCOUS,
    M_VOLUMETRIC,
    P_C1,
    P_C2,
    P_CH,
    P_CL,
    P_CV,
    P_CV2,
    P_G1,
    P_G2,
    P_KD,
    P_RHO0,
    P_TD,
)

drop_stale(__file__)  # before any kernel of this module loads from the cache

#: Law ids of ``ep[E_TLAW]``.
LAW_EXPONENTIAL, LAW_WATER, LAW_WALTHER = 0, 1, 2


@njit(cache=True, error_model="numpy", fastmath=_FM)
def _log_mu(T, law, beta, a, b):
    """ln of the law's viscosity at T [K] up to a constant (module docstring)."""
    if law == LAW_WATER:
        return a / max(T - b, 1.0)
    if law == LAW_WALTHER:
        nu = 10.0 ** (10.0 ** (a - b * math.log10(max(T, 1.0)))) - 0.7
        return math.log(max(nu, 1e-300))
    return -beta * T


@njit(cache=True, error_model="numpy", fastmath=_FM)
def viscosity_ratio(T, T_ref, law, beta, a, b):
    """mu(T) / mu(T_ref) [-] of law ``law`` (module docstring); T, T_ref [K].

    Examples
    --------
    >>> round(viscosity_ratio(303.15, 293.15, 0, 0.025, 0.0, 0.0), 12) == round(
    ...     math.exp(-0.25), 12)
    True
    >>> round(viscosity_ratio(313.15, 293.15, 1, 0.0, 247.8 * math.log(10), 140.0), 3)
    0.65
    """
    return math.exp(_log_mu(T, law, beta, a, b) - _log_mu(T_ref, law, beta, a, b))


@njit(cache=True, error_model="numpy", fastmath=_FM)
def law_temperature(T_state, prm, ep):
    """The temperature the viscosity law reads [K]: the thermal state, or the measured
    ``temperature`` channel (slot 0 of the input channels, ``prm[P_CH]``) where
    ``ep[E_TSRC]`` is 1."""
    if ep[E_TSRC] != 0.0:
        return prm[P_CH]
    return T_state


@njit(cache=True, error_model="numpy", fastmath=_FM)
def thermal_params(T, prm, ep):
    """Copy of ``prm`` with the loss coefficients at the fluid temperature T [K].

    The laminar ones (g1, c1, c_L, the viscous c and T_D = c1 / B) scale with the viscosity
    ratio r = mu(T) / mu(T_ref), the quadratic ones (g2, c2, the viscous c2) with
    r^gamma2 (``ep[E_TG2]``).
    """
    q = prm.copy()
    r = viscosity_ratio(T, ep[E_TREF], int(ep[E_TLAW]), ep[E_TBETA], ep[E_TA], ep[E_TB])
    for k in (P_G1, P_C1, P_CL, P_CV, P_TD):
        q[k] = q[k] * r
    r2 = r ** ep[E_TG2]
    for k in (P_G2, P_C2, P_CV2):
        q[k] = q[k] * r2
    return q


@njit(cache=True, error_model="numpy", fastmath=_FM)
def channel_power(mid, x, v, dp, prm):
    """Power the channel's losses dissipate [W] for base ``mid``: loss pressure drop times
    volumetric flow, at the coefficients in ``prm`` (already at the flow's direction and
    temperature).

    ``dp`` is the pressure difference driving the flow where the loss relation is
    algebraic (p1 - p2 plus any body-force rise: the whole of it drops across the losses),
    ``v`` the piston velocity of the stateless dashpot-type bases (their force
    c v (+ c2 v|v|) times v); the spring and the inerter dissipate nothing.
    """
    if mid == M_FULL or mid == M_INERTIAL:
        m = x[4] if mid == M_FULL else x[2]
        return (prm[P_G1] * m + prm[P_G2] * m * abs(m)) * m / prm[P_RHO0]
    if mid == M_INERTIAL_2STATE:
        q = x[1]
        return (prm[P_C1] * q + prm[P_C2] * q * abs(q)) * q
    if mid == M_MAXWELL:  # the Maxwell dashpot c = k_D T_D carries the force x0
        c = prm[P_KD] * prm[P_TD]
        return x[0] * x[0] / c if c > 0.0 else 0.0
    if mid == M_DASHPOT or mid == M_DASHPOT_INERTER:
        return prm[P_CL] * v * v
    if mid == M_VISCOUS:
        return (prm[P_CV] + prm[P_CV2] * abs(v)) * v * v
    if mid == M_NO_INERTIA or mid == M_CONSTANT_BULK:  # mass-flow relation (g1, g2)
        return dp * loss_flow(dp, prm[P_G1], prm[P_G2]) / prm[P_RHO0]
    if mid == M_VOLUMETRIC or mid == M_SINGLE_STATE:  # volumetric relation (c1, c2)
        return dp * loss_flow(dp, prm[P_C1], prm[P_C2])
    return 0.0


@njit(cache=True, error_model="numpy", fastmath=_FM)
def heat_rate(T, P, C, hA, T_amb):
    """dT/dt of the lumped fluid [K/s]: (P - h_A (T - T_amb)) / C (0 for C = inf)."""
    if math.isinf(C):
        return 0.0
    return (P - hA * (T - T_amb)) / C
