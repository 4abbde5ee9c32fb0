r"""The device in a rotating frame: how the centrifugal field enters the model family.

A lag damper mounted on a rotor turns with the rotor at the speed Omega.  In
the co-rotating frame the liquid sees the centrifugal body force
Omega^2 r per unit mass (r the distance from the shaft), which has the
potential -Omega^2 r^2 / 2 (rigid-body rotation, [1]_, [2]_).  The Coriolis
force is normal to the channel flow, so it does no work along the channel
and drops out of the one-dimensional momentum balance ([3]_); gravity
(|g| << Omega^2 r on a rotor), hub accelerations and the small rotation of
the device with the blade's own lag motion are neglected.  The device itself
is not pressurized: the field moves its mean chamber pressures, and with
them the bulk modulus of the entrained air (eq. 2 of [4]_) and the margin to
cavitation.  The compiled physics is :func:`liquidamp.device.kernels.rotating_heads`;
this module holds the Python-side helpers of the effect
:class:`liquidamp.device.effects.RotatingFrame`.

Geometry
--------
The axis coordinate ``s`` runs along the device axis from chamber 1 to
chamber 2, with s = 0 at the device mid-point (the piston at zero stroke),
which sits at the radius r_m.  The axis makes the angle theta with the
radial direction, in the plane of rotation (theta = 0: chamber 2 outboard;
theta = pi: chamber 1 outboard; theta = pi/2: tangential), so that

.. math:: r(s)^2 = r_m^2 + 2 r_m \cos\theta\, s + s^2 .

The chambers are cylinders of the piston area A_p that meet at the piston:
chamber 1 spans [-L1, -y], chamber 2 [-y, L2] at the piston stroke y
(V1 = V01 - A_p y, V2 = V02 + A_p y), with L_i = V0i / A_p.  Define the head

.. math:: h(s) = \int_0^s \mathbf{r}\cdot\mathbf{e}\, ds' = r_m\cos\theta\, s + s^2/2,

(the integral of r dr projected on the axis) and h_i its mean over chamber
i.  In each chamber the liquid is in rigid-body rotation (the chamber
pressure equalises at the speed of sound, far faster than the stroke), so
the pressure field is p(s) = p_i + rho_l Omega^2 (h(s) - h_i), where the
lumped pressure p_i of the model is the volume mean, the pressure that
goes with the chamber's mean density.  To first order in the chamber
length this is the pressure at the chamber's mid-point; the s^2 term adds
rho_l Omega^2 L_i^2 / 24, which cancels between equal chambers.

How it enters the model family
------------------------------
Channel momentum (eq. 10 of [4]_, from eq. 6).  Integrating the momentum
balance along any path from the lumped point of chamber 1 through port A,
the channel and port B to that of chamber 2 (the field is conservative, so
the channel's route and length do not matter, only where its ends are held:
the chambers' hydrostatics carry the rest),

.. math:: S_t \dot m_{12} = p_1 - p_2 + \Delta p_c - g_1 m_{12} - g_2 m_{12}|m_{12}|,

.. math:: \Delta p_c(y) = \rho_l \Omega^2 (h_2 - h_1)
    = \rho_l \Omega^2 \Big[ r_m\cos\theta\,\frac{L_1 + L_2}{2}
      + \frac{L_2^2 - L_1^2}{6} - \frac{L_1 + L_2}{6}\, y \Big].

For a symmetric device (L1 = L2 = L) at zero stroke this is
rho_l Omega^2 r_m L cos(theta): the rise of a straight channel of length L
(the distance between the chamber mid-points) along the axis, centred at
r_m.  The stroke term, slope -rho_l Omega^2 (L1 + L2)/6, comes from the
lumped points moving with the piston in the non-uniform field; it is tiny
(a few N/m of stiffness on a lag damper) but keeps the model exact.

Reductions.  Every flow path is driven by p1 - p2 + Delta p_c: the
inverted loss relation of the no-inertia reductions (eqs. 11, 13, 14, 15:
q = q(dp + Delta p_c)), the channel equation of the inertial ones (eqs. 17,
18) and the leakage bypass past the piston.

Load-cell force.  The piston faces sit at the same point s = -y, so
F = A_p (p_face1 - p_face2) = A_p (p1 - p2 + Delta p_c): at rest the
connected, resting liquid pushes equally on both faces, F = 0.

Cavitation margin.  The least pressure of chamber i is at its innermost
point (its inboard end, unless the point of the axis nearest the shaft lies
inside the chamber): p_i + o_i, o_i = rho_l Omega^2 (min h - h_i) <= 0
(:meth:`~liquidamp.device.effects.RotatingFrame.inboard_pressures`).  The
cavitation effect applies its switch to this pressure, whose rate is
dp_i/dt + (do_i/dy) v (the offset moves with the piston), so a cavity opens
at the inboard end first and holds the inboard-end pressure at p_v.

Rest state.  At rest on the rotor (v = 0, no flow) the sealed device holds
p2 - p1 = Delta p_c(y0), and its liquid mass is that of the filling,
rho_l (V01 + V02): the outboard chamber rises, the inboard one falls, by
amounts set by the chambers' bulk moduli (:func:`rest_state`).  A run
started there stays at rest.

Models without pressures or channel flow (maxwell, dashpot, spring,
inerter, dashpot_inerter, viscous) refuse the effect: the rotation acts on
the device through its mean chamber pressures, which they do not hold; in
their own assumptions (constant bulk moduli, no mean pressure) the field
is a constant pressure offset that leaves the force unchanged, so an
"equivalent" would only hide that the effect is missing.

References
----------
.. [1] F. M. White, Fluid Mechanics, 7th ed., McGraw-Hill, 2011, Sec. 2.9
   (pressure distribution in rigid-body rotation, p = const + rho Omega^2 r^2 / 2).
.. [2] R. Fitzpatrick, Theoretical Fluid Mechanics, IOP, 2017, Sec. 2.13
   (rotational hydrostatics: the centrifugal potential -Omega^2 (x^2 + y^2)/2).
.. [3] E. M. Greitzer, C. S. Tan, M. B. Graf, Internal Flow, Cambridge
   University Press, 2004, Sec. 7.1 (momentum equation in a rotating frame:
   Coriolis and centrifugal terms).
.. [4] B. Titurus, "Generalized Liquid-Based Damping Device for Passive
   Vibration Control", AIAA J. 56(10), 2018, eqs. (2), (6), (10)-(18).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from liquidamp.device import kernels as K
from liquidamp.device.fluid import density_constant_bulk, density_gholizadeh
from liquidamp.errors import ParameterError

__all__ = ["heads", "rest_state", "least_pressures", "ROTATING_BASES"]

#: Base equations the rotating frame applies to (chamber pressures or channel flow).
ROTATING_BASES = ("full", "no_inertia", "constant_bulk", "volumetric", "single_state",
                  "inertial", "inertial_2state")


def heads(params, ep: np.ndarray, stroke=0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centrifugal pressure rise and inboard offsets at the piston stroke (vectorized).

    Parameters
    ----------
    params : DeviceParams
        Device (A_p, V01, V02, rho_l).
    ep : ndarray
        Effect vector holding the rotating frame's slots (``E_OMEGA``,
        ``E_RM``, ``E_COSA`` of :mod:`liquidamp.device.kernels`).
    stroke : float or array
        Piston stroke y [m].

    Returns
    -------
    (dp_c, o1, o2) : ndarrays of the shape of ``stroke``
        Delta p_c(y) [Pa] and each chamber's innermost-point pressure minus
        its lumped pressure [Pa] (module notes; :func:`~liquidamp.device.kernels.rotating_heads`).
    """
    prm = K.pack_params(params)
    y = np.asarray(stroke, float)
    flat = y.reshape(-1)
    out = np.empty((3, flat.size))
    for k, yk in enumerate(flat):
        out[:, k] = K.rotating_heads(float(yk), prm, ep)
    return tuple(out[i].reshape(y.shape) for i in range(3))


