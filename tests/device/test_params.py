"""Parameters and presets against the paper's numbers (Titurus 2018, Tables 1-3)."""

import dataclasses
import math

import pytest

from liquidamp.device import DeviceParams, load_device, preset, preset_names
from liquidamp.device.params import initial_c1, initial_c2
from liquidamp.errors import DataFileError, ParameterError


def test_piston_area_from_bore_and_rod():
    # Sec. IV.A: 32 mm bore, 12 mm rod -> 691.15 mm^2 (Table 1: 6.9115e-4 m^2)
    assert preset("paper_initial").A_p == pytest.approx(6.9115e-4, rel=1e-5)
    assert preset("paper_initial").A_p == pytest.approx(math.pi / 4 * (0.032**2 - 0.012**2))


def test_fluid_inertance_is_89_4_kg():
    # Sec. IV.C: b_L = 89.4 kg, inertance-to-mass ratio 74.5 with m_D = 1.2 kg
    b_L = preset("paper_initial").b_L
    assert b_L == pytest.approx(89.4, abs=0.05)
    assert b_L / 1.2 == pytest.approx(74.5, abs=0.05)


def test_table2_initial_loss_coefficients():
    p = preset("paper_initial")
    assert p.c1 == pytest.approx(1.0485e9, rel=1e-4)
    assert p.c2 == pytest.approx(1.3539e14, rel=1e-4)
    assert p.S_t == pytest.approx(0.75 / 4e-6)
    assert p.g1 == pytest.approx(p.c1 / 998.2)
    assert p.g2 == pytest.approx(p.c2 / 998.2**2)


def test_table2_and_table3_multipliers():
    init = preset("paper_initial")
    cal = preset("paper_calibrated")
    for key, alpha in (("inv_gamma1", 0.75), ("inv_gamma2", 1.22), ("c1", 3.56), ("c2", 4.04)):
        assert getattr(cal, key) / getattr(init, key) == pytest.approx(alpha, rel=1e-12)
    assert cal.S_t == init.S_t
    # Table 3: final = alpha2 * alpha1 * initial
    table3 = {
        "spring": (2.1, 2.1, 10.0, 10.0, 0.1),
        "damper": (0.2, 0.2, 1.0, 1.2, 0.1),
        "inerter": (1.3e-4, 1.3e-4, 1.0, 1.0, 7.0),
        "device_a": (2.0, 2.0, 0.3, 0.3, 1.8),
        "device_b": (2.0, 2.0, 0.3, 0.3, 0.1),
    }
    alpha1 = (0.75, 0.75, 3.56, 4.04, 1.0)
    keys = ("inv_gamma1", "inv_gamma2", "c1", "c2", "S_t")
    for name, alpha2 in table3.items():
        p = preset(name)
        for key, a1, a2 in zip(keys, alpha1, alpha2, strict=True):
            assert getattr(p, key) / getattr(init, key) == pytest.approx(a1 * a2, rel=1e-12)


def test_derived_reduced_model_quantities():
    p = preset("reference")
    # symmetric device: k_D = 2 B0 A_p^2 / V0 and c_L = k_D T_D = c1 A_p^2 (eq. 16, 19)
    assert p.k_D == pytest.approx(2 * p.B01 * p.A_p**2 / p.V01, rel=1e-12)
    assert p.k_D * p.T_D == pytest.approx(p.c_L, rel=1e-12)
    # eq. (2) at p0: 1/B0 = (1 - X0)/B_l + X0/(n p0), compliances of liquid and air add
    X0 = p.X01
    assert p.B01 == pytest.approx(1 / ((1 - X0) / p.B_l + X0 / (p.n * p.p0)) * (1.0), rel=1e-12)


def test_geometric_estimates():
    assert initial_c1(8.9e-4, 0.75, 4e-6) == pytest.approx(8 * math.pi * 8.9e-4 * 0.75 / 16e-12)
    assert initial_c2(998.2, 4e-6) == pytest.approx(998.2 / (2 * 0.48**2 * 16e-12))


def test_params_are_frozen_and_replace_validates():
    p = preset("reference")
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.c1 = 1.0
    with pytest.raises(ParameterError, match=r"V01 must be > 0 \[m\^3\], got -1"):
        p.replace(V01=-1.0)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("V01", 0.0, "V01 must be > 0"),
        ("A_p", -1e-4, "A_p must be > 0"),
        ("rho_l", 0.0, "rho_l must be > 0"),
        ("inv_gamma1", -0.1, "inv_gamma1 must be >= 0"),
        ("n", 3.0, r"n must lie in \[1, 1.67\]"),
        ("c1", float("nan"), "c1 must be finite"),
        ("bulk_law", "ideal", "unknown bulk_law 'ideal'; valid: gholizadeh, constant"),
    ],
)
def test_bad_parameters_named(field, value, message):
    with pytest.raises(ParameterError, match=message):
        preset("reference").replace(**{field: value})


def test_unknown_preset_lists_valid_names():
    with pytest.raises(ParameterError) as err:
        preset("dampr")
    for name in preset_names():
        assert name in str(err.value)


def test_device_file_toml_and_json(tmp_path):
    f = tmp_path / "mine.toml"
    f.write_text(
        'mu = 1e-3\nrho_l = 1000.0\nB_l = 2e9\nV01 = 2e-5\nV02 = 2e-5\nbore_m = 0.04\n'
        'rod_m = 0.0\nA_t = 1e-5\nl_t = 1.0\np0 = 1e5\nn = 1.4\ninv_gamma1 = 0.01\n'
        'inv_gamma2 = 0.01\n'
    )
    p = load_device(f)
    assert p.A_p == pytest.approx(math.pi * 0.02**2)
    assert p.S_t == pytest.approx(1e5)
    assert p.name == "mine"
    j = tmp_path / "scaled.json"
    j.write_text('{"preset": "paper_initial", "multipliers": {"c1": 2.0}}')
    assert load_device(j).c1 == pytest.approx(2 * preset("paper_initial").c1)


def test_device_file_errors(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text('preset = "reference"\nvolume = 3\n')
    with pytest.raises(DataFileError, match="unknown key"):
        load_device(f)
    g = tmp_path / "short.toml"
    g.write_text("mu = 1e-3\n")
    with pytest.raises(DataFileError, match="missing key"):
        load_device(g)
    with pytest.raises(DataFileError, match="does not exist"):
        load_device(tmp_path / "nope.toml")


def test_every_preset_constructs_and_is_positive():
    for name in preset_names():
        p = preset(name)
        assert isinstance(p, DeviceParams)
        assert p.k_D > 0 and p.T_D > 0 and p.b_L > 0
