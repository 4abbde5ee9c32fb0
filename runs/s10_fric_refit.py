"""Session 10 (s10-fric): refit a saved friction-damper device on one record, predict the others.

Starts from a device file written by the default diagnosis (``liquidamp diagnose ...
--save-device DEV.toml``), optionally adds catalogue effects, refits the named parameters on
one record (conditioned as the diagnosis conditions it) and prints the NRMSE of every record
of the kind (steady or tapered), with the residual split of ``s10_fric_where.py``.

Data: Coble, Huggins, Cao, Ricles, Downey (2022), Dataset-Friction-Damper-with-Backlash
(ARTS-Laboratory), CC BY-SA 4.0 (``$LIQUIDAMP_SHARED/data/friction-damper-backlash``).

Usage::

    python runs/s10_fric_refit.py DEV.toml steady 0.5Hz \
        smooth_friction.force_N,smooth_friction.reverse_ratio,freeplay.gap_m \
        [+slip_weakening:ratio=0.1,distance_m=0.003] [fluid=0.01] [set:KEY=VALUE]
"""

from __future__ import annotations

import sys
import time
import warnings

from s10_fric_where import records, split

from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.fit_spec import FitSpec, scale_effect_bounds
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.device.effects import EFFECTS, with_effects
from liquidamp.device.models import get_model
from liquidamp.device.presets import load_device_file


def main(argv) -> None:
    """Command line (module docstring)."""
    warnings.filterwarnings("ignore")
    dev = load_device_file(argv[0])
    kind, on, keys = argv[1], argv[2], argv[3].split(",") if argv[3] != "-" else []
    effects, params, values, lag = list(dev.effects), dev.params, {}, 0.0
    for arg in argv[4:]:
        if arg.startswith("+"):
            name, _, kv = arg[1:].partition(":")
            kw = {k: float(v) for k, v in (p.split("=") for p in kv.split(",") if p)}
            effects.append(EFFECTS[name](**kw))
        elif arg.startswith("fluid="):
            s = float(arg.split("=")[1])
            params = params.scaled(c1=s, c2=s, S_t=s)
        elif arg.startswith("lag="):
            lag = float(arg.split("=")[1])
        elif arg.startswith("set:"):
            k, v = arg[4:].split("=")
            values[k] = float(v)
        elif arg.startswith("-"):
            effects = [e for e in effects if e.name != arg[1:]]
    recs = records(kind, lag)
    spec = FitSpec(())
    for e in effects:
        ks = tuple(k.split(".", 1)[1] for k in keys if k.split(".", 1)[0] == e.name)
        if ks:
            spec = spec.with_effect(e, keys=ks)
    spec = scale_effect_bounds(spec, [recs[on]])
    if values:
        spec = spec.with_values(values)
    t0 = time.time()
    if spec.names:
        val = [r for f, r in recs.items() if f != on]
        r = calibrate([recs[on]], model="full", params=params, effects=tuple(effects),
                      spec=spec, validate=val, start="spec", sizing="preset", warn=False,
                      max_nfev=120)
        params, effects = r.params, r.effects
        head = (f"{r.status} nfev {r.nfev} {time.time() - t0:.0f} s; "
                + ", ".join(f"{k} {v:.4g}" for k, v in r.values.items()))
    else:
        head = "no fit"
    print(f"{kind} fit on {on} [{' '.join(argv[4:])}]: {head}", flush=True)
    model = with_effects(get_model("full"), *effects)
    for f, rec in recs.items():
        out = simulate_record(model, params, rec)
        print(f"  {f}: NRMSE {nrmse(out.force, rec.force):.4f}; " + split(rec, out.force),
              flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