def _densities(base: str, params):
    """rho_i(p) [kg/m^3] of each chamber along its compression path from (p0, rho_l)."""
    p = params
    if base in ("full", "no_inertia") and p.bulk_law == "gholizadeh":
        return (lambda q: density_gholizadeh(q, p.rho0, p.B_l, p.X01, p.p0, p.n),
                lambda q: density_gholizadeh(q, p.rho0, p.B_l, p.X02, p.p0, p.n))
    return (lambda q: density_constant_bulk(q, p.rho0, p.B01, p.p0),
            lambda q: density_constant_bulk(q, p.rho0, p.B02, p.p0))


def rest_state(base: str, params, y0: float, dp_c: float, x_base: np.ndarray) -> np.ndarray:
    """States of base model ``base`` at rest on the rotor: sealed, not pressurized.

    The static equilibrium with the rotating frame: no flow, p2 - p1 =
    ``dp_c`` (so the channel, the loss relation and any leakage carry
    nothing), and the liquid mass of the filling, rho_l (V01 + V02), kept
    (``volumetric``: its own invariant V1 p1 / B01 + V2 p2 / B02, which is
    what its equations conserve); ``single_state`` and ``inertial_2state``
    hold dp = -dp_c.

    Parameters
    ----------
    base : str
        Base equation (one of :data:`ROTATING_BASES`).
    params : DeviceParams
        Device.
    y0 : float
        Stroke at rest [m].
    dp_c : float
        Centrifugal pressure rise Delta p_c(y0) from chamber 1 to chamber 2 [Pa].
    x_base : ndarray
        The base model's rest state without rotation (copied, not changed).

    Returns
    -------
    ndarray
        The base states at rest under rotation.

    Raises
    ------
    ParameterError
        When no rest state has both chamber pressures > 0 under the bulk law
        of eq. (2): the inboard chamber would have to expand its air past
        zero pressure (the rotor speed or the radius is too large for an
        unpressurized device).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> x = rest_state("constant_bulk", p, 0.0, 2000.0, np.array([p.p0, p.p0]))
    >>> round(float(x[1] - x[0]), 9), bool(x[0] < p.p0 < x[1])
    (2000.0, True)
    """
    x = np.array(x_base, dtype=float)
    if dp_c == 0.0:
        return x
    p = params
    if base in ("single_state", "inertial_2state"):
        x[0] = -dp_c
        return x
    V1, V2 = p.V01 - p.A_p * y0, p.V02 + p.A_p * y0
    if base == "volumetric":
        p1 = p.p0 - V2 / p.B02 * dp_c / (V1 / p.B01 + V2 / p.B02)
        x[0], x[1] = p1, p1 + dp_c
        return x
    if base not in ROTATING_BASES:
        raise ParameterError(f"no rest state under rotation for model {base!r}")
    r1, r2 = _densities(base, p)
    target = p.rho0 * (V1 + V2)
    gholizadeh = base in ("full", "no_inertia") and p.bulk_law == "gholizadeh"

    def excess(p1):
        return (float(r1(p1)) * V1 + float(r2(p1 + dp_c)) * V2) / target - 1.0

    a = abs(dp_c)
    lo = p.p0 - max(dp_c, 0.0)  # the higher chamber at p0: too little mass
    hi = lo + a                 # the lower chamber at p0: too much
    if gholizadeh and lo + min(dp_c, 0.0) <= 0.0:
        lo = 1e-9 * p.p0 - min(dp_c, 0.0)  # the lower chamber just above zero pressure
        if excess(lo) > 0.0:
            raise ParameterError(
                f"rotating_frame: no rest state with positive chamber pressures: the "
                f"centrifugal pressure rise {a:.6g} Pa exceeds what the inboard chamber's air "
                f"can give (filling pressure p0 = {p.p0:g} Pa, 1/gamma = "
                f"{p.inv_gamma1 if dp_c > 0 else p.inv_gamma2:g}); lower the rotor speed "
                "or the radius, or pressurize the device (raise p0)")
    p1 = brentq(excess, lo, hi, xtol=1e-13 * p.p0, rtol=4.0 * np.finfo(float).eps,
                maxiter=200)
    p2 = p1 + dp_c
    if base in ("full", "no_inertia"):
        x[0], x[1], x[2], x[3] = p1, float(r1(p1)), p2, float(r2(p2))
    else:
        x[0], x[1] = p1, p2
    return x


