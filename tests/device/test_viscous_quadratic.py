"""The viscous damper with a quadratic coefficient, F = c v + c2 v|v| (issue #13)."""

import math

import numpy as np
import pytest

from liquidamp.coupled.assembly import viscous
from liquidamp.device import kernels as K
from liquidamp.device.models import VISCOUS, ViscousParams
from liquidamp.errors import ParameterError


def test_force_and_packed_slot():
    p = ViscousParams(100.0, c2=2.0e3)
    spec, prm, ep = VISCOUS.packed(p)
    assert K.P_CV2 == 24 and K.N_PRM == 25  # the slot agreed between helpers
    assert prm[K.P_CV] == 100.0 and prm[K.P_CV2] == 2.0e3
    v = np.array([-0.3, -0.01, 0.0, 0.02, 0.5])
    F = VISCOUS.force(0.0, np.zeros((0, v.size)), (0 * v, v, 0 * v), p)
    assert np.allclose(F, 100.0 * v + 2.0e3 * v * np.abs(v), rtol=1e-15, atol=0)
    assert ViscousParams(1.0).c2 == 0.0  # the linear damper by default
    with pytest.raises(ParameterError, match="c2 must be >= 0"):
        ViscousParams(1.0, c2=-2.0)


def test_describing_function_against_the_first_harmonic():
    """8 c2 w Y / (3 pi): the first harmonic of c2 v|v| under y = Y sin(w t)."""
    p = ViscousParams(50.0, c2=4.0e3)
    Y, w = 2e-3, 2 * math.pi * 3.0
    t = np.arange(4096) / 4096 * (2 * math.pi / w)
    v = Y * w * np.cos(w * t)
    F = VISCOUS.force(t, np.zeros((0, t.size)), (0 * t, v, 0 * t), p)
    c_eq = 2 * np.mean(F * np.cos(w * t)) / (Y * w)
    assert c_eq == pytest.approx(p.describing_damping(Y, w), rel=1e-9)


def test_linear_models_of_the_quadratic_damper():
    """At rest c2 has no slope (small signal: c alone); at (Y, f) its describing function."""
    from liquidamp.analysis.stability.damped_stability import device_lti

    d = viscous(50.0, c2=4.0e3)
    small = device_lti(d)
    assert small.stiffness(2.0) == pytest.approx(2j * math.pi * 2.0 * 50.0)
    assert "no slope at rest" in small.kind
    eq = device_lti(d, amplitude=2e-3, frequency=3.0)
    c_eq = 50.0 + 8 * 4.0e3 * 2 * math.pi * 3.0 * 2e-3 / (3 * math.pi)
    assert eq.D[0, 1] == pytest.approx(c_eq, rel=1e-14)
    assert device_lti(viscous(50.0)).kind == "exact"


def test_compiled_rotor_has_the_quadratic_term():
    """The compiled rotor kernel runs the same base force as the scipy coupled route."""
    from liquidamp.coupled.assembly import rotor_system, simulate_coupled
    from liquidamp.coupled.fast_rotor import simulate_rotor
    from liquidamp.options import SolverOptions
    from liquidamp.structure.hostio import load_rotor

    rotor = load_rotor("hammond1974")
    W = 2 * math.pi * 260 / 60
    x0 = {"zeta_1": 0.02}
    opts = SolverOptions(method="DOP853", rtol=1e-9)
    dev = viscous(2e4, c2=5e6)
    a = simulate_rotor(rotor, W, dev, 0.3, x0, options=opts)
    b = simulate_coupled(rotor_system(rotor, W, dev), 0.3, x0, t_eval=a.time, options=opts,
                         strict=False, energy=False)
    lin = simulate_rotor(rotor, W, viscous(2e4), 0.3, x0, options=opts)
    scale = np.max(np.abs(b.host_states), axis=1, keepdims=True)
    assert np.max(np.abs(a.host_states - b.host_states) / scale) < 1e-8
    assert np.max(np.abs(a.host_states - lin.host_states) / scale) > 1e-3  # c2 acts
