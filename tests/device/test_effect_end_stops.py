"""End stops (issue #12 item 5): a stiff contact beyond centre +/- clearance, C1 onset.

* Static force: 0 inside the clearance, k (|y - centre| - clearance) sign(y - centre)
  beyond the onset width w = 0.01 clearance + 1e-7 m, exactly.
* The elastic stop does no net work over a cycle (a force of the stroke alone); with
  contact damping c the work per cycle under y = A sin(w t) is
  4 c A^2 w [(pi/2 - t0)/2 - sin(2 t0)/4], t0 = arcsin(clearance / A), less the onset's
  share c A w cos(t0) w_d / 2 at each of the four contact crossings.
* Describing function against the first harmonic of a steady state (centred and
  off-centre stops), and the small-signal model at rest (inactive, or the contact
  stiffness when the rest position is in contact).
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.analysis.stability.damped_stability import device_lti
from liquidamp.coupled.assembly import Device
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import EndStops, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
WEAK = P.replace(c1=1e-6)  # a dashpot with negligible force: the stops alone
A, F_HZ = 2e-3, 3.0
OPTS = SolverOptions(engine="compiled", rtol=1e-10, samples_per_period=4096)


def test_static_force_is_the_closed_form():
    k, clr, ctr = 2e6, 1e-3, 2e-4
    m = with_effects(get_model("dashpot"), EndStops(k, clr, 500.0, ctr))
    w = 0.01 * clr + 1e-7
    y = np.concatenate([np.linspace(ctr - clr, ctr + clr, 41),
                        ctr + np.linspace(clr + w, 3e-3, 37), ctr - np.linspace(clr + w, 3e-3, 37)])
    F = m.force(0.0, np.zeros((0, y.size)), (y, 0 * y, 0 * y), WEAK)  # at rest: no damping
    u = y - ctr
    expected = np.sign(u) * k * np.maximum(np.abs(u) - clr, 0.0)
    np.testing.assert_allclose(F, expected, rtol=1e-13, atol=1e-9)
    assert np.max(np.abs(F)) > 1e3
    # in the onset the force stays between 0 and the linear law, continuous in value and slope
    yo = ctr + clr + np.linspace(0, w, 11)
    Fo = m.force(0.0, np.zeros((0, 11)), (yo, 0 * yo, 0 * yo), WEAK)
    assert np.all(np.diff(Fo) >= 0) and Fo[0] == 0.0 and Fo[-1] == pytest.approx(k * w)


@pytest.mark.parametrize("engine", ["scipy", "compiled"])
def test_elastic_stop_does_no_net_work_and_damping_the_closed_form(engine):
    k, clr, c = 5e6, 1.2e-3, 800.0
    s = HarmonicStroke(A, F_HZ)
    opts = OPTS.replace(engine=engine)
    power = []
    for cs in (0.0, c):
        m = with_effects(get_model("dashpot"), EndStops(k, clr, cs))
        r = steady_state(m, WEAK, s, options=opts)
        power.append(float(np.sum(r.force * r.stroke_rate)) / (F_HZ * r.time.size))
        assert np.max(r.force) == pytest.approx(k * (A - clr), rel=1e-3)
    elastic_scale = 0.5 * k * (A - clr) ** 2
    assert abs(power[0]) < 1e-9 * elastic_scale
    t0 = math.asin(clr / A)
    w = s.omega
    closed = 4 * c * A**2 * w * ((math.pi / 2 - t0) / 2 - math.sin(2 * t0) / 4)
    # the damping's smoothstep onset (width wd) at each of the 4 contact crossings passes
    # half of c v over wd: c V cos(t0) wd / 2 less per crossing (1.1 % here)
    wd = 0.01 * clr + 1e-7
    onset = 4 * c * A * w * math.cos(t0) * wd / 2
    assert power[1] == pytest.approx(closed - onset, rel=1e-3)
    assert abs(power[1] - closed) > 0.005 * closed


@pytest.mark.parametrize("centre", [0.0, 4e-4])
def test_describing_function_equals_the_first_harmonic(centre):
    e = EndStops(3e6, 1e-3, 1500.0, centre)
    m = with_effects(get_model("dashpot"), e)
    K = dynamic_stiffness(steady_state(m, WEAK, HarmonicStroke(A, F_HZ), options=OPTS)).value
    k, c, b = e.describing_function(A, 2 * math.pi * F_HZ, WEAK)
    predicted = k + 2j * math.pi * F_HZ * c
    # exact up to the onset width (0.01 clearance): a few 1e-4
    assert abs(K - predicted) < 2e-3 * abs(predicted)
    lti = device_lti(Device(m, WEAK), amplitude=A, frequency=F_HZ)
    assert lti.stiffness(F_HZ) == pytest.approx(predicted + 2j * math.pi * F_HZ * WEAK.c_L,
                                                   rel=1e-12)
    if centre == 0.0:  # the dead-zone closed form
        rho = 1e-3 / A
        N = 1 - 2 / math.pi * (math.asin(rho) + rho * math.sqrt(1 - rho**2))
        assert (k, c) == pytest.approx((3e6 * N, 1500.0 * N), rel=1e-14)


def test_small_signal_at_rest_and_errors():
    f = 3.0
    bare = device_lti(Device("full", P)).stiffness(f)
    free = device_lti(Device(with_effects(get_model("full"), EndStops(1e7, 1e-3)), P))
    assert free.stiffness(f) == pytest.approx(bare, rel=1e-6)   # inactive at rest
    touching = device_lti(Device(with_effects(get_model("full"), EndStops(1e7, 1e-3, 0.0,
                                                                           -2e-3)), P))
    assert touching.stiffness(f) - bare == pytest.approx(1e7, rel=1e-5)
    with pytest.raises(ParameterError, match="clearance_m must be >= 0"):
        EndStops(1e6, -1e-3)
    with pytest.raises(ParameterError, match="centre_m must be finite"):
        EndStops(1e6, 1e-3, 0.0, math.nan)
