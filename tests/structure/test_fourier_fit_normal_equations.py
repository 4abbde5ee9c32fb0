"""FourierStroke.fit solves its harmonic least squares by the scaled normal equations where
they are well conditioned (a long record: whole cycles, orthogonal columns) and by the SVD
otherwise; both give the SVD's answer."""

import math

import numpy as np
import pytest

from liquidamp.structure.testmachine import (
    FourierStroke,
    _harmonic_lstsq,
    _harmonic_normal_fit,
)


def _design(t, f, K):
    w = 2 * math.pi * f * t
    return np.column_stack([np.ones_like(t)] + [g(k * w) for k in range(1, K + 1)
                                               for g in (np.sin, np.cos)])


def test_normal_equations_match_the_svd_on_a_long_record():
    rng = np.random.default_rng(3)
    t = np.arange(6000) / 3000.0
    A = _design(t, 2.0 + 1e-4, 40)  # a fundamental a little off whole cycles
    y = A @ rng.normal(size=A.shape[1]) + rng.normal(0.0, 0.1, t.size)
    c, rank = _harmonic_lstsq(A, y)
    ref, _, rank_ref, _ = np.linalg.lstsq(A, y, rcond=None)
    assert rank == rank_ref == A.shape[1]
    np.testing.assert_allclose(c, ref, rtol=0.0, atol=1e-10 * np.max(np.abs(ref)))


def test_power_sum_normal_equations_match_the_svd():
    """The Gram matrix from power sums of exp(i w) and the explicit residual: the SVD's
    coefficients and sum of squares, for a subset of harmonics and for a short record
    (None: too few samples for the normal equations)."""
    rng = np.random.default_rng(4)
    t = np.arange(9000) / 3000.0
    w = 2 * math.pi * (2.0 + 3e-4) * t
    ks = [1, 2, 5, 9]
    A = np.column_stack([np.ones_like(t)] + [g(k * w) for k in ks for g in (np.sin, np.cos)])
    y = A @ rng.normal(size=A.shape[1]) * 1e-3 + rng.normal(0.0, 1e-6, t.size)
    c, rss, rank = _harmonic_normal_fit(w, ks, y)
    ref, res, rank_ref, _ = np.linalg.lstsq(A, y, rcond=None)
    assert rank == rank_ref == A.shape[1]
    np.testing.assert_allclose(c, ref, rtol=0.0, atol=1e-9 * np.max(np.abs(ref)))
    assert rss == pytest.approx(float(res[0]), rel=1e-6)
    assert _harmonic_normal_fit(w[:30], ks, y[:30]) is None


def test_a_rank_deficient_design_falls_back_to_the_svd():
    t = np.arange(4000) / 2000.0
    A = _design(t, 2.0, 3)
    A = np.column_stack([A, A[:, 1]])  # a repeated column: singular normal equations
    y = A[:, 1] * 0.003
    c, rank = _harmonic_lstsq(A, y)
    assert rank == A.shape[1] - 1  # the SVD's rank, not the column count
    np.testing.assert_allclose(A @ c, y, atol=1e-12)


def test_fit_of_a_3khz_record_finds_its_harmonics():
    rng = np.random.default_rng(5)
    t = np.arange(30000) / 3000.0
    y = (0.003 * np.sin(2 * np.pi * 2.0 * t) + 2e-5 * np.cos(2 * np.pi * 6.0 * t)
         + rng.normal(0.0, 2e-6, t.size))
    s = FourierStroke.fit(t, y, 2.0)
    assert s.harmonics == 3
    assert abs(s.sine[0] / 0.003 - 1) < 1e-4
    assert abs(s.cosine[2] / 2e-5 - 1) < 0.02
    assert abs(s.sine[1]) < 1e-7 and abs(s.cosine[1]) < 1e-7
