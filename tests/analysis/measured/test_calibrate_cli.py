"""The calibrate and diagnose commands: JSON contents, report, errors."""

import json

import pytest

from liquidamp.analysis.measured.records import write_record
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.cli import main


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("rec")
    eff = {"force_offset": {"offset_N": 30.0}}
    cal = write_record(d / "cal.csv", synthetic_record(frequency=3.0, amplitude=0.003,
                                                       cycles=3, seed=41, effects=eff))
    val = write_record(d / "val.csv", synthetic_record(frequency=4.0, amplitude=0.002,
                                                       cycles=3, seed=42, effects=eff))
    return d, cal, val


def test_calibrate_command(files):
    d, cal, val = files
    out = d / "cal.json"
    code = main(["calibrate", str(cal), "--validate", str(val), "--preset", "paper_initial",
                 "--vary", "inv_gamma1,inv_gamma2,c1,c2", "--json", str(out),
                 "--report", str(d / "rep")])
    data = json.loads(out.read_text())
    assert code in (0, 1)
    assert (code == 0) == data["fit"]["converged"]
    assert set(data["nrmse"]) == {"calibration", "validation"}
    assert 0 < data["nrmse"]["calibration"] < 0.2
    assert set(data["parameters"]["multipliers"]) == {"inv_gamma1", "inv_gamma2", "c1", "c2"}
    assert (d / "rep" / "index.html").exists() and (d / "rep" / "loops_validation.png").exists()
    for f in ("damper_fv_0.png", "damper_fv_0.svg", "damper_peaks.png", "damper_peaks.svg"):
        assert (d / "rep" / f).stat().st_size > 1000
    assert "Damper characteristics" in (d / "rep" / "index.html").read_text()
    dc = data["damper_characteristics"]
    assert dc["records"] == ["cal"]
    # the records carry a 30 N offset; the model fitted without the offset effect lacks it
    assert dc["measured"]["gas_force [N]"] == pytest.approx(30.0, abs=6.0)
    assert dc["model"]["gas_force [N]"] < dc["measured"]["gas_force [N]"] - 20.0


def test_diagnose_command(files):
    d, cal, val = files
    out = d / "diag.json"
    code = main(["diagnose", str(cal), "--validate", str(val), "--json", str(out),
                 "--top", "1", "--max-steps", "2", "--max-nfev", "40",
                 "--report", str(d / "drep")])
    assert code == 0
    data = json.loads(out.read_text())
    assert [s["effect"] for s in data["steps"]] == ["force_offset"]
    step = data["steps"][0]
    assert step["parameters"]["offset_N"] == pytest.approx(30.0, rel=0.25)
    assert step["nrmse"]["validation"] < data["baseline"]["nrmse"]["validation"]
    assert step["evidence"][0]["effect"] == "force_offset"
    assert data["final"]["nrmse"]["validation"] == step["nrmse"]["validation"]
    html = (d / "drep" / "index.html").read_text()
    assert "Candidates" in html and "force_offset" in html


def test_diagnose_named_candidates_only(files):
    """--candidate restricts the round to the named candidates (here an effect screened
    only on request beside the offset)."""
    d, cal, val = files
    out = d / "diag_named.json"
    code = main(["diagnose", str(cal), "--validate", str(val), "--json", str(out), "--top", "1",
                 "--max-steps", "1", "--max-nfev", "40", "--candidate", "force_offset",
                 "--candidate", "relief_valve"])
    assert code == 0
    data = json.loads(out.read_text())
    assert [s["effect"] for s in data["steps"]] == ["force_offset"]
    assert {c["effect"] for c in data["steps"][0]["evidence"]} == {"force_offset",
                                                                    "relief_valve"}


def test_bad_record_is_rejected_with_row(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("time [s],displacement [mm],force [N]\n0,1,2\n0.005,x,3\n")
    code = main(["calibrate", str(bad), "--json", str(tmp_path / "o.json")])
    assert code == 2
    assert "line 3, column 2 (displacement)" in capsys.readouterr().err
