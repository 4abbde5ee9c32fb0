"""Ground-resonance stability of a rotor on its landing gear against rotor speed.

Two routes (:class:`~liquidamp.structure.rotor.GroundResonanceRotor`):

``coleman``
    Eigenvalues of the constant-coefficient multiblade (Coleman) model; valid
    when all blades are alike.  The imaginary parts are fixed-frame
    frequencies; the modes are tracked across the sweep (MAC + Hungarian),
    which gives the Coleman diagram.
``floquet``
    Floquet exponents of the rotating-frame periodic model (one revolution,
    :mod:`liquidamp.analysis.floquet`); valid always, required when a damper
    differs or has failed.  The real parts are exact; the frequencies are
    defined modulo the rotor speed and are resolved by matching the
    eigenvalues of the revolution-averaged multiblade model.

When the blades differ, :func:`ground_resonance_sweep` uses Floquet whatever
the request, and says so in :attr:`GroundResonanceSweep.note`.  Unstable
rotor-speed ranges are bracketed on the grid and their ends found by
:func:`scipy.optimize.brentq` on the largest real part.

References
----------
.. [1] R. P. Coleman, A. M. Feingold, NACA Report 1351, 1958.
.. [2] C. E. Hammond, "An application of Floquet theory to prediction of
   mechanical instability", J. American Helicopter Society 19(4), 14-23,
   1974.
.. [3] W. Johnson, *Rotorcraft Aeromechanics*, Cambridge University Press,
   2013, Ch. 20.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from liquidamp.analysis.floquet import (
    FloquetOptions,
    FloquetResult,
    floquet_analysis,
    resolve_frequencies,
)
from liquidamp.analysis.modes import track_modes
from liquidamp.errors import ParameterError, check_choice, check_nonnegative
from liquidamp.structure.rotor import GroundResonanceRotor

__all__ = [
    "METHODS",
    "GroundResonanceSweep",
    "coleman_eigenvalues",
    "rotor_floquet",
    "rotor_eigenvalues",
    "ground_resonance_sweep",
    "unstable_ranges",
    "rpm_to_rad_s",
    "rad_s_to_rpm",
]

METHODS = ("coleman", "floquet")

FLOQUET_NOTE = (
    "Floquet exponents: real parts exact; frequencies defined modulo the rotor speed, "
    "resolved by matching the revolution-averaged multiblade eigenvalues"
)


def rpm_to_rad_s(rpm):
    """Rotor speed in [rpm] to [rad/s].

    Examples
    --------
    >>> round(rpm_to_rad_s(60.0), 6)
    6.283185
    """
    return np.asarray(rpm, dtype=float) * (2.0 * math.pi / 60.0) if np.ndim(rpm) else \
        float(rpm) * 2.0 * math.pi / 60.0


def rad_s_to_rpm(omega):
    """Rotor speed in [rad/s] to [rpm]."""
    return np.asarray(omega, dtype=float) * (60.0 / (2.0 * math.pi)) if np.ndim(omega) else \
        float(omega) * 60.0 / (2.0 * math.pi)


def coleman_eigenvalues(rotor: GroundResonanceRotor, Omega: float, *, vectors: bool = False):
    """Eigenvalues [1/s] (and eigenvectors) of the multiblade model at ``Omega`` [rad/s].

    Raises
    ------
    ParameterError
        If the blades differ (periodic coefficients) or ``n_blades < 3``.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> lam = coleman_eigenvalues(load_rotor("hammond1974"), rpm_to_rad_s(250.0))
    >>> lam.shape
    (12,)
    """
    if not rotor.blades_alike:
        raise ParameterError(
            "the multiblade (Coleman) model needs all blades alike; lag dampers are "
            f"{rotor.blade_damping} N m s/rad: use the Floquet method"
        )
    A, _ = rotor.multiblade_matrices(Omega, 0.0)
    if vectors:
        return np.linalg.eig(A)
    return np.linalg.eigvals(A)


def rotor_floquet(
    rotor: GroundResonanceRotor, Omega: float, options: FloquetOptions | None = None
) -> tuple[FloquetResult, np.ndarray]:
    """Floquet analysis of the rotating-frame model over one revolution.

    Parameters
    ----------
    rotor : GroundResonanceRotor
    Omega : float
        Rotor speed > 0 [rad/s].
    options : FloquetOptions, optional

    Returns
    -------
    result : FloquetResult
        Multipliers and principal exponents.
    resolved : ndarray of complex
        Exponents [1/s] with the frequency branch matched to the
        revolution-averaged multiblade eigenvalues (``n_blades >= 3``;
        principal values otherwise).
    """
    sys = rotor.periodic_statespace(Omega)
    res = floquet_analysis(sys.A, sys.period, sys.nstates, options)
    if rotor.n_blades >= 3:
        ref = np.linalg.eigvals(rotor.averaged_multiblade_matrix(Omega))
        return res, resolve_frequencies(res.exponents, ref, Omega)
    return res, res.exponents.copy()


def _choose_method(rotor: GroundResonanceRotor, method: str) -> tuple[str, str]:
    check_choice("stability method", method, METHODS)
    if method == "coleman" and not rotor.blades_alike:
        return "floquet", (
            f"blade lag dampers differ {rotor.blade_damping} N m s/rad: periodic coefficients, "
            "Floquet analysis used instead of the multiblade (Coleman) eigenvalues. "
            + FLOQUET_NOTE
        )
    if method == "coleman":
        return "coleman", "multiblade (Coleman) eigenvalues, constant coefficients"
    return "floquet", FLOQUET_NOTE


def rotor_eigenvalues(
    rotor: GroundResonanceRotor,
    Omega: float,
    method: str = "coleman",
    options: FloquetOptions | None = None,
) -> np.ndarray:
    """Fixed-frame eigenvalues or resolved Floquet exponents [1/s] at ``Omega`` [rad/s].

    ``method`` is ``coleman`` or ``floquet``; ``coleman`` falls back to
    Floquet when the blades differ.
    """
    used, _ = _choose_method(rotor, method)
    if used == "coleman":
        return coleman_eigenvalues(rotor, Omega)
    return rotor_floquet(rotor, Omega, options)[1]


def unstable_ranges(
    func: Callable[[float], float], x, values, *, xtol: float = 1e-8, threshold: float = 0.0
) -> tuple[tuple[float, float], ...]:
    """Intervals of ``x`` where ``func > threshold``, ends refined by Brent's method.

    Parameters
    ----------
    func : callable
        ``func(x) -> float`` (the largest real part); continuous.
    x : array
        Increasing grid.
    values : array
        ``func`` on the grid.
    xtol : float
        Absolute tolerance of the ends, relative to the grid span [-].
    threshold : float
        Level that counts as unstable (a small positive margin keeps
        neutrally stable modes, e.g. undamped ones, out) [unit of func].

    Returns
    -------
    tuple of (start, end)
        An interval that is open at a grid end starts or stops at that end.

    Examples
    --------
    >>> f = lambda x: 1.0 - x * x
    >>> x = np.linspace(-2.0, 2.0, 5)
    >>> [(round(a, 9), round(b, 9)) for a, b in unstable_ranges(f, x, f(x))]
    [(-1.0, 1.0)]
    """
    x = np.asarray(x, dtype=float)
    v = np.asarray(values, dtype=float) - threshold
    g = (lambda xx: func(xx) - threshold) if threshold else func
    tol = xtol * max(float(x[-1] - x[0]), 1.0) if x.size > 1 else xtol
    ranges = []
    start = x[0] if v[0] > 0.0 else None
    for i in range(x.size - 1):
        a, b = v[i] > 0.0, v[i + 1] > 0.0
        if a == b:
            continue
        root = brentq(g, x[i], x[i + 1], xtol=tol) if v[i] * v[i + 1] < 0.0 else (
            x[i] if v[i] == 0.0 else x[i + 1])
        if b:
            start = root
        else:
            ranges.append((float(start), float(root)))
            start = None
    if start is not None:
        ranges.append((float(start), float(x[-1])))
    return tuple(ranges)


@dataclass(frozen=True, eq=False)
class GroundResonanceSweep:
    """Stability of a rotor against rotor speed.

    Attributes
    ----------
    rotor_name : str
    Omega : ndarray
        Rotor speeds [rad/s].
    method : str
        Method used (``coleman`` or ``floquet``).
    requested_method : str
        Method asked for.
    eigenvalues : ndarray of complex, shape (n_Omega, n_states)
        Fixed-frame eigenvalues (or resolved Floquet exponents) [1/s], each
        column one tracked mode.
    max_real_part : ndarray
        Largest real part at each speed [1/s].
    unstable_ranges : tuple of (float, float)
        Unstable rotor-speed intervals [rad/s].
    note : str
        What was computed and its caveats.
    """

    rotor_name: str
    Omega: np.ndarray
    method: str
    requested_method: str
    eigenvalues: np.ndarray
    max_real_part: np.ndarray
    unstable_ranges: tuple[tuple[float, float], ...]
    note: str

    @property
    def rpm(self) -> np.ndarray:
        """Rotor speeds [rpm]."""
        return rad_s_to_rpm(self.Omega)

    @property
    def unstable_ranges_rpm(self) -> list[list[float]]:
        """Unstable intervals [rpm]."""
        return [[rad_s_to_rpm(a), rad_s_to_rpm(b)] for a, b in self.unstable_ranges]

    def frequencies_hz(self) -> list[list[float]]:
        """Per speed, the damped frequencies Im(lambda)/(2 pi) > 0, ascending [Hz]."""
        out = []
        for lam in self.eigenvalues:
            f = np.sort(lam.imag[lam.imag > 1e-9]) / (2.0 * math.pi)
            out.append(f.tolist())
        return out

    def real_parts(self) -> list[list[float]]:
        """Per speed, the real parts [1/s] in the order of :meth:`frequencies_hz`."""
        out = []
        for lam in self.eigenvalues:
            sel = lam[lam.imag > 1e-9]
            out.append(sel.real[np.argsort(sel.imag)].tolist())
        return out

    def to_dict(self) -> dict:
        """JSON-ready dictionary (rpm and Hz at this edge)."""
        return {
            "rotor": self.rotor_name,
            "method": self.method,
            "requested_method": self.requested_method,
            "note": self.note,
            "rpm": self.rpm.tolist(),
            "max_real_part [1/s]": self.max_real_part.tolist(),
            "unstable_ranges [rpm]": self.unstable_ranges_rpm,
            "frequencies [Hz]": self.frequencies_hz(),
            "real_parts [1/s]": self.real_parts(),
        }


def ground_resonance_sweep(
    rotor: GroundResonanceRotor,
    Omega,
    method: str = "coleman",
    options: FloquetOptions | None = None,
    *,
    neutral_tol: float = 1e-6,
) -> GroundResonanceSweep:
    """Eigenvalues, largest real part and unstable ranges over rotor speeds.

    Parameters
    ----------
    rotor : GroundResonanceRotor
    Omega : array
        Rotor speeds [rad/s], finite, increasing, >= 0 (> 0 for Floquet).
    method : {"coleman", "floquet"}
        ``coleman`` falls back to ``floquet`` when the blades differ.
    options : FloquetOptions, optional
    neutral_tol : float
        A largest real part up to this is neutral, not unstable [1/s]
        (undamped modes sit at 0 within round-off).

    Returns
    -------
    GroundResonanceSweep

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> sweep = ground_resonance_sweep(load_rotor("hammond1974"),
    ...                                rpm_to_rad_s(np.linspace(150, 350, 5)))
    >>> sweep.method, sweep.unstable_ranges
    ('coleman', ())
    """
    W = np.atleast_1d(np.asarray(Omega, dtype=float))
    if W.size == 0:
        raise ParameterError("the rotor-speed range is empty; give at least one speed [rad/s]")
    if not np.all(np.isfinite(W)) or np.any(W < 0.0):
        raise ParameterError(f"rotor speeds must be finite and >= 0 [rad/s], got {W.tolist()}")
    if W.size > 1 and np.any(np.diff(W) <= 0.0):
        raise ParameterError("rotor speeds must be strictly increasing [rad/s]")
    used, note = _choose_method(rotor, method)
    if used == "floquet" and W[0] <= 0.0:
        raise ParameterError(
            f"Floquet analysis needs rotor speeds > 0 [rad/s] (period 2 pi/Omega), got {W[0]:g}"
        )
    if used == "coleman":
        lams, vecs = [], []
        for w in W:
            lam, vec = coleman_eigenvalues(rotor, w, vectors=True)
            lams.append(lam)
            vecs.append(vec)
        tracked = track_modes(W, lams, vecs).eigenvalues
    else:
        lams = [rotor_floquet(rotor, w, options)[1] for w in W]
        tracked = track_modes(W, lams).eigenvalues
    maxre = tracked.real.max(axis=1)

    def f(w):
        return float(np.max(rotor_eigenvalues(rotor, w, used, options).real))

    ranges = unstable_ranges(f, W, maxre, threshold=check_nonnegative(
        "neutral_tol", neutral_tol, "1/s"))
    return GroundResonanceSweep(
        rotor.name, W, used, method, tracked, maxre, ranges, note
    )
