"""Issue #19's must-show on the real friction-damper records (../shared/data/
friction-damper-backlash/; CC BY-SA 4.0, Coble, Huggins, Cao, Ricles, Downey 2022, see that
folder's README), by the command's defaults: calibrated on the 0.5 Hz record, held out the
1 Hz and 0.25 Hz ones, steady (3 full cycles) and whole (tapered) records.

The issue asks for a validation NRMSE of at most 0.13 with friction and the dead band found.
Read as the issue's own figure (0.1147 with ``--sizing preset --max-steps 4``: the pooled
held-out NRMSE), the default reaches 0.1115 (steady) and 0.1293 (tapered).  Per record the
1 Hz records stay at 0.132 and 0.149, about what the same model reaches fitted on those
records themselves (0.127 and 0.134, runs/s20_lead/README.md section 4): the bounds below hold
them where they are, not at 0.13.

Cost: about 2 and 3 minutes, so they run only with ``LIQUIDAMP_INDEPENDENT=all``.
"""

import os

import pytest

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record
from liquidamp.analysis.measured.records import read_record

FRICTION = {"coulomb_friction", "smooth_friction"}
DEAD_BAND = {"freeplay", "floating_freeplay"}


@pytest.mark.parametrize("kind, per_record_1hz", [("steady", 0.136), ("full", 0.153)])
def test_the_default_diagnosis_of_the_friction_damper(friction_damper_records, kind,
                                                      per_record_1hz):
    """Pooled held-out NRMSE at most 0.13, friction and a dead band in the final model, the
    0.25 Hz record at most 0.13 on its own, the 1 Hz record within 3 % of session 20's figure
    (0.1322 / 0.1491), and the summary's first line saying the residual keeps structure."""
    if os.environ.get("LIQUIDAMP_INDEPENDENT") != "all":
        pytest.skip("long held-out check: set LIQUIDAMP_INDEPENDENT=all to run it")
    d = friction_damper_records
    cal = read_record(d / f"brfd30_0.5Hz_0.5in_{kind}.csv")
    val = [read_record(d / f"brfd30_{f}_0.5in_{kind}.csv") for f in ("1Hz", "0.25Hz")]
    res = diagnose([cal], val)
    names = {e.name for e in res.final.effects}
    assert names & FRICTION and names & DEAD_BAND, names
    assert res.final.nrmse_validation <= 0.13
    per = heldout_per_record(res.final)
    assert per[f"brfd30_0.25Hz_0.5in_{kind}"] <= 0.13
    assert per[f"brfd30_1Hz_0.5in_{kind}"] <= per_record_1hz
    assert res.summary().startswith("UNEXPLAINED")
