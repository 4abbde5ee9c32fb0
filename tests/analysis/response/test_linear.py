"""Transfer functions (eqs. 16, 18, 19), their limits, and the state-space linearization."""

import math

import control
import numpy as np
import pytest

from liquidamp.analysis.response.linear import (
    dashpot_inerter_tf,
    flow_tf,
    inertial_2state_tf,
    linearize,
    maxwell_tf,
    tf_frequency_response,
    transfer_function,
)
from liquidamp.device import preset, preset_names
from liquidamp.device.models import get_model, model_names
from liquidamp.errors import ParameterError

F = np.geomspace(0.05, 200.0, 41)  # [Hz], well beyond 0.5-20 Hz on both sides
S = 2j * math.pi * F
STATE_MODELS = [m for m in model_names() if get_model(m).n_states > 0]


def K(tf, f=F):
    return tf_frequency_response(tf, f)


def rel(a, b):
    return np.max(np.abs(a / b - 1.0))


@pytest.mark.parametrize("name", preset_names())
def test_eq18_tf_matches_hand_formula(name):
    p = preset(name)
    B, L, c, A = p.B_eff, p.L_t, p.c1, p.A_p
    hand = A**2 * B * S * (L * S + c) / (L * S**2 + c * S + B)
    assert rel(K(inertial_2state_tf(p)), hand) < 1e-12
    flow = A * B * S / (L * S**2 + c * S + B)
    assert rel(K(flow_tf(p)), flow) < 1e-12


def test_named_signals_and_maxwell_closed_form():
    p = preset("reference")
    for tf in (maxwell_tf(p), dashpot_inerter_tf(p), inertial_2state_tf(p)):
        assert tf.input_labels == ["stroke"] and tf.output_labels == ["force"]
    k = K(maxwell_tf(p))
    w = 2 * math.pi * F
    hand = p.k_D * (1j * w * p.T_D) / (1j * w * p.T_D + 1)
    assert rel(k, hand) < 1e-12
    assert rel(K(dashpot_inerter_tf(p)), p.c_L * S + p.b_L * S**2) < 1e-12


@pytest.mark.parametrize("name", ["reference", "inerter", "spring", "device_a"])
def test_eq18_limits_at_every_frequency(name):
    """B -> inf: eq.19; L_t -> 0: Maxwell; c1 -> 0: spring-inerter series; c1 -> inf: spring."""
    p = preset(name)
    A2 = p.A_p**2
    # incompressible: error ~ 1/B, shrinks 1000x per 1000x stiffer liquid
    e = [rel(K(inertial_2state_tf(p, B=p.B_eff * g)), K(dashpot_inerter_tf(p)))
         for g in (1e6, 1e9)]
    assert e[1] < 1.5e-3 * e[0] + 1e-12 and e[1] < 1e-5
    # no inertance: exactly Maxwell as L_t -> 0
    e = [rel(K(inertial_2state_tf(p, L_t=p.L_t * g)), K(maxwell_tf(p))) for g in (1e-6, 1e-9)]
    assert e[1] < 1.5e-3 * e[0] + 1e-12 and e[1] < 1e-5
    # no resistance: 1/K = 1/k_D + 1/(b_L s^2)
    series = 1.0 / (1.0 / p.k_D + 1.0 / (p.b_L * S**2))
    assert rel(K(inertial_2state_tf(p, c1=0.0)), series) < 1e-12
    assert rel(K(inertial_2state_tf(p, c1=p.c1 * 1e-9)), series) < 1e-5
    # closed channel: a spring k_D
    e = [rel(K(inertial_2state_tf(p, c1=p.c1 * g)), p.k_D + 0 * S) for g in (1e6, 1e9)]
    assert e[1] < 1.5e-3 * e[0] + 1e-12 and e[1] < 1e-3
    assert A2 * p.B_eff == pytest.approx(p.k_D, rel=1e-14)


@pytest.mark.parametrize("name", preset_names())
def test_full_at_rest_equals_eq18(name):
    """Quadratic loss has zero slope at rest: full (eq. 10) linearized = eq. (18) with c1."""
    p = preset(name)
    lin = linearize("full", p)
    assert rel(lin.frequency_response(F), K(inertial_2state_tf(p))) < 1e-10
    # three invariants (total mass, two density-pressure curves): zero eigenvalues
    ev = np.linalg.eigvals(lin.A)
    scale = np.max(np.abs(ev))
    assert np.sum(np.abs(ev) < 1e-9 * scale) == 3
    m = lin.minimal()
    assert m.nstates == 2
    assert rel(K(lin.transfer_function()), K(inertial_2state_tf(p))) < 1e-8


