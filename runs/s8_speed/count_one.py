"""Count model runs and integrator steps of one bench effect's diagnosis.

PYTHONPATH=. python runs/s8_speed/count_one.py CASE EFFECT
"""
import collections
import sys
import time

import liquidamp.coupled.fast as F
from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

C = collections.Counter()
_orig_run = F._run
def _run(options, args, out, info):
    t = time.perf_counter()
    x, rerun = _orig_run(options, args, out, info)
    spec = args[0]
    key = f"n{int(spec[1])}_ic{int(spec[4])}_ifp{int(spec[5])}_an{int(spec[11])}"
    C[key + ":calls"] += 1
    C[key + ":steps"] += int(info[3])
    C[key + ":explicit"] += int(info[8])
    C[key + ":rerun"] += int(rerun)
    C[key + ":cycles"] += int(info[5])
    C[key + ":seconds"] += time.perf_counter() - t
    return x, rerun
F._run = _run

name, effect = sys.argv[1], sys.argv[2]
warm = real_rate_records(name, effect, warm=True)  # compile or load the kernels first
diagnose(warm, warm, max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
C.clear()
t0 = time.perf_counter()
d = diagnose([recs[0]], [recs[1]])
print("seconds", round(time.perf_counter() - t0, 2), "added", list(d.added))
for s in d.steps:
    print(" ", s.effect, s.parameters)
for key in sorted(C):
    print(key, round(C[key], 3) if isinstance(C[key], float) else C[key])
