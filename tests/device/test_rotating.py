"""The rotating frame: centrifugal heads from the geometry, the rest state on the rotor, limits
(zero speed, tangential axis), the linearized stiffness in closed form, cavitation at the inboard
end, and clear refusals."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from liquidamp.analysis.response.linear import linearize
from liquidamp.analysis.response.stiffness import nonlinear_stiffness
from liquidamp.coupled.testrig import simulate
from liquidamp.device import preset
from liquidamp.device.effects import (
    Cavitation,
    RotatingFrame,
    least_pressures,
    make_effect,
    with_effects,
)
from liquidamp.device.models import get_model
from liquidamp.device.rotating import ROTATING_BASES
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
#: The Hammond (1974) rotor at its chosen nominal 250 rpm
#: (liquidamp.analysis.stability.sizing.HAMMOND_NOMINAL_RPM), the damper's mid-point at the
#: lag hinge (offset 0.3048 m, the one radius the rotor data gives), axis radial.
W_HAMMOND = 250.0 * 2.0 * math.pi / 60.0
R_HAMMOND = 0.3048


def _geometric_heads(p, W, rm, theta, y, n=200_001):
    """(dp_c, o1, o2) from 2-D positions in the plane of rotation, by quadrature."""
    L1, L2 = p.V01 / p.A_p, p.V02 / p.A_p
    e = np.array([math.cos(theta), math.sin(theta)])  # axis, chamber 1 -> 2

    def potential(s):  # Omega^2 |r|^2 / 2 per unit mass, relative to the mid-point
        r = np.array([rm, 0.0])[:, None] + e[:, None] * s[None, :]
        return 0.5 * W * W * (np.sum(r * r, axis=0) - rm * rm)

    x, w = np.polynomial.legendre.leggauss(4)  # exact for the quadratic potential

    def mean(a, b):
        return float(np.sum(w * potential(0.5 * (b - a) * x + 0.5 * (a + b)))) / 2.0

    m1, m2 = mean(-L1, -y), mean(-y, L2)
    lo1 = float(potential(np.linspace(-L1, -y, n)).min())
    lo2 = float(potential(np.linspace(-y, L2, n)).min())
    rho = p.rho_l
    return rho * (m2 - m1), rho * (lo1 - m1), rho * (lo2 - m2)


@pytest.mark.parametrize("theta", [0.0, 0.7, math.pi / 2, 2.5, math.pi])
@pytest.mark.parametrize("rm", [0.3048, 0.012])
def test_heads_match_the_geometry_in_the_plane_of_rotation(theta, rm):
    """Asymmetric chambers, off-centre stroke; rm = 12 mm puts the point nearest the shaft
    inside a chamber for the oblique axes (the least pressure is then not at an end)."""
    p = P.replace(V02=1.6 * P.V01)
    W, y = 40.0, 0.003
    rf = RotatingFrame(W, rm, theta)
    dpc, o1, o2 = _geometric_heads(p, W, rm, theta, y)
    scale = p.rho_l * W * W * rm * p.V01 / p.A_p + 1.0
    assert abs(rf.pressure_rise(p, y) - dpc) < 1e-12 * scale
    q1, q2 = rf.inboard_pressures(1e5, 2e5, p, y)
    assert abs(q1 - (1e5 + o1)) < 1e-9 * scale and abs(q2 - (2e5 + o2)) < 1e-9 * scale
    # the closed form of the module notes
    L1, L2 = p.V01 / p.A_p, p.V02 / p.A_p
    closed = p.rho_l * W * W * (rm * math.cos(theta) * (L1 + L2) / 2 + (L2**2 - L1**2) / 6
                                - (L1 + L2) * y / 6)
    assert abs(dpc - closed) < 1e-12 * scale
    # the stroke slopes (the force's and the inboard ends') against central differences
    from liquidamp.device import kernels as K
    prm, ep = K.pack_params(p), np.zeros(K.N_EP)
    rf.pack(ep)
    h = 1e-6
    d = (np.array(K.rotating_heads(y + h, prm, ep)) - np.array(K.rotating_heads(y - h, prm, ep)))
    d /= 2 * h
    assert abs(K.rotating_slope(prm, ep) - d[0]) < 1e-6 * abs(d[0])
    np.testing.assert_allclose(K.rotating_offset_slopes(y, prm, ep), d[1:], rtol=1e-6,
                               atol=1e-6 * scale / p.V01 * p.A_p)
    # vectorized over the stroke
    ys = np.array([-0.004, 0.0, y])
    np.testing.assert_allclose(rf.pressure_rise(p, ys)[2], dpc, rtol=0, atol=1e-12 * scale)


def test_sign_convention_chamber_two_outboard_at_zero_angle():
    rf = RotatingFrame(W_HAMMOND, R_HAMMOND, 0.0)
    m = with_effects(get_model("full"), rf)
    x = m.initial_state(P, 0.0)
    assert x[2] > P.p0 > x[0]  # chamber 2 outboard: higher
    x = with_effects(get_model("full"), rf.replace(axis_angle_rad=math.pi)).initial_state(P, 0.0)
    assert x[0] > P.p0 > x[2]


@pytest.mark.parametrize("base", ROTATING_BASES)
def test_rest_state_is_the_static_equilibrium_reached_from_the_non_rotating_state(base):
    """The rest state solves the equilibrium (closed-form pressure difference, the filling
    mass, zero force); integrating the ODE from the non-rotating rest state with the stroke
    held settles there (Radau, a different route)."""
    p = P.replace(V02=1.3 * P.V01)
    rf = RotatingFrame(W_HAMMOND, R_HAMMOND, 0.4)
    bare = get_model(base)
    m = with_effects(bare, rf)
    y0 = 0.004
    u = (y0, 0.0, 0.0)
    x = m.initial_state(p, y0)
    L1, L2 = p.V01 / p.A_p, p.V02 / p.A_p
    dpc = p.rho_l * W_HAMMOND**2 * (R_HAMMOND * math.cos(0.4) * (L1 + L2) / 2
                                    + (L2**2 - L1**2) / 6 - (L1 + L2) * y0 / 6)
    if base in ("single_state", "inertial_2state"):
        assert abs(x[0] + dpc) < 1e-9 * dpc
    else:
        i2 = m.state_names.index("p2")
        assert abs(x[i2] - x[0] - dpc) < 1e-9 * dpc
        assert x[0] < p.p0 < x[i2]
        if m.conserves_mass:
            M = float(m.mass(x, u, p))
            assert abs(M / (p.rho_l * (p.V01 + p.V02)) - 1) < 1e-12
    assert abs(float(m.force(0.0, x, u, p))) < 1e-9 * p.A_p * dpc
    sc = m.state_scales(p)
    assert np.max(np.abs(m.rhs(0.0, x, u, p)) / sc) < 1e-12
    sol = solve_ivp(lambda t, z: m.rhs(t, z, u, p), (0.0, 4.0), bare.initial_state(p, y0),
                    method="Radau", rtol=1e-11, atol=1e-12 * sc,
                    jac=lambda t, z: m.jacobian(t, z, u, p))
    assert sol.status == 0
    xe = sol.y[:, -1]
    np.testing.assert_allclose(xe, x, rtol=1e-9, atol=1e-9 * float(np.max(sc)))
    if base not in ("single_state", "inertial_2state"):
        i2 = m.state_names.index("p2")
        assert abs((xe[i2] - xe[0]) / dpc - 1) < 1e-6


def test_zero_speed_is_the_bare_model_exactly():
    bare = get_model("full")
    m = with_effects(bare, RotatingFrame(0.0, 0.5, 0.3))
    rng = np.random.default_rng(7)
    np.testing.assert_array_equal(m.initial_state(P, 0.002), bare.initial_state(P, 0.002))
    for _ in range(5):
        x = bare.initial_state(P, 0.0) * (1 + rng.uniform(-0.3, 0.3, 5))
        x[4] = rng.uniform(-0.01, 0.01)
        u = (rng.uniform(-0.01, 0.01), rng.uniform(-0.1, 0.1), 0.0)
        np.testing.assert_array_equal(m.rhs(0.0, x, u, P), bare.rhs(0.0, x, u, P))
        assert m.force(0.0, x, u, P) == bare.force(0.0, x, u, P)


def test_tangential_axis_keeps_the_rest_state_and_only_the_stroke_term_remains():
    """theta = pi/2, equal chambers: the rest state is the non-rotating one (to round-off of
    cos(pi/2)); the linearized K* changes by exactly the stroke term of dp_c,
    K_rot / K_bare = 1 + A_p d(dp_c)/dy / k_D, with d(dp_c)/dy = -rho_l Omega^2 (L1 + L2)/6."""
    W = 200.0  # fast, so that the stroke term stands well above the linearization error
    m = with_effects(get_model("full"), RotatingFrame(W, R_HAMMOND, math.pi / 2))
    bare = get_model("full")
    np.testing.assert_allclose(m.initial_state(P, 0.0), bare.initial_state(P, 0.0),
                               rtol=1e-14, atol=0)
    f = [0.5, 3.0, 40.0]
    ratio = linearize(m, P).frequency_response(f) / linearize(bare, P).frequency_response(f)
    slope = -P.rho_l * W * W * (P.V01 + P.V02) / P.A_p / 6
    expected = 1 + P.A_p * slope / P.k_D
    assert expected < 1 - 1e-3
    np.testing.assert_allclose(ratio, expected, rtol=0, atol=1e-5)


def _closed_form_full(m, p, f, slope):
    """K*(f) of the full model linearized at its rest state (channel with inertance, laminar
    loss; the quadratic loss has zero slope at rest): with Bs = B1/V1 + B2/V2 and
    Bm = B1/(V1 rho1) + B2/(V2 rho2) at the rest pressures and densities,
    K = A_p (A_p Bs + dp_c') s (S_t s + g1) / (s (S_t s + g1) + Bm)."""
    x = m.initial_state(p, 0.0)
    B1, B2 = p.bulk_modulus_at(x[0], 1), p.bulk_modulus_at(x[2], 2)
    Bs = B1 / p.V01 + B2 / p.V02
    Bm = B1 / (p.V01 * x[1]) + B2 / (p.V02 * x[3])
    s = 2j * math.pi * np.asarray(f, float)
    return p.A_p * (p.A_p * Bs + slope) * s * (p.S_t * s + p.g1) / (s * (p.S_t * s + p.g1) + Bm)


def test_stiffness_at_the_hammond_rotor_speed_rises_as_the_convex_bulk_law_predicts():
    """At 250 rpm, mid-point at the lag hinge, radial axis, the symmetric reference device:
    the outboard chamber rises and the inboard falls by about 2.6 kPa each, and the mean
    rises (the sealed liquid mass and the concave rho(p) of the air-liquid mixture); the
    air's bulk modulus is convex in p (B ~ p^(1 + 1/n)), so B1/V1 + B2/V2, the spring of the
    blocked channel, grows: the storage stiffness rises (by 0.13 % at 40 Hz, in the spring
    regime above the channel's resonance).  The linearization matches the closed form and
    the nonlinear first harmonic at a small stroke shows the same change."""
    rf = RotatingFrame(W_HAMMOND, R_HAMMOND, 0.0)
    m = with_effects(get_model("full"), rf)
    bare = get_model("full")
    x = m.initial_state(P, 0.0)
    assert 0.5 * (x[0] + x[2]) > P.p0
    Bs = P.bulk_modulus_at(x[0], 1) / P.V01 + P.bulk_modulus_at(x[2], 2) / P.V02
    assert Bs > P.B_eff
    f = np.array([0.5, 1.19, 3.0, 10.0, 40.0])
    slope = -P.rho_l * W_HAMMOND**2 * (P.V01 + P.V02) / P.A_p / 6
    kr = linearize(m, P).frequency_response(f)
    kb = linearize(bare, P).frequency_response(f)
    np.testing.assert_allclose(kr, _closed_form_full(m, P, f, slope), rtol=1e-5)
    np.testing.assert_allclose(kb, _closed_form_full(bare, P, f, 0.0), rtol=1e-5)
    lin_change = kr[-1].real / kb[-1].real - 1
    assert 1e-3 < lin_change < 2e-3
    nl = nonlinear_stiffness(P, [40.0], [1e-4], model=m).value[0, 0]
    nb = nonlinear_stiffness(P, [40.0], [1e-4], model=bare).value[0, 0]
    assert abs((nl.real / nb.real - 1) / lin_change - 1) < 0.05


def test_cavitation_composed_with_rotation_opens_at_the_inboard_end():
    """A vapour pressure between the lowest lumped pressure and the lowest inboard-end
    pressure of the rotating device: only the inboard-aware composition opens a cavity, and
    it holds the inboard-end pressure at p_v (whose offset from the lumped pressure moves
    with the piston) while conserving mass."""
    p = preset("paper_calibrated")
    rf = RotatingFrame(60.0, 0.5, 0.0)
    s = HarmonicStroke(0.003, 3.0)
    opts = SolverOptions(rtol=1e-9)
    rot = with_effects(get_model("full"), rf)
    r = simulate(rot, p, s, 0.7, options=opts)
    q1, q2 = least_pressures(rot, r.states, (r.stroke, r.stroke_rate, r.stroke_acceleration),
                             p)
    lumped, inboard = r.min_pressure, float(min(q1.min(), q2.min()))
    assert inboard < lumped - 5e3
    pv = 0.5 * (lumped + inboard)
    m = with_effects(get_model("full"), rf, Cavitation(pv))
    assert [e.name for e in m.effects] == ["rotating_frame", "cavitation"]
    rc = simulate(m, p, s, 0.7, options=opts)
    u = (rc.stroke, rc.stroke_rate, rc.stroke_acceleration)
    q1, q2 = least_pressures(m, rc.states, u, p)
    assert float(min(q1.min(), q2.min())) > pv * (1 - 1e-3)  # held at p_v as the piston moves
    assert rc.min_pressure > pv  # the lumped pressure stays above p_v
    assert max(rc.state("Vc1").max(), rc.state("Vc2").max()) > 1e-9  # a cavity opened
    M = np.asarray(m.mass(rc.states, u, p))
    assert np.max(np.abs(M / M[0] - 1)) < 1e-7


def test_inboard_pressure_warning_names_the_rotating_frame():
    p = preset("paper_calibrated")
    m = with_effects(get_model("full"), RotatingFrame(60.0, 0.5, 0.0))
    r = simulate(m, p, HarmonicStroke(0.004, 3.0), 0.5,
                 options=SolverOptions(vapour_pressure=3.0e4))
    assert any("inboard end, rotating frame" in w for w in r.warnings)


@pytest.mark.parametrize("base", ["maxwell", "dashpot", "spring", "inerter", "dashpot_inerter"])
def test_models_without_pressures_or_channel_flow_refuse_it(base):
    with pytest.raises(ParameterError, match="needs a model with chamber pressures or channel "
                                             "flow"):
        with_effects(get_model(base), RotatingFrame(W_HAMMOND, R_HAMMOND))


def test_bad_parameters_and_impossible_rest_states():
    with pytest.raises(ParameterError, match="rotor_speed_rad_per_s must be >= 0"):
        RotatingFrame(-1.0, 0.3)
    with pytest.raises(ParameterError, match="axis_angle_rad must be finite"):
        RotatingFrame(10.0, 0.3, math.nan)
    with pytest.raises(ParameterError, match="mounting_radius_m must be >= 0"):
        make_effect("rotating_frame", rotor_speed_rad_per_s=10.0, mounting_radius_m=-0.1)
    # 2.7 MPa of centrifugal rise in a device without air: the inboard chamber would have to
    # fall below zero pressure (with air it expands instead, however little there is)
    m = with_effects(get_model("full"), RotatingFrame(600.0, 0.3))
    with pytest.raises(ParameterError, match="no rest state with positive chamber pressures"):
        m.initial_state(P.replace(inv_gamma1=0.0, inv_gamma2=0.0), 0.0)
    assert RotatingFrame(600.0, 0.3).fit_keys == ()


def test_devices_on_the_hammond_rotor_start_at_rest_and_both_routes_agree():
    """Four full devices with the rotating frame on the Hammond rotor, nothing disturbed: the
    devices start at their rest state on the rotor and the rotor stays at rest (started from
    the non-rotating state they would push it); with a lag disturbance the compiled rotor
    kernel and simulate_coupled agree."""
    from liquidamp.coupled.assembly import Device, rotor_system, simulate_coupled
    from liquidamp.coupled.fast_rotor import simulate_rotor
    from liquidamp.structure.hostio import load_rotor

    rotor = load_rotor("hammond1974")
    m = with_effects(get_model("full"), RotatingFrame(W_HAMMOND, R_HAMMOND, 0.0))
    dev = Device(m, P.replace(A_p=4 * 6.91e-4))
    opts = SolverOptions(method="DOP853", rtol=1e-8, engine="scipy")
    still = simulate_rotor(rotor, W_HAMMOND, dev, 0.2, {}, options=opts)
    assert still.status == "completed"
    assert np.max(np.abs(still.host_states)) < 1e-12
    import dataclasses
    pushed = Device(dataclasses.replace(m, initial_state=get_model("full").initial_state),
                    dev.params)
    moved = simulate_rotor(rotor, W_HAMMOND, pushed, 0.2, {}, options=opts)
    assert np.max(np.abs(moved.host_states)) > 1e-7
    x0 = {"zeta_1": 2e-3, "hub_x": 2e-4}
    run = simulate_rotor(rotor, W_HAMMOND, dev, 0.2, x0, options=opts)
    ref = simulate_coupled(rotor_system(rotor, W_HAMMOND, dev), 0.2, x0, t_eval=run.time,
                           options=opts, strict=False, energy=False)
    assert run.status == ref.status == "completed"
    scale = np.max(np.abs(ref.host_states), axis=1, keepdims=True)
    assert np.max(np.abs(run.host_states - ref.host_states) / scale) < 1e-8
