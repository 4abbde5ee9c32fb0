"""Held-out sweep of the default diagnosis on records it was not tuned on (issue 19).

    python runs/s10_unseen/sweep.py all OUTDIR [ID ...]   # every record (or those named)
    python runs/s10_unseen/sweep.py one ID OUTDIR         # one record (what `all` runs)
    python runs/s10_unseen/sweep.py table OUTDIR          # OUTDIR/*.json -> table.md

`all` runs each record in its own subprocess under ``timeout 300`` (one at a time) and
writes OUTDIR/ID.{json,out,err,time}, then the table (OUTDIR/table.md).

Conditions (all unlike the bench's paper_calibrated, 200 Hz, 10 cycles, 3 Hz 3 mm / 4 Hz 2 mm
and unlike the shared d01-d12's reference preset, 200 Hz):

- ``A``: preset device_a (increased flow inertia), cal 1.5 Hz 5 mm, val 2.5 Hz 3 mm, 500 Hz,
  8 cycles, load-cell noise 2 N, seeds 3100 + 10 k.
- ``B``: preset inerter, cal 2 Hz 4 mm, val 3.5 Hz 2 mm, 1 kHz, 10 cycles, noise 3 N,
  seeds 3300 + 10 k.
- ``C``: preset device_b (reduced flow inertia), cal 6 Hz 1.5 mm, val 5 Hz 2.5 mm, 2 kHz,
  12 cycles, noise 0.5 N, seeds 3500 + 10 k.

Effect strengths are fractions of the device's own calibration force amplitude F0, peak
pressure difference dp0 = F0 / A_p and peak displaced flow Q0 = A_p 2 pi f Y (F0 measured
without effects: device_a 204 N, inerter 610 N, device_b 92 N), so each effect is as
prominent relative to the device as a seal or rig imperfection is in practice (a few
per cent of the force) and the sweep does not depend on the device's absolute size:

- friction (Coulomb, LuGre): 6 % of F0 (seal friction of a well-made damper); LuGre
  pre-sliding stiffness so that the pre-sliding travel F/k is 3 % of Y;
- force offset: 5 % of F0 (load-cell zero); moving mass: m w^2 Y = 5 % of F0;
- series compliance: F0 / k = 5 % of Y (rig elasticity eats 5 % of the stroke);
- freeplay: half-gap 3 % of Y;
- leakage: 8 % of the peak flow bypasses the channel at dp0;
- relief valve: cracks at 60 % of dp0 and passes 25 % of Q0 at dp0;
- asymmetric loss: rebound 1.35 x compression;
- elastomer: parallel stiffness k_p Y = 5 % of F0, branch 2 k_p, corner at the cal frequency;
- end stops: clearance 85 % of Y, contact stiffness so that 15 % of Y overtravel would
  carry 30 % of F0 (real contact is far stiffer; the stroke only grazes);
- cavitation: water's vapour pressure at 20 C (2339 Pa), present only where the chamber
  pressure would fall below it;
- bypass groove: depth 0.3, centred, half width 30 % of Y;
- digressive valve: compression cracks at 55 % of dp0, rebound at 75 %, each passing 20 %
  of Q0 at dp0.

Not swept: gas_charge (at these strokes its preload is a force offset: indistinguishable by
any test), field_yield (needs an input channel), self_heating (needs long records; d06/d07
cover it), rotating_frame (needs a rotor), slip_weakening (a modifier of smooth friction).
"""
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

#: condition -> (preset, (f, Y) cal, (f, Y) val, rate [Hz], cycles, noise [N], seed base, F0 [N])
CONDITIONS = {
    "A": ("device_a", (1.5, 0.005), (2.5, 0.003), 500.0, 8.0, 2.0, 3100, 204.0),
    "B": ("inerter", (2.0, 0.004), (3.5, 0.002), 1000.0, 10.0, 3.0, 3300, 610.0),
    "C": ("device_b", (6.0, 0.0015), (5.0, 0.0025), 2000.0, 12.0, 0.5, 3500, 92.0),
}
A_P = 6.911503837897544e-4  # piston area of every preset [m^2]

#: effect -> (key parameter, names the diagnosis may add first for it)
KEYS = {
    "null": (None, ()),
    "force_offset": ("offset_N", ("force_offset",)),
    "coulomb_friction": ("force_N", ("coulomb_friction", "smooth_friction")),
    "moving_mass": ("mass_kg", ("moving_mass",)),
    "asymmetric_loss": ("rebound_ratio", ("asymmetric_loss",)),
    "leakage": ("coefficient_m3_per_s_Pa", ("leakage",)),
    "relief_valve": ("cracking_pressure_Pa", ("relief_valve",)),
    "smooth_friction": ("force_N", ("smooth_friction", "coulomb_friction")),
    "series_compliance": ("stiffness_N_per_m", ("series_compliance",)),
    "freeplay": ("gap_m", ("freeplay", "backlash")),
    "cavitation": ("vapour_pressure_Pa", ("cavitation",)),
    "elastomer": ("parallel_stiffness_N_per_m", ("elastomer",)),
    "end_stops": ("clearance_m", ("end_stops",)),
    "bypass_groove": ("depth", ("bypass_groove",)),
    "digressive_valve": ("compression_cracking_Pa", ("digressive_valve",)),
}

