"""Friction behind backlash on a fluid device is found first, as one composite (issue #19).

The paper's calibrated device with smooth friction (40 N) that engages only after the rod has
travelled 2g = 0.6 mm past each reversal, the fluid on the rod (toolkit-made records, 3 cycles
at 200 Hz).  The calibrated fluid model holds no friction, so the composite ``backlash`` adds
smooth friction behind its own dead band, the gap from the profile of its additive signature
(:func:`~liquidamp.analysis.measured.candidates.backlash_gap`).  Before, the composite needed
friction in the model first and moved it behind a dead band that the fluid sat behind too:
the default took friction, a relief valve or more friction before any dead band.
"""

import pytest

from liquidamp.analysis.measured.candidates import backlash_gap
from liquidamp.analysis.measured.diagnosis import COMPOSITES, diagnose
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.device.effects import EFFECTS

ALL = tuple(n for n, c in EFFECTS.items() if c.fit_keys) + tuple(COMPOSITES)
FORCE, GAP = 40.0, 3e-4
TRUTH = {"smooth_friction": {"force_N": FORCE, "stiffness_N_per_m": 1e6,
                             "location": "piston"},
         "freeplay": {"gap_m": GAP, "drives": "friction"}}


@pytest.fixture(scope="module")
def diagnosis():
    cal = synthetic_record(preset="paper_calibrated", frequency=3.0, amplitude=0.003, cycles=3,
                           seed=87, effects=TRUTH)
    val = synthetic_record(preset="paper_calibrated", frequency=4.0, amplitude=0.0025,
                           cycles=3, seed=187, effects=TRUTH)
    return diagnose([cal], [val], top=1, max_nfev=40, max_steps=1, candidates=ALL)


def test_friction_behind_its_own_dead_band_is_added_first(diagnosis):
    d = diagnosis
    assert d.added == ("backlash",), (d.added, d.stop_reason)
    params = d.steps[0].parameters
    assert params["gap_m"] == pytest.approx(GAP, rel=0.3)
    assert params["smooth_friction.force_N"] == pytest.approx(FORCE, rel=0.3)
    fp = next(e for e in d.final.effects if e.name == "freeplay")
    assert fp.drives == "friction"
    assert d.final.nrmse_validation < 0.5 * d.baseline.nrmse_validation


def test_the_gap_profile_of_the_baseline_residual_peaks_at_the_dead_band(diagnosis):
    gap, drop = backlash_gap(diagnosis.baseline)
    assert gap == pytest.approx(GAP, rel=0.3)
    assert 0.0 < drop <= 1.0
