"""The two-frequency stroke on the test machine: both engines, the common period."""

import math

import numpy as np
import pytest

from liquidamp.coupled.testrig import simulate, steady_state
from liquidamp.device import preset
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke, TwoFrequencyStroke


def test_stroke_values_and_period():
    s = TwoFrequencyStroke(0.002, 4.2, 0.0005, 1.26, offset=1e-4, phase1=0.3, phase2=-0.7)
    t = np.linspace(0.0, 1.0, 7)
    y, v, a = s(t)
    h1 = HarmonicStroke(0.002, 4.2, phase=0.3)(t)
    h2 = HarmonicStroke(0.0005, 1.26, offset=1e-4, phase=-0.7)(t)
    for got, p, q in zip((y, v, a), h1, h2, strict=True):
        assert np.allclose(got, p + q, rtol=0, atol=1e-15)
    assert s.ratio == (10, 3) and s.period == pytest.approx(10 / 4.2, rel=1e-15)
    assert s.shortest_period == pytest.approx(1 / 4.2)
    assert s(0.5)[0] == pytest.approx(float(y[3]), abs=1e-16)  # scalar and array agree
    irr = TwoFrequencyStroke(0.002, 4.2, 0.0005, 4.2 / math.sqrt(2))
    assert irr.common_period is None
    with pytest.raises(ParameterError, match="has no common period"):
        _ = irr.period
    with pytest.raises(ParameterError, match="not both 0"):
        TwoFrequencyStroke(0.0, 4.2, 0.0, 1.26)
    with pytest.raises(ParameterError, match=r"stroke frequency2 must lie in \(0, 1e4\]"):
        TwoFrequencyStroke(0.001, 4.2, 0.001, 2e4)


def test_compiled_engine_runs_it_as_scipy_does():
    p = preset("paper_calibrated")
    s = TwoFrequencyStroke(0.002, 4.2, 0.0005, 1.26, phase2=0.4)
    t = np.linspace(0.0, 1.0, 201)
    a = simulate("full", p, s, 1.0, t_eval=t, options=SolverOptions(engine="compiled"))
    b = simulate("full", p, s, 1.0, t_eval=t, options=SolverOptions(engine="scipy"))
    assert np.max(np.abs(a.force - b.force)) < 1e-5 * np.max(np.abs(b.force))
    assert np.allclose(a.stroke, s(t)[0])


def test_steady_state_over_the_common_period():
    p = preset("device_a")
    s = TwoFrequencyStroke(0.002, 4.2, 0.0005, 1.26)
    r = steady_state("full", p, s)
    assert r.status == "steady" and r.time[-1] < s.period
    assert r.mass_error < 1e-9
    # one more common period from the last state repeats the force
    x_end = simulate("full", p, s, s.period, x0=r.states[:, 0], t_eval=r.time).force
    assert np.max(np.abs(x_end - r.force)) < 1e-5 * np.max(np.abs(r.force))
    with pytest.raises(ParameterError, match="has no common period"):
        steady_state("full", p, TwoFrequencyStroke(0.002, 4.2, 0.0005, 4.2 / math.sqrt(3)))
