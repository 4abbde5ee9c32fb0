"""Record to margin on the command line (issue 22, item 5): synthetic records of a known
device, ``calibrate --save-device``, then ``sweep ... --device --confidence`` with intervals;
``--degrade`` with the Floquet and smeared answers; bad input refused before work."""

import json

import numpy as np
import pytest

from liquidamp.analysis.measured.synthetic import Recipe, write_synthetic
from liquidamp.cli import main

SECTION = """name = "hodges-pierce-10m"
a = -0.2
e = -0.1
mu = 20.0
r2 = 0.24
sigma = 0.4
semichord = 1.0
omega_theta = 25.132741228718345
air_density = 1.225
span = 10.0
pitch_arm = 0.25
"""


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    d = tmp_path_factory.mktemp("margin")
    rec = write_synthetic(d / "rec.csv", Recipe(preset="paper_calibrated", cycles=6, seed=3,
                                                force_noise=3.0))
    dev = d / "d.toml"
    assert main(["calibrate", str(rec), "--preset", "paper_calibrated", "--vary",
                 "inv_gamma1,c1", "--sizing", "preset", "--max-nfev", "30", "--save-device",
                 str(dev), "--json", str(d / "cal.json"), "--quiet"]) == 0
    return d, dev


def test_record_to_ground_resonance_margin(fitted, capsys):
    """All dampers (Coleman) through a 1 m arm: both edges with intervals, near the true
    device's band (paper_calibrated: 206.5-305.0 rpm)."""
    d, dev = fitted
    out, fig = d / "gr.json", d / "gr.png"
    assert main(["sweep", "ground-resonance", "--rotor", "hammond1974", "--device", str(dev),
                 "--arm", "1m", "--rpm", "150:350:11", "--confidence", "95%", "--json",
                 str(out), "--plot", str(fig), "--quiet"]) == 0
    assert "unstable ranges [rpm] (edge [interval])" in capsys.readouterr().out
    j = json.loads(out.read_text())
    m = j["margin"]
    assert m["confidence"] == 0.95 and "delta method" in m["method"]
    assert m["uncertainty"]["varied"] == ["inv_gamma1", "c1"] and m["uncertainty"]["log"] == \
        [True, True]
    band, = m["unstable_ranges [rpm]"]
    for k in ("start", "end"):
        lo, hi = band[f"{k}_interval"]
        assert lo < band[k] < hi and hi - lo < 20.0
    assert (band["start"], band["end"]) == pytest.approx((206.5, 305.0), abs=3.0)
    z = m["min_damping_ratio"]
    assert z["interval"][0] < z["value"] < z["interval"][1] and z["value"] < 0
    assert j["sized"] is False and fig.stat().st_size > 0


def test_record_to_margin_with_a_failed_damper(fitted):
    """--inoperative 1 (Floquet) inside the band: open edges (zero width, flagged), the
    minimum damping ratio with its interval."""
    d, dev = fitted
    out = d / "gr1.json"
    assert main(["sweep", "ground-resonance", "--device", str(dev), "--arm", "1.5m",
                 "--rpm", "240,260", "--inoperative", "1", "--confidence", "0.95",
                 "--json", str(out), "--quiet"]) == 0
    m = json.loads(out.read_text())["margin"]
    band, = m["unstable_ranges [rpm]"]
    assert band["open_start"] and band["open_end"] and band["start_interval"] == [240.0,
                                                                                   240.0]
    z = m["min_damping_ratio"]
    assert z["interval"][0] < z["value"] < z["interval"][1] < 0
    assert "Floquet" in m["note"]


def test_record_to_flutter_margin(fitted, capsys):
    d, dev = fitted
    sec = d / "wing.toml"
    sec.write_text(SECTION)
    out = d / "fl.json"
    assert main(["sweep", "flutter", "--section", str(sec), "--device", str(dev),
                 "--speeds", "2.0:2.6:7", "--confidence", "0.9", "--samples", "40",
                 "--json", str(out),
                 "--plot", str(d / "fl.png"), "--quiet"]) == 0
    j = json.loads(out.read_text())
    m = j["margin"]
    f = m["flutter_speed"]
    s = j["sampling"]
    assert "sampling" in s["method"] and s["flutter_share_of_draws"] == 1.0
    lo, hi = s["flutter_speed"]["interval"]
    assert lo <= f["value"] <= hi
    assert f["interval"][0] < f["value"] < f["interval"][1]
    assert f["value"] == pytest.approx(2.3274, abs=5e-3)  # the true device: 2.32736
    assert m["confidence"] == 0.9
    assert m["unstable_ranges [U/(b omega_theta)]"][0]["start"] == f["value"]


def test_degraded_damper_floquet_beside_smeared(tmp_path):
    out, fig = tmp_path / "deg.json", tmp_path / "deg.png"
    assert main(["sweep", "ground-resonance", "--rpm", "180:330:7", "--degrade", "2:0.5",
                 "--json", str(out), "--plot", str(fig), "--quiet"]) == 0
    deg = json.loads(out.read_text())["degradation"]
    zi = deg["intact"]["min_damping_ratio"]["value"]
    lf, ls = (zi - deg[k]["min_damping_ratio"]["value"] for k in ("floquet", "smeared"))
    assert deg["loss_ratio_smeared_to_floquet"] == pytest.approx(ls / lf, rel=1e-12)
    assert 0 < ls < lf
    assert np.isfinite(deg["damping_loss"]["floquet"]) and fig.stat().st_size > 0


@pytest.mark.parametrize("argv, message", [
    (["--rpm", "200:300:3", "--confidence", "0.95"], "needs --device FILE"),
    (["--rpm", "200:300:3", "--confidence", "1.5"], "confidence must be in (0, 1)"),
    (["--rpm", "200:300:3", "--degrade", "1:2"], "fraction of its damper force lost"),
    (["--rpm", "200:300:3", "--degrade", "1:0.5", "--inoperative", "2"], "without"),
])
def test_bad_margin_input_is_refused(argv, message, capsys):
    code = main(["sweep", "ground-resonance", *argv, "--json", "-", "--quiet"])
    assert code == 2 and message in capsys.readouterr().err
