"""Relief (blow-off) valve (issue #12 item 2): a pressure-limited second flow path.

* On the stateless dashpot-type bases it is the exact static law
  F(v) = sign(v) min(c |v|, F_r + c_o (|v| - F_r / c)), F_r = p_r A, c_o = 1 / (1/c + G/A^2)
  (the viscous base is a dashpot of unit area); its single-frequency describing function
  c_eq = c_o + (c - c_o) (2/pi) (arcsin rho + rho sqrt(1 - rho^2)), rho = F_r / (c V),
  is checked against the time-domain first harmonic and carried by device_lti.
* On the chamber models it is a second path beside the channel: mass is conserved, the
  pressure difference is limited, and with a stiff liquid and a laminar loss they tend to
  the dashpot's exact law (within w T_D).
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness, first_harmonic
from liquidamp.analysis.stability.damped_stability import device_lti
from liquidamp.coupled.assembly import Device
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import ReliefValve, saturation_damping, with_effects
from liquidamp.device.models import VISCOUS, ViscousParams, get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
OPTS = SolverOptions(engine="compiled", rtol=1e-10, samples_per_period=4096)


def _law(v, c, F_r, c_o):
    return np.sign(v) * np.minimum(c * np.abs(v), F_r + c_o * (np.abs(v) - F_r / c))


def test_static_law_on_the_dashpot_types_is_exact():
    v = np.linspace(-0.05, 0.05, 201)
    for name, params, c, A in (("dashpot", P, P.c_L, P.A_p),
                               ("dashpot_inerter", P, P.c_L, P.A_p),
                               ("viscous", ViscousParams(8e4), 8e4, 1.0)):
        p_r, G = 0.3 * c * 0.05 / A, 0.5 * A**2 / c  # cracking at 0.015 m/s; c_o = c/1.5
        base = VISCOUS if name == "viscous" else get_model(name)
        m = with_effects(base, ReliefValve(p_r, G))
        a = 3.0
        F = m.force(0.0, np.zeros((0, v.size)), (np.zeros_like(v), v, np.full_like(v, a)),
                    params)
        c_o = 1 / (1 / c + G / A**2)
        expected = _law(v, c, p_r * A, c_o) + (P.b_L * a if name == "dashpot_inerter" else 0)
        np.testing.assert_allclose(F, expected, rtol=1e-13, atol=1e-12 * np.max(np.abs(F)))
        assert np.any(np.abs(v) * c > p_r * A)  # the valve opens on part of the range


@pytest.mark.parametrize("ratio", [0.2, 0.6, 0.95, 1.5])
def test_describing_function_equals_the_time_domain_first_harmonic(ratio):
    """dashpot: K* of the (algebraic) steady state against saturation_damping and
    device_lti; viscous: the first harmonic of the model's force over one period."""
    f, Y = 3.0, 0.002
    w = 2 * math.pi * f
    V = w * Y
    c, G = P.c_L, 2.0 / (P.c1 * 1.0)  # the valve path twice the channel's conductance
    p_r = ratio * c * V / P.A_p      # cracking at ``ratio`` of the peak force
    c_o = 1 / (1 / c + G / P.A_p**2)
    c_eq = saturation_damping(c, c_o, p_r * P.A_p, V)
    if ratio < 1:
        rho = ratio
        closed = c_o + (c - c_o) * 2 / math.pi * (math.asin(rho) + rho * math.sqrt(1 - rho**2))
        assert c_eq == pytest.approx(closed, rel=1e-14) and c_o < c_eq < c
    else:
        assert c_eq == c
    m = with_effects(get_model("dashpot"), ReliefValve(p_r, G))
    K = dynamic_stiffness(steady_state(m, P, HarmonicStroke(Y, f), options=OPTS)).value
    assert abs(K.real) < 1e-9 * abs(K)
    assert K.imag / w == pytest.approx(c_eq, rel=1e-6)
    lti = device_lti(Device(m, P), amplitude=Y, frequency=f)
    assert lti.stiffness(f) == pytest.approx(1j * w * c_eq, rel=1e-12)
    # the viscous damper, given the relief as a force
    cv, F_r, cvo = 6e4, ratio * 6e4 * V, 1.5e4
    mv = with_effects(VISCOUS, ReliefValve.from_force(F_r, cv, cvo))
    t = np.arange(4096) / (4096 * f)
    v = V * np.cos(w * t)
    Fv = mv.force(t, np.zeros((0, t.size)), (Y * np.sin(w * t), v, 0 * t), ViscousParams(cv))
    F1 = first_harmonic(t, Fv, f)   # sine convention: V cos = i V sin
    assert (F1 / (1j * V)).real == pytest.approx(saturation_damping(cv, cvo, F_r, V), rel=1e-6)
    ltiv = device_lti(Device(mv, ViscousParams(cv)), amplitude=Y, frequency=f)
    assert ltiv.stiffness(f) == pytest.approx(1j * w * saturation_damping(cv, cvo, F_r, V),
                                                 rel=1e-12)


