"""Calibration NRMSE of the truth model along one multiplier or effect key of the 200 Hz
bench record (smoothness of the objective the fits see).

PYTHONPATH=. python runs/s10_b200/scan.py EFFECT KEY LO HI N
"""
import sys

import numpy as np

from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.diagnosis_options import march_options
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.models import get_model

name = "diagnosis_200hz_10_cycles"
eff, key = sys.argv[1], sys.argv[2]
lo, hi, n = float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
truth = REAL_RATE_RECORDS[name][-1][eff]
rec = condition(real_rate_records(name, eff)[0])[0]
opts = march_options(None, [rec])
p0 = preset("paper_calibrated")
for s in np.linspace(lo, hi, n):
    kv = dict(truth)
    p = p0
    if key in kv:
        kv[key] = truth[key] * s
    else:
        p = p0.scaled(**{key: s})
    model = with_effects(get_model("full"), make_effect(eff, **kv))
    r = simulate_record(model, p, rec, options=opts)
    print(f"{s:.5f} {nrmse(r.force, rec.force):.6f} {r.solver_stats.get('route')} "
          f"{r.solver_stats.get('march_cycles')} {r.solver_stats.get('shooting_runs')}")
