"""Stability margins with confidence and partial degradation (issue 22, items 2, 3, 5)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from liquidamp.analysis.stability.ground_resonance import (
    coleman_eigenvalues,
    ground_resonance_sweep,
    rpm_to_rad_s,
)
from liquidamp.analysis.stability.margins import (
    FitUncertainty,
    MarginOptions,
    _damping_ratio,
    changed_device,
    confidence_z,
    degradation_comparison,
    flutter_margin,
    ground_resonance_margin,
    host_viscous_device,
)
from liquidamp.coupled.assembly import Device
from liquidamp.device import preset
from liquidamp.errors import ParameterError
from liquidamp.structure.hostio import load_rotor, load_section

RPM = np.linspace(180.0, 330.0, 7)


@pytest.fixture(scope="module")
def rotor():
    return load_rotor("hammond1974")


def _fit(values, stderr, corr, log=None):
    se = np.asarray(stderr, float)
    cov = (np.outer(se, se) * np.asarray(corr, float)).tolist()
    out = {"varied": ["inv_gamma1", "c1"], "values": list(values), "stderr": list(se),
           "covariance": cov}
    if log is not None:
        out["log"] = log
    return out


def test_fit_covariance_is_carried_back_to_the_log_space_of_the_fit():
    """The device file's covariance is linear (s_i = v_i sd_log_i); the log-space one has
    sd_log = s / v and the same correlation; a linear parameter is left as it is."""
    u = FitUncertainty.from_fit(_fit([0.5, 4.0], [0.05, 0.2], [[1, -0.6], [-0.6, 1]]))
    sd = np.sqrt(np.diag(u.covariance))
    assert sd == pytest.approx([0.1, 0.05], rel=1e-12)
    assert u.covariance[0, 1] / (sd[0] * sd[1]) == pytest.approx(-0.6, rel=1e-12)
    lin = FitUncertainty.from_fit(_fit([0.5, 4.0], [0.05, 0.2], np.eye(2), [True, False]))
    assert lin.covariance[1, 1] == pytest.approx(0.04, rel=1e-12)
    # principal axes reproduce the covariance: A A^T = C
    A = u.axes()
    assert A @ A.T == pytest.approx(u.covariance, rel=1e-10, abs=1e-18)
    with pytest.raises(ParameterError, match="not finite"):
        FitUncertainty.from_fit(_fit([0.5, 4.0], [math.nan, 0.2], np.eye(2)))


def test_apply_moves_a_multiplier_by_exp_delta():
    d = Device("full", preset("reference"), "ref")
    u = FitUncertainty.from_fit(_fit([0.5, 4.0], [0.05, 0.2], np.eye(2)))
    moved = u.apply(d, [0.0, math.log(1.5)])
    assert moved.params.c1 / d.params.c1 == pytest.approx(1.5, rel=1e-12)
    assert moved.params.inv_gamma1 == d.params.inv_gamma1
    assert changed_device(d, "inv_gamma1", 2.0).params.inv_gamma1 == pytest.approx(
        2.0 * d.params.inv_gamma1, rel=1e-12)


def test_fraction_zero_is_intact_and_one_is_the_inoperative_floquet_result(rotor):
    """Degraded damper: f = 0 gives the all-working (Coleman) answer, f = 1 the existing
    inoperative-damper Floquet sweep of the host (another route: the host's own
    periodic matrices), band edges and all."""
    W = rpm_to_rad_s(RPM)
    intact = ground_resonance_margin(rotor, W, degraded=(1, 0.0))
    ref = ground_resonance_sweep(rotor, W, "coleman")
    assert intact.max_real_part == pytest.approx(ref.max_real_part, abs=1e-9)
    failed = ground_resonance_margin(rotor, W, degraded=(1, 1.0))
    host = ground_resonance_sweep(rotor.with_inoperative_damper(1), W, "floquet")
    assert failed.max_real_part == pytest.approx(host.max_real_part, abs=1e-6)
    (a, b), = host.unstable_ranges_rpm
    (ea, eb), = failed.band_edges()
    assert (ea.value, eb.value) == pytest.approx((a, b), abs=1e-3)
    # the degraded answer lies between the two, monotone in f
    half = ground_resonance_margin(rotor, W, degraded=(1, 0.5))
    z = [m.min_damping_ratio.value for m in (intact, half, failed)]
    assert z[0] > z[1] > z[2]


def test_smeared_is_the_intact_rotor_with_damping_scaled_by_one_minus_f_over_n(rotor):
    """Closed form: the smeared rotor has every lag damper at c (1 - f/N); its answer is the
    host's own Coleman eigenvalues with those dampers (no device in the loop)."""
    f, N = 0.6, rotor.n_blades
    W = rpm_to_rad_s(RPM)
    comp = degradation_comparison(rotor, W, fraction=f, blade=2)
    c = rotor.blade_damping[0] * (1.0 - f / N)
    scaled = rotor.with_lag_dampers([c] * N)
    for w, zeta in zip(W, comp.smeared.damping_ratio, strict=True):
        assert zeta == pytest.approx(_damping_ratio(coleman_eigenvalues(scaled, w)),
                                     abs=1e-10)
    zi = comp.intact.min_damping_ratio.value
    ratio = (zi - comp.smeared.min_damping_ratio.value) / (
        zi - comp.floquet.min_damping_ratio.value)
    assert comp.loss_ratio == pytest.approx(ratio, rel=1e-12)
    assert 0.0 < comp.loss_ratio < 1.0  # smearing misses part of the loss Floquet finds
    d = comp.to_dict()
    assert d["loss_ratio_smeared_to_floquet"] == comp.loss_ratio
    assert d["floquet"]["method"].startswith("none")


