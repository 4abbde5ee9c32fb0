"""Wall time and least-squares fits of every refit and restart of one 200 Hz bench effect's
default diagnosis, by candidate.

PYTHONPATH=. python runs/s9_bench200/cost.py EFFECT [CASE]
"""
import collections
import sys
import time

import liquidamp.analysis.measured.diagnosis as D
import liquidamp.analysis.measured.diagnosis_select as DS
from liquidamp.analysis.bench_diagnosis import real_rate_records

T = collections.Counter()
N = collections.Counter()


def wrap(mod, name, key):
    f = getattr(mod, name)

    def w(*a, **k):
        t = time.perf_counter()
        try:
            return f(*a, **k)
        finally:
            T[(name, key(a))] += time.perf_counter() - t
            N[(name, key(a))] += 1
    setattr(mod, name, w)


wrap(D, "_refit", lambda a: a[0].effect)
wrap(DS, "_refit", lambda a: a[0].effect)
wrap(D, "_restart", lambda a: "+".join(e.name for e in a[0].effects) or "-")
wrap(D, "_screen", lambda a: "screen")
wrap(D, "_device_round", lambda a: "device")
effect = sys.argv[1]
name = sys.argv[2] if len(sys.argv) > 2 else "diagnosis_200hz_10_cycles"
warm = real_rate_records(name, effect, warm=True)
D.diagnose(warm, warm, max_steps=1, max_nfev=2, top=1)
T.clear()
N.clear()
recs = real_rate_records(name, effect)
t0 = time.perf_counter()
d = D.diagnose([recs[0]], [recs[1]])
print(f"{effect}: {time.perf_counter() - t0:.1f} s, added {list(d.added)}")
for k, v in sorted(T.items(), key=lambda kv: -kv[1]):
    print(f"  {k[0]:14s} {k[1]:50s} {v:6.1f} s  x{N[k]}")
