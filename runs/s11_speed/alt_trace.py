"""Every alternative start of one default diagnosis: the model held when it is tried, its
baseline, its one-step probe and what it costs (s11-speed gate study).

    PYTHONPATH=. python runs/s11_speed/alt_trace.py CAL.csv VAL.csv
    PYTHONPATH=. python runs/s11_speed/alt_trace.py sweep RECORD_ID    # runs/s10_unseen/sweep.py

Prints, per alternative: the held model's calibration and held-out NRMSE (per record), the
alternative's baseline and its probe (after one step), whether the probe passed, seconds.
"""
import sys
import time

import liquidamp.analysis.measured.class_revisit as CR
import liquidamp.analysis.measured.diagnosis as D
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record

_orig = CR._alternative_loop


def transplant(held, base2, config):
    """The held model's effects on the alternative's device: one fit from the held effect
    values and the alternative baseline's multipliers."""
    from liquidamp.analysis.measured.calibration import calibrate
    from liquidamp.analysis.measured.fit_spec import FitSpec

    spec = FitSpec(tuple(p.replace(value=base2.values.get(p.name, p.value))
                         for p in base2.spec.parameters if p.kind == "multiplier"))
    for e in held.effects:
        keys = [n.split(".", 1)[1] for n in held.varying if n.startswith(e.name + ".")]
        spec = spec.with_effect(e, keys=keys)
    bud = config.budget
    return calibrate(base2.calibration, model=held.model, params=base2.start_params,
                     effects=held.effects, spec=spec, validate=base2.validation,
                     start="spec", sizing="preset", max_nfev=bud.max_nfev,
                     preroll=bud.preroll, tol=bud.tol, warn=False)


def fmt(res):
    h = heldout_per_record(res)
    return (f"cal {res.nrmse_calibration:.4g} val "
            + ",".join(f"{v:.4g}" for v in h.values())
            + f" k {len(res.varying)} [{','.join(e.name for e in res.effects)}]")


def _alt(base2, run, gated, loop, config):
    t0 = time.perf_counter()
    out = _orig(base2, run, gated, loop, config)
    dt = time.perf_counter() - t0
    held = run["current"]
    print(f"  held      {fmt(held)}")
    print(f"  alt base  {fmt(base2)}  start {base2.start_params.name}")
    t1 = time.perf_counter()
    try:
        tr = transplant(held, base2, config)
        print(f"  transplant {fmt(tr)}  {time.perf_counter() - t1:.1f} s  nfev {tr.nfev}")
    except Exception as exc:  # noqa: BLE001
        print(f"  transplant failed: {exc}")
    print(f"  alt final {fmt(out['current'])} steps {[s.effect for s in out['steps']]}"
          f"  passes {CR.passes(run, out, config.selection)}  {dt:.1f} s", flush=True)
    return out


CR._alternative_loop = _alt

if __name__ == "__main__":
    if sys.argv[1] == "sweep":
        sys.path.insert(0, "runs/s10_unseen")
        from sweep import records

        cal, val = records(sys.argv[2])
    else:
        from liquidamp.analysis.measured.records import read_record

        cal, val = read_record(sys.argv[1]), read_record(sys.argv[2])
    t0 = time.perf_counter()
    d = D.diagnose([cal], [val])
    print(f"wall {time.perf_counter() - t0:.1f} s; added {list(d.added)}; "
          f"held-out {d.final.nrmse_validation:.4g}; noise {d.noise_nrmse:.3g}")