def test_linearized_interval_matches_re_solving_the_perturbed_device(rotor):
    """Two routes to an edge's and the minimum damping ratio's standard deviation: the
    implicit-function / envelope secants at the answer's point against re-running the
    whole sweep (Brent edges, refined minimum) on the device moved along each principal
    axis by +-1 sd."""
    r = rotor.replace(blade=rotor.blade.replace(damper_arm=1.0))
    dev = Device("full", preset("paper_calibrated"), "pc")
    u = FitUncertainty.from_fit(_fit([1.0, 1.0], [0.01, 0.03], [[1, -0.5], [-0.5, 1]]))
    W = rpm_to_rad_s(np.linspace(150.0, 350.0, 11))
    m = ground_resonance_margin(r, W, dev, u)
    (s, e), = m.band_edges()
    var = np.zeros(3)
    for a in u.axes().T:
        out = []
        for sign in (+1.0, -1.0):
            mm = ground_resonance_margin(r, W, u.apply(dev, sign * a))
            (ps, pe), = mm.band_edges()
            out.append([ps.value, pe.value, mm.min_damping_ratio.value])
        var += (0.5 * (np.array(out[0]) - np.array(out[1]))) ** 2
    z = confidence_z(0.95)
    hw = z * np.sqrt(var)
    assert s.half_width == pytest.approx(hw[0], rel=0.02)
    assert e.half_width == pytest.approx(hw[1], rel=0.02)
    assert m.min_damping_ratio.half_width == pytest.approx(hw[2], rel=0.02)
    assert s.half_width > 0.1  # rpm: a real interval, not a zero
    assert m.to_dict()["unstable_ranges [rpm]"][0]["may_vanish"] is False


def test_flutter_speed_interval_and_a_band_that_may_vanish():
    """Flutter: the interval of the flutter speed against re-solving the perturbed device;
    a band whose peak interval reaches zero is flagged, a stable hump that may cross is
    listed."""
    sec = dataclasses.replace(load_section("hodges-pierce"), span=10.0, semichord=1.0)
    dev = Device("full", preset("paper_calibrated"), "pc")
    u = FitUncertainty.from_fit(_fit([1.0, 1.0], [0.02, 0.05], np.eye(2)))
    V = np.linspace(2.0, 2.6, 7)
    m = flutter_margin(sec, V, dev, u)
    var = 0.0
    for a in u.axes().T:
        vp, vm = (flutter_margin(sec, V, u.apply(dev, s * a)).flutter_speed.value
                  for s in (1.0, -1.0))
        var += (0.5 * (vp - vm)) ** 2
    assert m.flutter_speed.half_width == pytest.approx(confidence_z(0.95) * math.sqrt(var),
                                                       rel=0.02)
    d = m.to_dict()
    assert d["flutter_speed"]["interval"][0] < d["flutter_speed"]["value"] < \
        d["flutter_speed"]["interval"][1]
    assert "delta method" in d["method"] and d["confidence"] == 0.95


