"""FourierStroke.fit solves the harmonic least squares of a long record (20 000 samples or
more) by normal equations from power sums where they are well conditioned, and by the SVD
otherwise (and on shorter records); both give the SVD's answer."""

import math

import numpy as np
import pytest

from liquidamp.structure.testmachine import (
    FourierStroke,
    _harmonic_normal_fit,
)


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


def test_a_rank_deficient_design_is_left_to_the_svd():
    """Aliased harmonics (the same column twice): the normal equations decline."""
    t = np.arange(40000) / 2000.0
    w = 2 * math.pi * 2.0 * t
    assert _harmonic_normal_fit(w, [1, 1, 2], np.sin(w)) is None


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
