"""Held-out sweep 2: test conditions runs/s10_unseen/sweep.py never met (issue 19).

    python runs/s11_combo/sweep.py all OUTDIR [ID ...]   # every record (or those named)
    python runs/s11_combo/sweep.py one ID OUTDIR         # one record (what `all` runs)
    python runs/s11_combo/sweep.py table OUTDIR [ID ...] # OUTDIR/*.json -> table.md

`all` runs each record pair in its own subprocess under ``timeout 300`` (one at a time) and
writes OUTDIR/ID.{json,out,err,rc,time}, then the table (OUTDIR/table.md).  Each pair is
diagnosed as ``liquidamp diagnose CAL --validate VAL`` does (``diagnose([cal], [val])``, no
options); the truth (effects and their parameters, the test) is written beside the result.

Effect strengths are runs/s10_unseen/sweep.py's fractions of the device's own calibration
force amplitude F0 (first harmonic, no effects), peak pressure F0 / A_p and peak flow
A_p w Y (its ``truth``, imported; the conditions below are registered in its ``CONDITIONS``
in this process only).  F0: reference 598 N and paper_calibrated 531 N at 3 Hz 3 mm,
device_b 118 N at 5 Hz 2 mm, device_a 204 N at 1.5 Hz 5 mm (s10's value).

What is new against s10 (one effect at a time, clean sines, three presets):

- two effects at once (Coulomb friction + leakage on device_a; freeplay + asymmetric loss on
  the reference preset; force offset + moving mass on device_b);
- a short record (4 cycles) and a low sampling rate (100 Hz at 3 Hz: 33 samples a cycle);
- dual-frequency strokes as rotorcraft lag-damper tests use (1/rev + lag frequency: 4 Hz +
  1.3 Hz summed) for the calibration record, and for both records;
- a sine whose stroke drifts by 2 % of its amplitude over the record (actuator mean drift);
- coloured load-cell noise (white noise through a 2nd-order Butterworth low-pass at 10 Hz,
  the same RMS: a conditioning amplifier's band or rig vibration, not white);
- a mean stroke offset (absolute stroke about -10 mm on the double-rod device: the chambers
  are not at V01, V02 about the mean);
- calibration and validation at the same frequency and different amplitudes.

Records with a plain (distorted) sine use the library's generator
(:func:`liquidamp.analysis.measured.synthetic.synthetic_record`); the others
(:func:`custom_record`) march the same model (``integrate``, LSODA) under a summed stroke from
rest over a settling time of ten periods of the slowest component, then sample it with the
same LVDT (2 um) and load-cell noise, through ``Record.from_arrays``.
"""
import json
import math
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np