def test_reductions_at_rest():
    p = preset("reference")
    for name in ("no_inertia", "constant_bulk", "single_state", "volumetric"):
        assert rel(linearize(name, p).frequency_response(F), K(maxwell_tf(p))) < 1e-7, name
    assert rel(linearize("inertial", p).frequency_response(F), K(inertial_2state_tf(p))) < 1e-9


@pytest.mark.parametrize("name", model_names())
def test_state_space_and_transfer_function_agree(name):
    p = preset("device_a")
    lin = linearize(name, p)
    k = lin.frequency_response(F)
    assert rel(K(lin.transfer_function()), k) < 1e-8
    assert rel(K(transfer_function(name, p)), k) < 1e-7
    if lin.is_proper_in_stroke:
        ss = lin.stroke_system()
        kss = np.array([complex(np.asarray(ss(s)).reshape(-1)[0]) for s in S])
        assert rel(kss, k) < 1e-9
    else:
        with pytest.raises(ParameterError, match="improper"):
            lin.stroke_system()
    sysm = lin.system
    assert sysm.input_labels == ["stroke", "stroke_rate", "stroke_acceleration"]
    assert sysm.output_labels[0] == "force"


@pytest.mark.parametrize("name", [m for m in STATE_MODELS if get_model(m).analytic_jacobian])
def test_analytic_jacobian_matches_differences_off_rest(name):
    """Away from rest (stroke, flow, pressure offsets) the analytic and FD Jacobians agree."""
    p = preset("reference")
    m = get_model(name)
    x0 = m.initial_state(p, 0.0).astype(float)
    x0 = x0 + 0.05 * m.state_scales(p) * np.linspace(0.3, 1.0, m.n_states)
    u0 = np.array([2e-3, 0.01, 0.0])
    a = linearize(m, p, x0=x0, u0=u0)
    assert a.jacobian == "analytic"
    # central differences of the right-hand side with one Richardson step (linear._central)
    from liquidamp.analysis.response.linear import _central, _rel_steps

    sc = m.state_scales(p)
    h = _rel_steps(sc)
    Afd = np.column_stack([_central(lambda x: m.rhs(0.0, x, tuple(u0), p), x0, j, h[j])
                           for j in range(m.n_states)])
    Ta, Tb = a.A * sc[None, :] / sc[:, None], Afd * sc[None, :] / sc[:, None]
    assert np.max(np.abs(Ta - Tb)) < 1e-7 * np.max(np.abs(Ta))


def test_rate_input_convention_is_consistent():
    """K(s) = G_y(s) + s G_v(s) + s^2 G_a(s) from the three-input system."""
    p = preset("reference")
    lin = linearize("full", p)
    sysm = lin.system
    f = np.array([0.7, 7.0, 17.0])
    g = [np.array([complex(sysm(2j * math.pi * fi)[0, k]) for fi in f]) for k in range(3)]
    s = 2j * math.pi * f
    assert rel(g[0] + s * g[1] + s**2 * g[2], lin.frequency_response(f)) < 1e-9


def test_improper_models_as_static_maps():
    p = preset("reference")
    lin = linearize("dashpot_inerter", p)
    assert lin.n_states == 0
    assert np.allclose(lin.D[0], [0.0, p.c_L, p.b_L], rtol=1e-9)
    tf = lin.transfer_function()
    assert np.allclose(tf.num[0][0], [p.b_L, p.c_L, 0.0], rtol=1e-9)
    assert isinstance(tf, control.TransferFunction)


def test_bad_inputs():
    p = preset("reference")
    with pytest.raises(ParameterError, match="u0"):
        linearize("full", p, u0=[0.0, 0.0])
    with pytest.raises(ParameterError, match="0.025"):
        linearize("full", p, u0=[0.03, 0.0, 0.0])
    with pytest.raises(ParameterError, match="x0"):
        linearize("full", p, x0=[1.0, 2.0])
    with pytest.raises(ParameterError, match="B"):
        inertial_2state_tf(p, B=-1.0)
    with pytest.raises(ParameterError, match="S_t"):
        linearize("full", p.replace(S_t=0.0))
