"""A rotor on its landing gear: ground resonance (Coleman & Feingold).

``N`` articulated blades in lead-lag (:class:`~liquidamp.structure.blade.ArticulatedBlade`)
on a hub that translates in ``x`` and ``y`` on springs and dampers (the
landing gear and fuselage reduced to the hub).  Blade ``k = 1..N`` sits at
azimuth ``psi_k = Omega t + 2 pi (k - 1)/N``; ``psi = Omega t`` is blade 1's
azimuth.  Lag angles ``zeta_k`` [rad] are positive lagging.  With
``q = [zeta_1..zeta_N, x, y]`` the linearized equations in *rotating*
(individual blade) coordinates are ``M(psi) q'' + C(psi) q' + K(psi) q = G u``:

.. math::

   I_b\\ddot\\zeta_k + C_k\\dot\\zeta_k + (K_\\zeta + eS_b\\Omega^2)\\zeta_k
     + S_b(\\ddot x\\sin\\psi_k - \\ddot y\\cos\\psi_k) &= -a F_k + M_k \\\\
   M_x\\ddot x + C_x\\dot x + K_x x + S_b\\sum_k \\frac{d^2}{dt^2}(\\zeta_k\\sin\\psi_k) &= F_x \\\\
   M_y\\ddot y + C_y\\dot y + K_y y - S_b\\sum_k \\frac{d^2}{dt^2}(\\zeta_k\\cos\\psi_k) &= F_y

with ``M_x = m_hub,x + N m_b`` (the translating mass includes the blades;
the hub masses of Hammond's table exclude them), ``C_k`` the viscous lag
damper of blade ``k`` and ``M_k`` an external lag moment on blade ``k``
[N m], positive lagging (inputs ``moment_k``; ``F_x``, ``F_y`` are the
inputs ``hub_force_x``, ``hub_force_y``).  The coefficients are periodic in ``psi``; when all
blades are alike the multiblade (Coleman) transformation

.. math:: \\zeta_k = \\zeta_0 + \\sum_n (\\zeta_{nc}\\cos n\\psi_k + \\zeta_{ns}\\sin n\\psi_k)
          + \\zeta_d(-1)^k

makes them constant (fixed-frame frequencies).  With one damper different or
failed they stay periodic: use Floquet theory
(:mod:`liquidamp.analysis.stability.floquet`).

Device ports: blade ``k`` has the port ``blade_k`` with outputs ``stroke_k``
= ``a zeta_k`` [m], ``stroke_rate_k`` [m/s] and input ``force_k`` [N].  A
device replacing blade ``k``'s damper is connected to that port with the
host's own damper of that blade set to zero
(:meth:`GroundResonanceRotor.with_lag_dampers`).

References
----------
.. [1] R. P. Coleman, A. M. Feingold, "Theory of self-excited mechanical
   oscillations of helicopter rotors with hinged blades", NACA Report 1351,
   1958.
.. [2] C. E. Hammond, "An application of Floquet theory to prediction of
   mechanical instability", J. American Helicopter Society 19(4), 14-23,
   1974.  doi:10.4050/JAHS.19.14
.. [3] W. Johnson, *Rotorcraft Aeromechanics*, Cambridge University Press,
   2013, Ch. 20 (ground resonance) and Sec. 15.x (multiblade coordinates).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import control
import numpy as np

from liquidamp.errors import (
    ParameterError,
    check_nonnegative,
    check_positive,
)
from liquidamp.structure.blade import ArticulatedBlade
from liquidamp.structure.port import DevicePort, PeriodicStateSpace

__all__ = ["GroundResonanceRotor", "multiblade_names", "multiblade_basis"]


def multiblade_names(n_blades: int) -> tuple[str, ...]:
    """Names of the multiblade lag coordinates for ``n_blades`` >= 3.

    Examples
    --------
    >>> multiblade_names(4)
    ('zeta_0', 'zeta_1c', 'zeta_1s', 'zeta_d')
    >>> multiblade_names(5)
    ('zeta_0', 'zeta_1c', 'zeta_1s', 'zeta_2c', 'zeta_2s')
    """
    _check_mbc(n_blades)
    names = ["zeta_0"]
    for n in range(1, (n_blades - 1) // 2 + 1):
        names += [f"zeta_{n}c", f"zeta_{n}s"]
    if n_blades % 2 == 0:
        names.append("zeta_d")
    return tuple(names)


def _check_mbc(n_blades: int) -> None:
    if int(n_blades) < 3:
        raise ParameterError(
            f"the multiblade transformation needs n_blades >= 3, got {n_blades}; "
            "a two-bladed rotor has periodic coefficients: use Floquet analysis"
        )


def multiblade_basis(n_blades: int, psi: float):
    """Multiblade (Coleman) basis T_b(psi) and its first two psi-derivatives.

    Parameters
    ----------
    n_blades : int
        Number of blades N >= 3.
    psi : float
        Azimuth of blade 1 [rad].

    Returns
    -------
    Tb, dTb, d2Tb : ndarray
        (N x N) matrices with zeta = T_b zeta_mbc (columns: collective, cyclic
        cos/sin pairs, differential for even N) and d/dpsi, d^2/dpsi^2 [-].

    Examples
    --------
    >>> Tb, _, _ = multiblade_basis(4, 0.0)
    >>> Tb[:, 0].tolist(), Tb[:, 3].tolist()
    ([1.0, 1.0, 1.0, 1.0], [-1.0, 1.0, -1.0, 1.0])
    """
    N = n_blades
    k = np.arange(1, N + 1)
    psik = psi + 2.0 * np.pi * (k - 1) / N
    cols, d1, d2 = [np.ones(N)], [np.zeros(N)], [np.zeros(N)]
    for n in range(1, (N - 1) // 2 + 1):
        c, s = np.cos(n * psik), np.sin(n * psik)
        cols += [c, s]
        d1 += [-n * s, n * c]
        d2 += [-n * n * c, -n * n * s]
    if N % 2 == 0:
        cols.append((-1.0) ** k)
        d1.append(np.zeros(N))
        d2.append(np.zeros(N))
    return np.column_stack(cols), np.column_stack(d1), np.column_stack(d2)


@dataclass(frozen=True)
class GroundResonanceRotor:
    """Parameters of a rotor on a flexible hub (SI); see the module notes.

    Parameters
    ----------
    blade : ArticulatedBlade
        The blade (all blades share its mass, static moment, inertia,
        offset, spring and damper arm).
    n_blades : int
        Number of blades N >= 2 (>= 3 for the multiblade transformation).
    hub_mass_x, hub_mass_y : float
        Hub (fuselage) masses in x and y, *without* the blades > 0 [kg].
    hub_stiffness_x, hub_stiffness_y : float
        Hub stiffness >= 0 [N/m].
    hub_damping_x, hub_damping_y : float
        Hub damping >= 0 [N s/m].
    lag_damping : tuple of float or None
        Per-blade viscous lag damper [N m s/rad] (length N, each >= 0);
        ``None`` gives every blade ``blade.lag_damping``.  An inoperative
        damper is 0.
    name : str
        Label.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> rotor = load_rotor("hammond1974")
    >>> rotor.n_blades, rotor.blade_damping
    (4, (4067.5, 4067.5, 4067.5, 4067.5))
    >>> failed = rotor.with_inoperative_damper(1)
    >>> failed.blade_damping, failed.blades_alike
    ((0.0, 4067.5, 4067.5, 4067.5), False)
    >>> [round(w, 3) for w in rotor.body_frequencies]   # sqrt(K / (m_hub + N m_b)) [rad/s]
    [12.148, 18.402]
    """

    blade: ArticulatedBlade
    n_blades: int
    hub_mass_x: float
    hub_mass_y: float
    hub_stiffness_x: float
    hub_stiffness_y: float
    hub_damping_x: float = 0.0
    hub_damping_y: float = 0.0
    lag_damping: tuple[float, ...] | None = None
    name: str = "rotor"

    def __post_init__(self) -> None:
        if not isinstance(self.blade, ArticulatedBlade):
            raise ParameterError(f"blade must be an ArticulatedBlade, got {type(self.blade)}")
        if isinstance(self.n_blades, bool) or int(self.n_blades) != self.n_blades:
            raise ParameterError(f"n_blades must be an integer, got {self.n_blades!r}")
        if self.n_blades < 2:
            raise ParameterError(f"n_blades must be >= 2 [-], got {self.n_blades}")
        check_positive("hub mass x", self.hub_mass_x, "kg")
        check_positive("hub mass y", self.hub_mass_y, "kg")
        check_nonnegative("hub stiffness x", self.hub_stiffness_x, "N/m")
        check_nonnegative("hub stiffness y", self.hub_stiffness_y, "N/m")
        check_nonnegative("hub damping x", self.hub_damping_x, "N s/m")
        check_nonnegative("hub damping y", self.hub_damping_y, "N s/m")
        if self.lag_damping is not None:
            values = tuple(self.lag_damping)
            if len(values) != self.n_blades:
                raise ParameterError(
                    f"lag_damping needs one value per blade ({self.n_blades}), got {len(values)}"
                )
            for k, c in enumerate(values, start=1):
                check_nonnegative(f"lag damping of blade {k}", c, "N m s/rad")
            object.__setattr__(self, "lag_damping", tuple(float(c) for c in values))

    # ------------------------------------------------------------------ helpers
    def replace(self, **changes) -> GroundResonanceRotor:
        """Copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    @property
    def blade_damping(self) -> tuple[float, ...]:
        """Viscous lag damper of each blade [N m s/rad]."""
        if self.lag_damping is None:
            return (float(self.blade.lag_damping),) * self.n_blades
        return self.lag_damping

    @property
    def blades_alike(self) -> bool:
        """True when every blade has the same lag damper (constant MBC coefficients)."""
        c = self.blade_damping
        return all(ci == c[0] for ci in c)

    def check_blade(self, k: int) -> int:
        """Return ``k`` if blade ``k`` (1-based) exists, else raise."""
        if isinstance(k, bool) or int(k) != k or not 1 <= k <= self.n_blades:
            raise ParameterError(f"blade index must lie in [1, {self.n_blades}], got {k!r}")
        return int(k)

    def with_lag_dampers(self, values) -> GroundResonanceRotor:
        """Copy with per-blade lag dampers ``values`` [N m s/rad] (length N).

        Examples
        --------
        >>> from liquidamp.structure.hostio import load_rotor
        >>> load_rotor("hammond1974").with_lag_dampers([0, 0, 0, 0]).blade_damping
        (0.0, 0.0, 0.0, 0.0)
        """
        return self.replace(lag_damping=tuple(values))

    def with_inoperative_damper(self, k: int) -> GroundResonanceRotor:
        """Copy with blade ``k``'s (1-based) lag damper set to zero."""
        k = self.check_blade(k)
        c = list(self.blade_damping)
        c[k - 1] = 0.0
        return self.with_lag_dampers(c)

    @property
    def total_mass_x(self) -> float:
        """Translating mass in x, hub plus blades [kg]."""
        return self.hub_mass_x + self.n_blades * self.blade.mass

    @property
    def total_mass_y(self) -> float:
        """Translating mass in y, hub plus blades [kg]."""
        return self.hub_mass_y + self.n_blades * self.blade.mass

    @property
    def body_frequencies(self) -> tuple[float, float]:
        """Uncoupled hub frequencies sqrt(K/M) in x and y, blades included [rad/s]."""
        return (
            math.sqrt(self.hub_stiffness_x / self.total_mass_x),
            math.sqrt(self.hub_stiffness_y / self.total_mass_y),
        )

    # ------------------------------------------------------------ signal names
    @property
    def coordinate_names(self) -> tuple[str, ...]:
        """Rotating-frame coordinates ``zeta_1..zeta_N, hub_x, hub_y``."""
        return tuple(f"zeta_{k}" for k in range(1, self.n_blades + 1)) + ("hub_x", "hub_y")

    @property
    def state_names(self) -> tuple[str, ...]:
        """First-order states: coordinates [rad, m] then their rates [rad/s, m/s]."""
        q = self.coordinate_names
        rates = tuple(f"zeta_dot_{k}" for k in range(1, self.n_blades + 1))
        return q + rates + ("hub_x_dot", "hub_y_dot")

    @property
    def input_names(self) -> tuple[str, ...]:
        """``force_1..force_N`` [N] (device ports), ``hub_force_x``, ``hub_force_y`` [N],
        then ``moment_1..moment_N`` [N m] (external lag moments, positive lagging)."""
        f = tuple(f"force_{k}" for k in range(1, self.n_blades + 1))
        m = tuple(f"moment_{k}" for k in range(1, self.n_blades + 1))
        return f + ("hub_force_x", "hub_force_y") + m

    @property
    def output_names(self) -> tuple[str, ...]:
        """``stroke_k`` [m], ``stroke_rate_k`` [m/s] per blade, then ``hub_x``, ``hub_y`` [m]."""
        N = self.n_blades
        s = tuple(f"stroke_{k}" for k in range(1, N + 1))
        r = tuple(f"stroke_rate_{k}" for k in range(1, N + 1))
        return s + r + ("hub_x", "hub_y")

    @property
    def ports(self) -> tuple[DevicePort, ...]:
        """One port ``blade_k`` per blade: ``stroke_k``, ``stroke_rate_k``, ``force_k``."""
        a = self.blade.damper_arm
        return tuple(
            DevicePort(f"blade_{k}", f"stroke_{k}", f"stroke_rate_{k}", f"force_{k}", a,
                       f"zeta_{k}")
            for k in range(1, self.n_blades + 1)
        )

    # ----------------------------------------------------------- the equations
    def second_order(self, Omega: float, psi: float):
        """Rotating-frame ``M, C, K`` at rotor speed ``Omega`` [rad/s] and azimuth ``psi`` [rad].

        Returns
        -------
        M, C, K : ndarray, shape (N + 2, N + 2)
            Mass [kg, kg m, kg m^2], damping and stiffness matrices of
            ``q = [zeta_1..zeta_N, x, y]``.

        Examples
        --------
        >>> from liquidamp.structure.hostio import load_rotor
        >>> M, C, K = load_rotor("hammond1974").second_order(2 * math.pi * 4, 0.0)
        >>> M.shape, bool(np.allclose(M, M.T))
        ((6, 6), True)
        """
        W = check_nonnegative("rotor speed Omega", Omega, "rad/s")
        N, b = self.n_blades, self.blade
        S = b.static_moment
        psik = psi + 2.0 * np.pi * np.arange(N) / N
        s, c = np.sin(psik), np.cos(psik)
        n = N + 2
        ix, iy = N, N + 1
        M = np.zeros((n, n))
        M[:N, :N] = b.inertia * np.eye(N)
        M[:N, ix], M[:N, iy] = S * s, -S * c
        M[ix, :N], M[iy, :N] = S * s, -S * c
        M[ix, ix], M[iy, iy] = self.total_mass_x, self.total_mass_y
        C = np.zeros((n, n))
        C[:N, :N] = np.diag(self.blade_damping)
        C[ix, :N], C[iy, :N] = 2.0 * S * W * c, 2.0 * S * W * s
        C[ix, ix], C[iy, iy] = self.hub_damping_x, self.hub_damping_y
        K = np.zeros((n, n))
        K[:N, :N] = b.lag_stiffness(W) * np.eye(N)
        K[ix, :N], K[iy, :N] = -S * W * W * s, S * W * W * c
        K[ix, ix], K[iy, iy] = self.hub_stiffness_x, self.hub_stiffness_y
        return M, C, K

    def harmonic_second_order(self, Omega: float):
        """``M, C, K`` of :meth:`second_order` as first harmonics of the azimuth.

        Every entry of the rotating-frame matrices is a constant plus a first
        harmonic of psi (the blade azimuths are psi + 2 pi k / N), so
        ``X(psi) = X0 + Xc cos(psi) + Xs sin(psi)`` exactly for X = M, C, K.
        The coefficients are read off :meth:`second_order` at psi = 0, pi/2,
        pi and checked at two more azimuths, so the compiled rotor kernel
        evaluates the same equations without a copy of them.

        Parameters
        ----------
        Omega : float
            Rotor speed >= 0 [rad/s].

        Returns
        -------
        tuple of 9 ndarrays
            ``(M0, Mc, Ms, C0, Cc, Cs, K0, Kc, Ks)``, each (N + 2, N + 2), in
            the units of :meth:`second_order`.

        Raises
        ------
        ParameterError
            If the matrices are not first harmonics of psi (a subclass with
            other equations).

        Examples
        --------
        >>> from liquidamp.structure.hostio import load_rotor
        >>> r = load_rotor("hammond1974")
        >>> M0, Mc, Ms, *_ = r.harmonic_second_order(27.0)
        >>> M = r.second_order(27.0, 0.3)[0]
        >>> bool(np.allclose(M, M0 + Mc * np.cos(0.3) + Ms * np.sin(0.3), rtol=0, atol=1e-9))
        True
        """
        return _harmonic_second_order(self, float(Omega))

    def _harmonic_uncached(self, Omega: float):
        a, b, c = (self.second_order(Omega, psi) for psi in (0.0, 0.5 * np.pi, np.pi))
        out = []
        for X0, X1, X2 in zip(a, b, c, strict=True):
            mean = 0.5 * (X0 + X2)
            out += [mean, 0.5 * (X0 - X2), X1 - mean]
        for psi in (0.3, 2.2):
            for X, (X0, Xc, Xs) in zip(self.second_order(Omega, psi),
                                       (out[0:3], out[3:6], out[6:9]), strict=True):
                err = np.max(np.abs(X - (X0 + Xc * np.cos(psi) + Xs * np.sin(psi))))
                if err > 1e-12 * max(np.max(np.abs(X)), 1.0):
                    raise ParameterError(
                        f"{type(self).__name__}: rotating-frame matrices are not first "
                        f"harmonics of the azimuth (error {err:.3g} at psi = {psi}); the "
                        "compiled rotor kernel cannot represent them")
        for X in out:
            X.flags.writeable = False
        return tuple(out)

    def force_matrix(self) -> np.ndarray:
        """``G`` mapping inputs (``input_names``) to generalized forces of ``q``."""
        N = self.n_blades
        G = np.zeros((N + 2, 2 * N + 2))
        G[:N, :N] = -self.blade.damper_arm * np.eye(N)
        G[N, N] = G[N + 1, N + 1] = 1.0
        G[:N, N + 2:] = np.eye(N)
        return G

    def output_matrix(self) -> np.ndarray:
        """``C`` mapping the states to ``output_names`` (constant)."""
        N = self.n_blades
        n = N + 2
        Cout = np.zeros((2 * N + 2, 2 * n))
        a = self.blade.damper_arm
        Cout[:N, :N] = a * np.eye(N)
        Cout[N:2 * N, n:n + N] = a * np.eye(N)
        Cout[2 * N, N] = Cout[2 * N + 1, N + 1] = 1.0
        return Cout

    def first_order(self, Omega: float, psi: float):
        """Rotating-frame ``A(psi), B(psi)`` for the states ``state_names``.

        ``A`` is [1/s] blocks ``[[0, I], [-M^-1 K, -M^-1 C]]``; ``B`` maps the
        inputs ``input_names`` [N].
        """
        M, C, K = self.second_order(Omega, psi)
        n = M.shape[0]
        Minv = np.linalg.inv(M)
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = -Minv @ K
        A[n:, n:] = -Minv @ C
        G = self.force_matrix()
        B = np.zeros((2 * n, G.shape[1]))
        B[n:, :] = Minv @ G
        return A, B

    def statespace(self, Omega: float, psi: float = 0.0) -> control.StateSpace:
        """Rotating-frame coefficients frozen at azimuth ``psi`` [rad], named.

        The eigenvalues of this frozen system mean nothing for stability (the
        coefficients are periodic); use :meth:`periodic_statespace` with
        Floquet analysis, or :meth:`multiblade_statespace`.
        """
        A, B = self.first_order(Omega, psi)
        return control.ss(
            A, B, self.output_matrix(),
            np.zeros((2 * self.n_blades + 2, len(self.input_names))),
            states=list(self.state_names), inputs=list(self.input_names),
            outputs=list(self.output_names), name=self.name,
        )

    def periodic_statespace(self, Omega: float) -> PeriodicStateSpace:
        """The rotating-frame system as periodic matrices of time, period 2 pi/Omega [s].

        Examples
        --------
        >>> from liquidamp.structure.hostio import load_rotor
        >>> sys = load_rotor("hammond1974").periodic_statespace(2 * math.pi * 4)
        >>> round(sys.period, 6), sys.nstates, sys.ports[0].force_input
        (0.25, 12, 'force_1')
        """
        W = check_positive("rotor speed Omega", Omega, "rad/s")
        return PeriodicStateSpace(
            period=2.0 * math.pi / W,
            A=lambda t: self.first_order(W, W * t)[0],
            B=lambda t: self.first_order(W, W * t)[1],
            C=self.output_matrix(),
            D=np.zeros((2 * self.n_blades + 2, len(self.input_names))),
            state_names=self.state_names,
            input_names=self.input_names,
            output_names=self.output_names,
            ports=self.ports,
            name=self.name,
        )

    # --------------------------------------------------- multiblade coordinates
    @property
    def multiblade_state_names(self) -> tuple[str, ...]:
        """States in multiblade coordinates (``zeta_0, zeta_1c, ...``, hub, rates)."""
        q = multiblade_names(self.n_blades) + ("hub_x", "hub_y")
        return q + tuple(f"{s}_dot" for s in q)

    def _mbc_transform(self, Omega: float, psi: float):
        N = self.n_blades
        _check_mbc(N)
        Tb, Tb1, Tb2 = multiblade_basis(N, psi)
        n = N + 2
        T, T1, T2 = np.eye(n), np.zeros((n, n)), np.zeros((n, n))
        T[:N, :N], T1[:N, :N], T2[:N, :N] = Tb, Tb1, Tb2
        P = np.block([[T, np.zeros((n, n))], [Omega * T1, T]])
        Pdot = Omega * np.block([[T1, np.zeros((n, n))], [Omega * T2, T1]])
        return P, Pdot

    def multiblade_matrices(self, Omega: float, psi: float = 0.0):
        """``A, B`` in multiblade coordinates at azimuth ``psi`` [rad].

        With ``x_rot = P(psi) z`` the fixed-frame state ``z`` obeys
        ``z' = P^-1 (A P - P') z + P^-1 B u``.  When all blades are alike the
        result does not depend on ``psi``; otherwise it is periodic (period
        ``2 pi/Omega``).  ``B`` keeps the columns of ``input_names``.
        """
        W = check_nonnegative("rotor speed Omega", Omega, "rad/s")
        P, Pdot = self._mbc_transform(W, psi)
        A, B = self.first_order(W, psi)
        Pinv = np.linalg.inv(P)
        return Pinv @ (A @ P - Pdot), Pinv @ B

    def averaged_multiblade_matrix(self, Omega: float, samples: int = 64) -> np.ndarray:
        """The multiblade ``A`` averaged over one revolution (constant-coefficient approximation).

        Exact (equal to :meth:`multiblade_matrices`) when all blades are alike.
        """
        psis = 2.0 * np.pi * np.arange(samples) / samples
        return np.mean([self.multiblade_matrices(Omega, p)[0] for p in psis], axis=0)

    def multiblade_statespace(self, Omega: float) -> control.StateSpace:
        """Constant-coefficient fixed-frame model (all blades alike), named.

        States ``multiblade_state_names``; inputs ``hub_force_x``,
        ``hub_force_y`` [N]; outputs ``hub_x``, ``hub_y`` [m].  The per-blade
        device ports live in the rotating frame (:meth:`periodic_statespace`).

        Examples
        --------
        >>> from liquidamp.structure.hostio import load_rotor
        >>> sys = load_rotor("hammond1974").multiblade_statespace(2 * math.pi * 4)
        >>> sys.state_labels[:4]
        ['zeta_0', 'zeta_1c', 'zeta_1s', 'zeta_d']
        """
        if not self.blades_alike:
            raise ParameterError(
                "the multiblade model has constant coefficients only when all blades are "
                f"alike; lag dampers are {self.blade_damping} N m s/rad: use Floquet analysis"
            )
        A, B = self.multiblade_matrices(Omega, 0.0)
        N = self.n_blades
        n = N + 2
        Cout = np.zeros((2, 2 * n))
        Cout[0, N] = Cout[1, N + 1] = 1.0
        return control.ss(
            A, B[:, N:N + 2], Cout, np.zeros((2, 2)),
            states=list(self.multiblade_state_names), inputs=["hub_force_x", "hub_force_y"],
            outputs=["hub_x", "hub_y"], name=f"{self.name}_mbc",
        )


@functools.lru_cache(maxsize=64)
def _harmonic_second_order(rotor: GroundResonanceRotor, Omega: float):
    """Memoized :meth:`GroundResonanceRotor.harmonic_second_order` (read-only arrays)."""
    return rotor._harmonic_uncached(Omega)
