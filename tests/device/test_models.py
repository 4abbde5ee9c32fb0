"""One contract over every registered device model (finite, passive, mass, Jacobian)."""

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.models import REGISTRY, get_model, model_names
from liquidamp.errors import ParameterError
from liquidamp.structure.testmachine import HarmonicStroke

ALL = model_names()


def test_registry_names_match_the_issue():
    assert set(ALL) == {
        "full", "no_inertia", "constant_bulk", "volumetric", "single_state", "inertial",
        "inertial_2state", "maxwell", "dashpot", "spring", "dashpot_inerter", "inerter",
    }
    for m in REGISTRY.values():
        assert m.equation and m.limits and m.description
        assert len(m.state_names) == len(m.state_units)


@pytest.fixture(scope="module")
def responses():
    params = preset("reference").replace(friction_N=5.0)
    stroke = HarmonicStroke(0.001, 3.0)
    return {name: steady_state(name, params, stroke) for name in ALL}


@pytest.mark.parametrize("name", ALL)
def test_contract_finite_and_steady(responses, name):
    r = responses[name]
    assert r.status == "steady"
    assert np.all(np.isfinite(r.force)) and np.all(np.isfinite(r.states))
    assert r.states.shape == (get_model(name).n_states, r.time.size)
    assert r.residual < 1e-5


@pytest.mark.parametrize("name", ALL)
def test_contract_passive(responses, name):
    # energy dissipated per cycle W = closed integral F dy = T mean(F v) >= 0
    r = responses[name]
    T = 1.0 / r.frequency
    W = T * float(np.mean(r.force * r.stroke_rate))
    scale = T * float(np.mean(np.abs(r.force * r.stroke_rate)))
    assert W >= -1e-6 * scale
    # friction alone dissipates 4 Ff Y per cycle; every model adds its fluid loss on top
    assert W >= 4 * 5.0 * 0.001 * (1 - 1e-3)


@pytest.mark.parametrize("name", [n for n in ALL if REGISTRY[n].conserves_mass])
def test_contract_mass_conservation(responses, name):
    assert responses[name].mass_error < 1e-9


@pytest.mark.parametrize("name", [n for n in ALL if REGISTRY[n].n_states])
@pytest.mark.parametrize("preset_name", ["reference", "inerter"])
def test_contract_jacobian_matches_finite_differences(name, preset_name):
    params = preset(preset_name).replace(bulk_law="gholizadeh")
    m = get_model(name)
    rng = np.random.default_rng(3)
    scales = m.state_scales(params)
    x = m.initial_state(params, 0.0) + 0.05 * scales * rng.standard_normal(m.n_states)
    u = (0.001, 0.02, -0.3)
    J = m.jacobian(0.0, x, u, params)
    Jfd = np.empty_like(J)
    for j in range(m.n_states):
        h = 1e-6 * scales[j]
        e = np.zeros(m.n_states)
        e[j] = h
        Jfd[:, j] = (m.rhs(0.0, x + e, u, params) - m.rhs(0.0, x - e, u, params)) / (2 * h)
    # compare column-scaled so tiny entries are judged against their row's size
    norm = np.abs(Jfd * scales).max(axis=1, keepdims=True) + 1e-300
    np.testing.assert_allclose(J * scales / norm, Jfd * scales / norm, atol=1e-6)


def test_ideal_elements_closed_forms(responses):
    p = preset("reference")
    w = 2 * np.pi * 3.0
    expected = {
        "spring": p.k_D,
        "dashpot": 1j * w * p.c_L,
        "dashpot_inerter": 1j * w * p.c_L - w**2 * p.b_L,
        "inerter": -(w**2) * p.b_L,
        "maxwell": p.k_D * 1j * w * p.T_D / (1 + 1j * w * p.T_D),
    }
    for name, K in expected.items():
        r = responses[name]
        # friction (5 N) adds 4 Ff/(pi Y) i to the first harmonic
        # (sampling the discontinuous sign(v) at 512 points costs ~1 % of that part)
        K_fric = 4 * 5.0 / (np.pi * 0.001)
        got = dynamic_stiffness(r).value
        assert abs(got - (K + 1j * K_fric)) <= 1e-6 * abs(K) + 1e-2 * K_fric, name


def test_models_refuse_parameters_outside_their_domain():
    p = preset("reference")
    with pytest.raises(ParameterError, match="needs S_t > 0"):
        steady_state("inertial_2state", p.replace(S_t=0.0), HarmonicStroke(0.001, 3.0))
    with pytest.raises(ParameterError, match="needs c1 > 0"):
        steady_state("maxwell", p.replace(c1=0.0), HarmonicStroke(0.001, 3.0))
