"""Lag damping under 1/rev motion (issue #13 part 4): Floquet about the forced orbit against
a free decay (matrix pencil and moving block), the rest limit, the linear damper, the K_lag
prediction hook and the errors.

Sizing (documented in the report): the Hammond (1974) blade (hub fixed, own damper removed,
arm 0.25 m) at Omega = 2 pi 4.2 rad/s (nu = 0.285/rev, lag frequency 1.20 Hz) with two
parallel copies of a liquid preset (``scale_device(preset, 2)``) in the full model: lag
damping ratio of a few percent under a 1/rev damper stroke of 0.5-1 mm.
"""

import json
import math

import numpy as np
import pytest

from liquidamp.analysis.stability.damped_stability import closed_loop_matrix, device_lti
from liquidamp.analysis.stability.forced_lag import (
    forced_lag_damping,
    lag_damping_from_stiffness,
    lag_decay_check,
)
from liquidamp.analysis.stability.sizing import scale_device
from liquidamp.coupled.assembly import Device, blade_system, viscous
from liquidamp.device import preset
from liquidamp.device.effects import CoulombFriction, SmoothFriction, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import ConvergenceError, ParameterError
from liquidamp.structure.hostio import load_blade

BLADE = load_blade("hammond1974").replace(lag_damping=0.0)
W = 2.0 * math.pi * 4.2  # [rad/s]
ARM = BLADE.damper_arm


def _viscous_exact(c, blade=BLADE):
    """Roots of I s^2 + (C + c a^2) s + K = 0: (damping ratio, damped frequency)."""
    I, C, K = blade.inertia, blade.lag_damping + c * blade.damper_arm**2, blade.lag_stiffness(W)
    wn = math.sqrt(K / I)
    z = C / (2.0 * math.sqrt(I * K))
    return z, wn * math.sqrt(1.0 - z * z)


@pytest.mark.parametrize("name,stroke", [("paper_calibrated", 1e-3), ("damper", 0.5e-3)])
def test_floquet_lag_damping_agrees_with_the_time_domain_decay(name, stroke):
    """The lag damping on top of the 1/rev orbit from Floquet, from the matrix pencil and from
    the moving-block analysis of a kicked nonlinear run, within 5 % (measured: pencil ~1e-6,
    moving block ~5e-4 relative)."""
    dev = Device("full", scale_device(preset(name), 2.0))
    r = forced_lag_damping(BLADE, W, dev, stroke=stroke)
    assert r.stroke_amplitude == pytest.approx(stroke, rel=1e-5)
    assert r.lag_amplitude == pytest.approx(stroke / ARM, rel=1e-3)
    assert 0.03 < r.damping_ratio < 0.06  # a few percent (the sizing of the module notes)
    assert r.frequency == pytest.approx(BLADE.lag_frequency(W), rel=0.02)
    assert r.orbit.residual < 1e-9
    # three multipliers at exactly 1 (the sealed device's invariants), the lag pair inside
    assert np.sum(np.abs(r.multipliers - 1.0) < 1e-7) == 3
    assert abs(r.lag_multiplier) == pytest.approx(math.exp(r.exponent.real * r.orbit.period),
                                                  rel=1e-12)
    chk = lag_decay_check(r)
    assert abs(chk.pencil_error) < 0.05 and abs(chk.moving_block_error) < 0.05
    # the frequencies too, and the decay really is there (several e-folds recorded)
    assert chk.pencil.frequency == pytest.approx(r.frequency, rel=1e-3)
    assert chk.moving_block.frequency == pytest.approx(r.frequency, rel=1e-2)
    assert chk.signal[0] != 0.0
    assert -r.exponent.real * chk.time[-1] > 2.5
    # the 1/rev motion adds damping to a quadratic loss: more than at rest
    rest = forced_lag_damping(BLADE, W, dev, moment=0.0)
    assert r.damping_ratio > 1.2 * rest.damping_ratio