#: the records, cheap ones first
RECORDS = ([f"A_{e}" for e in KEYS]
           + [f"B_{e}" for e in ("null", "coulomb_friction", "leakage", "asymmetric_loss",
                                 "relief_valve", "series_compliance", "elastomer",
                                 "end_stops", "cavitation")]
           + [f"C_{e}" for e in ("null", "smooth_friction", "freeplay")])


def truth(cond: str, effect: str) -> dict:
    """The effect's parameters [SI] for condition ``cond`` (fractions of F0, dp0, Q0)."""
    _, (f, y), _, _, _, _, _, f0 = CONDITIONS[cond]
    dp0 = f0 / A_P
    q0 = A_P * 2.0 * math.pi * f * y
    w = 2.0 * math.pi * f
    return {
        "null": {},
        "force_offset": {"offset_N": 0.05 * f0},
        "coulomb_friction": {"force_N": 0.06 * f0},
        "moving_mass": {"mass_kg": 0.05 * f0 / (w * w * y)},
        "asymmetric_loss": {"rebound_ratio": 1.35},
        "leakage": {"coefficient_m3_per_s_Pa": 0.08 * q0 / dp0},
        "relief_valve": {"cracking_pressure_Pa": 0.6 * dp0,
                         "conductance_m3_per_s_Pa": 0.25 * q0 / (0.4 * dp0)},
        "smooth_friction": {"force_N": 0.06 * f0,
                            "stiffness_N_per_m": 0.06 * f0 / (0.03 * y)},
        "series_compliance": {"stiffness_N_per_m": f0 / (0.05 * y)},
        "freeplay": {"gap_m": 0.03 * y},
        "cavitation": {"vapour_pressure_Pa": 2339.0},
        "elastomer": {"parallel_stiffness_N_per_m": 0.05 * f0 / y,
                      "branch_stiffness_N_per_m": 0.1 * f0 / y,
                      "branch_damping_N_s_per_m": 0.1 * f0 / y / w},
        "end_stops": {"clearance_m": 0.85 * y,
                      "stiffness_N_per_m": 0.3 * f0 / (0.15 * y)},
        "bypass_groove": {"depth": 0.3, "half_width_m": 0.3 * y},
        "digressive_valve": {"compression_cracking_Pa": 0.55 * dp0,
                             "compression_conductance_m3_per_s_Pa": 0.2 * q0 / (0.45 * dp0),
                             "rebound_cracking_Pa": 0.75 * dp0,
                             "rebound_conductance_m3_per_s_Pa": 0.2 * q0 / (0.25 * dp0)},
    }[effect]


def records(rid: str, with_effect: bool = True):
    """(cal, val) of record ``rid`` (e.g. ``A_leakage``)."""
    from liquidamp.analysis.measured.synthetic import synthetic_record

    cond, effect = rid.split("_", 1)
    pre, cal, val, rate, cycles, noise, seed0, _ = CONDITIONS[cond]
    k = list(KEYS).index(effect)
    eff = {effect: truth(cond, effect)} if effect != "null" and with_effect else {}
    return tuple(synthetic_record(preset=pre, frequency=f, amplitude=y, cycles=cycles,
                                  sampling_rate=rate, force_noise=noise,
                                  seed=seed0 + 10 * k + i, effects=eff)
                 for i, (f, y) in enumerate((cal, val)))


def one(rid: str, out: Path) -> None:
    import numpy as np

    from liquidamp.analysis.measured.diagnosis import diagnose

    t0 = time.perf_counter()
    cal, val = records(rid)
    size = None
    if not rid.endswith("_null"):
        bare = records(rid, with_effect=False)[0]
        size = float(np.sqrt(np.mean((cal.meta["true_force"] - bare.meta["true_force"]) ** 2)))
    t_make = time.perf_counter() - t0
    t0 = time.perf_counter()
    d = diagnose([cal], [val])
    sec = time.perf_counter() - t0
    j = d.as_dict()
    j["sweep"] = {"id": rid, "truth": truth(*rid.split("_", 1)), "seconds": sec,
                  "seconds_make": t_make, "effect_rms_N": size,
                  "noise_N": CONDITIONS[rid[0]][5], "stop_reason": d.stop_reason,
                  "summary_first": d.summary().splitlines()[0]}
    out.write_text(json.dumps(j, indent=1, default=str))
    print(d.summary())
    for w in d.warnings:
        print("warning:", w)


