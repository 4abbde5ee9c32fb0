"""Tabulate default-diagnosis JSON results: python runs/tabulate.py DIR [DIR2]."""
import json
import sys
from pathlib import Path

# case -> (expected first effect(s), [(effect, key, truth)], kind)
CASES = {
    "d01": (("asymmetric_loss",), [("asymmetric_loss", "rebound_ratio", 1.8)], "effect"),
    "d02": (("relief_valve",), [("relief_valve", "cracking_pressure_Pa", 9e5)], "effect"),
    "d03": (("elastomer",), [("elastomer", "parallel_stiffness_N_per_m", 2e4)], "effect"),
    "d04": (("end_stops",), [("end_stops", "clearance_m", 3.2e-3)], "effect"),
    "d05": (("backlash",), [("freeplay", "gap_m", 4e-4), ("coulomb_friction", "force_N", 40.0),
                            ("smooth_friction", "force_N", 40.0)], "effect"),
    "d11": (("smooth_friction", "coulomb_friction", "leakage"),
            [("smooth_friction", "force_N", 20.0), ("coulomb_friction", "force_N", 20.0),
             ("leakage", "coefficient_m3_per_s_Pa", 1.2e-11)], "effect"),
    "d12": ((), [], "null"),
    "d07": ((), [], "drift"),
    "d08": (("bypass_groove",), [("bypass_groove", "depth", 0.4),
                                 ("bypass_groove", "half_width_m", 1.5e-3)], "effect"),
    "d06": ((), [], "info"), "d09": ((), [], "info"),
    # the MR record: field_yield first (the field class), dp_y1 and dp_y0 within 30 %, held
    # out at most 0.20 and at most half the fit without the voltage's
    "d10": (("field_yield",), [("field_yield", "yield_pressure_per_input", 2.2e5),
                               ("field_yield", "yield_pressure_Pa", 6e4)], "field"),
    "fd_steady": ((), [], "fd"), "fd_full": ((), [], "fd"),
}


def row(d, tag):
    p = d / f"{tag}.json"
    t = (d / f"{tag}.time").read_text().strip() if (d / f"{tag}.time").exists() else "?"
    if not p.exists():
        ef = d / f"{tag}.err"
        err = ef.read_text().strip().splitlines() if ef.exists() else []
        return {"case": tag, "error": (err[-1] if err else "no output")[:200], "time": t}
    j = json.loads(p.read_text())
    eff = j["final"]["parameters"].get("effects", {})
    added = [s["effect"] for s in j["steps"]]
    keys = []
    for e, k, truth in CASES[tag][1]:
        if e in eff and k in eff[e]:
            v = eff[e][k]
            keys.append(f"{e}.{k}={v:.3g} ({(v / truth - 1):+.0%})")
    before = j["baseline"]["heldout_records"]
    after = j["heldout"]
    pooled = (f" (pooled {j['baseline']['nrmse']['validation']:.4g}->"
              f"{j['final']['nrmse']['validation']:.4g})") if len(after) > 1 else ""
    ho = "; ".join(f"{k.split('_')[-1] if tag.startswith('d') else k}: "
                   f"{before[k]:.4g}->{after[k]:.4g}" for k in after)
    refs = "; ".join(f"{n}: " + ",".join(f"{r['nrmse']:.3g}" for r in v["records"]
                                         if r["role"] == "validation")
                     for n, v in j["reference_models"].items())
    exp, _, kind = CASES[tag]
    halved = all(after[k] <= 0.5 * before[k] for k in after)
    if kind == "effect":
        ok = bool(added) and added[0] in exp and halved
    elif kind == "null":
        ok = not added
    elif kind == "drift":
        first = j["summary"].splitlines()[0]
        bound = [k for k in j["final"]["parameter_flags"].get("at_bound", {})
                 if "." in k and k.split(".")[0] in added]
        ok = not bound and ("NON-STATIONARY" in first or "UNEXPLAINED" in first)
    elif kind == "field":
        wi = j.get("without_input") or {}
        near = [abs(eff.get(e, {}).get(k, 0.0) / t - 1.0) <= 0.3 for e, k, t in CASES[tag][1]]
        dc = j["baseline"].get("device_class") or {}
        ok = ((dc.get("chosen") if isinstance(dc, dict) else dc) == "field" and all(near)
              and j["final"]["nrmse"]["validation"] <= 0.20
              and j["final"]["nrmse"]["validation"] <= 0.5 * wi.get("nrmse_validation", 0.0))
        ho += f" (without the {wi.get('input')}: {wi.get('nrmse_validation', float('nan')):.3g})"
    elif kind == "fd":
        allfx = set(eff)
        ok = (j["final"]["nrmse"]["validation"] <= 0.13
              and any("friction" in e for e in allfx)
              and ("freeplay" in allfx or "backlash" in added))
    else:
        ok = None
    cls = (j["baseline"].get("device_class") or {})
    cls = cls.get("chosen") if isinstance(cls, dict) else cls
    return {"case": tag, "ok": ok, "class": cls, "added": ",".join(added) or "-",
            "key": "; ".join(keys) or "-", "heldout": ho + pooled, "refs": refs,
            "first": j["summary"].splitlines()[0][:160], "time": t}


def main():
    for d in map(Path, sys.argv[1:]):
        print(f"## {d}")
        print("| case | ok | class | added (order) | key parameter vs truth | "
              "held-out before->after | references held out | first summary line | wall s |")
        print("|---|---|---|---|---|---|---|---|---|")
        for tag in CASES:
            if not (d / f"{tag}.err").exists():
                continue
            r = row(d, tag)
            if "error" in r:
                print(f"| {tag} | ERROR | | | | | | {r['error']} | {r['time'][:5]} |")
                continue
            print(f"| {tag} | {r['ok']} | {r['class']} | {r['added']} | {r['key']} | "
                  f"{r['heldout']} | {r['refs']} | {r['first']} | {float(r['time']):.0f} |")


if __name__ == "__main__":
    main()
