"""A/B: a thread pool per Jacobian (as committed) vs one persistent pool, 200 Hz bench records
(session 16).  Usage: PYTHONPATH=. python runs/s16_lead/pool_ab.py [effects...]"""
import statistics
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import liquidamp.analysis.measured.fit_objective as fo
from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

_shared = ThreadPoolExecutor(max_workers=2, thread_name_prefix="shared")


class Persistent:
    def __init__(self, max_workers=None, thread_name_prefix=""):
        pass

    def __enter__(self):
        return _shared

    def __exit__(self, *a):
        return False


effects = sys.argv[1:] or ["elastomer", "leakage", "series_compliance"]
name = "diagnosis_200hz_10_cycles"
warm = real_rate_records(name, effects[0], warm=True)[0]
diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
times = {(e, m): [] for e in effects for m in ("per_call", "persistent")}
for rep in range(3):
    for e in effects:
        recs = real_rate_records(name, e)
        for mode in (("per_call", "persistent") if rep % 2 == 0 else ("persistent", "per_call")):
            fo.ThreadPoolExecutor = ThreadPoolExecutor if mode == "per_call" else Persistent
            t = time.perf_counter()
            d = diagnose([recs[0]], [recs[1]])
            times[(e, mode)].append(time.perf_counter() - t)
for (e, m), v in times.items():
    print(e, m, "median %.3f" % statistics.median(v), [round(x, 3) for x in v])
