"""Records of dampers outside the device family (session 12, issue #19 items 4-6): the
default commands read, check and judge them honestly."""

import argparse

import numpy as np
import pytest

from liquidamp.analysis.measured.records import Record
from liquidamp.commands.calibrate import checked
from liquidamp.device import preset
from liquidamp.errors import DataFileError


def _power_law_damper(stroke=0.050, freq=0.5, alpha=0.3, fs=200.0):
    """A building fluid-viscous damper F = C |v|^alpha sign v + k y (Symans et al. 2008):
    400 kN at 0.25 m/s, a 160 kN/m accumulator spring, 50 mm stroke."""
    t = np.arange(int(4 / freq * fs)) / fs
    y = stroke * np.sin(2 * np.pi * freq * t)
    v = stroke * 2 * np.pi * freq * np.cos(2 * np.pi * freq * t)
    F = 400e3 / 0.25 ** alpha * np.abs(v) ** alpha * np.sign(v) + 1.6e5 * y
    F = F + np.random.default_rng(3).normal(0.0, 1e3, t.size)
    return Record.from_arrays(t, y, F, source="fvd.csv", first_line=2)


def test_long_stroke_passes_the_checks_unless_the_chambers_are_held():
    """A 50 mm stroke is twice the paper device's chamber end (V0/A_p = 25 mm): by default
    (--sizing auto) the start stretches the chambers to the records, so the stroke is no
    problem of the record; with --sizing preset the device keeps its chambers and the
    stroke is refused with its line, as before."""
    rec = _power_law_damper()
    assert np.max(np.abs(rec.displacement)) > 1.9 * preset("paper_initial").stroke_limit
    args = argparse.Namespace(outliers="refuse", sizing="auto")
    cal, val = checked([rec], [], args, preset("paper_initial"), "calibrate")
    assert cal[0] is rec and val == []
    args.sizing = "preset"
    with pytest.raises(DataFileError, match=r"fvd.csv, line \d+ \(t = .* s\): displacement "
                       r"[+-]50 mm from the mid-position, past the chamber end at 25 mm"):
        checked([rec], [], args, preset("paper_initial"), "calibrate")


def _dahl_spring(fs=500.0, freq=1.0, cycles=3, fc=200.0, sigma=2e6, k=2e4, noise=2.0):
    """A Dahl (1968) friction element beside a spring: dF_f/dy = sigma (1 - F_f/Fc sgn v),
    integrated exactly per sample (F_f relaxes exponentially towards Fc sgn v in the
    stroke), no fluid at all."""
    t = np.arange(int(cycles * fs / freq)) / fs
    y = 0.01 * np.sin(2 * np.pi * freq * t)
    ff = np.zeros_like(y)
    for i in range(1, y.size):
        dy = y[i] - y[i - 1]
        target = fc * np.sign(dy)
        ff[i] = target + (ff[i - 1] - target) * np.exp(-sigma * abs(dy) / fc)
    F = ff + k * y + np.random.default_rng(7).normal(0.0, noise, t.size)
    return Record.from_arrays(t, y, F, source="dahl.csv", first_line=2)


def test_a_converged_fit_far_above_the_noise_says_so():
    """A fit the optimizer calls converged may still leave structure: the summary leads with
    ABOVE THE NOISE where the calibration NRMSE is more than twice the records' noise floor
    (the diagnosis's structure factor), and a model at the noise floor is not so labelled."""
    from liquidamp.analysis.measured.calibration import FitSpec, calibrate
    from liquidamp.analysis.measured.synthetic import synthetic_record

    rec = _dahl_spring()
    res = calibrate([rec], spec=FitSpec.default(vary=("c1",)), max_nfev=4, start="spec",
                    warn=False)
    # the floor is the load cell's 2 N over the force's RMS (two routes)
    rms = float(np.std(rec.force))
    assert res.noise_nrmse == pytest.approx(2.0 / rms, rel=0.25)
    assert res.nrmse_calibration > 10 * res.noise_nrmse
    assert res.summary().startswith("ABOVE THE NOISE: calibration NRMSE ")
    assert res.as_dict()["above_noise"] and res.as_dict()["noise_floor_nrmse"] > 0
    # the device's own record, fitted from its own parameters: at the noise floor
    own = synthetic_record(frequency=3.0, amplitude=0.003, cycles=3, seed=21)
    ok = calibrate([own], spec=FitSpec.default(vary=("c1",)), max_nfev=4, start="spec",
                   params=preset("paper_calibrated"), warn=False)
    assert ok.nrmse_calibration < 2 * ok.noise_nrmse
    assert "ABOVE THE NOISE" not in ok.summary() and ok.as_dict()["above_noise"] == ""


def _bingham(freq, amp=0.01, fs=500.0, cycles=3, seed=1):
    """A Bingham damper (an MR damper's yield plus its viscosity): F = 300 N tanh(v / 5 mm/s)
    + 3 kN s/m v, with 1 N of load-cell noise."""
    t = np.arange(int(cycles * fs / freq)) / fs
    y = amp * np.sin(2 * np.pi * freq * t)
    v = amp * 2 * np.pi * freq * np.cos(2 * np.pi * freq * t)
    F = 300.0 * np.tanh(v / 0.005) + 3e3 * v + np.random.default_rng(seed).normal(0, 1, t.size)
    return Record.from_arrays(t, y, F, source=f"bingham_{freq:g}Hz.csv", first_line=2)


