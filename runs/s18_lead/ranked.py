"""Print each screen's ranking of one 200 Hz bench diagnosis:
python runs/s18_lead/ranked.py EFFECT."""
import sys
import time

import liquidamp.analysis.measured.diagnosis as dg
from liquidamp.analysis.bench_diagnosis import real_rate_records

name = "diagnosis_200hz_10_cycles"
effect = sys.argv[1]
orig = dg._screen


def screen(*a, **k):
    t = time.perf_counter()
    out = orig(*a, **k)
    ranked, probes, scored, queue, extra, n_now = out
    print(f"screen {time.perf_counter() - t:.3f} s n_eff {n_now:.4g}; queue",
          [c.effect for c in queue], "extra", [c.effect for c in extra])
    for c in ranked[:8]:
        k = len(probes[c.effect].free) if c.effect in probes else '-'
        print(f"   {c.effect:22s} {c.score:.4f} k={k} {c.note[:90]}")
    return out


dg._screen = screen
warm = real_rate_records(name, effect, warm=True)[0]
dg.diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
print("---- timed")
t = time.perf_counter()
d = dg.diagnose([recs[0]], [recs[1]])
print("total", time.perf_counter() - t, d.added)
