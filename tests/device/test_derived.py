"""Derived quantities are derived (issue #11 item 1): c1, c2, S_t follow the geometry.

The values pinned in :data:`PINNED` were printed by the code before the redesign
(branch params-derived, parent of the redesign commit); every preset must keep them.
"""

import dataclasses
import json
import math
import pickle

import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import (
    DeviceParams,
    device_file_dict,
    load_device,
    load_device_file,
    preset,
    preset_names,
    write_device_file,
)
from liquidamp.device.effects import make_effect
from liquidamp.device.params import initial_c1, initial_c2
from liquidamp.errors import DataFileError, ParameterError
from liquidamp.structure.testmachine import HarmonicStroke

#: (c1 [kg m^-4 s^-1], c2 [kg m^-7], S_t [1/m], b_L [kg]) of each preset before the redesign.
PINNED = {
    "paper_initial": (1048506548.1355934, 135389539930555.56, 187500.0, 89.4054399519941),
    "paper_calibrated": (3732683311.3627124, 546973741319444.5, 187500.0, 89.4054399519941),
    "reference": (3732683311.3627124, 546973741319444.5, 187500.0, 89.4054399519941),
    "spring": (37326833113.62713, 5469737413194445.0, 18750.0, 8.94054399519941),
    "damper": (3732683311.3627124, 656368489583333.4, 18750.0, 8.94054399519941),
    "inerter": (3732683311.3627124, 546973741319444.5, 1312500.0, 625.8380796639588),
    "device_a": (1119804993.4088137, 164092122395833.34, 337500.0, 160.92979191358938),
    "device_b": (1119804993.4088137, 164092122395833.34, 18750.0, 8.94054399519941),
}


def test_pinned_presets_cover_every_preset():
    assert set(PINNED) == set(preset_names())


@pytest.mark.parametrize("name", sorted(PINNED))
def test_preset_values_unchanged(name):
    p = preset(name)
    for got, want in zip((p.c1, p.c2, p.S_t, p.b_L), PINNED[name], strict=True):
        assert got == pytest.approx(want, rel=1e-14)


# ---------------------------------------------------------------------------
# derived quantities follow their sources



@pytest.mark.parametrize("name", sorted(PINNED))
def test_geometry_changes_reach_c1_c2_S_t_for_every_preset(name):
    p = preset(name)
    q = p.replace(mu=2.0 * p.mu)
    assert q.c1 == pytest.approx(2.0 * p.c1, rel=1e-14)
    assert (q.c2, q.S_t) == (p.c2, p.S_t)
    q = p.replace(l_t=3.0 * p.l_t)
    assert q.c1 == pytest.approx(3.0 * p.c1, rel=1e-14)
    assert q.S_t == pytest.approx(3.0 * p.S_t, rel=1e-14)
    assert q.b_L == pytest.approx(3.0 * p.b_L, rel=1e-14)
    q = p.scaled(A_t=2.0)  # c1, c2 ~ 1/A_t^2, S_t ~ 1/A_t
    assert q.c1 == pytest.approx(p.c1 / 4, rel=1e-14)
    assert q.c2 == pytest.approx(p.c2 / 4, rel=1e-14)
    assert q.S_t == pytest.approx(p.S_t / 2, rel=1e-14)
    q = p.replace(rho_l=1.1 * p.rho_l)  # c2 ~ rho_l; c1 does not depend on it
    assert q.c2 == pytest.approx(1.1 * p.c2, rel=1e-14)
    assert q.c1 == p.c1
    assert p.unused() == {}


def test_preset_factors_are_the_paper_multipliers():
    # Table 3: final = alpha2 * alpha1 * initial; the factor holds alpha2 * alpha1
    p = preset("inerter")
    assert (p.c1_factor, p.c2_factor, p.S_t_factor) == pytest.approx((3.56, 4.04, 7.0))
    assert p.c1 == pytest.approx(3.56 * initial_c1(8.9e-4, 0.75, 4e-6), rel=1e-14)
    assert p.c2 == pytest.approx(4.04 * initial_c2(998.2, 4e-6), rel=1e-14)
    assert p.explicit == ()


def test_mu_override_changes_dashpot_stiffness_by_the_exact_factor():
    # dashpot model: F = c_L v, c_L = c1 A_p^2 -> K* = j omega c_L (phase +90 deg)
    p = preset("reference")
    q = p.replace(mu=2.0 * p.mu)
    stroke = HarmonicStroke(0.001, 3.0)
    w = 2 * math.pi * 3.0
    K = {r: dynamic_stiffness(steady_state("dashpot", r, stroke)) for r in (p, q)}
    for r in (p, q):
        assert K[r].magnitude == pytest.approx(w * r.c1 * r.A_p**2, rel=1e-9)
        assert K[r].phase_deg == pytest.approx(90.0, abs=1e-6)
    assert K[q].magnitude / K[p].magnitude == pytest.approx(2.0, rel=1e-9)


