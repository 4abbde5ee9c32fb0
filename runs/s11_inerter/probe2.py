"""Refits of one candidate on the inerter-start baseline from chosen starts (multipliers and
the effect's parameters): PYTHONPATH=. python runs/s11_inerter/probe2.py ID EFFECT JSON..."""
import json
import sys
import time

sys.argv, extra = sys.argv[:3], sys.argv[3:]
exec(open("runs/s11_inerter/probe.py").read().split("for tag, cur in")[0])  # noqa: S102
from liquidamp.device.effects import make_effect  # noqa: E402

for js in extra:
    vals = json.loads(js)
    how = vals.pop("_start", "spec")
    effs = tuple(e.replace(**{k.split(".", 1)[1]: v for k, v in vals.items()
                              if k.startswith(e.name + ".")}) for e in change.effects)
    spec = base.spec
    for e in effs:
        spec = spec.with_effect(e)
    spec = spec.with_values(vals)
    t0 = time.perf_counter()
    r = calibrate(base.calibration, model=base.model, params=base.start_params, effects=effs,
                  spec=spec, validate=(val,), options=options, start=how,
                  max_nfev=bud.max_nfev, preroll=bud.preroll, tol=bud.tol, warn=False,
                  sizing="auto")
    print(js, f"{time.perf_counter() - t0:.1f} s", r.status, "cal", r.nrmse_calibration,
          "val", r.nrmse_validation, {k: f"{v:.4g}" for k, v in r.values.items()})