def test_zero_forcing_reduces_to_the_linearization_at_rest():
    """Without 1/rev forcing the orbit is the rest state and the lag exponent is the
    eigenvalue of the closed loop with the device linearized at rest (device_lti)."""
    dev = Device("full", scale_device(preset("damper"), 5.0))
    r = forced_lag_damping(BLADE, W, dev, moment=0.0)
    assert r.stroke_amplitude == 0.0 and r.orbit.iterations == 0
    lam = np.linalg.eigvals(closed_loop_matrix(blade_system(BLADE, W, dev), [device_lti(dev)]))
    ref = lam[np.argmin(np.abs(lam - r.exponent))]
    assert abs(r.exponent - ref) < 1e-8 * abs(ref)
    assert r.damping_ratio == pytest.approx(-ref.real / abs(ref), rel=1e-7)
    # the other multipliers are those of the linearization too: exp(lambda T)
    T = r.orbit.period
    for z in np.exp(lam * T):
        assert np.min(np.abs(r.multipliers - z)) < 1e-9


def test_viscous_damper_damping_does_not_depend_on_the_1rev_amplitude():
    """A linear damper: the variational equations do not see the orbit (exact), and the
    damping is the closed form c a^2 / (2 sqrt(I K))."""
    c = 6e3
    z, wd = _viscous_exact(c)
    res = [forced_lag_damping(BLADE, W, viscous(c), moment=M) for M in (0.0, 2e3, 2e4)]
    for r in res:
        assert r.damping_ratio == pytest.approx(z, rel=1e-9)
        assert r.frequency == pytest.approx(wd, rel=1e-9)
    assert res[2].lag_amplitude == pytest.approx(10.0 * res[1].lag_amplitude, rel=1e-9)
    d = json.loads(json.dumps(res[1].as_dict()))
    assert d["moment_amplitude [N m]"] == 2e3 and d["damping_ratio [-]"] == res[1].damping_ratio
    assert len(d["multipliers [-]"]) == 2 and d["host"] == "blade"
    assert res[2].lag_amplitude > 0.02
    # amplitude-independent to the integration error (monodromy at rtol 1e-10)
    assert res[2].damping_ratio == pytest.approx(res[0].damping_ratio, rel=1e-9)


def test_solving_for_the_moment_of_a_target_lag_angle_and_the_scipy_route():
    """The moment for a target lag angle; the reference route (scipy on coupled_jacobian)
    gives the same multipliers as the compiled variational kernel."""
    from liquidamp.analysis.stability.forced_orbit import forced_orbit
    from liquidamp.options import SolverOptions

    dev = Device("full", scale_device(preset("paper_calibrated"), 2.0))
    r = forced_lag_damping(BLADE, W, dev, lag_angle=0.004)
    assert r.lag_amplitude == pytest.approx(0.004, rel=2e-6)
    assert "solved for the lag_angle amplitude" in r.notes
    ref = forced_orbit(r.orbit.system, x0=r.orbit.x0,
                       options=SolverOptions(method="DOP853", rtol=1e-10, engine="scipy"))
    assert ref.iterations == 0
    S = r.orbit.scales
    diff = (ref.monodromy - r.orbit.monodromy) * (S[None, :] / S[:, None])
    assert np.max(np.abs(diff)) < 1e-7
    z = np.log(complex(r.lag_multiplier)) / r.orbit.period
    assert np.min(np.abs(np.log(ref.floquet.multipliers.astype(complex)) / ref.period - z)) \
        < 1e-7 * abs(z)


def test_smooth_friction_effect_runs_and_coulomb_friction_is_refused():
    p = scale_device(preset("paper_calibrated"), 2.0)
    smooth = Device(with_effects(get_model("full"), SmoothFriction(20.0, 2e5)), p)
    r = forced_lag_damping(BLADE, W, smooth, stroke=1e-3)
    assert 0.0 < r.damping_ratio < 1.0
    coulomb = Device(with_effects(get_model("full"), CoulombFriction(20.0)), p)
    with pytest.raises(ParameterError, match=r"effect 'coulomb_friction' is not smooth .*"
                                             r"saltation matrix"):
        forced_lag_damping(BLADE, W, coulomb, stroke=1e-3)
    with pytest.raises(ParameterError, match=r"friction_N = 20 N jumps at every stroke "):
        forced_lag_damping(BLADE, W, Device("full", p.replace(friction_N=20.0)), stroke=1e-3)