def test_a_physics_fit_beaten_by_the_dyno_map_says_so_first():
    """The two-slope force-velocity map draws a Bingham damper's loop almost exactly; a
    physics fit that predicts the held-out record worse says so at the head of its summary
    and in the JSON, as it does for the line."""
    from liquidamp.analysis.measured.calibration import FitSpec, calibrate

    cal, val = _bingham(2.0), _bingham(1.0, seed=2)
    res = calibrate([cal], validate=[val], spec=FitSpec.default(vary=("c1",)), max_nfev=4,
                    start="spec", warn=False)
    ref = res.references["two_slope"].validation_of(val.label)
    physics = res.heldout_records()[val.label]
    assert ref < 0.05 < physics
    first = res.summary().split("; ABOVE THE NOISE")[0]
    assert "PHYSICS MODEL LOSES TO THE TWO-SLOPE MAP: the physics model does not beat the " \
           f"dyno's two-slope force-velocity map on held-out record {val.label} " \
           f"({physics:.3g} vs {ref:.3g})" in first
    assert res.as_dict()["physics_loses_to_two_slope"] == res.versus_map() != ""


def test_a_dyno_test_programme_is_not_taken_for_a_drift():
    """A dyno's test programme (one stroke amplitude, four speeds in sequence, 5 cycles each)
    of a digressive damper: the force's gain on a linear regression falls as the speed
    rises, which is the valve, not a drift.  The excitation's own RMS rises monotonically
    (Mann-Kendall), so the record is not tested; a stationary broadband stroke under a force
    that fades 10 % is still found non-stationary, and without the fade stationary."""
    from scipy.signal import butter, filtfilt

    from liquidamp.analysis.measured.drift import record_drift

    fs, Y, parts = 300.0, 0.018, []
    t0 = 0.0
    for vp in (0.05, 0.10, 0.26, 0.52):
        f = vp / (2 * np.pi * Y)
        t = t0 + np.arange(int(5 / f * fs)) / fs
        parts.append((t, Y * np.sin(2 * np.pi * f * (t - t0))))
        t0 = t[-1] + 1 / fs
    t = np.concatenate([p[0] for p in parts])
    y = np.concatenate([p[1] for p in parts])
    v = np.gradient(y, t)
    F = 150.0 * np.tanh(v / 0.03) + 400.0 * v  # bleed, then the blown-off valve's slope
    rng = np.random.default_rng(5)
    prog = Record.from_arrays(t, y, F + rng.normal(0, 1.0, t.size))
    assert not prog.periodic
    d = record_drift(prog)
    assert not d.tested and not d.nonstationary
    assert "the excitation itself changes" in d.reason and "Kendall" in d.reason
    # a stationary broadband stroke: drift found where the force fades, not where it does not
    t = np.arange(0.0, 20.0, 1e-3)
    b, a = butter(4, [0.5 / 500, 20.0 / 500], "band")
    y = filtfilt(b, a, rng.normal(0, 1, t.size))
    y = 0.003 * y / np.std(y)
    v = np.gradient(y, t)
    fade = 1.0 - 0.1 * t / t[-1]
    d = record_drift(Record.from_arrays(t, y, fade * (2e4 * y + 800 * v)
                                        + rng.normal(0, 0.5, t.size)))
    assert d.tested and d.nonstationary and d.amplitude_change == pytest.approx(-0.1, abs=0.02)
    d = record_drift(Record.from_arrays(t, y, 2e4 * y + 800 * v + rng.normal(0, 0.5, t.size)))
    assert d.tested and not d.nonstationary


def test_the_viscous_start_takes_a_building_dampers_mean_force():
    """A 400 kN building damper's record over a part cycle has a mean force of tens of kN,
    beyond the catalogue's +-10 kN offset: the viscous start starts its offset there, bounded
    by the records' force scale (+-2 F_s, as every fit scales it), instead of failing; for a
    record inside the catalogue bounds the fit's parameters are the same as before."""
    from liquidamp.analysis.measured.device_class import read_loop, viscous_start
    from liquidamp.analysis.measured.fit_spec import FitSpec, scale_effect_bounds

    full = _power_law_damper(alpha=0.6)
    n = int(0.6 * full.time.size)  # 2.4 cycles: the mean is far from zero
    rec = Record.from_arrays(full.time[:n], full.displacement[:n], full.force[:n])
    L = read_loop([rec])
    assert abs(L.mean_force) > 1e4
    cs = viscous_start(preset("paper_initial"), (), [rec], L)
    p = cs.spec["force_offset.offset_N"]
    Fs = 0.5 * float(np.ptp(rec.force))
    assert p.value == L.mean_force and p.min == pytest.approx(-2 * Fs)
    assert p.max == pytest.approx(2 * Fs)
    small = _power_law_damper(alpha=0.6)
    small = Record.from_arrays(small.time, small.displacement, 1e-2 * small.force)
    cs = viscous_start(preset("paper_initial"), (), [small], read_loop([small]))
    old = FitSpec.default(vary=("c1",), effects=cs.effects)
    assert scale_effect_bounds(cs.spec, [small]).parameters == \
        scale_effect_bounds(old, [small]).parameters
