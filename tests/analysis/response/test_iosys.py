"""to_iosys: named signals, agreement with control.linearize and with the test rig."""

import math

import control
import numpy as np
import pytest

from liquidamp.analysis.response.iosys import to_iosys
from liquidamp.analysis.response.linear import linearize
from liquidamp.coupled.testrig import simulate
from liquidamp.device import preset
from liquidamp.device.models import get_model, model_names
from liquidamp.structure.testmachine import HarmonicStroke


@pytest.mark.parametrize("name", model_names())
def test_signals_and_control_linearize_agree(name):
    p = preset("reference")
    sys = to_iosys(name, p)
    m = get_model(name)
    assert sys.input_labels == ["stroke", "stroke_rate", "stroke_acceleration"]
    assert sys.output_labels[0] == "force"
    assert sys.nstates == m.n_states
    if m.n_states:
        assert sys.state_labels == list(m.state_names)
    lin = linearize(name, p)
    # control.linearize uses forward differences with an absolute step: states that are
    # zero at rest can take a tiny step; states near p0 ~ 1e5 Pa need a larger one
    eps = 1e-12 if not np.any(lin.x0) else 1e-6
    cl = control.linearize(sys, lin.x0, lin.u0, eps=eps)
    for a, b in ((cl.A, lin.A), (cl.B, lin.B), (cl.C, lin.C), (cl.D, lin.D)):
        if b.size:
            scale = max(np.max(np.abs(b)), 1e-300)
            assert np.max(np.abs(a - b)) < 2e-4 * scale, name
    if m.n_states:  # and the stroke-to-force response, through the rate convention
        f = np.array([0.5, 3.0, 20.0])
        s = 2j * math.pi * f
        g = [np.array([complex(np.asarray(cl[0, k](si)).reshape(-1)[0]) for si in s])
             for k in range(3)]
        k_cl = g[0] + s * g[1] + s**2 * g[2]
        assert np.max(np.abs(k_cl / lin.frequency_response(f) - 1)) < 1e-3, name


def test_input_output_response_matches_testrig():
    p = preset("reference").replace(friction_N=30.0)
    stroke = HarmonicStroke(1e-3, 3.0)
    t = np.linspace(0.0, 0.5, 501)
    y, v, a = stroke(t)
    sys = to_iosys("inertial_2state", p)
    r = control.input_output_response(sys, t, [y, v, a], X0=[0.0, 0.0],
                                      solve_ivp_kwargs={"rtol": 1e-10, "atol": 1e-12,
                                                        "max_step": 1e-3})
    ref = simulate("inertial_2state", p, stroke, 0.5, t_eval=t)
    err = np.max(np.abs(r.outputs - ref.force)) / np.max(np.abs(ref.force))
    assert err < 1e-4
    assert np.max(np.abs(ref.force)) > 100.0  # friction included in both


def test_interconnect_with_a_host():
    """A mass on the device: m y'' = -F; the device gets stroke, rate and acceleration."""
    p = preset("reference")
    dev = to_iosys("inertial_2state", p, name="dev")
    mass = 10.0
    # host states y, v; acceleration output is algebraic in the force: feed y, v and use
    # the stroke-rate form of the device (its force does not depend on acceleration)
    host = control.ss([[0, 1], [0, 0]], [[0], [-1 / mass]], [[1, 0], [0, 1], [0, 0]],
                      [[0], [0], [0]], inputs="force", outputs=["stroke", "stroke_rate",
                                                                  "stroke_acceleration"],
                      states=["y", "v"], name="host")
    cl = control.interconnect([host, dev], inputs=[], outputs=["force", "stroke"])
    assert cl.nstates == 4
    x0 = np.array([1e-3, 0.0, 0.0, 0.0])
    lsys = control.linearize(cl, np.zeros(4), [], eps=1e-12)
    ev = np.linalg.eigvals(lsys.A)
    assert np.all(ev.real < 1e-9)  # passive device on a mass: no growth
    t = np.linspace(0, 0.2, 201)
    r = control.input_output_response(cl, t, X0=x0)
    assert np.all(np.isfinite(r.outputs))
