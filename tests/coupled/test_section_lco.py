"""Typical section (Hodges & Pierce, Jones aerodynamics) with a liquid flutter damper.

Measured (reference design sized by size_flutter_damper, zeta 0.05, full
model eq. 10, airspeed 1.03 x the damped flutter speed):

* pitch port (V_F = 2.1936 b omega_theta): linear critical eigenvalue
  +0.4905 +/- 15.42i 1/s; the time-domain growth rate at 1e-7 m stroke is
  within 0.06 % of it (at 1e-5 m already 5 % lower: the quadratic loss of
  the small device matters from ~1e-5 m).  Below flutter (0.97 V_F) the
  decay rate agrees to 0.005 %.  The describing function has g(Y) falling
  through zero: a stable limit cycle, stroke 1.0524e-3 m (bulk at rest) or
  1.0940e-3 m (cycle-averaged bulk); simulated 1.085e-3 m (settled to
  0.02 %, from 0.85 Y* or from 1e-5 m alike), i.e. 3.1 % and 0.8 %.
  Frequency 2.460 Hz predicted, 2.448 Hz simulated.
* plunge port (V_F = 2.2350): growth rate within 0.02 %.  With B at rest
  g(Y) *rises* with amplitude (the larger c_eq stiffens the Maxwell-like
  device and detunes plunge: no limit cycle predicted), but the time
  domain settles on a limit cycle of 2.835e-3 m plunge: the chamber
  pressures swing by bars and the pressure-dependent bulk modulus softens
  the device.  The cycle-averaged bulk captures it: 3.327e-3 m, 17 % high.
"""

import math

import pytest

from liquidamp.analysis.stability.damped_stability import damped_flutter_analysis
from liquidamp.analysis.stability.lco import (
    predict_section_lco,
    section_critical_mode,
    simulate_section_lco,
)
from liquidamp.analysis.stability.sizing import flutter_damper_device
from liquidamp.structure.hostio import load_section

SECTION = load_section("hodges-pierce")


def _case(port):
    dev, _ = flutter_damper_device("reference", SECTION, port=port, zeta=0.05)
    VF = damped_flutter_analysis(SECTION, {port: dev}).flutter_speed
    return dev, VF


@pytest.fixture(scope="module")
def pitch():
    return _case("pitch")


@pytest.fixture(scope="module")
def plunge():
    return _case("plunge")


def test_damper_raises_flutter_speed(pitch, plunge):
    assert pitch[1] == pytest.approx(2.1936, abs=1e-3)
    assert plunge[1] == pytest.approx(2.2350, abs=1e-3)
    assert min(pitch[1], plunge[1]) > 2.1704  # bare section, Jones


@pytest.mark.parametrize("port,factor", [("pitch", 1.03), ("pitch", 0.97), ("plunge", 1.03)])
def test_small_amplitude_rate_equals_eigenvalue(pitch, plunge, port, factor):
    dev, VF = pitch if port == "pitch" else plunge
    U = SECTION.speed(factor * VF)
    cm = section_critical_mode(SECTION, U, dev, port=port)
    assert (cm.eigenvalue.real > 0.3) == (factor > 1) and abs(cm.eigenvalue.real) > 0.3
    sim = simulate_section_lco(SECTION, U, dev, port=port, initial_stroke=1e-7, t_end=5.0,
                               mode=cm)
    assert sim.growth.rate == pytest.approx(cm.eigenvalue.real, rel=0.05)


def test_pitch_limit_cycle_predicted(pitch):
    dev, VF = pitch
    U = SECTION.speed(1.03 * VF)
    rest = predict_section_lco(SECTION, U, dev, port="pitch", bulk="rest")
    avg = predict_section_lco(SECTION, U, dev, port="pitch")
    assert rest.stable and avg.stable
    assert rest.linear_eigenvalue.real == pytest.approx(0.4905, abs=1e-3)
    assert rest.stroke_amplitude == pytest.approx(1.0524e-3, rel=0.01)
    assert avg.stroke_amplitude == pytest.approx(1.0940e-3, rel=0.01)
    assert avg.host_amplitude == pytest.approx(avg.stroke_amplitude / SECTION.pitch_arm)
    sim = simulate_section_lco(SECTION, U, dev, port="pitch",
                               initial_stroke=0.85 * avg.stroke_amplitude, t_end=12.0)
    assert sim.response.status == "completed"
    assert sim.amplitude_change < 0.01
    assert sim.stroke_amplitude == pytest.approx(avg.stroke_amplitude, rel=0.02)
    assert sim.stroke_amplitude == pytest.approx(rest.stroke_amplitude, rel=0.05)
    assert math.isclose(sim.host_amplitude, sim.stroke_amplitude / SECTION.pitch_arm)


def test_plunge_limit_cycle_needs_bulk_softening(plunge):
    dev, VF = plunge
    U = SECTION.speed(1.03 * VF)
    rest = predict_section_lco(SECTION, U, dev, port="plunge", bulk="rest")
    assert rest.stroke_amplitude is None and rest.real_parts[-1] > rest.real_parts[0] > 0
    avg = predict_section_lco(SECTION, U, dev, port="plunge")
    assert avg.stable and avg.stroke_amplitude == pytest.approx(3.327e-3, rel=0.01)
    sim = simulate_section_lco(SECTION, U, dev, port="plunge", initial_stroke=1e-4,
                               t_end=16.0)
    assert sim.response.status == "completed"
    assert sim.amplitude_change < 0.01
    assert sim.stroke_amplitude == pytest.approx(2.835e-3, rel=0.01)
    assert sim.stroke_amplitude == pytest.approx(avg.stroke_amplitude, rel=0.20)
