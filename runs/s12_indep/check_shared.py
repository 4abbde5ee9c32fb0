"""Reproduce shared independent records with runs/s12_indep/simulator.py (no liquidamp).

    PYTHONPATH=. python runs/s12_indep/check_shared.py [d12_null d01_asym_loss ...]

Prints per record the fitted third-harmonic (relative amplitude, phase), and the NRMSE
(RMS of record - simulation over the record's force RMS) and RMS residual / force noise.
"""
import json
import sys

import numpy as np

from runs.s12_indep.simulator import simulate

ROOT = "/work/shared/data/independent-records/"


def fit_h3(t, y, f):
    w = 2 * np.pi * f
    A = np.column_stack([np.sin(w * t), np.cos(w * t), np.sin(3 * w * t), np.cos(3 * w * t),
                         np.ones_like(t)])
    c = np.linalg.lstsq(A, y, rcond=None)[0]
    Y = np.hypot(c[0], c[1])
    return Y, np.hypot(c[2], c[3]) / Y, np.arctan2(c[3], c[2]), np.arctan2(c[1], c[0])


SETTINGS = {  # simulator_settings -> this simulator's parameters
    "d01_asym_loss": lambda s: {"asym_lin": s["asym_lin"], "asym_quad": s["asym_quad"]},
    "d12_null": lambda s: {},
    "d02_relief_valve": lambda s: {"pc_relief": s["p_relief"], "G_relief": s["G_relief"],
                                     "valve_linear": 1.0},
    "d03_elastomer": lambda s: {"k_e": s["k_e"], "k_m": s["k_m"], "c_m": s["c_m"]},
}


def main(names, relief_linear=False):
    truth = json.load(open(ROOT + "truth.json"))
    for name in names:
        case = truth[name]
        dev = {k: v for k, v in case["device"]["values"].items()}
        eff = SETTINGS[name](case["simulator_settings"])
        for part in ("cal", "val"):
            r = case["records"][part]
            d = np.loadtxt(ROOT + r["file"], delimiter=",", skiprows=1)
            t, y, F = d[:, 0], d[:, 1] * 1e-3, d[:, 2]
            f = r["frequency_Hz"]
            Y, h3, ph3, ph1 = fit_h3(t, y, f)
            s = simulate(dev, f, r["amplitude_m"], fs=r["sample_rate_Hz"], h3=h3, phi3=ph3,
                         effects=eff)
            res = F - s["F"]
            rms = np.sqrt(np.mean(res ** 2))
            print(f"{name} {part}: Y {Y * 1e3:.4f} mm h3 {h3:.4f} phi3 {ph3:+.3f} phi1 "
                  f"{ph1:+.4f}; stroke rms diff {np.sqrt(np.mean((y - s['y']) ** 2)) * 1e6:.2f}"
                  f" um; force NRMSE {rms / np.sqrt(np.mean(F ** 2)):.5f}, residual rms "
                  f"{rms:.2f} N = {rms / 1.5:.2f} x noise, mean {res.mean():+.2f} N", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:] or ["d12_null", "d01_asym_loss", "d02_relief_valve", "d03_elastomer"])
