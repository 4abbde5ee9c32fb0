"""The end_stops case of tests/analysis/measured/test_class_alternatives.py, timed.

``PYTHONPATH=. python runs/s13_speed/endstops_case.py [end_stops|elastomer] [--trace]``:
the test's records (cached in /tmp/s13_speed_records_CASE.pkl), ``diagnose([cal], [val],
max_steps=1)``, its wall time and answers; with ``--trace`` every Newton shooting is timed
with the model's effects and the caller (score test or fit).
"""

import pickle
import sys
import time
import traceback
from pathlib import Path

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.synthetic import synthetic_record

_STOPS = {"end_stops": {"stiffness_N_per_m": 2e6, "clearance_m": 0.0032,
                        "damping_N_s_per_m": 300.0}}
_ELASTOMER = {"elastomer": {"parallel_stiffness_N_per_m": 2e4, "branch_stiffness_N_per_m": 4e4,
                            "branch_damping_N_s_per_m": 1800.0}}


def records(case):
    path = Path(f"/tmp/s13_speed_records_{case}.pkl")
    if path.exists():
        return pickle.loads(path.read_bytes())
    if case == "end_stops":
        common = dict(preset="reference", effects=_STOPS, cycles=5, force_noise=1.5,
                      multipliers=(("inv_gamma1", 1.06), ("inv_gamma2", 0.9), ("c1", 0.95),
                                   ("c2", 1.1), ("S_t", 0.9)))
        cal = synthetic_record(frequency=1.5, amplitude=0.0035, seed=41, **common)
        val = synthetic_record(frequency=2.5, amplitude=0.00335, seed=42, **common)
    else:
        common = dict(preset="device_b", effects=_ELASTOMER, cycles=5, force_noise=1.5,
                      multipliers=(("inv_gamma1", 0.95), ("inv_gamma2", 1.08), ("c1", 1.1),
                                   ("c2", 0.95), ("S_t", 1.2)))
        cal = synthetic_record(frequency=2.0, amplitude=0.0035, seed=43, **common)
        val = synthetic_record(frequency=5.0, amplitude=0.0018, seed=44, **common)
    path.write_bytes(pickle.dumps((cal, val)))
    return cal, val


def trace():
    import liquidamp.coupled.periodic as per

    orig = per._shoot

    def shoot(rig, *a, **k):
        t0 = time.perf_counter()
        try:
            return orig(rig, *a, **k)
        finally:
            st = [f.name for f in traceback.extract_stack()]
            who = next((n for n in ("screened", "score", "_refit", "_restart", "calibrate")
                        if n in st), "?")
            eff = [e.name for e in getattr(rig.model, "effects", ())]
            print(f"shoot {time.perf_counter() - t0:6.2f} s  via {who}  effects {eff}  "
                  f"S_t {rig.params.S_t:.3g}  f {1 / rig.stroke.period:.3g} Hz  "
                  f"{'screened' in st}", flush=True)

    per._shoot = shoot

    import liquidamp.analysis.measured.class_revisit as cr
    import liquidamp.analysis.measured.diagnosis as dg

    orig_screened = cr.screened
    seen = []

    def screened(run, base2, first, sel):
        seen.append(base2)
        try:
            Path(f"/tmp/s13_speed_base2_{len(seen)}.pkl").write_bytes(
                pickle.dumps((run["current"], base2)))
        except Exception as exc:  # noqa: BLE001
            print("not pickled", exc)
        t0 = time.perf_counter()
        out = orig_screened(run, base2, first, sel)
        print(f"screened {len(seen)} {time.perf_counter() - t0:.1f} s: {out[:80]}", flush=True)
        return out

    cr.screened = screened
    orig_score = dg.score

    def score(name, result, options, preroll):
        t0 = time.perf_counter()
        cand, change = orig_score(name, result, options, preroll)
        print(f"  score {name} {time.perf_counter() - t0:.2f} s {cand.score:.3g} "
              f"{cand.note[:100]}", flush=True)
        return cand, change

    dg.score = score


if __name__ == "__main__":
    case = sys.argv[1] if len(sys.argv) > 1 else "end_stops"
    cal, val = records(case)
    if "--trace" in sys.argv:
        trace()
    t0 = time.perf_counter()
    d = diagnose([cal], [val], max_steps=1)
    print(f"wall {time.perf_counter() - t0:.1f} s")
    print("class", d.baseline.device_class, "added", d.added,
          "params", d.steps[0].parameters if d.steps else {},
          "val", d.baseline.nrmse_validation, "->", d.final.nrmse_validation)
    for w in d.warnings:
        print("W:", w[:400])
