"""Must-show of issue #12 on real records: the banded rotary friction damper with backlash
(../shared/data/friction-damper-backlash/; CC BY-SA 4.0, Coble, Huggins, Cao, Ricles,
Downey 2022, see that folder's README).  Calibrated on the 0.5 Hz steady record, validated on
the 1 Hz and 0.25 Hz ones, the diagnosis must add friction and the dead band (freeplay in
series with the friction), leave no parameter at a bound without a warning, and reach a
validation NRMSE of at most 0.12 (0.29 with smooth friction alone before issue #12; the
issue measured 0.22 with friction and an offset)."""

import math

import pytest

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.records import read_record

CAL = "brfd30_0.5Hz_0.5in_steady.csv"
VAL = ("brfd30_1Hz_0.5in_steady.csv", "brfd30_0.25Hz_0.5in_steady.csv")
FRICTION = {"coulomb_friction", "smooth_friction"}


@pytest.fixture(scope="module")
def diagnosis(friction_damper_records):
    d = friction_damper_records
    return diagnose([read_record(d / CAL)], [read_record(d / v) for v in VAL])


def _at_bound(result):
    out = []
    for name in result.varying:
        p = result.spec[name]
        lo, hi = p.x_bounds()
        x = p.to_x(result.values[name])
        if min(x - lo, hi - x) <= 1e-3 * (hi - lo):
            out.append(name)
    return out


@pytest.mark.xfail(run=False, reason="needs freeplay in series with friction (effects "
                   "branch) and the backlash candidate; validation NRMSE is 0.55 on the "
                   "records as given without it")
def test_friction_damper_diagnosis_meets_the_issue(diagnosis):
    d = diagnosis
    assert FRICTION & set(d.added), d.added
    assert "backlash" in d.added, d.added  # freeplay in series with the friction
    warned = " ".join(d.final.warnings + d.warnings)
    for name in _at_bound(d.final):
        assert name in warned, f"{name} at a bound without a warning"
    assert d.nrmse_raw["validation"] <= 0.12
    assert d.final.nrmse_validation <= 0.12
    assert math.isfinite(d.noise_nrmse) and d.noise_nrmse > 0.01


def test_friction_damper_conditioning_floor_and_rule(diagnosis):
    """What holds whatever the catalogue: the records are decimated 27x, 13x and 54x to keep
    30 harmonics (3 cycles each: not averaged); the noise floor is the record's scatter from
    cycle to cycle (NRMSE about 0.02 once decimated, not the 0.0007 of the 4th-difference
    estimate, so the stop rule can fire); every effect added passed the rule, delta BIC
    below -10 counted over far fewer effective samples than samples, and the held-out
    error did not rise by more than 2 %."""
    d = diagnosis
    assert [c.factor for c in d.conditioning] == [27, 13, 54]
    assert all(c.cycles_averaged == 1 for c in d.conditioning)
    assert 0.015 < d.noise_nrmse < 0.035
    n = d.final.n_samples
    before = d.baseline.nrmse_validation
    for step in d.steps:
        ev = next(c for c in step.candidates if c.effect == step.effect)
        assert ev.accepted and ev.delta_bic < -10 and ev.n_effective < 0.5 * n
        assert step.nrmse_validation <= 1.02 * before
        before = step.nrmse_validation
