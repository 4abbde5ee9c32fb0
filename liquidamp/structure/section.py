"""The typical wing section in pitch and plunge (flutter and divergence).

A rigid airfoil of semichord ``b`` on a plunge spring ``k_h`` and a pitch
spring ``k_theta`` at the reference point (elastic axis) ``a`` semichords
aft of mid-chord; the mass centre lies ``e`` semichords aft of mid-chord.
Plunge ``h`` is positive down, pitch ``theta`` nose up.  Per unit span:

.. math::

   m\\ddot h + m b x_\\theta\\ddot\\theta + k_h h &= -L - F_h/s \\\\
   m b x_\\theta\\ddot h + I_\\theta\\ddot\\theta + k_\\theta\\theta &= M - a_\\theta F_\\theta/s

with ``x_theta = e - a``, ``I_theta = m b^2 r^2``, ``omega_h^2 = k_h/m``,
``omega_theta^2 = k_theta/I_theta``, ``sigma = omega_h/omega_theta``,
``mu = m/(pi rho b^2)``.  ``L`` and ``M`` are the aerodynamic lift and
moment about the reference point per span (:mod:`liquidamp.structure.aero`).
``F_h`` and ``F_theta`` [N] are the forces of devices on the plunge port
(stroke ``h``) and on the pitch port (stroke ``a_theta theta``) of a
section of span ``s`` [m] (see :mod:`liquidamp.structure.port` for the sign
convention).

The nondimensional parameters ``a, e, mu, r^2, sigma`` decide flutter and
divergence in terms of ``V = U/(b omega_theta)``; the dimensional ones
(``b``, ``omega_theta``, ``rho``, span, pitch arm) only scale the SI
state-space model.  The preset ``hodges-pierce`` stores Hodges & Pierce's
nondimensional set with a chosen ``b = 0.5 m``, ``omega_theta = 2 pi 4
rad/s`` and sea-level air (not from the book; they do not change ``V_F``).

Limits of validity: 2-D incompressible thin-airfoil theory, small motions,
attached flow.

References
----------
.. [1] D. H. Hodges, G. A. Pierce, *Introduction to Structural Dynamics and
   Aeroelasticity*, 2nd ed., Cambridge University Press, 2011, Ch. 5.
.. [2] R. L. Bisplinghoff, H. Ashley, R. L. Halfman, *Aeroelasticity*,
   Addison-Wesley, 1955, Ch. 9.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import control
import numpy as np

from liquidamp.errors import (
    ParameterError,
    check_choice,
    check_in_range,
    check_nonnegative,
    check_positive,
)
from liquidamp.structure.aero import (
    JONES_COEFFICIENTS,
    STATE_SPACE_MODELS,
    aero_matrices,
)
from liquidamp.structure.port import DevicePort

__all__ = ["TypicalSection"]


@dataclass(frozen=True)
class TypicalSection:
    """Parameters of the typical section (nondimensional set plus SI scales).

    Parameters
    ----------
    a : float
        Reference point aft of mid-chord, in (-1, 1) [semichords].
    e : float
        Mass centre aft of mid-chord, in (-1, 1) [semichords].
    mu : float
        Mass ratio m/(pi rho b^2) > 0 [-].
    r2 : float
        Squared radius of gyration about the reference point, I/(m b^2) > 0
        [-]; must exceed ``(e - a)^2`` (else the mass matrix is singular).
    sigma : float
        Frequency ratio omega_h/omega_theta > 0 [-].
    semichord : float
        b > 0 [m].
    omega_theta : float
        Uncoupled pitch frequency > 0 [rad/s].
    air_density : float
        rho > 0 [kg/m^3].
    pitch_arm : float
        Arm of a device on the pitch port, stroke = arm * theta > 0 [m].
    span : float
        Span the section stands for (device forces are spread over it) > 0 [m].
    name : str
        Label.

    Examples
    --------
    >>> s = TypicalSection(a=-0.2, e=-0.1, mu=20.0, r2=0.24, sigma=0.4,
    ...                    semichord=0.5, omega_theta=8 * math.pi, pitch_arm=0.25)
    >>> round(s.x_theta, 6), round(s.divergence_speed_steady, 4)   # sqrt(mu r^2/(1+2a))
    (0.1, 2.8284)
    >>> round(s.mass, 3)   # m = mu pi rho b^2 [kg/m]
    19.242
    """

    a: float
    e: float
    mu: float
    r2: float
    sigma: float
    semichord: float
    omega_theta: float
    air_density: float = 1.225
    pitch_arm: float = 0.25
    span: float = 1.0
    name: str = "section"

    def __post_init__(self) -> None:
        check_in_range("a (reference point)", self.a, -1.0, 1.0, "semichords",
                       low_open=True, high_open=True)
        check_in_range("e (mass centre)", self.e, -1.0, 1.0, "semichords",
                       low_open=True, high_open=True)
        check_positive("mu (mass ratio)", self.mu, "-")
        check_positive("r^2 (radius of gyration squared)", self.r2, "-")
        check_positive("sigma (omega_h/omega_theta)", self.sigma, "-")
        check_positive("semichord b", self.semichord, "m")
        check_positive("omega_theta", self.omega_theta, "rad/s")
        check_positive("air density", self.air_density, "kg/m^3")
        check_positive("pitch arm", self.pitch_arm, "m")
        check_positive("span", self.span, "m")
        xt = self.e - self.a
        if self.r2 <= xt * xt * (1.0 + 1e-9):
            raise ParameterError(
                f"singular section: r^2 must exceed x_theta^2 = (e - a)^2 = {xt * xt:.6g} [-] "
                f"for a positive-definite mass matrix, got r^2={self.r2:.6g}"
            )

    @classmethod
    def from_dimensional(
        cls,
        *,
        semichord: float,
        mass: float,
        inertia: float,
        static_moment: float,
        plunge_stiffness: float,
        pitch_stiffness: float,
        a: float,
        air_density: float = 1.225,
        pitch_arm: float = 0.25,
        span: float = 1.0,
        name: str = "section",
    ) -> TypicalSection:
        """Build from SI quantities per unit span.

        Parameters
        ----------
        semichord : float
            b [m].
        mass : float
            m [kg/m].
        inertia : float
            I_theta about the reference point [kg m^2/m].
        static_moment : float
            S_theta = m b x_theta, positive with the mass centre aft [kg m/m].
        plunge_stiffness, pitch_stiffness : float
            k_h [N/m^2] and k_theta [N m/(rad m)].
        a : float
            Reference point aft of mid-chord [semichords].
        air_density, pitch_arm, span, name
            As in the class.

        Examples
        --------
        >>> s = TypicalSection.from_dimensional(
        ...     semichord=0.5, mass=19.242, inertia=19.242 * 0.25 * 0.24,
        ...     static_moment=19.242 * 0.5 * 0.1, plunge_stiffness=19.242 * (0.4 * 25.0) ** 2,
        ...     pitch_stiffness=19.242 * 0.25 * 0.24 * 25.0**2, a=-0.2)
        >>> round(s.e, 6), round(s.r2, 6), round(s.sigma, 6), round(s.omega_theta, 6)
        (-0.1, 0.24, 0.4, 25.0)
        """
        b = check_positive("semichord b", semichord, "m")
        m = check_positive("section mass per span", mass, "kg/m")
        I = check_positive("section inertia per span", inertia, "kg m^2/m")
        kh = check_positive("plunge stiffness", plunge_stiffness, "N/m^2")
        kt = check_positive("pitch stiffness", pitch_stiffness, "N m/(rad m)")
        rho = check_positive("air density", air_density, "kg/m^3")
        wt = math.sqrt(kt / I)
        return cls(
            a=a, e=a + static_moment / (m * b), mu=m / (math.pi * rho * b * b),
            r2=I / (m * b * b), sigma=math.sqrt(kh / m) / wt, semichord=b, omega_theta=wt,
            air_density=rho, pitch_arm=pitch_arm, span=span, name=name,
        )

    def replace(self, **changes) -> TypicalSection:
        """Copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    # -------------------------------------------------------- derived values
    @property
    def x_theta(self) -> float:
        """Mass centre aft of the reference point, e - a [semichords]."""
        return self.e - self.a

    @property
    def mass(self) -> float:
        """m = mu pi rho b^2 [kg/m]."""
        return self.mu * math.pi * self.air_density * self.semichord**2

    @property
    def inertia(self) -> float:
        """I_theta = m b^2 r^2 about the reference point [kg m^2/m]."""
        return self.mass * self.semichord**2 * self.r2

    @property
    def omega_h(self) -> float:
        """Uncoupled plunge frequency sigma omega_theta [rad/s]."""
        return self.sigma * self.omega_theta

    @property
    def divergence_speed_steady(self) -> float:
        """Closed-form divergence speed sqrt(mu r^2/(1 + 2a)) [-] (inf if a <= -1/2).

        Every model here has C(0) = 1, so this holds for all of them.
        """
        if 1.0 + 2.0 * self.a <= 0.0:
            return math.inf
        return math.sqrt(self.mu * self.r2 / (1.0 + 2.0 * self.a))

    def speed(self, V: float) -> float:
        """Airspeed U = V b omega_theta [m/s] of the reduced speed ``V`` [-]."""
        return float(V) * self.semichord * self.omega_theta

    def reduced_speed(self, U: float) -> float:
        """Reduced speed V = U/(b omega_theta) [-] of the airspeed ``U`` [m/s]."""
        return float(U) / (self.semichord * self.omega_theta)

    def structural_matrices(self):
        """Nondimensional mass and stiffness ``M_s, K_s`` of ``q = [h/b, theta]``."""
        xt = self.x_theta
        M = np.array([[1.0, xt], [xt, self.r2]])
        K = np.array([[self.sigma**2, 0.0], [0.0, self.r2]])
        return M, K

    # ------------------------------------------------------------ state space
    def state_names_for(self, aero: str) -> tuple[str, ...]:
        """State names of :meth:`statespace` with aerodynamic model ``aero``.

        ``h`` [m], ``theta`` [rad], ``h_dot`` [m/s], ``theta_dot`` [rad/s]
        and, for ``jones``, the lag states ``aero_lag_1``, ``aero_lag_2``
        [m/s] (filtered three-quarter-chord downwash).
        """
        check_choice("state-space aerodynamic model", aero, STATE_SPACE_MODELS)
        base = ("h", "theta", "h_dot", "theta_dot")
        return base + (("aero_lag_1", "aero_lag_2") if aero == "jones" else ())

    @property
    def state_names(self) -> tuple[str, ...]:
        """States of the default (``jones``) state-space model."""
        return self.state_names_for("jones")

    @property
    def ports(self) -> tuple[DevicePort, ...]:
        """``plunge`` (stroke = h) and ``pitch`` (stroke = pitch_arm * theta)."""
        return (
            DevicePort("plunge", "stroke_plunge", "stroke_rate_plunge", "force_plunge", 1.0, "h"),
            DevicePort("pitch", "stroke_pitch", "stroke_rate_pitch", "force_pitch",
                       self.pitch_arm, "theta"),
        )

    def nondimensional_matrices(self, V: float, aero: str):
        """First-order nondimensional ``A(V), B`` (time omega_theta t, state [h/b, theta, ...]).

        ``B``'s columns are the generalized plunge and pitch loads (divided by
        ``m b omega_theta^2`` and ``m b^2 omega_theta^2``).

        Raises
        ------
        ParameterError
            For ``theodorsen``, which has no finite state-space form.

        Examples
        --------
        >>> s = TypicalSection(-0.2, -0.1, 20.0, 0.24, 0.4, 0.5, 8 * math.pi)
        >>> A, B = s.nondimensional_matrices(1.0, "jones")
        >>> A.shape, B.shape
        ((6, 6), (6, 2))
        """
        if aero not in STATE_SPACE_MODELS:
            raise ParameterError(
                f"aerodynamic model {aero!r} has no finite state-space form; valid for state "
                f"space (p method, time domain): {', '.join(STATE_SPACE_MODELS)}"
            )
        V = check_nonnegative("reduced speed V", V, "-")
        Ms, Ks = self.structural_matrices()
        Mnc, Dnc, l, w1, w0 = aero_matrices(self.a, self.mu)
        circ = 2.0 * V / self.mu * l  # (2, 1)
        if aero == "steady":
            M2, D2, K2 = Ms, np.zeros((2, 2)), Ks - V * circ @ w0
        else:
            M2 = Ms - Mnc
            D2 = -V * Dnc
            K2 = Ks.copy()
        nlag = 2 if aero == "jones" else 0
        n = 4 + nlag
        M2inv = np.linalg.inv(M2)
        A = np.zeros((n, n))
        A[0:2, 2:4] = np.eye(2)
        if aero == "steady":
            A[2:4, 0:2] = -M2inv @ K2
            A[2:4, 2:4] = -M2inv @ D2
        else:
            # circulatory: (2V/mu) l [c0 w + sum A_j b_j x_j], w = w1 q' + V w0 q
            c0 = 0.5 if aero == "jones" else 1.0
            Kc = K2 - c0 * V * circ @ w0
            Dc = D2 - c0 * circ @ w1
            A[2:4, 0:2] = -M2inv @ Kc
            A[2:4, 2:4] = -M2inv @ Dc
            for j, (Aj, bj) in enumerate(JONES_COEFFICIENTS[:nlag]):
                A[2:4, 4 + j] = (M2inv @ (Aj * bj * circ)).ravel()
                A[4 + j, 0:2] = V * V * w0.ravel()
                A[4 + j, 2:4] = V * w1.ravel()
                A[4 + j, 4 + j] = -V * bj
        B = np.zeros((n, 2))
        B[2:4, :] = M2inv
        return A, B

    def statespace(self, U: float, aero: str = "jones") -> control.StateSpace:
        """Named SI state-space model at airspeed ``U`` [m/s].

        States :meth:`state_names_for`; inputs ``force_plunge``,
        ``force_pitch`` [N]; outputs ``stroke_plunge`` = h [m],
        ``stroke_rate_plunge`` [m/s], ``stroke_pitch`` = arm theta [m],
        ``stroke_rate_pitch`` [m/s].

        Examples
        --------
        >>> s = TypicalSection(-0.2, -0.1, 20.0, 0.24, 0.4, 0.5, 8 * math.pi)
        >>> sys = s.statespace(s.speed(1.0), "quasi-steady")
        >>> sys.state_labels
        ['h', 'theta', 'h_dot', 'theta_dot']
        """
        V = self.reduced_speed(check_nonnegative("airspeed U", U, "m/s"))
        Abar, Bbar = self.nondimensional_matrices(V, aero)
        b, w = self.semichord, self.omega_theta
        n = Abar.shape[0]
        scale = np.array([b, 1.0, b * w, w] + [b * w] * (n - 4))
        A = w * (scale[:, None] * Abar / scale[None, :])
        m = self.mass
        gen = np.diag([-1.0 / (m * b * w * w * self.span),
                       -self.pitch_arm / (m * b * b * w * w * self.span)])
        B = w * scale[:, None] * (Bbar @ gen)
        arm = self.pitch_arm
        C = np.zeros((4, n))
        C[0, 0], C[1, 2], C[2, 1], C[3, 3] = 1.0, 1.0, arm, arm
        return control.ss(
            A, B, C, np.zeros((4, 2)),
            states=list(self.state_names_for(aero)), inputs=["force_plunge", "force_pitch"],
            outputs=["stroke_plunge", "stroke_rate_plunge", "stroke_pitch", "stroke_rate_pitch"],
            name=self.name,
        )
