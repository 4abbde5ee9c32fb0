"""``liquidamp stiffness``: files, JSON layout, numbers that match the library."""

import csv
import json

import numpy as np

from liquidamp.analysis.response.linear import inertial_2state_tf, tf_frequency_response
from liquidamp.cli import main
from liquidamp.device import preset


def test_stiffness_report(tmp_path, capsys):
    out = tmp_path / "rep"
    js = tmp_path / "k.json"
    code = main(["stiffness", "--preset", "damper", "--frequency", "0.5:2:2",
                 "--amplitude", "1mm,0.002", "--out", str(out), "--json", str(js)])
    assert code == 0
    for name in ("stiffness.png", "stiffness.csv", "stiffness.json"):
        assert (out / name).stat().st_size > 200
    data = json.loads(js.read_text())
    assert data == json.loads((out / "stiffness.json").read_text())
    f = np.array(data["frequency [Hz]"])
    assert np.allclose(f, [0.5, 2.0])
    assert set(data["linear"]) == {"full", "maxwell", "dashpot_inerter", "inertial_2state"}
    assert set(data["nonlinear"]) == {"0.001", "0.002"} == set(data["equivalent"])
    k18 = tf_frequency_response(inertial_2state_tf(preset("damper")), f)
    assert np.allclose(data["linear"]["full"]["magnitude [N/m]"], np.abs(k18), rtol=1e-9)
    assert np.allclose(data["linear"]["inertial_2state"]["phase [deg]"],
                       np.degrees(np.angle(k18)), atol=1e-9)
    nl = data["nonlinear"]["0.001"]
    eq = data["equivalent"]["0.001"]
    # damper preset at 1 mm: equivalent within 10 % of the nonlinear first harmonic
    assert np.all(np.abs(np.array(eq["magnitude [N/m]"]) / nl["magnitude [N/m]"] - 1) < 0.1)
    assert all(eq["valid"])
    assert data["failures"] == []
    rows = list(csv.DictReader((out / "stiffness.csv").open()))
    assert len(rows) == 2 * (4 + 2 + 2)
    assert {r["curve"] for r in rows} >= {"linear:full", "nonlinear:full", "equivalent:full"}
    assert "wrote" in capsys.readouterr().out


def test_stiffness_bad_input(tmp_path, capsys):
    code = main(["stiffness", "--preset", "reference", "--frequency", "1,2",
                 "--amplitude", "3 parsecs", "--out", str(tmp_path)])
    assert code == 2
    assert "amplitude" in capsys.readouterr().err
    assert main(["stiffness", "--preset", "reference", "--frequency", "1"]) == 2
