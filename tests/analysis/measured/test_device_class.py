"""Issue #19 item 4: starts that find the device class, and plausibility flags."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.calibration_result import RecordError
from liquidamp.analysis.measured.device_class import choose_start, read_loop
from liquidamp.analysis.measured.plausibility import plausibility_flags, turn_stiffness
from liquidamp.analysis.measured.records import Record
from liquidamp.analysis.measured.start import first_harmonic_stiffness
from liquidamp.device import preset
from liquidamp.device.effects import make_effect
from liquidamp.errors import ConvergenceError, ParameterError

K_SPRING, F_C = 2e4, 150.0  # a friction element with a parallel spring [N/m], [N]


def _friction_spring(f, Y, seed, v0=2e-3):
    """F = k y + F_c tanh(v / v0) + noise: a device outside the fluid family."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, 4 / f, 1 / 200.0)
    y = Y * np.sin(2 * np.pi * f * t)
    v = Y * 2 * np.pi * f * np.cos(2 * np.pi * f * t)
    F = K_SPRING * y + F_C * np.tanh(v / v0) + rng.normal(0, 1.0, t.size)
    return Record.from_arrays(t, y + rng.normal(0, 2e-6, t.size), F)


@pytest.fixture(scope="module")
def friction_spring():
    return _friction_spring(2.0, 0.005, 1), _friction_spring(3.0, 0.003, 2)


def test_loop_reading_finds_friction_level_spring_and_offset(friction_spring):
    cal, _ = friction_spring
    L = read_loop([cal])
    assert L.friction == pytest.approx(F_C, rel=0.05)
    assert L.stiffness == pytest.approx(K_SPRING, rel=0.25)
    assert abs(L.offset) < 2.0 and L.friction_source.startswith("least squares")
    # a sharp transition: the pre-sliding stroke is a small share of the stroke
    assert L.presliding < 0.05 * cal.amplitude


def test_friction_element_with_a_spring_gets_the_friction_start(friction_spring):
    """No fluid impostor: the friction start wins on calibration and held-out records."""
    cal, val = friction_spring
    res = calibrate([cal], validate=[val], warn=False)
    assert res.device_class == "friction"
    by = {o.name: o for o in res.class_starts}
    assert set(by) == {"fluid", "friction", "viscous", "valved"} and by["friction"].chosen
    # the fluid start, continued, predicts the held-out record with twice the error (0.64
    # against 0.30; on the calibration record it draws the spring, 0.39 against 0.42)
    assert by["fluid"].continued
    assert by["fluid"].nrmse_validation > 2 * res.nrmse_validation
    fr = {e.name: e for e in res.effects}["smooth_friction"]
    assert fr.force_N == pytest.approx(F_C, rel=0.1)
    # the fluid is held at the record's noise floor: only the friction was fitted
    assert set(res.varying) == {"smooth_friction.force_N", "smooth_friction.stiffness_N_per_m"}
    assert res.plausibility == ()
    d = res.as_dict()
    assert d["device_class"]["chosen"] == "friction" and len(d["device_class"]["starts"]) == 4
    assert "device class friction (fluid: calibration" in res.summary()
    assert "device class       = friction" in res.fit_report()


def _fake(cal, val, k, cal_rec=None):
    """A stand-in CalibrationResult: calibration NRMSE ``cal`` (white residual of 400
    samples), pooled held-out ``val``, ``k`` varied parameters."""
    r = cal * np.random.default_rng(0).standard_normal(400)  # RSS proportional to cal^2
    errs = (RecordError("c", "calibration", cal_rec or cal, 1.0, 1e-3),
            RecordError("v", "validation", val, 2.0, 1e-3))
    return SimpleNamespace(residuals=lambda role: [r], varying=tuple(range(k)),
                           nrmse_calibration=cal, nrmse_validation=val,
                           record_errors=errs, nfev=10)


