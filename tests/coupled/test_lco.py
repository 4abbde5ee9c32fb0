"""Time domain against the linear view: growth rates and limit-cycle amplitudes.

Measured (Hammond rotor, devices sized by size_lag_damper, full model eq. 10):
* Device A, all dampers working, 230 rpm (linearly unstable, +0.208 1/s):
  time-domain growth rate at 2.5 um stroke within 0.3 % of the eigenvalue;
  limit cycle predicted by the describing function 2.731e-3 rad against
  2.748e-3 rad simulated (30 s, settled to 0.8 %): 0.6 %.  Tolerance here 5 %
  (shorter runs that have not fully settled).
* Reference design, damper 1 failed, 250 rpm (Floquet, +0.32 1/s): growth
  rate within 5 %.
"""

import math

import pytest

from liquidamp.analysis.stability.lco import critical_mode, growth_rate, predict_lco, simulate_lco
from liquidamp.analysis.stability.sizing import size_lag_damper
from liquidamp.coupled.assembly import Device
from liquidamp.device import preset
from liquidamp.structure.hostio import load_rotor

ROTOR = load_rotor("hammond1974")
RPM = math.pi / 30


@pytest.fixture(scope="module")
def device_a():
    return Device("full", size_lag_damper(preset("device_a"), ROTOR).params, "device_a")


def test_small_amplitude_growth_equals_eigenvalue(device_a):
    W = 230 * RPM
    cm = critical_mode(ROTOR, W, device_a)
    assert cm.eigenvalue.real == pytest.approx(0.2077, abs=1e-3)
    sim = simulate_lco(ROTOR, W, device_a, initial_lag=1e-5, t_end=6.0, mode=cm)
    assert sim.growth.rate == pytest.approx(cm.eigenvalue.real, rel=0.05)


def test_small_amplitude_decay_equals_eigenvalue():
    dev = Device("full", size_lag_damper(preset("reference"), ROTOR).params, "reference")
    W = 300 * RPM
    cm = critical_mode(ROTOR, W, dev)
    assert cm.eigenvalue.real < -0.05
    sim = simulate_lco(ROTOR, W, dev, initial_lag=1e-5, t_end=5.0, mode=cm)
    assert sim.growth.rate == pytest.approx(cm.eigenvalue.real, rel=0.05)


def test_growth_with_failed_damper_floquet():
    dev = Device("full", size_lag_damper(preset("reference"), ROTOR).params, "reference")
    W = 250 * RPM
    cm = critical_mode(ROTOR, W, dev, inoperative=[1])
    assert cm.method == "floquet" and cm.eigenvalue.real > 0.2
    sim = simulate_lco(ROTOR, W, dev, inoperative=[1], initial_lag=1e-5, t_end=5.0, mode=cm)
    assert sim.growth.rate == pytest.approx(cm.eigenvalue.real, rel=0.05)


def test_limit_cycle_amplitude_predicted(device_a):
    W = 230 * RPM
    pred = predict_lco(ROTOR, W, device_a)
    assert pred.stable
    assert pred.lag_amplitude == pytest.approx(2.731e-3, rel=0.01)
    sim = simulate_lco(ROTOR, W, device_a, initial_lag=0.85 * pred.lag_amplitude, t_end=12.0)
    assert sim.response.status == "completed"
    assert sim.lag_amplitude == pytest.approx(pred.lag_amplitude, rel=0.05)


def test_growth_rate_fit_closed_form():
    import numpy as np

    t = np.linspace(0.0, 8.0, 1601)
    fit = growth_rate(t, np.exp(0.25 * t) * np.cos(7.0 * t + 0.3))
    assert fit.rate == pytest.approx(0.25, abs=1e-4)


def test_default_run_takes_the_compiled_rotor_route_with_the_same_answer(device_a):
    """The default options pick the compiled DOP853 where the system allows it."""
    import numpy as np

    from liquidamp.coupled.assembly import Device, compiled_support, rotor_system, viscous
    from liquidamp.device import preset
    from liquidamp.options import SolverOptions

    W = 230.0 * 2.0 * math.pi / 60.0
    assert compiled_support(rotor_system(ROTOR, W, device_a)) is None
    assert compiled_support(rotor_system(ROTOR, W, viscous(5e4))) is None  # compiled too
    assert "stroke acceleration" in compiled_support(
        rotor_system(ROTOR, W, Device("inerter", preset("inerter"))))
    cm = critical_mode(ROTOR, W, device_a)
    fast = simulate_lco(ROTOR, W, device_a, initial_lag=1e-3, t_end=2.0, mode=cm)
    ref = simulate_lco(ROTOR, W, device_a, initial_lag=1e-3, t_end=2.0, mode=cm,
                       options=SolverOptions(method="DOP853", rtol=1e-7))
    assert fast.response.time.shape == ref.response.time.shape
    scale = np.max(np.abs(ref.response.host_states))
    assert np.max(np.abs(fast.response.host_states - ref.response.host_states)) < 1e-10 * scale
    assert fast.lag_amplitude == pytest.approx(ref.lag_amplitude, rel=1e-9)
