"""Record pairs (cal + val) of dampers OUTSIDE liquidamp's model family, each coded here from
the literature (not with liquidamp's models), written as CSV to /tmp/s12_outside/ (or argv[1]).

Usage: ``PYTHONPATH=. python runs/s12_outside/make.py [OUTDIR]``

Physics (each integrated with scipy's solve_ivp on the prescribed stroke):

- fvd_a03, fvd_a06: building fluid-viscous damper F = C |v|^alpha sign(v) + k_acc y
  (Constantinou & Symans 1993; Symans et al. 2008), alpha 0.3 / 0.6, strokes 25-50 mm, kN,
  cal 0.5 Hz / val 1.5 Hz; the accumulator spring k_acc is 2 % of the peak force over the stroke.
- mr_spencer: Spencer, Dyke, Sain & Carlson (1997) phenomenological MR damper (Bouc-Wen with
  the filtered-velocity extension), the paper's parameters at a constant 1 V, sine strokes.
- veh_dyno: a vehicle damper on a scotch-yoke dyno, 300 Hz, +-18 mm about -31 mm, gas preload
  30 N + 0.8 N/mm gas spring, digressive bleed + blow-off valving (rebound/compression
  curves differ), seal friction 25 N (Dixon 2007, The Shock Absorber Handbook, ch. 5-7).
- lag_elastomer: elastomeric lag damper, elastic spring + 3-term Maxwell ladder + an
  elasto-plastic (Berg 1998) friction element that makes stiffness and damping depend on
  amplitude; cal 1 Hz / val 5 Hz at 2 kHz.
- dahl_spring: Dahl (1968) friction element with a parallel spring (no fluid at all).
- veh_programme: the vehicle damper's dyno test programme (four peak velocities in sequence,
  each 5 cycles) vs one 1.5 Hz record.
- lag_chirp: the lag damper under a 0.5-8 Hz sine sweep vs a 3 Hz sine.
- fvd_kn_in: fvd_a06 written in inches and kN.
- veh_ringing: the vehicle damper with a 10 Hz rig resonance between damper and
  load cell (zeta 0.05), ringing after each reversal's friction step.
- veh_drift: the vehicle damper with a load-cell zero drift (2 % of the peak force, linear
  plus a slow thermal swing).

Noise: load-cell white noise 0.2-1 % of the peak force, stroke noise 5 um, quantised
(force to 0.5 N or 0.05 kN, stroke to 2.5 um).
"""

from __future__ import annotations

import json
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

RNG = np.random.default_rng(20261126)


def sine(amp, freq, mean=0.0, phase=0.0):
    """Stroke y(t), v(t) [m, m/s] of a sine."""
    w = 2 * np.pi * freq
    return (lambda t: mean + amp * np.sin(w * t + phase),
            lambda t: amp * w * np.cos(w * t + phase))


def programme(amps_freqs, cycles=5, mean=0.0):
    """Several sines in sequence (each a whole number of cycles, starting at y = mean)."""
    edges = [0.0]
    for _, f in amps_freqs:
        edges.append(edges[-1] + cycles / f)

    def seg(t):
        i = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, len(amps_freqs) - 1)
        return i, t - np.asarray(edges)[i]

    def y(t):
        i, tl = seg(t)
        a = np.asarray([af[0] for af in amps_freqs])[i]
        f = np.asarray([af[1] for af in amps_freqs])[i]
        return mean + a * np.sin(2 * np.pi * f * tl)

    def v(t):
        i, tl = seg(t)
        a = np.asarray([af[0] for af in amps_freqs])[i]
        f = np.asarray([af[1] for af in amps_freqs])[i]
        return a * 2 * np.pi * f * np.cos(2 * np.pi * f * tl)
    return y, v, edges[-1]


def chirp(amp, f0, f1, duration):
    """Linear sine sweep from f0 to f1 [Hz] over duration [s], amplitude amp [m]."""
    k = (f1 - f0) / duration

    def y(t):
        return amp * np.sin(2 * np.pi * (f0 * t + 0.5 * k * t * t))

    def v(t):
        return amp * 2 * np.pi * (f0 + k * t) * np.cos(2 * np.pi * (f0 * t + 0.5 * k * t * t))
    return y, v


def integrate(rhs, x0, t, y, v):
    sol = solve_ivp(lambda tt, x: rhs(tt, x, y(tt), v(tt)), (t[0], t[-1]), x0, t_eval=t,
                    method="LSODA", rtol=1e-7, atol=1e-10, max_step=(t[1] - t[0]))
    if not sol.success:
        raise RuntimeError(sol.message)
    return sol.y


