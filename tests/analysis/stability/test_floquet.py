"""Floquet analysis: Mathieu's equation, constant coefficients, and the rotor.

The rotor check compares two independent routes: Floquet exponents of the
rotating-frame periodic model (integrated over one revolution) against the
eigenvalues of the constant-coefficient multiblade model (Hammond 1974; Johnson,
Rotorcraft Aeromechanics, 2013, Ch. 20).
"""

import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import linear_sum_assignment

from liquidamp.analysis.stability.floquet import (
    FloquetOptions,
    floquet_analysis,
    monodromy,
    resolve_frequencies,
)
from liquidamp.analysis.stability.ground_resonance import coleman_eigenvalues, rotor_floquet
from liquidamp.errors import ParameterError
from liquidamp.structure import load_rotor


def mathieu(delta, eps, c=0.0):
    return lambda t: np.array([[0.0, 1.0], [-(delta + eps * np.cos(t)), -c]])


def test_constant_coefficients_give_expm():
    A = np.array([[0.0, 1.0], [-4.0, -0.3]])
    Phi = monodromy(lambda t: A, 1.3, 2)
    assert np.allclose(Phi, expm(A * 1.3), rtol=1e-9, atol=1e-11)
    res = floquet_analysis(lambda t: A, 1.3, 2)
    assert np.allclose(np.sort(res.exponents.real), np.sort(np.linalg.eigvals(A).real),
                       atol=1e-9)


def test_mathieu_first_tongue():
    # first instability tongue of x'' + (delta + eps cos t) x = 0:
    # delta = 1/4 +- eps/2 + O(eps^2) (Nayfeh & Mook, Nonlinear Oscillations, 1979, 5.2)
    eps = 0.1
    inside = floquet_analysis(mathieu(0.25, eps), 2 * np.pi, 2)
    outside = floquet_analysis(mathieu(0.25 + 0.1, eps), 2 * np.pi, 2)
    assert inside.spectral_radius > 1.05
    assert outside.spectral_radius == pytest.approx(1.0, abs=1e-8)  # Hamiltonian: neutral
    # growth rate at the tongue centre: eps/(4 omega) = eps/2 with omega = 1/2
    # (first-order averaging)
    assert inside.max_real_part == pytest.approx(eps / 2, rel=0.02)


def test_resolve_frequencies_shifts_only_imaginary_parts():
    eta = np.array([-0.2 + 0.5j, -0.2 - 0.5j])
    ref = np.array([-0.21 + 10.4j, -0.19 - 10.6j])
    out = resolve_frequencies(eta, ref, 10.0)
    assert np.allclose(out, [-0.2 + 10.5j, -0.2 - 10.5j])
    with pytest.raises(ParameterError):
        resolve_frequencies(eta, ref[:1], 10.0)


@pytest.mark.parametrize("rpm", [150.0, 280.0])
def test_floquet_equals_multiblade_eigenvalues(rpm):
    rotor = load_rotor("hammond1974")
    W = rpm * 2 * math.pi / 60
    lam = coleman_eigenvalues(rotor, W)
    res, eta = rotor_floquet(rotor, W)
    rows, cols = linear_sum_assignment(np.abs(eta[:, None] - lam[None, :]))
    # four digits (far better in practice), frequencies included after branch matching
    assert np.max(np.abs(eta[rows] - lam[cols]) / np.abs(lam[cols])) < 1e-4
    assert res.max_real_part == pytest.approx(lam.real.max(), abs=1e-6)


def test_options_reject_unknown():
    with pytest.raises(ParameterError, match="unknown Floquet option 'rtl'"):
        FloquetOptions.from_mapping({"rtl": 1e-8})
    with pytest.raises(ParameterError, match="rtol must be <= 1e-4"):
        FloquetOptions(rtol=1e-2)


def test_batched_rotor_route_equals_dop853_with_a_failed_damper():
    rotor = load_rotor("hammond1974").with_inoperative_damper(1)
    W = 260.0 * 2 * math.pi / 60
    fast, eta_fast = rotor_floquet(rotor, W)  # default: batched RK4 + Richardson
    ref, eta_ref = rotor_floquet(rotor, W, FloquetOptions(method="DOP853"))
    assert np.allclose(fast.monodromy, ref.monodromy, rtol=0, atol=1e-8)
    assert np.max(np.abs(np.sort_complex(eta_fast) - np.sort_complex(eta_ref))) < 1e-8


def test_batched_monodromy_general_family_and_fixed_steps():
    from liquidamp.analysis.stability.floquet import batched_monodromy

    def coeffs(psi):  # not of second-order form: the full products are used
        c = np.zeros((psi.size, 3, 2, 2))
        c[:, 0, 0, 1] = 1.0
        c[:, 0, 1, 1] = -0.1
        c[:, 1, 0, 0] = 0.05 * np.sin(psi)
        c[:, 2, 1, 0] = -(0.25 + 0.1 * np.cos(psi))
        return c

    W = np.array([0.7, 1.6])
    Phi, N = batched_monodromy(coeffs, W)
    again, _ = batched_monodromy(coeffs, W, steps=N)
    assert np.array_equal(Phi, again)
    for w, P in zip(W, Phi, strict=True):
        def A(t, w=w):
            return (coeffs(np.array([w * t]))[0] * np.array([1.0, w, w * w])[:, None, None]).sum(0)
        assert np.allclose(monodromy(A, 2 * np.pi / w, 2), P, rtol=0, atol=1e-9)
    with pytest.raises(ParameterError, match="speeds must be finite and > 0"):
        batched_monodromy(coeffs, [0.0])
