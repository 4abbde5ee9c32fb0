"""Issue #19 item 6 and the drift of item 3: data checks that real records pass.

Spikes are judged against the record's own local rates, on the record as read (never on
samples the conditioning made); every problem is listed at once with the file's own line
numbers; ``outliers`` / ``--outliers`` refuse|drop|keep; a force that drifts over the record
is reported as non-stationary and its drift is kept out of the noise floor.
"""

import json
import math

import numpy as np
import pytest

from liquidamp.analysis.measured.checks import check_records
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.drift import Drift, record_drift
from liquidamp.analysis.measured.record_model import integrate
from liquidamp.analysis.measured.record_quality import check_record, noise_floor
from liquidamp.analysis.measured.records import Record, read_record, write_record
from liquidamp.analysis.measured.spikes import find_spikes
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.cli import main
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import DataFileError

FS = 3000.0


def _multisine(t, rms, lo, hi, seed):
    rng = np.random.default_rng(seed)
    f = np.arange(lo, hi + 1e-9, lo)
    ph = rng.uniform(-np.pi, np.pi, f.size)
    arg = np.outer(t, 2 * np.pi * f) + ph
    A = rms * math.sqrt(2.0 / f.size)
    return A * np.sin(arg).sum(1), A * (np.cos(arg) * 2 * np.pi * f).sum(1)