def test_choose_start_bic_then_held_out_dominance():
    # the lowest BIC wins ...
    name, out, note = choose_start({"fluid": _fake(0.30, 0.6, 4), "friction": _fake(0.20, 0.6, 6)})
    assert name == "friction" and note == ""
    # ... extra parameters are paid for: a 1 % lower residual does not buy two parameters
    name, *_ = choose_start({"fluid": _fake(0.200, 0.3, 4), "friction": _fake(0.198, 0.3, 6)})
    assert name == "fluid"
    # a start better held-out and no worse on any record dominates the BIC leader where its
    # BIC is higher by less than BIC_POSITIVE (2: 1.6 here) ...
    fits = {"viscous": _fake(0.200, 0.60, 4), "friction": _fake(0.2004, 0.30, 4)}
    name, out, note = choose_start(fits)
    assert name == "friction" and not {o.name: o for o in out}["viscous"].admissible
    # ... not where it pays for its match with parameters the calibration records do not
    # support (two more, a 2.5 % larger residual: BIC higher by 32): the leader is not
    # dominated, and the strong evidence keeps it (the rule before session 13 let the
    # 5 % NRMSE tolerance alone exclude it)
    fits = {"viscous": _fake(0.200, 0.60, 4), "friction": _fake(0.205, 0.30, 6)}
    name, out, note = choose_start(fits)
    assert name == "viscous" and {o.name: o for o in out}["viscous"].admissible
    assert note.startswith("the records disagree: the friction start")
    # the fluid start gives way only to a start at least as good held-out
    fits = {"fluid": _fake(0.30, 0.40, 4), "friction": _fake(0.20, 0.41, 2, 0.35)}
    name, out, note = choose_start(fits)
    assert name == "fluid" and "predicts the held-out records worse" in note
    # the records disagree (better held-out, far worse calibration): strong BIC evidence
    # keeps the leader, said so
    fits = {"fluid": _fake(0.02, 0.22, 4), "friction": _fake(0.06, 0.17, 6)}
    name, out, note = choose_start(fits)
    assert name == "fluid" and note.startswith("the records disagree: the friction start")
    # ... weak BIC evidence (a residual 0.5 % lower): the held-out records decide
    weak = {"fluid": _fake(0.200, 0.44, 4), "friction": _fake(0.201, 0.22, 4, 0.25)}
    name, out, note = choose_start(weak)
    b = {o.name: o.bic for o in out}
    assert 0 < b["friction"] - b["fluid"] < 10
    assert name == "friction" and note.startswith("the held-out records decide")
    # only eligible fits win; a failed start is reported, not chosen
    name, out, _ = choose_start({**fits, "viscous": ConvergenceError("x")},
                                eligible=("friction",))
    assert name == "friction" and {o.name: o for o in out}["viscous"].error
    with pytest.raises(ConvergenceError, match="no start could be calibrated"):
        choose_start({"fluid": ConvergenceError("a")})
    with pytest.raises(ParameterError, match="tolerance must be a number >= 0"):
        choose_start(fits, tolerance=-0.1)


def _coulomb_record(turn=5e-4, Y=0.01, F=1000.0):
    """A friction loop whose force turns over ``turn`` [m] of stroke after each reversal."""
    t = np.arange(0, 3.0, 0.001)
    y = Y * np.sin(2 * np.pi * t)
    v = np.gradient(y, t)
    z, out = -1.0, np.empty_like(t)
    for i in range(t.size):  # Dahl state, pre-sliding stroke ``turn``
        dy = abs(v[i]) * 0.001
        z = np.sign(v[i]) + (z - np.sign(v[i])) * math.exp(-dy / turn)
        out[i] = z
    return Record.from_arrays(t, y, F * out)


