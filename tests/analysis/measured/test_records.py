"""Reading, checking and differentiating test-machine records; driving a model with them."""

import numpy as np
import pytest

from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.analysis.measured.record_quality import noise_floor
from liquidamp.analysis.measured.records import Record, read_record, write_record
from liquidamp.device import preset
from liquidamp.errors import DataFileError


def _sine(n=600, f=3.0, fs=200.0, Y=0.003, phase=0.4):
    t = 2.0 + np.arange(n) / fs
    return t, Y * np.sin(2 * np.pi * f * t + phase), 400 * np.cos(2 * np.pi * f * t)


def _write(path, header, rows):
    path.write_text(header + "\n" + "\n".join(",".join(str(c) for c in r) for r in rows) + "\n")
    return path


def test_roundtrip_units_and_inference(tmp_path):
    t, y, F = _sine()
    p = _write(tmp_path / "r.csv", "time [ms],displacement [mm],force [kN]",
               zip(t * 1e3, y * 1e3, F / 1e3, strict=True))
    r = read_record(p)
    assert r.frequency == pytest.approx(3.0, rel=1e-6)
    assert r.amplitude == pytest.approx(0.003, rel=1e-4)
    assert r.force.max() == pytest.approx(400.0, rel=1e-3)
    # SG edges dropped; velocity is the derivative of the stroke
    assert r.time.size == t.size - 20
    v_exact = 0.003 * 2 * np.pi * 3 * np.cos(2 * np.pi * 3 * r.time + 0.4)
    assert np.max(np.abs(r.velocity - v_exact)) < 3e-3 * 0.0566
    out = write_record(tmp_path / "w.csv", r)
    r2 = read_record(out)
    assert np.allclose(r2.force, r.force[10:-10], atol=1e-3)


def test_imperial_units_and_parenthesised_headers_read_as_si(tmp_path):
    """A US laboratory's record (inches, kips; units in parentheses) reads as its SI twin:
    1 in = 0.0254 m and 1 lbf = 4.4482216152605 N exactly (the friction-damper dataset of
    Coble et al. 2022 was recorded in inches and kips)."""
    t, y, F = _sine()
    si = read_record(_write(tmp_path / "si.csv", "time [s],displacement [m],force [N]",
                            zip(t, y, F, strict=True)))
    us = read_record(_write(tmp_path / "us.csv", "Time (s), Displacement (in), Force (kip)",
                            zip(t, y / 0.0254, F / 4448.2216152605, strict=True)))
    lb = read_record(_write(tmp_path / "lb.csv", "time [s],displacement [in],force [lbf]",
                            zip(t, y / 0.0254, F / 4.4482216152605, strict=True)))
    # as laboratories also spell them: sec, msec, inch(es), lb(s) (pound-force), kips
    spelt = read_record(_write(tmp_path / "sp.csv", "Time (sec), Disp (inches), Force (lbs)",
                               zip(t, y / 0.0254, F / 4.4482216152605, strict=True)))
    ms = read_record(_write(tmp_path / "ms.csv", "Time [msec],Displacement [inch],Load [kips]",
                            zip(t * 1e3, y / 0.0254, F / 4448.2216152605, strict=True)))
    for r in (us, lb, spelt, ms):
        assert np.allclose(r.displacement, si.displacement, rtol=1e-9, atol=1e-12)
        assert np.allclose(r.force, si.force, rtol=1e-9, atol=1e-9)
        assert r.sampling_rate == pytest.approx(si.sampling_rate, rel=1e-9)
    assert us.amplitude == pytest.approx(0.003, rel=1e-4)


