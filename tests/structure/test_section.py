"""Typical section: Theodorsen's function, Jones' approximation, state space, input."""

import math

import numpy as np
import pytest
from scipy.special import j0, j1, y0, y1

from liquidamp.errors import ParameterError
from liquidamp.structure import TypicalSection, load_section
from liquidamp.structure.aero import jones, theodorsen

# Theodorsen's function, tabulated (Bisplinghoff, Ashley & Halfman 1955, Table 5-1;
# Theodorsen, NACA Rep. 496): k, F, G
TABLE = [(0.1, 0.832, -0.172), (0.2, 0.728, -0.189), (0.5, 0.598, -0.151),
         (1.0, 0.539, -0.100)]


@pytest.mark.parametrize("k,F,G", TABLE)
def test_theodorsen_table(k, F, G):
    c = theodorsen(k)
    assert c.real == pytest.approx(F, abs=6e-4)
    assert c.imag == pytest.approx(G, abs=6e-4)


def test_theodorsen_bessel_form_and_limits():
    # independent route: F, G from J and Y Bessel functions
    k = np.array([0.05, 0.3, 0.8, 2.0])
    d = (j1(k) + y0(k)) ** 2 + (y1(k) - j0(k)) ** 2
    F = (j1(k) * (j1(k) + y0(k)) + y1(k) * (y1(k) - j0(k))) / d
    G = -(y1(k) * y0(k) + j1(k) * j0(k)) / d
    assert np.allclose(theodorsen(k), F + 1j * G, atol=1e-12)
    assert theodorsen(0.0) == 1.0
    assert abs(theodorsen(200.0) - 0.5) < 2e-3


def test_jones_close_to_theodorsen():
    k = np.linspace(0.01, 2.0, 200)
    err = np.abs(jones(1j * k) - theodorsen(k))
    assert err.max() < 0.02  # R. T. Jones' fit: within 0.02 everywhere
    assert jones(0.0) == 1.0 and abs(jones(1e6j) - 0.5) < 1e-6


def test_preset_and_dimensional_round_trip():
    s = load_section("hodges-pierce")
    assert (s.a, s.e, s.mu, s.r2, s.sigma) == (-0.2, -0.1, 20.0, 0.24, 0.4)
    d = TypicalSection.from_dimensional(
        semichord=s.semichord, mass=s.mass, inertia=s.inertia,
        static_moment=s.mass * s.semichord * s.x_theta,
        plunge_stiffness=s.mass * s.omega_h**2,
        pitch_stiffness=s.inertia * s.omega_theta**2, a=s.a)
    for f in ("e", "mu", "r2", "sigma", "omega_theta"):
        assert getattr(d, f) == pytest.approx(getattr(s, f), rel=1e-12)


def test_si_statespace_scales_the_nondimensional_one():
    s = load_section("hodges-pierce")
    V = 1.5
    Abar, _ = s.nondimensional_matrices(V, "jones")
    A = s.statespace(s.speed(V), "jones").A
    lam = np.sort_complex(np.linalg.eigvals(A)) / s.omega_theta
    assert np.allclose(lam, np.sort_complex(np.linalg.eigvals(Abar)), atol=1e-10)


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_plunge_port_adds_damping():
    # a plunge damper F = c dh/dt on a section in still air: c/(m span) more decay
    import control

    s = load_section("hodges-pierce")
    c = 5.0
    sys = s.statespace(0.0, "steady")
    damper = control.ss([], [], [], [[c]], inputs=["stroke_rate_plunge"],
                        outputs=["force_plunge"])
    closed = control.interconnect([sys, damper], inplist=["force_pitch"], outlist=["stroke_plunge"])
    tr_open, tr_closed = np.trace(sys.A), np.trace(closed.A)
    Minv = np.linalg.inv(np.array([[s.mass, s.mass * s.semichord * s.x_theta],
                                   [s.mass * s.semichord * s.x_theta, s.inertia]]))
    assert tr_open - tr_closed == pytest.approx(c / s.span * Minv[0, 0], rel=1e-10)


def test_bad_sections():
    s = load_section("hodges-pierce")
    with pytest.raises(ParameterError, match=r"singular section: r\^2 must exceed"):
        s.replace(r2=0.01)
    with pytest.raises(ParameterError, match=r"mu \(mass ratio\) must be > 0"):
        s.replace(mu=0.0)
    with pytest.raises(ParameterError, match="no finite state-space form"):
        s.statespace(10.0, "theodorsen")
    with pytest.raises(ParameterError, match=r"a \(reference point\) must lie in \(-1, 1\)"):
        s.replace(a=-1.0)
    assert math.isinf(s.replace(a=-0.6, e=-0.5).divergence_speed_steady)
