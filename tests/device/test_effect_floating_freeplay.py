"""floating_freeplay: the dead band before a piston no seal holds.

Checked against an independent route (a piston WITH mass between a contact spring-damper
and a Maxwell fluid, integrated by scipy's Radau with its own equations), against its limits
(a closing band is a series spring; gap 0 is the bare model: tests/device/test_effects.py),
and for the physics that tells it from ``freeplay``: inside the band the force is zero and
the chambers hold their pressures (the piston drifts with the channel's flow), and the rod
loses the piston where the chambers have unloaded, not where it reverses.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from liquidamp.coupled.invariants import onto_invariants
from liquidamp.coupled.testrig import HarmonicStroke, steady_state
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.kernels_laws import (
    float_contact,
    float_contact_force,
    float_contact_offset,
)
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError

GAP, K_C = 4e-4, 2e7


def _massive_piston_maxwell(p, Y, f, gap, k_c, m_p=5e-3, c_c=None, cycles=3):
    """Load-cell force [N] over the last cycle of a massive piston behind a dead band and a
    Maxwell fluid (dF/dt = k_D v_p - F / T_D), written here from the physics (not liquidamp's
    kernels): m v_p' = f_c - F, f_c = k_c (e -+ gap) + c_c (v - v_p) beyond the band (a
    contact only pushes), 0 inside it."""
    w = 2 * math.pi * f
    c_c = 0.2 * math.sqrt(k_c * m_p) if c_c is None else c_c

    def contact(t, z):
        y, v = Y * math.sin(w * t), Y * w * math.cos(w * t)
        e, ev = y - z[1], v - z[2]
        if e > gap:
            return max(k_c * (e - gap) + c_c * ev, 0.0)
        if e < -gap:
            return min(k_c * (e + gap) + c_c * ev, 0.0)
        return 0.0

    def rhs(t, z):
        F, yp, vp = z
        return [p.k_D * vp - F / p.T_D, vp, (contact(t, z) - F) / m_p]

    T = 1.0 / f
    t_eval = np.linspace((cycles - 1) * T, cycles * T, 401)
    sol = solve_ivp(rhs, (0.0, cycles * T), [0.0, 0.0, 0.0], method="Radau", t_eval=t_eval,
                    rtol=1e-8, atol=[1e-6, 1e-12, 1e-9], max_step=T / 400)
    assert sol.success
    return t_eval, np.array([contact(t, z) for t, z in zip(t_eval, sol.y.T, strict=True)])


def test_a_massless_floating_piston_is_the_limit_of_a_massive_one():
    """The Maxwell device behind the band: liquidamp's massless floating piston against an
    independent Radau run of a 5 g piston between the contact and the fluid (its contact
    resonance 10 kHz; the Maxwell relaxation time 16 ms settles it within the first of three
    cycles).  Measured: 0.6 % (1 g and 5 g pistons alike, 1.1 % at 20 g)."""
    p = preset("reference")
    Y, f = 2e-3, 3.0
    t, F_ref = _massive_piston_maxwell(p, Y, f, GAP, K_C)
    m = with_effects(get_model("maxwell"),
                     make_effect("floating_freeplay", gap_m=GAP, contact_stiffness_N_per_m=K_C))
    r = steady_state(m, p, HarmonicStroke(Y, f))
    # the liquidamp orbit on the reference run's phase grid (one period, sine stroke)
    ph = (np.asarray(r.time) * f) % 1.0
    order = np.argsort(ph)
    F = np.interp((t * f) % 1.0, ph[order], np.asarray(r.force)[order], period=1.0)
    err = float(np.sqrt(np.mean((F - F_ref) ** 2)) / np.sqrt(np.mean(F_ref ** 2)))
    assert err < 0.015
    # and the seal-held freeplay of the same gap is a different device (the route can fail)
    held = steady_state(with_effects(get_model("maxwell"),
                                     make_effect("freeplay", gap_m=GAP)),
                        p, HarmonicStroke(Y, f))
    ph2 = (np.asarray(held.time) * f) % 1.0
    o2 = np.argsort(ph2)
    Fh = np.interp((t * f) % 1.0, ph2[o2], np.asarray(held.force)[o2], period=1.0)
    assert float(np.sqrt(np.mean((Fh - F_ref) ** 2)) / np.sqrt(np.mean(F_ref ** 2))) > 5 * err


@pytest.fixture(scope="module")
def device_b_orbits():
    p = preset("device_b")
    stroke = HarmonicStroke(2e-3, 3.0)
    fl = steady_state(with_effects(get_model("full"), make_effect(
        "floating_freeplay", gap_m=GAP, contact_stiffness_N_per_m=K_C)), p, stroke)
    held = steady_state(with_effects(get_model("full"), make_effect("freeplay", gap_m=GAP)),
                        p, stroke)
    return p, fl, held


def test_inside_the_band_the_force_is_zero_and_the_chambers_hold(device_b_orbits):
    p, fl, _ = device_b_orbits
    i = fl.state_names.index("y_piston")
    e = np.asarray(fl.stroke) - fl.states[i]
    inside = np.abs(e) < 0.8 * GAP
    assert 0.05 < inside.mean() < 0.5  # the band is crossed twice a cycle
    Fmax = float(np.max(np.abs(fl.force)))
    assert np.max(np.abs(fl.force[inside])) < 1e-5 * Fmax
    # the piston drifts with the channel flow, so that neither chamber's volume changes
    # against its liquid: the pressures hold (to the integration's tolerance)
    for pk in (fl.p1, fl.p2):
        runs = np.split(np.asarray(pk)[inside], np.flatnonzero(np.diff(np.flatnonzero(inside))
                                                                > 1) + 1)
        for run in runs:
            if run.size > 3:
                assert np.ptp(run) < 1e-4 * p.p0
    # and the piston does move there (it floats; the held one would not)
    yp = fl.states[i][inside]
    assert np.ptp(yp) > 0.05 * GAP


def test_the_rod_loses_the_piston_where_the_chambers_unload(device_b_orbits):
    """Just past the stroke's top the floating piston still carries the fluid's force (the
    fluid pushes it back after the rod) and only inside the band is it free, with no force;
    ``freeplay``'s piston stays put in its band, held by its seals, while the force it
    reads relaxes through the channel."""
    _, fl, held = device_b_orbits
    y = np.asarray(fl.stroke)
    top = int(np.argmax(y))
    Fmax = float(np.max(np.abs(fl.force)))
    assert abs(float(fl.force[min(top + 2, y.size - 1)])) > 0.2 * Fmax
    i = held.state_names.index("y_fp")
    e = np.asarray(held.stroke) - held.states[i]
    inside = np.abs(e) < 0.8 * GAP
    assert inside.any()
    assert np.max(np.abs(held.force[inside])) > 0.05 * float(np.max(np.abs(held.force)))
    runs = np.split(held.states[i][inside],
                    np.flatnonzero(np.diff(np.flatnonzero(inside)) > 1) + 1)
    assert max(float(np.ptp(run)) for run in runs) < 1e-9


def test_a_closing_band_is_a_series_spring():
    p = preset("device_b")
    stroke = HarmonicStroke(2e-3, 4.0)
    k = 3e5  # soft enough to matter
    series = steady_state(with_effects(get_model("full"), make_effect(
        "series_compliance", stiffness_N_per_m=k)), p, stroke)
    closing = steady_state(with_effects(get_model("full"), make_effect(
        "floating_freeplay", gap_m=1e-7, contact_stiffness_N_per_m=k)), p, stroke)
    scale = float(np.max(np.abs(series.force)))
    ph = lambda r: (np.asarray(r.time) * 4.0) % 1.0  # noqa: E731
    o = np.argsort(ph(closing))
    F = np.interp(ph(series), ph(closing)[o], np.asarray(closing.force)[o], period=1.0)
    # 1e-7 m of band against 2 mm of stroke and k: the force moves by about k x 1e-7
    assert np.max(np.abs(F - series.force)) < 0.01 * scale


def test_contact_law_and_its_inverse_agree():
    for e in (-3e-3, -1.2e-3, -1.001e-3, -0.999e-3, 0.0, 9.9e-4, 1.0e-3, 1.003e-3, 2e-3):
        F = float_contact_force(e, 1e-3, 1e6)
        back = float_contact_offset(F, 1e-3, 1e6, e)
        if abs(e) >= 1e-3 - 0.5 * (0.05e-3 + 1e-7) + 1e-12:
            assert back == pytest.approx(e, abs=1e-12)
        else:  # inside the band: no force, the offset kept
            assert F == 0.0 and back == e
        # the engaged stiffness is the force law's slope
        h = 1e-9
        slope = (float_contact_force(e + h, 1e-3, 1e6) - float_contact_force(e - h, 1e-3, 1e6))
        assert slope / (2 * h) == pytest.approx(1e6 * float_contact(e, 1e-3), abs=1e-3 * 1e6)


def test_a_warm_start_from_another_gap_is_put_back_on_the_contact_law():
    """The massless piston's balance f_c(y - y_p) = F_fluid is conserved by the rates; a
    state from another gap's orbit breaks it and would run on another orbit: the invariant
    projection puts the piston back where the contact carries the fluid's force."""
    p = preset("device_b")
    fp = make_effect("floating_freeplay", gap_m=GAP, contact_stiffness_N_per_m=K_C)
    m = with_effects(get_model("full"), fp)
    r = steady_state(m, p, HarmonicStroke(2e-3, 3.0))
    j = int(np.argmax(np.asarray(r.force)))  # in contact, pushing
    x = np.array(r.states[:, j])
    y = float(r.stroke[j])
    i = m.state_names.index("y_piston")
    x_bad = x.copy()
    x_bad[i] -= 0.5 * GAP  # as another gap's orbit would hold it
    rest = m.initial_state(p, y)
    assert float_contact_force(y - x_bad[i], GAP, K_C) > 1.5 * float(r.force[j])
    z = onto_invariants(m, p, x_bad, rest, y)
    F = float(np.asarray(m.force(0.0, z, (y, 0.0, 0.0), p)))
    assert float_contact_force(y - z[i], GAP, K_C) == pytest.approx(F, rel=1e-6)
    assert F == pytest.approx(float(r.force[j]), rel=0.05)


def test_bad_parameters_are_refused_naming_them():
    with pytest.raises(ParameterError, match="contact_stiffness_N_per_m must be a finite"):
        make_effect("floating_freeplay", gap_m=1e-4, contact_stiffness_N_per_m=math.inf)
    with pytest.raises(ParameterError, match="gap_m"):
        make_effect("floating_freeplay", gap_m=-1e-4)
    with pytest.raises(ParameterError, match="series_compliance"):
        with_effects(get_model("full"), make_effect("series_compliance",
                                                    stiffness_N_per_m=1e6),
                     make_effect("floating_freeplay", gap_m=1e-4))