def test_laboratory_layouts_read_as_the_plain_record(tmp_path):
    """What test machines export reads as the plain record: another column name
    (stroke, position, load cell force), a preamble and ``#`` comments before the header
    (the file's own line numbers kept), columns separated by spaces, centimetres and
    decanewtons (1 daN = 10 N, 1 cm = 10 mm: SI values to 1e-12), and a column the format
    does not read (velocity) passed over with a warning naming it."""
    t, y, F = _sine()
    plain = read_record(_write(tmp_path / "p.csv", "time [s],displacement [m],force [N]",
                               zip(t, y, F, strict=True)))
    lab = tmp_path / "lab.txt"
    lab.write_text("# MTS export\nSpecimen: lag damper 3\nDate: 2026-11-26\n\n"
                   "Time (s)  Piston stroke (cm)  Stroke velocity (mm/s)  Load cell force (daN)\n"
                   + "\n".join(f"{a:.17g}   {b * 100:.17g}  {c:.17g}  {d / 10:.17g}"
                                for a, b, c, d in zip(t, y, np.gradient(y, t) * 1e3, F,
                                                      strict=True)) + "\n")
    with pytest.warns(UserWarning, match="not read: 3 'Stroke velocity \\(mm/s\\)'"):
        r = read_record(lab)
    assert np.allclose(r.displacement, plain.displacement, rtol=1e-12, atol=1e-15)
    assert np.allclose(r.force, plain.force, rtol=1e-12, atol=1e-9)
    assert r.line(0) == plain.line(0) + 4  # header on line 5 of the file, not 1
    alt = read_record(_write(tmp_path / "a.csv", "time [s],position [mm],load [kN]",
                             zip(t, y * 1e3, F / 1e3, strict=True)))
    assert np.allclose(alt.force, plain.force, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("header,rows,match", [
    ("time [s],force [N]", [[0, 1]] * 50, "missing column"),
    ("time [s],displacement [ft],force [N]", [[0, 1, 1]] * 50, r"unknown unit \[ft\]"),
    ("time (s),displacement (mm,force (N)", [[0, 1, 1]] * 50, "column 2"),
    ("time [s],speed [mm/s],force [N]", [[0, 1, 1]] * 50,
     r"missing column\(s\) displacement.*not read: 2 'speed \[mm/s\]'"),
    ("time [s],stroke [mm],displacement [mm],force [N]", [[0, 1, 1, 1]] * 50,
     "column 3: 'displacement \\[mm\\]' reads as column 'displacement', which column 2"),
    ("time,displacement [mm],force [N]", [[0, 1, 1]] * 50, "column 1"),
])
def test_bad_header(tmp_path, header, rows, match):
    """A required column missing (naming the columns not read), a known column's unit
    unknown or its cell malformed, a quantity given by two columns."""
    with pytest.raises(DataFileError, match=match):
        read_record(_write(tmp_path / "b.csv", header, rows))


def test_bad_rows_named(tmp_path):
    t, y, F = _sine()
    rows = [list(r) for r in zip(t, y * 1e3, F, strict=True)]
    bad = [r[:] for r in rows]
    bad[5][2] = "nan"
    with pytest.raises(DataFileError, match="line 7, column 3 \\(force\\)"):
        read_record(_write(tmp_path / "nan.csv", "time [s],displacement [mm],force [N]", bad))
    bad = [r[:] for r in rows]
    bad[30][0] = bad[28][0]
    with pytest.raises(DataFileError, match="row 32.*does not increase"):
        read_record(_write(tmp_path / "t.csv", "time [s],displacement [mm],force [N]", bad))
    bad = [r[:] for r in rows]
    bad[9][1] = "abc"
    with pytest.raises(DataFileError, match="line 11, column 2 \\(displacement\\): 'abc'"):
        read_record(_write(tmp_path / "a.csv", "time [s],displacement [mm],force [N]", bad))
    with pytest.raises(DataFileError, match="less than one cycle"):
        read_record(_write(tmp_path / "s.csv", "time [s],displacement [mm],force [N]",
                           rows[:60]))


def test_noise_floor_and_nrmse():
    rng = np.random.default_rng(3)
    t, y, F = _sine(n=800)
    r = Record.from_arrays(t, y + rng.normal(0, 2e-6, t.size), F + rng.normal(0, 1.5, t.size))
    nf = noise_floor(r)
    assert nf.force_std == pytest.approx(1.5, rel=0.15)
    assert nf.displacement_std == pytest.approx(2e-6, rel=0.2)
    pooled = nrmse([np.zeros(2), np.ones(2)], [np.zeros(2), 2 * np.ones(2)])
    assert pooled == pytest.approx(0.5 ** 0.5)


def test_record_drive_reaches_steady_state():
    """Pre-roll removes the start-up transient: record-driven force matches the steady state."""
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.structure.testmachine import HarmonicStroke

    p = preset("paper_calibrated")
    t = np.arange(0, 1.2, 0.005)
    r = Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), 0 * t)
    sim = simulate_record("full", p, r, preroll=2)
    ss = steady_state("full", p, HarmonicStroke(0.003, 3.0))
    ref = np.interp((r.time % (1 / 3)), ss.time, ss.force, period=1 / 3)
    assert np.sqrt(np.mean((sim.force - ref) ** 2)) / np.ptp(ref) < 5e-3


