"""Compiled monodromy of many (speed, damper) points of a rotor (the map kernel).

The rotating-frame rotor is ``dx/dpsi = (A0(psi)/W + A1(psi) + W A2(psi)
+ sum_k c_k D_k(psi)/W) x`` where ``c_k`` is blade ``k``'s lag damper
[N m s/rad] and ``D_k`` has one non-zero column (the lag rate of blade
``k``) in its lower half.  Each point is integrated by classical RK4 with
Richardson extrapolation, exactly as
:func:`liquidamp.analysis.stability.floquet.batched_monodromy` with fixed
``steps`` does for a batch of speeds.  Points go through the kernel in
blocks of :data:`LANES` (the innermost array axis, so that the compiler uses
SIMD across points); lanes never mix, so a point's arithmetic does not depend
on the block, chunk, thread, process or cluster it is computed in: a map
gives the same numbers bit for bit on every route.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from liquidamp._numba_cache import drop_stale

__all__ = ["LANES", "monodromies", "monodromies_parallel"]

#: Points integrated together (the innermost axis of every work array).
LANES = 16

drop_stale(__file__)  # before any kernel of this module loads from the cache


@njit(cache=True, error_model="numpy")
def _coef(B, G, cols, pw, dw, node, out):
    r, n, P = out.shape
    for i in range(r):
        for j in range(n):
            b0, b1, b2 = B[node, 0, i, j], B[node, 1, i, j], B[node, 2, i, j]
            for p in range(LANES):
                out[i, j, p] = pw[0, p] * b0 + b1 + pw[2, p] * b2
    for b in range(cols.shape[0]):
        c = cols[b]
        for i in range(r):
            g = G[node, b, i]
            for p in range(LANES):
                out[i, c, p] += dw[b, p] * g


@njit(cache=True, error_model="numpy")
def _apply(C, X, invW, out):
    """out = A X for the first-order form of a second-order system (top = rates / W)."""
    n = X.shape[0]
    r = C.shape[0]
    r0 = n - r
    for i in range(r0):
        for j in range(n):
            for p in range(LANES):
                out[i, j, p] = X[r0 + i, j, p] * invW[p]
    P = X.shape[2]  # a run-time trip count: the compiler vectorizes the lane loops
    for i in range(r):
        for j in range(n):
            o = out[r0 + i, j]
            c = C[i, 0]
            x = X[0, j]
            for p in range(P):
                o[p] = c[p] * x[p]
            for l in range(1, n):
                c = C[i, l]
                x = X[l, j]
                for p in range(P):
                    o[p] += c[p] * x[p]


@njit(cache=True, error_model="numpy")
def _axpy(X, a, K, out):
    n, _, P = X.shape
    for i in range(n):
        for j in range(n):
            for p in range(LANES):
                out[i, j, p] = X[i, j, p] + a * K[i, j, p]


@njit(cache=True, error_model="numpy")
def _rk4(B, G, cols, pw, dw, invW, N, stride, out):
    m = B.shape[0]
    r, n = B.shape[2], B.shape[3]
    P = pw.shape[1]
    h = 2.0 * math.pi / N
    C1 = np.empty((r, n, P))
    C2 = np.empty((r, n, P))
    C3 = np.empty((r, n, P))
    k1 = np.empty((n, n, P))
    k2 = np.empty((n, n, P))
    k3 = np.empty((n, n, P))
    k4 = np.empty((n, n, P))
    Y = np.empty((n, n, P))
    for i in range(n):
        for j in range(n):
            for p in range(LANES):
                out[i, j, p] = 1.0 if i == j else 0.0
    _coef(B, G, cols, pw, dw, 0, C1)
    for s in range(N):
        _coef(B, G, cols, pw, dw, ((2 * s + 1) * stride) % m, C2)
        _coef(B, G, cols, pw, dw, ((2 * s + 2) * stride) % m, C3)
        _apply(C1, out, invW, k1)
        _axpy(out, 0.5 * h, k1, Y)
        _apply(C2, Y, invW, k2)
        _axpy(out, 0.5 * h, k2, Y)
        _apply(C2, Y, invW, k3)
        _axpy(out, h, k3, Y)
        _apply(C3, Y, invW, k4)
        for i in range(n):
            for j in range(n):
                for p in range(LANES):
                    out[i, j, p] += (h / 6.0) * (k1[i, j, p] + 2.0 * (k2[i, j, p] + k3[i, j, p])
                                                 + k4[i, j, p])
        C1, C3 = C3, C1


@njit(cache=True, error_model="numpy")
def _block(B, G, cols, W, D, N, lo, out):
    """Points ``lo .. lo + LANES - 1`` (the last point repeated past the end) into ``out``."""
    n = B.shape[3]
    nb = cols.shape[0]
    npts = W.shape[0]
    P = LANES
    pw = np.empty((3, P))
    dw = np.empty((nb, P))
    invW = np.empty(P)
    for p in range(LANES):
        q = min(lo + p, npts - 1)
        invW[p] = 1.0 / W[q]
        pw[0, p] = invW[p]
        pw[1, p] = 1.0
        pw[2, p] = W[q]
        for b in range(nb):
            dw[b, p] = D[q, b] / W[q]
    P1 = np.empty((n, n, P))
    P2 = np.empty((n, n, P))
    _rk4(B, G, cols, pw, dw, invW, N, 2, P1)
    _rk4(B, G, cols, pw, dw, invW, 2 * N, 1, P2)
    for p in range(min(P, npts - lo)):
        for i in range(n):
            for j in range(n):
                out[lo + p, i, j] = P2[i, j, p] + (P2[i, j, p] - P1[i, j, p]) / 15.0


@njit(cache=True, error_model="numpy")
def monodromies(B, G, cols, W, D, N):
    """Monodromies (n_points, n, n) of points ``W[i]`` [rad/s], dampers ``D[i]``, one thread.

    ``B`` (nodes, 3, r, n): lower rows of ``A0, A1, A2`` on ``4 N`` azimuth
    nodes; ``G`` (nodes, n_blades, r): each damper's column (``cols``) per
    unit damping; ``N`` coarse steps per revolution.
    """
    n = B.shape[3]
    out = np.empty((W.shape[0], n, n))
    for k in range((W.shape[0] + LANES - 1) // LANES):
        _block(B, G, cols, W, D, N, k * LANES, out)
    return out


@njit(cache=True, error_model="numpy", parallel=True)
def monodromies_parallel(B, G, cols, W, D, N):
    """:func:`monodromies` with the blocks shared among numba's threads (same numbers)."""
    n = B.shape[3]
    out = np.empty((W.shape[0], n, n))
    for k in prange((W.shape[0] + LANES - 1) // LANES):
        _block(B, G, cols, W, D, N, k * LANES, out)
    return out
