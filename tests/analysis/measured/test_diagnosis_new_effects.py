"""Issue #12's effects are diagnosis candidates (the catalogue is the effects registry).

Since issue 19 they are default candidates like every catalogue effect (a relief valve at a
low cracking pressure is a laminar bypass: where it ties with ``leakage`` on held-out data
the simpler leakage is added, which the leakage case of test_diagnosis.py guards).  Each
states its own probe
(:meth:`liquidamp.device.effects.Effect.probe`); a record made with a hidden relief
valve on the paper's calibrated device must be traced to it among the new candidates,
with its cracking pressure and conductance recovered.
"""

import numpy as np
import pytest

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import EFFECTS
from liquidamp.structure.testmachine import HarmonicStroke

NEW = ("relief_valve", "asymmetric_loss", "elastomer", "end_stops")


def test_every_catalogue_effect_states_a_probe():
    p = preset("paper_calibrated")
    for name in NEW:
        probe = EFFECTS[name].probe(800.0, 0.003, 6 * np.pi, p)
        assert probe.name == name and probe != EFFECTS[name]()


def test_hidden_relief_valve_is_found_among_the_new_candidates():
    r0 = steady_state("full", preset("paper_calibrated"), HarmonicStroke(0.003, 3.0))
    p_r = 0.6 * float(np.max(np.abs(r0.p1 - r0.p2)))  # about 0.71 MPa
    truth = {"relief_valve": {"cracking_pressure_Pa": p_r, "conductance_m3_per_s_Pa": 3e-10}}
    cal = synthetic_record(preset="paper_calibrated", frequency=3.0, amplitude=0.003, cycles=3,
                           seed=71, effects=truth)
    val = synthetic_record(preset="paper_calibrated", frequency=4.0, amplitude=0.0025,
                           cycles=3, seed=171, effects=truth)
    d = diagnose([cal], [val], top=1, max_nfev=40, max_steps=1, candidates=NEW)
    assert d.added == ("relief_valve",)
    step = d.steps[0]
    assert {c.effect for c in step.candidates} == set(NEW)
    assert all("failed" not in c.note for c in step.candidates)
    assert step.parameters["cracking_pressure_Pa"] == pytest.approx(p_r, rel=0.05)
    assert step.parameters["conductance_m3_per_s_Pa"] == pytest.approx(3e-10, rel=0.1)
    assert d.final.nrmse_validation < 0.1 * d.baseline.nrmse_validation

