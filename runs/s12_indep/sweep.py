"""Held-out sweep on records made by runs/s12_indep/simulator.py (NOT liquidamp's code).

    PYTHONPATH=. python runs/s12_indep/sweep.py gen RECDIR            # records + truth.json
    PYTHONPATH=. python runs/s12_indep/sweep.py run RECDIR OUT [ID..] # default diagnose each
    PYTHONPATH=. python runs/s12_indep/sweep.py table RECDIR OUT      # OUT/table.md

``run`` calls ``python -m liquidamp diagnose CAL.csv --validate VAL.csv --json OUT/ID.json``
(the DEFAULT command, no other flag) for each pair, one at a time, under ``timeout 600``,
and writes OUT/ID.{json,out,err,rc,time} (the time with the load average at its start).

Protocol as the shared independent records' README: sine + 1 % third harmonic (phase 0.70
rad, as fitted on d12), run 16 cycles from rest and keep the last 10 (samples on the global
grid k / fs), white noise 1.5 N on the force and 2 um on the stroke; the base device is the
paper's Table 3 reference design (``R_``) or Device B (``B_``) with each of inv_gamma1,
inv_gamma2, c1, c2, S_t multiplied by a seeded factor in [0.85, 1.2]; one effect per case,
sized (by scaling its strength parameter) so that its noise-free RMS force on the cal record
is about ``target`` x the force noise.  Conditions (1-8 Hz, 1-5 mm, 200 Hz - 2 kHz) differ
from the shared set's.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from runs.s12_indep.simulator import device, simulate, write_csv

NOISE_F = 1.5
NOISE_Y = 2e-6
PHI3 = 0.70
A_P = 0.00069115

# id -> (base, (f, Y) cal, (f, Y) val, fs, effect kind, target effect RMS / noise)
CASES = {
    "R_null": ("reference", (2.5, 3e-3), (5.0, 1.5e-3), 500.0, "null", 0),
    "B_null": ("device_b", (1.0, 5e-3), (7.0, 1e-3), 1000.0, "null", 0),
    "R_coulomb": ("reference", (1.0, 4e-3), (3.0, 2e-3), 200.0, "coulomb", 6),
    "B_coulomb": ("device_b", (4.0, 2e-3), (2.0, 4e-3), 500.0, "coulomb", 6),
    "R_leakage": ("reference", (2.0, 3e-3), (4.0, 2e-3), 200.0, "leakage", 8),
    "B_leakage": ("device_b", (6.0, 1.5e-3), (3.0, 3e-3), 1000.0, "leakage", 8),
    "R_relief": ("reference", (4.0, 2.5e-3), (2.5, 4e-3), 200.0, "relief", 8),
    "B_relief": ("device_b", (5.0, 2e-3), (3.0, 3e-3), 500.0, "relief", 8),
    "R_freeplay": ("reference", (3.0, 2e-3), (1.5, 4e-3), 2000.0, "freeplay", 8),
    "B_freeplay": ("device_b", (2.0, 3e-3), (5.0, 1.5e-3), 200.0, "freeplay", 8),
    "R_series": ("reference", (5.0, 2e-3), (3.0, 3e-3), 200.0, "series", 6),
    "B_series": ("device_b", (8.0, 1e-3), (4.0, 2e-3), 1000.0, "series", 6),
    "R_mass": ("reference", (8.0, 1e-3), (6.0, 2e-3), 500.0, "mass", 5),
    "B_offset": ("device_b", (3.0, 2e-3), (1.5, 5e-3), 200.0, "offset", 5),
    "R_asym": ("reference", (1.5, 5e-3), (3.0, 2e-3), 200.0, "asym", 10),
    "B_asym": ("device_b", (4.0, 3e-3), (2.0, 2e-3), 500.0, "asym", 10),
    "R_elastomer": ("reference", (1.0, 3e-3), (4.0, 1.5e-3), 200.0, "elastomer", 8),
    "B_elastomer": ("device_b", (2.5, 2e-3), (6.0, 1e-3), 1000.0, "elastomer", 8),
    "R_endstops": ("reference", (2.0, 3e-3), (3.5, 2.8e-3), 2000.0, "endstops", 8),
    "B_endstops": ("device_b", (1.5, 4e-3), (4.0, 3.6e-3), 500.0, "endstops", 8),
    "R_digressive": ("reference", (3.0, 3e-3), (5.0, 2e-3), 200.0, "digressive", 8),
    "B_cavitation": ("device_b", (8.0, 2e-3), (6.0, 2.5e-3), 1000.0, "cavitation", 0),
    # the effects the base absorbed at 6-8 x noise, three times stronger (detection limit)
    "R_leakage3": ("reference", (2.0, 3e-3), (4.0, 2e-3), 200.0, "leakage", 24),
    "B_leakage3": ("device_b", (6.0, 1.5e-3), (3.0, 3e-3), 1000.0, "leakage", 24),
    "R_relief3": ("reference", (4.0, 2.5e-3), (2.5, 4e-3), 200.0, "relief", 24),
    "R_series3": ("reference", (5.0, 2e-3), (3.0, 3e-3), 200.0, "series", 18),
    "B_series3": ("device_b", (8.0, 1e-3), (4.0, 2e-3), 1000.0, "series", 18),
}

#: effect kind -> (liquidamp effect names accepted first, key parameter, truth key)
KEYS = {
    "null": ((), None, None),
    "coulomb": (("coulomb_friction", "smooth_friction"), "force_N", "Fc"),
    "leakage": (("leakage",), "coefficient_m3_per_s_Pa", "k_leak"),
    "relief": (("relief_valve",), "cracking_pressure_Pa", "pc_relief"),
    "freeplay": (("freeplay", "backlash", "floating_freeplay"), "gap_m", "gap"),
    "series": (("series_compliance",), "stiffness_N_per_m", "k_series"),
    "mass": (("moving_mass",), "mass_kg", "mass"),
    "offset": (("force_offset",), "offset_N", "offset"),
    "asym": (("asymmetric_loss",), "rebound_ratio", "asym_quad"),
    "elastomer": (("elastomer",), "parallel_stiffness_N_per_m", "k_e"),
    "endstops": (("end_stops",), "clearance_m", "y_stop"),
    "digressive": (("digressive_valve", "relief_valve"), "compression_cracking_Pa", "pc_comp"),
    "cavitation": (("cavitation",), "vapour_pressure_Pa", "p_vap"),
}

WORDS = {
    "coulomb": "Coulomb friction on the rod, F_c v / sqrt(v^2 + (0.5 mm/s)^2)",
    "leakage": "laminar leakage between the chambers, q = k_leak (p1 - p2)",
    "relief": ("relief poppet valve beside the channel: q = G (|dp| - p_c)+ sqrt(|dp| / p_c) "
               "sign(dp) (orifice law, opening linear in the overpressure)"),
    "freeplay": ("freeplay: the rod drives the piston through a dead band of half-width g; "
                 "the piston (0.05 kg) floats in the band under the fluid force; contact "
                 "2e7 N/m, 600 N s/m"),
    "series": "a massless spring k_s in series between the actuator and the device",
    "mass": "a moving mass m between the load cell and the device: F += m d2y/dt2",
    "offset": "a constant load-cell offset F0",
    "asym": "asymmetric channel loss: in rebound c1 x asym_lin, c2 x asym_quad",
    "elastomer": "elastomer on the rod: parallel spring k_e + Maxwell branch (k_m, c_m)",
    "endstops": ("end stops beyond |y| > y_s: contact k_s delta^e + c_s delta_dot, only "
                 "pushes"),
    "digressive": ("digressive valve pair: compression poppet (p_comp, G_comp) for p1 > p2, "
                   "rebound poppet (p_reb, G_reb) for p2 > p1, orifice law as the relief"),
    "cavitation": ("cavitation: chamber pressure floor at the vapour pressure (vapour cavity "
                   "takes the volume demand), on a fully degassed device"),
}


def _device(cid: str) -> tuple[dict, dict, dict]:
    base = CASES[cid][0]
    base_id = cid.rstrip("0123456789")  # a stronger variant keeps its base case's device
    rng = np.random.default_rng(sum(ord(c) * (i + 1) for i, c in enumerate(base_id)))
    mult = {k: float(np.round(rng.uniform(0.85, 1.2), 3))
            for k in ("inv_gamma1", "inv_gamma2", "c1", "c2", "S_t")}
    over = {}
    if CASES[cid][4] == "cavitation":  # fully degassed (with any air the gas absorbs it)
        over = {"inv_gamma1": 0.0, "inv_gamma2": 0.0}
    return device(base, mult, **over), mult, over


def _sim(dev, fY, fs, eff, seed=None):
    f, Y = fY
    s = simulate(dev, f, Y, fs=fs, phi3=PHI3, effects=eff)
    if seed is not None:
        rng = np.random.default_rng(seed)
        s["y_noisy"] = s["y"] + NOISE_Y * rng.standard_normal(len(s["y"]))
        s["F_noisy"] = s["F"] + NOISE_F * rng.standard_normal(len(s["F"]))
    return s


def _peak_dp(dev, fY, fs):
    s = _sim(dev, fY, fs, {})
    dp = s["states"][:, 0] - s["states"][:, 2]
    return float(np.max(np.abs(dp))), s


def _effect(kind, dev, cal, val, fs, strength, cid=""):
    """Effect parameters at ``strength`` (a multiplier of the natural scale)."""
    dpc, s = _peak_dp(dev, cal, fs)
    dpv, _ = _peak_dp(dev, val, fs)
    f, Y = cal
    w = 2 * math.pi * f
    F0 = float(np.max(np.abs(s["F"])))
    q0 = A_P * w * Y
    if kind == "coulomb":
        return {"Fc": strength}
    if kind == "leakage":
        return {"k_leak": strength * 1e-12}
    if kind == "relief":
        return {"pc_relief": 0.5 * min(dpc, dpv), "G_relief": strength * q0 / dpc}
    if kind == "freeplay":
        return {"gap": strength * 1e-5}
    if kind == "series":
        return {"k_series": F0 / (strength * 1e-3 * Y)}
    if kind == "mass":
        return {"mass": strength}
    if kind == "offset":
        return {"offset": strength}
    if kind == "asym":
        return {"asym_lin": 1.0 + 0.4 * strength, "asym_quad": 1.0 + 0.3 * strength}
    if kind == "elastomer":
        tau = 1.0 / (2 * math.pi * 2.0)
        return {"k_e": strength * 1e3, "k_m": 2 * strength * 1e3, "c_m": 2 * strength * 1e3 * tau}
    if kind == "endstops":
        ys = 0.87 * min(cal[1], val[1])
        return {"y_stop": ys, "k_stop": strength * 1e6, "c_stop": 50.0,
                "e_stop": 1.5 if cid.startswith("R_") else 1.0}
    if kind == "digressive":
        m = min(dpc, dpv)
        return {"pc_comp": 0.55 * m, "G_comp": strength * q0 / dpc,
                "pc_reb": 0.75 * m, "G_reb": 0.7 * strength * q0 / dpc}
    if kind == "cavitation":
        return {"p_vap": 2339.0}
    return {}


def _size(dev, fY, fs, eff, bare=None):
    s = _sim(dev, fY, fs, eff)
    b = bare if bare is not None else _sim(dev, fY, fs, {})
    return float(np.sqrt(np.mean((s["F"] - b["F"]) ** 2))), s, b


def _strength(kind, dev, cal, val, fs, target, cid):
    """Strength whose cal-record effect RMS is about target x noise (secant in logs)."""
    if kind in ("null", "cavitation"):
        return 1.0
    if kind == "asym":
        lo, hi = 0.01, 2.0
        bare = _sim(dev, cal, fs, {})
        for _ in range(14):
            mid = math.sqrt(lo * hi)
            sz = _size(dev, cal, fs, _effect(kind, dev, cal, val, fs, mid, cid), bare)[0]
            lo, hi = (mid, hi) if sz < target * NOISE_F else (lo, mid)
        return math.sqrt(lo * hi)
    x = 1.0
    bare = _sim(dev, cal, fs, {})
    for _ in range(6):
        sz = _size(dev, cal, fs, _effect(kind, dev, cal, val, fs, x, cid), bare)[0]
        if sz <= 0:
            x *= 10
            continue
        r = target * NOISE_F / sz
        if abs(r - 1) < 0.05:
            break
        x *= r ** (0.5 if kind in ("freeplay", "endstops") else 1.0)
    return x


def gen(recdir: Path, ids) -> None:
    recdir.mkdir(parents=True, exist_ok=True)
    tpath = recdir / "truth.json"
    truth = json.loads(tpath.read_text()) if tpath.exists() else {
        "_about": {"simulator": "runs/s12_indep/simulator.py (numba RK4, fixed step 1e-5 s; "
                                "imports nothing from liquidamp)",
                   "columns": "time [s], displacement [mm], force [N]",
                   "signs": "displacement positive = into the damper (chamber 1 shrinks); "
                            "force positive when it resists a positive stroke",
                   "noise_rms": {"force_N": NOISE_F, "stroke_m": NOISE_Y},
                   "effect_size": "noise-free RMS force difference against the same device "
                                  "without the effect, per record"}}
    for k, cid in enumerate(ids):
        base, cal, val, fs, kind, target = CASES[cid]
        dev, mult, over = _device(cid)
        x = _strength(kind, dev, cal, val, fs, target, cid)
        eff = _effect(kind, dev, cal, val, fs, x, cid)
        recs, sizes = {}, {}
        for i, (part, fY) in enumerate((("cal", cal), ("val", val))):
            s = _sim(dev, fY, fs, eff, seed=7000 + 10 * list(CASES).index(cid) + i)
            b = _sim(dev, fY, fs, {})
            fn = f"{cid}_{part}.csv"
            write_csv(recdir / fn, s["t"], s["y_noisy"], s["F_noisy"])
            sz = float(np.sqrt(np.mean((s["F"] - b["F"]) ** 2)))
            st = s["states"]
            sizes[part] = {"effect_rms_N": sz, "effect_over_noise": sz / NOISE_F,
                           "force_pp_N": float(np.ptp(s["F"])), "samples": len(s["F"]),
                           "chamber_pressure_range_bar": [
                               float(min(st[:, 0].min(), st[:, 2].min()) / 1e5),
                               float(max(st[:, 0].max(), st[:, 2].max()) / 1e5)]}
            recs[part] = {"file": fn, "test": (f"sine {fY[0]:g} Hz, amplitude {fY[1] * 1e3:g} mm "
                                               f"(+1 % third harmonic); run 16 cycles from "
                                               f"rest, last 10 kept; {fs:g} Hz sampling"),
                          "columns": ["time [s]", "displacement [mm]", "force [N]"],
                          "sample_rate_Hz": fs, "frequency_Hz": fY[0], "amplitude_m": fY[1],
                          "mean_stroke_m": 0.0}
        truth[cid] = {"title": kind, "effect": WORDS.get(kind, "none: the base device only"),
                      "records": recs, "simulator_settings": eff,
                      "key": {"effects": list(KEYS[kind][0]), "parameter": KEYS[kind][1],
                              "truth": eff.get(KEYS[kind][2]) if KEYS[kind][2] else None},
                      "device": {"words": f"Table 3 {base}, perturbed", "preset": base,
                                 "multipliers": mult, "overrides": over, "values": dev},
                      "effect_size": sizes}
        tpath.write_text(json.dumps(truth, indent=1))
        print(cid, kind, {k: f"{v:.3g}" for k, v in eff.items()},
              {p: f"{v['effect_rms_N']:.3g} N, p {v['chamber_pressure_range_bar'][0]:.3g}-"
                  f"{v['chamber_pressure_range_bar'][1]:.3g} bar" for p, v in sizes.items()},
              flush=True)


def run(recdir: Path, out: Path, ids) -> None:
    out.mkdir(parents=True, exist_ok=True)
    for cid in ids:
        load = os.getloadavg()[0]
        t0 = time.time()
        cmd = ["timeout", "600", sys.executable, "-m", "liquidamp", "diagnose",
               str(recdir / f"{cid}_cal.csv"), "--validate", str(recdir / f"{cid}_val.csv"),
               "--json", str(out / f"{cid}.json")]
        with open(out / f"{cid}.out", "w") as fo, open(out / f"{cid}.err", "w") as fe:
            rc = subprocess.call(cmd, stdout=fo, stderr=fe)
        (out / f"{cid}.rc").write_text(f"{rc}\n")
        (out / f"{cid}.time").write_text(f"{time.time() - t0:.1f} (load {load:.2f})\n")
        print(cid, rc, f"{time.time() - t0:.0f} s (load {load:.2f})", flush=True)


def row(recdir: Path, out: Path, cid: str) -> str:
    truth = json.loads((recdir / "truth.json").read_text())[cid]
    kind = truth["title"]
    ok_first, key, _ = KEYS[kind]
    tv = truth["key"]["truth"]
    size = truth["effect_size"]["cal"]["effect_rms_N"]
    t = (out / f"{cid}.time").read_text().strip() if (out / f"{cid}.time").exists() else "?"
    rc = (out / f"{cid}.rc").read_text().strip() if (out / f"{cid}.rc").exists() else "?"
    p = out / f"{cid}.json"
    head = f"| {cid} | {size / NOISE_F:.3g} |"
    if not p.exists():
        err = [ln for ln in ((out / f"{cid}.err").read_text().splitlines()
                             if (out / f"{cid}.err").exists() else []) if ln.strip()]
        cls = "timeout" if rc == "124" else ("refusal" if rc in ("1", "2") else "crash")
        return f"{head} - | - | - | rc {rc}: {(err[-1] if err else '')[:120]} | {t} | {cls} |"
    j = json.loads(p.read_text())
    eff = j["final"]["parameters"].get("effects", {})
    added = [s["effect"] for s in j["steps"]]
    fitted = None
    names = [added[0]] if added else []
    names += list(ok_first) + (["smooth_friction", "coulomb_friction"] if kind in
                               ("freeplay", "coulomb") else [])
    for name in names:
        if name in eff and key in eff[name]:
            fitted = eff[name][key]
            break
    if fitted is None and kind == "digressive" and "relief_valve" in eff:
        fitted = eff["relief_valve"].get("cracking_pressure_Pa")
    kp = (f"{key}={fitted:.3g} vs {tv:.3g} ({fitted / tv - 1:+.0%})" if fitted is not None
          and tv else (f"{key}: not fitted (truth {tv:.3g})" if tv else "-"))
    before = max(j["baseline"]["heldout_records"].values())
    after = max(j["heldout"].values())
    first = j["summary"].splitlines()[0] if j.get("summary") else ""
    if kind == "null" or (kind == "cavitation" and size < 2 * NOISE_F):
        cls = "right" if not added else "spurious"
    elif not added:
        cls = "missed"
    elif added[0] not in ok_first:
        cls = "wrong first effect"
    else:
        good_key = fitted is not None and tv and abs(fitted / tv - 1) <= 0.3
        halved = after <= 0.5 * before
        cls = "right" if good_key and halved else (
            "right effect, " + ", ".join(([] if good_key else ["key > 30 % off"])
                                         + ([] if halved else ["held-out not halved"])))
    return (f"{head} {','.join(added) or '-'} | {kp} | {before:.4g}->{after:.4g} "
            f"| {j['stop_reason'][:80]} / {first[:90]} | {t} | {cls} |")


def table(recdir: Path, out: Path, ids) -> str:
    lines = [f"# Independent-simulator sweep: {recdir} -> {out}", "",
             "Records from runs/s12_indep/simulator.py (not liquidamp's code); each pair run "
             "with the DEFAULT `python -m liquidamp diagnose CAL --validate VAL --json OUT` "
             "under `timeout 600`. Class: right = the true effect added first, key parameter "
             "within 30 %, held-out NRMSE at least halved (nulls: nothing added; a cavitation "
             "record whose effect is under 2 x the noise counts as a null); missed = nothing "
             "added; spurious = something added to a null; timeout (rc 124) / refusal (rc 1-2) "
             "/ crash. No library file was changed, so there is no 'after' table.", "",
             f"load average at the end: {os.getloadavg()}", "",
             "| record | effect rms / noise (cal) | added (order) | key parameter vs truth "
             "| held-out NRMSE before->after | stop reason / summary first line "
             "| wall s (load at start) | class |",
             "|---|---|---|---|---|---|---|---|"]
    for cid in ids:
        if (out / f"{cid}.rc").exists() or (out / f"{cid}.json").exists():
            lines.append(row(recdir, out, cid))
    text = "\n".join(lines) + "\n"
    (out / "table.md").write_text(text)
    return text


def main_with(cases: dict, argv) -> None:
    """:func:`main` on ``cases`` added to :data:`CASES`, run alone where no id is named (the
    sweeps that extend this one: runs/s14_lead/strong.py, runs/s19_lead/fresh.py)."""
    CASES.update(cases)
    argv = list(argv)
    if argv[1] in ("gen", "run", "table") and len(argv) <= (3 if argv[1] == "gen" else 4):
        argv += list(cases)
    main(argv)


def main(argv):
    mode = argv[1]
    recdir = Path(argv[2])
    if mode == "gen":
        gen(recdir, argv[3:] or list(CASES))
        return
    out = Path(argv[3])
    ids = argv[4:] or list(CASES)
    if mode == "run":
        run(recdir, out, ids)
    print(table(recdir, out, ids))


if __name__ == "__main__":
    main(sys.argv)
