"""Digressive valves per direction (issue #20 item 4): a knee in compression, another in rebound.

* Rigid-fluid limit (the dashpot-type bases): the two-slope force-velocity closed form per
  direction, F = c v below v_d = p_d A / c, p_d A + c_d (|v| - v_d) above, exactly; issue
  #20's damper (2.2 / 1.1 kN s/m about 25 mm/s in compression, 1.2 / 1.0 in rebound).
* The describing function (half a cycle per valve) against the time-domain first harmonic.
* On the chamber models: mass conserved on both engines, each direction's pressure
  difference held near its own cracking pressure, and the stiff-liquid laminar models tend
  to the dashpot's law; equal pairs are the relief valve exactly; Jacobians against
  differences.
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.analysis.stability.damped_stability import device_lti
from liquidamp.coupled.assembly import Device
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import (
    AsymmetricLoss,
    DigressiveValve,
    ReliefValve,
    saturation_damping,
    with_effects,
)
from liquidamp.device.models import VISCOUS, ViscousParams, get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
OPTS = SolverOptions(engine="compiled", rtol=1e-10, samples_per_period=4096)


def _two_slopes(v, c, v_d, c_d):
    a = np.abs(v)
    return np.sign(v) * np.where(a <= v_d, c * a, c * v_d + c_d * (a - v_d))


def test_two_slope_closed_form_per_direction_on_the_dashpot_types():
    v = np.linspace(-0.2, 0.2, 401)
    # issue #20's vehicle damper as a viscous damper: the rebound bleed 1.2 kN s/m through
    # asymmetric_loss (rebound ratio 1.2 / 2.2)
    d = DigressiveValve.from_knees(2200.0, 0.025, 1100.0, 1200.0, 0.025, 1000.0)
    m = with_effects(VISCOUS, d, AsymmetricLoss(1200.0 / 2200.0))
    F = m.force(0.0, np.zeros((0, v.size)), (0 * v, v, 0 * v), ViscousParams(2200.0))
    expected = np.where(v >= 0, _two_slopes(v, 2200.0, 0.025, 1100.0),
                        _two_slopes(v, 1200.0, 0.025, 1000.0))
    np.testing.assert_allclose(F, expected, rtol=1e-13, atol=1e-10)
    # the dashpot with the paper device's piston area: knees at 10 and 30 mm/s
    c, A = P.c_L, P.A_p
    dd = DigressiveValve.from_knees(c, 0.01, 0.5 * c, c, 0.03, 0.25 * c, area_m2=A)
    md = with_effects(get_model("dashpot"), dd)
    Fd = md.force(0.0, np.zeros((0, v.size)), (0 * v, v, 0 * v), P)
    expected = np.where(v >= 0, _two_slopes(v, c, 0.01, 0.5 * c), _two_slopes(v, c, 0.03,
                                                                              0.25 * c))
    np.testing.assert_allclose(Fd, expected, rtol=1e-12, atol=1e-9 * np.max(np.abs(Fd)))
    # each knee where its own direction puts it
    slopes = np.diff(Fd) / np.diff(v)
    assert slopes[np.argmin(np.abs(v[1:] - 0.02))] == pytest.approx(0.5 * c, rel=1e-9)
    assert slopes[np.argmin(np.abs(v[1:] + 0.02))] == pytest.approx(c, rel=1e-9)


@pytest.mark.parametrize("engine", ["scipy", "compiled"])
def test_describing_function_equals_the_time_domain_first_harmonic(engine):
    f, Y = 3.0, 0.002
    w = 2 * math.pi * f
    V = w * Y
    c, A = P.c_L, P.A_p
    dd = DigressiveValve.from_knees(c, 0.4 * V, 0.4 * c, c, 0.7 * V, 0.6 * c, area_m2=A)
    m = with_effects(get_model("dashpot"), dd)
    K = dynamic_stiffness(steady_state(m, P, HarmonicStroke(Y, f),
                                       options=OPTS.replace(engine=engine))).value
    c_eq = 0.5 * (saturation_damping(c, 0.4 * c, 0.4 * V * c, V)
                  + saturation_damping(c, 0.6 * c, 0.7 * V * c, V))
    assert abs(K.real) < 1e-9 * abs(K)
    assert K.imag / w == pytest.approx(c_eq, rel=1e-6)
    lti = device_lti(Device(m, P), amplitude=Y, frequency=f)
    assert lti.stiffness(f) == pytest.approx(1j * w * c_eq, rel=1e-12)
    assert c_eq < 0.9 * c


def test_chamber_models_conserve_mass_and_each_direction_has_its_knee():
    r0 = steady_state("full", P, HarmonicStroke(0.003, 3.0), options=OPTS)
    peak = float(np.max(np.abs(r0.p1 - r0.p2)))
    p_c, p_r = 0.3 * peak, 0.6 * peak
    m = with_effects(get_model("full"), DigressiveValve(p_c, 1e-9, p_r, 1e-9))
    dps = []
    for engine in ("scipy", "compiled"):
        r = steady_state(m, P, HarmonicStroke(0.003, 3.0),
                         options=OPTS.replace(engine=engine, samples_per_period=256, rtol=1e-9))
        assert r.mass_error < 1e-9
        dp = r.p1 - r.p2
        dps.append((float(dp.max()), float(-dp.min())))
        assert p_c < dp.max() < 1.25 * p_c   # compression held near its cracking pressure
        assert p_r < -dp.min() < 1.25 * p_r  # rebound near its own
    assert dps[0] == pytest.approx(dps[1], rel=1e-5)
    # the same valve both ways is the relief valve, exactly
    same = with_effects(get_model("full"), DigressiveValve(p_c, 1e-9, p_c, 1e-9))
    relief = with_effects(get_model("full"), ReliefValve(p_c, 1e-9))
    x = m.initial_state(P, 0.0).astype(float)
    x[0], x[2], x[4] = 3e6, 1e5, 2e-3
    for xs in (x, x[[2, 1, 0, 3, 4]] * np.array([1, 1, 1, 1, -1])):
        np.testing.assert_array_equal(same.rhs(0.0, xs, (1e-3, 0.02), P),
                                      relief.rhs(0.0, xs, (1e-3, 0.02), P))


def test_stiff_laminar_chamber_models_tend_to_the_dashpot_law():
    S = HarmonicStroke(0.003, 0.5)
    stiff = P.replace(inv_gamma1=0.0, inv_gamma2=0.0, c2=0.0)  # liquid only, laminar loss
    V = S.amplitude * S.omega
    c, A = stiff.c_L, stiff.A_p
    dv = DigressiveValve.from_knees(c, 0.3 * V, 0.5 * c, c, 0.6 * V, 0.3 * c, area_m2=A)
    K = {n: dynamic_stiffness(steady_state(with_effects(get_model(n), dv), stiff, S,
                                           options=OPTS.replace(samples_per_period=512))).value
         for n in ("dashpot", "constant_bulk")}
    for n in ("constant_bulk",):
        assert abs(K[n] - K["dashpot"]) < 2 * S.omega * stiff.T_D * abs(K["dashpot"]), n
    assert abs(K["dashpot"]) < 0.8 * c * S.omega


@pytest.mark.parametrize("name", ["single_state", "maxwell", "full"])
def test_jacobian_matches_differences_in_both_directions(name):
    m = with_effects(get_model(name), DigressiveValve(2e5, 3e-10, 5e5, 1e-10))
    p = preset("device_a")
    sc = m.state_scales(p)
    for sgn in (1.0, -1.0):
        x = m.initial_state(p, 0.0).astype(float)
        if "p1" in m.state_names:
            x[0], x[2] = p.p0 + sgn * 8e5, p.p0 - sgn * 8e5
        if name == "single_state":
            x[0] = sgn * 1.2e6
        if name == "maxwell":
            x[0] = sgn * 1.2e6 * p.A_p
        u = (0.001, 0.02 * sgn, 0.0)
        J = m.jacobian(0.0, x, u, p)
        for j in range(m.n_states):
            h = 1e-6 * max(abs(x[j]), sc[j])
            xp, xm = x.copy(), x.copy()
            xp[j] += h
            xm[j] -= h
            fd = (m.rhs(0.0, xp, u, p) - m.rhs(0.0, xm, u, p)) / (2 * h)
            np.testing.assert_allclose(J[:, j], fd, rtol=1e-4,
                                       atol=1e-6 * np.max(np.abs(fd)) + 1e-300)


def test_errors():
    with pytest.raises(ParameterError, match="cannot be composed with 'relief_valve'"):
        with_effects(get_model("full"), DigressiveValve(), ReliefValve())
    with pytest.raises(ParameterError, match="rebound_cracking_Pa must be >= 0"):
        DigressiveValve(1e6, 0.0, -1.0)
    with pytest.raises(ParameterError, match="high-speed damping must be <="):
        DigressiveValve.from_knees(1e3, 0.01, 2e3, 1e3, 0.01, 5e2)
    with pytest.raises(ParameterError, match="needs a flow path"):
        with_effects(get_model("spring"), DigressiveValve())
    m = with_effects(get_model("full"), DigressiveValve(1e5, 1e-9, 2e5, 1e-9))
    with pytest.raises(ParameterError, match="effect 'digressive_valve' has no equivalent"):
        device_lti(Device(m, P), amplitude=1e-3, frequency=3.0)
    bare = device_lti(Device("full", P)).stiffness(3.0)
    assert device_lti(Device(m, P)).stiffness(3.0) == pytest.approx(bare, rel=1e-5)
    with pytest.raises(ParameterError, match=r"c2 = 3.0 N s\^2/m\^2 must be 0"):
        with_effects(VISCOUS, DigressiveValve()).packed(ViscousParams(1e4, c2=3.0))
