"""Side-by-side table of two bench JSON files (old = main bf75667, new = s8-speed)."""
import json
import sys
from pathlib import Path


def _error(result, effect):
    """The bench's largest relative parameter error of ``effect``, or '-'."""
    v = result.get(f"parameter_error_{effect}")
    return "-" if v is None else f"{v:.4g}"


d = Path(sys.argv[1])
for case in ("diagnosis_200hz_10_cycles", "diagnosis_3khz_20s"):
    try:
        old = json.loads((d / f"old_{case}.json").read_text())
        new = json.loads((d / f"new_{case}.json").read_text())
    except (OSError, ValueError) as exc:
        print(case, "missing", exc)
        continue
    def find(js):
        if isinstance(js, dict):
            if any(k.startswith("seconds_") for k in js):
                return js
            for v in js.values():
                r = find(v)
                if r:
                    return r
        return None
    o, n = find(old), find(new)
    loads = [(d / f"{w}_{case}.load{i}").read_text().split("load average:")[1].strip()
             for w in ("old", "new") for i in (0, 1)]
    print(f"\n### {case} (1-min/5-min/15-min load: old start {loads[0]}, old end {loads[1]}, "
          f"new start {loads[2]}, new end {loads[3]})")
    print("| effect | old s | new s | added old | added new | param. rel. error old | new |")
    print("|---|---|---|---|---|---|---|")
    eff = [k[8:] for k in o if k.startswith("seconds_")]
    so, sn = [], []
    for e in eff:
        so.append(o[f"seconds_{e}"])
        sn.append(n.get(f"seconds_{e}", float("nan")))
        print(f"| {e} | {so[-1]:.1f} | {sn[-1]:.1f} | {','.join(o[f'added_{e}'])} | "
              f"{','.join(n.get(f'added_{e}', []))} | {_error(o, e)} | {_error(n, e)} |")
    import statistics
    print(f"| median | {statistics.median(so):.1f} | {statistics.median(sn):.1f} | | | | |")
    print(f"| total | {sum(so):.1f} | {sum(sn):.1f} | | | | |")
