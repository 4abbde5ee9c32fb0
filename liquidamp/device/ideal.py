"""Ideal characteristics of the device for comparison overlays (Figs. 7-11 of the paper).

Each isolates one fluid effect without dynamic interaction:

- :func:`ideal_spring_force` -- closed channel: each chamber keeps its mass
  and the pressures follow the liquid-air law (eq. 2-3) as the volumes
  change: the nonlinear pneumatic spring of Fig. 7.
- :func:`ideal_damper_force` -- incompressible liquid: the channel carries
  q = A_p v and the force is A_p (c1 q + c2 q|q|), eq. (5): Fig. 8.
- :func:`ideal_inerter_force` -- F = b_L a, eq. (20): Fig. 9.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. III.D and IV.D.
"""

from __future__ import annotations

import numpy as np

from liquidamp.device.fluid import bulk_modulus_gholizadeh, loss_pressure
from liquidamp.device.params import DeviceParams

__all__ = ["ideal_spring_force", "ideal_damper_force", "ideal_inerter_force"]


def _pressure_of_density(X0: float, params: DeviceParams):
    """Inverse of the chamber's density law, p(rho) [Pa], as a callable on arrays.

    For eq. (2) the law ln(rho/rho0) = integral dp/B is tabulated on a
    logarithmic pressure grid (Simpson-accurate cumulative quadrature) and
    inverted by a monotone cubic interpolant; the constant-bulk law is
    inverted in closed form.
    """
    from scipy.integrate import cumulative_simpson
    from scipy.interpolate import PchipInterpolator

    if params.bulk_law == "constant":
        B0 = bulk_modulus_gholizadeh(params.p0, params.B_l, X0, params.p0, params.n)
        return lambda rho: params.p0 + B0 * np.log(rho / params.rho0)
    s = np.linspace(np.log(params.p0 * 1e-3), np.log(params.p0 * 1e3), 4001)
    p = np.exp(s)
    B = np.array([bulk_modulus_gholizadeh(q, params.B_l, X0, params.p0, params.n) for q in p])
    ln_rho = cumulative_simpson(p / B, x=s, initial=0.0)
    ln_rho -= np.interp(np.log(params.p0), s, ln_rho)
    inverse = PchipInterpolator(ln_rho, s, extrapolate=False)

    def pressure(rho):
        out = np.exp(inverse(np.log(np.asarray(rho, float) / params.rho0)))
        if not np.all(np.isfinite(out)):
            from liquidamp.errors import ParameterError

            raise ParameterError(
                "ideal spring: chamber density outside the tabulated range "
                f"[{params.p0 * 1e-3:g}, {params.p0 * 1e3:g}] Pa of pressure"
            )
        return out

    return pressure


def ideal_spring_force(y, params: DeviceParams):
    """Closed-channel (pneumatic spring) force at stroke ``y`` [N].

    Chamber masses are those at rest, rho0 V0i; each chamber's density at
    stroke y is M_i / V_i(y) and its pressure follows by inverting the
    density law (eq. 3 with eq. 2).

    Parameters
    ----------
    y : float or array
        Stroke, |y| < V0/A_p [m].
    params : DeviceParams
        Device parameters.

    Returns
    -------
    float or ndarray
        Force A_p (p1 - p2) [N]; its slope at y = 0 is k_D.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("spring")
    >>> h = 1e-6
    >>> slope = (ideal_spring_force(h, p) - ideal_spring_force(-h, p)) / (2 * h)
    >>> round(slope / p.k_D, 5)
    1.0
    """
    ys = np.atleast_1d(np.asarray(y, float))
    M1, M2 = params.rho0 * params.V01, params.rho0 * params.V02
    V1, V2 = params.V01 - params.A_p * ys, params.V02 + params.A_p * ys
    p1 = _pressure_of_density(params.X01, params)(M1 / V1)
    p2 = _pressure_of_density(params.X02, params)(M2 / V2)
    out = params.A_p * (p1 - p2)
    return out if np.ndim(y) else float(out[0])


def ideal_damper_force(v, params: DeviceParams):
    """Incompressible nonlinear damper force A_p (c1 q + c2 q|q|), q = A_p v [N].

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("damper")
    >>> round(ideal_damper_force(1e-9, p) / (p.c_L * 1e-9), 6)
    1.0
    """
    q = params.A_p * np.asarray(v, float) if np.ndim(v) else params.A_p * v
    return params.A_p * loss_pressure(q, params.c1, params.c2)


def ideal_inerter_force(a, params: DeviceParams):
    """Ideal inerter force b_L a, eq. (20) [N].

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> round(ideal_inerter_force(1.0, preset("paper_initial")), 1)
    89.4
    """
    return params.b_L * (np.asarray(a, float) if np.ndim(a) else a)


