"""``liquidamp dual-frequency``: files, JSON layout, numbers that match the library."""

import json

import pytest

from liquidamp.analysis.response.dual_frequency import dual_frequency_stiffness
from liquidamp.cli import build_parser, main
from liquidamp.device import preset


def test_dual_frequency_json_and_plot(tmp_path, capsys):
    js, png = tmp_path / "d.json", tmp_path / "d.png"
    code = main(["dual-frequency", "--preset", "device_a", "--rev-frequency", "4.2",
                 "--lag-frequency", "1.26", "--rev-amplitude", "0,1mm,2mm",
                 "--lag-amplitude", "0.5mm,0.001", "--json", str(js), "--plot", str(png)])
    assert code == 0
    assert png.stat().st_size > 2000
    data = json.loads(js.read_text())
    assert data["model"] == "full" and data["preset"] == "device_a"
    assert data["method"] == "harmonic_balance" and data["failures"] == []
    assert data["rev_frequency [Hz]"] == 4.2 and data["lag_frequency [Hz]"] == 1.26
    assert data["rev_amplitude [m]"] == [0.0, 0.001, 0.002]
    assert data["lag_amplitude [m]"] == [0.0005, 0.001]
    pts = data["points"]
    assert len(pts) == 6
    for key in ("rev_amplitude [m]", "lag_amplitude [m]", "storage [N/m]", "loss [N/m]",
                "equivalent_damping [N s/m]", "single_frequency_storage [N/m]",
                "single_frequency_loss [N/m]", "single_frequency_equivalent_damping [N s/m]"):
        assert all(key in p for p in pts), key
    p = next(p for p in pts if p["rev_amplitude [m]"] == 0.002 and p["lag_amplitude [m]"] == 5e-4)
    r = dual_frequency_stiffness("full", preset("device_a"), 4.2, 1.26, 0.002, 5e-4)
    assert p["storage [N/m]"] == pytest.approx(r.storage, rel=1e-12)
    assert p["loss [N/m]"] == pytest.approx(r.loss, rel=1e-12)
    assert p["equivalent_damping [N s/m]"] == pytest.approx(r.loss / (2 * 3.141592653589793 *
                                                                       1.26), rel=1e-12)
    assert "wrote" in capsys.readouterr().out


def test_dual_frequency_time_method_and_effect(tmp_path):
    js, png = tmp_path / "d.json", tmp_path / "d.svg"
    assert main(["dual-frequency", "--preset", "damper", "--model", "dashpot", "--effect",
                 "coulomb_friction:force_N=20", "--rev-frequency", "4.2", "--lag-frequency",
                 "1.26", "--rev-amplitude", "2mm", "--lag-amplitude", "0.2mm", "--method",
                 "time", "--json", str(js), "--plot", str(png)]) == 0
    data = json.loads(js.read_text())
    assert data["model"] == "dashpot+coulomb_friction"
    assert data["effects"] == {"coulomb_friction": {"force_N": 20.0, "reverse_ratio": 1.0}}
    (p,) = data["points"]
    assert p["method"] == "time_periodic"
    c_L = preset("damper").c_L
    V1 = 2e-3 * 2 * 3.141592653589793 * 4.2
    assert p["equivalent_damping [N s/m]"] == pytest.approx(
        c_L + 2 * 20.0 / (3.141592653589793 * V1), rel=1e-2)


def test_dual_frequency_help_states_units():
    text = " ".join(build_parser()._subparsers._group_actions[0].choices["dual-frequency"]
                    .format_help().split())
    assert "[Hz]" in text and "SI metres or with a unit" in text
    assert "START:STOP:COUNT (COUNT points linearly spaced)" in text
