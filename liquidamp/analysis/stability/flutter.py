"""Flutter and divergence of the typical section: p-k, k and p methods.

All speeds are reduced, ``V = U/(b omega_theta)``; frequencies are
``omega/omega_theta``; eigenvalues ``p`` are in units of ``omega_theta``
(see :mod:`liquidamp.structure.aero` for the loads).

``pk`` (p-k method)
    For each speed and each structural mode, the equations with motion
    ``exp(p tau)`` are solved for ``p`` with the lift deficiency frozen at
    ``C(k)``, ``k = Im(p)/V``, and ``k`` is iterated to consistency.  Exact
    at the flutter point (``Re p = 0``) for any frequency-domain model.
    ``damping`` is ``Re(p)`` (a decay rate over ``omega_theta``).
``k`` (V-g method)
    Harmonic motion with an artificial structural damping ``g`` that makes
    it possible: ``(1 + i g) K q = Omega^2 (M + A(k)) q`` for a sweep of
    reduced frequencies; ``V = Omega/k``; flutter where ``g = 0``.
    ``damping`` is ``g``; off ``g = 0`` it is not a physical damping.
``p`` (state-space method)
    Eigenvalues of the finite-state model (``steady``, ``quasi-steady`` or
    R. T. Jones' two-lag approximation of ``C``).  ``damping`` is
    ``Re(p)``.

The k method needs frequency-dependent loads (not ``steady``: without
aerodynamic damping ``g`` leaves zero at a fold of the frequency curves, not
at flutter); the p method needs a state-space model (not the exact
Theodorsen function).  The divergence
speed is where the static stiffness with steady aerodynamic moment vanishes
(all models have ``C(0) = 1``); in closed form ``sqrt(mu r^2/(1 + 2a))``.

References
----------
.. [1] D. H. Hodges, G. A. Pierce, *Introduction to Structural Dynamics and
   Aeroelasticity*, 2nd ed., Cambridge University Press, 2011, Secs. 5.3-5.6.
.. [2] H. J. Hassig, "An approximate true damping solution of the flutter
   equation by determinant iteration", J. Aircraft 8(11), 885-889, 1971.
.. [3] R. L. Bisplinghoff, H. Ashley, R. L. Halfman, *Aeroelasticity*,
   Addison-Wesley, 1955, Ch. 9 (the V-g method).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from liquidamp.analysis.stability.modes import mac, track_modes
from liquidamp.errors import ConvergenceError, ParameterError, check_choice
from liquidamp.structure.aero import (
    AERO_MODELS,
    STATE_SPACE_MODELS,
    aero_matrices,
    lift_deficiency,
)
from liquidamp.structure.section import TypicalSection

__all__ = [
    "FLUTTER_METHODS",
    "VALID_COMBINATIONS",
    "FlutterResult",
    "check_combination",
    "divergence_speed",
    "pk_roots",
    "flutter_analysis",
]

FLUTTER_METHODS = ("pk", "k", "p")
VALID_COMBINATIONS = {
    "pk": AERO_MODELS,
    "k": ("quasi-steady", "theodorsen", "jones"),
    "p": STATE_SPACE_MODELS,
}
_NEUTRAL = 1e-9  # a real part (or g) up to this counts as neutral, not unstable [-]


def check_combination(aero: str, method: str) -> None:
    """Raise unless ``aero`` can be used with ``method``.

    Examples
    --------
    >>> check_combination("theodorsen", "p")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: the p method needs a state-space aerodynamic model; \
