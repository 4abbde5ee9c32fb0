"""Is the relief valve's law the cause of R_relief3's miss?  With the device at its true
parameters, fit the LINEAR relief law (p_c, G on a grid) to the poppet valve's noise-free
cal record and predict the val record.

    PYTHONPATH=. python runs/s12_indep/relief_law_check.py [RECDIR]
"""
import json
import sys

import numpy as np

from runs.s12_indep.simulator import simulate


def main(recdir="/tmp/s12_indep/records", cid="R_relief3"):
    case = json.load(open(f"{recdir}/truth.json"))[cid]
    dev = case["device"]["values"]
    eff = case["simulator_settings"]
    recs = case["records"]

    def force(part, e):
        r = recs[part]
        return simulate(dev, r["frequency_Hz"], r["amplitude_m"], fs=r["sample_rate_Hz"],
                        phi3=0.70, effects=e)["F"]

    def rms(x):
        return float(np.sqrt(np.mean(x ** 2)))

    tc, tv = force("cal", eff), force("val", eff)
    best = None
    for pc in np.linspace(0.8, 1.3, 6) * eff["pc_relief"]:
        for G in np.geomspace(0.5, 4, 10) * eff["G_relief"]:
            ec = rms(tc - force("cal", {"pc_relief": pc, "G_relief": G, "valve_linear": 1.0}))
            if best is None or ec < best[0]:
                best = (ec, pc, G)
    ec, pc, G = best
    ev = rms(tv - force("val", {"pc_relief": pc, "G_relief": G, "valve_linear": 1.0}))
    print(f"{cid}: poppet p_c {eff['pc_relief']:.3g} G {eff['G_relief']:.3g}; best linear law "
          f"on cal p_c {pc:.3g} G {G:.3g}: residual cal {ec:.2f} N, val {ev:.2f} N (noise "
          f"1.5 N; effect RMS cal {case['effect_size']['cal']['effect_rms_N']:.1f} N, val "
          f"{case['effect_size']['val']['effect_rms_N']:.1f} N)")


if __name__ == "__main__":
    main(*sys.argv[1:2])
