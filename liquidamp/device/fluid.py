"""Fluid laws of the device: bulk modulus (eq. 2), density (eq. 3), losses (eqs. 4-6).

All functions take and return SI values: pressures [Pa], densities [kg/m^3],
mass flows [kg/s], volumetric flows [m^3/s].  Scalar functions use
:mod:`math` (they sit in the hot loop of the right-hand side); the ``_np``
variants accept arrays.

References
----------
.. [1] B. Titurus, "Generalized Liquid-Based Damping Device for Passive
   Vibration Control", AIAA J. 56(10), 2018, eqs. (2)-(6).
.. [2] A. Gholizadeh, R. Burton, G. Schoenau, "Fluid bulk modulus: a literature
   survey", Int. J. Fluid Power 12(3), 2011.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from liquidamp.errors import ParameterError

__all__ = [
    "air_fraction",
    "bulk_modulus_gholizadeh",
    "bulk_modulus_gholizadeh_dp",
    "density_constant_bulk",
    "density_gholizadeh",
    "loss_pressure",
    "loss_flow",
    "loss_flow_dp",
]


def air_fraction(inv_gamma: float) -> float:
    """Volumetric fraction of air X0 = 1/(1 + gamma) from 1/gamma = V_g0/V_l0.

    Parameters
    ----------
    inv_gamma : float
        Gas-to-liquid volume ratio 1/gamma at the reference pressure [-].

    Returns
    -------
    float
        X0 = V_g0 / (V_g0 + V_l0) [-] (eq. 2 of [1]_).

    Examples
    --------
    >>> round(air_fraction(0.1), 6)
    0.090909
    """
    return inv_gamma / (1.0 + inv_gamma)


def bulk_modulus_gholizadeh(p: float, B_l: float, X0: float, p0: float, n: float) -> float:
    """Tangent bulk modulus B(p) of a liquid-air mixture, eq. (2) [Pa].

    .. math:: B(p) = B_l \\frac{1 - X_0 + X_0 (p_0/p)^{1/n}}
                         {1 - X_0 + \\frac{B_l X_0}{n p} (p_0/p)^{1/n}}

    Parameters
    ----------
    p : float
        Absolute pressure, must be > 0 [Pa].
    B_l : float
        Bulk modulus of the pure liquid [Pa].
    X0 : float
        Volumetric fraction of air at ``p0`` [-].
    p0 : float
        Reference (filling) pressure [Pa].
    n : float
        Polytropic coefficient of the air [-].

    Returns
    -------
    float
        B(p) [Pa]; tends to ``n p`` as p -> 0 and to ``B_l`` as p -> inf.

    Notes
    -----
    The law is singular at p = 0 and undefined below; callers must keep the
    pressure positive (see :class:`liquidamp.errors.PressureError`).

    Examples
    --------
    >>> B = bulk_modulus_gholizadeh(101325.0, 1.5513e9, 0.0, 101325.0, 1.35)
    >>> B == 1.5513e9
    True
    >>> round(bulk_modulus_gholizadeh(101325.0, 1.5513e9, 1/11, 101325.0, 1.35) / 1e6, 4)
    1.5034
    """
    r = (p0 / p) ** (1.0 / n)
    return B_l * (1.0 - X0 + X0 * r) / (1.0 - X0 + B_l * X0 * r / (n * p))


def bulk_modulus_gholizadeh_dp(p: float, B_l: float, X0: float, p0: float, n: float) -> float:
    """Derivative dB/dp of eq. (2) [-], used by analytic Jacobians.

    Examples
    --------
    >>> args = (2e5, 1.5513e9, 0.05, 101325.0, 1.35)
    >>> h = 1.0
    >>> fd = (bulk_modulus_gholizadeh(2e5 + h, *args[1:]) -
    ...       bulk_modulus_gholizadeh(2e5 - h, *args[1:])) / (2 * h)
    >>> abs(bulk_modulus_gholizadeh_dp(*args) / fd - 1) < 1e-6
    True
    """
    r = (p0 / p) ** (1.0 / n)
    dr = -r / (n * p)  # d r / d p
    num = 1.0 - X0 + X0 * r
    den = 1.0 - X0 + B_l * X0 * r / (n * p)
    dnum = X0 * dr
    dden = B_l * X0 / n * (dr / p - r / (p * p))
    return B_l * (dnum * den - num * dden) / (den * den)


def density_constant_bulk(p, rho0: float, B0: float, p0: float):
    """Explicit density of a constant-bulk-modulus fluid, r(p) = rho0 exp((p - p0)/B0).

    Parameters
    ----------
    p : float or array
        Absolute pressure [Pa].
    rho0 : float
        Density at ``p0`` [kg/m^3].
    B0 : float
        Constant bulk modulus [Pa].
    p0 : float
        Reference pressure [Pa].

    Returns
    -------
    float or ndarray
        Density [kg/m^3] (the integral of eq. 3 with B = B0).

    Examples
    --------
    >>> round(density_constant_bulk(101325.0 + 1.5e9, 998.2, 1.5e9, 101325.0) / 998.2, 6)
    2.718282
    """
    return rho0 * np.exp((np.asarray(p) - p0) / B0) if np.ndim(p) else rho0 * math.exp(
        (p - p0) / B0
    )


def density_gholizadeh(p, rho0: float, B_l: float, X0: float, p0: float, n: float, *,
                       points: int = 64):
    """Density from eq. (3) integrated with the pressure-dependent law of eq. (2).

    rho(p) = rho0 exp( integral_{p0}^{p} dp'/B(p') ), evaluated by Gauss-Legendre
    quadrature on a logarithmic pressure scale (the integrand is smooth in
    ln p).  Used to check that the full model's density state stays on this
    curve (an invariant of eq. 10) and by the ideal pneumatic spring.

    Parameters
    ----------
    p : float or array
        Absolute pressure, > 0 [Pa].
    rho0, B_l, X0, p0, n
        As in :func:`bulk_modulus_gholizadeh`; ``rho0`` is the density at
        ``p0`` [kg/m^3].
    points : int
        Quadrature points.

    Returns
    -------
    float or ndarray
        Density [kg/m^3].

    Examples
    --------
    >>> rho = density_gholizadeh(101325.0, 998.2, 1.5513e9, 0.05, 101325.0, 1.35)
    >>> float(rho)
    998.2
    >>> [round(float(r), 2) for r in density_gholizadeh([5e4, 2e5], 998.2, 1.5513e9, 0.05,
    ...                                                 101325.0, 1.35)]
    [965.0, 1018.41]
    """
    p_arr = np.atleast_1d(np.asarray(p, dtype=float)).ravel()
    if not np.all(p_arr > 0.0):
        bad = p_arr[~(p_arr > 0.0)][0]
        raise ParameterError(f"pressure must be > 0 Pa (absolute) for eq. (3), got {bad:g} Pa")
    x, w = _gauss_legendre(int(points))
    a = math.log(p0)
    b = np.log(p_arr)[:, None]
    half = 0.5 * (b - a)
    pp = np.exp(half * x + 0.5 * (a + b))  # quadrature pressures, one row per p
    B = bulk_modulus_gholizadeh(pp, B_l, X0, p0, n)
    out = rho0 * np.exp(half[:, 0] * np.sum(w * pp / B, axis=1))
    return out.reshape(np.shape(p)) if np.ndim(p) else float(out[0])


@functools.lru_cache(maxsize=8)
def _gauss_legendre(points: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1] (cached)."""
    return np.polynomial.legendre.leggauss(points)


