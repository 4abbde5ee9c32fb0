"""Side by side: runs/s12_lead/table.md against runs/s13_valved/shared (tabulate rows).

Usage: ``python runs/s13_valved/compare.py`` (prints markdown).
"""
import subprocess


def rows(text):
    out = {}
    for line in text.splitlines():
        if line.startswith("| ") and not line.startswith("| case") and "---" not in line:
            cells = [c.strip() for c in line.strip("|").split("|")]
            out[cells[0]] = cells
    return out


old = rows(open("runs/s12_lead/table.md").read())
new = rows(subprocess.run(["python", "runs/tabulate.py", "runs/s13_valved/shared"],
                          capture_output=True, text=True).stdout)
print("| case | s12_lead ok / class / added / held-out | s13_valved ok / class / added / held-out"
      " | same | wall s s12 -> s13 |")
print("|---|---|---|---|---|")
for case, n in new.items():
    o = old.get(case)
    if o is None:
        continue
    same = o[1:4] + o[5:6] == n[1:4] + n[5:6]
    print(f"| {case} | {o[1]} / {o[2]} / {o[3]} / {o[5]} | {n[1]} / {n[2]} / {n[3]} / {n[5]} | "
          f"{'yes' if same else 'NO'} | {o[-1]} -> {n[-1]} |")
