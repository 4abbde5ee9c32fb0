"""Profile one bench effect: python runs/s8_speed/prof_one.py CASE EFFECT [profile_out]."""
import cProfile, pstats, sys, time
from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS
from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.synthetic import synthetic_record

name, effect = sys.argv[1], sys.argv[2]
rate, duration, cycles, (fc, yc), (fv, yv), truths = REAL_RATE_RECORDS[name]
k = list(truths).index(effect)
truth = truths[effect]
warm = synthetic_record(preset="paper_calibrated", frequency=fc, amplitude=yc, cycles=2,
                        sampling_rate=200.0, seed=699, effects={effect: truth})
diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
recs = []
for i, (f, y) in enumerate(((fc, yc), (fv, yv))):
    n_cyc = duration * f if duration else cycles
    recs.append(synthetic_record(preset="paper_calibrated", frequency=f, amplitude=y,
                                 cycles=n_cyc, sampling_rate=rate,
                                 seed=700 + 10 * k + i, effects={effect: truth}))
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
st = pstats.Stats(pr); st.sort_stats("cumulative").print_stats(45)
st.sort_stats("tottime").print_stats(25)
