import warnings; warnings.simplefilter("ignore")
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.conditioning import condition
truth={"series_compliance": {"stiffness_N_per_m": 5e5}}
cal = synthetic_record(preset="paper_calibrated", frequency=3.0, amplitude=0.003, cycles=3, seed=54, effects=truth)
val = synthetic_record(preset="paper_calibrated", frequency=4.0, amplitude=0.002, cycles=3, seed=154, effects=truth)
cal=condition(cal)[0]; val=condition(val)[0]
res=calibrate([cal], validate=[val], warn=False, max_nfev=40, tol=1e-5)
print(res.summary()); print(res.start.get("held_out_note"))
for o in res.class_starts: print(o.name, o.nrmse_calibration, o.nrmse_validation, o.bic, o.continued, o.admissible)
