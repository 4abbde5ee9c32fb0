"""Slip-weakening smooth friction (``slip_weakening``) and the friction start's fluid levels.

Closed form: sliding forward at a constant velocity v from bristles and slip memory both
loaded in reverse (z = w = -1), with no Stribeck dip (r = 1) and n = 1, the bristle and
memory laws are linear in the slip s = v t,

    z(s) = 1 - 2 exp(-s / delta),   w(s) = 1 - 2 exp(-s / D),   delta = F_c / sigma0,

so the friction force is, once z > 0,

    F(s) = F_c z(s) (1 + beta (1 - w(s)) / 2) = F_c (1 - 2 e^{-s/delta}) (1 + beta e^{-s/D}),

the same function of the slip at any velocity (a slip-distance law): the breakaway peak sits
at the same slip at every rate.  beta = 0 is the smooth friction alone.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from liquidamp.device import preset
from liquidamp.device.effects import (
    EFFECTS,
    Freeplay,
    SlipWeakening,
    SmoothFriction,
    with_effects,
)
from liquidamp.device.kernels import slip_memory_rate, weakening
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError

FC, SIGMA, BETA, DW = 100.0, 1e6, 0.3, 2e-3
P = preset("reference")


def _force_vs_slip(model, v, s_end=8e-3, n=41):
    """Integrate the model's effect states at constant velocity ``v`` from z = w = -1 and
    return (slip, friction force) with the dashpot's own c_L v removed."""
    bare = get_model("dashpot")
    T = s_end / v
    t_eval = np.linspace(0.0, T, n)

    def rhs(t, x):
        return model.rhs(t, x, (v * t, v, 0.0), P)

    x0 = -np.ones(model.n_states)
    sol = solve_ivp(rhs, (0.0, T), x0, method="Radau", rtol=1e-10, atol=1e-12,
                    t_eval=t_eval)
    assert sol.success
    F = np.array([float(model.force(t, sol.y[:, i], (v * t, v, 0.0), P))
                  - float(bare.force(t, np.zeros(0), (v * t, v, 0.0), P))
                  for i, t in enumerate(sol.t)])
    return v * sol.t, F


@pytest.mark.parametrize("v", [1e-3, 0.1])
def test_slip_weakening_follows_its_closed_form_at_any_rate(v):
    m = with_effects(get_model("dashpot"), SmoothFriction(FC, SIGMA),
                     SlipWeakening(BETA, DW))
    assert m.state_names == ("z_friction", "w_slip")
    s, F = _force_vs_slip(m, v)
    delta = FC / SIGMA
    exact = FC * (1 - 2 * np.exp(-s / delta)) * (1 + BETA * np.exp(-s / DW))
    on = s > 2 * delta  # z > 0 there (the closed form's branch)
    np.testing.assert_allclose(F[on], exact[on], rtol=1e-6, atol=1e-6 * FC)
    # the breakaway peak: near (1 + beta) F_c just after the pre-sliding stroke, the
    # sliding level F_c after several weakening distances
    assert F.max() > (1 + 0.6 * BETA) * FC
    assert F[-1] == pytest.approx(FC * (1 + BETA * math.exp(-s[-1] / DW)), rel=1e-6)


def test_zero_ratio_is_the_smooth_friction_alone():
    plain = with_effects(get_model("dashpot"), SmoothFriction(FC, SIGMA))
    weak0 = with_effects(get_model("dashpot"), SmoothFriction(FC, SIGMA),
                         SlipWeakening(0.0, DW))
    s0, F0 = _force_vs_slip(plain, 0.02)
    s1, F1 = _force_vs_slip(weak0, 0.02)
    np.testing.assert_allclose(F1, F0, rtol=1e-7, atol=1e-7 * FC)


def test_laws_and_limits():
    # memory rate: |v| (sign v - w) / D; factor 1 + beta (1 - w sign z) / 2
    assert slip_memory_rate(-0.02, 1.0, 1e-3) == pytest.approx(-40.0)
    assert slip_memory_rate(0.0, 0.3, 1e-3) == 0.0
    assert weakening(0.5, -1.0, 0.4) == pytest.approx(1.4)
    assert weakening(-0.5, -1.0, 0.4) == pytest.approx(1.0)
    assert weakening(0.0, 0.0, 0.4) == pytest.approx(1.2)  # F_c z = 0 there anyway


