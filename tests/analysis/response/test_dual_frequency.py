"""Dual-frequency response (issue #13 parts 1-2): closed forms, HB against the time domain.

Stroke y = A1 sin(Omega t) + A2 sin(omega t), Omega = 2 pi 4.2 rad/s (1/rev), omega = 2 pi
1.26 rad/s (lag); their ratio 10/3 gives the time route a common period of 2.38 s.
"""

import math
import warnings

import numpy as np
import pytest

from liquidamp.analysis.response.dual_frequency import (
    TAIL_TOL,
    dual_frequency_stiffness,
    torus_invariants,
)
from liquidamp.analysis.response.linear import transfer_function
from liquidamp.device import preset
from liquidamp.device.effects import CoulombFriction, SmoothFriction, make_effect, with_effects
from liquidamp.device.models import VISCOUS, ViscousParams, get_model
from liquidamp.errors import LiquidampWarning, ParameterError

F1, F2 = 4.2, 1.26
W, w = 2 * math.pi * F1, 2 * math.pi * F2
A2 = 0.5e-3


def dfs(*args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LiquidampWarning)
        return dual_frequency_stiffness(*args, **kwargs)


# ------------------------------------------------------------------ closed forms (to 1 %)
def test_quadratic_damper_closed_forms():
    """c2 v|v|: lag damping 4 c2 V1 / pi under 1/rev motion, 8 c2 V2 / (3 pi) alone."""
    c2 = 2.0e4
    A1, a2 = 3e-3, 0.15e-3  # V2 / V1 = 0.015
    r = dfs(VISCOUS, ViscousParams(0.0, c2=c2), F1, F2, A1, a2)
    V1, V2 = A1 * W, a2 * w
    assert r.method == "quadrature" and r.converged
    assert r.equivalent_damping == pytest.approx(4 * c2 * V1 / math.pi, rel=1e-2)
    assert r.single_equivalent_damping == pytest.approx(8 * c2 * V2 / (3 * math.pi), rel=1e-2)
    assert abs(r.storage) < 1e-6 * abs(r.loss)  # a damper: no storage
    # the 1/rev harmonic is the quadratic damper's own describing function at V1
    assert r.K_rev.imag / W == pytest.approx(8 * c2 * V1 / (3 * math.pi), rel=1e-3)


def test_coulomb_friction_closed_forms():
    """F_c sign(v): lag damping 2 F_c / (pi V1) under 1/rev motion, 4 F_c / (pi V2) alone."""
    Fc = 100.0
    A1, a2 = 3e-3, 0.5e-3  # V2 / V1 = 0.05: the asymptote is exact to (V2/V1)^2 / 8
    m = with_effects(VISCOUS, CoulombFriction(Fc))
    r = dfs(m, ViscousParams(0.0), F1, F2, A1, a2)
    V1, V2 = A1 * W, a2 * w
    assert r.equivalent_damping == pytest.approx(2 * Fc / (math.pi * V1), rel=1e-2)
    assert r.single_equivalent_damping == pytest.approx(4 * Fc / (math.pi * V2), rel=1e-2)
    assert r.grid == (4096, 64) and 0 < r.quadrature_error < 1e-2
    # the friction damper loses lag damping under 1/rev motion: here to V2 / (2 V1) of it
    assert r.damping_ratio == pytest.approx(V2 / (2 * V1), rel=1e-2)


@pytest.mark.parametrize("c_open", [1e-6 * 4e4, 0.2 * 4e4])
def test_relief_valve_saturated_dashpot_closed_form(c_open):
    """F = sign(v) min(c|v|, F_r + c_o(|v| - F_r/c)) under a large 1/rev velocity V1
    (c V1 > F_r): the small lag motion sees c while |v1| < F_r/c and c_o beyond, so the lag
    damping is c_o + (c - c_o) (2/pi) arcsin(F_r / (c V1)); c_o -> 0 gives the issue's
    c (2/pi) arcsin(F_r / (c V1)).  Alone (V2 c < F_r) the valve stays shut: c."""
    from liquidamp.device.effects import ReliefValve

    c, F_r = 4e4, 300.0
    A1, a2 = 3e-3, 0.05e-3  # c V1 = 3.2 kN > F_r; V2 / V1 = 0.005
    m = with_effects(VISCOUS, ReliefValve.from_force(F_r, c, c_open))
    r = dfs(m, ViscousParams(c), F1, F2, A1, a2)
    V1 = A1 * W
    expected = c_open + (c - c_open) * (2 / math.pi) * math.asin(F_r / (c * V1))
    assert r.equivalent_damping == pytest.approx(expected, rel=1e-2)
    assert r.single_equivalent_damping == pytest.approx(c, rel=1e-9)  # c V2 < F_r: shut
    assert r.equivalent_damping < 0.5 * c  # the valve takes most of the lag damping away


