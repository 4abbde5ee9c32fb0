"""Ground-resonance stability of a rotor on its landing gear against rotor speed.

Two routes (:class:`~liquidamp.structure.rotor.GroundResonanceRotor`):

``coleman``
    Eigenvalues of the constant-coefficient multiblade (Coleman) model; valid
    when all blades are alike.  The imaginary parts are fixed-frame
    frequencies; the modes are tracked across the sweep (MAC + Hungarian),
    which gives the Coleman diagram.
``floquet``
    Floquet exponents of the rotating-frame periodic model (one revolution,
    :mod:`liquidamp.analysis.stability.floquet`); valid always, required when a damper
    differs or has failed.  The real parts are exact; the frequencies are
    defined modulo the rotor speed and are resolved by matching the
    eigenvalues of the revolution-averaged multiblade model.

When the blades differ, :func:`ground_resonance_sweep` uses Floquet whatever
the request, and says so in :attr:`GroundResonanceSweep.note`.  Unstable
rotor-speed ranges are bracketed on the grid and their ends found by
:func:`scipy.optimize.brentq` on the largest real part (Coleman, or Floquet
with a :mod:`scipy` integrator) or, on the default batched Floquet route, by
batched safeguarded regula falsi (all ends at once, a few rounds).

The batched Floquet route (``FloquetOptions(method="auto" | "batched")``)
uses that the rotating-frame ``A(Omega, psi)`` is a quadratic polynomial in
``Omega`` at each azimuth: the coefficients are evaluated once on an azimuth
grid and every rotor speed is integrated together
(:func:`~liquidamp.analysis.stability.floquet.batched_monodromy`); the
revolution-averaged multiblade matrix, a degree-4 polynomial in ``Omega``,
is interpolated from five speeds (checked at a sixth).

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

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from liquidamp.analysis.stability.floquet import (
    FloquetOptions,
    FloquetResult,
    batched_monodromy,
    floquet_analysis,
    floquet_from_monodromy,
    resolve_frequencies,
)
from liquidamp.analysis.stability.modes import track_modes
from liquidamp.errors import ConvergenceError, ParameterError, check_choice, check_nonnegative
from liquidamp.structure.rotor import GroundResonanceRotor

__all__ = [
    "METHODS",
    "clear_coefficient_cache",
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


def _batched(options: FloquetOptions | None) -> bool:
    return options is None or options.method in ("auto", "batched")


class _RotorCoefficients:
    """``A(Omega, psi) = A0(psi) + Omega A1(psi) + Omega^2 A2(psi)`` of the rotating frame.

    Evaluated from :meth:`GroundResonanceRotor.second_order` at Omega = 0, 1,
    2 per azimuth (exact: the mass matrix does not depend on Omega, the
    damping is linear and the stiffness quadratic in it; checked at Omega = 3
    on the first grid).  Grids (uniform, ``m`` nodes) are cached.
    """

    def __init__(self, rotor: GroundResonanceRotor):
        self.rotor = rotor
        self._grids: dict[int, np.ndarray] = {}

    def _evaluate(self, psi: np.ndarray) -> np.ndarray:
        r = self.rotor
        M = np.array([r.second_order(0.0, p)[0] for p in psi])
        CK = np.array([[r.second_order(w, p)[1:] for w in (0.0, 1.0, 2.0)] for p in psi])
        X0, X1, X2 = CK[:, 0], CK[:, 1], CK[:, 2]  # (m, 2, n, n): C, K
        c2 = 0.5 * (X2 - 2.0 * X1 + X0)
        coef = (X0, X1 - X0 - c2, c2)
        Minv = np.linalg.inv(M)
        n = M.shape[1]
        A = np.zeros((psi.size, 3, 2 * n, 2 * n))
        A[:, 0, :n, n:] = np.eye(n)
        for j, X in enumerate(coef):
            A[:, j, n:, :n] = -Minv @ X[:, 1]
            A[:, j, n:, n:] = -Minv @ X[:, 0]
        return A

    def check(self) -> None:
        psi = np.array([0.3, 1.9])
        A = self._evaluate(psi)
        for k, p in enumerate(psi):
            direct = self.rotor.first_order(3.0, p)[0]
            poly = A[k, 0] + 3.0 * A[k, 1] + 9.0 * A[k, 2]
            if not np.allclose(poly, direct, rtol=1e-10, atol=1e-10 * np.abs(direct).max()):
                raise ConvergenceError("rotor coefficients are not quadratic in Omega; "
                                       "use FloquetOptions(method='DOP853')")

    def __call__(self, psi) -> np.ndarray:
        psi = np.asarray(psi, dtype=float)
        m = psi.size
        if np.allclose(psi, np.arange(m) * (2.0 * math.pi / m), rtol=0.0, atol=1e-12):
            if m not in self._grids:
                self._grids[m] = self._evaluate(psi)
            return self._grids[m]
        return self._evaluate(psi)


@functools.lru_cache(maxsize=8)
def _coefficients_cached(rotor: GroundResonanceRotor) -> _RotorCoefficients:
    c = _RotorCoefficients(rotor)
    c.check()
    return c


def clear_coefficient_cache() -> None:
    """Forget the cached periodic coefficients of recently swept rotors (up to 8 are kept).

    The Floquet route evaluates each rotor's periodic coefficient matrices on an azimuth grid
    once and keeps them; clear the cache to time a sweep from scratch (the benchmark does) or
    to free their memory.

    Examples
    --------
    >>> clear_coefficient_cache()
    """
    _coefficients_cached.cache_clear()


def _coefficients(rotor: GroundResonanceRotor) -> _RotorCoefficients:
    try:
        return _coefficients_cached(rotor)
    except TypeError:  # unhashable
        c = _RotorCoefficients(rotor)
        c.check()
        return c


def _averaged_multiblade(rotor: GroundResonanceRotor, W: np.ndarray) -> np.ndarray:
    """Revolution-averaged multiblade matrices at speeds ``W``, shape (n_W, n, n).

    Degree-4 polynomial in Omega (P^-1 linear, A quadratic, P linear, P'
    quadratic), so for many speeds it is interpolated from five Chebyshev
    speeds and checked at a sixth; direct evaluation otherwise.
    """
    if W.size <= 6 or W[-1] - W[0] <= 0.0:
        return np.array([rotor.averaged_multiblade_matrix(w) for w in W])
    lo, hi = float(W[0]), float(W[-1])
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    u = np.cos(np.pi * (np.arange(5) + 0.5) / 5)
    nodes = np.array([rotor.averaged_multiblade_matrix(mid + half * x) for x in u])
    V = np.vander(u, 5, increasing=True)
    coef = np.linalg.solve(V, nodes.reshape(5, -1))

    def interp(w):
        x = (np.asarray(w, dtype=float) - mid) / half
        return (np.vander(np.atleast_1d(x), 5, increasing=True) @ coef).reshape(
            -1, *nodes.shape[1:])

    probe = lo + 0.37 * (hi - lo)
    direct = rotor.averaged_multiblade_matrix(probe)
    if not np.allclose(interp(probe)[0], direct, rtol=1e-9, atol=1e-9 * np.abs(direct).max()):
        return np.array([rotor.averaged_multiblade_matrix(w) for w in W])
    return interp(W)


def _batched_floquet(rotor, W, options, steps=None):
    """Resolved exponents (n_W, n) [1/s] and the step count, all speeds at once."""
    Phi, N = batched_monodromy(_coefficients(rotor), W, options, steps=steps)
    mult = np.linalg.eigvals(Phi)
    if np.any(mult == 0.0):
        raise ConvergenceError("a Floquet multiplier is exactly zero: the monodromy is singular")
    period = 2.0 * math.pi / W
    expo = np.log(mult.astype(complex)) / period[:, None]
    return Phi, expo, N


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
    if _batched(options):
        W = float(Omega)
        if not W > 0.0:
            raise ParameterError(f"rotor speed Omega must be > 0 [rad/s], got {Omega!r}")
        Phi, _, _ = _batched_floquet(rotor, np.array([W]), options)
        res = floquet_from_monodromy(Phi[0], 2.0 * math.pi / W)
    else:
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
    return _stitch_ranges(x, v, lambda i: brentq(g, x[i], x[i + 1], xtol=tol))


def _stitch_ranges(x, v, root_of) -> tuple[tuple[float, float], ...]:
    """Intervals where ``v > 0`` on grid ``x``; ``root_of(i)`` refines a sign change in
    ``(x[i], x[i+1])`` (called in increasing ``i``), a zero on the grid is its own end."""
    ranges = []
    start = x[0] if v[0] > 0.0 else None
    for i in range(x.size - 1):
        a, b = v[i] > 0.0, v[i + 1] > 0.0
        if a == b:
            continue
        root = root_of(i) if v[i] * v[i + 1] < 0.0 else (x[i] if v[i] == 0.0 else x[i + 1])
        if b:
            start = root
        else:
            ranges.append((float(start), float(root)))
            start = None
    if start is not None:
        ranges.append((float(start), float(x[-1])))
    return tuple(ranges)


def _unstable_ranges_batched(fb, x, values, *, xtol: float = 1e-8, threshold: float = 0.0,
                             points: int = 6) -> tuple[tuple[float, float], ...]:
    """:func:`unstable_ranges` with a batched ``fb(x_array) -> values``: multisection.

    Per round and bracket, ``points`` equally spaced speeds plus speeds at
    ``+-tol/2 * 10**k`` (k = 0..4) about the regula-falsi estimate are
    evaluated, all brackets in one call; the bracket shrinks to the sign
    change until narrower than the tolerance, and the end is the linear
    interpolation within it.
    """
    v = np.asarray(values, dtype=float) - threshold
    tol = xtol * max(float(x[-1] - x[0]), 1.0) if x.size > 1 else xtol
    brackets = []  # [a, b, va, vb]
    for i in range(x.size - 1):
        if (v[i] > 0.0) != (v[i + 1] > 0.0) and v[i] * v[i + 1] < 0.0:
            brackets.append([x[i], x[i + 1], v[i], v[i + 1]])
    while True:
        active = [br for br in brackets if br[1] - br[0] > tol]
        if not active:
            break
        pts = []
        for a, b, va, vb in active:
            r = a - va * (b - a) / (vb - va)  # regula falsi, then geometric spread about it
            spread = r + 0.5 * tol * np.outer([-1.0, 1.0], 10.0 ** np.arange(5)).ravel()
            cand = np.concatenate((np.linspace(a, b, points + 2)[1:-1], spread))
            pts.append(np.unique(cand[(cand > a) & (cand < b)]))
        vals = np.asarray(fb(np.concatenate(pts)), dtype=float) - threshold
        offs = np.cumsum([0] + [p.size for p in pts])
        for k, br in enumerate(active):
            xs = np.concatenate(([br[0]], pts[k], [br[1]]))
            vs = np.concatenate(([br[2]], vals[offs[k]:offs[k + 1]], [br[3]]))
            j = int(np.flatnonzero((vs[:-1] > 0.0) != (vs[1:] > 0.0))[0])
            if vs[j + 1] == 0.0:
                br[:] = [xs[j + 1], xs[j + 1], vs[j + 1], vs[j + 1]]
            else:
                br[:] = [xs[j], xs[j + 1], vs[j], vs[j + 1]]
    roots = iter(
        a if va == vb else a - va * (b - a) / (vb - va) for a, b, va, vb in brackets
    )
    return _stitch_ranges(x, v, lambda i: next(roots))


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
    elif _batched(options):
        _, expo, N = _batched_floquet(rotor, W, options)
        if rotor.n_blades >= 3:
            refs = np.linalg.eigvals(_averaged_multiblade(rotor, W))
            lams = [resolve_frequencies(e, r, w) for e, r, w in zip(expo, refs, W, strict=True)]
        else:
            lams = list(expo)
        tracked = track_modes(W, lams).eigenvalues
        maxre = tracked.real.max(axis=1)

        def fb(ws):
            return _batched_floquet(rotor, np.asarray(ws), options, steps=N)[1].real.max(axis=1)

        ranges = _unstable_ranges_batched(fb, W, maxre, threshold=check_nonnegative(
            "neutral_tol", neutral_tol, "1/s"))
        return GroundResonanceSweep(
            rotor.name, W, used, method, tracked, maxre, ranges, note
        )
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
