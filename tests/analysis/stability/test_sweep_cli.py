"""The ``liquidamp sweep`` command: JSON keys, Floquet fallback, plots and bad input."""

import json

import pytest

from liquidamp.cli import main


def test_ground_resonance_failed_damper(tmp_path, capsys):
    out, fig = tmp_path / "gr.json", tmp_path / "gr.png"
    code = main(["sweep", "ground-resonance", "--rotor", "hammond1974", "--rpm", "150:350:9",
                 "--inoperative", "1", "--json", str(out), "--plot", str(fig)])
    assert code == 0
    err = capsys.readouterr().err
    assert "Floquet" in err
    d = json.loads(out.read_text())
    assert d["method"] == "floquet" and "Floquet" in d["note"]
    assert len(d["rpm"]) == len(d["max_real_part [1/s]"]) == len(d["frequencies [Hz]"]) == 9
    (a, b), = d["unstable_ranges [rpm]"]
    assert a == pytest.approx(210.37, abs=0.1) and b == pytest.approx(307.08, abs=0.1)
    assert fig.stat().st_size > 0


def test_ground_resonance_nominal_coleman(tmp_path):
    out = tmp_path / "gr.json"
    assert main(["sweep", "ground-resonance", "--rpm", "100,200,300", "--method", "coleman",
                 "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["method"] == "coleman" and d["unstable_ranges [rpm]"] == []
    assert all(v < 0 for v in d["max_real_part [1/s]"])


def test_flutter_cli(tmp_path):
    out, fig = tmp_path / "fl.json", tmp_path / "fl.png"
    assert main(["sweep", "flutter", "--section", "hodges-pierce", "--aero", "jones",
                 "--method", "p", "--speeds", "0.1:2.6:26", "--json", str(out),
                 "--plot", str(fig)]) == 0
    d = json.loads(out.read_text())
    assert d["flutter_speed"] == pytest.approx(2.1704, abs=1e-4)
    assert d["divergence_speed"] == pytest.approx(2.8284, abs=1e-4)
    assert len(d["speed"]) == len(d["damping"]) == len(d["frequency"]) == 2
    assert fig.stat().st_size > 0


@pytest.mark.parametrize("argv,message", [
    (["flutter", "--aero", "theodorsen", "--method", "p"], "valid combinations"),
    (["ground-resonance", "--rpm", "100:200:0"], "COUNT must lie in [1, 100000]"),
    (["ground-resonance", "--rpm", "100:200:3", "--inoperative", "5"],
     "blade index must lie in [1, 4], got 5"),
    (["ground-resonance", "--rpm", "100:200:3", "--rotor", "nope"], "unknown rotor preset"),
    (["ground-resonance", "--rpm", "300:200:3"], "strictly increasing"),
])
def test_bad_input_exits_2(tmp_path, capsys, argv, message):
    code = main(["sweep", *argv, "--json", str(tmp_path / "x.json")])
    assert code == 2
    assert message in capsys.readouterr().err
