"""Fluid laws: eq. (2) limits, eq. (3) integration, eq. (5) and its analytic inverse."""

import numpy as np
import pytest

from liquidamp.device import fluid


def test_bulk_modulus_limits():
    B_l, p0, n = 1.5513e9, 101325.0, 1.35
    assert fluid.bulk_modulus_gholizadeh(5e5, B_l, 0.0, p0, n) == pytest.approx(B_l)
    # p -> 0: B -> n p (gas dominates)
    p = 0.01
    assert fluid.bulk_modulus_gholizadeh(p, B_l, 0.05, p0, n) == pytest.approx(n * p, rel=1e-3)
    # p -> inf: B -> B_l
    assert fluid.bulk_modulus_gholizadeh(1e12, B_l, 0.05, p0, n) == pytest.approx(B_l, rel=1e-3)


def test_bulk_modulus_increases_with_pressure():
    ps = np.geomspace(1e3, 1e8, 50)
    B = [fluid.bulk_modulus_gholizadeh(p, 1.5513e9, 0.07, 101325.0, 1.35) for p in ps]
    assert np.all(np.diff(B) > 0)


def test_density_law_is_consistent_with_bulk_modulus():
    # eq. (3): d rho / rho = dp / B  ->  B = rho dp / drho
    args = (998.2, 1.5513e9, 0.07, 101325.0, 1.35)
    p, h = 2.0e5, 10.0
    r_plus = fluid.density_gholizadeh(p + h, *args)
    r_minus = fluid.density_gholizadeh(p - h, *args)
    r = fluid.density_gholizadeh(p, *args)
    B = r * 2 * h / (r_plus - r_minus)
    assert B == pytest.approx(fluid.bulk_modulus_gholizadeh(p, *args[1:]), rel=1e-6)


def test_density_constant_bulk_closed_form():
    assert fluid.density_constant_bulk(101325.0, 998.2, 2e9, 101325.0) == pytest.approx(998.2)
    # for X0 = 0 the Gholizadeh law is constant-B: both routes agree
    p = np.array([5e4, 3e5])
    a = fluid.density_gholizadeh(p, 998.2, 1.5513e9, 0.0, 101325.0, 1.35)
    b = fluid.density_constant_bulk(p, 998.2, 1.5513e9, 101325.0)
    np.testing.assert_allclose(a, b, rtol=1e-12)


@pytest.mark.parametrize(("k1", "k2"), [(1e9, 1e14), (0.0, 1e14), (1e9, 0.0), (3.0, 0.5)])
def test_loss_inverse_is_exact(k1, k2):
    flows = np.linspace(-2e-4, 2e-4, 41) if k2 > 1 else np.linspace(-5, 5, 41)
    dp = fluid.loss_pressure(flows, k1, k2)
    np.testing.assert_allclose(fluid.loss_flow(dp, k1, k2), flows, rtol=1e-12, atol=1e-18)


def test_loss_flow_derivative():
    k1, k2, dp, h = 1e9, 1e14, 3e4, 1.0
    fd = (fluid.loss_flow(dp + h, k1, k2) - fluid.loss_flow(dp - h, k1, k2)) / (2 * h)
    assert fluid.loss_flow_dp(dp, k1, k2) == pytest.approx(fd, rel=1e-7)
