import warnings; warnings.simplefilter("ignore")
import sys; sys.path.insert(0,"tests/analysis/measured")
from test_diagnosis_composition import _records, CASES, ALL
from liquidamp.analysis.measured.diagnosis import diagnose
cal,val=_records(CASES["elastomer"][0], 91)
d = diagnose([cal], [val], top=1, max_nfev=40, max_steps=2, candidates=ALL)
print(d.added, d.stop_reason)
print(d.baseline.summary()[:600])
for s in d.steps: print(s.effect, s.nrmse_calibration, s.nrmse_validation)
print(d.noise_nrmse)
