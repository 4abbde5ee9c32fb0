"""Fit the 200 Hz bench freeplay record's model (four multipliers + the gap) from a given
point: does the least-squares fit reach the truth's residual?

PYTHONPATH=. python runs/s10_b200/refit_from.py EFFECT JSON_START [JSON_CALIBRATE_KW]
"""
import json
import sys
import time

import numpy as np
import scipy.optimize

from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records
from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.diagnosis_options import march_options
from liquidamp.analysis.measured.fit_spec import FitSpec
from liquidamp.device.effects import make_effect

_ls = scipy.optimize.least_squares


def ls(fun, x0, *a, **k):
    s = _ls(fun, x0, *a, **k)
    print(f"  lsq k={len(x0)} cost {s.cost:.4g} nfev {s.nfev} status {s.status} "
          f"x={np.round(s.x, 4)} step {np.round(s.x - x0, 4)}")
    return s


scipy.optimize.least_squares = ls
name = "diagnosis_200hz_10_cycles"
eff = sys.argv[1]
start = json.loads(sys.argv[2])
kw = json.loads(sys.argv[3]) if len(sys.argv) > 3 else {}
truth = REAL_RATE_RECORDS[name][-1][eff]
recs = [condition(r)[0] for r in real_rate_records(name, eff)]
e = make_effect(eff, **{**truth, **start.get(eff, {})})
spec = FitSpec.default(effects=(e,)).with_values(start.get("mult", {}))
t = time.perf_counter()
r = calibrate(recs[:1], effects=(e,), spec=spec, validate=recs[1:], start="spec",
              options=march_options(None, recs), warn=False, sizing="preset", **kw)
print(f"{time.perf_counter() - t:.1f} s cal {r.nrmse_calibration:.5g} val "
      f"{r.nrmse_validation:.5g} {r.status} {r.message[:80]}")
print({k: round(v, 5) for k, v in r.values.items()})
