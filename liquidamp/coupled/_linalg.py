"""Small dense linear algebra of the compiled steppers (numba): LU with partial pivoting.

Private module.  :func:`lu_factor` / :func:`lu_solve` for any n x n system (the rotor's
mass matrix, compositions with more than five states); :func:`lu5_factor` /
:func:`lu5_solve` for 5 x 5 with constant trip counts (every base model, smaller
systems padded with the identity).  Singular matrices are reported (False), never
divided by.

References
----------
.. [1] G. H. Golub, C. F. Van Loan, Matrix Computations, 4th ed., Johns Hopkins, 2013,
   Sec. 3.4 (Gaussian elimination with partial pivoting).
"""

from __future__ import annotations

import math

from numba import njit

from liquidamp._numba_cache import drop_stale

drop_stale(__file__)  # before any kernel of this module loads from the cache

__all__ = ["lu_factor", "lu_solve", "lu5_factor", "lu5_solve"]

#: Fast-math flags (reciprocal and contraction only, as the device kernels).
_FM = {"arcp", "contract"}


@njit(cache=True, error_model="numpy")
def lu_factor(A, piv):
    """In-place LU factorisation of ``A`` with partial pivoting ``piv``; False if singular."""
    n = A.shape[0]
    for k in range(n):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > amax:
                amax = abs(A[i, k])
                p = i
        piv[k] = p
        if amax == 0.0 or not math.isfinite(amax):
            return False
        if p != k:
            for j in range(n):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
        inv = 1.0 / A[k, k]
        for i in range(k + 1, n):
            A[i, k] *= inv
            f = A[i, k]
            if f != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= f * A[k, j]
    return True


@njit(cache=True, error_model="numpy")
def lu_solve(A, piv, b):
    """Solve with the factors of :func:`_lu`, overwriting ``b``."""
    n = A.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(n):
        s = b[i]
        for j in range(i):
            s -= A[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= A[i, j] * b[j]
        b[i] = s / A[i, i]


@njit(cache=True, error_model="numpy", fastmath=_FM, inline="always")
def lu5_factor(A, piv, dinv):
    """:func:`_lu` for a 5 x 5 matrix (constant trip counts); ``dinv`` = 1/diag(U)."""
    for k in range(5):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, 5):
            if abs(A[i, k]) > amax:
                amax = abs(A[i, k])
                p = i
        piv[k] = p
        if amax == 0.0 or not math.isfinite(amax):
            return False
        if p != k:
            for j in range(5):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
        inv = 1.0 / A[k, k]
        dinv[k] = inv
        for i in range(k + 1, 5):
            f = A[i, k] * inv
            A[i, k] = f
            for j in range(k + 1, 5):
                A[i, j] -= f * A[k, j]
    return True


@njit(cache=True, error_model="numpy", fastmath=_FM, inline="always")
def lu5_solve(A, piv, dinv, b):
    """:func:`_solve` with the factors of :func:`_lu5`."""
    for k in range(5):
        p = piv[k]
        tmp = b[k]
        b[k] = b[p]
        b[p] = tmp
    for i in range(1, 5):
        s = b[i]
        for j in range(i):
            s -= A[i, j] * b[j]
        b[i] = s
    for i in range(4, -1, -1):
        s = b[i]
        for j in range(i + 1, 5):
            s -= A[i, j] * b[j]
        b[i] = s * dinv[i]
