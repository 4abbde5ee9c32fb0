"""Every least-squares solve of one 200 Hz bench effect's diagnosis: start and end cost,
evaluations, status, the step and the final values (why a fit stops where it stops).

PYTHONPATH=. python runs/s10_b200/lsq.py EFFECT [DIAGNOSE_KEYWORDS_JSON]
"""
import json
import sys
import time

import numpy as np
import scipy.optimize

import liquidamp.analysis.measured.diagnosis as D
from liquidamp.analysis.bench_diagnosis import real_rate_records

_ls = scipy.optimize.least_squares
LOG = []


def ls(fun, x0, *a, **k):
    t = time.perf_counter()
    f0 = np.asarray(fun(x0))
    s = _ls(fun, x0, *a, **k)
    LOG.append((len(x0), 0.5 * float(f0 @ f0), s.cost, s.nfev, s.status,
                float(np.max(np.abs(s.x - x0))), float(s.optimality),
                time.perf_counter() - t, np.round(s.x, 4), getattr(s, "active_mask", None)))
    return s


scipy.optimize.least_squares = ls
effect = sys.argv[1]
kw = json.loads(sys.argv[2]) if len(sys.argv) > 2 else {}
name = "diagnosis_200hz_10_cycles"
warm = real_rate_records(name, effect, warm=True)
D.diagnose(warm, warm, max_steps=1, max_nfev=2, top=1)
LOG.clear()
recs = real_rate_records(name, effect)
t0 = time.perf_counter()
d = D.diagnose([recs[0]], [recs[1]], **kw)
print(f"{effect}: {time.perf_counter() - t0:.1f} s, added {list(d.added)}")
for row in LOG:
    n, c0, c1, nfev, st, dx, opt, sec, x, am = row
    print(f"k={n} cost {c0:.4g} -> {c1:.4g} nfev {nfev} status {st} max|dx| {dx:.3g} "
          f"opt {opt:.3g} {sec:.1f}s x={x} active={am}")
