"""The analytic Jacobian and time derivative of a fluid behind series compliance or freeplay
(``kernels_stroke_map``: the stiff RODAS4 route's d rhs / dx and d rhs / dt) against
Richardson-extrapolated central differences of the right-hand side, in both stroke
directions, with the effects that may sit beside them."""

import numpy as np
import pytest

from liquidamp.device import kernels_model as KM
from liquidamp.device import kernels_stroke_map as SM
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.models import get_model

P = preset("paper_calibrated")
GAP = 1e-4
DELTA = 0.05 * GAP + 1e-7  # the dead band's smoothing width (play_contact)

CASES = {
    "compliance": ("full", [("series_compliance", {"stiffness_N_per_m": 5e5})]),
    "compliance_no_inertia_leak": ("no_inertia", [
        ("series_compliance", {"stiffness_N_per_m": 2e5}),
        ("leakage", {"coefficient_m3_per_s_Pa": 2e-11})]),
    "compliance_friction_elastomer": ("full", [
        ("series_compliance", {"stiffness_N_per_m": 5e5}),
        ("smooth_friction", {"force_N": 30.0, "stiffness_N_per_m": 2e5}),
        ("elastomer", {"parallel_stiffness_N_per_m": 5e4, "branch_stiffness_N_per_m": 1e5,
                       "branch_damping_N_s_per_m": 5.3e3})]),
    "freeplay": ("full", [("freeplay", {"gap_m": GAP})]),
    "freeplay_leak_friction": ("full", [
        ("freeplay", {"gap_m": GAP}), ("leakage", {"coefficient_m3_per_s_Pa": 2e-11}),
        ("smooth_friction", {"force_N": 30.0, "stiffness_N_per_m": 2e5})]),
    # the backlash composite: the bristles behind the dead band (piston_contact)
    "freeplay_bristles_at_piston": ("full", [
        ("freeplay", {"gap_m": GAP}),
        ("smooth_friction", {"force_N": 30.0, "stiffness_N_per_m": 2e5,
                             "location": "piston"})]),
    "freeplay_drives_friction": ("full", [
        ("freeplay", {"gap_m": GAP, "drives": "friction"}),
        ("smooth_friction", {"force_N": 30.0, "stiffness_N_per_m": 2e5,
                             "location": "piston"})]),
}