# ---- (a) fluid-viscous damper ---------------------------------------------------------
def fvd(alpha, c, k_acc):
    def force(t, y, v):
        return c * np.abs(v(t)) ** alpha * np.sign(v(t)) + k_acc * y(t)
    return force


# ---- (b) Spencer 1997 MR damper -------------------------------------------------------
SPENCER = dict(c0a=21.0e2, c0b=3.50e2, k0=46.9e2, c1a=283e2, c1b=2.95e2, k1=5.00e2, x0=0.143,
               aa=140e2, ab=695e2, gamma=363e4, beta=363e4, A=301.0, n=2, eta=190.0)


def spencer(volt, t, y, v):
    p = SPENCER
    u = volt  # steady voltage: the first-order filter du/dt = -eta (u - V) has settled
    c0 = p["c0a"] + p["c0b"] * u
    c1 = p["c1a"] + p["c1b"] * u
    al = p["aa"] + p["ab"] * u

    def rhs(tt, x, yy, vv):
        z, yi = x  # Bouc-Wen z [m], internal displacement y [m]
        yd = (al * z + c0 * vv + p["k0"] * (yy - yi)) / (c0 + c1)
        dv = vv - yd
        zd = (-p["gamma"] * abs(dv) * z * abs(z) ** (p["n"] - 1) - p["beta"] * dv * abs(z) ** p["n"]
              + p["A"] * dv)
        return [zd, yd]
    z, yi = integrate(rhs, [0.0, y(t[0])], t, y, v)
    yd = (al * z + c0 * v(t) + p["k0"] * (y(t) - yi)) / (c0 + c1)
    return c1 * yd + p["k1"] * (y(t) - p["x0"])


# ---- (c) vehicle damper -----------------------------------------------------------------
VEH = dict(reb=(2200.0, 0.025, 1200.0, 0.300, 500.0), com=(1800.0, 0.025, 1000.0, 0.350, 400.0),
           preload=30.0, k_gas=800.0, y_ref=-0.031, friction=25.0, v_fric=0.004)


def valve(vv, c_bleed, v_knee, c_blow, v_blow, c_high):
    """Digressive bleed + blow-off valve: force vs |v| (smooth knees) [N]."""
    s = np.abs(vv)
    f_knee = c_bleed * v_knee
    # bleed up to the knee, then the blow-off slope c_blow, then the high-speed slope c_high
    soft = 0.005
    f = c_bleed * s - (c_bleed - c_blow) * soft * np.logaddexp(0.0, (s - v_knee) / soft)
    f = f - (c_blow - c_high) * soft * np.logaddexp(0.0, (s - v_blow) / soft)
    del f_knee
    return f


def vehicle(t, y, v):
    p = VEH
    vv, yy = v(t), y(t)
    f = np.where(vv >= 0, valve(vv, *p["reb"]), -valve(vv, *p["com"]))
    # rod gas force pushes the rod out: on a dyno it reads as a compression (negative) preload
    f = f - p["preload"] - p["k_gas"] * (yy - p["y_ref"])
    return f + p["friction"] * np.tanh(vv / p["v_fric"])


# ---- (d) elastomeric lag damper ---------------------------------------------------------
LAG = dict(k_e=0.8e6, branches=((1.2e6, 0.4e3 * 1e0), (0.6e6, 6.0e3), (0.4e6, 4.0e4)),
           f_berg=1.2e3, x2=0.25e-3)


def lag(t, y, v):
    p = LAG
    br = p["branches"]

    def rhs(tt, x, yy, vv):
        out = []
        for (k, c), fm in zip(br, x[:3], strict=True):
            out.append(k * vv - k / c * fm)  # Maxwell: dF/dt = k v - F k/c
        fb = x[3]
        # Berg's smooth friction, in a rate form (Dahl-like, its own shape x2): it reaches
        # f_berg after about x2 of travel, softening the loop as the amplitude grows
        out.append(p["f_berg"] / p["x2"] * vv * (1 - np.sign(vv) * fb / p["f_berg"]) ** 2)
        return out
    x = integrate(rhs, [0.0, 0.0, 0.0, 0.0], t, y, v)
    return p["k_e"] * y(t) + x.sum(axis=0)