def test_a_band_that_may_appear_within_the_interval_is_told(rotor):
    """Through a 1.4 m arm the device holds the rotor just stable (largest real part about
    -0.18 1/s at 244 rpm): with c1 known to 5 % nothing is flagged; with 20 % the hump's
    peak interval reaches above zero and the band is listed as possible; through a 1.0 m
    arm the band is there and, with 20 %, may vanish."""
    dev = Device("full", preset("paper_calibrated"), "pc")
    W = rpm_to_rad_s(np.linspace(150.0, 350.0, 11))
    r = rotor.replace(blade=rotor.blade.replace(damper_arm=1.4))
    tight = FitUncertainty.from_fit(_fit([1.0, 1.0], [1e-6, 0.05], np.eye(2)))
    loose = FitUncertainty.from_fit(_fit([1.0, 1.0], [1e-6, 0.2], np.eye(2)))
    m = ground_resonance_margin(r, W, dev, tight)
    assert m.bands == () and m.possible_bands == ()
    m = ground_resonance_margin(r, W, dev, loose)
    (at, peak), = m.possible_bands
    assert peak.value < 0.0 < peak.high and 230.0 < at * m.to_unit < 260.0
    assert m.to_dict()["possible_bands"][0]["at [rpm]"] == pytest.approx(at * m.to_unit)
    r1 = rotor.replace(blade=rotor.blade.replace(damper_arm=1.0))
    band, = ground_resonance_margin(r1, W, dev, tight).bands
    assert not band.may_vanish
    band, = ground_resonance_margin(r1, W, dev, FitUncertainty.from_fit(
        _fit([1.0, 1.0], [1e-6, 0.6], np.eye(2)))).bands
    assert band.peak.low < 0.0 and band.may_vanish


def test_degraded_device_rotor_and_changed_parameter(rotor):
    """With the liquid device: a blade at f = 1 gives the device's inoperative-damper
    Floquet exponents; a blade whose device has c1 x1 (Floquet) the intact Coleman ones."""
    from liquidamp.analysis.stability.damped_stability import rotor_device_eigenvalues
    from liquidamp.analysis.stability.margins import _RotorProblem

    r = rotor.replace(blade=rotor.blade.replace(damper_arm=1.5))
    dev = Device("full", preset("paper_calibrated"), "pc")
    w = rpm_to_rad_s(250.0)
    failed = _RotorProblem(r, dev, None, [0.0, 1.0, 1.0, 1.0]).eig(w)
    ref = rotor_device_eigenvalues(r, w, dev, inoperative=[1], method="floquet")
    assert np.sort(failed.real) == pytest.approx(np.sort(ref.real), abs=1e-9)
    same = _RotorProblem(r, dev, None, [1.0] * 4, (1, changed_device(dev, "c1", 1.0)))
    assert not same.symmetric
    assert same.g(w) == pytest.approx(_RotorProblem(r, dev, None, [1.0] * 4).g(w), abs=1e-6)


def test_bad_input_is_refused_before_work(rotor):
    with pytest.raises(ParameterError, match="confidence"):
        MarginOptions(confidence=1.5)
    with pytest.raises(ParameterError, match="degradation fraction"):
        ground_resonance_margin(rotor, rpm_to_rad_s(RPM), degraded=(1, 1.2))
    with pytest.raises(ParameterError, match="varies no parameter"):
        FitUncertainty.from_fit({"varied": [], "values": [], "stderr": [], "covariance": []})
    with pytest.raises(ParameterError, match="increasing"):
        ground_resonance_margin(rotor, [30.0, 20.0])
    assert host_viscous_device(rotor).params.c == pytest.approx(4067.5 / 0.25 ** 2)


def test_sampling_and_linearized_intervals_agree_where_the_answers_are_nearly_linear(rotor):
    """Two routes to the same spread: 150 draws of the device (whole analyses) against the
    delta method (Coleman, 1 m arm, c1 to 2 %): standard deviations within 20 % (the
    sampling error of a standard deviation from 150 draws is about 6 %)."""
    from liquidamp.analysis.stability.margin_sampling import sampled_margin

    r = rotor.replace(blade=rotor.blade.replace(damper_arm=1.0))
    dev = Device("full", preset("paper_calibrated"), "pc")
    u = FitUncertainty.from_fit(_fit([1.0, 1.0], [0.005, 0.02], [[1, 0.3], [0.3, 1]]))
    W = rpm_to_rad_s(np.linspace(150.0, 350.0, 7))
    lin = ground_resonance_margin(r, W, dev, u)
    smp = sampled_margin(lambda d: ground_resonance_margin(r, W, d), dev, u, samples=150)
    (s, e, share), = smp.edges
    band, = lin.bands
    assert share == 1.0
    assert s.std == pytest.approx(band.start.std, rel=0.2)
    assert e.std == pytest.approx(band.end.std, rel=0.2)
    assert smp.min_damping_ratio.std == pytest.approx(lin.min_damping_ratio.std, rel=0.2)
    assert s.low < band.start.value < s.high
