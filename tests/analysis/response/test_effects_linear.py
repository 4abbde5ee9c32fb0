"""Effects in the linear views (issue #11 item 5): included, or refused naming the effect.

The force effects are driven by the stroke alone, so under a harmonic stroke their
first harmonic adds exactly to the device's: the describing function each effect states
must equal the difference of two nonlinear steady states (with and without it), and
device_lti must carry it.
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
from liquidamp.device.effects import (
    Cavitation,
    CoulombFriction,
    ForceOffset,
    Freeplay,
    Leakage,
    MovingMass,
    SeriesCompliance,
    SmoothFriction,
    with_effects,
)
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
Y, F = 1e-3, 3.0
W = 2 * math.pi * F
FAST = SolverOptions(engine="compiled", rtol=1e-9, samples_per_period=4096)


def test_device_lti_includes_coulomb_friction_instead_of_dropping_it():
    """The case of issue #11: the equivalent model of full + 300 N Coulomb friction at
    1 mm, 3 Hz was exactly the bare device's (39 809 + 76 182j N/m)."""
    bare = device_lti(Device("full", P), amplitude=Y, frequency=F).stiffness(F)
    m = with_effects(get_model("full"), CoulombFriction(300.0))
    lti = device_lti(Device(m, P), amplitude=Y, frequency=F)
    k = lti.stiffness(F)
    assert abs(k - bare) > 1e5
    assert k - bare == pytest.approx(4 * 300.0 / (math.pi * Y) * 1j, rel=1e-12)
    assert "coulomb_friction" in lti.kind


@pytest.mark.parametrize("effect", [CoulombFriction(40.0), MovingMass(3.0), ForceOffset(25.0),
                                    SmoothFriction(40.0, 2e5, 0.01, 1.5)],
                         ids=lambda e: e.name)
def test_describing_function_equals_the_time_domain_difference(effect):
    """Two independent routes: the effect's stated (k, c, b) against the first harmonics of
    two compiled nonlinear steady states, with and without the effect."""
    s = HarmonicStroke(Y, F)
    bare = dynamic_stiffness(steady_state("full", P, s, options=FAST)).value
    withe = dynamic_stiffness(
        steady_state(with_effects(get_model("full"), effect), P, s, options=FAST)).value
    k, c, b = effect.describing_function(Y, W, P)
    predicted = k + 1j * W * c - W**2 * b
    scale = max(abs(predicted), 1e-3 * abs(bare))
    assert abs((withe - bare) - predicted) < 2e-3 * scale


def test_smooth_friction_describing_function_limits():
    """Large bristle stiffness: Coulomb's 4 F_c/(pi w Y); tiny amplitude: the bristle spring."""
    coul = CoulombFriction(30.0).describing_function(Y, W, P)[1]
    k, c, _ = SmoothFriction(30.0, 1e8).describing_function(Y, W, P)
    assert c == pytest.approx(coul, rel=2e-3) and k < 1e-2 * 1e8
    k, c, _ = SmoothFriction(30.0, 1e4).describing_function(1e-6, W, P)
    assert k == pytest.approx(1e4, rel=1e-3) and abs(c * W) < 1e-3 * k


@pytest.mark.parametrize("effect", [SeriesCompliance(1e6), Freeplay(1e-4), Leakage(1e-12),
                                    Cavitation(2339.0)], ids=lambda e: e.name)
def test_equivalent_linearization_refuses_effects_it_cannot_hold(effect):
    m = with_effects(get_model("full"), effect)
    with pytest.raises(ParameterError, match=f"effect '{effect.name}' has no equivalent "):
        device_lti(Device(m, P), amplitude=Y, frequency=F)


def test_small_signal_holds_linear_effects_and_refuses_the_others():
    # series compliance is linear: in series with the bare model's small-signal stiffness
    k_s = 2e6
    bare = device_lti(Device("full", P)).stiffness(F)
    comp = device_lti(Device(with_effects(get_model("full"), SeriesCompliance(k_s)), P))
    # (the composition's Jacobian is the compiled central differences: ~1e-6 accurate)
    assert comp.stiffness(F) == pytest.approx(1 / (1 / bare + 1 / k_s), rel=2e-5)
    # leakage: a laminar path in parallel with the channel lowers the stiffness at 3 Hz
    leak = device_lti(Device(with_effects(get_model("full"), Leakage(2e-11)), P))
    assert abs(leak.stiffness(F)) < abs(bare)
    # the moving mass: - m w^2 on top
    mm = device_lti(Device(with_effects(get_model("full"), MovingMass(2.0)), P))
    assert mm.stiffness(F) - bare == pytest.approx(-2.0 * W**2, rel=1e-6)
    for effect in (CoulombFriction(10.0), Freeplay(1e-4)):
        with pytest.raises(ParameterError, match=f"effect '{effect.name}' has no small-signal"):
            linearize(with_effects(get_model("full"), effect), P)
    low = P.replace(p0=2500.0)
    with pytest.raises(ParameterError, match="filling pressure p0 = 2500 Pa is within"):
        linearize(with_effects(get_model("full"), Cavitation(2339.0)), low)
    assert np.all(np.isfinite(linearize(with_effects(get_model("full"),
                                                     Cavitation(2339.0)), P).A))
