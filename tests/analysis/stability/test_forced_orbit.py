"""Forced periodic orbits: the coupled Jacobian, the compiled variational equations, the
invariants held by the shooting, and the period rules."""

import math

import numpy as np
import pytest

from liquidamp.analysis.response.periodic import invariants
from liquidamp.analysis.stability.forced_orbit import (
    coupled_jacobian,
    floquet_mode,
    forced_orbit,
    orbit_period,
)
from liquidamp.analysis.stability.sizing import scale_device
from liquidamp.coupled.assembly import Device, blade_system, rotor_system, viscous
from liquidamp.coupled.fast_rotor import second_order_flow
from liquidamp.coupled.inputs import HarmonicInput
from liquidamp.device import preset
from liquidamp.device.effects import SeriesCompliance, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError
from liquidamp.structure.hostio import load_blade, load_rotor, load_section

BLADE = load_blade("hammond1974").replace(lag_damping=0.0)
W = 2.0 * math.pi * 4.2


def _state(system):
    """A moving state off rest: stroke 2 mm, rate 0.05 m/s, chambers swung."""
    x = system.initial_state({"zeta": 0.008, "zeta_dot": 0.2})
    z = system.device_slice(0)
    x[z] = x[z] * (1.0 + 0.01 * np.arange(1, x[z].size + 1) / x[z].size)
    return x


@pytest.mark.parametrize("model", ["full", "compliance"])
def test_coupled_jacobian_equals_differences_of_the_coupled_rhs(model):
    """Host A + B_F dF/dx and the device rows: central differences of system.rhs (an
    independent route through the Python right-hand side)."""
    m = get_model("full") if model == "full" else with_effects(get_model("full"),
                                                               SeriesCompliance(5e6))
    sys_ = blade_system(BLADE, W, Device(m, preset("paper_calibrated")),
                        inputs=[HarmonicInput("moment", W, 0.0, 900.0)])
    x = _state(sys_)
    J = coupled_jacobian(sys_, 0.13, x)
    scale = np.maximum(np.abs(x), 1e-3)
    for k in range(x.size):
        h = 1e-6 * scale[k]
        e = np.zeros_like(x)
        e[k] = h
        col = (sys_.rhs(0.13, x + e) - sys_.rhs(0.13, x - e)) / (2 * h)
        assert np.allclose(J[:, k], col, rtol=1e-5, atol=1e-6 * np.max(np.abs(col)) + 1e-12)


def test_compiled_variational_equations_match_the_python_route_on_the_rotor():
    """One period of Phi' = J Phi from a moving state of the rotor with devices on three
    blades and a failed one (periodic host): kernel against solve_ivp on coupled_jacobian."""
    from liquidamp.analysis.stability import forced_orbit as fo
    from liquidamp.options import SolverOptions

    rotor = load_rotor("hammond1974")
    dev = Device("full", scale_device(preset("damper"), 2.0))
    sys_ = rotor_system(rotor, W, {2: dev, 3: dev, 4: viscous(3e4)}, inoperative=[1])
    x = sys_.initial_state({"zeta_1": 0.01, "zeta_dot_2": 0.1, "hub_x": 1e-3})
    T = 2 * math.pi / W
    S = fo._scales(sys_, np.abs(x) + 1e-3, W)
    opts = SolverOptions(method="DOP853", rtol=1e-10, atol_scale=1e-12)
    r = second_order_flow(sys_, x, T, monodromy=True, scales=S, options=opts)
    xT, Phi, _ = fo._flow(sys_, x, T, S, opts, compiled=False)
    assert np.max(np.abs(r.x_end - xT) / S) < 1e-9
    ratio = S[None, :] / S[:, None]
    assert np.max(np.abs((r.monodromy - Phi) * ratio)) < 1e-7
    assert np.max(np.abs(Phi * ratio)) > 0.5


def test_orbit_holds_the_device_invariants_and_is_periodic():
    dev = Device("full", scale_device(preset("reference"), 2.0))
    sys_ = blade_system(BLADE, W, dev, inputs=[HarmonicInput("moment", W, 400.0, 1500.0)])
    orb = forced_orbit(sys_)
    z = sys_.device_slice(0)
    rest = sys_.initial_state()
    v0, _ = invariants(dev.model, dev.params, rest[z], 0.0)
    y = float(sys_.stroke_matrix[0] @ orb.x0[:2])
    v1, _ = invariants(dev.model, dev.params, orb.x0[z], y)
    assert np.allclose(v1, v0, rtol=1e-12, atol=0)
    r = second_order_flow(sys_, orb.x0, orb.period)
    assert np.max(np.abs(r.x_end - orb.x0) / orb.scales) < 1e-8
    assert orb.states.shape == (sys_.n_states, 64) and np.allclose(orb.states[:, 0], orb.x0)
    # the 1/rev moment has a cosine part: the stroke's first harmonic is not a pure sine
    c = orb.first_harmonic(orb.strokes()[0])
    assert abs(c.real) > 0.05 * abs(c)
    m = floquet_mode(orb, ["zeta", "zeta_dot"])
    assert abs(m.vector[0]) == pytest.approx(1.0, rel=1e-12) or abs(m.vector[1]) == 1.0


def test_period_rules_and_refusals():
    sys_ = blade_system(BLADE, W, viscous(1e4))
    with pytest.raises(ParameterError, match="no harmonic input and constant coefficients"):
        orbit_period(sys_)
    assert orbit_period(sys_, 0.5) == 0.5
    two = sys_.with_inputs([HarmonicInput("moment", 2 * W, 1.0)])
    assert orbit_period(two) == pytest.approx(math.pi / W, rel=1e-15)
    bad = sys_.with_inputs([HarmonicInput("moment", 1.5 * W, 1.0)])
    rotor = rotor_system(load_rotor("hammond1974"), W, viscous(1e4), inputs=[
        HarmonicInput("moment_1", W, 1.0), HarmonicInput("moment_2", 2.5 * W, 1.0)])
    with pytest.raises(ParameterError, match="not integer multiples"):
        orbit_period(rotor)
    rotor_bad = rotor_system(load_rotor("hammond1974"), W, viscous(1e4),
                             inputs=[HarmonicInput("moment_1", 0.7 * W, 1.0)])
    with pytest.raises(ParameterError, match="host's period .* is not a multiple"):
        orbit_period(rotor_bad)
    assert orbit_period(bad) == pytest.approx(2 * math.pi / (1.5 * W), rel=1e-15)
    from liquidamp.coupled.assembly import section_system

    sec = section_system(load_section("hodges-pierce"), 5.0, {"pitch": viscous(10.0)})
    with pytest.raises(ParameterError, match=r"forced_orbit: pass options with "
                                             r"engine='scipy'"):
        forced_orbit(sec, period=1.0)
    inert = blade_system(BLADE, W, Device("inerter", preset("inerter")))
    with pytest.raises(ParameterError, match="uses the stroke acceleration"):
        forced_orbit(inert, period=1.0)
    with pytest.raises(ParameterError, match="tol must lie in"):
        forced_orbit(sys_, period=1.0, tol=0.5)
