"""Kernel time against wall time of one 200 Hz bench diagnosis (all threads):
python runs/s18_lead/kernel_share.py EFFECT [REPEATS]."""
import statistics
import sys
import time

import liquidamp.coupled.fast as fast
from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

name = "diagnosis_200hz_10_cycles"
effect = sys.argv[1]
reps = int(sys.argv[2]) if len(sys.argv) > 2 else 3
warm = real_rate_records(name, effect, warm=True)[0]
diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
orig = fast._run
acc = []
spans = []


def union(sp):
    sp = sorted(sp)
    tot, end = 0.0, -1e300
    for a, b in sp:
        if b > end:
            tot += b - max(a, end)
            end = b
    return tot



def run(*a, **k):
    t = time.perf_counter()
    try:
        return orig(*a, **k)
    finally:
        acc.append(time.perf_counter() - t)
        spans.append((t, time.perf_counter()))


fast._run = run
walls = []
for _ in range(reps):
    acc.clear()
    spans.clear()
    t = time.perf_counter()
    d = diagnose([recs[0]], [recs[1]])
    walls.append(time.perf_counter() - t)
    print(f"wall {walls[-1]:.3f} s, kernel calls {len(acc)}, kernel sum {sum(acc):.3f} s "
          f"(mean {1e3 * sum(acc) / len(acc):.2f} ms), some kernel running {union(spans):.3f} s, "
          f"added {d.added}")
print("median wall", statistics.median(walls))
