"""One sweep record's inerter-start baseline and one candidate's refit from several starts:
as the loop does it (the baseline's air), and with the confounded partner (the air ratios)
back at the start's value.

PYTHONPATH=. python runs/s11_inerter/probe.py ID EFFECT
"""
import sys
import time
from pathlib import Path

import liquidamp.analysis.measured.diagnosis as D
from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.class_revisit import fluid_alternatives
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.diagnosis_evidence import score
from liquidamp.analysis.measured.diagnosis_fits import _refit
from liquidamp.analysis.measured.diagnosis_options import DiagnoseOptions, march_options
from liquidamp.device import preset

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "s10_unseen"))
import sweep  # noqa: E402

rid, eff = sys.argv[1], sys.argv[2]
cal, val = sweep.records(rid)
config = DiagnoseOptions.from_keywords(None)
bud = config.budget
kw = config.conditioning.keywords()
cal = condition(cal, **kw)[0]
val = condition(val, **kw)[0]
options = march_options(None, (cal, val))
p0 = preset("paper_initial")
label, kws = next((lab, k) for lab, k in fluid_alternatives(
    type("B", (), {"class_starts": (type("S", (), {"name": "fluid", "sized": False})(),),
                   "calibration": (cal,)})(), {"current": type("C", (), {
                       "nrmse_calibration": 1.0})()}, 0.0, p0) if "inerter" in lab)
t0 = time.perf_counter()
base = calibrate((cal,), validate=(val,), options=options, max_nfev=bud.max_nfev,
                 preroll=bud.preroll, tol=bud.tol, warn=False, **kws)
print(label, f"{time.perf_counter() - t0:.1f} s", base.status, "cal", base.nrmse_calibration,
      "val", base.nrmse_validation, {k: round(v, 4) for k, v in base.values.items()})
cand, change = score(eff, base, options, bud.preroll)
print("score", cand.score, cand.estimate)
for tag, cur in (("as the loop", base),
                 ("air at start", D.dataclasses.replace(base, spec=base.spec.with_values(
                     {"inv_gamma1": 1.0, "inv_gamma2": 1.0})))):
    t0 = time.perf_counter()
    r = _refit(cand, change, cur, (val,), options, bud.preroll, bud.max_nfev, bud.tol, "auto")
    print(tag, f"{time.perf_counter() - t0:.1f} s", r.status, "cal", r.nrmse_calibration,
          "val", r.nrmse_validation, {k: f"{v:.4g}" for k, v in r.values.items()})

# the confounded partner held at the start's value, then released
held = D.dataclasses.replace(base, spec=D.FitSpec(tuple(
    p.replace(value=1.0, vary=False) if p.name in ("inv_gamma1", "inv_gamma2") else p
    for p in base.spec.parameters)))
t0 = time.perf_counter()
r = _refit(cand, change, held, (val,), options, bud.preroll, bud.max_nfev, bud.tol, "auto")
print("air held at start", f"{time.perf_counter() - t0:.1f} s", r.status, "cal",
      r.nrmse_calibration, "val", r.nrmse_validation,
      {k: f"{v:.4g}" for k, v in r.values.items()})
spec = D.FitSpec(tuple(p.replace(vary=True) if p.name in ("inv_gamma1", "inv_gamma2") else p
                       for p in r.spec.parameters))
t0 = time.perf_counter()
r2 = calibrate(r.calibration, model=r.model, params=r.start_params, effects=r.effects,
               spec=spec.with_values(r.values), validate=(val,), options=options,
               start="spec", max_nfev=bud.max_nfev, preroll=bud.preroll, tol=bud.tol,
               warn=False, sizing="auto")
print("then released", f"{time.perf_counter() - t0:.1f} s", r2.status, "cal",
      r2.nrmse_calibration, "val", r2.nrmse_validation,
      {k: f"{v:.4g}" for k, v in r2.values.items()})