def test_chamber_models_conserve_mass_and_tend_to_the_dashpot_law():
    S = HarmonicStroke(0.003, 0.5)
    stiff = P.replace(inv_gamma1=0.0, inv_gamma2=0.0, c2=0.0)  # liquid only, laminar loss
    V = S.amplitude * S.omega
    rv = ReliefValve(0.4 * stiff.c_L * V / stiff.A_p, 2.0 / stiff.c1)
    K = {n: dynamic_stiffness(steady_state(with_effects(get_model(n), rv), stiff, S,
                                           options=OPTS)).value
         for n in ("dashpot", "constant_bulk", "no_inertia")}  # no channel inertance
    for n in ("constant_bulk", "no_inertia"):
        assert abs(K[n] - K["dashpot"]) < 2 * S.omega * stiff.T_D * abs(K["dashpot"]), n
    bare = dynamic_stiffness(steady_state("dashpot", stiff, S, options=OPTS)).value
    assert abs(K["dashpot"]) < 0.7 * abs(bare)  # the valve matters
    # the reference device at 3 mm, 3 Hz: mass conserved, |dp| held near p_r
    r0 = steady_state("full", P, HarmonicStroke(0.003, 3.0), options=OPTS)
    p_r = 0.5 * np.max(np.abs(r0.p1 - r0.p2))
    m = with_effects(get_model("full"), ReliefValve(p_r, 1e-9))
    for engine in ("scipy", "compiled"):
        r = steady_state(m, P, HarmonicStroke(0.003, 3.0),
                         options=OPTS.replace(engine=engine, samples_per_period=256, rtol=1e-9))
        assert r.mass_error < 1e-9
        assert p_r < np.max(np.abs(r.p1 - r.p2)) < 0.6 * np.max(np.abs(r0.p1 - r0.p2))


def test_relief_errors_and_small_signal():
    with pytest.raises(ParameterError, match="needs a flow path"):
        with_effects(get_model("spring"), ReliefValve(1e6, 1e-9))
    with pytest.raises(ParameterError, match="cracking_pressure_Pa must be >= 0"):
        ReliefValve(-1.0)
    with pytest.raises(ParameterError, match="open_damping_N_s_per_m must be <="):
        ReliefValve.from_force(100.0, 1e3, 2e3)
    m = with_effects(get_model("full"), ReliefValve(1e5, 1e-9))
    with pytest.raises(ParameterError, match="effect 'relief_valve' has no equivalent"):
        device_lti(Device(m, P), amplitude=1e-3, frequency=3.0)
    # closed at rest: the small-signal model is the bare one
    bare = device_lti(Device("full", P)).stiffness(3.0)
    assert device_lti(Device(m, P)).stiffness(3.0) == pytest.approx(bare, rel=1e-5)


def test_quadratic_viscous_with_relief_or_rebound_ratio_is_refused_naming_c2():
    """The dashpot-type relief and rebound laws are written for F = c v: a viscous damper
    with c2 != 0 is refused (naming c2), not run with its quadratic part dropped."""
    from liquidamp.device.effects import AsymmetricLoss, ReliefValve, with_effects
    from liquidamp.device.models import VISCOUS, ViscousParams
    from liquidamp.errors import ParameterError

    for e in (ReliefValve.from_force(500.0, 1e4, 1e3), AsymmetricLoss(1.5)):
        m = with_effects(VISCOUS, e)
        m.packed(ViscousParams(1e4))  # c2 = 0: fine
        with pytest.raises(ParameterError, match=r"c2 = 3.0 N s\^2/m\^2 must be 0"):
            m.packed(ViscousParams(1e4, c2=3.0))
