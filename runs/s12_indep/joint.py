"""Direction check for the effects the base absorbs: calibrate on BOTH records of a pair
(cal + val) and hold out a third record of the same device and effect at another condition.

    PYTHONPATH=. python runs/s12_indep/joint.py RECDIR OUT ID [ID ...]

Writes RECDIR/ID_third.csv (3 Hz, 2.5 mm, the pair's sampling rate, a noise seed from ID) and
runs ``python -m liquidamp diagnose CAL VAL --validate THIRD --json OUT/ID_joint.json``
under ``timeout 600`` (NOT the default protocol: two calibration records).
"""
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from runs.s12_indep.simulator import simulate, write_csv
from runs.s12_indep.sweep import NOISE_F, NOISE_Y, PHI3


def main(recdir, out, ids):
    recdir, out = Path(recdir), Path(out)
    out.mkdir(parents=True, exist_ok=True)
    truth = json.loads((recdir / "truth.json").read_text())
    for cid in ids:
        case = truth[cid]
        fs = case["records"]["cal"]["sample_rate_Hz"]
        s = simulate(case["device"]["values"], 3.0, 2.5e-3, fs=fs, phi3=PHI3,
                     effects=case["simulator_settings"])
        rng = np.random.default_rng(9100 + sum(ord(c) * (i + 1) for i, c in enumerate(cid)))
        write_csv(recdir / f"{cid}_third.csv", s["t"],
                  s["y"] + NOISE_Y * rng.standard_normal(len(s["y"])),
                  s["F"] + NOISE_F * rng.standard_normal(len(s["F"])))
        load = os.getloadavg()[0]
        t0 = time.time()
        cmd = ["timeout", "600", sys.executable, "-m", "liquidamp", "diagnose",
               str(recdir / f"{cid}_cal.csv"), str(recdir / f"{cid}_val.csv"), "--validate",
               str(recdir / f"{cid}_third.csv"), "--json", str(out / f"{cid}_joint.json")]
        r = subprocess.run(cmd, capture_output=True, text=True)
        (out / f"{cid}_joint.out").write_text(r.stdout + r.stderr)
        j = json.loads((out / f"{cid}_joint.json").read_text()) if r.returncode == 0 else {}
        steps = [st["effect"] for st in j.get("steps", [])]
        eff = j.get("final", {}).get("parameters", {}).get("effects", {})
        ho = (max(j["baseline"]["heldout_records"].values()), max(j["heldout"].values())) \
            if j else None
        print(cid, "rc", r.returncode, f"{time.time() - t0:.0f} s (load {load:.2f})",
              "added", steps, eff, "held-out before->after", ho, flush=True)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
