"""The device on the test machine: reductions against their parents, the paper's behaviour,
steady-state reliability and clear errors (Titurus 2018, Sec. III.D and IV.D)."""

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.coupled.testrig import simulate, steady_state
from liquidamp.device import preset
from liquidamp.errors import ParameterError, PressureError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke, RecordedStroke


def K(model, params, Y, f, **kw):
    return dynamic_stiffness(steady_state(model, params, HarmonicStroke(Y, f), **kw))


# ----------------------------------------------------------------- reductions


@pytest.mark.parametrize("f", [1.0, 4.0])
def test_full_with_vanishing_inertance_tends_to_eq11(f):
    """eq. (10) with S_t -> 0 approaches eq. (11); the gap shrinks in proportion to S_t."""
    p = preset("reference")
    k11 = K("no_inertia", p, 0.002, f).value
    gaps = [abs(K("full", p.replace(S_t=p.S_t * s), 0.002, f).value - k11) / abs(k11)
            for s in (1e-2, 1e-3)]
    assert gaps[1] < 2e-3
    assert gaps[1] < 0.2 * gaps[0]  # first-order convergence in S_t


@pytest.mark.parametrize("name", ["reference", "device_a"])
def test_full_with_constant_bulk_is_eq17(name):
    """With B = B(p0) the density states of eq. (10) follow r_i(p_i): eq. (17) exactly."""
    p = preset(name).replace(bulk_law="constant")
    a = K("full", p, 0.001, 3.0).value
    b = K("inertial", p, 0.001, 3.0).value
    assert abs(a - b) / abs(b) < 1e-6


def test_no_inertia_with_constant_bulk_is_eq13():
    p = preset("damper").replace(bulk_law="constant")
    a = K("no_inertia", p, 0.001, 3.0).value
    b = K("constant_bulk", p, 0.001, 3.0).value
    assert abs(a - b) / abs(b) < 1e-6


def test_eq18_incompressible_tends_to_eq19():
    """eq. (18) with B^-1 -> 0 and c2 = 0 is dashpot plus inerter (eq. 19); gap ~ 1/B.

    Started on the eq. (19) solution (q = A_p v, dp = c1 q) so the lightly damped
    high-frequency compressibility mode is barely excited.
    """
    p = preset("device_a").replace(c2=0.0, inv_gamma1=0.0, inv_gamma2=0.0)
    stroke = HarmonicStroke(0.001, 3.0)
    target = K("dashpot_inerter", p, 0.001, 3.0).value
    v0 = stroke(0.0)[1]
    gaps = []
    for s in (0.1, 1.0):
        q = p.replace(B_l=p.B_l * s)
        x0 = [q.c1 * q.A_p * v0, q.A_p * v0]
        gaps.append(abs(K("inertial_2state", q, 0.001, 3.0, x0=x0).value - target) / abs(target))
    assert gaps[1] < 1e-3
    assert 0.05 < gaps[1] / gaps[0] < 0.2  # first order in 1/B


@pytest.mark.parametrize("f", [0.5, 3.0, 20.0])
def test_eq16_linear_is_the_maxwell_unit(f):
    """single_state (eq. 15) with c2 = 0 at small stroke equals the Maxwell closed form."""
    p = preset("reference").replace(c2=0.0)
    w = 2 * np.pi * f
    closed = p.k_D * 1j * w * p.T_D / (1 + 1j * w * p.T_D)
    got = K("single_state", p, 1e-6, f).value
    assert abs(got - closed) / abs(closed) < 1e-5


def test_eq14_drifts_where_eq13_does_not():
    """The volumetric model loses mass every cycle (r1 != r2); eq. (13) keeps it."""
    p = preset("reference").replace(inv_gamma1=0.0, inv_gamma2=0.0)
    stroke = HarmonicStroke(0.002, 3.0)
    r13 = simulate("constant_bulk", p, stroke, 10.0)
    r14 = simulate("volumetric", p, stroke, 10.0)
    assert r13.mass_error < 1e-10
    # mean pressure over the first and last second: eq. 14 drifts down, eq. 13 does not
    def mean_p(r, lo, hi):
        sel = (r.time >= lo) & (r.time < hi)
        return float(np.mean(r.p1[sel] + r.p2[sel]) / 2)

    drift14 = mean_p(r14, 9.0, 10.0) - mean_p(r14, 0.0, 1.0)
    drift13 = mean_p(r13, 9.0, 10.0) - mean_p(r13, 0.0, 1.0)
    assert drift14 < -1e3  # Pa, monotone loss of mass
    assert abs(drift13) < 1e-3 * abs(drift14)
    assert r14.mass_error > 1e3 * max(r13.mass_error, 1e-16)


# ------------------------------------------------------ the paper's behaviour