def test_fast_kinks_and_yield_steps_are_not_spikes_a_30mm_sample_is(tmp_path):
    """An MR-like record: broadband stroke at 3 kHz moving at up to ~0.6 m/s with 1 % kinks,
    a force with Bingham yield steps (a jump of 2 F_y in one sample at every reversal,
    F_y following a stepped voltage).  Nothing in it is a spike; one 30 mm sample is."""
    rng = np.random.default_rng(3)
    t = np.arange(0, 4.0, 1 / FS)
    y, v = _multisine(t, 1.0e-3, 0.5, 50.0, 1)
    # 1 % kinks: the rate changes by 1 % of its RMS at 40 random instants, and back 20 ms on
    for tk in rng.uniform(0.2, 3.8, 20):
        ramp = np.clip(t - tk, 0.0, 0.02)
        y = y + 0.01 * np.std(v) * ramp * rng.choice((-1, 1))
    v = np.gradient(y, t)
    assert 0.5 < np.max(np.abs(v)) < 0.8  # a stroke moving at up to 500-800 mm/s
    u = np.repeat(rng.uniform(0.0, 2.0, 20), t.size // 20 + 1)[:t.size]  # voltage steps
    F = 800.0 * v + (40.0 + 150.0 * u) * np.sign(v) + rng.normal(0, 1.5, t.size)
    ym = y + rng.normal(0, 2e-6, t.size)
    rec = Record.from_arrays(t, ym, F, source="mr.csv", channels={"voltage": u})
    assert not rec.periodic
    q = check_record(rec)
    assert q.outliers == () and q.problems == ()
    # the voltage channel is written and read back with its unit
    back = read_record(write_record(tmp_path / "mr.csv", rec))
    assert back.channels["voltage"] == pytest.approx(rec.channels["voltage"][10:-10], abs=1e-6)
    # a triangle stroke at 580 mm/s: a kink of 100 % of the rate at every reversal
    tri = 0.003 * (2 / np.pi) * np.arcsin(np.sin(2 * np.pi * 0.0 + 2 * np.pi * 24.2 * t))
    assert find_spikes(tri)[0].size == 0
    # one 30 mm sample on the 3 mm stroke, and one 300 N force spike on a fast stretch (no
    # reversal within 10 samples), with their file lines
    i = next(k for k in range(7000, t.size) if np.all(np.sign(v[k - 10:k + 11]) == np.sign(v[k])))
    y2, F2 = ym.copy(), F.copy()
    y2[4000] = 0.030
    F2[i] += 300.0
    bad = Record.from_arrays(t, y2, F2, source="mr.csv")
    q = check_record(bad)
    assert [(o.column, o.index, o.line) for o in q.outliers] == [
        ("force", i - 10, i + 2), ("displacement", 3990, 4002)]  # 10 SG samples trimmed
    assert q.outliers[1].expected == pytest.approx(ym[3999:4002:2].mean(), abs=1e-4)


class TaperedStroke:
    """y = Y(t) sin(w t), the amplitude ramping up over 2 cycles, held 3, down over 2."""

    def __init__(self, amplitude, frequency):
        self.Y, self.w = amplitude, 2 * math.pi * frequency
        self.T = 1.0 / frequency
        self.max_abs = amplitude

    def _env(self, t):
        c = t / self.T
        if c < 2.0:
            return 0.25 + 0.375 * c, 0.375 / self.T
        if c < 5.0:
            return 1.0, 0.0
        return max(1.0 - 0.375 * (c - 5.0), 0.25), (-0.375 / self.T if c < 7.0 else 0.0)

    def __call__(self, t):
        e, de = self._env(float(t))
        s, c = math.sin(self.w * t), math.cos(self.w * t)
        Y = self.Y
        return (Y * e * s, Y * (de * s + e * self.w * c), -Y * e * self.w ** 2 * s
                + 2 * Y * de * self.w * c)

    def arrays(self, t):
        out = np.array([self(float(x)) for x in t])
        return out[:, 0], out[:, 1], out[:, 2]


def test_toolkit_tapered_and_broadband_records_pass_a_spike_is_refused_by_file_line(tmp_path):
    """Records made by this toolkit's own model plus noise (Coulomb friction: force steps at
    every reversal) pass the checks; a 30 mm sample written into the file is refused with
    the line it is on in the file (a blank line before it counted)."""
    broad = synthetic_record(band=(0.5, 6.0), amplitude=0.003, frequency=0.5, cycles=4,
                             sampling_rate=1000.0, seed=7,
                             effects={"coulomb_friction": {"force_N": 30.0}})
    assert broad.shape.kind == "broadband"
    p = preset("paper_calibrated")
    model = with_effects(get_model("full"), make_effect("coulomb_friction", force_N=30.0))
    stroke = TaperedStroke(0.003, 2.0)
    t = np.arange(0, 3.5, 1 / 500.0)
    X = integrate(model, p, stroke, t, model.initial_state(p, 0.0), rtol=1e-7,
                  atol_scale=1e-10, hmax=stroke.T / 200)
    y, v, a = stroke.arrays(t)
    rng = np.random.default_rng(2)
    F = np.asarray(model.force(t, X, (y, v, a), p)) + rng.normal(0, 1.0, t.size)
    ym = y + rng.normal(0, 2e-6, t.size)
    tapered = Record.from_arrays(t, ym, F, source="tapered.csv")
    assert tapered.shape.kind == "tapered"
    for rec in (broad, tapered):
        q = check_record(rec, p)
        assert q.outliers == () and q.problems == (), rec.label
    qs, dropped = check_records([broad, tapered], p)
    assert dropped == () and not any(q.nonstationary for q in qs)
    assert qs[1].drift.method == "not tested"  # the amplitude changes by design
    # the same tapered record in a file, one sample 30 mm off, a blank line before it
    path = write_record(tmp_path / "tapered.csv", time=t, displacement=ym, force=F)
    lines = path.read_text().splitlines()
    i = 700  # sample 700 sits on line 702 of the file ...
    cells = lines[i + 1].split(",")
    cells[1] = f"{float(cells[1]) + 30.0:.7g}"  # + 30 mm
    lines[i + 1] = ",".join(cells)
    lines.insert(300, "")  # ... and on line 703 with a blank line above it
    path.write_text("\n".join(lines) + "\n")
    rec = read_record(path)
    with pytest.raises(DataFileError, match=r"tapered.csv: 1 displacement spike\(s\) on line "
                       r"703 .*cannot be dropped.*outliers='keep'"):
        check_records([rec], outliers="drop")
    qs, _ = check_records([rec], outliers="keep")
    assert [o.line for o in qs[0].outliers] == [703]


def test_friction_damper_full_records_pass_after_conditioning(friction_damper_records):
    """The whole (tapered) real records were refused for 11 "displacement spikes" that the
    decimation made, with line numbers of the decimated record; the checks now run on the
    records as read (CC BY-SA 4.0, Coble, Huggins, Cao, Ricles, Downey 2022)."""
    recs = [read_record(f) for f in sorted(friction_damper_records.glob("*_full.csv"))]
    conditioned = [condition(r)[0] for r in recs]
    assert all(c.meta["conditioning"].factor > 1 for c in conditioned)
    qs, dropped = check_records(conditioned, preset("paper_initial"), what="diagnose")
    assert dropped == ()
    for q, r in zip(qs, recs, strict=True):
        assert q.outliers == () and q.problems == ()
        assert q.stroke["sampling_rate [Hz]"] == pytest.approx(1024.0, rel=1e-3)  # as read
        assert q.source == r.source


def test_independent_records_checks_and_drift_verdicts(independent_records):
    """Every shared independent record (CC0) passes the data checks, with its measured
    channel where it has one (d06 temperature, d10 voltage); the thermal records d06 and d07
    are non-stationary, the others are not; the drift is kept out of their noise floor
    (the simulator's load-cell noise is 1.5 N RMS)."""
    truth = json.loads((independent_records / "truth.json").read_text())
    for f in sorted(independent_records.glob("d*.csv")):
        rec = read_record(f)
        q = check_record(rec)
        assert q.outliers == () and q.problems == (), f.name
        thermal = f.name.startswith(("d06", "d07"))
        assert q.nonstationary == thermal, (f.name, q.drift.reason)
        if f.name.startswith("d10"):
            assert set(rec.channels) == {"voltage"} and q.channels["voltage"]["unit"] == "V"
            assert 0.0 <= q.channels["voltage"]["min"] < q.channels["voltage"]["max"] < 2.1
        if f.name.startswith("d06"):
            assert q.channels["temperature"]["unit"] == "K"
            col = np.loadtxt(f, delimiter=",", skiprows=1)[10:-10, 3]  # [C], SG ends trimmed
            assert q.channels["temperature"]["mean"] == pytest.approx(col.mean() + 273.15,
                                                                      abs=1e-9)
        if thermal:
            case = "d06_thermal_drift_with_temperature" if "d06" in f.name else "d07_thermal_drift"
            role = f.stem.rsplit("_", 1)[1]
            true = truth[case]["effect_size"][role]["h1_amplitude_drift_first_to_last_cycle"]
            d = q.drift
            assert d.amplitude_p < 1e-6 and d.amplitude_trend < 0
            # a linear trend through an exponential warm-up: the sign and the size
            assert 0.5 * true > d.amplitude_change > 1.5 * true, (f.name, true)
            nf = noise_floor(rec)
            assert nf.force_std == pytest.approx(1.5, rel=0.1), f.name
            if role == "cal":  # the drift left in, the floor was inflated
                stationary = Drift(True, False, "cycles")
                assert noise_floor(rec, stationary).force_std > 1.2 * nf.force_std


def test_drift_rule_figures_and_noise_floor():
    """A force whose amplitude fades 5 % over 30 cycles is non-stationary, with its figures;
    the same record without the fade is not; a mean that creeps by 3 % of the amplitude is;
    the noise floor with the drift removed is the load-cell noise."""
    rng = np.random.default_rng(11)
    t = np.arange(0, 10.0, 1 / 200.0)
    y = 0.003 * np.sin(2 * np.pi * 3 * t) + rng.normal(0, 2e-6, t.size)
    F0 = 500 * np.cos(2 * np.pi * 3 * t) + 60 * np.sin(6 * np.pi * t)
    noise = rng.normal(0, 1.5, t.size)
    fade = 1.0 - 0.05 * t / t[-1]
    rec = Record.from_arrays(t, y, fade * F0 + noise)
    q = check_record(rec)
    d = q.drift
    assert d.nonstationary and d.method == "cycles" and d.segments == 29
    # the fitted line from the first to the last whole cycle: 5 % x 28/30 of the span
    assert d.amplitude_change == pytest.approx(-0.05 * 28 / 30, rel=0.05)
    assert d.amplitude_trend == pytest.approx(100 * d.amplitude_change / 28, rel=1e-6)
    assert d.amplitude_p < 1e-12 and abs(d.mean_change) < 0.5
    assert any("non-stationary" in n for n in q.notes)
    js = json.loads(json.dumps(q.as_dict()))
    assert js["nonstationary"] is True and js["drift"]["amplitude_change"] == d.amplitude_change
    nf = noise_floor(rec)
    assert nf.force_std == pytest.approx(1.5, rel=0.08) and "drift removed" in nf.method
    # the drift taken out: 0.05 (t / T - 1/2) F0, RMS 0.05 / sqrt(12) of the force's
    assert nf.drift_nrmse == pytest.approx(0.05 / math.sqrt(12), rel=0.05)
    assert noise_floor(rec, Drift(True, False, "cycles")).force_std > 3.0
    # the conditioning still averages its cycles, its floor with the drift removed
    c = condition(rec)[1]
    assert c.cycles_averaged == 29 and c.noise.method.startswith("cycle scatter, drift removed")
    # each averaged point interpolates two samples: sigma^2 x E[(1 - a)^2 + a^2] = 2/3 sigma^2
    assert c.noise.force_std == pytest.approx(nf.force_std * math.sqrt(2 / 3 / 29), rel=0.05)
    steady = record_drift(Record.from_arrays(t, y, F0 + noise))
    assert steady.tested and not steady.nonstationary and steady.amplitude_p > 1e-3
    creep = record_drift(Record.from_arrays(t, y, F0 + 15.0 * t / t[-1] + noise))
    assert creep.nonstationary and creep.mean_change == pytest.approx(15.0 * 28 / 30, rel=0.05)


@pytest.fixture(scope="module")
def spiky_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("spiky")
    cal = synthetic_record(frequency=3.0, amplitude=0.003, cycles=3, seed=21)
    F = np.array(cal.force)
    F[[30, 95]] = 5e4
    path = write_record(d / "spiky.csv", time=cal.time, displacement=cal.displacement,
                        force=F)
    val = write_record(d / "val.csv", synthetic_record(frequency=4.0, amplitude=0.002,
                                                       cycles=3, seed=22))
    return d, path, val


@pytest.mark.parametrize("command", ["calibrate", "diagnose"])
def test_commands_refuse_spikes_naming_their_own_option(spiky_files, command, capsys):
    """The advice names --outliers (the option that exists on the command line), never the
    Python keyword; the lines are those of the file (header = 1)."""
    d, path, val = spiky_files
    code = main([command, str(path), "--validate", str(val), "--json", str(d / "x.json")])
    assert code == 2
    err = capsys.readouterr().err
    assert "2 force outlier(s) on lines 32 and 97" in err
    assert "--outliers drop" in err and "--outliers keep" in err and "outliers='" not in err
    assert not (d / "x.json").exists()  # refused before any model run


def test_outliers_keep_and_drop_through_a_conditioned_record(spiky_files):
    """keep: the spikes stay kept in every later check of the record (a refit checks it
    again); drop on a record already conditioned: the record as read is repaired and
    conditioned again as it was."""
    from liquidamp.analysis.measured.calibration import calibrate
    from liquidamp.analysis.measured.checks import drop_outliers, keep_outliers

    _, path, val = spiky_files
    rec = read_record(path)
    q = check_records([rec], outliers="keep")[0][0]
    kept = keep_outliers(rec, q)
    check_records([kept])  # no error: the user kept them
    cond, _ = condition(rec, average=True)
    fixed = drop_outliers(cond, q)
    assert fixed.meta["conditioning"].cycles_averaged == cond.meta["conditioning"].cycles_averaged
    assert check_records([fixed])[0][0].outliers == ()
    assert np.max(np.abs(fixed.force)) < 0.2 * np.max(np.abs(cond.force))
    with pytest.warns(Warning, match=r"2 force outlier\(s\) dropped"):
        res = calibrate([cond], validate=[read_record(val)], outliers="drop", max_nfev=2,
                        start="spec")
    assert [o.line for _, o in res.dropped] == [32, 97]
    assert res.calibration[0].meta["conditioning"].cycles_averaged > 1
