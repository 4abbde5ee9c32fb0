"""Friction in series with freeplay (issue #12 item 1): rod -> dead band -> friction element.

Closed forms under y = A sin(w t) on a dashpot whose own force is negligible
(c1 = 1e-6, c_L about 5e-13 N s/m), so that the load cell reads the friction alone:

* Coulomb friction behind a dead band of half-width g: the loop is flat while the rod
  crosses the gap (a stroke of 2g after each reversal) and F_c elsewhere; the energy
  dissipated per cycle is 2 F_c (2A - 2g).
* Dahl friction (smooth_friction with static_ratio 1) on the rod dissipates
  2 F_c (2A - 2 tanh(s A) / s) per cycle, s = sigma0 / F_c (the bristle state from
  dz/dy = s (1 - z sign(v)) on the periodic orbit, z at reversal = tanh(s A)); behind the
  dead band the bristles unload elastically as the rod backs off (the piston springs back
  with the rod), the rod then crosses the gap unloaded, and the loop is the rod's with A
  replaced by A - g: 2 F_c (2 (A - g) - 2 tanh(s (A - g)) / s).
"""

import json
import math

import numpy as np
import pytest

from liquidamp.analysis.measured.fit_spec import Parameter
from liquidamp.analysis.measured.synthetic import recipe_from_dict, synthetic_record
from liquidamp.commands._args import parse_effect
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import (
    CoulombFriction,
    Freeplay,
    SeriesCompliance,
    SmoothFriction,
    with_effects,
)
from liquidamp.device.kernels import Z_HOLD
from liquidamp.device.models import get_model
from liquidamp.device.presets import device_file_text, load_device_file
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

A, G, FC, F_HZ = 2e-3, 3e-4, 100.0, 2.0
P = preset("reference").replace(c1=1e-6)  # the dashpot's own force is negligible
S = HarmonicStroke(A, F_HZ)
DELTA = 0.05 * G + 1e-7  # the dead band's smoothing width (kernels.play_contact)


def _steady(model, engine):
    r = steady_state(model, P, S, options=SolverOptions(engine=engine, rtol=1e-8))
    assert r.status == "steady"
    return r


def _work(r):
    """Energy dissipated per cycle, the integral of F dy = F v dt over a period [J]."""
    return float(np.sum(r.force * r.stroke_rate)) / (F_HZ * r.time.size)


def test_coulomb_behind_freeplay_is_flat_in_the_gap_and_dissipates_2Fc_2A_minus_2g():
    m = with_effects(get_model("dashpot"), Freeplay(G), CoulombFriction(FC, location="piston"))
    runs = {e: _steady(m, e) for e in ("scipy", "compiled")}
    for r in runs.values():
        y, v, F = r.stroke, r.stroke_rate, r.force
        # after each reversal the rod crosses the gap (a stroke of 2g) before contact
        gap = ((v < 0) & (y > A - 2 * G + DELTA)) | ((v > 0) & (y < -A + 2 * G - DELTA))
        contact = ((v < 0) & (y < A - 2 * G - 5 * DELTA)) | ((v > 0) & (y > -A + 2 * G + 5 * DELTA))
        assert gap.sum() > 100 and contact.sum() > 300
        assert np.max(np.abs(F[gap])) < 0.01 * FC
        assert np.max(np.abs(np.abs(F[contact]) - FC)) < 0.01 * FC
        assert np.all(np.sign(F[contact]) == np.sign(v[contact]))
        assert _work(r) == pytest.approx(2 * FC * (2 * A - 2 * G), rel=0.01)
    # the two engines integrate the same equations to the same loop
    assert np.max(np.abs(runs["scipy"].force - runs["compiled"].force)) < 1e-3 * FC
    # on the rod the same friction dissipates 4 F_c A: the location matters
    rod = _steady(with_effects(get_model("dashpot"), Freeplay(G), CoulombFriction(FC)),
                  "compiled")
    assert _work(rod) == pytest.approx(4 * FC * A, rel=1e-3)


