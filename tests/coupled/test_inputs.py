"""External harmonic inputs on coupled systems: closed forms, both engines, energy, errors."""

import math

import numpy as np
import pytest

from liquidamp.coupled import fast_rotor
from liquidamp.coupled.assembly import (
    Device,
    blade_system,
    compiled_support,
    couple,
    rotor_system,
    section_system,
    simulate_coupled,
    viscous,
)
from liquidamp.coupled.inputs import HarmonicInput, input_values
from liquidamp.device import preset
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.hostio import load_blade, load_rotor, load_section

BLADE = load_blade("hammond1974").replace(lag_damping=0.0)
ROTOR = load_rotor("hammond1974")
W = 2.0 * math.pi * 4.2  # [rad/s]
SCIPY = SolverOptions(method="DOP853", rtol=1e-9, engine="scipy")
COMPILED = SCIPY.replace(engine="compiled")


def test_harmonic_input_values_and_forms():
    u = HarmonicInput("moment", 3.0, cos_amplitude=2.0, sin_amplitude=-1.0, mean=0.5)
    t = np.array([0.0, 0.1, 0.7])
    assert np.allclose(u(t), 0.5 + 2.0 * np.cos(3.0 * t) - np.sin(3.0 * t), rtol=0, atol=1e-15)
    assert u.amplitude == pytest.approx(math.sqrt(5.0), rel=1e-15)
    p = HarmonicInput.polar("moment", 4.0, 3.0, phase=0.3, mean=1.0)
    assert np.allclose(p(t), 1.0 + 4.0 * np.sin(3.0 * t + 0.3), rtol=0, atol=1e-14)
    assert p.scaled(2.0).amplitude == pytest.approx(8.0, rel=1e-15) and p.scaled(2.0).mean == 1.0
    assert input_values([u, p], 0.1).tolist() == [float(u(0.1)), float(p(0.1))]
    with pytest.raises(ParameterError, match=r"input frequency omega must be >= 0 \[rad/s\]"):
        HarmonicInput("moment", -1.0)
    with pytest.raises(ParameterError, match="input cos_amplitude must be finite"):
        HarmonicInput("moment", 1.0, cos_amplitude=math.inf)


def test_blade_moment_input_closed_form_and_blade_matrices():
    """The moment enters as +1/I_b on the lag rate; the harmonic form is the state space."""
    ss = BLADE.statespace(W)
    assert list(ss.input_labels) == ["force", "moment"]
    assert ss.B[1, 1] == pytest.approx(1.0 / BLADE.inertia, rel=1e-15)
    assert ss.B[1, 0] == pytest.approx(-BLADE.damper_arm / BLADE.inertia, rel=1e-15)
    M0, *_, K0, Kc, Ks = BLADE.harmonic_second_order(W)
    assert K0[0, 0] == BLADE.lag_stiffness(W) and not Kc.any() and not Ks.any()
    # steady 1/rev response of the blade with a viscous damper to M sin(W t): closed form
    c, M = 2e4, 800.0  # lag damping ratio 7.7 %: the transient is gone (e^-35) at 60 s
    sys_ = blade_system(BLADE, W, viscous(c), inputs=[HarmonicInput("moment", W, 0.0, M)])
    H = 1.0 / (BLADE.lag_stiffness(W) - BLADE.inertia * W**2 + 1j * W * c * 0.25**2)
    t = np.linspace(60.0, 61.0, 9)
    run = simulate_coupled(sys_, 61.0, t_eval=t, options=COMPILED)
    assert np.allclose(run.host_state("zeta"), (M * H * np.exp(1j * W * t) / 1j).real,
                       rtol=0, atol=1e-7 * M * abs(H))


