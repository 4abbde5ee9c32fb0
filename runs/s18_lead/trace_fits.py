"""Trace every calibrate() of one 200 Hz bench diagnosis:
python runs/s18_lead/trace_fits.py EFFECT."""
import sys
import time
import traceback

import liquidamp.analysis.measured.calibration as cal
import liquidamp.analysis.measured.record_model as rm
from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

name = "diagnosis_200hz_10_cycles"
effect = sys.argv[1]
warm = real_rate_records(name, effect, warm=True)[0]
diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
orig = cal.calibrate
sims = [0]
osim = rm.simulate_record


def sim(*a, **k):
    sims[0] += 1
    return osim(*a, **k)


rm.simulate_record = sim
depth = [0]


def traced(*a, **k):
    caller = [f.name for f in traceback.extract_stack(limit=6)[:-1]]
    s0 = sims[0]
    t = time.perf_counter()
    depth[0] += 1
    try:
        r = orig(*a, **k)
    finally:
        depth[0] -= 1
    dt = time.perf_counter() - t
    spec = k.get("spec", a[1] if len(a) > 1 else None)
    print(f"{'  ' * depth[0]}calibrate {dt:6.3f} s  sims(main) {sims[0] - s0:4d}  nfev "
          f"{getattr(r, 'nfev', '?')} njev {getattr(r, 'njev', '?')} free "
          f"{getattr(r, 'names', getattr(spec, 'names', '?'))} <- {caller[-3:]}")
    return r


cal.calibrate = traced
for mod in list(sys.modules.values()):
    if getattr(mod, "__name__", "").startswith("liquidamp.analysis.measured") and \
            getattr(mod, "calibrate", None) is orig:
        mod.calibrate = traced
t = time.perf_counter()
d = diagnose([recs[0]], [recs[1]])
print("total", time.perf_counter() - t, d.added, "main-thread sims", sims[0])