def _model(case):
    base, effs = CASES[case]
    return with_effects(get_model(base), *[make_effect(n, **kw) for n, kw in effs])


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("sgn", [1.0, -1.0])
def test_stroke_map_jacobian_matches_central_differences(case, sgn):
    m = _model(case)
    names = list(m.state_names)
    sc = m.state_scales(P)
    x = m.initial_state(P, 0.0).astype(float)
    i1, i2 = names.index("p1"), names.index("p2")
    x[i1], x[i2] = P.p0 + sgn * 3e5, P.p0 - sgn * 2e5
    if "m12" in names:
        x[names.index("m12")] = sgn * 0.3 * sc[names.index("m12")]
    y = sgn * 1.2e-3
    u = (y, sgn * 0.04, 0.0)
    for j, name in enumerate(names):
        if name not in ("p1", "p2", "m12", "r1", "r2"):
            x[j] = 0.2 * sgn * sc[j]
    spec, prm, ep = m.packed(P)
    if spec[KM.S_IC] >= 0:
        x[spec[KM.S_IC]] = y - sgn * 4e-4  # the spring loaded
    if spec[KM.S_IFP] >= 0:
        x[spec[KM.S_IFP]] = y - sgn * (GAP - 0.5 * DELTA)  # inside the contact's smoothing
        if spec[KM.S_ZPIST] != 0:  # the bristle contact: |e + lam z| inside its smoothing
            lam = 30.0 / 2e5
            dc = min(DELTA, 0.01 * lam)
            x[spec[KM.S_IZ]] = (sgn * (GAP - 0.5 * dc) - (y - x[spec[KM.S_IFP]])) / lam
    # the analytic branch is the one taken (not the differences of model_jac)
    Ja = np.zeros((m.n_states, m.n_states))
    assert SM.stroke_map_jac(spec, x, u[0], u[1], prm, ep, Ja)
    J = Ja

    def central(j, h):
        xp, xm = x.copy(), x.copy()
        xp[j] += h
        xm[j] -= h
        return (m.rhs(0.0, xp, u, P) - m.rhs(0.0, xm, u, P)) / (2 * h)

    for j in range(m.n_states):
        h = 1e-4 * sc[j]  # (1e-6: round-off in the density columns)
        fd = (4.0 * central(j, 0.5 * h) - central(j, h)) / 3.0  # Richardson: O(h^4)
        np.testing.assert_allclose(J[:, j], fd, rtol=1e-4,
                                   atol=1e-6 * np.max(np.abs(fd)) + 1e-300,
                                   err_msg=f"{case}: column {names[j]}")
    if spec[KM.S_IFP] >= 0:  # the contact's slope is in the dead band's own entry
        assert J[spec[KM.S_IFP], spec[KM.S_IFP]] != 0.0
        if spec[KM.S_ZPIST] != 0:  # and the bristles' coupling to it
            assert J[spec[KM.S_IFP], spec[KM.S_IZ]] != 0.0


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("sgn", [1.0, -1.0])
def test_stroke_map_time_derivative_matches_central_differences(case, sgn):
    """d rhs / dt at fixed x along the stroke (RODAS4's df/dt) against differences of the
    right-hand side along (y + yd dt, v + vd dt)."""
    m = _model(case)
    spec, prm, ep = m.packed(P)
    x = m.initial_state(P, 0.0).astype(float)
    names = list(m.state_names)
    x[names.index("p1")], x[names.index("p2")] = P.p0 + sgn * 3e5, P.p0 - sgn * 2e5
    y, v, yd, vd = sgn * 1.2e-3, sgn * 0.04, sgn * 0.04, -sgn * 3.0
    if spec[KM.S_IC] >= 0:
        x[spec[KM.S_IC]] = y - sgn * 4e-4
    if spec[KM.S_IFP] >= 0:
        x[spec[KM.S_IFP]] = y - sgn * (GAP - 0.5 * DELTA)
        if spec[KM.S_ZPIST] != 0:
            lam = 30.0 / 2e5
            x[spec[KM.S_IZ]] = (sgn * (GAP - 0.5 * min(DELTA, 0.01 * lam))
                                - (y - x[spec[KM.S_IFP]])) / lam
    out = np.zeros(m.n_states)
    assert SM.stroke_map_rhs_t(spec, x, y, v, yd, vd, prm, ep, out)

    def central(h):
        return (m.rhs(0.0, x, (y + h * yd, v + h * vd, 0.0), P)
                - m.rhs(0.0, x, (y - h * yd, v - h * vd, 0.0), P)) / (2 * h)

    h = 2e-6  # [s]: the stroke moves 0.08 um, inside the contact's smoothing width
    fd = (4.0 * central(0.5 * h) - central(h)) / 3.0
    np.testing.assert_allclose(out, fd, rtol=1e-4, atol=1e-6 * np.max(np.abs(fd)))
    if spec[KM.S_IFP] >= 0:  # inside the smoothing the contact's slope carries dy/dt too
        still = np.zeros(m.n_states)
        SM.stroke_map_rhs_t(spec, x, y, v, 0.0, vd, prm, ep, still)
        assert abs(out[spec[KM.S_IFP]] - still[spec[KM.S_IFP]]) > 1e-3 * abs(still[
            spec[KM.S_IFP]])


def test_other_compositions_keep_the_differences():
    """Cavities behind the spring, or both maps at once, are not covered: False."""
    for effs in ([("series_compliance", {"stiffness_N_per_m": 5e5}),
                  ("cavitation", {"vapour_pressure_Pa": 4e4})],
                 [("series_compliance", {"stiffness_N_per_m": 5e5}),
                  ("freeplay", {"gap_m": GAP})]):
        m = with_effects(get_model("full"), *[make_effect(n, **kw) for n, kw in effs])
        spec, prm, ep = m.packed(P)
        x = m.initial_state(P, 0.0).astype(float)
        J = np.zeros((m.n_states, m.n_states))
        assert not SM.stroke_map_jac(spec, x, 0.0, 0.01, prm, ep, J)
