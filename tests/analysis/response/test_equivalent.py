"""Equivalent (describing-function) linearization against the nonlinear first harmonic.

Measured tolerances: the table in the docstring of
:mod:`liquidamp.analysis.response.equivalent` (issue #3 report).  Summary, full model
eq. 10 as the judge, ``bulk="auto"`` (averaged bulk modulus):

* the quadratic-loss describing function alone (model inertial_2state,
  constant B): <= 2 % at 1-3 mm, 0.5-20 Hz (reference);
* full model at 0.5-2 Hz: <= 2 % at 1 mm, <= 10 % at 2-3 mm (spring preset
  30 % at 3 mm);
* full model at 5-20 Hz: 2-19 % at 1 mm, up to 25-50 % at 2-3 mm (chambers
  stiffen; a fold/jump near resonance at 3 mm for device_a).

The spot checks below reproduce table entries to +-0.01 and hold them to a
tolerance; points were picked for runtime.
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.response.equivalent import (
    equivalent_linearization,
    equivalent_stiffness,
    equivalent_transfer_function,
    friction_df,
    linear_range_amplitude,
    quadratic_loss_df,
)
from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.analysis.response.linear import flow_tf, inertial_2state_tf, tf_frequency_response
from liquidamp.analysis.response.stiffness import nonlinear_stiffness
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.errors import ParameterError
from liquidamp.structure.testmachine import HarmonicStroke


def test_quadratic_df_is_energy_balance():
    th = np.linspace(0, 2 * np.pi, 20001)[:-1]
    q_hat, c2 = 2.0e-5, 5.0e14
    q = q_hat * np.sin(th)
    e_nl = np.mean(c2 * q * np.abs(q) * q)          # mean power of the quadratic loss
    c = quadratic_loss_df(0.0, c2, q_hat)
    assert np.mean(c * q * q) == pytest.approx(e_nl, rel=1e-9)


def test_friction_df_is_energy_balance():
    Ff, f, Y = 30.0, 2.0, 1e-3
    w = 2 * np.pi * f
    c = friction_df(Ff, f, Y)
    # energy per cycle: 4 Ff Y (friction) = pi c w Y^2 (viscous)
    assert math.pi * c * w * Y**2 == pytest.approx(4 * Ff * Y, rel=1e-12)


def test_fixed_point_is_consistent_and_small_amplitude_is_linear():
    p = preset("reference")
    for f in (0.5, 5.0, 20.0):
        e = equivalent_linearization(p, f, 2e-3, "inertial_2state")
        q = abs(tf_frequency_response(flow_tf(p, c1=e.c_eq), [f])[0]) * 2e-3
        assert e.flow_amplitude == pytest.approx(q, rel=1e-10)
        assert e.c_eq == pytest.approx(quadratic_loss_df(p.c1, p.c2, q), rel=1e-10)
        small = equivalent_stiffness(p, f, 1e-10, "full")
        k_lin = tf_frequency_response(inertial_2state_tf(p), [f])[0]
        assert abs(small.value / k_lin - 1) < 1e-5


def test_linear_range_amplitude_sets_the_loss_fraction():
    p = preset("damper")
    for f in (0.5, 20.0):
        Y = linear_range_amplitude(p, f, 0.05)
        e = equivalent_linearization(p, f, Y, "inertial_2state")
        assert 1.0 < e.c_eq / p.c1 < 1.05


def test_transfer_function_signals_and_friction():
    p = preset("reference").replace(friction_N=30.0)
    tf = equivalent_transfer_function(p, amplitude=1e-3, frequency=2.0)
    assert tf.input_labels == ["stroke"] and tf.output_labels == ["force"]
    e = equivalent_linearization(p, 2.0, 1e-3, "inertial_2state")
    k = tf_frequency_response(tf, [2.0])[0]
    assert k == pytest.approx(e.stiffness.value, rel=1e-12)
    e0 = equivalent_linearization(p.replace(friction_N=0.0), 2.0, 1e-3, "inertial_2state")
    assert (e.stiffness.value - e0.stiffness.value).imag == pytest.approx(4 * 30.0 / math.pi /
                                                                          1e-3, rel=1e-9)
    with pytest.raises(TypeError):
        equivalent_transfer_function(p, 1e-3, 2.0)   # keyword-only: easy to swap


@pytest.mark.parametrize("f,Y", [(0.5, 1e-3), (5.0, 1e-3), (5.0, 3e-3), (20.0, 2e-3)])
def test_quadratic_loss_df_against_nonlinear_eq18(f, Y):
    p = preset("reference")
    nl = dynamic_stiffness(steady_state("inertial_2state", p, HarmonicStroke(Y, f)))
    eq = equivalent_stiffness(p, f, Y, "inertial_2state")
    assert abs(eq.value / nl.value - 1) < 0.02


def test_friction_against_nonlinear():
    p = preset("damper").replace(friction_N=30.0)
    nl = dynamic_stiffness(steady_state("inertial_2state", p, HarmonicStroke(1e-3, 2.0)))
    eq = equivalent_stiffness(p, 2.0, 1e-3, "inertial_2state")
    assert abs(eq.value / nl.value - 1) < 0.01


# (preset, frequency [Hz], amplitude [m], measured error, tolerance)
FULL_POINTS = [
    ("reference", 2.0, 1e-3, 0.011, 0.03),
    ("reference", 5.0, 1e-3, 0.071, 0.10),
    ("reference", 20.0, 3e-3, 0.241, 0.30),
    ("paper_initial", 0.5, 3e-3, 0.002, 0.01),
    ("spring", 2.0, 1e-3, 0.020, 0.03),
    ("spring", 5.0, 2e-3, 0.105, 0.15),
]


@pytest.mark.slow
@pytest.mark.parametrize("name,f,Y,measured,tol", FULL_POINTS)
def test_full_model_within_measured_tolerance(name, f, Y, measured, tol):
    p = preset(name)
    nl = nonlinear_stiffness(p, [f], [Y], model="full").curve(0).point(0)
    e = equivalent_linearization(p, f, Y, "full")
    assert e.valid
    err = abs(e.stiffness.value / nl.value - 1)
    assert err < tol
    assert err == pytest.approx(measured, abs=0.01)  # the table entry is reproducible
    # and the equivalent at rest bulk modulus is much worse where the chambers stiffen
    rest = equivalent_linearization(p, f, Y, "full", bulk="rest")
    if f >= 5.0:
        assert abs(rest.stiffness.value / nl.value - 1) > 2 * err


def test_cavitation_is_reported_not_hidden():
    p = preset("inerter")
    e = equivalent_linearization(p, 5.0, 3e-3, "full")
    assert not e.valid
    assert any("cavitat" in w for w in e.warnings)
    ok = equivalent_linearization(p, 0.5, 1e-4, "full")
    assert ok.valid and ok.warnings == ()


def test_bad_inputs():
    p = preset("reference")
    with pytest.raises(ParameterError, match="frequency"):
        equivalent_linearization(p, -1.0, 1e-3)
    with pytest.raises(ParameterError, match="0.025"):
        equivalent_linearization(p, 1.0, 0.03)
    with pytest.raises(ParameterError, match="bulk"):
        equivalent_linearization(p, 1.0, 1e-3, bulk="mean")
