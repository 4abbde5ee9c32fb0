"""The test fixture's friction-damper diagnosis (sizing preset, max_steps 4), printed."""
import sys
import time
import warnings

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.records import read_record

D = "/work/shared/data/friction-damper-backlash/"
warnings.simplefilter("ignore")
t = time.time()
d = diagnose([read_record(D + "brfd30_0.5Hz_0.5in_steady.csv")],
             [read_record(D + v) for v in ("brfd30_1Hz_0.5in_steady.csv",
                                           "brfd30_0.25Hz_0.5in_steady.csv")],
             sizing="preset", max_steps=int(sys.argv[1]) if len(sys.argv) > 1 else 4)
print(d.summary())
for s in d.steps:
    print(s.effect, s.tie, s.nrmse_validation)
print(d.warnings)
print(time.time() - t)
