"""The command line: params, simulate and the main job (demo), end to end."""

import json
import re

import pytest

from liquidamp.cli import main


def test_params_json_keys_and_values(tmp_path):
    out = tmp_path / "p.json"
    assert main(["params", "--preset", "paper_initial", "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["A_p [m^2]"] == pytest.approx(6.9115e-4, rel=1e-5)
    assert d["b_L [kg]"] == pytest.approx(89.4, abs=0.05)
    assert d["c1 [kg m^-4 s^-1]"] == pytest.approx(1.0485e9, rel=1e-4)
    assert d["c2 [kg m^-7]"] == pytest.approx(1.3539e14, rel=1e-4)
    assert d["S_t [1/m]"] == pytest.approx(187500.0)
    for key in d:
        assert key in ("name", "bulk_law") or re.fullmatch(r".+ \[.+\]", key), key


def test_simulate_json_and_plot(tmp_path):
    out, png = tmp_path / "s.json", tmp_path / "s.png"
    args = ["simulate", "--preset", "damper", "--frequency", "3", "--amplitude", "3mm",
            "--json", str(out), "--plot", str(png)]
    assert main(args) == 0
    d = json.loads(out.read_text())
    assert d["amplitude [m]"] == pytest.approx(0.003)
    assert 75 < d["dynamic_stiffness"]["phase [deg]"] < 95
    assert d["mass_conservation_error [-]"] < 1e-9
    assert d["steady_state_residual [-]"] < 1e-5
    assert d["min_pressure [Pa]"] > 0
    assert d["peak_force [N]"]["max"] > 0 > d["peak_force [N]"]["min"]
    assert png.stat().st_size > 10_000


def test_simulate_engines_agree(tmp_path):
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    common = ["simulate", "--preset", "device_a", "--frequency", "2", "--amplitude", "0.0015"]
    assert main(common + ["--engine", "compiled", "--json", str(a)]) == 0
    assert main(common + ["--engine", "python", "--json", str(b)]) == 0
    c = tmp_path / "c.json"
    assert main(common + ["--engine", "compiled", "--compiled-method", "rodas4",
                          "--json", str(c)]) == 0
    da, db, dc = (json.loads(f.read_text()) for f in (a, b, c))
    ka, kb, kc = (d["dynamic_stiffness"]["magnitude [N/m]"] for d in (da, db, dc))
    assert ka == pytest.approx(kb, rel=1e-6) and kc == pytest.approx(kb, rel=1e-6)
    # how each run was integrated is part of the output
    assert da["solver"]["method"] == "auto" and da["solver"]["explicit_steps"] > 0
    assert dc["solver"]["explicit_steps"] == 0 and dc["solver"]["rodas4_steps"] > 0
    assert db["solver"]["engine"] == "scipy" and db["solver"]["nfev"] > 0


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--preset", "dampr"], "unknown preset 'dampr'; valid: paper_initial"),
        (["--model", "ful"], "unknown model 'ful'; valid: full"),
        (["--amplitude", "30mm"], "past the chamber end"),
        (["--amplitude", "3 parsecs"], "amplitude"),
        (["--frequency", "0"], "frequency must be > 0"),
    ],
)
def test_simulate_bad_input_is_one_clear_line(capsys, argv, message):
    base = {"--preset": "reference", "--model": "full", "--frequency": "3", "--amplitude": "1mm"}
    for flag, value in zip(argv[::2], argv[1::2], strict=True):
        base[flag] = value
    args = ["simulate"] + [x for kv in base.items() for x in kv]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]


def test_demo_writes_the_case_study(tmp_path):
    out = tmp_path / "demo"
    assert main(["demo", "--out", str(out), "--quiet"]) == 0
    page = (out / "index.html").read_text()
    for stem in ("fig07_spring", "fig08_damper", "fig09_inerter", "fig10_device_a",
                 "fig11_device_b"):
        assert (out / f"{stem}.png").stat().st_size > 20_000
        assert f'src="{stem}.png"' in page
    # one table row per case: 3 x 2 specializations + 2 x 4 general + 2 reference runs,
    # then the baseline and final rows of the measured-data loop
    assert page.count("<tr><td>") == 6 + 8 + 2 + 2
    assert "Closing the loop with measured data" in page
    assert (out / "diagnosis" / "report" / "index.html").exists()
    assert "smooth_friction" in page  # the undeclared effect of the bundled records is found
    # lag damping in forward flight: quadratic loss gains, friction loses under 1/rev motion
    assert "Lag damping in forward flight" in page and 'src="lag_damping.png"' in page
    lag = json.loads((out / "lag_damping.json").read_text())
    paper, fric = lag["devices"].values()
    assert paper["floquet_damping_ratio [-]"][1] == pytest.approx(0.0491, abs=5e-4)
    assert fric["floquet_damping_ratio [-]"][2] < 0.6 * fric["floquet_damping_ratio [-]"][1]
