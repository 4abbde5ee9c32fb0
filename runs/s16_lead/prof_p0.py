"""Profile the pressurised-device diagnosis of tests/analysis/measured/test_selection_rule.py
(168 s in the suite; session 16).  Usage: PYTHONPATH=. python runs/s16_lead/prof_p0.py [OUT]"""
import cProfile
import pstats
import sys
import time

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.synthetic import synthetic_record

kw = dict(preset="paper_calibrated", multipliers={"p0": 8.0}, cycles=3,
          effects={"force_offset": {"offset_N": 40.0}})
cal = synthetic_record(frequency=3.0, amplitude=0.003, seed=93, **kw)
val = synthetic_record(frequency=4.5, amplitude=0.002, seed=193, **kw)
out = sys.argv[1] if len(sys.argv) > 1 else "/tmp/prof_p0.prof"
pr = cProfile.Profile()
t = time.perf_counter()
pr.enable()
d = diagnose([cal], [val], max_steps=1, top=1, max_nfev=40)
pr.disable()
print("seconds", time.perf_counter() - t, d.added, [s.effect for s in d.device_steps])
print(d.summary()[:2000])
pr.dump_stats(out)
st = pstats.Stats(out)
st.sort_stats("cumulative").print_stats(60)
st.sort_stats("tottime").print_stats(25)
