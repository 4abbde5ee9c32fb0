"""The candidate scored and refitted from the baseline refitted with its confounded partner
(the air ratios) held at the start's value: PYTHONPATH=. python runs/s11_inerter/probe3.py ID
EFFECT"""
import sys
import time

exec(open("runs/s11_inerter/probe.py").read().split("for tag, cur in")[0])  # noqa: S102

AIR = ("inv_gamma1", "inv_gamma2")
spec_h = D.FitSpec(tuple(p.replace(value=1.0, vary=False) if p.name in AIR else p
                         for p in base.spec.parameters))
t0 = time.perf_counter()
bh = calibrate(base.calibration, model=base.model, params=base.start_params,
               effects=base.effects, spec=spec_h, validate=(val,), options=options,
               start="spec", max_nfev=bud.max_nfev, preroll=bud.preroll, tol=bud.tol,
               warn=False, sizing="auto")
print("held baseline", f"{time.perf_counter() - t0:.1f} s", bh.status, "cal",
      bh.nrmse_calibration, "val", bh.nrmse_validation,
      {k: f"{v:.4g}" for k, v in bh.values.items()})
c2, ch2 = score(eff, bh, options, bud.preroll)
print("score there", c2.score, c2.estimate)
for tag, cur in (("refit, air held", bh),
                 ("refit, air freed from 1", D.dataclasses.replace(bh, spec=D.FitSpec(tuple(
                     p.replace(vary=True) if p.name in AIR else p
                     for p in bh.spec.parameters))))):
    t0 = time.perf_counter()
    r = _refit(c2, ch2, cur, (val,), options, bud.preroll, bud.max_nfev, bud.tol, "auto")
    print(tag, f"{time.perf_counter() - t0:.1f} s", r.status, "cal", r.nrmse_calibration,
          "val", r.nrmse_validation, {k: f"{v:.4g}" for k, v in r.values.items()})
