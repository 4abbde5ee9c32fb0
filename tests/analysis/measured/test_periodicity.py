"""Issue #12 item 6: periodic, tapered and broadband strokes; the fallbacks that need no
single frequency."""

import json
import math

import numpy as np
import pytest

from liquidamp.analysis.measured.calibration_result import RecordError
from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.analysis.measured.record_quality import check_record, noise_floor
from liquidamp.analysis.measured.records import Record, read_record, stroke_shape
from liquidamp.analysis.measured.start import first_harmonic_stiffness, physics_factors
from liquidamp.device import preset

FS = 300.0


def _band_limited(t, rms, lo, hi, seed):
    """A random-phase multisine from lo to hi [Hz] of RMS ``rms`` and its two derivatives."""
    rng = np.random.default_rng(seed)
    f = np.arange(lo, hi + 1e-9, lo)
    ph = rng.uniform(-np.pi, np.pi, f.size)
    A = rms * math.sqrt(2.0 / f.size)
    w = 2 * np.pi * f
    arg = np.outer(t, w) + ph
    return (A * np.sin(arg).sum(1), A * (np.cos(arg) * w).sum(1),
            -A * (np.sin(arg) * w * w).sum(1))


def test_white_noise_stroke_is_broadband_never_one_frequency():
    """The issue's case: white noise was summarized as '7.93 Hz, 0.383 mm'."""
    rng = np.random.default_rng(5)
    t = np.arange(0, 20.0, 1 / FS)
    y = rng.normal(0.0, 0.383e-3, t.size)
    r = Record.from_arrays(t, y, 1e3 * np.gradient(y, t) + rng.normal(0, 1.0, t.size))
    assert not r.periodic and r.shape.kind == "broadband"
    assert r.shape.periodicity < 0.05  # the sine at the periodogram peak holds ~nothing
    text = r.describe()
    assert text.startswith("broadband stroke (not periodic), RMS 0.38")
    assert f"{r.frequency:.3g} Hz, {r.amplitude * 1e3:.3g} mm" not in text
    s = r.summary()
    assert "frequency [Hz]" not in s and "amplitude [m]" not in s and s["periodic"] is False
    assert s["rms [m]"] == pytest.approx(0.383e-3, rel=0.02)
    lo, hi = s["band [Hz]"]
    assert 0.03 * FS / 2 < lo < 0.1 * FS / 2 and 0.9 * FS / 2 < hi <= FS / 2  # white: flat
    e = RecordError.of(r, "calibration", 0.1)
    assert e.frequency is None and e.amplitude is None and e.stroke == text
    q = check_record(r)
    assert q.force_first_harmonic is None and q.periodic_fraction is None
    assert q.stroke["kind"] == "broadband"
    assert any("not periodic" in n for n in q.notes)
    json.dumps(q.as_dict())  # JSON-ready


def test_steady_tapered_and_ramped_strokes():
    t = np.arange(0, 4.0, 1 / 200.0)
    y = 0.003 * np.sin(2 * np.pi * 3 * t) + 3e-5 * np.sin(2 * np.pi * 6 * t + 1)
    sh = stroke_shape(t, y, 3.0)
    assert sh.kind == "periodic" and sh.periodicity > 0.9999
    assert sh.amplitude_variation < 1e-3 and len(sh.cycle_amplitudes) == 12
    # amplitude ramping 1 -> 0.25 over 12 cycles: one frequency, cycle by cycle
    env = 1.0 - 0.75 * t / 4.0
    sh = stroke_shape(t, env * 0.003 * np.sin(2 * np.pi * 3 * t), 3.0)
    assert sh.kind == "tapered" and sh.cycle_share > 0.999 and sh.phase_coherence > 0.999
    # the mean envelope of the first and last cycle: 1 - 0.75 (0.5/12) and 1 - 0.75 (11.5/12)
    assert sh.cycle_amplitudes[0] == pytest.approx(0.003 * (1 - 0.75 * 0.5 / 12), rel=2e-3)
    assert sh.cycle_amplitudes[-1] == pytest.approx(0.003 * (1 - 0.75 * 11.5 / 12), rel=2e-3)
    assert sh.amplitude_variation == pytest.approx(0.75 * 11 / 12 / (1 - 0.75 * 0.5 / 12),
                                                   rel=5e-3)
    r = Record.from_arrays(t, env * 0.003 * np.sin(2 * np.pi * 3 * t), np.cos(6 * np.pi * t))
    assert r.describe().startswith("tapered stroke (not periodic) at 3 Hz")


