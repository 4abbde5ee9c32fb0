"""Ground resonance of the Hammond (1974) rotor and Coleman's undamped instability.

References: R. P. Coleman, A. M. Feingold, NACA Rep. 1351, 1958; C. E. Hammond,
J. American Helicopter Society 19(4), 14-23, 1974 (four-bladed rotor, one damper
inoperative analysed by Floquet theory).
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.stability.ground_resonance import (
    ground_resonance_sweep,
    rad_s_to_rpm,
    rotor_eigenvalues,
    rpm_to_rad_s,
)
from liquidamp.errors import ParameterError
from liquidamp.structure import load_rotor


@pytest.fixture(scope="module")
def hammond():
    return load_rotor("hammond1974")


def test_coleman_undamped_instability_at_regressing_lag_crossing(hammond):
    # without any damping the regressing lag mode Omega (1 - nu) coalesces with each
    # body mode: an instability interval around Omega = omega_body / (1 - nu)
    undamped = hammond.with_lag_dampers([0.0] * 4).replace(hub_damping_x=0.0, hub_damping_y=0.0)
    sweep = ground_resonance_sweep(undamped, rpm_to_rad_s(np.linspace(60, 420, 37)))
    nu = math.sqrt(hammond.blade.hinge_offset * hammond.blade.static_moment
                   / hammond.blade.inertia)
    centres = [rad_s_to_rpm(w / (1 - nu)) for w in hammond.body_frequencies]
    assert len(sweep.unstable_ranges_rpm) == 2
    for (a, b), c in zip(sweep.unstable_ranges_rpm, centres, strict=True):
        assert a < c < b
    # neutral (not unstable) far from the crossings
    assert abs(sweep.max_real_part[0]) < 1e-8 and abs(sweep.max_real_part[-1]) < 1e-8


def test_all_dampers_working_is_stable(hammond):
    sweep = ground_resonance_sweep(hammond, rpm_to_rad_s(np.linspace(60, 420, 19)))
    assert sweep.method == "coleman" and sweep.unstable_ranges == ()
    assert sweep.max_real_part.max() < -0.3


def test_one_damper_inoperative_floquet(hammond):
    failed = hammond.with_inoperative_damper(1)
    sweep = ground_resonance_sweep(failed, rpm_to_rad_s(np.linspace(150, 350, 11)))
    assert sweep.method == "floquet" and sweep.requested_method == "coleman"
    assert "Floquet" in sweep.note
    (a, b), = sweep.unstable_ranges_rpm
    # this model: unstable between 210.4 and 307.1 rpm (regression values)
    assert a == pytest.approx(210.37, abs=0.1) and b == pytest.approx(307.08, abs=0.1)
    # the ends are zero crossings of the largest real part (root-found, not interpolated)
    for end in (a, b):
        lam = rotor_eigenvalues(failed, rpm_to_rad_s(end), "floquet")
        assert abs(lam.real.max() - 1e-6) < 1e-6


def test_smeared_damper_loss_is_less_pessimistic(hammond):
    # spreading the failed damper over all blades ((N-1)/N of nominal each) keeps
    # constant coefficients but misses the instability Floquet theory finds
    W = rpm_to_rad_s(260.0)
    smeared = hammond.with_lag_dampers([0.75 * 4067.5] * 4)
    lam_smeared = rotor_eigenvalues(smeared, W, "coleman")
    lam_failed = rotor_eigenvalues(hammond.with_inoperative_damper(2), W, "floquet")
    assert lam_smeared.real.max() < 0.0 < lam_failed.real.max()


def test_floquet_route_on_alike_blades_matches_coleman(hammond):
    W = rpm_to_rad_s(np.array([180.0, 300.0]))
    a = ground_resonance_sweep(hammond, W, "coleman")
    b = ground_resonance_sweep(hammond, W, "floquet")
    assert np.allclose(a.max_real_part, b.max_real_part, atol=1e-7)


def test_bad_sweep_input(hammond):
    with pytest.raises(ParameterError, match="rotor-speed range is empty"):
        ground_resonance_sweep(hammond, [])
    with pytest.raises(ParameterError, match="strictly increasing"):
        ground_resonance_sweep(hammond, [20.0, 10.0])
    with pytest.raises(ParameterError, match="unknown stability method 'eig'"):
        ground_resonance_sweep(hammond, [20.0], "eig")
    with pytest.raises(ParameterError, match=r"Floquet analysis needs rotor speeds > 0"):
        ground_resonance_sweep(hammond, [0.0, 10.0], "floquet")


def test_averaged_multiblade_interpolation_is_exact(hammond):
    from liquidamp.analysis.stability.ground_resonance import _averaged_multiblade

    failed = hammond.with_inoperative_damper(3)
    W = rpm_to_rad_s(np.linspace(150, 350, 9))
    direct = np.array([failed.averaged_multiblade_matrix(w) for w in W])
    assert np.allclose(_averaged_multiblade(failed, W), direct, rtol=1e-10,
                       atol=1e-10 * np.abs(direct).max())


def test_batched_sweep_equals_scipy_route_on_a_coarse_grid(hammond):
    from liquidamp.analysis.stability.floquet import FloquetOptions

    failed = hammond.with_inoperative_damper(1)
    W = rpm_to_rad_s(np.linspace(200, 320, 4))
    a = ground_resonance_sweep(failed, W, "floquet")
    b = ground_resonance_sweep(failed, W, "floquet", FloquetOptions(method="DOP853"))
    assert np.allclose(a.max_real_part, b.max_real_part, atol=1e-9)
    for (a0, a1), (b0, b1) in zip(a.unstable_ranges_rpm, b.unstable_ranges_rpm, strict=True):
        assert a0 == pytest.approx(b0, abs=1e-4) and a1 == pytest.approx(b1, abs=1e-4)