def test_parameter_set_friction_is_the_same_law():
    """``friction_N`` of a DeviceParams and the coulomb_friction effect give one answer."""
    p = preset("reference")
    a = dfs("dashpot", p.replace(friction_N=50.0), F1, F2, 2e-3, A2)
    b = dfs(with_effects(get_model("dashpot"), CoulombFriction(50.0)), p, F1, F2, 2e-3, A2)
    assert a.K_lag == pytest.approx(b.K_lag, rel=1e-12)
    # and the dashpot adds its c_L exactly
    assert a.equivalent_damping - p.c_L == pytest.approx(
        2 * 50.0 / (math.pi * 2e-3 * W), rel=1e-2)


# ------------------------------------------------------------------ the physical trend
def test_quadratic_loss_lag_damping_rises_with_rev_amplitude_friction_falls():
    p = preset("paper_calibrated")
    full = [dfs("full", p, F1, F2, A1, A2).equivalent_damping for A1 in (0.0, 1e-3, 2e-3)]
    assert full[0] < full[1] < full[2]
    assert full[2] > 3 * full[0]  # the quadratic loss: about 5x at 2 mm
    quad = [dfs(VISCOUS, ViscousParams(0.0, c2=1e4), F1, F2, A1, A2).equivalent_damping
            for A1 in (0.0, 1e-3, 2e-3)]
    assert quad[0] < quad[1] < quad[2]
    fric = [dfs(with_effects(VISCOUS, CoulombFriction(50.0)), ViscousParams(0.0), F1, F2, A1,
                A2).equivalent_damping for A1 in (0.0, 1e-3, 2e-3)]
    assert fric[0] > fric[1] > fric[2]


# ------------------------------------------------------------------ HB against time domain
@pytest.mark.parametrize("name", ["damper", "device_a", "paper_calibrated"])
def test_harmonic_balance_agrees_with_time_domain(name):
    """|K_lag| within 0.5 % (measured: 0.2 % at worst over 0-3 mm, 0.01-0.1 % mostly)."""
    p = preset(name)
    for A1 in (0.0, 1.5e-3, 3e-3):
        hb = dfs("full", p, F1, F2, A1, A2)
        td = dfs("full", p, F1, F2, A1, A2, method="time")
        assert hb.method == "harmonic_balance" and td.method == "time_periodic"
        assert hb.converged and hb.truncation <= TAIL_TOL and hb.residual < 1e-8
        assert abs(hb.K_lag - td.K_lag) < 5e-3 * abs(td.K_lag), (name, A1)
        if A1 > 0:
            assert abs(hb.K_rev - td.K_rev) < 5e-3 * abs(td.K_rev), (name, A1)
        else:
            assert hb.K_rev is None and td.K_rev is None
            # the lag motion alone: the single-frequency steady state
            assert abs(hb.K_lag - hb.K_single) < 1e-3 * abs(hb.K_single)
        assert hb.K_single == td.K_single


@pytest.mark.parametrize("kwargs", [
    dict(rev_amplitude=1e-3, offset=2e-3, lag_phase=0.7),  # mean stroke, lag phase
    dict(rev_amplitude=1e-4, lag_amplitude=1e-3),  # the lag velocity the larger: theta2 leads
    dict(rev_amplitude=1.5e-3, lag_frequency=F2 * math.sqrt(2)),  # no common period
])
def test_harmonic_balance_agrees_with_time_domain_elsewhere(kwargs):
    args = dict(rev_frequency=F1, lag_frequency=F2, lag_amplitude=A2)
    args.update(kwargs)
    p = preset("paper_calibrated")
    hb = dfs("full", p, **args)
    td = dfs("full", p, method="time", **args)
    assert abs(hb.K_lag - td.K_lag) < 5e-3 * abs(td.K_lag)
    assert abs(hb.K_rev - td.K_rev) < 5e-3 * abs(td.K_rev)
    if "lag_frequency" in kwargs:
        assert td.method == "time_window" and td.residual < 1e-6