def test_noise_floor_fallback_for_a_broadband_stroke():
    """No harmonics to remove: the 4th differences of the signal itself (documented)."""
    t = np.arange(0, 20.0, 1 / FS)
    y, v, a = _band_limited(t, 0.4e-3, 0.25, 8.0, 3)
    rng = np.random.default_rng(9)
    F = 2e5 * y + 3e3 * v + rng.normal(0.0, 2.0, t.size)
    r = Record.from_arrays(t, y + rng.normal(0, 1e-6, t.size), F)
    assert not r.periodic
    nf = noise_floor(r)
    assert nf.force_std == pytest.approx(2.0, rel=0.1)
    assert nf.displacement_std == pytest.approx(1e-6, rel=0.15)


def test_first_harmonic_stiffness_fallback_and_physics_factors():
    """K* at the dominant frequency from the regression F ~ F0 + k y + c v + m a."""
    t = np.arange(0, 20.0, 1 / FS)
    y, v, a = _band_limited(t, 0.4e-3, 0.25, 8.0, 4)
    k, c, m = 2e5, 3e3, 20.0
    r = Record.from_arrays(t, y, 50.0 + k * y + c * v + m * a)
    assert not r.periodic
    w = 2 * np.pi * r.frequency
    K = first_harmonic_stiffness(r)
    assert K.real == pytest.approx(k - w * w * m, rel=0.01)
    assert K.imag == pytest.approx(w * c, rel=0.01)
    f_air, f_loss = physics_factors([r], preset("paper_initial"))
    assert f_air is not None and f_loss is not None and f_loss > 0


def test_non_periodic_record_runs_without_preroll():
    t = np.arange(0, 3.0, 1 / 200.0)
    y, _, _ = _band_limited(t, 0.5e-3, 0.5, 8.0, 2)
    broad = Record.from_arrays(t, y, 0 * t)
    p = preset("paper_calibrated")
    f0 = simulate_record("full", p, broad, preroll=0).force
    f2 = simulate_record("full", p, broad, preroll=2).force
    assert np.array_equal(f0, f2)
    sine = Record.from_arrays(t, 0.001 * np.sin(2 * np.pi * 3 * t), 0 * t)
    g0 = simulate_record("full", p, sine, preroll=0).force
    g2 = simulate_record("full", p, sine, preroll=2).force
    # issue #19 replaces the pre-roll (which changed a periodic record's force, asserted
    # here before): a periodic record is simulated on its periodic orbit, preroll ignored
    assert np.array_equal(g0, g2)
    from liquidamp.coupled.testrig import simulate, steady_state
    from liquidamp.structure.testmachine import HarmonicStroke

    s = HarmonicStroke(0.001, 3.0)
    orbit = steady_state("full", p, s)
    ref = simulate("full", p, s, sine.time[-1], x0=orbit.states[:, 0], t_eval=sine.time)
    assert np.max(np.abs(g0 - ref.force)) < 1e-4 * np.max(np.abs(ref.force))


def test_real_records_full_are_tapered_steady_are_periodic(friction_damper_records):
    for f in sorted(friction_damper_records.glob("brfd30_*.csv")):
        r = read_record(f)
        if f.stem.endswith("_steady"):
            assert r.periodic and r.shape.amplitude_variation < 0.01, f.name
            assert r.describe().endswith("12.8 mm") or r.describe().endswith("12.9 mm")
        else:  # about 2 ramp-up, 3 full, 2 ramp-down cycles
            assert r.shape.kind == "tapered", f.name
            assert 0.7 < r.shape.amplitude_variation < 0.8
            assert len(r.shape.cycle_amplitudes) == 7
        q = check_record(r)  # rig ringing is not taken for spikes on the tapered ones either
        assert q.outliers == () and q.problems == () and q.loss_share > 0.6, f.name
