"""Assemble runs/s12_outside/table.md from before/, after/ and final/ (latest valid run per
record and command: final/ > after/ > before/, with the code each ran on).

Usage: ``python runs/s12_outside/assemble.py > runs/s12_outside/table.md``
"""

from __future__ import annotations

import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
from tabulate import row  # noqa: E402

HERE = os.path.dirname(__file__)
TAGS = ("fvd_a03", "fvd_a06", "fvd_kn_in", "mr_spencer", "veh_dyno", "veh_ringing",
        "veh_drift", "veh_programme", "lag_elastomer", "lag_chirp", "dahl_spring")
CODE = {"final": "final", "after": "after", "before": "before"}


def main():
    print("| record | command | code | class | added | physics held-out | line | two-slope | "
          "summary first line (260 chars) | plausibility flags | wall s (load start-end) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for tag in TAGS:
        for cmd in ("diagnose", "calibrate"):
            for d in ("final", "after", "before"):
                base = os.path.join(HERE, d, f"{tag}.{cmd}")
                if os.path.exists(base + ".rc"):
                    r = row(base + ".json", tag, cmd)
                    print(r.replace(f"| {tag} | {cmd} |", f"| {tag} | {cmd} | {d} |", 1))
                    break


if __name__ == "__main__":
    main()