@pytest.mark.parametrize("effects", ["friction+offset", "freeplay", "compliance+cavitation"])
def test_composed_models_run_on_the_compiled_engine_like_lsoda(effects):
    """Every composition runs on the compiled engine with the record's stroke and gives the
    force of the scipy route (LSODA on the same right-hand side)."""
    from liquidamp.analysis.measured.calibration import FIT_OPTIONS
    from liquidamp.analysis.measured.synthetic import synthetic_record
    from liquidamp.device.effects import (
        Cavitation,
        ForceOffset,
        Freeplay,
        SeriesCompliance,
        SmoothFriction,
        with_effects,
    )
    from liquidamp.device.models import get_model

    rec = synthetic_record(preset="reference", frequency=3.0, amplitude=0.003, cycles=2,
                           seed=3)
    chosen = {"friction+offset": (SmoothFriction(30.0, 3e5), ForceOffset(5.0)),
              "freeplay": (Freeplay(1e-4),),
              "compliance+cavitation": (SeriesCompliance(5e5), Cavitation(2339.0))}[effects]
    m = with_effects(get_model("full"), *chosen)
    p = preset("reference")
    tight = FIT_OPTIONS.replace(rtol=1e-9)  # the freeplay's contact kinks: both engines tight
    a = simulate_record(m, p, rec, options=tight)
    b = simulate_record(m, p, rec, options=tight.replace(engine="scipy"))
    assert np.max(np.abs(a.force - b.force)) < 1e-4 * np.max(np.abs(b.force))
    if "z_friction" in m.state_names:  # the bristle state saturates at +-1 between reversals
        z = a.state("z_friction")
        assert 0.9 < np.max(np.abs(z)) <= 1.0 + 1e-6


@pytest.mark.parametrize("name", ["full", "no_inertia", "constant_bulk"])
def test_leakage_runs_alike_on_both_engines(name):
    """Leakage (with smooth friction) on the compiled engine and on LSODA agree; it matters."""
    from liquidamp.analysis.measured.calibration import FIT_OPTIONS
    from liquidamp.analysis.measured.synthetic import synthetic_record
    from liquidamp.device.effects import Leakage, SmoothFriction, with_effects
    from liquidamp.device.models import get_model

    rec = synthetic_record(preset="paper_calibrated", frequency=2.5, amplitude=0.0035,
                           cycles=2, seed=5)
    base = get_model(name)
    m = with_effects(base, Leakage(2e-11), SmoothFriction(30.0, 3e5))
    p = preset("paper_calibrated")
    a = simulate_record(m, p, rec, options=FIT_OPTIONS)
    b = simulate_record(m, p, rec, options=FIT_OPTIONS.replace(engine="scipy"))
    c = simulate_record(with_effects(base, SmoothFriction(30.0, 3e5)), p, rec,
                        options=FIT_OPTIONS)
    peak = np.max(np.abs(b.force))
    assert np.max(np.abs(a.force - b.force)) < 1e-4 * peak
    assert np.max(np.abs(a.force - c.force)) > 1e-2 * peak  # the leak matters here
