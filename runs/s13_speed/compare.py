"""Compare a tabulated run with the reference table, case by case (all but the wall time).

``python runs/s13_speed/compare.py REF.md NEW.md``: for each case in NEW, whether its row
(ok, class, added effects, key parameter, held-out NRMSE before->after, references, first
summary line) equals REF's, and the held-out NRMSE after of both with their relative
difference.
"""

import re
import sys


def rows(path):
    out = {}
    for line in open(path):
        if line.startswith("| ") and not line.startswith("| case") and "---" not in line:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            out[cells[0]] = cells
    return out


def after(cell):
    return [float(x) for x in re.findall(r"->([0-9.eE+-]+)", cell)]


if __name__ == "__main__":
    ref, new = rows(sys.argv[1]), rows(sys.argv[2])
    print("| case | same row (but wall) | held-out after ref | new | max rel diff "
          "| wall s ref | new |")
    print("|---|---|---|---|---|---|---|")
    for case, c in new.items():
        r = ref.get(case)
        if r is None:
            print(f"| {case} | no reference | | | | | {c[-1]} |")
            continue
        a, b = after(r[5]), after(c[5])
        rel = max((abs(x - y) / abs(x) for x, y in zip(a, b, strict=False)), default=float("nan"))
        print(f"| {case} | {r[1:-1] == c[1:-1]} | {', '.join(map(str, a))} | "
              f"{', '.join(map(str, b))} | {rel:.2g} | {r[-1]} | {c[-1]} |")
