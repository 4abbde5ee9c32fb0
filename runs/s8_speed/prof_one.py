"""Profile one bench effect: python runs/s8_speed/prof_one.py CASE EFFECT [profile_out]."""
import cProfile
import pstats
import sys
import time

from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

name, effect = sys.argv[1], sys.argv[2]
warm = real_rate_records(name, effect, warm=True)  # compile or load the kernels first
diagnose(warm, warm, max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
pr = cProfile.Profile()
t0 = time.perf_counter()
pr.enable()
d = diagnose([recs[0]], [recs[1]])
pr.disable()
print("seconds", time.perf_counter() - t0, "added", list(d.added))
for s in d.steps:
    print(s.effect, s.parameters)
if len(sys.argv) > 3:
    pr.dump_stats(sys.argv[3])
st = pstats.Stats(pr)
st.sort_stats("cumulative").print_stats(45)
st.sort_stats("tottime").print_stats(25)