def test_plausibility_flags_name_their_numbers():
    rec = _coulomb_record()
    kt = turn_stiffness([rec])
    assert 1e6 < kt < 1e7  # F_a over the ~0.7 mm the Dahl state needs to swing by F_a
    p = preset("paper_initial")
    K = abs(first_harmonic_stiffness(rec))  # 4 F / (pi Y) = 1.27e5 N/m
    assert K == pytest.approx(4e3 / (math.pi * 0.01), rel=0.05)
    soft = make_effect("series_compliance", stiffness_N_per_m=1.5 * K)
    flags = plausibility_flags(p, (soft,), [rec])
    assert [f.kind for f in flags] == ["series_softer_than_loop"]
    assert flags[0].values["series_stiffness [N/m]"] == 1.5 * K
    # below the turn stiffness but more than 2 |K*|: the spring takes under half the stroke
    assert plausibility_flags(p, (make_effect("series_compliance",
                                              stiffness_N_per_m=2.5 * K),), [rec]) == ()
    assert "below the loop's own turn stiffness" in flags[0].message
    # a rig spring much stiffer than the loop is not flagged
    assert plausibility_flags(p, (make_effect("series_compliance",
                                              stiffness_N_per_m=10 * kt),), [rec]) == ()
    # a dead band of half the stroke, end stops past the chamber
    gap = make_effect("freeplay", gap_m=0.006)
    stops = make_effect("end_stops", stiffness_N_per_m=1e6, clearance_m=0.03)
    kinds = [f.kind for f in plausibility_flags(p, (gap, stops), [rec])]
    assert kinds == ["gap_comparable_to_stroke", "end_stops_unsupported"]
    floating = make_effect("floating_freeplay", gap_m=0.006, contact_stiffness_N_per_m=1e7)
    flags = plausibility_flags(p, (floating,), [rec])
    assert [f.kind for f in flags] == ["gap_comparable_to_stroke"]
    assert flags[0].message.startswith("floating_freeplay gap 6 mm")
    narrow = make_effect("floating_freeplay", gap_m=0.001, contact_stiffness_N_per_m=1e7)
    assert plausibility_flags(p, (narrow,), [rec]) == ()
    # a fluid device sized 150x with its air ratios at a bound: the impostor
    flags = plausibility_flags(p, (), [rec], force_scale=150.0, at_bound=("inv_gamma1", "c2"))
    assert [f.kind for f in flags] == ["fluid_unsupported"]
    assert flags[0].values["at_bound"] == ["inv_gamma1", "c2"]
    assert plausibility_flags(p, (), [rec], force_scale=2.0, at_bound=("c2",)) == ()
    # a piston so large that the force needs 1 % of p0
    big = p.replace(A_p=1000.0 / (0.01 * p.p0), V01=1.0, V02=1.0)
    flags = plausibility_flags(big, (), [rec])
    assert [f.kind for f in flags] == ["piston_too_large"]
    assert flags[0].values["pressure_swing [Pa]"] == pytest.approx(0.01 * p.p0, rel=0.02)


def test_real_friction_damper_gets_the_friction_start(friction_damper_records):
    """Issue #19: the default calibration of the real friction-damper records (as the
    calibrate command conditions them) starts from the friction damper, not from a
    fluid impostor; the fluid start's held-out error is 3x the friction start's."""
    from liquidamp.analysis.measured.conditioning import condition
    from liquidamp.analysis.measured.records import read_record

    d = friction_damper_records
    cal, val = ([condition(read_record(d / f"brfd30_{f}_0.5in_steady.csv"))[0] for f in fs]
                for fs in (("0.5Hz",), ("1Hz", "0.25Hz")))
    res = calibrate(cal, validate=val, warn=False)
    assert res.device_class == "friction" and res.plausibility == ()
    by = {o.name: o for o in res.class_starts}
    assert by["fluid"].nrmse_validation > 3 * res.nrmse_validation  # 0.87 against 0.24
    assert res.nrmse_validation < 0.3 and res.nrmse_calibration < 0.25
    fr = {e.name: e for e in res.effects}["smooth_friction"]
    assert 5e3 < fr.force_N < 15e3  # the band slips at +13 / -10 kN
    # the fluid carries what the friction leaves: not the impostor's 338 mm piston
    assert 2 * math.sqrt(res.params.A_p / math.pi) < 0.17