def test_device_file_l_t_multiplier_changes_S_t_b_L_and_inerter_stiffness(tmp_path):
    f = tmp_path / "long.toml"
    f.write_text('preset = "reference"\nmultipliers = { l_t = 2 }\n')
    p, q = preset("reference"), load_device(f)
    assert q.l_t == 2 * p.l_t
    assert q.S_t == pytest.approx(2 * p.S_t, rel=1e-14)
    assert q.b_L == pytest.approx(2 * p.b_L, rel=1e-14)
    assert q.c1 == pytest.approx(2 * p.c1, rel=1e-14)  # Poiseuille: c1 ~ l_t
    assert q.c2 == p.c2
    # inerter model: F = b_L a -> K* = -omega^2 b_L (phase 180 deg)
    stroke = HarmonicStroke(0.001, 3.0)
    w = 2 * math.pi * 3.0
    K = {r: dynamic_stiffness(steady_state("inerter", r, stroke)) for r in (p, q)}
    for r in (p, q):
        assert K[r].magnitude == pytest.approx(w**2 * r.b_L, rel=1e-9)
    assert K[q].magnitude / K[p].magnitude == pytest.approx(2.0, rel=1e-9)


def test_explicit_values_win_and_report_unused_inputs():
    p = preset("reference")
    q = p.replace(c1=2.0e9)
    assert q.c1 == 2.0e9 and q.explicit == ("c1",)
    assert set(q.unused()) == {"mu", "c1_factor"}
    assert "c1 is given explicitly" in q.unused()["mu"]
    assert q.derived()["unused"] == q.unused()
    # mu no longer enters anything; l_t and A_t still derive c2 and S_t
    r = q.replace(mu=5 * q.mu)
    assert r.c1 == 2.0e9 and r.c_L == q.c_L
    assert q.replace(l_t=2 * q.l_t).S_t == pytest.approx(2 * q.S_t)
    everything = p.replace(c1=1e9, c2=1e14, S_t=2e5)
    assert list(everything.unused()) == ["mu", "A_t", "l_t", "c1_factor", "c2_factor"]
    assert (everything.c1, everything.c2, everything.S_t) == (1e9, 1e14, 2e5)
    # None returns to the derived value (with the preset's factor)
    assert q.replace(c1=None).c1 == p.c1 and q.replace(c1=None) == p


def test_dataclasses_replace_keeps_explicit_and_derived_apart():
    p = preset("damper")
    q = dataclasses.replace(p, c1=1.5e9, c2=0.0)
    assert (q.c1, q.c2) == (1.5e9, 0.0)
    assert dataclasses.replace(q, mu=2 * p.mu).c1 == 1.5e9          # explicit stays
    assert dataclasses.replace(p, mu=2 * p.mu).c1 == pytest.approx(2 * p.c1)  # derived follows
    assert dataclasses.replace(q, c1=None, c2=None) == p
    # positional construction as before: c1, c2, S_t after inv_gamma2
    base = [8.9e-4, 998.2, 1.5513e9, 1.7279e-5, 1.7279e-5, 6.9115e-4, 4e-6, 0.75, 101325.0,
            1.35, 0.1, 0.1]
    assert DeviceParams(*base, 1e9).c1 == 1e9
    assert DeviceParams(*base).c1 == pytest.approx(preset("paper_initial").c1, rel=1e-4)


def test_scaled_factor_or_explicit_and_refuses_unused():
    p = preset("reference")
    assert p.scaled(c1=2.0).c1_factor == pytest.approx(2 * 3.56)
    q = p.replace(c1=1e9)
    assert q.scaled(c1=3.0).c1 == 3e9 and q.scaled(c1=3.0).c1_factor == p.c1_factor
    with pytest.raises(ParameterError, match=r"cannot scale mu by 2: it is unused \(c1 is given"):
        q.scaled(mu=2.0)
    assert q.scaled(mu=1.0) == q


