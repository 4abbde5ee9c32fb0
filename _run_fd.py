import sys, time, warnings
warnings.simplefilter("ignore")
from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.records import read_record
D="/work/shared/data/friction-damper-backlash/"
cal=read_record(D+"brfd30_0.5Hz_0.5in_steady.csv")
val=[read_record(D+f"brfd30_{f}_0.5in_steady.csv") for f in ("1Hz","0.25Hz")]
t=time.time()
res=calibrate([cal], validate=val, warn=False)
print(time.time()-t)
print(res.summary())
print(res)
import json; print(json.dumps(res.start["loop"], indent=0)[:600])
for o in res.class_starts: print(o.describe(), o.bic, o.nfev, o.reason)
