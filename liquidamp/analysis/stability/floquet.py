"""Floquet analysis of linear systems with periodic coefficients.

For ``x' = A(t) x`` with ``A(t + T) = A(t)`` the monodromy matrix
``Phi(T)`` (the state-transition matrix over one period, ``Phi(0) = I``)
decides stability: its eigenvalues are the Floquet (characteristic)
multipliers ``rho_j`` and the Floquet exponents are

.. math:: \\eta_j = \\frac{\\ln \\rho_j}{T}.

The system is asymptotically stable when every ``|rho_j| < 1``, i.e. every
``Re(eta_j) < 0``.  The real part is unique; the imaginary part (the
frequency) is only defined modulo ``2 pi / T`` (for a rotor, modulo the
rotor speed ``Omega``): :func:`floquet_analysis` returns the principal value
in ``(-pi/T, pi/T]`` and :func:`resolve_frequencies` picks the branch that
best matches a reference (e.g. the eigenvalues of the revolution-averaged
constant-coefficient system).

For a general ``A(t)`` the monodromy matrix is integrated column by column
with :func:`scipy.integrate.solve_ivp` at tight tolerances
(:class:`FloquetOptions`).  For a family of systems whose coefficients are
polynomials in a speed ``Omega`` and ``2 pi``-periodic in the angle
``psi = Omega t`` (a rotor), :func:`batched_monodromy` integrates all speeds
at once: classical RK4 with fixed steps on a uniform azimuth grid shared by
every speed (the coefficient matrices are evaluated once per grid node),
batched matrix products over ``(n_Omega, n, n)``, Richardson extrapolation
between step counts, and the step count doubled until the estimated error is
within the tolerances.

References
----------
.. [1] G. Floquet, Ann. Sci. ENS 12, 47-88, 1883.
.. [2] P. P. Friedmann, C. E. Hammond, T.-H. Woo, "Efficient numerical
   treatment of periodic systems with application to stability problems",
   Int. J. Numer. Meth. Eng. 11, 1117-1136, 1977.
.. [3] C. E. Hammond, J. American Helicopter Society 19(4), 14-23, 1974.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import linear_sum_assignment

from liquidamp.errors import ConvergenceError, ParameterError, check_choice, check_positive

__all__ = [
    "FloquetOptions",
    "FloquetResult",
    "monodromy",
    "batched_monodromy",
    "floquet_analysis",
    "floquet_from_monodromy",
    "resolve_frequencies",
]

_METHODS = ("auto", "batched", "DOP853", "RK45", "Radau", "LSODA")
_SOLVE_IVP = ("DOP853", "RK45", "Radau", "LSODA")


@dataclass(frozen=True)
class FloquetOptions:
    """Integration settings of the monodromy matrix.

    Parameters
    ----------
    method : str
        ``auto`` (default): ``batched`` where the coefficients are known as a
        polynomial family in the rotor speed (the rotor), otherwise
        ``DOP853``.  ``batched``: fixed-step RK4 with Richardson
        extrapolation on a shared azimuth grid (:func:`batched_monodromy`).
        Otherwise a :func:`scipy.integrate.solve_ivp` method (``DOP853``:
        explicit 8th order, right for the non-stiff structural systems here).
    rtol : float
        Relative tolerance [-].
    atol : float
        Absolute tolerance on the entries of Phi [-] (Phi(0) = I).

    Examples
    --------
    >>> FloquetOptions().rtol
    1e-10
    >>> FloquetOptions(method="Euler")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown Floquet integration method 'Euler'; \