# ---- (e) Dahl friction with a spring -----------------------------------------------------
def dahl_spring(t, y, v, fc=200.0, sigma=2.0e6, k=20e3):
    def rhs(tt, x, yy, vv):
        return [sigma * vv * (1 - x[0] / fc * np.sign(vv))]
    f = integrate(rhs, [0.0], t, y, v)[0]
    return f + k * y(t)


# ---- writing --------------------------------------------------------------------------
def write(path, t, y, f, *, f_noise_rel, f_q, y_q=2.5e-6, y_noise=5e-6, disp_unit="mm",
          force_unit="N", drift=None, ringing=None):
    fs = 1 / (t[1] - t[0])
    f = np.asarray(f, float).copy()
    if ringing is not None:  # rig resonance between damper and load cell
        from scipy.signal import lsim
        fn, zeta = ringing
        wn = 2 * np.pi * fn
        _, f, _ = lsim(([wn * wn], [1, 2 * zeta * wn, wn * wn]), f, t)
    peak = np.max(np.abs(f))
    f = f + RNG.normal(0, f_noise_rel * peak, f.size)
    if drift is not None:
        f = f + drift(t, peak)
    ym = y + RNG.normal(0, y_noise, y.size)
    ym = np.round(ym / y_q) * y_q
    f = np.round(f / f_q) * f_q
    yc = ym / {"mm": 1e-3, "in": 0.0254, "m": 1.0}[disp_unit]
    fc = f / {"N": 1.0, "kN": 1e3}[force_unit]
    with open(path, "w") as fh:
        fh.write(f"time [s],displacement [{disp_unit}],force [{force_unit}]\n")
        for row in zip(t, yc, fc, strict=True):
            fh.write(f"{row[0]:.6f},{row[1]:.6g},{row[2]:.6g}\n")
    return dict(file=os.path.basename(path), fs_Hz=round(fs, 3), samples=int(t.size),
                peak_force_N=float(peak))


def times(fs, duration):
    return np.arange(int(round(duration * fs))) / fs