def row(out: Path, rid: str) -> dict:
    p = out / f"{rid}.json"
    cond, effect = rid.split("_", 1)
    key, ok_first = KEYS[effect]
    r = {"id": rid, "effect": effect, "time": "?"}
    tf = out / f"{rid}.time"
    if tf.exists():
        r["time"] = tf.read_text().strip()
    if not p.exists():
        ef = out / f"{rid}.err"
        err = [ln for ln in (ef.read_text().splitlines() if ef.exists() else []) if ln.strip()]
        rc = (out / f"{rid}.rc").read_text().strip() if (out / f"{rid}.rc").exists() else "?"
        r["error"] = f"rc {rc}: " + (err[-1] if err else "no output")[:200]
        return r
    j = json.loads(p.read_text())
    s = j["sweep"]
    eff = j["final"]["parameters"].get("effects", {})
    added = [st["effect"] for st in j["steps"]]
    r["added"] = added
    r["size"] = s["effect_rms_N"]
    r["noise"] = s["noise_N"]
    tv = s["truth"].get(key) if key else None
    fitted = None
    for name in (effect, "smooth_friction" if effect in ("coulomb_friction", "freeplay")
                 else None, "coulomb_friction" if effect == "smooth_friction" else None):
        if name and name in eff and key in eff[name]:
            fitted = eff[name][key]
            break
    r["key"] = (f"{key}={fitted:.3g} vs {tv:.3g} ({fitted / tv - 1:+.0%})"
                if fitted is not None and tv else (f"{key}: not fitted (truth {tv:.3g})"
                                                   if tv else "-"))
    r["key_err"] = abs(fitted / tv - 1) if fitted is not None and tv else None
    before = j["baseline"]["heldout_records"]
    after = j["heldout"]
    r["before"] = max(before.values())
    r["after"] = max(after.values())
    r["stop"] = s["stop_reason"]
    r["first"] = s["summary_first"]
    r["seconds"] = s["seconds"]
    # classes
    cls = []
    absent = r["size"] is not None and r["size"] < 0.1 * r["noise"] / math.sqrt(
        max(1.0, CONDITIONS[cond][4]))
    if effect == "null" or absent:
        if absent:
            cls.append("effect absent from the record (its RMS force far below the noise)")
        if added:
            cls.append("spurious extra effects")
    else:
        if not added:
            cls.append("effect missed")
        elif added[0] not in ok_first:
            cls.append("wrong effect first")
        if added and r["key_err"] is not None and r["key_err"] > 0.3:
            cls.append("parameter > 30 % off")
        if len(added) > 1:
            cls.append("spurious extra effects")
    if r["after"] > r["before"]:
        cls.append("held-out worse")
    elif effect != "null" and not absent and r["after"] > 0.5 * r["before"]:
        cls.append("held-out not halved")
    if s["seconds"] > 120:
        cls.append("very slow")
    r["classes"] = cls
    return r


def table(out: Path, ids) -> str:
    lines = ["| record | effect rms / noise [N] | added (order) | key parameter vs truth "
             "| held-out NRMSE before->after | stop reason | diagnose s (whole subprocess s, load "
             "at its start) | failure classes |",
             "|---|---|---|---|---|---|---|---|"]
    for rid in ids:
        r = row(out, rid)
        if "error" in r:
            slow = r["error"].startswith("rc 124")
            lines.append(f"| {rid} | | {'TIMEOUT' if slow else 'CRASH'} | | | {r['error']} "
                         f"| {r['time']} | {'very slow (timeout)' if slow else 'crash'} |")
            continue
        size = f"{r['size']:.3g} / {r['noise']:g}" if r["size"] is not None else \
            f"- / {r['noise']:g}"
        lines.append(f"| {rid} | {size} | {','.join(r['added']) or '-'} | {r['key']} "
                     f"| {r['before']:.4g}->{r['after']:.4g} | {r['stop'][:90]} "
                     f"| {r['seconds']:.0f} ({r['time']}) "
                     f"| {'; '.join(r['classes']) or 'ok'} |")
    return "\n".join(lines) + "\n"


def run_each(script: Path, ids, out: Path) -> None:
    """``script one ID OUT`` for each record in its own subprocess under ``timeout 300``,
    one at a time: OUT/ID.{out,err,rc,time} (the time with the load at its start)."""
    env = {**os.environ, "PYTHONPATH": str(script.parents[2])}
    for rid in ids:
        load = os.getloadavg()[0]
        t0 = time.time()
        with open(out / f"{rid}.out", "w") as fo, open(out / f"{rid}.err", "w") as fe:
            rc = subprocess.call(["timeout", "300", sys.executable, str(script), "one",
                                  rid, str(out)], stdout=fo, stderr=fe, env=env)
        (out / f"{rid}.rc").write_text(f"{rc}\n")
        (out / f"{rid}.time").write_text(f"{time.time() - t0:.1f} (load {load:.2f})\n")
        print(rid, rc, f"{time.time() - t0:.0f} s", flush=True)


def main(argv):
    mode = argv[1]
    if mode == "one":
        one(argv[2], Path(argv[3]) / f"{argv[2]}.json")
        return
    out = Path(argv[2])
    out.mkdir(parents=True, exist_ok=True)
    ids = argv[3:] or RECORDS
    if mode == "all":
        run_each(Path(__file__).resolve(), ids, out)
    ids = [i for i in ids if (out / f"{i}.rc").exists() or (out / f"{i}.json").exists()]
    text = (f"# Held-out sweep (runs/s10_unseen/sweep.py), {out}\n\nload average at the end: "
            f"{os.getloadavg()}\n\n" + table(out, ids))
    (out / "table.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main(sys.argv)