def test_phase_does_not_matter_at_ten_thirds():
    """At 10/3 the phase-dependent (resonant) harmonics are of order 12: the periodic
    K_lag moves by less than 1e-5 with the lag phase (measured 7e-7), and the torus answer
    is phase-free up to its discretization (the grid moves with the phase: 6e-5)."""
    p = preset("device_a")
    ks = [dfs("full", p, F1, F2, 3e-3, A2, method="time", lag_phase=ph).K_lag
          for ph in (0.0, 1.0, 2.0)]
    assert max(abs(k - ks[0]) for k in ks) < 1e-5 * abs(ks[0])
    hb = [dfs("full", p, F1, F2, 3e-3, A2, lag_phase=ph).K_lag for ph in (0.0, 1.0)]
    assert abs(hb[1] - hb[0]) < 5e-4 * abs(hb[0])


def test_linear_model_superposes():
    """Maxwell (eq. 16) is linear: K_lag = K(i omega) whatever the 1/rev motion, by every route,
    including the windowed march where the frequencies are incommensurate."""
    p = preset("reference")
    K = complex(transfer_function("maxwell", p)(1j * w))
    for method in ("harmonic_balance", "time"):
        r = dfs("maxwell", p, F1, F2, 2e-3, A2, method=method)
        assert r.K_lag == pytest.approx(K, rel=1e-6)
        assert r.K_rev == pytest.approx(complex(transfer_function("maxwell", p)(1j * W)),
                                        rel=1e-6)
    f_irr = F2 * math.sqrt(2.0)  # no common period
    r = dfs("maxwell", p, F1, f_irr, 2e-3, A2, method="time", tol=1e-7)
    assert r.method == "time_window"
    Ki = complex(transfer_function("maxwell", p)(2j * math.pi * f_irr))
    assert r.K_lag == pytest.approx(Ki, rel=1e-4)


def test_model_with_effect_states_and_a_jump():
    """Smooth friction (a state) and Coulomb friction (a jump in the force, integrated on the
    fine grid with the states interpolated): HB against the time domain."""
    p = preset("paper_calibrated")
    m = with_effects(get_model("full"), SmoothFriction(20.0, 2e5), CoulombFriction(30.0))
    hb = dfs(m, p, F1, F2, 2e-3, A2)
    td = dfs(m, p, F1, F2, 2e-3, A2, method="time")
    assert hb.quadrature_error > 0  # the jump was integrated on the fine grid
    assert abs(hb.K_lag - td.K_lag) < 5e-3 * abs(td.K_lag)


def test_invariants_are_held_on_the_torus():
    """The converged torus keeps the filling mass and each chamber on its pressure curve,
    pointwise, though only their means over the grid are imposed."""
    from liquidamp.analysis.response._torus import grid_strokes
    from liquidamp.structure.testmachine import TwoFrequencyStroke

    p = preset("device_a")
    m = get_model("full")
    inv = torus_invariants(m, p)
    assert inv.target[2] == pytest.approx(p.rho_l * (p.V01 + p.V02), rel=1e-14)
    gaps = []
    for grid in ((51, 11), (75, 15)):
        r = dfs(m, p, F1, F2, 2e-3, A2, grid=grid)
        n, N1, N2 = r.torus.shape
        Y, _, _ = grid_strokes(TwoFrequencyStroke(2e-3, F1, A2, F2), N1, N2)
        vals, _ = inv.evaluate(r.torus.reshape(n, -1), Y.ravel())
        gaps.append(np.max(np.abs(vals[:2])))  # ln rho_i - ln r_i(p_i); ln rho swings 0.25
        assert np.max(np.abs(vals[2] / inv.target[2] - 1)) < 1e-7
        assert r.min_pressure == pytest.approx(min(r.torus[0].min(), r.torus[2].min()))
    # a discretization error: it falls spectrally with the grid (measured 5e-4, 8e-6)
    assert gaps[1] < 2e-5 and gaps[1] < gaps[0] / 20


