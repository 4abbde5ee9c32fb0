"""Position-dependent channel losses (``bypass_groove``): s(y) = 1 - d exp(-((y - y_c)/w)^2).

Depth 0 is the base device exactly; with a rigid fluid at a fixed stroke the steady channel
law is the scaled quadratic law dp = s(y) (c1 Q + c2 Q|Q|); the analytic Jacobian and the
time derivative along the stroke (the groove's d ln s / dt term) match differences of the
right-hand side on every base with states; the stateless dashpot's force is s(y) c v,
whose first harmonic is the describing function; the compiled and scipy engines agree on
the full model's periodic orbit.
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.analysis.response.linear import linearize
from liquidamp.analysis.stability.damped_stability import device_lti
from liquidamp.coupled.assembly import Device
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import AsymmetricLoss, BypassGroove, with_effects
from liquidamp.device.models import REGISTRY, VISCOUS, ViscousParams, get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
STATEFUL = [n for n in REGISTRY if REGISTRY[n].n_states]


def _state(m, p, sgn=1.0):
    """A state off rest: a pressure difference and a channel flow of sign ``sgn``."""
    x = m.initial_state(p, 0.0).astype(float)
    sc = m.state_scales(p)
    if "p1" in m.state_names:
        i1, i2 = m.state_names.index("p1"), m.state_names.index("p2")
        x[i1], x[i2] = p.p0 + sgn * 2e4, p.p0 - sgn * 2e4
    for k in ("m12", "q12", "dp", "F"):
        if k in m.state_names:
            x[m.state_names.index(k)] = sgn * 0.3 * sc[m.state_names.index(k)]
    return x


@pytest.mark.parametrize("name", STATEFUL + ["dashpot", "viscous"])
def test_depth_zero_is_the_base_device_exactly(name):
    base = VISCOUS if name == "viscous" else get_model(name)
    m = with_effects(base, BypassGroove(0.0, 4e-4, 1e-3))
    p = ViscousParams(3e4, 2e5) if name == "viscous" else P
    x = _state(base, p) if base.n_states else np.zeros(0)
    u = (1.2e-3, 0.04, 2.0)
    assert np.array_equal(m.rhs(0.0, x, u, p), base.rhs(0.0, x, u, p))
    assert np.array_equal(m.jacobian(0.0, x, u, p), base.jacobian(0.0, x, u, p))
    assert np.array_equal(m.rhs_t(0.0, x, u, (0.04, 2.0), p),
                          base.rhs_t(0.0, x, u, (0.04, 2.0), p))
    assert m.force(0.0, x, u, p) == base.force(0.0, x, u, p)


def test_rigid_steady_flow_follows_the_scaled_quadratic_law():
    """Steady channel flow Q at a fixed stroke: the full model's momentum balance and the
    no-inertia model's flow law are at rest exactly at dp = s(y) (c1 Q + c2 Q|Q|)."""
    g = BypassGroove(0.4, 5e-4, 1.5e-3)
    y, Q = 1.1e-3, 2.0e-5
    s = 1 - 0.4 * math.exp(-((y - 5e-4) / 1.5e-3) ** 2)
    dp = s * (P.c1 * Q + P.c2 * Q * abs(Q))
    assert dp == pytest.approx((P.c1 * Q + P.c2 * Q * Q) * float(g.scale(y)), rel=1e-14)
    full = with_effects(get_model("full"), g)
    x = full.initial_state(P, y).astype(float)
    x[0], x[2], x[4] = P.p0 + dp / 2, P.p0 - dp / 2, P.rho_l * Q
    f = full.rhs(0.0, x, (y, 0.0, 0.0), P)
    assert abs(f[4]) < 1e-12 * dp / P.S_t          # the momentum balance is at rest
    x[0], x[2] = P.p0 + dp / 2 / s, P.p0 - dp / 2 / s   # the unscaled law is not
    assert full.rhs(0.0, x, (y, 0.0, 0.0), P)[4] == pytest.approx(dp * (1 / s - 1) / P.S_t,
                                                                   rel=1e-9)
    # no inertia: the flow follows dp; the chamber mass is steady where r1 A_p v = m
    ni = with_effects(get_model("no_inertia"), g)
    x = ni.initial_state(P, y).astype(float)
    x[0], x[2] = P.p0 + dp / 2, P.p0 - dp / 2
    v = P.rho_l * Q / (x[1] * P.A_p)
    assert abs(ni.rhs(0.0, x, (y, v, 0.0), P)[1]) < 1e-9 * P.rho_l * Q / P.V01
    # the dashpot: F = s(y) c_L v
    d = with_effects(get_model("dashpot"), g)
    assert d.force(0.0, np.zeros(0), (y, 0.02, 0.0), P) == pytest.approx(s * P.c_L * 0.02,
                                                                           rel=1e-14)
    # the groove sits on the absolute stroke: a model whose zero is 3 mm along the tube
    # sees it 3 mm nearer (as a record about a mean stroke of 3 mm does)
    shifted = with_effects(get_model("dashpot"), g.replace(stroke_offset_m=3e-3))
    assert shifted.force(0.0, np.zeros(0), (y - 3e-3, 0.02, 0.0), P) == pytest.approx(
        s * P.c_L * 0.02, rel=1e-12)


