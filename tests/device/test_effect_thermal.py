"""Self-heating (issue #20 item 5): a lumped fluid temperature, losses that follow it.

* Constant power: T(t) = T_amb + P / h_A (1 - exp(-t h_A / C)) on both engines.
* beta = 0 (and gamma2 = 0) is the device without the effect exactly, on both engines.
* Energy closure: heat stored + heat lost = mechanical work (stateless bases: all of it is
  dissipated) to 1e-6 over a run, with the quadratic loss, a rebound ratio and a valve.
* The temperature's Jacobian entry against its closed form, every entry against
  differences of the right-hand side the engines share.
* Viscosity laws against published data (water 20-40 C; Walther through its own points).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from liquidamp.coupled.testrig import simulate
from liquidamp.device import preset
from liquidamp.device.effects import (
    AsymmetricLoss,
    GasCharge,
    ReliefValve,
    SelfHeating,
    make_effect,
    with_effects,
)
from liquidamp.device.effects_thermal import WALTHER_VG32
from liquidamp.device.models import VISCOUS, ViscousParams, get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke, RecordedStroke

P = preset("reference")
OPTS = SolverOptions(rtol=1e-10, atol_scale=1e-12)


@pytest.mark.parametrize("engine", ["scipy", "compiled"])
def test_constant_power_heating_is_the_closed_form(engine):
    # the rigid-fluid dashpot F = c_L v at a constant rate: P = c_L V^2
    V, C, hA = 0.005, 0.05, 0.01  # tau = 5 s
    c = P.c_L
    t = np.linspace(0.0, 8.0, 801)
    stroke = RecordedStroke(t, V * t - 0.02, V + 0 * t, 0 * t)
    e = SelfHeating(heat_capacity_J_per_K=C, conductance_W_per_K=hA, beta_per_K=0.0)
    m = with_effects(get_model("dashpot"), e)
    r = simulate(m, P, stroke, 8.0, t_eval=t, options=OPTS.replace(engine=engine))
    T = r.states[0]
    closed = e.ambient_temperature_K + c * V * V / hA * (1.0 - np.exp(-t * hA / C))
    np.testing.assert_allclose(T - 293.15, closed - 293.15, rtol=1e-6, atol=1e-7)
    assert T[-1] - T[0] > 3.0


@pytest.mark.parametrize("engine", ["scipy", "compiled"])
def test_zero_beta_is_the_device_without_the_effect(engine):
    S = HarmonicStroke(0.003, 3.0)
    opts = SolverOptions(rtol=1e-9, engine=engine)
    t = np.linspace(0.0, 1.0, 401)
    bare = simulate("full", P, S, 1.0, t_eval=t, options=opts)
    e = SelfHeating(beta_per_K=0.0, c2_exponent=0.0, heat_capacity_J_per_K=0.5)
    hot = simulate(with_effects(get_model("full"), e), P, S, 1.0, t_eval=t, options=opts)
    np.testing.assert_allclose(hot.force, bare.force, rtol=0, atol=2e-6 * np.ptp(bare.force))
    assert hot.states[-1, -1] > e.initial_temperature_K + 1.0  # it warmed all the same
    # with beta the warm device is softer: the force falls as it warms
    w = simulate(with_effects(get_model("full"), e.replace(beta_per_K=0.05)), P, S, 1.0,
                 t_eval=t, options=opts)
    late = t > 0.67
    assert np.ptp(w.force[late]) < 0.97 * np.ptp(bare.force[late])


@pytest.mark.parametrize("base, params, extra", [
    ("viscous", ViscousParams(1500.0, 4000.0), ()),
    ("dashpot", P, (AsymmetricLoss(1.6), ReliefValve(4e5, 3e-10))),
])
def test_energy_closure(base, params, extra):
    """Heat stored + heat lost = work done on the device (all dissipated: no states but T)."""
    e = SelfHeating(heat_capacity_J_per_K=0.3, conductance_W_per_K=0.2, beta_per_K=0.03,
                    c2_exponent=0.4, initial_temperature_K=300.0)
    m = with_effects(VISCOUS if base == "viscous" else get_model(base), *extra, e)
    S = HarmonicStroke(0.004, 4.0)

    def f(t, z):
        u = tuple(float(q) for q in S(t))
        x = z[:1]
        F = float(m.force(t, x, u, params))
        return [m.rhs(t, x, u, params)[0], F * u[1], e.conductance_W_per_K * (
            z[0] - e.ambient_temperature_K)]

    sol = solve_ivp(f, (0.0, 3.1), [300.0, 0.0, 0.0], method="DOP853", rtol=1e-12,
                    atol=1e-12, max_step=2e-3)
    T1, W, L = sol.y[:, -1]
    stored = e.heat_capacity_J_per_K * (T1 - 300.0)
    assert W > 1.0 and stored > 0.1 * W  # a run that warms and loses heat
    assert abs(stored + L - W) <= 1e-6 * W


@pytest.mark.parametrize("base", ["full", "no_inertia", "single_state", "inertial_2state",
                                  "maxwell"])
def test_jacobian_matches_differences(base):
    p = P.replace(c1=P.c1) if base != "maxwell" else P
    e = SelfHeating(heat_capacity_J_per_K=0.5, conductance_W_per_K=0.1, beta_per_K=0.03,
                    c2_exponent=0.3, initial_temperature_K=305.0)
    m = with_effects(get_model(base), e)
    r = simulate(m, p, HarmonicStroke(0.003, 3.0), 0.3, t_eval=np.linspace(0, 0.3, 31),
                 options=SolverOptions(rtol=1e-8))
    x = np.array(r.states[:, 17])
    u = tuple(float(q) for q in HarmonicStroke(0.003, 3.0)(0.17))
    J = m.jacobian(0.0, x, u, p)
    sc = m.state_scales(p)
    for j in range(m.n_states):
        h = 1e-6 * max(abs(x[j]), sc[j])
        xp, xm = x.copy(), x.copy()
        xp[j] += h
        xm[j] -= h
        fd = (m.rhs(0.0, xp, u, p) - m.rhs(0.0, xm, u, p)) / (2 * h)
        np.testing.assert_allclose(J[:, j], fd, rtol=1e-4,
                                   atol=1e-6 * np.max(np.abs(fd)) + 1e-300)
    assert np.any(J[:-1, -1] != 0.0)  # the temperature reaches the fluid equations


def test_temperature_jacobian_entry_is_the_closed_form():
    """d(dT/dt)/dT = (dP/dT - h_A) / C, dP/dT = -beta c v^2 on the viscous damper."""
    c, v, C, hA, b = 900.0, 0.2, 1.5, 0.3, 0.04
    e = SelfHeating(heat_capacity_J_per_K=C, conductance_W_per_K=hA, beta_per_K=b)
    m = with_effects(VISCOUS, e)
    T = e.reference_temperature_K + 7.0
    J = m.jacobian(0.0, np.array([T]), (0.0, v, 0.0), ViscousParams(c))
    r = math.exp(-b * 7.0)
    assert J[0, 0] == pytest.approx((-b * c * r * v * v - hA) / C, rel=1e-6)


def test_viscosity_laws_against_published_data():
    # water (IAPWS: 1.0016 mPa s at 20 C, 0.6527 at 40 C, 0.2818 at 100 C)
    w = SelfHeating(law="water")
    assert w.viscosity_ratio(313.15) == pytest.approx(0.6527 / 1.0016, rel=0.01)
    assert w.viscosity_ratio(373.15) == pytest.approx(0.2818 / 1.0016, rel=0.03)
    # about -2.4 %/K near 20 C: the exponential law's default is of that size
    assert -math.log(w.viscosity_ratio(294.15)) == pytest.approx(0.024, abs=0.001)
    # Walther through its two points (ISO VG 32: 32 and 5.4 mm^2/s at 40 and 100 C)
    o = SelfHeating(law="walther", reference_temperature_K=313.15, initial_temperature_K=313.15)
    assert (o.law_a, o.law_b) == WALTHER_VG32
    assert o.viscosity_ratio(373.15) == pytest.approx(5.4 / 32.0, rel=1e-9)
    # a mineral oil thins faster than water near room temperature
    assert o.viscosity_ratio(323.15) < w.viscosity_ratio(323.15) / w.viscosity_ratio(313.15)
    e = SelfHeating(beta_per_K=0.02)
    assert e.viscosity_ratio(e.reference_temperature_K + 10) == pytest.approx(math.exp(-0.2))


def test_errors_and_refusals():
    with pytest.raises(ParameterError, match="heat_capacity_J_per_K must be > 0"):
        SelfHeating(heat_capacity_J_per_K=0.0)
    with pytest.raises(ParameterError, match="beta_per_K"):
        SelfHeating(beta_per_K=-0.01)
    with pytest.raises(ParameterError, match="c2_exponent must be in"):
        SelfHeating(c2_exponent=2.0)
    with pytest.raises(ParameterError, match="law must be one of"):
        make_effect("self_heating", law="honey")
    with pytest.raises(ParameterError, match="needs a flow path"):
        with_effects(get_model("spring"), SelfHeating())
    with pytest.raises(ParameterError, match="no equivalent linearization"):
        SelfHeating().describing_function(0.001, 10.0, P)
    assert SelfHeating().held(310.0).heat_capacity_J_per_K == math.inf
    # at rest it points to the time domain, not to an equivalent linearization it refuses too
    with pytest.raises(ParameterError, match="no amplitude-independent linearization holds it"):
        SelfHeating().check_small_signal(P)


def test_the_gas_charge_follows_the_fluid_temperature():
    """An ideal gas at its reference volume: (p_c + p_a) T / T_ref - p_a; at T_ref unchanged."""
    g = GasCharge(4.5e-5, 6.894757e5, 2e-6, 1.0)
    e = SelfHeating()
    m = with_effects(get_model("dashpot"), g, e)
    Tr = e.reference_temperature_K
    for T in (Tr, Tr + 30.0):
        F = float(m.force(0.0, np.array([T]), (0.0, 0.0, 0.0), P))
        closed = g.rod_area_m2 * ((g.charge_pressure_Pa + g.ambient_pressure_Pa) * T / Tr
                                  - g.ambient_pressure_Pa)
        assert F == pytest.approx(closed, rel=1e-12)
    assert closed > 1.09 * g.force(0.0)
