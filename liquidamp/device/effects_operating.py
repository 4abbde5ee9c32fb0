"""Operating-condition effects (the rotating frame: the device on a rotor).

Part of the catalogue of :mod:`liquidamp.device.effects` (the public face: the
table, the composition order, :func:`~liquidamp.device.effects.with_effects`);
the :class:`~liquidamp.device.effects_base.Effect` base is in
:mod:`liquidamp.device.effects_base`.  References as in :mod:`liquidamp.device.effects`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.effects_base import (
    Effect,
    _shaped,
)
from liquidamp.device.rotating import ROTATING_BASES, heads, rest_state
from liquidamp.errors import (
    ParameterError,
    check_finite,
    check_nonnegative,
)


@dataclass(frozen=True)
class RotatingFrame(Effect):
    """The device on a rotor: the centrifugal field along its axis.

    A lag damper turning with the rotor at Omega, its mid-point (the piston
    at zero stroke) at the radius r_m and its axis (chamber 1 -> chamber 2)
    at the angle theta to the radial direction in the plane of rotation.
    With the head h(s) = r_m cos(theta) s + s^2/2 along the axis (s from
    the mid-point; the integral of r dr projected on the axis) and h_i its
    mean over chamber i (chamber 1 on [-L1, -y], chamber 2 on [-y, L2],
    L_i = V0i / A_p, y the piston stroke), the centrifugal pressure rise
    from chamber 1's lumped pressure to chamber 2's ([1]_, rigid-body
    rotation) is

        Delta p_c(y) = rho_l Omega^2 (h_2 - h_1)
                     = rho_l Omega^2 [r_m cos(theta) (L1 + L2)/2
                       + (L2^2 - L1^2)/6 - (L1 + L2) y / 6],

    i.e. rho_l Omega^2 r_m L cos(theta) for equal chambers of length L at
    zero stroke.  It enters (kernel :func:`~liquidamp.device.kernels.rotating_heads`):

    - the channel momentum equation (eq. 10 of [2]_, ``full``, ``inertial``,
      ``inertial_2state``): S_t dm12/dt = p1 - p2 + Delta p_c - g1 m12 -
      g2 m12 |m12| (the Coriolis force is normal to the flow);
    - the loss relation of the reductions without inertia (``no_inertia``,
      ``constant_bulk``, ``volumetric``, ``single_state``) and the leakage
      bypass: the flow is driven by dp + Delta p_c;
    - the load-cell force: F = A_p (p1 - p2 + Delta p_c) (both piston faces
      at one point, so F = 0 at rest);
    - the cavitation effect: its switch acts on each chamber's
      innermost-point pressure (:meth:`inboard_pressures`), so a cavity
      opens at the inboard end and holds it at p_v;
    - the rest state: sealed and unpressurized, the device keeps its filling
      mass, and at rest p2 - p1 = Delta p_c: the outboard chamber rises, the
      inboard one falls (:func:`~liquidamp.device.rotating.rest_state`), so a
      run on the rotor starts at rest.

    The models without chamber pressures or channel flow (``maxwell``, the
    ideal elements, ``viscous``) refuse it: the rotation acts through the
    mean chamber pressures, which they do not hold.  Zero speed is the bare
    model exactly.  A tangential axis (theta = pi/2) leaves a symmetric
    device's rest state unchanged; only the stroke term of Delta p_c
    remains, a stiffness change of A_p dDelta p_c/dy = -A_p rho_l Omega^2
    (L1 + L2)/6 in the fluid's flow path (a few N/m).  Rotor speed and
    radius are operating conditions, not fitted (no ``fit_keys``).  For a
    device on the ground-resonance host, use the host's rotor speed.  The
    derivation, assumptions and limits are in :mod:`liquidamp.device.rotating`.

    Parameters
    ----------
    rotor_speed_rad_per_s : float
        Rotor speed Omega >= 0 [rad/s].
    mounting_radius_m : float
        Distance r_m >= 0 from the shaft to the device mid-point [m].
    axis_angle_rad : float
        Angle theta between the device axis (chamber 1 -> chamber 2) and the
        radial direction, in the plane of rotation [rad]: 0 = chamber 2
        outboard, pi = chamber 1 outboard, pi/2 = tangential.

    References
    ----------
    .. [1] F. M. White, Fluid Mechanics, 7th ed., McGraw-Hill, 2011, Sec. 2.9.
    .. [2] B. Titurus, AIAA J. 56(10), 2018, eqs. (6), (10)-(18).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> p = preset("reference")                       # L1 = L2 = V0/A_p = 25 mm
    >>> rf = RotatingFrame(26.18, 0.3, 0.0)           # 250 rpm, 0.3 m, radial
    >>> dp_c = rf.pressure_rise(p)                    # rho_l Omega^2 r_m L
    >>> round(dp_c, 1), round(dp_c / (p.rho_l * 26.18**2 * 0.3 * p.V01 / p.A_p), 12)
    (5131.3, 1.0)
    >>> from liquidamp.device.effects import with_effects
    >>> m = with_effects(get_model("full"), rf)
    >>> x = m.initial_state(p, 0.0)                   # at rest on the rotor
    >>> round(float(x[2] - x[0]), 1), [round(float(q)) for q in (x[0], x[2])]
    (5131.3, [98812, 103944])
    >>> abs(float(m.force(0.0, x, (0.0, 0.0, 0.0), p))) < 1e-9   # both faces pushed alike
    True
    >>> [round(q) for q in rf.inboard_pressures(x[0], x[2], p)]   # innermost points
    [96389, 101307]
    """

    rotor_speed_rad_per_s: float = 0.0
    mounting_radius_m: float = 0.0
    axis_angle_rad: float = 0.0
    name: ClassVar[str] = "rotating_frame"
    units: ClassVar[dict] = {"rotor_speed_rad_per_s": "rad/s", "mounting_radius_m": "m",
                             "axis_angle_rad": "rad"}
    fit_keys: ClassVar[tuple] = ()
    bounds: ClassVar[dict] = {}
    order: ClassVar[int] = 8
    description: ClassVar[str] = "centrifugal field of a device turning with a rotor"
    slot: ClassVar[int] = K.S_ROT
    kind: ClassVar[str] = "fluid"

    def __post_init__(self):
        check_nonnegative("rotating_frame rotor_speed_rad_per_s", self.rotor_speed_rad_per_s,
                          "rad/s")
        check_nonnegative("rotating_frame mounting_radius_m", self.mounting_radius_m, "m")
        check_finite("rotating_frame axis_angle_rad", self.axis_angle_rad, "rad")

    describing_reason: ClassVar[str | None] = (
        "it moves the mean chamber pressures and with them the air's bulk modulus")

    def check(self, model):
        if model.base not in ROTATING_BASES:
            raise ParameterError(
                f"effect {self.name!r} needs a model with chamber pressures or channel flow; "
                f"model {model.name!r} ({model.family}) has states "
                f"({', '.join(model.state_names) or 'none'}): the centrifugal field acts "
                "through the mean chamber pressures (bulk modulus, cavitation margin), which "
                "it does not hold, and in its assumptions it would be a constant pressure "
                "offset that leaves the force unchanged; use one of "
                f"{', '.join(ROTATING_BASES)}")

    def pack(self, ep):
        ep[K.E_OMEGA] = self.rotor_speed_rad_per_s
        ep[K.E_RM] = self.mounting_radius_m
        ep[K.E_COSA] = math.cos(self.axis_angle_rad)

    def _ep(self) -> np.ndarray:
        ep = np.zeros(K.N_EP)
        self.pack(ep)
        return ep

    def pressure_rise(self, params, stroke=0.0):
        """Centrifugal pressure rise Delta p_c from chamber 1 to chamber 2 [Pa] (vectorized).

        Parameters
        ----------
        params : DeviceParams
            Device (chamber lengths V0i / A_p, liquid density rho_l).
        stroke : float or array
            Piston stroke y [m].

        Returns
        -------
        float or ndarray
            rho_l Omega^2 (h_2 - h_1) at each stroke [Pa].
        """
        return _shaped(heads(params, self._ep(), stroke)[0], stroke)

    def inboard_pressures(self, p1, p2, params, stroke=0.0):
        """Pressure at each chamber's innermost point [Pa]: the cavitation margin (vectorized).

        The chambers' lumped pressures (the model's p1, p2, volume means)
        lowered by the centrifugal head between the chamber's mean and its
        point nearest the shaft, p_i + rho_l Omega^2 (min h - h_i): the
        inboard end, unless the axis passes its point nearest the shaft
        inside the chamber (nearly tangential axes).  Compare it with the
        vapour pressure.

        Parameters
        ----------
        p1, p2 : float or array
            Lumped chamber pressures [Pa] (e.g. ``response.p1``, ``response.p2``).
        params : DeviceParams
            Device.
        stroke : float or array
            Piston stroke y [m] (the rod stroke without kinematic effects).

        Returns
        -------
        (p1_in, p2_in) : floats or ndarrays
            Least pressure in chamber 1 and chamber 2 [Pa].
        """
        _, o1, o2 = heads(params, self._ep(), stroke)
        return (_shaped(np.asarray(p1, float) + o1, p1, stroke),
                _shaped(np.asarray(p2, float) + o2, p2, stroke))

    def rest_base_state(self, model, params, y0, x_base):
        """The static equilibrium on the rotor (:func:`~liquidamp.device.rotating.rest_state`)."""
        if self.rotor_speed_rad_per_s == 0.0:
            return x_base
        dp_c = float(self.pressure_rise(params, y0))
        return rest_state(model.base, params, y0, dp_c, x_base)
