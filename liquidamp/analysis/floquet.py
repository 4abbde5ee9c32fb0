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

The monodromy matrix is integrated column by column with
:func:`scipy.integrate.solve_ivp` at tight tolerances
(:class:`FloquetOptions`).

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
    "floquet_analysis",
    "resolve_frequencies",
]

_METHODS = ("DOP853", "RK45", "Radau", "LSODA")


@dataclass(frozen=True)
class FloquetOptions:
    """Integration settings of the monodromy matrix.

    Parameters
    ----------
    method : str
        :func:`scipy.integrate.solve_ivp` method (``DOP853``: explicit
        8th order, right for the non-stiff structural systems here).
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
valid: DOP853, RK45, Radau, LSODA
    """

    method: str = "DOP853"
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
        Integration settings (defaults: DOP853, rtol 1e-10, atol 1e-12).

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

    sol = solve_ivp(rhs, (0.0, T), np.eye(n).ravel(), method=opts.method,
                    rtol=opts.rtol, atol=opts.atol)
    if not sol.success:
        raise ConvergenceError(f"monodromy integration failed: {sol.message}")
    return sol.y[:, -1].reshape(n, n)


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
    Phi = monodromy(A, period, n, options)
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

