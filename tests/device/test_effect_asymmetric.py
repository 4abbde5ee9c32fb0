"""Direction-dependent losses (issue #12 item 3): rebound unlike compression.

On the stateless bases F = c v in compression, r c v in rebound: under v = V cos(w t)
the first harmonic's damping is the average c (1 + r) / 2, the compression half cycle
dissipates c V^2 T / 4 and the rebound half r times that.  On the chamber models the
ratio scales the channel's loss coefficients by the flow's direction; the analytic
Jacobian (piecewise constant ratio) must match differences of the right-hand side, and
a stiff liquid with a laminar loss tends to the dashpot's law.
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness, first_harmonic
from liquidamp.analysis.response.linear import linearize
from liquidamp.analysis.stability.damped_stability import device_lti
from liquidamp.coupled.assembly import Device
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import AsymmetricLoss, ReliefValve, with_effects
from liquidamp.device.models import REGISTRY, VISCOUS, ViscousParams, get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
OPTS = SolverOptions(engine="compiled", rtol=1e-10, samples_per_period=4096)
F_HZ, Y = 3.0, 0.002
W = 2 * math.pi * F_HZ


@pytest.mark.parametrize("r", [0.4, 2.5])
def test_first_harmonic_is_the_average_and_the_energy_splits_by_the_ratio(r):
    m = with_effects(get_model("dashpot"), AsymmetricLoss(r))
    res = steady_state(m, P, HarmonicStroke(Y, F_HZ), options=OPTS)
    K = dynamic_stiffness(res).value
    c = P.c_L
    assert K.imag / W == pytest.approx(c * (1 + r) / 2, rel=1e-9)
    assert abs(K.real) < 1e-9 * abs(K)
    V, T = W * Y, 1 / F_HZ
    power = res.force * res.stroke_rate * T / res.time.size
    comp, reb = power[res.stroke_rate > 0].sum(), power[res.stroke_rate < 0].sum()
    assert comp == pytest.approx(c * V**2 * T / 4, rel=1e-6)
    assert reb == pytest.approx(r * c * V**2 * T / 4, rel=1e-6)
    lti = device_lti(Device(m, P), amplitude=Y, frequency=F_HZ)
    assert lti.stiffness(F_HZ) == pytest.approx(K, rel=1e-9)
    # viscous base: the model's force over one period
    mv = with_effects(VISCOUS, AsymmetricLoss(r))
    t = np.arange(4096) / (4096 * F_HZ)
    Fv = mv.force(t, np.zeros((0, t.size)), (Y * np.sin(W * t), V * np.cos(W * t), 0 * t),
                  ViscousParams(5e4))
    assert (first_harmonic(t, Fv, F_HZ) / (1j * V)).real == pytest.approx(5e4 * (1 + r) / 2,
                                                                           rel=1e-9)


def test_relief_on_an_asymmetric_dashpot_describing_function():
    """The two describing functions add up to the combined law's first harmonic: each half
    cycle saturates its own dashpot (c in compression, r c in rebound)."""
    r, V = 2.0, W * Y
    m = with_effects(get_model("dashpot"), AsymmetricLoss(r),
                     ReliefValve(0.6 * P.c_L * V / P.A_p, 1.0 / P.c1))
    K = dynamic_stiffness(steady_state(m, P, HarmonicStroke(Y, F_HZ), options=OPTS)).value
    lti = device_lti(Device(m, P), amplitude=Y, frequency=F_HZ)
    assert lti.stiffness(F_HZ) == pytest.approx(K, rel=1e-6)
    bare_asym = P.c_L * (1 + r) / 2
    assert K.imag / W < 0.9 * bare_asym  # the valve opens in both directions


@pytest.mark.parametrize("name", [n for n in REGISTRY if REGISTRY[n].n_states])
def test_analytic_jacobian_matches_differences_in_both_directions(name):
    m = with_effects(get_model(name), AsymmetricLoss(3.0))
    assert m.analytic_jacobian
    p = preset("device_a")
    x0 = m.initial_state(p, 0.0).astype(float)
    sc = m.state_scales(p)
    u = (0.002, 0.03, 1.0)
    for sgn in (1.0, -1.0):  # flow (and pressure difference) in compression, then rebound
        x = x0.copy()
        if "p1" in m.state_names:
            i1, i2 = m.state_names.index("p1"), m.state_names.index("p2")
            x[i1], x[i2] = p.p0 + sgn * 2e4, p.p0 - sgn * 2e4
        for k in ("m12", "q12", "dp", "F"):
            if k in m.state_names:
                x[m.state_names.index(k)] = sgn * 0.3 * sc[m.state_names.index(k)]
        J = m.jacobian(0.0, x, u, p)
        for j in range(m.n_states):
            h = 1e-7 * sc[j]
            xp, xm = x.copy(), x.copy()
            xp[j] += h
            xm[j] -= h
            fd = (m.rhs(0.0, xp, u, p) - m.rhs(0.0, xm, u, p)) / (2 * h)
            np.testing.assert_allclose(J[:, j], fd, rtol=1e-5,
                                       atol=1e-6 * np.max(np.abs(fd)) + 1e-300)
        bare = get_model(name).rhs(0.0, x, u, p)
        f = m.rhs(0.0, x, u, p)
        assert (np.allclose(f, bare) if sgn > 0 else not np.allclose(f, bare))


def test_chamber_models_tend_to_the_dashpot_law_and_errors():
    S = HarmonicStroke(0.003, 0.5)
    stiff = P.replace(inv_gamma1=0.0, inv_gamma2=0.0, c2=0.0)
    K = {n: dynamic_stiffness(steady_state(with_effects(get_model(n), AsymmetricLoss(2.0)),
                                           stiff, S, options=OPTS)).value
         for n in ("dashpot", "constant_bulk", "no_inertia")}
    assert K["dashpot"].imag / S.omega == pytest.approx(1.5 * stiff.c_L, rel=1e-9)
    for n in ("constant_bulk", "no_inertia"):
        assert abs(K[n] - K["dashpot"]) < 2 * S.omega * stiff.T_D * abs(K["dashpot"]), n
    with pytest.raises(ParameterError, match="rebound_ratio must be > 0"):
        AsymmetricLoss(0.0)
    with pytest.raises(ParameterError, match="needs a loss"):
        with_effects(get_model("inerter"), AsymmetricLoss(2.0))
    with pytest.raises(ParameterError, match="no small-signal model at rest"):
        linearize(with_effects(get_model("full"), AsymmetricLoss(2.0)), P)
    with pytest.raises(ParameterError, match="has no equivalent"):
        device_lti(Device(with_effects(get_model("full"), AsymmetricLoss(2.0)), P),
                   amplitude=Y, frequency=F_HZ)
