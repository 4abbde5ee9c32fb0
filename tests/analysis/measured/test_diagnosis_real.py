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
                   "branch) and the backlash candidate; validation NRMSE is 0.25 on the "
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


def test_friction_damper_offset_and_friction_are_found(diagnosis):
    """What holds today: friction first, then the load-cell-like offset that the fixed 10 %
    rule rejected (held-out NRMSE -9.4 %, delta BIC -3860 counted over 6 000 correlated
    samples); the noise floor is the record's scatter (NRMSE about 0.02 once decimated,
    not 0.0007), and the records are decimated 27x, 13x and 54x to keep 30 harmonics."""
    d = diagnosis
    assert d.added[0] in FRICTION and "force_offset" in d.added, d.added
    offset = next(c for s in d.steps for c in s.candidates if c.effect == "force_offset"
                  and c.accepted)
    assert offset.delta_bic < -10 and offset.n_effective < 0.5 * d.final.n_samples
    assert 0.015 < d.noise_nrmse < 0.035
    assert [c.factor for c in d.conditioning] == [27, 13, 54]
    assert d.nrmse_raw["validation"] < 0.5 * d.baseline.nrmse_validation