@pytest.mark.parametrize("Y", [0.001, 0.003])
def test_spring_damper_specializations(Y):
    # Figs. 7-8: spring-like near 0 deg, damper-like near 90 deg
    assert K("full", preset("spring"), Y, 3.0).phase_deg < 20.0
    assert 75.0 < K("full", preset("damper"), Y, 3.0).phase_deg < 95.0


def test_inerter_specialization_is_inertia_dominated():
    # Fig. 9: phase beyond 120 deg; at 3 mm the low chamber nears zero pressure
    r = steady_state("full", preset("inerter"), HarmonicStroke(0.003, 3.0))
    assert dynamic_stiffness(r).phase_deg > 120.0
    assert 0.0 < r.min_pressure < 2339.0
    assert any("vapour pressure" in w for w in r.warnings)
    assert np.all(np.isfinite(r.force))


def test_device_a_inertia_to_stiffness():
    # Fig. 10: inertia-dominated at 1 Hz, stiffness-dominated at 7 Hz
    assert K("full", preset("device_a"), 0.0015, 1.0).phase_deg > 120.0
    assert K("full", preset("device_a"), 0.0015, 7.0).phase_deg < 20.0


def test_device_b_damping_towards_stiffness():
    # Fig. 11: damper-like at 1 Hz, phase falls monotonically with frequency
    phases = [K("full", preset("device_b"), 0.0015, f).phase_deg for f in (1.0, 2.0, 4.0, 7.0)]
    assert phases[0] > 80.0
    assert np.all(np.diff(phases) < 0)
    assert phases[-1] < 45.0


# ------------------------------------------------------ steady state and runs


def test_steady_state_agrees_with_a_long_march():
    p, stroke = preset("spring"), HarmonicStroke(0.001, 3.0)
    ss = steady_state("full", p, stroke)
    T = stroke.period
    n = ss.time.size
    t_eval = 60 * T + np.arange(n) * T / n
    long = simulate("full", p, stroke, 61 * T, t_eval=t_eval)
    err = np.max(np.abs(long.force - ss.force)) / np.max(np.abs(ss.force))
    assert err < 1e-5
    assert ss.residual < 1e-6


def test_full_model_conserves_mass_and_stays_on_its_density_curve():
    from liquidamp.device.fluid import density_gholizadeh

    p = preset("paper_calibrated")
    r = steady_state("full", p, HarmonicStroke(0.003, 3.0))
    assert r.mass_error < 1e-10
    rho1 = density_gholizadeh(r.p1[::64], p.rho0, p.B_l, p.X01, p.p0, p.n)
    np.testing.assert_allclose(r.state("rho1")[::64], rho1, rtol=1e-7)


def test_recorded_stroke_reproduces_the_harmonic_run():
    p, stroke = preset("reference"), HarmonicStroke(0.002, 2.0)
    t = np.arange(0, 3.0, 1 / 2000)
    y, v, a = stroke(t)
    rec = RecordedStroke(t, y, v, a)
    r1 = simulate("full", p, stroke, 2.9, t_eval=t[t <= 2.9])
    r2 = simulate("full", p, rec, 2.9, t_eval=t[t <= 2.9])
    assert np.max(np.abs(r1.force - r2.force)) < 2e-3 * np.max(np.abs(r1.force))


# ------------------------------------------------------------------ bad input


def test_stroke_past_chamber_end_is_refused_before_work():
    with pytest.raises(ParameterError, match=r"past the chamber end at 0.025 m"):
        steady_state("full", preset("reference"), HarmonicStroke(0.026, 1.0))


@pytest.mark.parametrize(("Y", "f", "msg"), [(0.0, 3.0, "amplitude must be > 0"),
                                             (0.001, -1.0, "frequency must be > 0"),
                                             (0.001, 1e6, "frequency must lie in"),
                                             (float("nan"), 3.0, "must be finite")])
def test_nonsense_strokes(Y, f, msg):
    with pytest.raises(ParameterError, match=msg):
        HarmonicStroke(Y, f)


def test_low_pressure_stops_with_a_clear_error():
    with pytest.raises(PressureError, match="fell to the floor 5000 Pa"):
        steady_state("full", preset("inerter"), HarmonicStroke(0.003, 3.0),
                     options=SolverOptions(pressure_floor=5000.0))


def test_unknown_model_and_options():
    with pytest.raises(ParameterError, match="unknown model 'fulll'; valid: full"):
        steady_state("fulll", preset("reference"), HarmonicStroke(0.001, 3.0))
    with pytest.raises(ParameterError, match="unknown solver option"):
        SolverOptions.from_mapping({"tolerance": 1e-3})


def test_constant_bulk_model_warns_of_negative_pressure():
    r = steady_state("constant_bulk", preset("reference"), HarmonicStroke(0.003, 3.0))
    assert r.min_pressure < 0
    assert any("went negative" in w for w in r.warnings)
