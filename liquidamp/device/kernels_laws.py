"""The compiled scalar laws of the device physics: fluid laws (bulk modulus, losses),
friction (LuGre, direction-dependent levels), the play operator, series compliance,
cavities, the rotating frame's heads, the relief valve, the elastomer and the end stops.
Part of :mod:`liquidamp.device.kernels` (the public face, which re-exports every name;
references there).
"""

from __future__ import annotations

import math

from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.device.kernels_layout import (
    _FM,
    E_COSA,
    E_OMEGA,
    E_RM,
    P_AP,
    P_BL,
    P_CONSTB,
    P_N,
    P_P0,
    P_RHO0,
    P_V01,
    P_V02,
)

drop_stale(__file__)  # before any kernel of this module loads from the cache


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
def float_contact(e, gap):
    """Share of a series contact's stiffness engaged at rod-piston offset ``e`` [-].

    A dead band of half-width ``gap`` [m] between the rod and a floating piston
    (``floating_freeplay``): 0 inside it, 1 in contact, the C1 smoothstep over a
    width ``delta = 0.05 gap + 1e-7 m`` centred on |e| = gap, so that the contact
    force, the integral of the engaged stiffness, is k (|e| - gap) sign(e) beyond
    gap + delta / 2 (:func:`float_contact_force`).  ``gap <= 0``: 1 (the spring
    as it is).

    Examples
    --------
    >>> float_contact(0.0, 1e-3), float_contact(2e-3, 1e-3), float_contact(1e-3, 1e-3)
    (0.0, 1.0, 0.5)
    >>> float_contact(0.0, 0.0)
    1.0
    """
    if gap <= 0.0:
        return 1.0
    delta = 0.05 * gap + 1e-7
    return _smoothstep((abs(e) - gap) / delta + 0.5)


def float_contact_force(e, gap, k):
    """Contact force of a series spring k [N/m] behind a dead band of half-width ``gap``
    [m] at rod-piston offset ``e`` [m]: the integral of k :func:`float_contact` [N].

    Examples
    --------
    >>> float_contact_force(3e-3, 1e-3, 1e6)     # 2 mm into the contact
    2000.0
    >>> float_contact_force(-5e-4, 1e-3, 1e6), float_contact_force(5e-4, 0.0, 1e6)
    (-0.0, 500.0)
    """
    if gap <= 0.0:
        return k * e
    delta = 0.05 * gap + 1e-7
    s = min(max((abs(e) - gap) / delta + 0.5, 0.0), 1.0)
    a = delta * (s ** 3 - 0.5 * s ** 4) + max(abs(e) - gap - 0.5 * delta, 0.0)
    return math.copysign(k * a, e)


def float_contact_offset(force, gap, k, e_now):
    """Rod-piston offset [m] at which :func:`float_contact_force` carries ``force`` [N];
    where the force is zero, ``e_now`` kept inside the band (any offset there carries none).

    Examples
    --------
    >>> round(float_contact_offset(2000.0, 1e-3, 1e6, 0.0), 12)
    0.003
    >>> float_contact_offset(0.0, 1e-3, 1e6, 5e-3) <= 1e-3
    True
    """
    if gap <= 0.0:
        return force / k
    delta = 0.05 * gap + 1e-7
    a = abs(force) / k
    if a == 0.0:
        inner = gap - 0.5 * delta
        return min(max(e_now, -inner), inner)
    if a >= 0.5 * delta:
        return math.copysign(gap + a, force)
    lo, hi = 0.0, 1.0  # the smoothstep's stretch: its integral is monotone in s
    for _ in range(60):
        s = 0.5 * (lo + hi)
        if delta * (s ** 3 - 0.5 * s ** 4) < a:
            lo = s
        else:
            hi = s
    return math.copysign(gap + (0.5 * (lo + hi) - 0.5) * delta, force)


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

    ``V`` is the volume the liquid fills (the chamber's less the cavity,
    V_i - Vc_i [m^3]) and ``dp_base`` B times its compression rate [Pa/s]
    (:func:`~liquidamp.device.kernels_model._fluid_rhs`), so that the liquid
    stays on its pressure curve, rho V_chamber = r(p) (V_chamber - Vc).
    The liquid's compression rate (volume per second) is w = dp_base V / B.
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
    >>> import numpy as np
    >>> from liquidamp.device.kernels import N_PRM, N_EP, P_AP, P_V01, P_V02, P_RHO0
    >>> from liquidamp.device.kernels import E_OMEGA, E_RM, E_COSA
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
def slip_memory_rate(v, w, distance):
    """dw/dt of the slip memory w in [-1, 1] of slip-weakening friction [1/s].

    ``dw/dt = |v| (sign(v) - w) / D``: w follows the slip direction over the
    weakening distance D [m], so after a reversal 1 - w sign(v) = 2 exp(-s / D),
    s the slip since the reversal (Dahl's law in the slip, without a level).

    Examples
    --------
    >>> slip_memory_rate(0.01, -1.0, 1e-3), slip_memory_rate(0.01, 1.0, 1e-3)
    (20.0, 0.0)
    """
    return abs(v) * (_sign(v) - w) / distance