def test_composition_and_parameters_are_checked():
    with pytest.raises(ParameterError, match="smooth_friction"):
        with_effects(get_model("dashpot"), SlipWeakening(0.2, 1e-3))
    with pytest.raises(ParameterError, match="ratio"):
        SlipWeakening(-0.1, 1e-3)
    with pytest.raises(ParameterError, match="distance_m"):
        SlipWeakening(0.1, 0.0)
    # behind a dead band with the friction at the piston: composes, memory after z
    m = with_effects(get_model("full"), Freeplay(1e-4),
                     SmoothFriction(FC, SIGMA, location="piston"), SlipWeakening(0.2, 1e-3))
    assert m.state_names[-2:] == ("z_friction", "w_slip")
    assert "slip_weakening" in EFFECTS and EFFECTS["slip_weakening"].screened
    e = SlipWeakening.probe(1e3, 5e-3, 6.0, P)
    assert (e.ratio, e.distance_m) == (0.1, pytest.approx(5e-4))


def test_friction_start_fluid_levels():
    from liquidamp.analysis.measured.device_class import (
        FLUID_FLOOR,
        fluid_levels,
        friction_start,
        read_loop,
    )
    from liquidamp.analysis.measured.records import Record

    t = np.arange(0, 8.0, 0.002)
    y = 0.01 * np.sin(2 * np.pi * t)
    F = 500.0 * np.tanh(np.gradient(y, t) / 1e-3)
    F = F + 50.0 * np.random.default_rng(1).standard_normal(t.size)  # noise floor ~0.1
    recs = [Record.from_arrays(t, y, F)]
    assert fluid_levels(recs) == (None, FLUID_FLOOR)
    L = read_loop(recs)
    floor = friction_start(P, (), recs, L)
    dry = friction_start(P, (), recs, L, fluid_share=FLUID_FLOOR)
    # the fluid's first-harmonic |K| scales with its target: the noise floor (~0.1) / 1e-3
    from liquidamp.analysis.measured.start import linear_stiffness

    ratio = abs(linear_stiffness(floor.params, 1.0, 0.01)) / abs(
        linear_stiffness(dry.params, 1.0, 0.01))
    assert 20.0 < ratio < 500.0
    assert "negligible fluid" in dry.reason and "noise floor" in floor.reason
    with pytest.raises(ParameterError, match="fluid_share"):
        friction_start(P, (), recs, L, fluid_share=1.5)


def test_default_diagnosis_finds_slip_weakening():
    """The paper's device with smooth friction (60 N) that breaks away 50 % higher and loses
    it over 1 mm of slip: the default screen adds the friction (``backlash``, a gap of a few
    micrometres: friction on the rod) and then ``slip_weakening``, beta and D within 30 %,
    the held-out error at least halved by the step (about 20 s)."""
    from liquidamp.analysis.measured.diagnosis import diagnose
    from liquidamp.analysis.measured.synthetic import synthetic_record

    truth = {"smooth_friction": {"force_N": 60.0, "stiffness_N_per_m": 2e5},
             "slip_weakening": {"ratio": 0.5, "distance_m": 1e-3}}
    cal = synthetic_record(preset="paper_calibrated", frequency=3.0, amplitude=0.003, cycles=4,
                           seed=5, effects=truth)
    val = synthetic_record(preset="paper_calibrated", frequency=4.0, amplitude=0.0025,
                           cycles=4, seed=105, effects=truth)
    d = diagnose([cal], [val])
    assert d.added[-1] == "slip_weakening", (d.added, d.stop_reason)
    step = d.steps[-1]
    assert step.parameters["ratio"] == pytest.approx(0.5, rel=0.3)
    assert step.parameters["distance_m"] == pytest.approx(1e-3, rel=0.3)
    assert step.nrmse_validation < 0.5 * d.steps[-2].nrmse_validation
