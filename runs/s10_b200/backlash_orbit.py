"""The backlash refit of the 200 Hz Coulomb-friction bench record: its model at the fitted
point run cold (from rest) and warm (from the fit's last orbit), timed.

PYTHONPATH=. python runs/s10_b200/backlash_orbit.py [EFFECT]
"""
import sys
import time

import numpy as np

import liquidamp.analysis.measured.diagnosis as D
from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.diagnosis_options import march_options
from liquidamp.analysis.measured.fit_objective import build
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.device.effects import with_effects
from liquidamp.device.models import get_model

effect = sys.argv[1] if len(sys.argv) > 1 else "coulomb_friction"
GOT = {}
_r = D._refit


def refit(cand, *a, **k):
    t = time.perf_counter()
    res = _r(cand, *a, **k)
    GOT[cand.effect] = (res, time.perf_counter() - t)
    return res


D._refit = refit
recs = real_rate_records("diagnosis_200hz_10_cycles", effect)
D.diagnose([recs[0]], [recs[1]], max_steps=1)
for name, (res, sec) in GOT.items():
    print(name, f"{sec:.1f} s", res.status, "cal", round(res.nrmse_calibration, 6),
          {k: f"{v:.4g}" for k, v in res.values.items()},
          [(e.name, e.as_dict()) for e in res.effects])
res = GOT["backlash"][0]
rec = res.calibration[0]
opts = march_options(None, res.calibration)
params, effects = build(res.start_params, res.effects, res.spec, res.values)
m = with_effects(get_model(res.model), *effects)
for label, x0 in (("cold", None), ("cold again", None)):
    t = time.perf_counter()
    r = simulate_record(m, params, rec, options=opts, x0=x0)
    print(label, f"{time.perf_counter() - t:.2f} s", nrmse(r.force, rec.force), r.solver_stats)
    last = r.states[:, 0]
t = time.perf_counter()
r = simulate_record(m, params, rec, options=opts, x0=last)
print("warm", f"{time.perf_counter() - t:.2f} s", nrmse(r.force, rec.force), r.solver_stats)
print("states cold", np.round(last, 9))