valid combinations: pk with steady, quasi-steady, theodorsen, jones; k with quasi-steady, \
theodorsen, jones; p with steady, quasi-steady, jones
    """
    check_choice("flutter method", method, FLUTTER_METHODS)
    check_choice("aerodynamic model", aero, AERO_MODELS)
    if aero not in VALID_COMBINATIONS[method]:
        combos = "; ".join(f"{m} with {', '.join(a)}" for m, a in VALID_COMBINATIONS.items())
        why = {
            "p": "the p method needs a state-space aerodynamic model",
            "k": "the k method needs frequency-dependent aerodynamics (steady loads have no "
                 "damping, so g = 0 marks a frequency fold, not flutter)",
        }[method]
        raise ParameterError(f"{why}; valid combinations: {combos}")


@dataclass(frozen=True, eq=False)
class FlutterResult:
    """Flutter analysis of a typical section (V-g and V-f data, flutter and divergence).

    Attributes
    ----------
    section_name, aero, method : str
    speed : ndarray, shape (n_modes, n_points)
        Reduced speed U/(b omega_theta) of each point of each mode [-].
    frequency : ndarray, shape (n_modes, n_points)
        omega/omega_theta [-].
    damping : ndarray, shape (n_modes, n_points)
        ``Re(p)`` [-] (pk, p) or the required structural damping ``g`` [-] (k).
    damping_kind : str
        What ``damping`` is.
    flutter_speed : float or None
        Lowest flutter speed U_F/(b omega_theta) [-]; None if none was found.
    flutter_frequency : float or None
        omega_F/omega_theta [-].
    divergence_speed : float
        U_D/(b omega_theta) [-]; ``inf`` if the section cannot diverge.
    note : str
    """

    section_name: str
    aero: str
    method: str
    speed: np.ndarray
    frequency: np.ndarray
    damping: np.ndarray
    damping_kind: str
    flutter_speed: float | None
    flutter_frequency: float | None
    divergence_speed: float
    note: str = ""

    def to_dict(self) -> dict:
        """JSON-ready dictionary (None for missing values; no NaN)."""

        def clean(a):
            return [[None if not np.isfinite(v) else float(v) for v in row] for row in a]

        return {
            "section": self.section_name,
            "aero": self.aero,
            "method": self.method,
            "flutter_speed": self.flutter_speed,
            "flutter_frequency": self.flutter_frequency,
            "divergence_speed": (None if not math.isfinite(self.divergence_speed)
                                 else self.divergence_speed),
            "speed_unit": "U/(b omega_theta)",
            "frequency_unit": "omega/omega_theta",
            "damping_kind": self.damping_kind,
            "speed": clean(self.speed),
            "frequency": clean(self.frequency),
            "damping": clean(self.damping),
            "note": self.note,
        }


def divergence_speed(section: TypicalSection) -> float:
    """Reduced divergence speed, from the static aeroelastic stiffness [-].

    Solves ``det(K_s - V^2 (2/mu) l w0) = 0``; ``inf`` when no positive root
    exists (reference point at or ahead of the quarter chord).

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> s = load_section("hodges-pierce")
    >>> round(divergence_speed(s), 6), round(math.sqrt(s.mu * s.r2 / (1 + 2 * s.a)), 6)
    (2.828427, 2.828427)
    """
    _, Ks = section.structural_matrices()
    _, _, l, _, w0 = aero_matrices(section.a, section.mu)
    Ka = 2.0 / section.mu * (l @ w0)
    lam = np.linalg.eigvals(np.linalg.solve(Ks, Ka))
    pos = [1.0 / z.real for z in lam if abs(z.imag) < 1e-12 and z.real > 1e-14]
    return math.sqrt(min(pos)) if pos else math.inf


def _quadratic(section: TypicalSection, V: float, aero: str, C: complex):
    Ms, Ks = section.structural_matrices()
    Mnc, Dnc, l, w1, w0 = aero_matrices(section.a, section.mu)
    circ = 2.0 * V / section.mu * C * l
    if aero == "steady":
        return Ms.astype(complex), np.zeros((2, 2), complex), Ks - V * (2.0 * V / section.mu) * (
            l @ w0)
    return Ms - Mnc, -V * Dnc - circ @ w1, Ks - V * circ @ w0


def _roots(M2, M1, M0):
    n = M2.shape[0]
    A = np.zeros((2 * n, 2 * n), dtype=complex)
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -np.linalg.solve(M2, M0)
    A[n:, n:] = -np.linalg.solve(M2, M1)
    return np.linalg.eig(A)


def pk_roots(section: TypicalSection, V: float, aero: str, guesses, *, tol: float = 1e-12,
             max_iter: int = 200) -> np.ndarray:
    """Converged p-k roots at reduced speed ``V`` [-], one per guess.

    Parameters
    ----------
    section : TypicalSection
    V : float
        Reduced speed > 0 [-].
    aero : str
        Any model of :data:`~liquidamp.structure.aero.AERO_MODELS`.
    guesses : array of complex
        One starting ``p`` per mode (``Im p > 0``) [-].
    tol : float
        Convergence of ``k`` [-].
    max_iter : int

    Returns
    -------
    ndarray of complex
        ``p`` per mode, in units of omega_theta.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> p = pk_roots(load_section("hodges-pierce"), 1e-3, "theodorsen", [0.4j, 1.0j])
    >>> np.round(p.imag, 4)   # in-vacuo 0.3984, 1.0255; apparent air mass lowers them
    array([0.3887, 1.0112])
    """
    if V <= 0.0:
        raise ParameterError(f"reduced speed V must be > 0 for the p-k method, got {V:g}")
    out = []
    for g in np.atleast_1d(np.asarray(guesses, dtype=complex)):
        p = complex(g)
        for _ in range(max_iter):
            k = abs(p.imag) / V
            lam, _ = _roots(*_quadratic(section, V, aero, complex(lift_deficiency(aero, k))))
            cand = lam[np.argmin(np.abs(lam - p))]
            if abs(abs(cand.imag) / V - k) <= tol * max(1.0, k):
                p = cand
                break
            p = cand
        else:
            raise ConvergenceError(
                f"p-k iteration did not converge at V={V:g} (aero {aero}) in {max_iter} steps"
            )
        out.append(p)
    return np.array(out)


def _wind_off(section: TypicalSection) -> np.ndarray:
    Ms, Ks = section.structural_matrices()
    w2 = np.sort(np.linalg.eigvals(np.linalg.solve(Ms, Ks)).real)
    return 1j * np.sqrt(w2)


def _first_crossing(values: np.ndarray) -> int | None:
    """Index i such that values[i] <= neutral < values[i+1], or None."""
    for i in range(values.size - 1):
        if values[i] <= _NEUTRAL < values[i + 1]:
            return i
    return None


def _pk(section, aero, V):
    n = V.size
    P = np.zeros((2, n), dtype=complex)
    guess = _wind_off(section)
    for i, v in enumerate(V):
        P[:, i] = pk_roots(section, v, aero, guess)
        guess = P[:, i]
    damping = P.real
    frequency = np.abs(P.imag)
    g = damping.max(axis=0)
    i = _first_crossing(g)
    VF = wF = None
    if i is not None:
        start = P[:, i]

        def f(v):
            return float(np.max(pk_roots(section, v, aero, start).real)) - _NEUTRAL

        VF = brentq(f, V[i], V[i + 1], xtol=1e-12)
        p = pk_roots(section, VF, aero, start)
        wF = float(abs(p[np.argmax(p.real)].imag))
    return np.tile(V, (2, 1)), frequency, damping, "Re(p) [-] (decay rate / omega_theta)", VF, wF


def _k_matrix(section, aero, k):
    Ms, Ks = section.structural_matrices()
    Mnc, Dnc, l, w1, w0 = aero_matrices(section.a, section.mu)
    mu = section.mu
    if aero == "steady":
        A = 2.0 / (mu * k * k) * (l @ w0)
    else:
        C = complex(lift_deficiency(aero, k))
        A = -Mnc + 1j / k * Dnc + 2.0 * C / (k * mu) * (1j * (l @ w1) + (l @ w0) / k)
    return np.linalg.solve(Ks, Ms + A)


def _k_eig(section, aero, k):
    Z, vec = np.linalg.eig(_k_matrix(section, aero, k))
    with np.errstate(divide="ignore", invalid="ignore"):
        ok = Z.real > 0.0
        Om = np.where(ok, 1.0 / np.sqrt(np.where(ok, Z.real, 1.0)), np.nan)
        g = np.where(ok, Z.imag / np.where(ok, Z.real, 1.0), np.nan)
    return Z, vec, Om, g


def _k(section, aero, kgrid):
    k = np.sort(np.asarray(kgrid, dtype=float))[::-1]  # decreasing k = increasing V
    lams, vecs = [], []
    for kk in k:
        Z, vec, _, _ = _k_eig(section, aero, kk)
        lams.append(Z)
        vecs.append(vec)
    tr = track_modes(-k, lams, vecs)
    Z = tr.eigenvalues.T  # (2, n)
    ok = Z.real > 0.0
    Om = np.full(Z.shape, np.nan)
    g = np.full(Z.shape, np.nan)
    Om[ok] = 1.0 / np.sqrt(Z.real[ok])
    g[ok] = Z.imag[ok] / Z.real[ok]
    V = Om / k[None, :]
    best = (None, None)
    for j in range(2):
        gj = np.where(np.isfinite(g[j]), g[j], -np.inf)
        i = _first_crossing(gj)
        if i is None:
            continue
        ref = tr.vectors[i][:, j]

        def gk(kk, ref=ref):
            Zk, vk, Omk, gkk = _k_eig(section, aero, kk)
            m = int(np.argmax(mac(ref[:, None], vk)[0]))
            return float(gkk[m]) - _NEUTRAL, float(Omk[m])

        kf = brentq(lambda kk: gk(kk)[0], k[i + 1], k[i], xtol=1e-13)
        OmF = gk(kf)[1]
        VF = OmF / kf
        if best[0] is None or VF < best[0]:
            best = (VF, OmF)
    return V, Om, g, "g [-] (structural damping needed for harmonic motion)", best[0], best[1]


def _p_eigs(section, aero, V):
    A, _ = section.nondimensional_matrices(V, aero)
    lam, vec = np.linalg.eig(A)
    part = np.sum(np.abs(vec[:4]) ** 2, axis=0) / np.sum(np.abs(vec) ** 2, axis=0)
    return lam, vec, part


def _structural(lam, vec, part):
    up = np.flatnonzero(lam.imag > 1e-9)
    order = list(up[np.argsort(-part[up])][:2])
    if len(order) < 2:
        rest = [i for i in np.argsort(-part) if i not in order and lam[i].imag >= -1e-9]
        order += rest[: 2 - len(order)]
    return lam[order], vec[:4, order]


def _p(section, aero, V):
    lams, vecs, maxre = [], [], []
    for v in V:
        lam, vec, part = _p_eigs(section, aero, v)
        s, sv = _structural(lam, vec, part)
        lams.append(s)
        vecs.append(sv)
        maxre.append(float(lam.real.max()))
    tr = track_modes(V, lams, vecs)
    P = tr.eigenvalues.T
    i = _first_crossing(np.asarray(maxre))
    VF = wF = None
    if i is not None:

        def f(v):
            return float(_p_eigs(section, aero, v)[0].real.max()) - _NEUTRAL

        VF = brentq(f, V[i], V[i + 1], xtol=1e-12)
        lam = _p_eigs(section, aero, VF)[0]
        wF = float(abs(lam[np.argmax(lam.real)].imag))
    return np.tile(V, (2, 1)), np.abs(P.imag), P.real, "Re(p) [-] (decay rate / omega_theta)", \
        VF, wF


def flutter_analysis(
    section: TypicalSection,
    aero: str = "theodorsen",
    method: str = "pk",
    speeds=None,
    reduced_frequencies=None,
) -> FlutterResult:
    """Flutter speed and frequency, divergence speed and V-g / V-f data.

    Parameters
    ----------
    section : TypicalSection
    aero : {"steady", "quasi-steady", "theodorsen", "jones"}
    method : {"pk", "k", "p"}
        See the module notes; invalid combinations raise
        :class:`~liquidamp.errors.ParameterError` naming the valid ones.
    speeds : array, optional
        Increasing reduced speeds V > 0 for ``pk`` and ``p`` [-]
        (default 0.05 to 3.5, 70 points).
    reduced_frequencies : array, optional
        Reduced frequencies k > 0 for ``k`` [-] (default 80 points
        log-spaced from 3 to 0.03).

    Returns
    -------
    FlutterResult

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> r = flutter_analysis(load_section("hodges-pierce"), "steady", "p")
    >>> round(r.flutter_speed, 4), round(r.divergence_speed, 4)
    (1.8425, 2.8284)
    """
    check_combination(aero, method)
    note = ""
    if method in ("pk", "p"):
        V = np.asarray(speeds if speeds is not None else np.linspace(0.05, 3.5, 70), float)
        if V.size < 2 or not np.all(np.isfinite(V)) or np.any(V <= 0.0) or np.any(
                np.diff(V) <= 0.0):
            raise ParameterError(
                "speeds must hold at least two finite, strictly increasing reduced speeds > 0 "
                f"[U/(b omega_theta)], got {np.asarray(V).tolist()}"
            )
        out = _pk(section, aero, V) if method == "pk" else _p(section, aero, V)
    else:
        k = np.asarray(reduced_frequencies if reduced_frequencies is not None
                       else np.geomspace(3.0, 0.03, 80), float)
        if k.size < 2 or not np.all(np.isfinite(k)) or np.any(k <= 0.0):
            raise ParameterError(
                "reduced_frequencies must hold at least two finite values k > 0 [-], "
                f"got {np.asarray(k).tolist()}"
            )
        if np.unique(k).size != k.size:
            raise ParameterError("reduced_frequencies must not repeat a value")
        out = _k(section, aero, k)
        note = "k method: damping is the structural damping g required; V = omega/k per mode"
    speed, freq, damp, kind, VF, wF = out
    if VF is None:
        note = (note + "; " if note else "") + "no flutter crossing in the range"
    return FlutterResult(
        section.name, aero, method, speed, freq, damp, kind,
        None if VF is None else float(VF), None if wF is None else float(wF),
        divergence_speed(section), note,
    )
