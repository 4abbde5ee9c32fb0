import sys, warnings, time
warnings.simplefilter("ignore")
import liquidamp.analysis.measured.device_class as dc
#
from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.records import read_record
D="/work/shared/data/friction-damper-backlash/"
cal=read_record(D+"brfd30_0.5Hz_0.5in_steady.csv")
val=[read_record(D+f"brfd30_{f}_0.5in_steady.csv") for f in ("1Hz","0.25Hz")]
t=time.time()
d=diagnose([cal], val)
print(sys.argv[1], time.time()-t, d.added, d.baseline.nrmse_validation, [s.nrmse_validation for s in d.steps], d.nrmse_raw)
print(d.baseline.summary())
print(d.stop_reason)