def _load_s10():
    """runs/s10_unseen/sweep.py as module ``s10_sweep`` (both files are named sweep.py)."""
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "s10_unseen" / "sweep.py"
    spec = importlib.util.spec_from_file_location("s10_sweep", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


S10 = _load_s10()

#: conditions registered in S10.CONDITIONS (for its ``truth``): preset, (f, Y) cal, (f, Y) val,
#: rate [Hz], cycles, noise [N], seed base, F0 [N]
S10.CONDITIONS.update({
    "R": ("reference", (3.0, 0.003), (4.0, 0.002), 200.0, 10.0, 1.0, 4100, 598.0),
    "P": ("paper_calibrated", (3.0, 0.003), (4.0, 0.002), 200.0, 10.0, 1.0, 4300, 531.0),
    "D": ("device_b", (5.0, 0.002), (3.0, 0.0025), 500.0, 10.0, 0.5, 4500, 118.0),
})


@dataclass(frozen=True)
class SumStroke:
    """y = mean + sum_k Y_k sin(2 pi f_k t + phi_k) + drift Y_1 (t / T_rec - 1/2) [m].

    ``parts``: ((Y [m], f [Hz], phase [rad]), ...); ``drift``: mean change over the record
    ``t_rec`` [s] as a fraction of the first component's amplitude.  Callable t -> (y, v, a).
    """

    parts: tuple
    mean: float = 0.0
    drift: float = 0.0
    t_rec: float = 1.0

    def arrays(self, t):
        t = np.asarray(t, float)
        y = self.mean + self.drift * self.parts[0][0] * (t / self.t_rec - 0.5)
        v = np.full_like(t, self.drift * self.parts[0][0] / self.t_rec)
        a = np.zeros_like(t)
        for Y, f, ph in self.parts:
            w = 2 * math.pi * f
            s, c = np.sin(w * t + ph), np.cos(w * t + ph)
            y = y + Y * s
            v = v + Y * w * c
            a = a - Y * w * w * s
        return y, v, a

    def __call__(self, t):
        y, v, a = self.arrays(np.array([float(t)]))
        return float(y[0]), float(v[0]), float(a[0])


def _noise(rng, n, rms, rate, colour_hz):
    e = rng.normal(0.0, 1.0, n)
    if colour_hz:
        from scipy.signal import butter, sosfilt

        e = sosfilt(butter(2, colour_hz, fs=rate, output="sos"), np.r_[rng.normal(0, 1, n), e])[n:]
        e = e / np.std(e)
    return rms * e


def custom_record(preset, stroke, rate, duration, effects, noise, seed, colour_hz=0.0,
                  slowest_hz=1.0):
    """A record of ``preset`` + ``effects`` under ``stroke`` (a SumStroke) [SI]."""
    from liquidamp.analysis.measured.record_model import integrate
    from liquidamp.analysis.measured.records import Record
    from liquidamp.device import preset as get_preset
    from liquidamp.device.effects import make_effect, with_effects
    from liquidamp.device.models import get_model

    params = get_preset(preset)
    model = with_effects(get_model("full"), *(make_effect(k, **v) for k, v in effects.items()))
    model.check_params(params)
    rng = np.random.default_rng(seed)
    n = int(round(duration * rate)) + 1
    t = np.arange(n) / rate
    fmax = max(f for _, f, _ in stroke.parts)
    t_settle = np.linspace(-10.0 / slowest_hz, 0.0, 401)
    x0 = model.initial_state(params, stroke(t_settle[0])[0])
    Xs = integrate(model, params, stroke, t_settle, x0, rtol=1e-8, atol_scale=1e-10,
                   hmax=1.0 / (200.0 * fmax))
    X = integrate(model, params, stroke, t, Xs[:, -1], rtol=1e-8, atol_scale=1e-10,
                  hmax=1.0 / (200.0 * fmax))
    y, v, a = stroke.arrays(t)
    force = np.asarray(model.force(t, X, (y, v, a), params), float) * np.ones(n)
    y_meas = y + rng.normal(0.0, 2e-6, n)
    f_meas = force + _noise(rng, n, noise, rate, colour_hz)
    meta = {"true_force": force[10:n - 10], "true_effects": effects,
            "recipe": {"preset": preset, "stroke": repr(stroke), "sampling_rate [Hz]": rate,
                       "duration [s]": duration, "force_noise [N]": noise,
                       "colour_hz": colour_hz, "seed": seed}}
    return Record.from_arrays(t + 1.0, y_meas, f_meas, meta=meta)


def _dual(f1, y1, f2, y2, seed):
    ph = np.random.default_rng(seed).uniform(-math.pi, math.pi, 2)
    return SumStroke(((y1, f1, float(ph[0])), (y2, f2, float(ph[1]))))


#: record -> (condition, effects, how): how is a dict of departures from the condition
SPEC = {
    "A_fric_leak": ("A", ("coulomb_friction", "leakage"), {}),
    "R_freeplay_asym": ("R", ("freeplay", "asymmetric_loss"), {}),
    "D_offset_mass": ("D", ("force_offset", "moving_mass"), {}),
    "R_short4": ("R", ("coulomb_friction",), {"cycles": 4.0}),
    "P_rate100": ("P", ("leakage",), {"rate": 100.0}),
    "R_dual_cal": ("R", ("coulomb_friction",), {"dual": (0,)}),
    "R_dual_both_null": ("R", (), {"dual": (0, 1)}),
    "R_drift": ("R", ("series_compliance",), {"drift": 0.02}),
    "R_colour_null": ("R", (), {"colour_hz": 10.0}),
    "D_colour_fric": ("D", ("coulomb_friction",), {"colour_hz": 10.0}),
    "R_mean_m10mm": ("R", ("leakage",), {"mean": -0.010}),
    "P_same_f": ("P", ("relief_valve",), {"val": (3.0, 0.0015)}),
}
RECORDS = list(SPEC)


def truth(rid):
    cond, effects, _ = SPEC[rid]
    return {e: S10.truth(cond, e) for e in effects}


def records(rid, with_effect=True):
    """(cal, val) of record ``rid``."""
    from liquidamp.analysis.measured.synthetic import synthetic_record

    cond, effects, how = SPEC[rid]
    pre, cal, val, rate, cycles, noise, seed0, _ = S10.CONDITIONS[cond]
    val = how.get("val", val)
    rate = how.get("rate", rate)
    cycles = how.get("cycles", cycles)
    eff = truth(rid) if with_effect else {}
    k = RECORDS.index(rid)
    out = []
    for i, (f, y) in enumerate((cal, val)):
        seed = seed0 + 10 * k + i
        custom = i in how.get("dual", ()) or "drift" in how or "colour_hz" in how \
            or "mean" in how
        if not custom:
            out.append(synthetic_record(preset=pre, frequency=f, amplitude=y, cycles=cycles,
                                        sampling_rate=rate, force_noise=noise, seed=seed,
                                        effects=eff))
            continue
        if i in how.get("dual", ()):
            # 1/rev at 4 Hz (3.5 Hz for val) + lag mode 1.3 Hz (1.1 Hz), each half the
            # condition's stroke so that the peak stroke is about the sine's
            f1, f2 = (4.0, 1.3) if i == 0 else (3.5, 1.1)
            stroke, dur, slow = _dual(f1, 0.5 * y, f2, 0.6 * y, seed), cycles / f2, f2
        else:
            ph = float(np.random.default_rng(seed).uniform(-math.pi, math.pi))
            dur = cycles / f
            stroke = SumStroke(((y, f, ph), (0.01 * y, 3 * f, 2 * ph)),
                               mean=how.get("mean", 0.0), drift=how.get("drift", 0.0),
                               t_rec=dur)
            slow = f
        out.append(custom_record(pre, stroke, rate, dur, eff, noise, seed,
                                 how.get("colour_hz", 0.0), slow))
    return tuple(out)


def one(rid: str, out: Path) -> None:
    from liquidamp.analysis.measured.diagnosis import diagnose

    t0 = time.perf_counter()
    cal, val = records(rid)
    size = None
    if SPEC[rid][1]:
        bare = records(rid, with_effect=False)[0]
        size = float(np.sqrt(np.mean((cal.meta["true_force"] - bare.meta["true_force"]) ** 2)))
    t_make = time.perf_counter() - t0
    t0 = time.perf_counter()
    d = diagnose([cal], [val])
    sec = time.perf_counter() - t0
    j = d.as_dict()
    cond, effects, how = SPEC[rid]
    j["sweep"] = {"id": rid, "condition": S10.CONDITIONS[cond], "departures": how,
                  "truth": truth(rid), "seconds": sec, "seconds_make": t_make,
                  "effect_rms_N": size, "noise_N": S10.CONDITIONS[cond][5],
                  "stop_reason": d.stop_reason, "summary_first": d.summary().splitlines()[0]}
    out.write_text(json.dumps(j, indent=1, default=str))
    print(d.summary())
    for w in d.warnings:
        print("warning:", w)


def row(out: Path, rid: str) -> dict:
    cond, effects, how = SPEC[rid]
    r = {"id": rid, "time": "?"}
    tf = out / f"{rid}.time"
    if tf.exists():
        r["time"] = tf.read_text().strip()
    p = out / f"{rid}.json"
    if not p.exists():
        ef = out / f"{rid}.err"
        err = [ln for ln in (ef.read_text().splitlines() if ef.exists() else []) if ln.strip()]
        rc = (out / f"{rid}.rc").read_text().strip() if (out / f"{rid}.rc").exists() else "?"
        r["error"] = f"rc {rc}: " + (err[-1] if err else "no output")[:200]
        r["classes"] = ["timeout" if rc == "124" else "crash/refused"]
        return r
    j = json.loads(p.read_text())
    s = j["sweep"]
    eff = j["final"]["parameters"].get("effects", {})
    added = [st["effect"] for st in j["steps"]]
    r.update(added=added, size=s["effect_rms_N"], noise=s["noise_N"], stop=s["stop_reason"],
             seconds=s["seconds"])
    keys, cls, right = [], [], set()
    for e in effects:
        key, ok = S10.KEYS[e]
        tv = s["truth"][e][key]
        hit = [a for a in added if a in ok]
        fitted = next((eff[a][key] for a in hit if key in eff.get(a, {})), None)
        keys.append(f"{key}={fitted:.3g} vs {tv:.3g} ({fitted / tv - 1:+.0%})"
                    if fitted is not None else f"{e}: not found (truth {key}={tv:.3g})")
        if hit:
            right.update(hit[:1])
            if fitted is not None and abs(fitted / tv - 1) > 0.3:
                cls.append(f"{e} parameter > 30 % off")
        else:
            cls.append(f"missed {e}")
    extra = [a for a in added if a not in right]
    if extra:
        cls.append("spurious extra: " + ",".join(extra) if right or not effects
                   else "wrong effect: " + ",".join(extra))
    r["key"] = "; ".join(keys) or "-"
    r["before"] = max(j["baseline"]["heldout_records"].values())
    r["after"] = max(j["heldout"].values())
    if r["after"] > r["before"]:
        cls.append("held-out worse")
    r["classes"] = cls
    return r


def table(out: Path, ids) -> str:
    lines = ["| record | truth | effect rms / noise [N] | added (order) | key parameters vs "
             "truth | held-out NRMSE before->after | stop reason | diagnose s (subprocess s, "
             "load at start) | class |", "|---|---|---|---|---|---|---|---|---|"]
    for rid in ids:
        r = row(out, rid)
        tr = "+".join(SPEC[rid][1]) or "null"
        if "error" in r:
            lines.append(f"| {rid} | {tr} | | | | | {r['error']} | {r['time']} "
                         f"| {r['classes'][0]} |")
            continue
        size = f"{r['size']:.3g} / {r['noise']:g}" if r["size"] is not None else \
            f"- / {r['noise']:g}"
        lines.append(f"| {rid} | {tr} | {size} | {','.join(r['added']) or '-'} | {r['key']} "
                     f"| {r['before']:.4g}->{r['after']:.4g} | {r['stop'][:90]} "
                     f"| {r['seconds']:.0f} ({r['time']}) | {'; '.join(r['classes']) or 'right'} |")
    return "\n".join(lines) + "\n"


def main(argv):
    mode = argv[1]
    if mode == "one":
        one(argv[2], Path(argv[3]) / f"{argv[2]}.json")
        return
    out = Path(argv[2])
    out.mkdir(parents=True, exist_ok=True)
    ids = argv[3:] or RECORDS
    if mode == "all":
        S10.run_each(Path(__file__).resolve(), ids, out)
    ids = [i for i in ids if (out / f"{i}.rc").exists() or (out / f"{i}.json").exists()]
    text = (f"# Held-out sweep 2 (runs/s11_combo/sweep.py), {out}\n\nload average at the end: "
            f"{os.getloadavg()}\n\n" + table(out, ids))
    (out / "table.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main(sys.argv)
