"""Profile the default diagnosis of one 200 Hz bench record:
python runs/s18_lead/prof200.py EFFECT [OUT.prof]."""
import cProfile
import pstats
import sys
import time

from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

name = "diagnosis_200hz_10_cycles"
effect = sys.argv[1]
warm = real_rate_records(name, effect, warm=True)[0]
diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
t = time.perf_counter()
d = diagnose([recs[0]], [recs[1]])
print("plain", time.perf_counter() - t, d.added)
pr = cProfile.Profile()
pr.enable()
d = diagnose([recs[0]], [recs[1]])
pr.disable()
out = sys.argv[2] if len(sys.argv) > 2 else f"/tmp/prof_{effect}.prof"
pr.dump_stats(out)
st = pstats.Stats(out)
st.sort_stats("cumulative").print_stats(45)
st.sort_stats("tottime").print_stats(25)