# ------------------------------------------------------------------ errors and limits
@pytest.mark.parametrize("kwargs, message", [
    (dict(lag_amplitude=0.0), "lag_amplitude must be > 0 [m], got 0"),
    (dict(lag_amplitude=-1e-3), "lag_amplitude must be > 0 [m], got -0.001"),
    (dict(rev_amplitude=-1e-3), "rev_amplitude must be >= 0 [m]"),
    (dict(rev_frequency=0.0), "rev_frequency must be > 0 [Hz], got 0"),
    (dict(lag_frequency=-1.0), "lag_frequency must be > 0 [Hz], got -1"),
    (dict(rev_amplitude=0.024, lag_amplitude=0.002), "past the chamber end at 0.025 m"),
    (dict(offset=-0.021, rev_amplitude=0.004), "allowed: |offset| + A1 + A2 < 0.025 m"),
    (dict(method="shooting"), "unknown dual-frequency method 'shooting'"),
    (dict(grid=(32, 9)), "grid points along theta1 must be an odd integer in [5, 127], got 32"),
    (dict(model="volumetric"), "model 'volumetric' (eq. 14) does not conserve mass"),
])
def test_bad_input_names_the_quantity(kwargs, message):
    args = dict(model="full", params=preset("reference"), rev_frequency=F1, lag_frequency=F2,
                rev_amplitude=1e-3, lag_amplitude=A2)
    args.update(kwargs)
    with pytest.raises(ParameterError) as exc:
        dual_frequency_stiffness(**args)
    assert message in str(exc.value)


def test_non_convergence_names_the_amplitudes_and_residual():
    from liquidamp.errors import ConvergenceError

    with pytest.raises(ConvergenceError) as exc:
        dual_frequency_stiffness("full", preset("damper"), F1, F2, 3e-3, A2, grid=(9, 7))
    text = str(exc.value)
    assert "1/rev 0.003 m at 4.2 Hz, lag 0.0005 m at 1.26 Hz" in text and "residual" in text


def test_cavities_send_the_harmonic_balance_to_the_time_route():
    p = preset("paper_calibrated")
    m = with_effects(get_model("full"), make_effect("cavitation", vapour_pressure_Pa=2339.0))
    with pytest.raises(ParameterError, match="use method='time'"):
        dual_frequency_stiffness(m, p, F1, F2, 1e-3, A2)
    # far above the vapour pressure the cavities stay shut: the time route gives the answer
    # of the model without them
    r = dfs(m, p, F1, F2, 1e-3, A2, method="time")
    bare = dfs("full", p, F1, F2, 1e-3, A2, method="time")
    assert r.method == "time_periodic" and r.K_lag == pytest.approx(bare.K_lag, rel=1e-6)


def test_every_model_and_effect_by_harmonic_balance():
    """The registry (volumetric has no steady state) and effects with states or invariants
    of their own (the piston balance of series compliance): HB against the time domain."""
    from liquidamp.device.models import REGISTRY

    p = preset("reference")
    models = [get_model(n) for n in REGISTRY if n != "volumetric"]
    models += [with_effects(get_model("full"), make_effect("leakage",
                                                           coefficient_m3_per_s_Pa=2e-11)),
               with_effects(get_model("full"), make_effect("series_compliance",
                                                           stiffness_N_per_m=5e5)),
               with_effects(get_model("no_inertia"), make_effect("series_compliance",
                                                                 stiffness_N_per_m=5e5)),
               with_effects(get_model("full"), make_effect("moving_mass", mass_kg=2.0),
                            make_effect("force_offset", offset_N=5.0)),
               with_effects(get_model("constant_bulk"),
                            make_effect("leakage", coefficient_m3_per_s_Pa=2e-11))]
    for m in models:
        hb = dfs(m, p, F1, F2, 1e-3, A2)
        td = dfs(m, p, F1, F2, 1e-3, A2, method="time")
        assert hb.method == ("harmonic_balance" if m.n_states else "quadrature"), m.name
        assert abs(hb.K_lag - td.K_lag) < 5e-3 * abs(td.K_lag), m.name
    with pytest.raises(ParameterError, match="'freeplay' effect"):
        dual_frequency_stiffness(with_effects(get_model("full"), make_effect(
            "freeplay", gap_m=1e-4)), p, F1, F2, 1e-3, A2)


