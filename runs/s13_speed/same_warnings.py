"""Whether two runs' diagnoses said the same: ``python runs/s13_speed/same_warnings.py REFDIR
NEWDIR TAG...`` compares each TAG.json's summary, held-out NRMSE and warnings (per tag)."""

import json
import sys
from pathlib import Path

if __name__ == "__main__":
    ref, new = Path(sys.argv[1]), Path(sys.argv[2])
    for tag in sys.argv[3:]:
        try:
            a = json.loads((ref / f"{tag}.json").read_text())
            b = json.loads((new / f"{tag}.json").read_text())
        except (OSError, ValueError) as exc:
            print(f"{tag}: not compared ({exc})")
            continue
        wa, wb = a.get("warnings", []), b.get("warnings", [])
        print(f"{tag}: summary identical {a.get('summary') == b.get('summary')}, held-out "
              f"identical {a.get('heldout') == b.get('heldout')}")
        same = sum(x == y for x, y in zip(wa, wb, strict=False))
        print(f"{tag}: warnings identical {same} of {len(wa)} (new {len(wb)})")
        for x, y in zip(wa, wb, strict=False):
            if x != y:
                print(f"  ref: {x[:240]}\n  new: {y[:240]}")
