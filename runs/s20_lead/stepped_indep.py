"""Session 20: the seed-21 fresh draw's cases with a calibration record whose stroke does not
repeat: the independent simulator (runs/s12_indep/simulator.py, NOT liquidamp's code) runs
the same device and effect settings under a stepped test from rest (amplitude Y/4, Y/2, Y,
4 cycles each, half-cycle cosine ramps, kept whole), with the sweep's noise; the held-out
record is the fresh draw's periodic one, unchanged.

    PYTHONPATH=. python runs/s20_lead/stepped_indep.py FRESH_RECDIR NEW_RECDIR
    FRESH_SEED=21 PYTHONPATH=. python runs/s19_lead/fresh.py run|table NEW_RECDIR OUT
"""
import json
import shutil
import sys
from pathlib import Path

import numpy as np

from runs.s12_indep.simulator import simulate_stepped, write_csv
from runs.s12_indep.sweep import NOISE_F, NOISE_Y

src, dst = Path(sys.argv[1]), Path(sys.argv[2])
dst.mkdir(parents=True, exist_ok=True)
truth = json.loads((src / "truth.json").read_text())
for k, (cid, case) in enumerate(c for c in truth.items() if not c[0].startswith("_")):
    cal = case["records"]["cal"]
    f, Y, fs = cal["frequency_Hz"], cal["amplitude_m"], cal["sample_rate_Hz"]
    s = simulate_stepped(case["device"]["values"], f, Y / 4, steps=3, ratio=2.0,
                         cycles_per_step=4.0, fs=fs, effects=case["simulator_settings"])
    b = simulate_stepped(case["device"]["values"], f, Y / 4, steps=3, ratio=2.0,
                         cycles_per_step=4.0, fs=fs, effects={})
    rng = np.random.default_rng(9100 + k)
    write_csv(dst / cal["file"], s["t"], s["y"] + NOISE_Y * rng.standard_normal(s["y"].size),
              s["F"] + NOISE_F * rng.standard_normal(s["F"].size))
    shutil.copy(src / case["records"]["val"]["file"], dst / case["records"]["val"]["file"])
    cal["test"] = (f"stepped test from rest at {f:g} Hz: amplitude {Y / 4 * 1e3:g}, "
                   f"{Y / 2 * 1e3:g}, {Y * 1e3:g} mm, 4 cycles each, half-cycle cosine ramps "
                   f"(+1 % third harmonic); kept whole; {fs:g} Hz sampling")
    sz = float(np.sqrt(np.mean((s["F"] - b["F"]) ** 2)))
    case["effect_size"]["cal"] = {"effect_rms_N": sz, "effect_over_noise": sz / NOISE_F,
                                  "force_pp_N": float(np.ptp(s["F"])), "samples": len(s["F"])}
    print(cid, f"stepped cal: effect {sz:.3g} N RMS ({sz / NOISE_F:.3g} x noise)", flush=True)
(dst / "truth.json").write_text(json.dumps(truth, indent=1))