valid: auto, batched, DOP853, RK45, Radau, LSODA
    """

    method: str = "auto"
    rtol: float = 1e-10
    atol: float = 1e-12

    def __post_init__(self) -> None:
        check_choice("Floquet integration method", self.method, _METHODS)
        check_positive("Floquet rtol", self.rtol, "-")
        check_positive("Floquet atol", self.atol, "-")
        if self.rtol > 1e-4:
            raise ParameterError(f"Floquet rtol must be <= 1e-4 [-], got {self.rtol:g}")

    @classmethod
    def from_mapping(cls, mapping: dict) -> FloquetOptions:
        """Build from a mapping; unknown keys raise."""
        names = [f.name for f in dataclasses.fields(cls)]
        for key in mapping:
            check_choice("Floquet option", key, names)
        return cls(**mapping)


@dataclass(frozen=True, eq=False)
class FloquetResult:
    """Floquet multipliers and exponents of a periodic system.

    Attributes
    ----------
    period : float
        Period T of the coefficients [s].
    monodromy : ndarray, shape (n, n)
        State-transition matrix over one period [-].
    multipliers : ndarray of complex, shape (n,)
        Eigenvalues of the monodromy matrix [-].
    exponents : ndarray of complex, shape (n,)
        ``log(multipliers)/T`` [1/s], imaginary part principal in
        ``(-pi/T, pi/T]`` (ambiguous modulo ``2 pi/T``).
    """

    period: float
    monodromy: np.ndarray
    multipliers: np.ndarray
    exponents: np.ndarray

    @property
    def max_real_part(self) -> float:
        """Largest real part of the exponents [1/s]; > 0 means unstable."""
        return float(np.max(self.exponents.real))

    @property
    def spectral_radius(self) -> float:
        """Largest multiplier modulus [-]; > 1 means unstable."""
        return float(np.max(np.abs(self.multipliers)))


def monodromy(
    A: Callable[[float], np.ndarray],
    period: float,
    n: int,
    options: FloquetOptions | None = None,
) -> np.ndarray:
    """Integrate ``Phi' = A(t) Phi``, ``Phi(0) = I`` over one period [s].

    Parameters
    ----------
    A : callable
        ``A(t) -> (n, n)`` array, ``t`` in [s].
    period : float
        T > 0 [s].
    n : int
        Number of states.
    options : FloquetOptions, optional
        Integration settings (defaults: DOP853, rtol 1e-10, atol 1e-12;
        ``auto`` and ``batched`` mean DOP853 for a general callable).

    Returns
    -------
    ndarray, shape (n, n)

    Examples
    --------
    >>> Phi = monodromy(lambda t: np.array([[0.0, 1.0], [-1.0, 0.0]]), 2 * np.pi, 2)
    >>> bool(np.allclose(Phi, np.eye(2), atol=1e-8))
    True
    """
    opts = options or FloquetOptions()
    T = check_positive("period", period, "s")

    def rhs(t, y):
        return (A(t) @ y.reshape(n, n)).ravel()

    method = opts.method if opts.method in _SOLVE_IVP else "DOP853"
    sol = solve_ivp(rhs, (0.0, T), np.eye(n).ravel(), method=method,
                    rtol=opts.rtol, atol=opts.atol)
    if not sol.success:
        raise ConvergenceError(f"monodromy integration failed: {sol.message}")
    return sol.y[:, -1].reshape(n, n)


def _second_order_form(B: np.ndarray) -> bool:
    """True when every node is ``[[0, I], [*, *]]`` (only for the power 0, zero otherwise)."""
    n = B.shape[-1]
    if n % 2 or B.shape[1] < 1:
        return False
    m = n // 2
    top = B[:, :, :m, :]
    want = np.zeros(top.shape[1:])
    want[0, :, m:] = np.eye(m)
    return bool(np.all(top == want))


def _rk4_product(B, Omega, N, stride):
    """Monodromy by classical RK4 over one revolution, ``N`` steps, all speeds at once.

    ``B`` holds the coefficient nodes ``(m, d + 1, n, n)`` at
    ``psi_k = k pi / (N stride)``, k = 0..2 N stride - 1 (half steps of the
    finest grid); this level uses every ``stride``-th node.  Stages are
    applied to ``Phi`` directly (four batched products per step); for the
    first-order form of a second-order system only the lower half of each
    product is computed (the upper half is a copy of the rates over Omega).
    """
    n = B.shape[-1]
    h = 2.0 * math.pi / N
    W = np.asarray(Omega, dtype=float)
    nW = W.shape[0]
    d1 = B.shape[1]
    pw = np.stack([W ** (j - 1) for j in range(d1)], axis=1)  # dx/dpsi = sum_j W^(j-1) A_j x
    half = _second_order_form(B)
    r0 = n // 2 if half else 0
    Bflat = B[:, :, r0:, :].reshape(B.shape[0], d1, -1)
    shape = (nW, n - r0, n)
    msize = B.shape[0]

    def coef(k):
        return (pw @ Bflat[(k * stride) % msize]).reshape(shape)

    invW = (1.0 / W)[:, None, None]
    Phi = np.broadcast_to(np.eye(n), (nW, n, n)).copy()
    k1, k2, k3, k4, Y = (np.empty((nW, n, n)) for _ in range(5))

    def apply(C, X, out):
        if half:
            np.multiply(X[:, r0:, :], invW, out=out[:, :r0, :])
            np.matmul(C, X, out=out[:, r0:, :])
        else:
            np.matmul(C, X, out=out)
        return out

    B1 = coef(0)
    for s in range(N):
        B2, B3 = coef(2 * s + 1), coef(2 * s + 2)
        apply(B1, Phi, k1)
        np.multiply(k1, 0.5 * h, out=Y)
        Y += Phi
        apply(B2, Y, k2)
        np.multiply(k2, 0.5 * h, out=Y)
        Y += Phi
        apply(B2, Y, k3)
        np.multiply(k3, h, out=Y)
        Y += Phi
        apply(B3, Y, k4)
        k2 += k3
        k2 *= 2.0
        k2 += k1
        k2 += k4
        k2 *= h / 6.0
        Phi += k2
        B1 = B3
    return Phi


def batched_monodromy(
    coefficients: Callable[[np.ndarray], np.ndarray],
    Omega,
    options: FloquetOptions | None = None,
    *,
    steps: int | None = None,
    min_steps: int = 64,
    max_steps: int = 8192,
) -> tuple[np.ndarray, int]:
    """Monodromy matrices of ``x' = A(Omega, Omega t) x`` for many speeds at once.

    The coefficients are a polynomial family in the speed,
    ``A(Omega, psi) = sum_j Omega**j A_j(psi)``, each ``A_j`` ``2 pi``-periodic
    in the angle ``psi`` [rad]; the period is ``2 pi/Omega`` [s].  In
    ``psi`` the equation reads ``dx/dpsi = sum_j Omega**(j-1) A_j(psi) x``,
    integrated by classical RK4 on a uniform grid of ``N`` steps per
    revolution shared by all speeds.  With ``N``, ``2N`` and ``4N`` steps
    the two Richardson-extrapolated results ``R = P_2N + (P_2N - P_N)/15``
    are compared; ``N`` is doubled until ``|R_4N - R_2N| / 31 <= atol + rtol
    max|Phi|`` at every speed (``options.rtol``, ``options.atol``).

    Parameters
    ----------
    coefficients : callable
        ``coefficients(psi) -> (m, d + 1, n, n)`` for an array ``psi`` of
        ``m`` angles [rad]; entry ``j`` multiplies ``Omega**j``.
    Omega : array
        Speeds > 0 [rad/s].
    options : FloquetOptions, optional
    steps : int, optional
        Use exactly ``steps`` (and ``2 steps``) steps per revolution, one
        Richardson extrapolation, no error control.
    min_steps, max_steps : int
        First and largest coarse step counts of the error control.

    Returns
    -------
    Phi : ndarray, shape (n_Omega, n, n)
        Monodromy matrices [-].
    steps : int
        Coarse step count used (the result combines ``steps`` and ``2 steps``).

    Examples
    --------
    The undamped oscillator ``x'' + (2 Omega)^2 x = 0`` (constant in psi)
    turns twice per revolution: its monodromy is the identity.

    >>> def coeffs(psi):
    ...     c = np.zeros((psi.size, 3, 2, 2))
    ...     c[:, 0, 0, 1] = 1.0
    ...     c[:, 2, 1, 0] = -4.0
    ...     return c
    >>> Phi, N = batched_monodromy(coeffs, np.array([1.0, 3.0]))
    >>> bool(np.allclose(Phi, np.eye(2), atol=1e-9))
    True
    """
    opts = options or FloquetOptions()
    W = np.atleast_1d(np.asarray(Omega, dtype=float))
    if W.ndim != 1 or not np.all(np.isfinite(W)) or np.any(W <= 0.0):
        raise ParameterError(f"speeds must be finite and > 0 [rad/s], got {W.tolist()}")

    def nodes(N):  # half-step nodes of the 2N-step grid
        return np.asarray(coefficients(np.arange(4 * N) * (math.pi / (2 * N))), dtype=float)

    if steps is not None:
        N = int(steps)
        if N < 1:
            raise ParameterError(f"steps must be >= 1, got {steps}")
        B = nodes(N)
        P1, P2 = _rk4_product(B, W, N, 2), _rk4_product(B, W, 2 * N, 1)
        return P2 + (P2 - P1) / 15.0, N
    N = int(min_steps)
    B = nodes(2 * N)
    P1, P2, P4 = (_rk4_product(B, W, N, 4), _rk4_product(B, W, 2 * N, 2),
                  _rk4_product(B, W, 4 * N, 1))
    while True:
        R1, R2 = P2 + (P2 - P1) / 15.0, P4 + (P4 - P2) / 15.0
        err = np.max(np.abs(R2 - R1), axis=(1, 2)) / 31.0
        scale = np.max(np.abs(R2), axis=(1, 2))
        if np.all(err <= opts.atol + opts.rtol * np.maximum(scale, 1.0)) or \
                not np.all(np.isfinite(err)):
            if not np.all(np.isfinite(R2)):
                raise ConvergenceError("batched monodromy integration produced non-finite values")
            return R2, 2 * N
        if 4 * N > max_steps:
            raise ConvergenceError(
                f"batched monodromy: error estimate {float(err.max()):.3g} above tolerance "
                f"with {4 * N} steps per revolution"
            )
        N *= 2
        P1, P2, P4 = P2, P4, _rk4_product(nodes(2 * N), W, 4 * N, 1)


def floquet_analysis(
    A: Callable[[float], np.ndarray],
    period: float,
    n: int,
    options: FloquetOptions | None = None,
) -> FloquetResult:
    """Floquet multipliers and exponents of ``x' = A(t) x`` (period ``period`` [s]).

    Examples
    --------
    Mathieu's equation ``x'' + (delta + eps cos t) x = 0`` at ``delta = 1/4``
    lies in the first instability tongue for any small ``eps``:

    >>> res = floquet_analysis(
    ...     lambda t: np.array([[0.0, 1.0], [-(0.25 + 0.1 * np.cos(t)), 0.0]]), 2 * np.pi, 2)
    >>> res.max_real_part > 0, round(float(np.prod(res.multipliers).real), 8)  # det = 1
    (True, 1.0)
    """
    return floquet_from_monodromy(monodromy(A, period, n, options), period)


def floquet_from_monodromy(Phi: np.ndarray, period: float) -> FloquetResult:
    """Multipliers and principal exponents from a monodromy matrix over ``period`` [s]."""
    Phi = np.asarray(Phi, dtype=float)
    mult = np.linalg.eigvals(Phi)
    if np.any(mult == 0.0):
        raise ConvergenceError("a Floquet multiplier is exactly zero: the monodromy is singular")
    expo = np.log(mult.astype(complex)) / period
    return FloquetResult(float(period), Phi, mult, expo)


def resolve_frequencies(exponents, reference, frequency: float) -> np.ndarray:
    """Shift exponents by ``i m frequency`` to best match ``reference`` eigenvalues.

    Each Floquet exponent is defined only modulo ``i frequency``
    (``frequency = 2 pi/T`` [rad/s], the rotor speed for a rotor).  The
    exponents are paired one-to-one with the reference eigenvalues
    (Hungarian assignment) and each is moved to the branch nearest its
    partner; the real parts are unchanged.

    Parameters
    ----------
    exponents : array of complex, shape (n,)
        Floquet exponents [1/s].
    reference : array of complex, shape (n,)
        Eigenvalues of a constant-coefficient approximation [1/s].
    frequency : float
        Branch spacing 2 pi/T [rad/s].

    Examples
    --------
    >>> resolve_frequencies([-0.1 + 1.0j], [-0.12 + 11.2j], 10.0)
    array([-0.1+11.j])
    """
    eta = np.asarray(exponents, dtype=complex)
    ref = np.asarray(reference, dtype=complex)
    if eta.shape != ref.shape:
        raise ParameterError(
            f"exponents and reference need the same shape, got {eta.shape} and {ref.shape}"
        )
    w = check_positive("branch frequency", frequency, "rad/s")
    m = np.round((ref.imag[None, :] - eta.imag[:, None]) / w)
    shifted = eta[:, None] + 1j * m * w
    cost = np.abs(shifted - ref[None, :])
    rows, cols = linear_sum_assignment(cost)
    out = eta.copy()
    out[rows] = shifted[rows, cols]
    return out

