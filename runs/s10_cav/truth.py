"""The cavitation bench records: the truth's NRMSE on each (conditioned) record, its route.

PYTHONPATH=. python runs/s10_cav/truth.py [EFFECT]
"""
import sys
import time

import numpy as np

from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.fit_objective import predict
from liquidamp.device import preset
from liquidamp.device.effects import make_effect

CASE = "diagnosis_200hz_10_cycles"
effect = sys.argv[1] if len(sys.argv) > 1 else "cavitation"
t0 = time.perf_counter()
recs = real_rate_records(CASE, effect)
print(f"records made in {time.perf_counter() - t0:.2f} s")
truth = make_effect(effect, **REAL_RATE_RECORDS[CASE][-1][effect])
for raw in recs:
    rec = condition(raw)[0]
    resp = []
    t0 = time.perf_counter()
    (f,) = predict("full", preset("paper_calibrated"), (truth,), [rec], responses=resp)
    dt = time.perf_counter() - t0
    e = f - rec.force
    nrmse = np.sqrt(np.mean(e ** 2)) / np.sqrt(np.mean((rec.force - rec.force.mean()) ** 2))
    # the noise floor: load-cell noise 1 N over the conditioned force's RMS
    floor = 1.0 / np.sqrt(np.mean((rec.force - rec.force.mean()) ** 2))
    print(f"{rec.label}: f {rec.frequency:.2f} Hz, NRMSE {nrmse:.5f} (1 N noise / RMS "
          f"{floor:.5f}), route {resp[0].solver_stats.get('route')}, {dt:.2f} s, "
          f"warnings {resp[0].warnings}")
    # the first cycles against the last: is the record stationary?
    n = rec.force.size
    k = int(round(n / (rec.frequency * (rec.time[-1] - rec.time[0]) + 1e-9)))
    print(f"   residual RMS first/last cycle: {np.sqrt(np.mean(e[:k] ** 2)):.3f} / "
          f"{np.sqrt(np.mean(e[-k:] ** 2)):.3f} N")