def loss_pressure(flow, k1: float, k2: float):
    """Resistive pressure drop, eq. (5): dp = k1 m + sign(m) k2 m^2 [Pa].

    Works for mass flow with (g1, g2) or volumetric flow with (c1, c2).

    Parameters
    ----------
    flow : float or array
        Mass flow [kg/s] or volumetric flow [m^3/s].
    k1 : float
        Linear coefficient (g1 [1/(m s)] or c1 [kg m^-4 s^-1]).
    k2 : float
        Quadratic coefficient (g2 [1/(kg m)] or c2 [kg m^-7]).

    Returns
    -------
    float or ndarray
        Pressure drop [Pa].

    Examples
    --------
    >>> loss_pressure(-2.0, 3.0, 0.5)
    -8.0
    """
    if np.ndim(flow):
        flow = np.asarray(flow, dtype=float)
        return k1 * flow + k2 * flow * np.abs(flow)
    return k1 * flow + k2 * flow * abs(flow)


def loss_flow(dp, k1: float, k2: float):
    """Analytic inverse of eq. (5): the flow that produces the pressure drop ``dp``.

    m = sign(dp) (-k1 + sqrt(k1^2 + 4 k2 |dp|)) / (2 k2), evaluated in the
    cancellation-free form m = 2 dp / (k1 + sqrt(k1^2 + 4 k2 |dp|)), which also
    holds for k2 = 0 (purely laminar) and k1 = 0 (purely quadratic).

    Parameters
    ----------
    dp : float or array
        Pressure drop [Pa].
    k1, k2 : float
        Coefficients as in :func:`loss_pressure`; not both zero.

    Returns
    -------
    float or ndarray
        Flow [kg/s or m^3/s].

    Examples
    --------
    >>> loss_flow(-8.0, 3.0, 0.5)
    -2.0
    >>> loss_flow(6.0, 3.0, 0.0)
    2.0
    """
    if np.ndim(dp):
        dp = np.asarray(dp, dtype=float)
        den = k1 + np.sqrt(k1 * k1 + 4.0 * k2 * np.abs(dp))
        return np.divide(2.0 * dp, den, out=np.zeros_like(dp), where=den > 0.0)
    if dp == 0.0:
        return 0.0
    return 2.0 * dp / (k1 + math.sqrt(k1 * k1 + 4.0 * k2 * abs(dp)))


def loss_flow_dp(dp: float, k1: float, k2: float) -> float:
    """Derivative d(flow)/d(dp) of :func:`loss_flow` [flow unit / Pa].

    Equals 1 / (k1 + 2 k2 |m|) = 1 / sqrt(k1^2 + 4 k2 |dp|); infinite at
    dp = 0 when k1 = 0 (purely quadratic loss), which is returned as a large
    finite slope so that Jacobians stay finite.

    Examples
    --------
    >>> loss_flow_dp(0.0, 4.0, 1.0)
    0.25
    """
    return 1.0 / max(math.sqrt(k1 * k1 + 4.0 * k2 * abs(dp)), 1e-300)
