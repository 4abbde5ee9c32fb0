"""An articulated rotor blade in lead-lag, in the rotating frame.

A rigid blade hinged in lag at the offset ``e`` from the shaft of a rotor
turning at ``Omega`` [rad/s], with the hub fixed.  The lag angle ``zeta``
[rad] is positive *lagging* (against the rotation).  Linearized about
``zeta = 0``:

.. math:: I_b \\ddot\\zeta + C_\\zeta \\dot\\zeta + (K_\\zeta + e S_b \\Omega^2)\\zeta
          = -a F + M

where ``S_b`` is the blade's static moment and ``I_b`` its inertia about
the lag hinge, ``K_zeta`` a lag spring, ``C_zeta`` the blade's own viscous
lag damper, ``F`` the force of a device attached through the moment arm
``a`` (stroke ``y = a zeta`` for small angles; see
:mod:`liquidamp.structure.port` for the sign convention) and ``M`` an
external lag moment [N m] about the hinge, positive lagging (the input
``moment``: the blade's periodic in-plane loads in forward flight, for one).  The lag natural
frequency is

.. math:: \\omega_\\zeta^2 = \\nu^2\\Omega^2 = \\frac{e S_b}{I_b}\\Omega^2 + \\frac{K_\\zeta}{I_b}.

Limits of validity: small lag angles, no flap-lag coupling, no aerodynamic
lag damping (negligible in ground resonance, Coleman & Feingold 1958).

References
----------
.. [1] W. Johnson, *Rotorcraft Aeromechanics*, Cambridge University Press,
   2013, Sec. 16.3 (lag dynamics) and Ch. 20 (ground resonance).
.. [2] R. L. Bielawa, *Rotary Wing Structural Dynamics and Aeroelasticity*,
   2nd ed., AIAA, 2006, Ch. 10.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import control
import numpy as np

from liquidamp.errors import ParameterError, check_nonnegative, check_positive
from liquidamp.structure.port import DevicePort

__all__ = ["ArticulatedBlade"]


@dataclass(frozen=True)
class ArticulatedBlade:
    """Parameters of an articulated blade in lead-lag (SI).

    Parameters
    ----------
    mass : float
        Blade mass m_b > 0 [kg] (enters the rotor's translating mass).
    static_moment : float
        First moment of mass about the lag hinge S_b > 0 [kg m].
    inertia : float
        Second moment of mass about the lag hinge I_b > 0 [kg m^2]; must
        satisfy S_b^2 <= m_b I_b.
    hinge_offset : float
        Lag-hinge offset from the shaft e >= 0 [m].
    damper_arm : float
        Moment arm of a device attached to the blade, stroke = arm * zeta
        > 0 [m].
    lag_spring : float
        Lag spring K_zeta >= 0 [N m/rad].
    lag_damping : float
        The blade's own viscous lag damper C_zeta >= 0 [N m s/rad].  Set it
        to 0 when a device on the port replaces it.

    Examples
    --------
    >>> b = ArticulatedBlade(94.9, 289.1, 1084.7, 0.3048, damper_arm=0.25)
    >>> round(b.nu(2 * math.pi * 4), 4)   # nu = sqrt(e S_b / I_b) without spring
    0.285
    >>> sys = b.statespace(2 * math.pi * 4)
    >>> sys.input_labels, sys.output_labels
    (['force', 'moment'], ['stroke', 'stroke_rate', 'zeta'])
    """

    mass: float
    static_moment: float
    inertia: float
    hinge_offset: float
    damper_arm: float
    lag_spring: float = 0.0
    lag_damping: float = 0.0

    def __post_init__(self) -> None:
        m = check_positive("blade mass", self.mass, "kg")
        S = check_positive("blade static moment S_b", self.static_moment, "kg m")
        I = check_positive("blade inertia I_b", self.inertia, "kg m^2")
        check_nonnegative("hinge offset e", self.hinge_offset, "m")
        check_positive("damper arm", self.damper_arm, "m")
        check_nonnegative("lag spring K_zeta", self.lag_spring, "N m/rad")
        check_nonnegative("lag damping C_zeta", self.lag_damping, "N m s/rad")
        if S * S > m * I * (1.0 + 1e-12):
            raise ParameterError(
                f"blade static moment S_b={S:g} kg m is too large for mass {m:g} kg and "
                f"inertia {I:g} kg m^2: need S_b^2 <= m_b I_b (= {m * I:.6g} kg^2 m^2)"
            )

    def replace(self, **changes) -> ArticulatedBlade:
        """Copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def nu(self, Omega: float) -> float:
        """Lag frequency in per rev, nu = omega_zeta / Omega [-] (Omega > 0 [rad/s])."""
        W = check_positive("rotor speed Omega", Omega, "rad/s")
        return self.lag_frequency(W) / W

    def lag_frequency(self, Omega: float) -> float:
        """Undamped lag natural frequency sqrt((K + e S_b Omega^2)/I_b) [rad/s]."""
        W = check_nonnegative("rotor speed Omega", Omega, "rad/s")
        return math.sqrt(self.lag_stiffness(W) / self.inertia)

    def lag_stiffness(self, Omega: float) -> float:
        """Lag stiffness K_zeta + e S_b Omega^2 [N m/rad] (spring plus centrifugal)."""
        return self.lag_spring + self.hinge_offset * self.static_moment * Omega**2

    @property
    def state_names(self) -> tuple[str, ...]:
        """``("zeta", "zeta_dot")``: lag angle [rad] and rate [rad/s]."""
        return ("zeta", "zeta_dot")

    @property
    def ports(self) -> tuple[DevicePort, ...]:
        """The lag-damper port ``"lag"``: stroke = arm * zeta [m]."""
        return (DevicePort("lag", "stroke", "stroke_rate", "force", self.damper_arm, "zeta"),)

    @property
    def input_names(self) -> tuple[str, ...]:
        """``force`` [N] (the device port) and ``moment`` [N m] (external lag moment)."""
        return ("force", "moment")

    @property
    def output_names(self) -> tuple[str, ...]:
        """``stroke`` [m], ``stroke_rate`` [m/s] and ``zeta`` [rad]."""
        return ("stroke", "stroke_rate", "zeta")

    def second_order(self, Omega: float, psi: float = 0.0):
        """``M, C, K`` (1 x 1) of ``I_b zeta'' + C_zeta zeta' + K zeta = G u`` [kg m^2, N m s, N m].

        ``psi`` [rad] is accepted for the interface of a periodic host; the
        blade's coefficients do not depend on it.
        """
        W = check_nonnegative("rotor speed Omega", Omega, "rad/s")
        return (np.array([[self.inertia]]), np.array([[self.lag_damping]]),
                np.array([[self.lag_stiffness(W)]]))

    def harmonic_second_order(self, Omega: float):
        """:meth:`second_order` as first harmonics of the azimuth (constant: the sine and
        cosine parts are zero), in the form of
        :meth:`~liquidamp.structure.rotor.GroundResonanceRotor.harmonic_second_order`.

        Examples
        --------
        >>> b = ArticulatedBlade(94.9, 289.1, 1084.7, 0.3048, damper_arm=0.25)
        >>> M0, Mc, Ms, C0, Cc, Cs, K0, Kc, Ks = b.harmonic_second_order(25.0)
        >>> float(M0[0, 0]), float(K0[0, 0]) == b.lag_stiffness(25.0), float(Mc[0, 0])
        (1084.7, True, 0.0)
        """
        M, C, K = self.second_order(Omega)
        z = np.zeros((1, 1))
        return (M, z, z, C, z, z, K, z, z)

    def force_matrix(self) -> np.ndarray:
        """``G`` (1 x 2) mapping ``input_names`` to the lag moment: ``[-a, 1]``."""
        return np.array([[-self.damper_arm, 1.0]])

    def output_matrix(self) -> np.ndarray:
        """``C`` (3 x 2) mapping the states to ``output_names``."""
        a = self.damper_arm
        return np.array([[a, 0.0], [0.0, a], [1.0, 0.0]])

    def statespace(self, Omega: float) -> control.StateSpace:
        """Named state-space model at rotor speed ``Omega`` [rad/s].

        States ``zeta`` [rad], ``zeta_dot`` [rad/s]; inputs ``force`` [N]
        (the device port) and ``moment`` [N m] (external lag moment, positive
        lagging); outputs ``stroke`` [m], ``stroke_rate`` [m/s], ``zeta`` [rad].
        """
        W = check_nonnegative("rotor speed Omega", Omega, "rad/s")
        I = self.inertia
        A = np.array([[0.0, 1.0], [-self.lag_stiffness(W) / I, -self.lag_damping / I]])
        B = np.zeros((2, 2))
        B[1] = self.force_matrix()[0] / I
        return control.ss(
            A, B, self.output_matrix(), np.zeros((3, 2)),
            states=list(self.state_names), inputs=list(self.input_names),
            outputs=list(self.output_names), name="blade",
        )