def test_clear_errors():
    dev = Device("full", scale_device(preset("damper"), 2.0))
    with pytest.raises(ParameterError, match="give exactly one of moment .* got moment, stroke"):
        forced_lag_damping(BLADE, W, dev, moment=1.0, stroke=1e-3)
    with pytest.raises(ParameterError, match="got none"):
        forced_lag_damping(BLADE, W, dev)
    with pytest.raises(ParameterError, match=r"target 1/rev stroke amplitude must be > 0 \[m\]"):
        forced_lag_damping(BLADE, W, dev, stroke=-1e-3)
    # the orbit does not converge: the message names the amplitude and the residual
    with pytest.raises(ConvergenceError, match=r"did not converge in 1 Newton iterations "
                                               r"\(input amplitudes: moment 5000\): "
                                               r"periodicity residual .* of the state scales"):
        forced_lag_damping(BLADE, W, dev, moment=5000.0, max_iter=1)
    # an overdamped lag mode has no frequency: not identified, and why
    with pytest.raises(ConvergenceError, match=r"lag mode not identified: the "
                                               r"orbit-averaged Jacobian has no oscillating "
                                               r"eigenvalue \(every mode is overdamped\)"):
        forced_lag_damping(BLADE, W, viscous(5e5), moment=100.0)


def test_lag_damping_from_stiffness_viscous_and_spring():
    """The K_lag hook: a viscous damper (K = i c omega) and a spring-damper element give the
    closed-form roots; with a viscous device it equals the Floquet result."""
    c = 6e3
    z, wd = _viscous_exact(c)
    zeta, w = lag_damping_from_stiffness(BLADE, W, 1j * c * 7.0, frequency=7.0)
    assert (zeta, w) == (pytest.approx(z, rel=1e-12), pytest.approx(wd, rel=1e-12))
    zeta2, w2 = lag_damping_from_stiffness(BLADE, W, lambda om: 1j * c * om)
    assert zeta2 == pytest.approx(z, rel=1e-12) and w2 == pytest.approx(wd, rel=1e-12)
    fl = forced_lag_damping(BLADE, W, viscous(c), moment=1e3)
    assert zeta == pytest.approx(fl.damping_ratio, rel=1e-9)
    # k' stiffens, k''/omega damps: I s^2 + (c a^2) s + K + a^2 k' = 0
    k, om = 2e4, 7.5
    zeta3, w3 = lag_damping_from_stiffness(BLADE, W, k + 1j * c * om, frequency=om)
    Kt = BLADE.lag_stiffness(W) + ARM**2 * k
    s = np.roots([BLADE.inertia, c * ARM**2, Kt])
    s = s[s.imag > 0][0]
    assert zeta3 == pytest.approx(-s.real / abs(s), rel=1e-12)
    assert w3 == pytest.approx(s.imag, rel=1e-12)
    with pytest.raises(ParameterError, match="K_lag must be finite"):
        lag_damping_from_stiffness(BLADE, W, complex(math.nan, 1.0))


def test_rotor_host_floquet_against_decay_and_coleman_at_rest():
    """Hammond rotor at 330 rpm, four copies of paper_calibrated on every blade, the same
    1/rev lag moment on each blade at its azimuth.  At rest the lag (reactionless) exponent
    is the multiblade eigenvalue with the device linearized at rest; with a 1 mm 1/rev
    stroke the rotor, ground-resonance unstable at rest, is stable, and the lag damping from
    Floquet agrees with the decay of a kicked run."""
    from liquidamp.analysis.stability.damped_stability import rotor_device_eigenvalues
    from liquidamp.structure.hostio import load_rotor

    rotor = load_rotor("hammond1974")
    Wr = 330.0 * math.pi / 30.0
    dev = Device("full", scale_device(preset("paper_calibrated"), 4.0))
    rest = forced_lag_damping(rotor, Wr, dev, moment=0.0)
    lam = rotor_device_eigenvalues(rotor, Wr, dev)
    assert np.min(np.abs(lam - rest.exponent)) < 1e-7 * abs(rest.exponent)
    assert np.max(lam.real) > 0.3  # ground resonance at rest
    r = forced_lag_damping(rotor, Wr, dev, stroke=1e-3)
    assert r.host == "rotor" and r.stroke_amplitude == pytest.approx(1e-3, rel=1e-5)
    expo = np.log(r.multipliers.astype(complex)) / r.orbit.period
    assert np.max(expo.real) < 1e-6  # only the devices' invariant multipliers at 1
    assert 0.05 < r.damping_ratio < 0.12 and r.damping_ratio > 2.0 * rest.damping_ratio
    chk = lag_decay_check(r)
    assert chk.state in ("zeta_1", "zeta_2", "zeta_3", "zeta_4")
    assert abs(chk.pencil_error) < 0.05 and abs(chk.moving_block_error) < 0.05
