"""Session 20: one timed default diagnosis of the bench's broadband field-input records
(liquidamp.analysis.bench_diagnosis.field_record, seeds 801/802, 10 s at 2 kHz), as the
bench case diagnosis_field_input runs it, without its repeats; run under PYTHONPATH=SNAP
for each code.  Prints seconds, what was added, the yield errors, held-out NRMSE, floor.
"""
import time

from liquidamp.analysis.bench_diagnosis import FIELD_DEVICE, field_record
from liquidamp.analysis.measured.diagnosis import diagnose

cal = field_record(801, 10.0, label="mr_cal")
val = field_record(802, 10.0, label="mr_val")
warm = field_record(803, 1.0, label="mr_warm")
diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
t0 = time.perf_counter()
d = diagnose([cal], [val])
s = time.perf_counter() - t0
fy = next((e for e in d.final.effects if e.name == "field_yield"), None)
err = {k: round(getattr(fy, k) / v - 1.0, 3) for k, v in FIELD_DEVICE["field_yield"].items()}
print(f"seconds {s:.1f}; added {list(d.added)}; yield errors {err}; held out "
      f"{d.final.nrmse_validation:.4g}; floors {d.noise_floors}; "
      f"{d.summary().splitlines()[0][:160]}")
