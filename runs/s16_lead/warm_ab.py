"""A/B: record simulations from a warm start marching at least 4 periods (min_cycles 3, as
before) vs 3 (WARM_MIN_CYCLES = 1), 200 Hz bench records (session 16).
Usage: PYTHONPATH=. python runs/s16_lead/warm_ab.py [effects...]"""
import statistics
import sys
import time

import liquidamp.analysis.measured.record_model as rm
from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

effects = sys.argv[1:] or ["elastomer", "leakage", "series_compliance"]
name = "diagnosis_200hz_10_cycles"
warm = real_rate_records(name, effects[0], warm=True)[0]
diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
modes = {"min3": 3, "min1": 1}
times = {(e, m): [] for e in effects for m in modes}
result = {}
for rep in range(3):
    for e in effects:
        recs = real_rate_records(name, e)
        order = list(modes) if rep % 2 == 0 else list(modes)[::-1]
        for mode in order:
            rm.WARM_MIN_CYCLES = modes[mode]
            t = time.perf_counter()
            d = diagnose([recs[0]], [recs[1]])
            times[(e, mode)].append(time.perf_counter() - t)
            truth = REAL_RATE_RECORDS[name][5][e]
            fitted = next((s.parameters for s in d.steps if s.effect == e), None)
            err = None if fitted is None else max(abs(fitted[k] / v - 1) for k, v in truth.items())
            result[(e, mode)] = (d.added, err, d.final.nrmse_validation)
for (e, m), v in times.items():
    print(e, m, "median %.3f" % statistics.median(v), [round(x, 3) for x in v], result[(e, m)])
