"""The DOP853 tableau written out in liquidamp.coupled._dop853 (Hairer, Norsett, Wanner)."""

from __future__ import annotations

import math

import numpy as np

from liquidamp.coupled._dop853 import A_EXTRA, C_EXTRA, E3, E5, N_STAGES, A, B, C, D


def test_row_sums_and_quadrature_conditions_up_to_order_8():
    """sum_j a_ij = c_i; sum_i b_i c_i^(k-1) = 1/k for k = 1..8 (order-8 quadrature)."""
    assert A.shape == (N_STAGES, N_STAGES) and not np.any(np.triu(A))
    assert np.allclose(A.sum(axis=1), C, rtol=0, atol=1e-14)
    assert np.allclose(A_EXTRA.sum(axis=1), C_EXTRA, rtol=0, atol=1e-14)
    for k in range(1, 9):
        assert abs(B @ C ** (k - 1) - 1.0 / k) < 1e-14, k
    # a 9th-order condition fails: the method is of order 8, not more
    assert abs(B @ C**8 - 1.0 / 9) > 1e-6
    # the error estimators are differences of weights of consistent formulas
    assert abs(E5.sum()) < 1e-14 and abs(E3[:N_STAGES].sum() + E3[N_STAGES]) < 1e-14


def _step(f, y, h):
    """One DOP853 step of y' = f(y) (12 stages); the error estimates as the kernel's."""
    k = np.zeros((N_STAGES + 1,) + np.shape(y))
    for i in range(N_STAGES):
        k[i] = f(y + h * (A[i, :i] @ k[:i]))
    y1 = y + h * (B @ k[:N_STAGES])
    k[N_STAGES] = f(y1)
    return y1, h * (E5 @ k), h * (E3 @ k)


def test_one_step_of_y_prime_equals_y_against_exp():
    """y' = y: the local error of a step h is about h^9/9! times the first lost term."""
    for h in (0.2, 0.1):
        y1, e5, _ = _step(lambda y: y, 1.0, h)
        err = abs(y1 - math.exp(h))
        assert err < 3e-3 * h**9 and abs(e5) < 1e-4
    y_a, _, _ = _step(lambda y: y, 1.0, 0.4)
    y_b, _, _ = _step(lambda y: y, 1.0, 0.2)
    order = math.log2(abs(y_a - math.exp(0.4)) / abs(y_b - math.exp(0.2)))
    assert 8.5 < order < 9.5  # local error O(h^9)


def test_harmonic_oscillator_over_one_period():
    """x'' = -x from (1, 0) over 2 pi in 64 steps: back to (1, 0) to 1e-10."""
    M = np.array([[0.0, 1.0], [-1.0, 0.0]])
    y, h = np.array([1.0, 0.0]), 2 * math.pi / 64
    for _ in range(64):
        y, _, _ = _step(lambda z: M @ z, y, h)
    assert np.allclose(y, [1.0, 0.0], rtol=0, atol=1e-10)


def test_dense_output_shape():
    assert D.shape == (4, N_STAGES + 4) and A_EXTRA.shape == (3, N_STAGES + 4)
