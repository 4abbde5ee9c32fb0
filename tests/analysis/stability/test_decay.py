"""Free-decay estimators: matrix pencil and moving block on signals with known poles."""

import math

import numpy as np
import pytest

from liquidamp.analysis.stability.decay import (
    dominant_mode,
    matrix_pencil,
    moving_block,
    pencil_damping,
)
from liquidamp.errors import ParameterError


def _floquet_like(t, sigma=0.4, w=7.5, W=26.0):
    """A Floquet mode: e^{-sigma t} times a 1/rev-modulated oscillation (harmonics w +- W)."""
    return np.exp(-sigma * t) * (np.cos(w * t) + 0.2 * np.cos((W - w) * t + 0.3)
                                 + 0.05 * np.sin((W + w) * t))


def test_matrix_pencil_recovers_every_pole_and_amplitude():
    dt = 2 * math.pi / 26.0 / 16
    t = np.arange(400) * dt
    s, a = matrix_pencil(_floquet_like(t), dt)
    want = np.array([-0.4 + 7.5j, -0.4 + 18.5j, -0.4 + 33.5j])
    for p in want:
        assert np.min(np.abs(s - p)) < 1e-8 and np.min(np.abs(s - p.conjugate())) < 1e-8
    assert s.size == 6
    assert dominant_mode(s) == pytest.approx(-0.4 + 7.5j, abs=1e-8)
    assert dominant_mode(s, near=19.0) == pytest.approx(-0.4 + 18.5j, abs=1e-8)
    k = np.argmin(np.abs(s - (-0.4 + 7.5j)))
    assert abs(a[k]) == pytest.approx(0.5, rel=1e-8)  # cos = (e^{iwt} + e^{-iwt}) / 2
    est = pencil_damping(_floquet_like(t), dt)
    assert est.damping_ratio == pytest.approx(0.4 / math.hypot(0.4, 7.5), rel=1e-8)
    assert est.exponent == pytest.approx(-0.4 + 7.5j, abs=1e-8)


def test_moving_block_on_a_modulated_decay():
    dt = 2 * math.pi / 26.0 / 16
    t = np.arange(1200) * dt
    est = moving_block(_floquet_like(t), dt)
    assert est.frequency == pytest.approx(7.5, rel=5e-3)
    assert est.sigma == pytest.approx(0.4, rel=5e-3)
    fixed = moving_block(_floquet_like(t), dt, frequency=7.5, block_cycles=6, stride=4)
    assert fixed.sigma == pytest.approx(0.4, rel=2e-3) and fixed.frequency == 7.5


def test_decay_estimators_refuse_what_they_cannot_do():
    with pytest.raises(ParameterError, match="at least 16 finite samples, got 5"):
        matrix_pencil(np.ones(5), 0.1)
    with pytest.raises(ParameterError, match="pencil parameter must lie in"):
        matrix_pencil(np.ones(40), 0.1, pencil=39)
    with pytest.raises(ParameterError, match="no oscillating pole"):
        pencil_damping(np.exp(-0.1 * np.arange(100)), 0.1)
    t = np.arange(100) * 0.01
    with pytest.raises(ParameterError, match="too short for blocks of 4 cycles"):
        moving_block(np.exp(-t) * np.cos(3 * t), 0.01, frequency=3.0)
    with pytest.raises(ParameterError, match="block_cycles must be an integer >= 2"):
        moving_block(np.cos(3 * t), 0.01, block_cycles=1)