def least_pressures(model, x, u, params):
    """Least pressure in each chamber [Pa] (vectorized): the margin to cavitation.

    The lumped chamber pressures (``model.pressures``), lowered with a
    :class:`RotatingFrame` to each chamber's innermost point
    (:meth:`RotatingFrame.inboard_pressures`, at the piston stroke).

    Parameters
    ----------
    model : DeviceModel
        A model with chamber pressure states (any effects).
    x : array
        States, shape (n,) or (n, N).
    u : tuple
        Rod stroke (y [m], v [m/s], a [m/s^2]), scalars or arrays of length N.
    params : DeviceParams
        Device.

    Returns
    -------
    (p1, p2) : floats or ndarrays
        Least pressure in chamber 1 and chamber 2 [Pa].

    Raises
    ------
    ParameterError
        For a model without chamber pressures.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.effects import RotatingFrame, with_effects
    >>> from liquidamp.device.models import get_model
    >>> p = preset("reference")
    >>> m = with_effects(get_model("inertial"), RotatingFrame(26.18, 0.3048))
    >>> x = m.initial_state(p, 0.0)
    >>> [round(float(q)) for q in least_pressures(m, x, (0.0, 0.0, 0.0), p)]
    [96252, 101252]
    """
    from liquidamp.device.effects_base import piston_stroke_index

    if model.pressures is None:
        raise ParameterError(f"model {model.name!r} has no chamber pressure states")
    p1, p2 = model.pressures(x, u, params)
    rf = model.effect("rotating_frame")
    if rf is None:
        return p1, p2
    ip = piston_stroke_index(model.effects, model.n_base_states)
    y = u[0] if ip is None else np.asarray(x)[ip]
    return rf.inboard_pressures(p1, p2, params, y)
