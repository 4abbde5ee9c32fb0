"""Flutter and divergence of the Hodges & Pierce typical section.

Section: a = -1/5, e = -1/10, mu = 20, r^2 = 6/25, sigma = 2/5 (Hodges & Pierce,
Introduction to Structural Dynamics and Aeroelasticity, 2nd ed., 2011, Ch. 5).
Each number is checked by an independent route: closed forms, a direct solution of
the flutter determinant, and agreement between the p-k, k and p methods.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq, fsolve

from liquidamp.analysis.stability.flutter import divergence_speed, flutter_analysis
from liquidamp.errors import ParameterError
from liquidamp.structure import load_section
from liquidamp.structure.aero import aero_matrices, theodorsen

A, MU, R2, SIGMA, XT = -0.2, 20.0, 0.24, 0.4, 0.1


@pytest.fixture(scope="module")
def hp():
    return load_section("hodges-pierce")


@pytest.fixture(scope="module")
def pk_theodorsen(hp):
    return flutter_analysis(hp, "theodorsen", "pk", speeds=np.linspace(0.1, 2.6, 26))


def test_divergence_closed_form(hp):
    # U_D/(b omega_theta) = sqrt(mu r^2/(1 + 2a))  (H&P Sec. 3.x / 5.x)
    assert divergence_speed(hp) == pytest.approx(math.sqrt(MU * R2 / (1 + 2 * A)), rel=1e-12)
    assert divergence_speed(hp) == pytest.approx(2.828427, abs=1e-6)


def test_steady_flutter_closed_form(hp):
    # steady aero: det([[s^2 - l, 2q - l x], [-l x, r^2 (1 - l) - (1 + 2a) q]]) = 0,
    # l = (omega/omega_theta)^2, q = V^2/mu, is a quadratic in l; flutter where its
    # discriminant vanishes (frequency coalescence)
    def quad(V):
        q = V * V / MU
        return (R2 - XT * XT,
                -SIGMA**2 * R2 - (R2 - (1 + 2 * A) * q) + 2 * q * XT,
                SIGMA**2 * (R2 - (1 + 2 * A) * q))

    def disc(V):
        c2, c1, c0 = quad(V)
        return c1 * c1 - 4 * c2 * c0

    VF = brentq(disc, 1.0, 2.0, xtol=1e-14)
    c2, c1, _ = quad(VF)
    wF = math.sqrt(-c1 / (2 * c2))
    assert VF == pytest.approx(1.842517, abs=1e-6)
    for method in ("p", "pk"):
        r = flutter_analysis(hp, "steady", method, speeds=np.linspace(0.1, 2.6, 26))
        assert r.flutter_speed == pytest.approx(VF, abs=1e-7)
        assert r.flutter_frequency == pytest.approx(wF, abs=1e-4)


def test_theodorsen_pk_against_direct_determinant(hp, pk_theodorsen):
    # independent route: solve det(K - W^2 (M + A(k))) = 0 at p = iW directly for (V, W)
    Mnc, Dnc, l, w1, w0 = aero_matrices(A, MU)
    M = np.array([[1.0, XT], [XT, R2]])
    K = np.diag([SIGMA**2, R2])

    def det(x):
        V, W = x
        p = 1j * W
        C = theodorsen(W / V)
        F = (p * p * (M - Mnc) - p * V * Dnc - 2 * V / MU * C * (l @ (p * w1 + V * w0)) + K)
        d = np.linalg.det(F)
        return [d.real, d.imag]

    V, W = fsolve(det, [2.2, 0.65], xtol=1e-13)
    assert pk_theodorsen.flutter_speed == pytest.approx(V, abs=1e-7)
    assert pk_theodorsen.flutter_frequency == pytest.approx(W, abs=1e-7)
    # values: V_F = 2.1839, omega_F/omega_theta = 0.6490.  Hodges & Pierce's p-k plot
    # reads about 2.17 (figure reading, within 1 %).
    assert V == pytest.approx(2.1839, abs=1e-4) and W == pytest.approx(0.6490, abs=1e-4)
    assert V == pytest.approx(2.17, rel=0.01)


def test_k_and_pk_agree_at_flutter(hp, pk_theodorsen):
    k = flutter_analysis(hp, "theodorsen", "k")
    assert k.flutter_speed == pytest.approx(pk_theodorsen.flutter_speed, rel=1e-6)
    assert k.flutter_frequency == pytest.approx(pk_theodorsen.flutter_frequency, rel=1e-6)


def test_jones_state_space_and_exact(hp, pk_theodorsen):
    speeds = np.linspace(0.1, 2.6, 26)
    p = flutter_analysis(hp, "jones", "p", speeds=speeds)
    pk = flutter_analysis(hp, "jones", "pk", speeds=speeds)
    # the p method with Jones' state space is exact for Jones' C: same flutter point
    assert p.flutter_speed == pytest.approx(pk.flutter_speed, rel=1e-8)
    assert p.flutter_frequency == pytest.approx(pk.flutter_frequency, rel=1e-6)
    # and the finite-state aerodynamics land close to Theodorsen's (0.6 %)
    assert p.flutter_speed == pytest.approx(pk_theodorsen.flutter_speed, rel=0.01)
    assert p.flutter_frequency == pytest.approx(pk_theodorsen.flutter_frequency, rel=0.01)


def test_quasi_steady_p_equals_pk(hp):
    speeds = np.linspace(0.1, 1.5, 15)
    a = flutter_analysis(hp, "quasi-steady", "p", speeds=speeds)
    b = flutter_analysis(hp, "quasi-steady", "pk", speeds=speeds)
    assert a.flutter_speed == pytest.approx(b.flutter_speed, rel=1e-9)
    assert a.flutter_speed == pytest.approx(0.93765, abs=1e-4)


def test_vg_data_shape_and_json(hp, pk_theodorsen):
    r = pk_theodorsen
    assert r.speed.shape == r.damping.shape == r.frequency.shape == (2, 26)
    d = r.to_dict()
    assert set(d) >= {"flutter_speed", "flutter_frequency", "divergence_speed", "speed",
                      "damping", "frequency"}
    # below flutter every mode is damped, above one is not
    below = r.speed[0] < r.flutter_speed
    assert np.all(r.damping[:, below] < 0) and np.any(r.damping[:, ~below] > 0)


def test_invalid_combinations(hp):
    with pytest.raises(ParameterError, match="p method needs a state-space"):
        flutter_analysis(hp, "theodorsen", "p")
    with pytest.raises(ParameterError, match="k method needs frequency-dependent"):
        flutter_analysis(hp, "steady", "k")
    with pytest.raises(ParameterError, match="unknown aerodynamic model 'piston'"):
        flutter_analysis(hp, "piston", "pk")
    with pytest.raises(ParameterError, match="strictly increasing"):
        flutter_analysis(hp, "jones", "p", speeds=[1.0, 0.5])