def test_params_are_hashable_equal_and_pickle():
    p = preset("device_a")
    assert pickle.loads(pickle.dumps(p)) == p
    assert hash(p.replace(name="other")) == hash(p)
    assert p.replace(c1=p.c1) != p  # explicit is a different parameter set ...
    assert p.replace(c1=p.c1).c1 == p.c1  # ... with the same value today


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"c1_factor": -1.0}, r"c1_factor must be >= 0 \[-\], got -1"),
        ({"S_t": -1.0}, r"S_t must be >= 0 \[1/m\], got -1"),
        ({"c1": 0.0, "c2": 0.0}, "c1 and c2 are both 0"),
        ({"c1_factor": 0.0, "c2_factor": 0.0}, "c1 and c2 are both 0"),
        ({"name": 3}, "name must be a str, got int 3"),
    ],
)
def test_bad_factors_and_explicit_values_named(changes, message):
    with pytest.raises(ParameterError, match=message):
        preset("reference").replace(**changes)


# ---------------------------------------------------------------------------
# device files (issue #14)


def _write(tmp_path, name, text):
    f = tmp_path / name
    f.write_text(text)
    return f


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('preset = "reference"\nmultipliers = 3\n',
         r"multipliers = 3 is a int; allowed: a table of name = number"),
        ('preset = "reference"\nV01 = "1e-4"\n',
         r"V01 = '1e-4' is a str; allowed: a number \[m\^3\]"),
        ('preset = "reference"\nV01 = true\n', r"V01 = True is a bool; allowed: a number"),
        ('preset = "reference"\nmultipliers = { c1 = "2" }\n',
         r"multipliers.c1 = '2' is a str; allowed: a number >= 0"),
        ('preset = "reference"\nmultipliers = { volume = 2.0 }\n',
         "multipliers: cannot scale 'volume'"),
        ("preset = 3\n", "preset = 3 is a int; allowed: a string"),
        ('preset = "reference"\nbulk_law = 1\n', "bulk_law = 1 is a int; allowed: a string"),
        ('preset = "reference"\neffects = 3\n', r"effects = 3 is a int; allowed: a table of"),
        ('preset = "reference"\n[effects.smooth_friction]\nforce_N = "30"\n',
         r"effects.smooth_friction.force_N = '30' is a str; allowed: a number"),
        ('preset = "reference"\n[effects]\nsmooth_friction = 30\n',
         r"effects.smooth_friction = 30 is a int; allowed: a table of the effect"),
    ],
)
def test_device_file_type_errors_name_key_value_type(tmp_path, text, message):
    with pytest.raises(DataFileError, match=message):
        load_device_file(_write(tmp_path, "bad.toml", text))


def test_device_file_range_and_effect_errors_name_the_file(tmp_path):
    f = _write(tmp_path, "bad.toml", 'preset = "reference"\n[effects.stiction]\nforce_N = 1.0\n')
    with pytest.raises(ParameterError, match="device file 'bad.toml': effects.stiction: unknown "
                                             "effect 'stiction'"):
        load_device_file(f)
    f = _write(tmp_path, "neg.toml", 'preset = "reference"\nV01 = -1.0\n')
    with pytest.raises(ParameterError, match=r"device file 'neg.toml': V01 must be > 0"):
        load_device_file(f)
    f = _write(tmp_path, "mu.toml", 'preset = "reference"\nc1 = 1e9\nmultipliers = {mu = 2}\n')
    with pytest.raises(ParameterError, match="cannot scale mu by 2: it is unused"):
        load_device_file(f)
    j = _write(tmp_path, "dup.json", '{"preset": "reference", "mu": 1e-3, "mu": 2e-3}')
    with pytest.raises(DataFileError, match="key 'mu' given twice"):
        load_device_file(j)


def test_device_file_effects_toml_and_json(tmp_path):
    f = _write(tmp_path, "fr.toml", 'preset = "reference"\n[effects.smooth_friction]\n'
               'force_N = 30\n[effects.cavitation]\nvapour_pressure_Pa = 2339.0\n')
    dev = load_device_file(f)
    assert [e.name for e in dev.effects] == ["smooth_friction", "cavitation"]
    assert dev.effects[0].force_N == 30.0 and dev.source == str(f)
    assert dev.params == preset("reference") and dev.params.name == "fr"
    assert load_device(f) == dev.params
    j = _write(tmp_path, "fr.json", json.dumps(
        {"preset": "damper", "effects": {"coulomb_friction": {"force_N": 12.5}}}))
    dev = load_device_file(j)
    assert dev.effects[0].name == "coulomb_friction" and dev.effects[0].force_N == 12.5


