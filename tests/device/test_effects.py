"""Add-on effects: zero strength is the bare model, physics invariants, clear errors."""

import math

import numpy as np
import pytest

from liquidamp.analysis.measured.record_model import integrate
from liquidamp.device import preset
from liquidamp.device.effects import (
    EFFECTS,
    Cavitation,
    CoulombFriction,
    Leakage,
    SeriesCompliance,
    make_effect,
    with_effects,
)
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("paper_calibrated")
STROKE = HarmonicStroke(0.003, 3.0)


def _stroke(t):
    y, v, a = STROKE(t)
    return float(y), float(v), float(a)


def _run(model, t_end=0.7, n=141, params=P):
    t = np.linspace(0, t_end, n)
    drive = _stroke
    if model.input_channels:  # a measured input held at 1 (issue #20: u = (y, v, a, c))
        def drive(tq):
            return _stroke(tq) + (np.ones(4),)
    X = integrate(model, params, drive, t, model.initial_state(params, 0.0), rtol=1e-9,
                  atol_scale=1e-11)
    u = STROKE(t)
    return t, X, u, np.asarray(model.force(t, X, u, params)) * np.ones(t.size)


ZERO = {"coulomb_friction": {"force_N": 0.0}, "smooth_friction": {"force_N": 0.0},
        "force_offset": {"offset_N": 0.0}, "moving_mass": {"mass_kg": 0.0},
        "series_compliance": {"stiffness_N_per_m": math.inf}, "freeplay": {"gap_m": 0.0},
        "leakage": {"coefficient_m3_per_s_Pa": 0.0}, "cavitation": {"vapour_pressure_Pa": 1.0},
        "relief_valve": {"conductance_m3_per_s_Pa": 0.0}, "asymmetric_loss": {"rebound_ratio": 1.0},
        "elastomer": {"parallel_stiffness_N_per_m": 0.0, "branch_stiffness_N_per_m": 0.0},
        "end_stops": {"stiffness_N_per_m": 0.0},
        "rotating_frame": {"rotor_speed_rad_per_s": 0.0, "mounting_radius_m": 0.5},
        "gas_charge": {"rod_area_m2": 0.0},
        "digressive_valve": {"compression_conductance_m3_per_s_Pa": 0.0,
                             "rebound_conductance_m3_per_s_Pa": 0.0},
        "field_yield": {"yield_pressure_Pa": 0.0, "yield_pressure_per_input": 0.0},
        "self_heating": {"beta_per_K": 0.0, "c2_exponent": 0.0},
        "bypass_groove": {"depth": 0.0},
        "slip_weakening": {"ratio": 0.0},
        "floating_freeplay": {"gap_m": 0.0, "contact_stiffness_N_per_m": 1e5}}
#: Effects that modify another one: the bare model holds that one (slip weakening weakens
#: smooth friction).
COMPANION = {"slip_weakening": ("smooth_friction", {"force_N": 30.0,
                                                    "stiffness_N_per_m": 1e6})}


@pytest.mark.parametrize("name", list(EFFECTS))
def test_zero_strength_is_bare_model(name):
    bare = get_model("full")
    if name in COMPANION:
        other, values = COMPANION[name]
        bare = with_effects(bare, make_effect(other, **values))
    F0 = _run(bare)[3]
    F1 = _run(with_effects(bare, make_effect(name, **ZERO[name])))[3]
    assert np.max(np.abs(F1 - F0)) < 1e-5 * np.max(np.abs(F0))


def test_force_effects_add_their_force():
    bare = get_model("full")
    t, X, u, F0 = _run(bare)
    m = with_effects(bare, CoulombFriction(30.0), make_effect("force_offset", offset_N=-5.0),
                     make_effect("moving_mass", mass_kg=2.0))
    F = np.asarray(m.force(t, X, u, P))
    assert np.allclose(F - F0, 30.0 * np.sign(u[1]) - 5.0 + 2.0 * u[2])


@pytest.mark.parametrize("model", ["full", "no_inertia", "constant_bulk", "inertial"])
def test_leakage_conserves_mass_and_changes_force(model):
    m = with_effects(get_model(model), Leakage(2e-10))
    t, X, u, F = _run(m)
    M = np.asarray(m.mass(X, u, P))
    assert np.max(np.abs(M / M[0] - 1)) < 1e-7
    F0 = _run(get_model(model))[3]
    assert np.max(np.abs(F - F0)) > 0.02 * np.max(np.abs(F0))