@njit(cache=True, error_model="numpy")
def weakening(z, w, ratio):
    """Factor on smooth friction's force of slip-weakening friction [-].

    ``1 + beta (1 - w sign(z)) / 2``: 1 + beta where the bristles have just
    reversed (w still of the old direction), falling to 1 as the slip since the
    reversal passes the weakening distance (w of the bristles' sign): the
    breakaway level (1 + beta) F_c decays to the sliding level F_c over a slip
    distance, at any rate (Ida's / Palmer and Rice's slip-weakening law in the
    exponential form).  Continuous in the force F_c z times the factor.

    Examples
    --------
    >>> weakening(0.9, -1.0, 0.2), weakening(0.9, 1.0, 0.2), weakening(-0.5, 0.0, 0.2)
    (1.2, 1.0, 1.1)
    """
    return 1.0 + ratio * 0.5 * (1.0 - w * _sign(z))


# ------------------------------------------------------------ issue #20: real dampers
@njit(cache=True, error_model="numpy")
def gas_pressure(y, A_r, p_c, V_g, n, p_a):
    """Gauge pressure of a gas charge at absolute rod stroke y [m] [Pa].

    ``p_g = (p_c + p_a) (V_g / (V_g - A_r y))^n - p_a``: the rod entering the
    body by y (compression, y > 0) displaces A_r y of liquid into the
    accumulator and compresses its gas polytropically (index n) from V_g at
    the absolute pressure p_c + p_a (p_c the charge above the ambient p_a,
    which acts on the rod's outer end).  The gas volume is floored at
    1e-3 V_g so that trial states of an implicit stepper stay finite; a
    record that gets there is past the accumulator's travel.

    Examples
    --------
    >>> gas_pressure(0.0, 5e-4, 1e6, 1e-4, 1.4, 1e5)
    1000000.0
    >>> round(gas_pressure(0.02, 5e-4, 1e6, 1e-4, 1.0, 0.0) / 1e6, 12)   # V_g / (V_g - 1e-5)
    1.111111111111
    """
    V = V_g - A_r * y
    if V < 1.0e-3 * V_g:
        V = 1.0e-3 * V_g
    return (p_c + p_a) * (V_g / V) ** n - p_a


@njit(cache=True, error_model="numpy")
def gas_force(y, A_r, p_c, V_g, n, p_a):
    """Force of a gas charge on the rod at absolute stroke y [N]: A_r p_g(y) (:func:`gas_pressure`).

    The preload p_c A_r at y = 0 and the gas spring n (p_c + p_a) A_r^2 / V_g
    about it; a zero rod area gives no force at all (the sealed device).

    Examples
    --------
    >>> round(gas_force(0.0, 4.5e-5, 689475.7, 1e-4, 1.0, 101325.0), 6)   # 100 psi, 45 mm^2
    31.026407
    """
    return A_r * gas_pressure(y, A_r, p_c, V_g, n, p_a)


@njit(cache=True, error_model="numpy")
def gas_slope(y, A_r, p_c, V_g, n, p_a):
    """d p_g / dy of :func:`gas_pressure` [Pa/m]: n (p_g + p_a) A_r / (V_g - A_r y) (0 past
    the floor)."""
    V = V_g - A_r * y
    if V < 1.0e-3 * V_g:
        return 0.0
    return n * (gas_pressure(y, A_r, p_c, V_g, n, p_a) + p_a) * A_r / V


@njit(cache=True, error_model="numpy")
def valve_flow(dp, p_c, G_c, p_r, G_r):
    """Flow of a pair of spring-loaded valves, one per direction [m^3/s].

    ``q = relief_flow(dp, p_c, G_c)`` for dp >= 0 (compression: flow from
    chamber 1 to chamber 2) and ``relief_flow(dp, p_r, G_r)`` for dp < 0
    (rebound): each direction has its own cracking pressure and opening
    conductance, hence its own knee; with equal pairs it is
    :func:`relief_flow`.  Continuous at dp = 0 (both are 0 there).

    Examples
    --------
    >>> valve_flow(3e6, 2e6, 1e-9, 1e6, 2e-9), valve_flow(-3e6, 2e6, 1e-9, 1e6, 2e-9)
    (0.001, -0.004)
    """
    if dp >= 0.0:
        return relief_flow(dp, p_c, G_c)
    return relief_flow(dp, p_r, G_r)


@njit(cache=True, error_model="numpy", fastmath=_FM)
def yield_drop(m, uf, dpy0, dpy1, meps):
    """Field-dependent yield pressure drop of an MR/ER channel [Pa] (Bingham-like).

    (dp_y0 + dp_y1 |u_f|) tanh(m / m_eps): the yield stress of the field ``uf`` [V or A]
    over the channel, smoothed over the flow ``meps`` [kg/s] about zero mass flow ``m``
    [kg/s]; it always opposes the flow (passive for any field sign).

    Examples
    --------
    >>> round(yield_drop(1.0, 2.0, 6e4, 2.2e5, 5e-4), 3)   # well past m_eps: dp_y
    500000.0
    >>> yield_drop(0.0, 2.0, 6e4, 2.2e5, 5e-4)
    0.0
    """
    return (dpy0 + dpy1 * abs(uf)) * math.tanh(m / meps)
