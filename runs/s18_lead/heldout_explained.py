"""Experiment (not in the library): a round counts as explained only where a refit reaches
the structure level on calibration AND predicts every held-out record within
structure_factor x that record's own floor.  python runs/s18_lead/heldout_explained.py CAL VAL."""
import sys

import liquidamp.analysis.measured.diagnosis as D
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record
from liquidamp.analysis.measured.records import read_record

held = {}
orig_noise = D._noise


def noise(*a, **k):
    out = orig_noise(*a, **k)
    held.clear()
    held.update(out[3])
    return out


def explained(refits, level):
    factor = D.DiagnoseOptions().selection.structure_factor
    for r in refits.values():
        if r.nrmse_calibration > level:
            continue
        got = heldout_per_record(r)
        if all(v <= factor * held.get(k, 0.0) for k, v in got.items()):
            return True
    return False


D._noise = noise
if len(sys.argv) > 3:
    D._explained = explained
d = D.diagnose([read_record(sys.argv[1])], [read_record(sys.argv[2])])
print(d.summary().splitlines()[0][:400])
print("held-out floors", held)
