"""Flutter of the Hodges & Pierce section with devices in the loop (p method, Jones)."""

import pytest

from liquidamp.analysis.stability.damped_stability import damped_flutter_analysis, device_lti
from liquidamp.analysis.stability.flutter import flutter_analysis
from liquidamp.analysis.stability.sizing import flutter_damper_device
from liquidamp.coupled.assembly import Device, viscous
from liquidamp.structure.hostio import load_section

S = load_section("hodges-pierce")


def test_vanishing_device_gives_bare_section():
    bare = flutter_analysis(S, "jones", "p").flutter_speed
    r = damped_flutter_analysis(S, {"pitch": viscous(1e-12)})
    assert r.flutter_speed == pytest.approx(bare, abs=1e-8)
    assert bare == pytest.approx(2.17036, abs=1e-5)


def test_plunge_damper_raises_flutter_speed_and_device_vs_viscous():
    dv, _ = flutter_damper_device("viscous", S, zeta=0.2)
    dl, sz = flutter_damper_device("reference", S, zeta=0.2)
    v_visc = damped_flutter_analysis(S, {"plunge": dv}).flutter_speed
    v_dev = damped_flutter_analysis(S, {"plunge": dl}).flutter_speed
    assert v_visc > 2.3 and v_dev > 2.3
    # same damping at the sizing frequency: the liquid device's stiffness and
    # inertance shift the result by a few per cent only
    assert v_dev == pytest.approx(v_visc, rel=0.05)
    assert v_dev == pytest.approx(2.4494, abs=2e-3)


def test_flutter_speed_moves_with_device_parameters():
    _, sz = flutter_damper_device("reference", S, zeta=0.2)
    base = sz.params
    speeds = {}
    for key, m in (("c1", 0.25), ("c1", 4.0), ("S_t", 4.0), ("inv_gamma1", 2.0)):
        d = Device("full", base.scaled(**{key: m}))
        speeds[(key, m)] = damped_flutter_analysis(S, {"plunge": d}).flutter_speed
    assert len({round(v, 4) for v in speeds.values()}) == 4  # each parameter matters
    assert all(2.0 < v < 3.0 for v in speeds.values())


def test_equivalent_device_in_flutter_loop():
    _, sz = flutter_damper_device("reference", S, zeta=0.2)
    d = Device("full", sz.params)
    small = device_lti(d)
    big = device_lti(d, amplitude=2e-3, frequency=2.5)
    v0 = damped_flutter_analysis(S, {"plunge": d}, ltis=[small]).flutter_speed
    v1 = damped_flutter_analysis(S, {"plunge": d}, ltis=[big]).flutter_speed
    assert v0 != pytest.approx(v1, rel=1e-4)