def test_device_file_rotating_frame_table(tmp_path):
    f = _write(tmp_path, "rot.toml", 'preset = "reference"\n[effects.rotating_frame]\n'
               'rotor_speed_rad_per_s = 26.18\nmounting_radius_m = 0.3048\n'
               'axis_angle_rad = 3.141592653589793\n')
    (e,) = load_device_file(f).effects
    assert e.name == "rotating_frame" and e.parameters == {
        "rotor_speed_rad_per_s": 26.18, "mounting_radius_m": 0.3048,
        "axis_angle_rad": 3.141592653589793}
    p = preset("reference")
    assert e.pressure_rise(p) == pytest.approx(-p.rho_l * 26.18**2 * 0.3048 * p.V01 / p.A_p,
                                               rel=1e-12)
    f = _write(tmp_path, "bad.toml", 'preset = "reference"\n[effects.rotating_frame]\n'
               'rotor_speed_rad_per_s = -1\n')
    with pytest.raises(ParameterError, match="effects.rotating_frame: rotating_frame "
                                             "rotor_speed_rad_per_s must be >= 0"):
        load_device_file(f)


def test_device_file_explicit_values_and_json_null(tmp_path):
    f = _write(tmp_path, "x.toml", 'preset = "reference"\nc1 = 2e9\nS_t = 1e5\n')
    p = load_device(f)
    assert (p.c1, p.S_t, p.explicit) == (2e9, 1e5, ("c1", "S_t"))
    assert set(p.unused()) == {"mu", "l_t", "c1_factor"}
    j = _write(tmp_path, "n.json", '{"preset": "reference", "c1": null}')
    assert load_device(j).c1 == preset("reference").c1


@pytest.mark.parametrize("suffix", [".json", ".toml"])
@pytest.mark.parametrize("derived", [False, True])
def test_device_file_round_trip(tmp_path, suffix, derived):
    effects = (make_effect("smooth_friction", force_N=30.0), make_effect("series_compliance"),
               make_effect("cavitation"))
    for p in (preset("inerter").replace(friction_N=3.0, name="my \"device\" ü"),
              preset("reference").replace(c1=2e9, S_t=1e5, bulk_law="constant", name="")):
        f = write_device_file(tmp_path / f"dev{suffix}", p, effects, derived=derived)
        dev = load_device_file(f)
        assert dev.params == p and dev.params.explicit == p.explicit
        assert dev.params.name == (p.name or "dev")
        assert [e.parameters for e in dev.effects] == [e.parameters for e in effects]
        assert dev.params.derived() == p.derived()


def test_device_file_derived_table_is_checked(tmp_path):
    d = device_file_dict(preset("reference"), derived=True)
    d["mu"] = 2 * d["mu"]  # edited the input, left the output: refuse, do not guess
    j = _write(tmp_path, "edited.json", json.dumps(d))
    with pytest.raises(DataFileError, match=r"disagrees with the file's inputs: mu \[Pa s\] = "
                       r"0.00089 \(inputs give 0.00178\); c1 \[kg m\^-4 s\^-1\] = "
                       r"3732683311.3627124 \(inputs give 7465366622"):
        load_device_file(j)
    d = device_file_dict(preset("reference"), derived=True)
    d["derived"]["b_L [kg]"] = 100.0  # edited the output expecting an effect: refuse
    j = _write(tmp_path, "edited2.json", json.dumps(d))
    with pytest.raises(DataFileError, match=r"inputs: b_L \[kg\] = 100.0 \(inputs give 89.405"):
        load_device_file(j)


# ---------------------------------------------------------------------------
# calibration may only vary what the parameter set uses (issue #11)


def test_calibration_refuses_to_fit_an_unused_input(tmp_path):
    import numpy as np

    from liquidamp.analysis.measured.calibration import FitSpec, build, calibrate
    from liquidamp.analysis.measured.records import read_record, write_record

    t = np.arange(0.0, 2.0, 1 / 200)
    y = 1e-3 * np.sin(2 * np.pi * 3.0 * t)
    f = write_record(tmp_path / "r.csv", time=t, displacement=y,
                     force=2e3 * np.cos(2 * np.pi * 3.0 * t))
    rec = read_record(f)
    explicit = preset("reference").replace(c1=1e9, c2=1e14)
    with pytest.raises(ParameterError, match=r"cannot fit 'mu': the starting parameters do not "
                                             r"use it \(c1 is given explicitly"):
        calibrate([rec], params=explicit, spec=FitSpec.default(vary=("mu", "c2")))
    # a derived c1 follows a fitted mu: the multiplier reaches the model
    base = preset("reference")
    p, _ = build(base, (), FitSpec.default(vary=("mu",)), {"mu": 2.0})
    assert p.c1 == pytest.approx(2.0 * base.c1, rel=1e-14) and p.mu == 2.0 * base.mu
    # a c1 multiplier scales the explicit value when c1 is explicit
    p, _ = build(explicit, (), FitSpec.default(vary=("c1",)), {"c1": 3.0})
    assert p.c1 == 3e9
