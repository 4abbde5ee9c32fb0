"""Direction-dependent friction levels and smooth friction's transition exponent (issue #12).

Closed forms under y = A sin(w t) on a dashpot whose own force is negligible (c1 = 1e-6):

* Coulomb friction sliding at +F_c forward and -q F_c in reverse dissipates
  2 A F_c (1 + q) per cycle and reads a mean force (1 - q) F_c / 2; its describing
  function's damping is 2 (1 + q) F_c / (pi w A).
* Behind a dead band of half-width g the asymmetric friction still reads zero in the gap
  (unlike a constant offset) and dissipates 2 (A - g) F_c (1 + q).
* The bristle law dz/dy = s (1 - z |z|^(n-1)) (sliding forward from z = 0, s = sigma0 / F_c,
  no Stribeck dip) gives z = 1 - exp(-s y) for n = 1 and z = tanh(s y) for n = 2; for a
  large n it tends to the elastic-plastic min(s y, 1).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import CoulombFriction, Freeplay, SmoothFriction, with_effects
from liquidamp.device.kernels import _lugre_dz_dv, friction_level, lugre_rate
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

A, G, FC, F_HZ, Q = 2e-3, 3e-4, 100.0, 2.0, 0.6
P = preset("reference").replace(c1=1e-6)
S = HarmonicStroke(A, F_HZ)


def _steady(model):
    r = steady_state(model, P, S, options=SolverOptions(engine="compiled", rtol=1e-8))
    assert r.status == "steady"
    return r


def _work(r):
    return float(np.sum(r.force * r.stroke_rate)) / (F_HZ * r.time.size)


def test_asymmetric_coulomb_loop_energy_mean_and_describing_function():
    r = _steady(with_effects(get_model("dashpot"), CoulombFriction(FC, reverse_ratio=Q)))
    assert _work(r) == pytest.approx(2 * A * FC * (1 + Q), rel=2e-3)
    assert float(np.mean(r.force)) == pytest.approx((1 - Q) * FC / 2, rel=0.02)
    sliding = np.abs(r.stroke_rate) > 1e-3 * r.stroke_rate.max()
    level = np.where(r.stroke_rate > 0, FC, -Q * FC)
    assert np.max(np.abs(r.force[sliding] - level[sliding])) < 1e-3 * FC
    w = 2 * math.pi * F_HZ
    k, c, b = CoulombFriction(FC, reverse_ratio=Q).describing_function(A, w, None)
    # the first harmonic of the loop measured, against the closed form
    F1 = 2 * np.mean(r.force * np.exp(-1j * w * r.time))
    assert c == pytest.approx(2 * (1 + Q) * FC / (math.pi * w * A), rel=1e-12)
    assert abs(F1) == pytest.approx(c * w * A, rel=0.01)


def test_asymmetric_friction_behind_a_dead_band_reads_zero_in_the_gap():
    m = with_effects(get_model("dashpot"), Freeplay(G),
                     CoulombFriction(FC, reverse_ratio=Q, location="piston"))
    r = _steady(m)
    assert _work(r) == pytest.approx(2 * (A - G) * FC * (1 + Q), rel=0.01)
    y, v, F = r.stroke, r.stroke_rate, r.force
    delta = 0.05 * G + 1e-7
    gap = ((v < 0) & (y > A - 2 * G + delta)) | ((v > 0) & (y < -A + 2 * G - delta))
    assert gap.sum() > 100 and np.max(np.abs(F[gap])) < 0.01 * FC


def test_smooth_friction_reverse_ratio_scales_the_reverse_branch_and_its_describing_function():
    sigma0 = 1e7
    sym = _steady(with_effects(get_model("dashpot"), SmoothFriction(FC, sigma0)))
    asym = _steady(with_effects(get_model("dashpot"), SmoothFriction(FC, sigma0,
                                                                     reverse_ratio=Q)))
    neg = sym.force < 0
    np.testing.assert_allclose(asym.force[neg], Q * sym.force[neg], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(asym.force[~neg], sym.force[~neg], rtol=1e-6, atol=1e-6)
    w = 2 * math.pi * F_HZ
    c_sym = SmoothFriction(FC, sigma0).describing_function(A, w, None)[1]
    c_asym = SmoothFriction(FC, sigma0, reverse_ratio=Q).describing_function(A, w, None)[1]
    assert c_asym / c_sym == pytest.approx((1 + Q) / 2, rel=1e-3)


@pytest.mark.parametrize("n, closed", [
    (1.0, lambda sy: 1 - np.exp(-sy)),
    (2.0, np.tanh),
    (20.0, lambda sy: np.minimum(sy, 1.0)),
])
def test_transition_exponent_shapes_the_pre_sliding(n, closed):
    sigma0, v = 1e6, 0.01
    s = sigma0 / FC
    y = np.linspace(0, 4 / s, 81)
    sol = solve_ivp(lambda t, z: [lugre_rate(v, z[0], FC, sigma0, 0.005, 1.0, n)],
                    (0, y[-1] / v), [0.0], t_eval=y / v, rtol=1e-10, atol=1e-12)
    tol = 1e-6 if n < 20 else 0.04  # n = 20 rounds the corner at s y = 1 by a few %
    np.testing.assert_allclose(sol.y[0], closed(s * y), atol=tol)


def test_bristle_jacobian_matches_finite_differences():
    args = (100.0, 1e6, 0.005, 1.5, 3.0)
    for v, z in ((0.004, 0.7), (-0.02, -0.3), (0.01, -0.9)):
        dz, dv = _lugre_dz_dv(v, z, *args)
        h = 1e-7
        fz = (lugre_rate(v, z + h, *args) - lugre_rate(v, z - h, *args)) / (2 * h)
        fv = (lugre_rate(v + h * 1e-2, z, *args) - lugre_rate(v - h * 1e-2, z, *args)) / (2e-2 * h)
        assert dz == pytest.approx(fz, rel=1e-6)
        assert dv == pytest.approx(fv, rel=1e-5)


def test_friction_shape_parameters_are_checked():
    assert friction_level(-2.0, 0.5) == -1.0 and friction_level(2.0, 0.5) == 2.0
    with pytest.raises(ParameterError, match=r"reverse_ratio must be in \[0.1, 10\].*got 0"):
        CoulombFriction(10.0, reverse_ratio=0.0)
    with pytest.raises(ParameterError, match=r"transition_exponent must be in \[1, 20\].*0.5"):
        SmoothFriction(10.0, transition_exponent=0.5)
    with pytest.raises(ParameterError, match="reverse_ratio must be finite"):
        SmoothFriction(10.0, reverse_ratio=float("nan"))
