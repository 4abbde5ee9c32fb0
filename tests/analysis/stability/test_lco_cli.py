"""``liquidamp lco`` and ``liquidamp sweep ... --damper``."""

import json

import pytest

from liquidamp.cli import main


def test_lco_cli_limit_cycle(tmp_path):
    out = tmp_path / "lco.json"
    png = tmp_path / "lco.png"
    rc = main(["lco", "--damper", "device_a", "--rpm", "230", "--t-end", "14",
               "--json", str(out), "--plot", str(png)])
    assert rc == 0
    d = json.loads(out.read_text())
    lin = d["linear_growth_rate [1/s]"]
    assert lin == pytest.approx(0.2077, abs=1e-3)
    assert d["time_domain_growth_rate [1/s]"] == pytest.approx(lin, rel=0.05)
    assert d["predicted_amplitude [rad]"] == pytest.approx(2.731e-3, rel=0.01)
    assert d["time_domain_amplitude [rad]"] == pytest.approx(2.731e-3, rel=0.05)
    assert png.stat().st_size > 10000


def test_lco_cli_stable_gives_null(tmp_path):
    out = tmp_path / "lco.json"
    assert main(["lco", "--damper", "viscous", "--rpm", "300", "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["linear_growth_rate [1/s]"] < 0
    assert d["time_domain_growth_rate [1/s]"] == pytest.approx(d["linear_growth_rate [1/s]"],
                                                               rel=0.05)
    assert d["predicted_amplitude [rad]"] is None
    assert d["time_domain_amplitude [rad]"] is None


def test_lco_cli_bad_input(tmp_path, capsys):
    assert main(["lco", "--damper", "oil", "--rpm", "230", "--json",
                 str(tmp_path / "x.json")]) == 2
    assert "unknown damper 'oil'" in capsys.readouterr().err


def test_sweep_ground_resonance_with_device(tmp_path):
    out = tmp_path / "gr.json"
    assert main(["sweep", "ground-resonance", "--damper", "device_a", "--rpm", "150:350:11",
                 "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    (a, b), = d["unstable_ranges [rpm]"]
    assert a == pytest.approx(195.6, abs=0.5) and b == pytest.approx(262.6, abs=0.5)
    assert d["sizing"]["scale [-]"] > 1


def test_sweep_flutter_with_device(tmp_path):
    out = tmp_path / "fl.json"
    assert main(["sweep", "flutter", "--damper", "reference", "--zeta", "0.2",
                 "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["flutter_speed"] == pytest.approx(2.4494, abs=2e-3)
    assert main(["sweep", "flutter", "--damper", "reference", "--method", "pk",
                 "--json", str(out)]) == 2