def test_scipy_and_compiled_routes_agree_with_inputs_and_energy_balances():
    """Blade and rotor with a liquid device under 1/rev moments: the compiled kernel's
    harmonic generalized forces equal B_u u on the Python route (same DOP853 steps)."""
    d = Device("full", preset("damper"))
    M = HarmonicInput("moment", W, cos_amplitude=300.0, sin_amplitude=1000.0)
    ins = [HarmonicInput.polar(f"moment_{k}", 500.0, W, 2 * math.pi * (k - 1) / 4)
           for k in range(1, 5)]
    for sys_, T in ((blade_system(BLADE, W, d, inputs=[M]), 1.0),
                    (rotor_system(ROTOR, W, d, inputs=ins + [HarmonicInput("hub_force_x", W,
                                                                            2e3)]), 0.4)):
        assert compiled_support(sys_) is None
        a = simulate_coupled(sys_, T, options=SCIPY, max_step=2 * math.pi / W / 20)
        b = simulate_coupled(sys_, T, options=COMPILED, max_step=2 * math.pi / W / 20)
        scale = np.max(np.abs(a.host_states))
        assert np.max(np.abs(a.host_states - b.host_states)) < 1e-9 * scale  # rtol 1e-9
        # the inputs do work and the energy balance holds with it
        assert a.energy.input_work is not None and abs(a.energy.input_work[-1]) > 0.1
        assert a.energy.relative_residual < 1e-4
        assert b.energy.relative_residual == pytest.approx(a.energy.relative_residual, rel=1e-4)
    free = blade_system(BLADE, W, d)
    assert simulate_coupled(free, 0.1, {"zeta": 1e-3}).energy.input_work is None


def test_inputs_are_checked_and_with_inputs_keeps_the_compiled_route():
    d = viscous(1e4)
    with pytest.raises(ParameterError, match=r"host 'blade' has no input 'torque'; inputs "
                                             r"without a device: moment"):
        blade_system(BLADE, W, d, inputs=[HarmonicInput("torque", W, 1.0)])
    with pytest.raises(ParameterError, match=r"host input 'force' takes the force of the "
                                             r"device at port 'lag'; drive another input"):
        blade_system(BLADE, W, d, inputs=[HarmonicInput("force", W, 1.0)])
    with pytest.raises(ParameterError, match="one HarmonicInput only"):
        blade_system(BLADE, W, d, inputs=[HarmonicInput("moment", W, 1.0)] * 2)
    with pytest.raises(ParameterError, match="inputs must be HarmonicInput, got tuple"):
        blade_system(BLADE, W, d, inputs=[("moment", 1.0)])
    free = blade_system(BLADE, W, d)
    forced = free.with_inputs([HarmonicInput("moment", W, 1.0)])
    assert compiled_support(forced) is None and forced.origin.inputs == forced.inputs
    assert forced.with_inputs(()).inputs == ()
    # a hand-coupled blade (no origin) runs on scipy only
    hand = couple(BLADE.statespace(W), {"lag": d}, BLADE.ports,
                  inputs=[HarmonicInput("moment", W, 1.0)])
    assert "was not built" not in compiled_support(hand)
    assert "constant coefficients" in compiled_support(hand)
    sec = section_system(load_section("hodges-pierce"), 5.0, {"pitch": viscous(10.0)})
    assert sec.inputs == ()
    with pytest.raises(ParameterError, match="device must be a Device"):
        blade_system(BLADE, W, 1e4)


def test_simulate_blade_matches_simulate_coupled():
    d = Device("full", preset("paper_calibrated"))
    M = [HarmonicInput("moment", W, 0.0, 700.0)]
    t = np.linspace(0.0, 1.0, 41)
    run = fast_rotor.simulate_blade(BLADE, W, d, 1.0, {"zeta": 1e-3}, inputs=M, t_eval=t,
                              options=COMPILED)
    ref = simulate_coupled(blade_system(BLADE, W, d, inputs=M), 1.0, {"zeta": 1e-3}, t_eval=t,
                           options=COMPILED.replace(engine="scipy"),
                           max_step=2 * math.pi / W / 20)
    assert np.max(np.abs(run.states - np.vstack([ref.host_states, *ref.device_states]))
                  / np.max(np.abs(run.states), axis=1, keepdims=True)) < 1e-9  # rtol 1e-9
