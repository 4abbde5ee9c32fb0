"""Articulated blade in lead-lag: closed forms and the device port."""

import math

import control
import numpy as np
import pytest

from liquidamp.errors import ParameterError
from liquidamp.structure import ArticulatedBlade, load_blade


def test_lag_frequency_closed_form():
    # nu^2 = e S_b / I_b + K / (I_b Omega^2)  (Johnson 2013, Sec. 16.3)
    b = load_blade("hammond1974").replace(lag_spring=2.0e4)
    W = 2 * math.pi * 4.0
    nu2 = b.hinge_offset * b.static_moment / b.inertia + 2.0e4 / (b.inertia * W * W)
    assert b.nu(W) == pytest.approx(math.sqrt(nu2), rel=1e-12)
    lam = np.linalg.eigvals(b.statespace(W).A)
    # eigenvalues -C/(2I) +- i sqrt(omega^2 - (C/2I)^2)
    s = b.lag_damping / (2 * b.inertia)
    wd = math.sqrt(nu2 * W * W - s * s)
    assert np.allclose(np.sort_complex(lam), [-s - 1j * wd, -s + 1j * wd], rtol=1e-12)


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_port_connects_a_linear_damper_by_name():
    # a linear damper F = c dy/dt on the port adds c arm^2 of lag damping
    b = load_blade("hammond1974").replace(lag_damping=0.0)
    W, c = 2 * math.pi * 4.0, 6.0e4
    port = b.ports[0]
    damper = control.ss([], [], [], [[c]], inputs=[port.rate_output], outputs=[port.force_input],
                        name="damper")
    closed = control.interconnect([b.statespace(W), damper], inplist=["force"], outlist=["zeta"])
    ref = b.replace(lag_damping=c * b.damper_arm**2).statespace(W)
    assert np.allclose(np.sort_complex(np.linalg.eigvals(closed.A)),
                       np.sort_complex(np.linalg.eigvals(ref.A)), rtol=1e-10)


@pytest.mark.parametrize("field,value,text", [
    ("inertia", 0.0, "blade inertia I_b must be > 0 [kg m^2], got 0"),
    ("mass", -1.0, "blade mass must be > 0 [kg], got -1"),
    ("static_moment", 400.0, "S_b^2 <= m_b I_b"),
])
def test_bad_blade(field, value, text):
    with pytest.raises(ParameterError, match=text.replace("^", r"\^").replace("[", r"\[")
                       .replace("]", r"\]")):
        load_blade("hammond1974").replace(**{field: value})


def test_blade_is_frozen():
    b = load_blade("hammond1974")
    with pytest.raises(AttributeError):
        b.inertia = 1.0  # type: ignore[misc]
    assert isinstance(b, ArticulatedBlade)