@pytest.mark.parametrize("sigma0", [2e5, 1e7])
def test_dahl_friction_behind_freeplay_matches_the_closed_form(sigma0):
    s = sigma0 / FC

    def closed(a):
        return 2 * FC * (2 * a - 2 * math.tanh(s * a) / s)

    rod = with_effects(get_model("dashpot"), SmoothFriction(FC, sigma0))
    assert _work(_steady(rod, "compiled")) == pytest.approx(closed(A), rel=1e-6)
    pis = with_effects(get_model("dashpot"), Freeplay(G),
                       SmoothFriction(FC, sigma0, location="piston"))
    runs = {e: _steady(pis, e) for e in ("scipy", "compiled")}
    for r in runs.values():
        assert _work(r) == pytest.approx(closed(A - G), rel=0.005)
        # the gap: after the spring-back stroke L the rod crosses 2g with no force
        y, v, F = r.stroke, r.stroke_rate, r.force
        L = math.log(1 + math.tanh(s * (A - G))) / s
        gap = (v < 0) & (y > A - L - 2 * G + 2 * DELTA) & (y < A - L - 2 * DELTA)
        assert gap.sum() > 10
        assert np.max(np.abs(F[gap])) < Z_HOLD * FC
    assert np.max(np.abs(runs["scipy"].force - runs["compiled"].force)) < 1e-3 * FC


def test_location_is_a_composition_choice_not_a_parameter(tmp_path):
    e = parse_effect("coulomb_friction:force_N=100,location=piston")
    assert e == CoulombFriction(100.0, location="piston")
    assert e.parameters == {"force_N": 100.0, "reverse_ratio": 1.0}  # what a fit may vary
    assert e.as_dict() == {"force_N": 100.0, "reverse_ratio": 1.0, "location": "piston"}
    assert str(e) == "coulomb_friction(force_N=100, reverse_ratio=1, location=piston)"
    assert e.replace(location="rod") == CoulombFriction(100.0)
    f = SmoothFriction(20.0, 1e6, location="piston")
    for fmt in ("toml", "json"):
        path = tmp_path / f"d.{fmt}"
        path.write_text(device_file_text(preset("reference"), (e, Freeplay(1e-4), f), fmt=fmt))
        back = load_device_file(path).effects
        assert set(back) == {e, Freeplay(1e-4), f}
    with pytest.raises(ParameterError, match="location must be one of 'rod', 'piston'"):
        parse_effect("coulomb_friction:location=seal")
    with pytest.raises(ParameterError, match="location must be one of"):
        CoulombFriction(1.0, location=1.0)
    with pytest.raises(ParameterError, match="unknown coulomb_friction parameter 'location'"):
        Parameter("coulomb_friction.location", 1.0, 0.5, 2.0)
    with pytest.raises(ParameterError, match="cannot sit behind series_compliance"):
        with_effects(get_model("full"), SeriesCompliance(1e6),
                     SmoothFriction(10.0, location="piston"))
    m = with_effects(get_model("full"), Freeplay(1e-4), CoulombFriction(5.0, location="piston"))
    assert m.effect("coulomb_friction").location == "piston"
    assert "location=piston" in m.description


def test_synthetic_record_with_freeplay_and_friction_at_the_piston():
    """The diagnosis's test record: freeplay + Coulomb friction behind it (full model).

    The friction does not move the piston, so the true force differs from the same record
    with the friction on the rod by F_c sign(v) (1 - C): F_c while the rod crosses the gap,
    0 in contact; the gap is crossed over a fraction arccos(1 - 2g/A)/pi of each period."""
    g, Y, fc = 1e-4, 2e-3, 30.0
    common = dict(preset="paper_calibrated", frequency=3.0, amplitude=Y, cycles=2, seed=7,
                  sampling_rate=3000.0, distortion=(0.0, 0.0), start_phase=0.0)
    truth = {"freeplay": {"gap_m": g}, "coulomb_friction": {"force_N": fc, "location": "piston"}}
    rec = synthetic_record(effects=truth, **common)
    recipe = recipe_from_dict(json.loads(json.dumps(rec.meta["recipe"])))
    assert recipe.effect_objects() == (Freeplay(g), CoulombFriction(fc, location="piston"))
    assert rec.meta["true_effects"]["coulomb_friction"] == {"force_N": fc, "reverse_ratio": 1.0,
                                                            "location": "piston"}
    rod = synthetic_record(effects={"freeplay": {"gap_m": g},
                                    "coulomb_friction": {"force_N": fc}}, **common)
    diff = rod.meta["true_force"] - rec.meta["true_force"]
    assert np.max(np.abs(diff)) == pytest.approx(fc, rel=1e-6)
    between = (np.abs(diff) > 0.02 * fc) & (np.abs(diff) < 0.98 * fc)  # the C1 onsets
    assert np.mean(between) < 0.01
    assert np.mean(np.abs(diff) > 0.5 * fc) == pytest.approx(
        math.acos(1 - 2 * g / Y) / math.pi, abs=0.005)
