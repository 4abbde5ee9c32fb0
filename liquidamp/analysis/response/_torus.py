"""Two-frequency harmonic balance on the torus: the numerics behind
:mod:`liquidamp.analysis.response.dual_frequency`.

Private module.  A quasi-periodic steady state under the stroke
y = y0 + A1 sin(theta1) + A2 sin(theta2 + phi), theta1 = Omega t, theta2 =
omega t, is a function x(theta1, theta2) on the torus that solves

.. math:: \\Omega\\, \\partial x/\\partial\\theta_1 + \\omega\\, \\partial x/\\partial\\theta_2
          = f(x, y(\\theta), v(\\theta)),

with f the compiled right-hand side of :mod:`liquidamp.device.kernels`
(:func:`~liquidamp.device.kernels.model_rhs`).  The states are collocated
on a uniform grid of odd sizes over both phases and differentiated
spectrally (alternating frequency-time: the derivative is exact for the
trigonometric interpolant, the nonlinearity is evaluated pointwise); the
Jacobian of the collocation equations is the linear spectral derivative
minus the pointwise :func:`~liquidamp.device.kernels.model_jac`.

The invariants of a sealed device (total mass, each chamber's
density-pressure relation) make the torus a member of a family, so the
Newton system is bordered: m multipliers ``lambda`` enter the residual
along fixed directions (the scaled invariant gradients at the start) and
m rows hold the grid means of the invariants at their rest values
(:class:`TorusProblem`).

Newton-Krylov: each Newton step is solved by GMRES, preconditioned by the
exact inverse of the operator with the Jacobian averaged over the
*secondary* phase (the one along which the stroke velocity amplitude is
smaller).  That operator is diagonal in the secondary Fourier index l, so
it factors into one dense block per l of size (points along the primary
phase) x (states), bordered for l = 0; only the variation of the Jacobian
along the secondary phase is left to GMRES (none at all when the
secondary amplitude is zero).  The blocks are factored once per grid, at
the start (a chord preconditioner: GMRES makes up for the Jacobian's
change over the Newton iterations); the linear algebra is compiled
(numba), so that it does not depend on a threaded BLAS on small blocks.

The force's first harmonics come from the torus grid by DFT
(:func:`harmonics_of`); a force with a jump is evaluated on a fine grid,
the states interpolated spectrally onto it (:func:`force_quadrature`).

References
----------
.. [1] T. M. Cameron, J. H. Griffin, "An alternating frequency/time domain
   method for calculating the steady-state response of nonlinear dynamic
   systems", J. Appl. Mech. 56(1), 1989, 149-154.
.. [2] M. Guskov, J.-J. Sinou, F. Thouverez, "Multi-dimensional harmonic
   balance applied to rotor dynamics", Mech. Res. Commun. 35(8), 2008,
   537-545.
.. [3] Y. Saad, M. H. Schultz, "GMRES: a generalized minimal residual
   algorithm for solving nonsymmetric linear systems", SIAM J. Sci. Stat.
   Comput. 7(3), 1986.
.. [4] C. T. Kelley, Solving Nonlinear Equations with Newton's Method, SIAM,
   2003 (Newton-Krylov, forcing terms, line search).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.coupled.kernels import lu_factor, lu_solve
from liquidamp.device import kernels as K
from liquidamp.errors import ConvergenceError
from liquidamp.structure.testmachine import TwoFrequencyStroke

drop_stale(__file__)  # before any kernel of this module loads from the cache

__all__ = ["spectral_matrix", "resample", "torus_rhs", "torus_rhs_jac", "TorusProblem",
           "Stalled", "grid_strokes", "harmonics_of", "upsample", "force_quadrature"]

#: Newton iterations after which a residual that has not halved over the last four
#: counts as stalled (an under-resolved grid has no solution near the start).
STALL_AFTER = 8


class Stalled(ConvergenceError):
    """The Newton iteration stopped making progress (raised by :meth:`TorusProblem.solve`)."""


@njit(cache=True, error_model="numpy")
def torus_rhs(spec, prm, ep, X, Y, V, F):
    """:func:`~liquidamp.device.kernels.model_rhs` at every grid point: X, F (n, N); Y, V (N,)."""
    n, N = X.shape
    xk = np.empty(n)
    fk = np.empty(n)
    for k in range(N):
        for i in range(n):
            xk[i] = X[i, k]
        K.model_rhs(spec, xk, Y[k], V[k], prm, ep, fk)
        for i in range(n):
            F[i, k] = fk[i]


@njit(cache=True, error_model="numpy")
def torus_rhs_jac(spec, prm, ep, X, Y, V, F, J):
    """:func:`torus_rhs` and :func:`~liquidamp.device.kernels.model_jac` into J (N, n, n)."""
    n, N = X.shape
    xk = np.empty(n)
    fk = np.empty(n)
    Jk = np.zeros((n, n))
    for k in range(N):
        for i in range(n):
            xk[i] = X[i, k]
        K.model_rhs(spec, xk, Y[k], V[k], prm, ep, fk)
        K.model_jac(spec, xk, Y[k], V[k], prm, ep, Jk)
        for i in range(n):
            F[i, k] = fk[i]
            for j in range(n):
                J[k, i, j] = Jk[i, j]


def spectral_matrix(N: int) -> np.ndarray:
    """Spectral differentiation matrix on N (odd) uniform points over 2 pi [1/rad].

    Examples
    --------
    >>> th = 2 * np.pi * np.arange(7) / 7
    >>> bool(np.allclose(spectral_matrix(7) @ np.sin(2 * th), 2 * np.cos(2 * th)))
    True
    """
    j = np.arange(N)
    d = j[:, None] - j[None, :]
    with np.errstate(divide="ignore"):
        D = 0.5 * (-1.0) ** d / np.sin(np.pi * d / N)
    D[d == 0] = 0.0
    return D


def resample(X: np.ndarray, N: int, axis: int = -1) -> np.ndarray:
    """Trigonometric interpolant of uniform periodic samples, resampled to N points.

    Harmonics above N // 2 are dropped (N odd keeps the real form exact).

    Examples
    --------
    >>> th = 2 * np.pi * np.arange(64) / 64
    >>> y = resample(1 + np.cos(th) - 0.5 * np.sin(3 * th), 9)
    >>> t9 = 2 * np.pi * np.arange(9) / 9
    >>> bool(np.allclose(y, 1 + np.cos(t9) - 0.5 * np.sin(3 * t9)))
    True
    """
    M = X.shape[axis]
    C = np.fft.rfft(X, axis=axis)
    H = min(N // 2, (M - 1) // 2)
    keep = [slice(None)] * X.ndim
    keep[axis] = slice(0, H + 1)
    C = C[tuple(keep)]
    return np.fft.irfft(C, n=N, axis=axis) * (N / M)


# ------------------------------------------------------------------ strokes and forces
def grid_strokes(stroke: TwoFrequencyStroke, N1: int, N2: int):
    """Stroke, rate and acceleration on the (N1, N2) torus grid [m, m/s, m/s^2]."""
    t1 = 2.0 * np.pi * np.arange(N1) / N1
    t2 = 2.0 * np.pi * np.arange(N2) / N2 + stroke.phase2
    W, w, A1, A2 = stroke.omega1, stroke.omega2, stroke.amplitude1, stroke.amplitude2
    s1, c1 = np.sin(t1)[:, None], np.cos(t1)[:, None]
    s2, c2 = np.sin(t2)[None, :], np.cos(t2)[None, :]
    Y = stroke.offset + A1 * s1 + A2 * s2
    V = A1 * W * c1 + A2 * w * c2
    A = -A1 * W * W * s1 - A2 * w * w * s2
    return Y, V, A


def harmonics_of(F, stroke: TwoFrequencyStroke):
    """(K_lag, K_rev) from the force F on a (N1, N2) torus grid [N/m]."""
    N1, N2 = F.shape
    th1 = 2.0 * np.pi * np.arange(N1) / N1
    th2 = 2.0 * np.pi * np.arange(N2) / N2
    F_lag = 2j * np.mean(F.mean(axis=0) * np.exp(-1j * th2))  # a + i b of a sin + b cos
    K_lag = complex(F_lag / (stroke.amplitude2 * np.exp(1j * stroke.phase2)))
    K_rev = None
    if stroke.amplitude1 > 0.0:
        K_rev = complex(2j * np.mean(F.mean(axis=1) * np.exp(-1j * th1)) / stroke.amplitude1)
    return K_lag, K_rev


def rel_change(a, b) -> float:
    """|a - b| / |a| (0 where ``a`` is None)."""
    if a is None:
        return 0.0
    return abs(a - b) / max(abs(a), 1e-300)


def upsample(X3, N1f: int, N2f: int):
    """Trigonometric interpolant of X3 (n, N1, N2) (odd sizes) on an (N1f, N2f) grid."""
    n, N1, N2 = X3.shape
    C = np.fft.fft2(X3, axes=(1, 2))
    H1, H2 = (N1 - 1) // 2, (N2 - 1) // 2
    P = np.zeros((n, N1f, N2f), complex)
    k1 = np.r_[0:H1 + 1, -H1:0]
    k2 = np.r_[0:H2 + 1, -H2:0]
    P[:, k1[:, None] % N1f, k2[None, :] % N2f] = C[:, k1[:, None] % N1, k2[None, :] % N2]
    return np.fft.ifft2(P, axes=(1, 2)).real * (N1f * N2f / (N1 * N2))


def force_quadrature(model, params, stroke, fine, primary: int, X3=None):
    """(K_lag, K_rev, relative error) from the force on the fine grid, states interpolated."""
    Na, Nb = int(fine[0]), int(fine[1])
    N1f, N2f = (Na, Nb) if primary == 1 else (Nb, Na)
    if X3 is not None:  # never coarser than the torus grid
        N1f, N2f = max(N1f, 2 * X3.shape[1]), max(N2f, 2 * X3.shape[2])
    Y, V, A = grid_strokes(stroke, N1f, N2f)
    n = model.n_states
    Xf = np.zeros((n, N1f * N2f)) if X3 is None else upsample(X3, N1f, N2f).reshape(n, -1)
    F = np.asarray(model.force(0.0, Xf, (Y.ravel(), V.ravel(), A.ravel()), params),
                   float).reshape(N1f, N2f)
    K_lag, K_rev = harmonics_of(F, stroke)
    h_lag, h_rev = harmonics_of(F[::2, ::2], stroke)
    err = max(rel_change(K_lag, h_lag), rel_change(K_rev, h_rev) if K_rev is not None else 0.0)
    return K_lag, K_rev, err


# ------------------------------------------------------------------ compiled linear algebra
@njit(cache=True, error_model="numpy")
def apply_operator(Da, Db, Js, Bm, Cm, u, out):
    """out = L u: the bordered Jacobian of the collocation equations (scaled).

    ``u`` holds z[i, a, b] (n, Na, Nb) flattened, then the m multipliers.
    """
    Na, Nb = Da.shape[0], Db.shape[0]
    n = Js.shape[1]
    m = Bm.shape[0]
    N = Na * Nb
    nN = n * N
    for i in range(n):
        for a in range(Na):
            for b in range(Nb):
                s = 0.0
                for q in range(Na):
                    s += Da[a, q] * u[(i * Na + q) * Nb + b]
                for q in range(Nb):
                    s += Db[b, q] * u[(i * Na + a) * Nb + q]
                k = a * Nb + b
                for j in range(n):
                    s -= Js[k, i, j] * u[j * N + k]
                for c in range(m):
                    s += Bm[c, i, k] * u[nN + c]
                out[i * N + k] = s
    for c in range(m):
        s = 0.0
        for i in range(n):
            for k in range(N):
                s += Cm[c, i, k] * u[i * N + k]
        out[nN + c] = s


@njit(cache=True, error_model="numpy")
def factor_preconditioner(Da, Jbar, Bbar, Cbar, shifts, M0, piv0, Mc, pivc):
    """Factor the blocks of the preconditioner in place; False if one is singular.

    ``M0`` (Na n + m square, real): the mode l = 0 along the secondary phase,
    ``Da (x) I - blockdiag(Jbar)`` bordered by ``Bbar`` (Na, n, m) and
    ``Cbar`` (m, Na, n); ``Mc[l - 1]`` (complex): mode l, the same plus
    ``shifts[l - 1] I`` (i l wb / w_ref), unbordered.
    """
    Na = Da.shape[0]
    n = Jbar.shape[1]
    m = Bbar.shape[2]
    S = Na * n
    M0[:, :] = 0.0
    for a in range(Na):
        for q in range(Na):
            d = Da[a, q]
            if d != 0.0:
                for i in range(n):
                    M0[a * n + i, q * n + i] = d
        for i in range(n):
            for j in range(n):
                M0[a * n + i, a * n + j] -= Jbar[a, i, j]
            for c in range(m):
                M0[a * n + i, S + c] = Bbar[a, i, c]
                M0[S + c, a * n + i] = Cbar[c, a, i]
    for lm in range(Mc.shape[0]):
        for r in range(S):
            for c in range(S):
                Mc[lm, r, c] = M0[r, c]
            Mc[lm, r, r] += shifts[lm]
    ok = lu_factor(M0, piv0)
    for lm in range(Mc.shape[0]):
        ok = ok and lu_factor(Mc[lm], pivc[lm])
    return ok


@njit(cache=True, error_model="numpy")
def apply_preconditioner(M0, piv0, Mc, pivc, cosb, sinb, n, Na, Nb, r, out):
    """out = P^{-1} r with the factors of :func:`factor_preconditioner`."""
    N = Na * Nb
    nN = n * N
    S = Na * n
    m = M0.shape[0] - S
    H = Mc.shape[0]
    rhs0 = np.empty(S + m)
    for i in range(n):
        for a in range(Na):
            s = 0.0
            for b in range(Nb):
                s += r[(i * Na + a) * Nb + b]
            rhs0[a * n + i] = s / Nb
    for c in range(m):
        rhs0[S + c] = r[nN + c]
    lu_solve(M0, piv0, rhs0)
    for i in range(n):
        for a in range(Na):
            z0 = rhs0[a * n + i]
            for b in range(Nb):
                out[(i * Na + a) * Nb + b] = z0
    for c in range(m):
        out[nN + c] = rhs0[S + c]
    rl = np.empty(S, np.complex128)
    for lm in range(H):
        for i in range(n):
            for a in range(Na):
                sr = 0.0
                si = 0.0
                for b in range(Nb):
                    v = r[(i * Na + a) * Nb + b]
                    sr += v * cosb[lm, b]
                    si -= v * sinb[lm, b]
                rl[a * n + i] = complex(sr, si)
        lu_solve(Mc[lm], pivc[lm], rl)
        for i in range(n):
            for a in range(Na):
                zr = rl[a * n + i].real * (2.0 / Nb)
                zi = rl[a * n + i].imag * (2.0 / Nb)
                for b in range(Nb):
                    out[(i * Na + a) * Nb + b] += zr * cosb[lm, b] - zi * sinb[lm, b]


@njit(cache=True, error_model="numpy")
def gmres_step(Da, Db, Js, Bm, Cm, M0, piv0, Mc, pivc, cosb, sinb, n, rhs, rtol, restart,
               max_iter, x):
    """Right-preconditioned restarted GMRES for L x = rhs from x = 0, into ``x``.

    Stops when the true residual norm is below ``rtol`` |rhs| or after
    ``max_iter`` iterations; returns (iterations, relative residual).
    """
    Na, Nb = Da.shape[0], Db.shape[0]
    size = rhs.size
    V = np.empty((restart + 1, size))
    Z = np.empty((restart, size))
    Hm = np.zeros((restart + 1, restart))
    cs = np.empty(restart)
    sn = np.empty(restart)
    g = np.empty(restart + 1)
    w = np.empty(size)
    r = rhs.copy()
    for q in range(size):
        x[q] = 0.0
    bnorm = np.sqrt(np.sum(rhs * rhs))
    if bnorm == 0.0:
        return 0, 0.0
    total = 0
    rel = 1.0
    while total < max_iter:
        beta = np.sqrt(np.sum(r * r))
        rel = beta / bnorm
        if rel <= rtol:
            break
        for q in range(size):
            V[0, q] = r[q] / beta
        g[:] = 0.0
        g[0] = beta
        Hm[:, :] = 0.0
        k_used = 0
        for k in range(restart):
            apply_preconditioner(M0, piv0, Mc, pivc, cosb, sinb, n, Na, Nb, V[k], Z[k])
            apply_operator(Da, Db, Js, Bm, Cm, Z[k], w)
            for j in range(k + 1):  # modified Gram-Schmidt
                h = 0.0
                for q in range(size):
                    h += w[q] * V[j, q]
                Hm[j, k] = h
                for q in range(size):
                    w[q] -= h * V[j, q]
            hn = np.sqrt(np.sum(w * w))
            Hm[k + 1, k] = hn
            if hn > 0.0:
                for q in range(size):
                    V[k + 1, q] = w[q] / hn
            for j in range(k):  # apply the previous rotations
                t = cs[j] * Hm[j, k] + sn[j] * Hm[j + 1, k]
                Hm[j + 1, k] = -sn[j] * Hm[j, k] + cs[j] * Hm[j + 1, k]
                Hm[j, k] = t
            d = np.sqrt(Hm[k, k] ** 2 + Hm[k + 1, k] ** 2)
            cs[k] = Hm[k, k] / d if d > 0.0 else 1.0
            sn[k] = Hm[k + 1, k] / d if d > 0.0 else 0.0
            Hm[k, k] = d
            Hm[k + 1, k] = 0.0
            g[k + 1] = -sn[k] * g[k]
            g[k] = cs[k] * g[k]
            total += 1
            k_used = k + 1
            if abs(g[k + 1]) / bnorm <= rtol or total >= max_iter or hn == 0.0:
                break
        y = np.zeros(k_used)  # back substitution, then x += Z^T y
        for j in range(k_used - 1, -1, -1):
            s = g[j]
            for q in range(j + 1, k_used):
                s -= Hm[j, q] * y[q]
            y[j] = s / Hm[j, j]
        for j in range(k_used):
            for q in range(size):
                x[q] += y[j] * Z[j, q]
        apply_operator(Da, Db, Js, Bm, Cm, x, w)
        for q in range(size):
            r[q] = rhs[q] - w[q]
        rel = np.sqrt(np.sum(r * r)) / bnorm
        if rel <= rtol:
            break
    return total, rel


def invariant_scales(target, G, scale) -> np.ndarray:
    """Scale of each invariant's constraint row [invariant units].

    The larger of the rest value ``|target|`` and the invariant's natural
    variation: the RMS over the grid of ``sum_i |dI/dx_i| s_i``, how far the
    invariant moves when every state moves by its swing ``s_i``.  A target
    that is zero only up to rounding (a piston balance ``k (y - y_p) -
    F_fluid`` at rest, whose fluid force ``A_p p1 - A_p p2`` a BLAS dot
    product with fused multiply-adds leaves at ~1e-15 N) must not set the
    scale: the constraint row would be weighted by 1e15 and Newton would
    chase rounding noise.  1 where both are zero.

    Parameters
    ----------
    target : array_like, shape (m,)
        The invariants' rest values [invariant units].
    G : ndarray, shape (m, n, N)
        Their gradients at the grid points [invariant units / state units].
    scale : ndarray, shape (n,)
        The state swings [state units].

    Returns
    -------
    ndarray, shape (m,)
        Positive scales [invariant units].

    Examples
    --------
    >>> G = np.zeros((2, 2, 3)); G[0, 0] = 2.0; G[1, 1] = -1e3; G[1, 0] = 1e3
    >>> invariant_scales([1e-15, 0.0], G, np.array([0.5, 1e-3])).tolist()
    [1.0, 501.0]
    >>> invariant_scales([4.0, 0.0], np.zeros((2, 2, 3)), np.ones(2)).tolist()
    [4.0, 1.0]
    """
    t = np.abs(np.asarray(target, float))
    natural = np.sqrt(np.mean(np.einsum("cik,i->ck", np.abs(G), np.asarray(scale, float))
                              ** 2, axis=1))
    out = np.maximum(t, natural)
    return np.where(out > 0.0, out, 1.0)


class TorusProblem:
    """Collocation equations of the torus on a grid, in scaled variables.

    The grid is ``(Na, Nb)`` over the primary phase (axis a, frequency
    ``wa`` [rad/s]) and the secondary phase (axis b, ``wb``); states are
    held as ``X[i, ja * Nb + jb]``.  Unknowns are ``z = x / s`` (``s`` a
    swing per state) and the multipliers ``lambda``; residual rows are
    scaled by ``1 / (s w_ref)``, ``w_ref = max(wa, wb)``; the invariant rows
    by :func:`invariant_scales` (their natural variation, not their rest value,
    which may be zero up to rounding).

    Parameters
    ----------
    packed : tuple
        ``(spec, prm, ep)`` of :meth:`DeviceModel.packed`.
    wa, wb : float
        Frequencies of the primary and secondary phases [rad/s].
    Y, V : ndarray, shape (Na, Nb)
        Rod stroke [m] and rate [m/s] on the grid.
    scale : ndarray, shape (n,)
        The swing ``s`` of each state [state units].
    invariants : object or None
        ``invariants.evaluate(X (n, N), Y (N,)) -> (values (m, N), gradients
        (m, n, N))`` and ``invariants.target`` (m,); None for no invariants.
    X0 : ndarray, shape (n, N)
        The starting torus (fixes the bordering directions).
    """

    def __init__(self, packed, wa, wb, Y, V, scale, invariants, X0):
        self.spec, self.prm, self.ep = packed
        self.wa, self.wb = float(wa), float(wb)
        self.wr = max(self.wa, self.wb)
        self.Na, self.Nb = Y.shape
        self.N = self.Na * self.Nb
        self.Y, self.V = np.ascontiguousarray(Y.ravel()), np.ascontiguousarray(V.ravel())
        self.s = np.asarray(scale, float)
        self.n = self.s.size
        self.Da = np.ascontiguousarray(spectral_matrix(self.Na) * (self.wa / self.wr))
        self.Db = np.ascontiguousarray(spectral_matrix(self.Nb) * (self.wb / self.wr))
        self.inv = invariants
        self.m = 0 if invariants is None else int(np.size(invariants.target))
        self.F = np.empty((self.n, self.N))
        self.J = np.empty((self.N, self.n, self.n))
        if self.m:
            _, G = invariants.evaluate(X0, self.Y)
            self.inv_scale = invariant_scales(invariants.target, G, self.s)
            # fixed bordering directions: the scaled invariant gradients at the start
            self.Bm = np.ascontiguousarray(
                G * self.s[None, :, None] / self.inv_scale[:, None, None])  # (m, n, N)
        else:
            self.Bm = np.zeros((0, self.n, self.N))
        self.G = np.zeros((self.m, self.n, self.N))
        Hb = (self.Nb - 1) // 2
        ang = 2.0 * np.pi * np.outer(np.arange(1, Hb + 1), np.arange(self.Nb)) / self.Nb
        self.cosb, self.sinb = np.cos(ang), np.sin(ang)
        self.shifts = 1j * np.arange(1, Hb + 1) * (self.wb / self.wr)
        self._factors = None

    # ------------------------------------------------------------- residual
    def derivative(self, Z):
        """(wa d/dtheta_a + wb d/dtheta_b) / w_ref of Z (n, Na, Nb)."""
        return np.einsum("jk,ikl->ijl", self.Da, Z) + Z @ self.Db.T

    def residual(self, X, lam):
        """Scaled residual (n N + m,) at states X (n, N); keeps the Jacobian there."""
        n, Na, Nb = self.n, self.Na, self.Nb
        torus_rhs_jac(self.spec, self.prm, self.ep, X, self.Y, self.V, self.F, self.J)
        Z = X / self.s[:, None]
        R = self.derivative(Z.reshape(n, Na, Nb)).reshape(n, -1) - self.F / (
            self.s * self.wr)[:, None]
        out = np.empty(n * self.N + self.m)
        if self.m:
            R += np.einsum("cik,c->ik", self.Bm, lam)
            vals, G = self.inv.evaluate(X, self.Y)
            self.G = G
            out[n * self.N:] = (vals.mean(axis=1) - self.inv.target) / self.inv_scale
        out[:n * self.N] = R.ravel()
        return out

    def _linear_parts(self):
        """Scaled Jacobian at the grid points and the constraint rows, at the last residual."""
        Js = self.J * (1.0 / (self.s * self.wr))[None, :, None] * self.s[None, None, :]
        Cm = self.G * self.s[None, :, None] / (self.inv_scale[:, None, None] * self.N) \
            if self.m else np.zeros((0, self.n, self.N))
        return np.ascontiguousarray(Js), np.ascontiguousarray(Cm)

    def factor(self, Js, Cm) -> None:
        """Factor the preconditioner: the Jacobian averaged over the secondary phase."""
        n, Na, Nb, m = self.n, self.Na, self.Nb, self.m
        S = Na * n
        Jbar = np.ascontiguousarray(Js.reshape(Na, Nb, n, n).mean(axis=1))
        Bbar = np.ascontiguousarray(self.Bm.reshape(m, n, Na, Nb).mean(axis=3).transpose(
            2, 1, 0))  # (Na, n, m)
        Cbar = np.ascontiguousarray(Cm.reshape(m, n, Na, Nb).sum(axis=3).transpose(0, 2, 1))
        H = self.shifts.size
        M0 = np.empty((S + m, S + m))
        piv0 = np.empty(S + m, np.int64)
        Mc = np.empty((H, S, S), np.complex128)
        pivc = np.empty((H, S), np.int64)
        if not factor_preconditioner(self.Da, Jbar, Bbar, Cbar, self.shifts, M0, piv0, Mc,
                                     pivc):
            raise ConvergenceError("harmonic balance: the preconditioner is singular (the "
                                   "averaged Jacobian has a zero mode the invariants do not "
                                   "remove)")
        self._factors = (M0, piv0, Mc, pivc)

    # ---------------------------------------------------------------- Newton
    def solve(self, X, *, tol: float, max_iter: int, what: str):
        """Newton-Krylov from X (n, N); returns (X, lam, iterations, residual, krylov).

        The preconditioner is factored at the start and kept (a chord
        preconditioner: GMRES makes up for the Jacobian's change).  The
        iteration stops when the Newton step, or its superlinear estimate
        ``step^2 / previous step`` of the distance still to go, is below
        ``tol`` (relative to the state swings).
        """
        n, N, m = self.n, self.N, self.m
        lam = np.zeros(m)
        r = self.residual(X, lam)
        if not np.all(np.isfinite(r)):
            raise ConvergenceError(f"harmonic balance: the starting torus gives a non-finite "
                                   f"residual ({what})")
        norm = float(np.linalg.norm(r) / math.sqrt(r.size))
        krylov = 0
        history = []
        prev_step = math.inf
        du = np.empty(r.size)
        a = step = 0.0
        for it in range(1, max_iter + 1):
            Js, Cm = self._linear_parts()
            if self._factors is None:
                self.factor(Js, Cm)
            M0, piv0, Mc, pivc = self._factors
            eta = min(1e-2, max(norm, 1e-10))  # forcing term: tighter as the residual falls
            its, _ = gmres_step(self.Da, self.Db, Js, self.Bm, Cm, M0, piv0, Mc, pivc,
                                self.cosb, self.sinb, n, -r, eta, 60, 300, du)
            krylov += its
            dz = du[:n * N].reshape(n, N)
            dlam = du[n * N:]
            step = float(np.max(np.abs(dz))) if dz.size else 0.0
            a = 1.0
            while True:
                Xt = X + a * dz * self.s[:, None]
                rt = self.residual(Xt, lam + a * dlam)
                nt = float(np.linalg.norm(rt) / math.sqrt(rt.size)) if np.all(
                    np.isfinite(rt)) else math.inf
                if nt <= (1.0 - 1e-4 * a) * norm or (a < 1.0 / 64 and math.isfinite(nt)):
                    break
                a *= 0.5
                if a < 1.0 / 1024:
                    raise ConvergenceError(
                        f"harmonic balance did not converge ({what}): no step along the "
                        f"Newton direction keeps the residual finite after {it} iterations; "
                        f"last residual {norm:.2e}")
            X, lam, r, norm = Xt, lam + a * dlam, rt, nt
            history.append(norm)
            if it >= STALL_AFTER and norm > 0.5 * history[-5]:
                raise Stalled(
                    f"harmonic balance stalled ({what}) on a {self.Na} x {self.Nb} grid after "
                    f"{it} Newton iterations: residual {norm:.2e} (scaled RMS), "
                    f"{history[-5]:.2e} four iterations before")
            taken = a * step
            if taken <= tol or (a == 1.0 and math.isfinite(prev_step)
                                and taken < 0.1 * prev_step
                                and taken * taken / prev_step <= tol):
                return X, lam, it, norm, krylov
            prev_step = taken
        raise ConvergenceError(
            f"harmonic balance did not converge ({what}) in {max_iter} Newton iterations: "
            f"residual {norm:.2e} (scaled RMS), last step {a * step:.2e} of the state swings "
            f"(allowed {tol:g}); residuals {', '.join(f'{h:.1e}' for h in history[-4:])}")

    def tail(self, X) -> tuple[float, float]:
        """Truncation estimates along the primary and the secondary phase [-].

        The largest Fourier coefficient (amplitude, twice the two-sided one)
        among the outer third of the harmonics along that phase, relative to
        each state's swing.
        """
        Z = (X / self.s[:, None]).reshape(self.n, self.Na, self.Nb)
        C = 2.0 * np.abs(np.fft.fft2(Z, axes=(1, 2))) / self.N
        ka = np.abs(np.fft.fftfreq(self.Na, 1.0 / self.Na))
        kb = np.abs(np.fft.fftfreq(self.Nb, 1.0 / self.Nb))
        Ha, Hb = (self.Na - 1) // 2, (self.Nb - 1) // 2
        out = []
        for outer in (np.broadcast_to(ka[:, None] > 2 * Ha / 3, C.shape[1:]),
                      np.broadcast_to(kb[None, :] > 2 * Hb / 3, C.shape[1:])):
            out.append(float(np.max(C[:, outer])) if outer.any() else 0.0)
        return out[0], out[1]
