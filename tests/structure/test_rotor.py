"""Ground-resonance rotor: multiblade form, closed forms, files and bad input.

Model checked against Coleman & Feingold (NACA Rep. 1351, 1958) and the
Hammond (1974) rotor (J. AHS 19(4), 14-23) as parametrized in DESIGN.md.
"""

import json
import math

import control
import numpy as np
import pytest

from liquidamp.errors import ParameterError
from liquidamp.structure import GroundResonanceRotor, load_rotor, multiblade_names

RPM = 2 * math.pi / 60


@pytest.fixture(scope="module")
def hammond():
    return load_rotor("hammond1974")


def test_preset_values(hammond):
    b = hammond.blade
    assert (hammond.n_blades, b.mass, b.static_moment, b.inertia, b.hinge_offset) == (
        4, 94.9, 289.1, 1084.7, 0.3048)
    assert b.lag_spring == 0.0 and b.lag_damping == 4067.5
    assert (hammond.hub_mass_x, hammond.hub_mass_y) == (8026.6, 3283.6)
    assert hammond.hub_stiffness_x == hammond.hub_stiffness_y == 1240481.8
    assert (hammond.hub_damping_x, hammond.hub_damping_y) == (51078.7, 25539.3)


@pytest.mark.parametrize("psi", [0.0, 0.3, 1.7])
def test_multiblade_matrices_constant_for_alike_blades(hammond, psi):
    W = 250 * RPM
    A0, B0 = hammond.multiblade_matrices(W, 0.0)
    A1, B1 = hammond.multiblade_matrices(W, psi)
    assert np.allclose(A0, A1, atol=1e-9 * np.abs(A0).max())
    assert np.allclose(B0[:, 4:6], B1[:, 4:6], atol=1e-12)  # the hub forces


@pytest.mark.parametrize("rpm", [80.0, 200.0, 350.0])
def test_reactionless_modes_real_part(hammond, rpm):
    # collective and differential lag modes do not couple with the hub:
    # real part -C/(2 I_b) at every rotor speed (underdamped for rpm > 63)
    lam = np.linalg.eigvals(hammond.multiblade_statespace(rpm * RPM).A)
    s = -hammond.blade.lag_damping / (2 * hammond.blade.inertia)
    wd = math.sqrt(hammond.blade.lag_frequency(rpm * RPM) ** 2 - s * s)
    n_match = np.sum(np.abs(lam - complex(s, wd)) < 1e-8)
    assert n_match == 2  # zeta_0 and zeta_d


def test_isotropic_hub_matches_complex_quartic(hammond):
    # isotropic hub: cyclic lag + hub reduce to the complex quartic
    # [I (l - iW)^2 + C (l - iW) + e S W^2](M l^2 + C_h l + K) - (N/2) S^2 l^4 = 0
    r = hammond.replace(hub_mass_y=hammond.hub_mass_x, hub_damping_y=hammond.hub_damping_x)
    b = r.blade
    for rpm in (150.0, 260.0):
        W = rpm * RPM
        pa = np.poly1d([b.inertia, b.lag_damping - 2j * W * b.inertia,
                        -b.inertia * W * W - 1j * W * b.lag_damping
                        + b.hinge_offset * b.static_moment * W * W])
        pd = np.poly1d([r.total_mass_x, r.hub_damping_x, r.hub_stiffness_x])
        roots = (pa * pd - np.poly1d([r.n_blades / 2 * b.static_moment**2, 0, 0, 0, 0])).r
        lam = np.linalg.eigvals(r.multiblade_statespace(W).A)
        for z in np.concatenate([roots, roots.conj()]):
            assert np.min(np.abs(lam - z)) < 1e-7 * abs(z)


def test_port_names_and_inoperative(hammond):
    assert [p.force_input for p in hammond.ports] == ["force_1", "force_2", "force_3", "force_4"]
    sys = hammond.statespace(200 * RPM, psi=0.4)
    assert "stroke_rate_3" in sys.output_labels and "force_2" in sys.input_labels
    failed = hammond.with_inoperative_damper(3)
    assert failed.blade_damping == (4067.5, 4067.5, 0.0, 4067.5)
    assert not failed.blades_alike


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_device_on_port_replaces_the_damper(hammond):
    # an external linear damper c = C/arm^2 on blade 2's port, with blade 2's own
    # damper removed, reproduces the nominal rotor at any azimuth
    W, psi = 230 * RPM, 0.9
    a = hammond.blade.damper_arm
    host = hammond.with_lag_dampers([4067.5, 0.0, 4067.5, 4067.5]).statespace(W, psi)
    p = hammond.ports[1]
    damper = control.ss([], [], [], [[4067.5 / a**2]], inputs=[p.rate_output],
                        outputs=[p.force_input], name="damper")
    closed = control.interconnect([host, damper], inplist=["hub_force_x"], outlist=["hub_x"])
    ref = hammond.statespace(W, psi)
    assert np.allclose(closed.A, ref.A, rtol=1e-10, atol=1e-9)


def test_rotor_from_files(tmp_path, hammond):
    t = tmp_path / "r.toml"
    t.write_text('preset = "hammond1974"\nlag_damping = [0.0, 4067.5, 4067.5, 4067.5]\n')
    r = load_rotor(t)
    assert r.blade_damping[0] == 0.0 and r.hub_mass_x == hammond.hub_mass_x
    j = tmp_path / "r.json"
    j.write_text(json.dumps({
        "n_blades": 3, "hub_mass_x": 1000.0, "hub_mass_y": 1000.0, "hub_stiffness_x": 1e5,
        "hub_stiffness_y": 1e5, "blade": {"mass": 10.0, "static_moment": 20.0,
                                          "inertia": 50.0, "hinge_offset": 0.2,
                                          "damper_arm": 0.1, "lag_damping": 100.0}}))
    r3 = load_rotor(j)
    assert r3.n_blades == 3 and multiblade_names(3) == ("zeta_0", "zeta_1c", "zeta_1s")
    bad = tmp_path / "bad.toml"
    bad.write_text('preset = "hammond1974"\nhub_mas_x = 1.0\n')
    with pytest.raises(ParameterError, match="unknown key"):
        load_rotor(bad)


def test_bad_rotor_input(hammond):
    with pytest.raises(ParameterError, match="n_blades >= 3, got 2"):
        hammond.replace(n_blades=2, lag_damping=None).multiblade_statespace(20.0)
    with pytest.raises(ParameterError, match=r"hub mass x must be > 0 \[kg\], got 0"):
        hammond.replace(hub_mass_x=0.0)
    with pytest.raises(ParameterError, match=r"blade index must lie in \[1, 4\], got 5"):
        hammond.with_inoperative_damper(5)
    with pytest.raises(ParameterError, match="one value per blade"):
        hammond.with_lag_dampers([1.0, 2.0])
    with pytest.raises(ParameterError, match="all blades are alike"):
        hammond.with_inoperative_damper(1).multiblade_statespace(20.0)
    with pytest.raises(ParameterError, match="unknown rotor preset 'nope'"):
        load_rotor("nope")
    assert isinstance(hammond, GroundResonanceRotor)
