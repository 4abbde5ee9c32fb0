"""Default diagnosis of one 200 Hz bench effect, its JSON written beside the timing.

PYTHONPATH=. python runs/s9_bench200/one.py EFFECT OUT.json [CASE]
"""
import json
import sys
import time

from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

effect, out = sys.argv[1], sys.argv[2]
name = sys.argv[3] if len(sys.argv) > 3 else "diagnosis_200hz_10_cycles"
warm = real_rate_records(name, effect, warm=True)
diagnose(warm, warm, max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
t0 = time.perf_counter()
d = diagnose([recs[0]], [recs[1]])
sec = time.perf_counter() - t0
truth = REAL_RATE_RECORDS[name][-1][effect]
fitted = next((s.parameters for s in d.steps if s.effect == effect), None)
err = None if fitted is None else max(abs(fitted[k] / v - 1.0) for k, v in truth.items())
print(f"{effect}: {sec:.1f} s, added {list(d.added)}, parameter error {err}")
print(d.summary())
for w in d.warnings:
    print("warning:", w)
dd = d.as_dict()
dd["seconds"] = sec
dd["parameter_error"] = err
with open(out, "w") as f:
    json.dump(dd, f, indent=1, default=str)