@pytest.mark.parametrize("name", STATEFUL)
def test_analytic_jacobian_and_stroke_derivative_match_differences(name):
    """At a stroke on the groove's edge (largest ds/dy), both flow directions, with a
    rebound ratio composed too."""
    m = with_effects(get_model(name), BypassGroove(0.6, 2e-4, 1e-3), AsymmetricLoss(1.7))
    assert m.analytic_jacobian
    p = preset("device_a")
    sc = m.state_scales(p)
    y, v, a = 2e-4 + 7e-4, 0.03, 40.0
    for sgn in (1.0, -1.0):
        x = _state(m, p, sgn)
        J = m.jacobian(0.0, x, (y, v, 0.0), p)
        for j in range(m.n_states):
            h = 1e-7 * sc[j]
            xp, xm = x.copy(), x.copy()
            xp[j] += h
            xm[j] -= h
            fd = (m.rhs(0.0, xp, (y, v, 0.0), p) - m.rhs(0.0, xm, (y, v, 0.0), p)) / (2 * h)
            np.testing.assert_allclose(J[:, j], fd, rtol=1e-5,
                                       atol=1e-6 * np.max(np.abs(fd)) + 1e-300)
        ft = m.rhs_t(0.0, x, (y, v, 0.0), (v, a), p)
        dt = 1e-8
        fd = (m.rhs(0.0, x, (y + dt * v, v + dt * a, 0.0), p)
              - m.rhs(0.0, x, (y - dt * v, v - dt * a, 0.0), p)) / (2 * dt)
        np.testing.assert_allclose(ft, fd, rtol=1e-5, atol=1e-6 * np.max(np.abs(fd)))
        # the groove's term is there: without it the derivative differs
        bare = with_effects(get_model(name), AsymmetricLoss(1.7))
        if m.base in ("full", "inertial", "inertial_2state", "maxwell"):
            assert not np.allclose(ft, bare.rhs_t(0.0, x, (y, v, 0.0), (v, a), p), rtol=1e-3)


def test_describing_function_is_the_first_harmonic_of_the_dashpot_law():
    F_HZ, Y = 2.0, 3e-3
    W = 2 * math.pi * F_HZ
    g = BypassGroove(0.5, 8e-4, 1.2e-3)
    m = with_effects(get_model("dashpot"), g)
    K = dynamic_stiffness(steady_state(m, P, HarmonicStroke(Y, F_HZ),
                                       options=SolverOptions(samples_per_period=4096))).value
    lti = device_lti(Device(m, P), amplitude=Y, frequency=F_HZ)
    assert lti.stiffness(F_HZ) == pytest.approx(K, rel=1e-9)
    assert abs(K.real) < 1e-9 * abs(K)            # no stiffness at any centre
    assert 0.6 * P.c_L < K.imag / W < 0.9 * P.c_L   # softer than the bare dashpot
    # viscous base with a quadratic loss: F = s(y) (c v + c2 v|v|)
    mv = with_effects(VISCOUS, g)
    vp = ViscousParams(4e4, 3e5)
    t = np.arange(8192) / (8192 * F_HZ)
    yv, vv = Y * np.sin(W * t), W * Y * np.cos(W * t)
    Fv = mv.force(t, np.zeros((0, t.size)), (yv, vv, 0 * t), vp)
    c_num = 2 * np.mean(Fv * np.cos(W * t)) / (W * Y)
    k, dc, b = g.describing_function(Y, W, vp, mv)
    assert vp.describing_damping(Y, W) + dc == pytest.approx(c_num, rel=1e-9)


def test_small_signal_at_rest_and_refusals():
    """At rest the groove is the constant scale s(0) on the losses: the linearization equals
    the bare model's with c1, c2 scaled; the equivalent linearization of a chamber model is
    refused naming the effect."""
    g = BypassGroove(0.3, 0.0, 2e-3)
    lin = linearize(with_effects(get_model("full"), g), P)
    ref = linearize(get_model("full"), P.replace(c1=0.7 * P.c1, c2=0.7 * P.c2))
    np.testing.assert_allclose(lin.A, ref.A, rtol=1e-12, atol=1e-12 * np.abs(ref.A).max())
    np.testing.assert_allclose(lin.B, ref.B, rtol=1e-6, atol=1e-9 * np.abs(ref.B).max())
    with pytest.raises(ParameterError, match="'bypass_groove' has no equivalent"):
        device_lti(Device(with_effects(get_model("full"), g), P), amplitude=2e-3,
                   frequency=3.0)
    with pytest.raises(ParameterError, match="beside asymmetric_loss"):
        device_lti(Device(with_effects(get_model("dashpot"), g, AsymmetricLoss(2.0)), P),
                   amplitude=2e-3, frequency=3.0)
    for bad, match in (({"depth": 1.0}, "depth must be in"),
                       ({"depth": -0.1}, "depth must be in"),
                       ({"half_width_m": 0.0}, "half_width_m")):
        with pytest.raises(ParameterError, match=match):
            BypassGroove(**{"depth": 0.2, **bad})
    with pytest.raises(ParameterError, match="has none"):
        with_effects(get_model("spring"), g)


def test_engines_agree_on_the_grooved_full_model():
    """The compiled stepper (analytic Jacobian and rhs_t with the groove's term) and scipy's
    Radau on the same periodic orbit; the groove softens the loop against the bare device."""
    m = with_effects(get_model("full"), BypassGroove(0.4, 0.0, 1.5e-3))
    S = HarmonicStroke(2.5e-3, 3.5)
    res = {e: steady_state(m, P, S, options=SolverOptions(engine=e, rtol=1e-8,
                                                          samples_per_period=256))
           for e in ("compiled", "scipy")}
    Fc, Fs = res["compiled"].force, res["scipy"].force
    assert np.max(np.abs(Fc - Fs)) < 1e-5 * np.max(np.abs(Fc))   # 9e-8 measured
    bare = steady_state(get_model("full"), P, S,
                        options=SolverOptions(engine="compiled", samples_per_period=256))
    Kg, Kb = dynamic_stiffness(res["compiled"]).value, dynamic_stiffness(bare).value
    assert Kg.imag < 0.9 * Kb.imag