def test_cavitation_keeps_pressure_at_or_above_vapour_pressure():
    pv = 40e3  # above the bare model's lowest pressure (about 30 kPa here)
    bare = get_model("full")
    t, X, u, _ = _run(bare)
    assert min(X[0].min(), X[2].min()) < pv
    m = with_effects(bare, Cavitation(pv))
    t, X, u, F = _run(m)
    p1, p2 = m.pressures(X, u, P)
    assert min(p1.min(), p2.min()) > pv * (1 - 1e-3)
    assert max(X[5].max(), X[6].max()) > 1e-8  # a cavity opened (m^3)
    M = np.asarray(m.mass(X, u, P))
    assert np.max(np.abs(M / M[0] - 1)) < 1e-7


@pytest.mark.parametrize("base", ["full", "inertial"])
def test_cavity_rates_keep_the_liquid_on_its_pressure_curve(base):
    """The liquid of a chamber with a cavity fills V - Vc at its curve's density: the
    invariants' rates grad(g) . dx/dt vanish (closed form: 0) inside the switch, where
    pressure and cavity share the compression, expanding and compressed; with the split over
    the whole chamber V (before session 10) they were of order Vc / V times the rate."""
    from liquidamp.coupled.invariants import invariants

    pv = 40e3
    m = with_effects(get_model(base), Cavitation(pv), make_effect("leakage",
                                                                  coefficient_m3_per_s_Pa=1e-11))
    ic = m.state_names.index("Vc1")
    y = 1e-3
    for p1, vc, v in ((41.0e3, 1e-7, -0.1), (41.5e3, 3e-9, 0.1), (42.0e3, 2e-7, 0.05)):
        x = m.initial_state(P, y)
        x[0], x[ic] = p1, vc
        x[ic + 1] = 0.5 * vc  # chamber 2 (far above p_v) holds a cavity too
        if base == "full":
            x[4] = 1e-3  # a flow through the channel (kg/s)
        else:
            x[2] = 1e-3
        g, G = invariants(m, P, x, y)
        dx = m.rhs(0.0, x, (y, v, 0.0), P)
        assert not np.allclose(dx[[ic, ic + 1]], 0.0)
        # the rate of each invariant (the stroke's change of V enters the chamber rows
        # and the mass through dg/dy v)
        h = 1e-7
        dgdy = (invariants(m, P, x, y + h)[0] - invariants(m, P, x, y - h)[0]) / (2 * h)
        rate = (G @ dx + dgdy * v) / g
        scale = np.abs(dx[0]) / 1e9 + abs(v) / 0.025  # typical d ln rho/dt [1/s]
        assert np.all(np.abs(rate) < 1e-7 * scale), rate


def test_compliance_softens_and_freeplay_delays():
    bare = get_model("full")
    F0 = _run(bare)[3]
    Fc = _run(with_effects(bare, SeriesCompliance(2e5)))[3]
    assert np.ptp(Fc) < 0.9 * np.ptp(F0)
    Ff = _run(with_effects(bare, make_effect("freeplay", gap_m=3e-4)))[3]
    assert np.ptp(Ff) < np.ptp(F0)


def test_smooth_friction_tends_to_coulomb():
    bare = get_model("full")
    t, X, u, F0 = _run(bare)
    Fs = _run(with_effects(bare, make_effect("smooth_friction", force_N=30.0,
                                             stiffness_N_per_m=1e7)))[3]
    late = t > 0.4
    moving = np.abs(u[1]) > 0.01
    assert np.allclose((Fs - F0)[late & moving], 30 * np.sign(u[1])[late & moving], atol=0.5)


def test_errors():
    with pytest.raises(ParameterError, match="needs a model with chamber pressure"):
        with_effects(get_model("single_state"), Cavitation())
    with pytest.raises(ParameterError, match="carried by its states"):
        with_effects(get_model("dashpot"), SeriesCompliance(1e5))
    with pytest.raises(ParameterError, match="given twice"):
        with_effects(get_model("full"), CoulombFriction(1.0), CoulombFriction(2.0))
    with pytest.raises(ParameterError, match="force_N"):
        CoulombFriction(-1.0)
    with pytest.raises(ParameterError, match="unknown coulomb_friction parameter"):
        CoulombFriction(1.0).replace(mass_kg=1.0)
