"""Coupling of hosts and devices: viscous reproduction of the host results (#4),
interconnect vs block closed loop, acceleration loop, energy balance, errors."""

import math

import numpy as np
import pytest

from liquidamp.analysis.stability.damped_stability import (
    closed_loop_interconnect,
    closed_loop_matrix,
    device_lti,
    rotor_device_eigenvalues,
    section_device_eigenvalues,
)
from liquidamp.analysis.stability.ground_resonance import coleman_eigenvalues, rotor_floquet
from liquidamp.coupled.assembly import (
    Device,
    couple,
    rotor_system,
    section_system,
    simulate_coupled,
    viscous,
)
from liquidamp.device import preset
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.hostio import load_rotor, load_section

ROTOR = load_rotor("hammond1974")
C_LIN = 4067.5 / 0.25**2  # blade damper through the 0.25 m arm [N s/m]


def _match(a, b):
    """Largest distance between two eigenvalue sets paired one-to-one (Hungarian)."""
    from scipy.optimize import linear_sum_assignment

    a, b = np.asarray(a), np.asarray(b)
    cost = np.abs(a[:, None] - b[None, :])
    r, c = linear_sum_assignment(cost)
    return float(cost[r, c].max())


@pytest.mark.parametrize("rpm", [120.0, 250.0, 400.0])
def test_viscous_devices_reproduce_coleman(rpm):
    W = rpm * math.pi / 30
    lam = rotor_device_eigenvalues(ROTOR, W, viscous(C_LIN))
    assert _match(lam, coleman_eigenvalues(ROTOR, W)) < 1e-8


def test_viscous_devices_reproduce_floquet_with_failed_damper():
    W = 250 * math.pi / 30
    lam = rotor_device_eigenvalues(ROTOR, W, viscous(C_LIN), inoperative=[1])
    _, ref = rotor_floquet(ROTOR.with_inoperative_damper(1), W)
    assert _match(lam, ref) < 1e-8
    assert lam.real.max() > 0.2  # Hammond: failed damper unstable here


def test_interconnect_equals_block_closed_loop_full_and_inerter():
    W = 25.0
    for model in ("full", "dashpot_inerter"):
        sys_ = rotor_system(ROTOR, W, Device(model, preset("reference").replace(
            A_p=4 * preset("reference").A_p)))
        ltis = [device_lti(d) for d in sys_.devices]
        a = np.linalg.eigvals(closed_loop_matrix(sys_, ltis, 0.037))
        b = np.linalg.eigvals(closed_loop_interconnect(sys_, ltis, 0.037).A)
        assert _match(a, b) < 1e-9 * np.max(np.abs(a))


def test_inerter_adds_to_blade_inertia():
    """An inerter b on every blade = lag inertia + b arm^2 (Coleman of the modified rotor)."""
    p = preset("reference")
    dev = Device("inerter", p)
    W = 25.0
    lam = rotor_device_eigenvalues(ROTOR, W, dev)
    b = ROTOR.blade
    heavier = ROTOR.replace(blade=b.replace(inertia=b.inertia + p.b_L * b.damper_arm**2))
    heavier = heavier.with_lag_dampers([0.0] * 4)  # the devices replace the dampers
    assert _match(lam, coleman_eigenvalues(heavier, W)) < 1e-8


def test_time_domain_viscous_matches_host_linear_response():
    """Viscous devices in the nonlinear path = the host's own linear system."""
    W = 25.0
    sys_ = rotor_system(ROTOR, W, viscous(C_LIN), inoperative=[1])
    x0 = {"zeta_2": 0.01, "hub_x": 0.002}
    res = simulate_coupled(sys_, 1.0, x0, options=SolverOptions(method="DOP853", rtol=1e-10))
    host = ROTOR.with_inoperative_damper(1).periodic_statespace(W)
    from scipy.integrate import solve_ivp

    xh0 = sys_.initial_state(x0)
    ref = solve_ivp(lambda t, x: host.A(t) @ x, (0, 1.0), xh0, t_eval=res.time,
                    method="DOP853", rtol=1e-11, atol=1e-14)
    assert np.max(np.abs(res.host_states - ref.y)) < 1e-8 * np.max(np.abs(ref.y))


def test_energy_balance_closes_with_full_devices_and_failed_damper():
    from liquidamp.analysis.stability.sizing import size_lag_damper

    dev = Device("full", size_lag_damper(preset("reference"), ROTOR).params)
    sys_ = rotor_system(ROTOR, 26.0, dev, inoperative=[1])
    res = simulate_coupled(sys_, 1.5, {"zeta_1": 0.004, "hub_x": 0.001},
                           options=SolverOptions(method="DOP853", rtol=1e-8))
    e = res.energy
    assert res.status == "completed"
    assert np.max(np.abs(e.device_work[:, -1])) > 0.01  # the devices do absorb work [J]
    assert e.relative_residual < 1e-5
    # the device work equals F v integrated: the three devices absorb energy
    assert np.all(e.device_work[:, -1] > 0.0)


def test_energy_balance_with_inerter_algebraic_loop():
    dev = Device("dashpot_inerter", preset("reference").replace(A_p=4 * 6.91e-4))
    sys_ = rotor_system(ROTOR, 26.0, dev)
    res = simulate_coupled(sys_, 1.0, {"zeta_2": 0.01},  # an inerter: the scipy engine
                           options=SolverOptions(method="DOP853", rtol=1e-9, engine="scipy"))
    assert res.energy.relative_residual < 1e-6
    # the force contains b_L * acceleration: check one sample
    p = dev.params
    i = 37
    F = p.c_L * res.stroke_rates[1, i] + p.b_L * res.stroke_accelerations[1, i]
    assert res.forces[1, i] == pytest.approx(F, rel=1e-10)


def test_section_viscous_plunge_equals_added_damping():
    """A viscous device on the plunge: closed loop = h-equation damping c/(m span)."""
    s = load_section("hodges-pierce")
    U = s.speed(1.0)
    c = 40.0
    lam = section_device_eigenvalues(s, U, {"plunge": viscous(c)})
    sys0 = s.statespace(U, "jones")
    A = np.array(sys0.A)
    B = np.array(sys0.B)
    Cm = np.array(sys0.C)
    ref = np.linalg.eigvals(A + B[:, [0]] @ (c * Cm[[1], :]))  # B carries the -1/(m span)
    assert _match(lam, ref) < 1e-9


def test_errors_name_the_problem():
    s = load_section("hodges-pierce")
    with pytest.raises(ParameterError, match="unknown port 'flap'"):
        section_system(s, 10.0, {"flap": viscous(1.0)})
    with pytest.raises(ParameterError, match="give at least one"):
        couple(s.statespace(10.0), {}, s.ports)
    with pytest.raises(ParameterError, match="viscous damping c"):
        viscous(-1.0)
    sys_ = rotor_system(ROTOR, 25.0, Device("full", preset("reference")))
    with pytest.raises(ParameterError, match="beyond the chamber end"):
        sys_.initial_state({"zeta_1": 0.2})


def test_stroke_limit_stops_with_status():
    dev = Device("full", preset("reference"))
    sys_ = rotor_system(ROTOR, 25.0, dev)
    res = simulate_coupled(sys_, 0.5, {"zeta_dot_1": 2.0}, strict=False,
                           options=SolverOptions(method="DOP853", rtol=1e-6))
    assert res.status in ("stroke_limit", "pressure_floor")
    assert res.time[-1] < 0.5