def main(out):
    os.makedirs(out, exist_ok=True)
    info = {}

    # (a) FVD, alpha 0.3 and 0.6: peak 400 kN at 0.25 m/s
    for tag, alpha in (("fvd_a03", 0.3), ("fvd_a06", 0.6)):
        c = 400e3 / 0.25 ** alpha
        k_acc = 0.02 * 400e3 / 0.05
        rows = []
        for kind, amp, freq, ncyc in (("cal", 0.050, 0.5, 4), ("val", 0.025, 1.5, 8)):
            y, v = sine(amp, freq, phase=0.3)
            t = times(200.0, ncyc / freq)
            rows.append(write(f"{out}/{tag}_{kind}.csv", t, y(t), fvd(alpha, c, k_acc)(t, y, v),
                              f_noise_rel=0.003, f_q=50.0, force_unit="kN"))
        info[tag] = dict(physics=f"F = C|v|^{alpha} sign v + k y", C=c, alpha=alpha,
                         k_acc_N_per_m=k_acc, records=rows)
    # (g1) the alpha 0.6 FVD in inches and kN
    c, k_acc = 400e3 / 0.25 ** 0.6, 0.02 * 400e3 / 0.05
    rows = []
    for kind, amp, freq, ncyc in (("cal", 1.5 * 0.0254, 0.5, 4), ("val", 1.0 * 0.0254, 1.0, 6)):
        y, v = sine(amp, freq)
        t = times(100.0, ncyc / freq)
        rows.append(write(f"{out}/fvd_kn_in_{kind}.csv", t, y(t), fvd(0.6, c, k_acc)(t, y, v),
                          f_noise_rel=0.003, f_q=50.0, y_q=0.0005 * 0.0254, disp_unit="in",
                          force_unit="kN"))
    info["fvd_kn_in"] = dict(physics="fvd_a06 in inches and kN", records=rows)

    # (b) Spencer MR damper at 1 V
    rows = []
    for kind, amp, freq, ncyc in (("cal", 0.010, 2.5, 6), ("val", 0.015, 1.0, 4)):
        y, v = sine(amp, freq)
        t = times(1000.0, ncyc / freq)
        rows.append(write(f"{out}/mr_spencer_{kind}.csv", t, y(t), spencer(1.0, t, y, v),
                          f_noise_rel=0.005, f_q=0.5))
    info["mr_spencer"] = dict(physics="Spencer 1997 MR damper, 1 V", params=SPENCER, records=rows)

    # (c) vehicle damper on a scotch-yoke dyno: 18 mm about -31 mm, 300 Hz
    def veh_pair(tag, cal_freq=2.3, val_freq=0.9, **kw):
        rows = []
        for kind, freq, ncyc in (("cal", cal_freq, 8), ("val", val_freq, 5)):
            y, v = sine(0.018, freq, mean=-0.031)
            t = times(300.0, ncyc / freq)
            rows.append(write(f"{out}/{tag}_{kind}.csv", t, y(t), vehicle(t, y, v),
                              f_noise_rel=0.004, f_q=0.5, **kw))
        return rows
    info["veh_dyno"] = dict(physics="vehicle damper, digressive valving, gas 30 N",
                            params=VEH, records=veh_pair("veh_dyno"))
    info["veh_ringing"] = dict(physics="veh_dyno + 10 Hz rig resonance zeta 0.05",
                               records=veh_pair("veh_ringing", ringing=(10.0, 0.05)))
    info["veh_drift"] = dict(
        physics="veh_dyno + load-cell zero drift 2 % of peak",
        records=veh_pair("veh_drift", drift=lambda t, pk: 0.02 * pk * (
            t / t[-1] + 0.3 * np.sin(2 * np.pi * t / (2 * t[-1])))))

    # (f1) the vehicle damper's dyno test programme: peak velocities 0.05, 0.1, 0.26, 0.52 m/s
    amps_freqs = [(0.018, vp / (2 * np.pi * 0.018)) for vp in (0.05, 0.10, 0.26, 0.52)]
    y, v, dur = programme(amps_freqs, cycles=5, mean=-0.031)
    t = times(300.0, dur)
    rows = [write(f"{out}/veh_programme_cal.csv", t, y(t), vehicle(t, y, v), f_noise_rel=0.004,
                  f_q=0.5)]
    y, v = sine(0.018, 1.5, mean=-0.031)
    t = times(300.0, 5 / 1.5)
    rows.append(write(f"{out}/veh_programme_val.csv", t, y(t), vehicle(t, y, v),
                      f_noise_rel=0.004, f_q=0.5))
    info["veh_programme"] = dict(physics="vehicle damper test programme",
                                 segments_Hz=[f for _, f in amps_freqs], records=rows)

    # (d) elastomeric lag damper: 1 Hz / 5 Hz at 2 kHz, +-2 mm
    rows = []
    for kind, amp, freq, ncyc in (("cal", 0.002, 1.0, 5), ("val", 0.0015, 5.0, 10)):
        y, v = sine(amp, freq)
        t = times(2000.0, ncyc / freq)
        rows.append(write(f"{out}/lag_elastomer_{kind}.csv", t, y(t), lag(t, y, v),
                          f_noise_rel=0.005, f_q=1.0))
    info["lag_elastomer"] = dict(physics="elastic + 3 Maxwell + Berg friction", params=LAG,
                                 records=rows)
    # (f2) the lag damper under a 0.5-8 Hz chirp, val a 3 Hz sine
    rows = []
    y, v = chirp(0.002, 0.5, 8.0, 20.0)
    t = times(1000.0, 20.0)
    rows.append(write(f"{out}/lag_chirp_cal.csv", t, y(t), lag(t, y, v), f_noise_rel=0.005,
                      f_q=1.0))
    y, v = sine(0.0018, 3.0)
    t = times(1000.0, 3.0)
    rows.append(write(f"{out}/lag_chirp_val.csv", t, y(t), lag(t, y, v), f_noise_rel=0.005,
                      f_q=1.0))
    info["lag_chirp"] = dict(physics="lag damper, 0.5-8 Hz chirp / 3 Hz sine", records=rows)

    # (e) Dahl friction element with a parallel spring: 10 mm at 1 Hz / 0.5 Hz, 1 kHz
    rows = []
    for kind, amp, freq, ncyc in (("cal", 0.010, 1.0, 5), ("val", 0.006, 0.5, 3)):
        y, v = sine(amp, freq)
        t = times(1000.0, ncyc / freq)
        rows.append(write(f"{out}/dahl_spring_{kind}.csv", t, y(t), dahl_spring(t, y, v),
                          f_noise_rel=0.005, f_q=0.5))
    info["dahl_spring"] = dict(physics="Dahl friction Fc 200 N sigma 2e6 N/m + spring 20 kN/m",
                               records=rows)

    with open(f"{out}/truth.json", "w") as fh:
        json.dump(info, fh, indent=1, default=float)
    print(json.dumps({k: [r["file"] for r in d["records"]] for k, d in info.items()}))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "/tmp/s12_outside")