def test_low_order_commensurate_frequencies_go_to_the_time_route():
    """f_rev = 2 f_lag: the harmonics j (1, -2) resonate; with the device's invariants the
    torus is not unique there, so the harmonic balance refuses and the time route answers
    (for the linear Maxwell unit, without invariants, both routes agree)."""
    p = preset("reference")
    with pytest.raises(ParameterError, match="commensurate at low order"):
        dual_frequency_stiffness("full", p, F1, F1 / 2, 1e-3, A2)
    r = dfs("full", p, F1, F1 / 2, 1e-3, A2, method="time")
    assert r.method == "time_periodic" and r.iterations >= 2
    hb = dfs("maxwell", p, F1, F1 / 2, 1e-3, A2)
    assert hb.K_lag == pytest.approx(complex(transfer_function("maxwell", p)(1j * w / 2 * F1
                                                                             / F2)), rel=1e-6)


def test_coarse_grid_is_flagged():
    r = dfs("full", preset("paper_calibrated"), F1, F2, 1e-3, A2, grid=(11, 5))
    assert not r.converged and r.truncation > TAIL_TOL
    with pytest.warns(LiquidampWarning, match="does not resolve the response"):
        dual_frequency_stiffness("full", preset("paper_calibrated"), F1, F2, 1e-3, A2,
                                 grid=(11, 5))


def test_result_dict_has_units():
    r = dfs("full", preset("device_a"), F1, F2, 1e-3, A2)
    d = r.as_dict()
    assert d["rev_amplitude [m]"] == 1e-3 and d["lag_amplitude [m]"] == A2
    assert d["equivalent_damping [N s/m]"] == pytest.approx(d["loss [N/m]"] / w)
    assert d["single_frequency_equivalent_damping [N s/m]"] == pytest.approx(
        d["single_frequency_loss [N/m]"] / w)
    assert d["method"] == "harmonic_balance" and len(d["grid"]) == 2


def test_invariant_rounding_does_not_scale_the_constraint(monkeypatch):
    """The piston balance of series compliance is 0 at rest, but a BLAS dot product with
    fused multiply-adds leaves A_p p0 - A_p p0 at ~1e-15 N (OpenBLAS 0.3.31, numpy 2.4):
    the constraint row must be scaled by the invariant's natural variation, not by |target|
    (a 1e-15 N scale weighted it by 1e15 and the Newton iteration stalled on rounding noise).
    A target of exactly 0 and one of -1.3e-15 N (as here) give the same torus, in a few
    iterations."""
    from types import SimpleNamespace

    from liquidamp.analysis.response import _torus

    m = with_effects(get_model("full"), make_effect("series_compliance",
                                                    stiffness_N_per_m=5e5))
    p = preset("reference")
    names = torus_invariants(m, p).names
    assert names[-1] == "piston balance [N]"
    init = _torus.TorusProblem.__init__
    out = {}
    for rounding in (0.0, -1.3e-15):
        def patched(self, packed, wa, wb, Y, V, scale, invariants, X0, rounding=rounding):
            t = np.array(invariants.target, float)
            t[-1] = rounding  # [N]
            init(self, packed, wa, wb, Y, V, scale,
                 SimpleNamespace(evaluate=invariants.evaluate, target=t), X0)
            # the piston balance moves by kN over the torus: its row scale says so
            assert 1e2 < self.inv_scale[-1] < 1e6

        monkeypatch.setattr(_torus.TorusProblem, "__init__", patched)
        out[rounding] = r = dfs(m, p, F1, F2, 1e-3, A2)
        assert r.method == "harmonic_balance" and r.converged and r.iterations <= 12
    assert out[-1.3e-15].K_lag == pytest.approx(out[0.0].K_lag, rel=1e-7)
    assert out[-1.3e-15].grid == out[0.0].grid
