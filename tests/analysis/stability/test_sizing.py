"""Device sizing: the parallel-copy scaling rule, lag and flutter dampers, Maxwell twin."""

import math

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.analysis.stability.sizing import (
    lag_damper_device,
    maxwell_equivalent,
    nominal_speed,
    scale_device,
    size_flutter_damper,
    size_lag_damper,
)
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.hostio import load_rotor, load_section
from liquidamp.structure.testmachine import HarmonicStroke

ROTOR = load_rotor("hammond1974")


def test_parallel_copies_scale_the_nonlinear_force_exactly():
    """Full model, 3 mm at 3 Hz: K*(s copies) = s K* to solver tolerance."""
    p = preset("reference")
    s = 7.3
    opts = SolverOptions(rtol=1e-9)
    stroke = HarmonicStroke(0.003, 3.0)
    k1 = dynamic_stiffness(steady_state("full", p, stroke, options=opts)).value
    ks = dynamic_stiffness(steady_state("full", scale_device(p, s), stroke, options=opts)).value
    assert abs(ks / (s * k1) - 1) < 1e-5


def test_lag_damper_sizing_hits_target_and_scales():
    sz = size_lag_damper(preset("reference"), ROTOR)
    assert sz.target_damping == pytest.approx(4067.5 / 0.25**2)
    assert sz.achieved_damping == pytest.approx(sz.target_damping, rel=1e-9)
    W = nominal_speed(ROTOR)
    assert W == pytest.approx(250 * math.pi / 30)
    assert sz.frequency_hz == pytest.approx(ROTOR.blade.lag_frequency(W) / (2 * math.pi))
    assert sz.scale == pytest.approx(31.73, rel=1e-3)
    assert sz.params.stroke_limit == pytest.approx(preset("reference").stroke_limit)
    assert sz.params.k_D == pytest.approx(sz.scale * preset("reference").k_D, rel=1e-12)


def test_larger_sizing_amplitude_needs_smaller_device():
    a = size_lag_damper(preset("reference"), ROTOR, amplitude=1e-4).scale
    b = size_lag_damper(preset("reference"), ROTOR, amplitude=1e-3).scale
    assert b < 0.8 * a  # the quadratic loss adds damping with amplitude


def test_maxwell_twin_same_stiffness_same_damping():
    sz = size_lag_damper(preset("reference"), ROTOR)
    q = maxwell_equivalent(sz.params, sz.target_damping, sz.frequency_hz)
    w = 2 * math.pi * sz.frequency_hz
    assert q.k_D == pytest.approx(sz.params.k_D)
    assert q.k_D * q.T_D / (1 + (w * q.T_D) ** 2) == pytest.approx(sz.target_damping)
    with pytest.raises(ParameterError, match="gives at most"):
        maxwell_equivalent(preset("reference"), 1e6, 1.0)


def test_flutter_damper_sizing():
    s = load_section("hodges-pierce")
    sz = size_flutter_damper(preset("reference"), s, zeta=0.1)
    wF = 2 * math.pi * sz.frequency_hz
    assert sz.target_damping == pytest.approx(2 * 0.1 * s.mass * s.span * wF)
    assert sz.achieved_damping == pytest.approx(sz.target_damping, rel=1e-9)
    pitch = size_flutter_damper(preset("reference"), s, port="pitch", zeta=0.1)
    assert pitch.target_damping == pytest.approx(2 * 0.1 * s.inertia / s.pitch_arm**2 * wF)
    with pytest.raises(ParameterError, match="unknown port"):
        size_flutter_damper(preset("reference"), s, port="flap")


def test_lag_damper_device_names():
    d, r, sz = lag_damper_device("viscous", ROTOR, arm=0.5)
    assert d.params.c == pytest.approx(4067.5 / 0.25)
    assert r.blade.damper_arm == 0.5
    d, _, sz = lag_damper_device("device_b", ROTOR)
    assert d.model.name == "full" and sz.scale > 1
    d, _, _ = lag_damper_device("maxwell", ROTOR)
    assert d.model.name == "maxwell"
    with pytest.raises(ParameterError, match="unknown damper 'oil'"):
        lag_damper_device("oil", ROTOR)
    assert np.isfinite(sz.storage_stiffness)
