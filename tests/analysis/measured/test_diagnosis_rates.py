"""Diagnosis at a test machine's sampling rate: records decimated and averaged over their
cycles, the conditioning stated in the result and the JSON; the command's options."""

import json

import pytest

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.records import write_record
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.cli import main

TRUTH = {"coulomb_friction": {"force_N": 30.0}}


@pytest.fixture(scope="module")
def dense():
    """6 s at 3 kHz (2 Hz stroke), validated on 6 s at 2.67 Hz: the paper's device with
    30 N of Coulomb friction (near paper_initial, so the fit starts from it, not from a
    device sized to the records)."""
    kw = dict(preset="paper_calibrated", sampling_rate=3000.0, effects=TRUTH)
    return (synthetic_record(frequency=2.0, amplitude=0.003, cycles=12, seed=71, **kw),
            synthetic_record(frequency=8 / 3, amplitude=0.002, cycles=16, seed=72, **kw))


def test_dense_record_is_diagnosed_through_its_conditioning(dense):
    cal, val = dense
    d = diagnose([cal], [val], top=1, max_nfev=40)
    assert d.added == ("coulomb_friction",), d.stop_reason
    assert d.steps[0].parameters["force_N"] == pytest.approx(30.0, rel=0.02)
    assert d.stop_reason.startswith("residual is noise")
    c = d.conditioning[0]
    assert (c.factor, c.cycles_averaged) == (20, 11)  # 150 Hz; 11 whole cycles of 11.99
    assert d.final.calibration[0].time.size == 75
    # the final model on the records as given: the load-cell noise (1 N) and the stroke
    # noise through the Savitzky-Golay rate are all that is left
    assert set(d.nrmse_raw) == {"calibration", "validation"}
    assert d.nrmse_raw["validation"] < 0.5 * d.baseline.nrmse_validation
    data = d.as_dict()
    cd = data["conditioning"][0]
    assert cd["decimation_factor"] == 20 and cd["fitted_rate [Hz]"] == pytest.approx(150.0)
    assert cd["anti_alias_cutoff [Hz]"] == pytest.approx(60.0)
    assert cd["cycles_averaged"] == 11 and cd["removed_rms [N]"] > 0
    assert data["noise_floors"][0]["method"].startswith("cycle scatter, averaged over 11")
    assert data["noise_floor_nrmse"] == pytest.approx(d.noise_nrmse)
    step = data["steps"][0]["evidence"][0]
    assert step["delta_bic"] < -10 and step["n_effective"] > 10


def test_diagnose_command_states_filter_and_decimation(tmp_path, dense):
    cal, val = dense
    fc, fv = write_record(tmp_path / "cal.csv", cal), write_record(tmp_path / "val.csv", val)
    out = tmp_path / "d.json"
    code = main(["diagnose", str(fc), "--validate", str(fv), "--json", str(out), "--top",
                 "2", "--max-steps", "1", "--max-nfev", "30", "--force-filter", "20",
                 "--decimate", "20", "--average", "no",
                 ])
    assert code == 0
    data = json.loads(out.read_text())
    c = data["conditioning"][0]
    assert c["force_cutoff [Hz]"] == 20.0 and c["decimation_factor"] == 20
    assert c["cycles_averaged"] == 1 and c["fitted_rate [Hz]"] == pytest.approx(150.0)
    assert set(c["removed_by_stage"]) == {"force filter", "anti-alias"}
    assert "force low-pass 20 Hz" in c["description"]
    # the backlash composite (friction behind its own dead band, a gap of any size) scores
    # within 0.3 % of Coulomb friction on this record (0.891 vs 0.888): both are refitted
    # (--top 2) and the held-out records choose
    assert [s["effect"] for s in data["steps"]] == ["coulomb_friction"]


def test_bad_conditioning_options_are_refused(tmp_path, capsys, dense):
    cal, val = dense
    fc = write_record(tmp_path / "cal.csv", cal)
    out = str(tmp_path / "o.json")
    assert main(["diagnose", str(fc), "--validate", str(fc), "--json", out, "--decimate",
                 "zero"]) == 2
    assert "--decimate must be 'auto' or an integer factor" in capsys.readouterr().err
    assert main(["calibrate", str(fc), "--json", out, "--force-filter", "1.5"]) == 2
    assert "force filter cut-off must lie above the stroke frequency" in \
        capsys.readouterr().err
