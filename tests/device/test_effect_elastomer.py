"""Parallel elastomer branch (issue #12 item 4): the standard linear solid on the rod.

Linear, so K(i w) = k0 + k1 i w tau / (1 + i w tau), tau = c1 / k1, holds at any
amplitude: the first harmonic of a time-domain steady state (both engines), the
small-signal model (linearize, device_lti) and the equivalent model must all give it.
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
from liquidamp.device.effects import Elastomer, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
EL = Elastomer(2e5, 6e5, 6e5 / (2 * math.pi * 4.0))  # w tau = 1 at 4 Hz


def _closed(f):
    w = 2 * math.pi * f
    tau = EL.branch_damping_N_s_per_m / EL.branch_stiffness_N_per_m
    return EL.parallel_stiffness_N_per_m + EL.branch_stiffness_N_per_m * 1j * w * tau / (
        1 + 1j * w * tau)


@pytest.mark.parametrize("engine", ["scipy", "compiled"])
@pytest.mark.parametrize("f", [1.0, 4.0, 15.0])
def test_time_domain_dynamic_stiffness_is_the_closed_form(engine, f):
    weak = P.replace(c1=1e-6)  # the dashpot's own c_L is 5e-13 N s/m: the elastomer alone
    m = with_effects(get_model("dashpot"), EL)
    r = steady_state(m, weak, HarmonicStroke(0.002, f),
                     options=SolverOptions(engine=engine, rtol=1e-9, samples_per_period=2048))
    K = dynamic_stiffness(r).value
    assert K == pytest.approx(_closed(f), rel=1e-5)
    assert EL.stiffness(2 * math.pi * f) == pytest.approx(_closed(f), rel=1e-14)


def test_linear_views_hold_it_exactly():
    m = with_effects(get_model("full"), EL)
    assert m.analytic_jacobian and m.state_names[-1] == "F_elastomer"
    lin = linearize(m, P)
    assert lin.jacobian == "analytic" and "F_elastomer" in lin.state_names
    bare = device_lti(Device("full", P))
    withe = device_lti(Device(m, P))
    for f in (0.5, 4.0, 20.0):
        assert withe.stiffness(f) - bare.stiffness(f) == pytest.approx(_closed(f),
                                                                              rel=1e-6)
        eq0 = device_lti(Device("full", P), amplitude=1e-3, frequency=f)
        eq = device_lti(Device(m, P), amplitude=1e-3, frequency=f)
        assert eq.stiffness(f) - eq0.stiffness(f) == pytest.approx(_closed(f), rel=1e-12)
    # a stateless base: the small-signal model is the dashpot plus the solid
    d = device_lti(Device(with_effects(get_model("dashpot"), EL), P))
    assert d.stiffness(4.0) == pytest.approx(_closed(4.0) + 2j * math.pi * 4.0 * P.c_L,
                                                rel=1e-6)
    # the time domain of the full model: the elastomer's force adds exactly (linear)
    s = HarmonicStroke(0.001, 4.0)
    o = SolverOptions(engine="compiled", rtol=1e-10, samples_per_period=2048)
    k0 = dynamic_stiffness(steady_state("full", P, s, options=o)).value
    k1 = dynamic_stiffness(steady_state(m, P, s, options=o)).value
    assert k1 - k0 == pytest.approx(_closed(4.0), rel=1e-5)


def test_elastomer_errors():
    with pytest.raises(ParameterError, match="branch_damping_N_s_per_m must be > 0"):
        Elastomer(1.0, 1.0, 0.0)
    with pytest.raises(ParameterError, match="parallel_stiffness_N_per_m must be >= 0"):
        Elastomer(-1.0)
    assert np.isclose(Elastomer(5.0).stiffness(3.0), 5.0)  # no branch: the spring alone
