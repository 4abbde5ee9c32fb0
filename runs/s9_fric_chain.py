"""Feasibility measurement for issue #19's friction-damper must-show (session 9, s9-fric).

A stand-alone model of the physical chain of a banded rotary friction damper (rack and
pinion with backlash driving a braked drum), fitted to the friction-damper records outside
the catalogue, to measure whether a contact mass / rig mode behind the dead band can bring
the 1 Hz held-out NRMSE to 0.13 when calibrated on the 0.5 Hz record (it cannot: see
runs/s9_fric_report.md).

Chain: the measured stroke x drives, through a dead band of half-width g, a compliant
contact (stiffness k_c [N/m], viscous damping c_c = 2 zeta_c sqrt(k_c m) [N s/m], pushing
only, zero in the gap) the reflected mass m [kg] of the pinion and drum; the drum is braked
by Dahl friction (pre-sliding stiffness k_f [N/m], level F_c forward and rr F_c in reverse
[N]) plus a small viscous term c_0 [N s/m].  The mass starts at rest at
z(0) = x(0) + (u0 - 1) g (u0 = 1: centred in the dead band; 0 or 2: in contact).
The load cell reads the contact force.

    m z'' = F_k - F_f,   F_k = k_c d + c_c (x' - z') (in contact, d = dead-band excess),
    F_f = L(s) s + c_0 z',   s' = (k_f / L(s)) z' (1 - s sgn z'),  L = F_c (s >= 0), rr F_c.

Limits: m -> 0 and k_c -> inf give the quasi-static dead band plus Dahl friction (the
catalogue's ``freeplay`` + ``smooth_friction`` at the piston, without the fluid); the
contact mode's natural frequency in sliding is sqrt(k_c / m) / (2 pi) and with the drum
stuck sqrt((k_c k_f / (k_c + k_f)) / m) / (2 pi).

The model force at the record's samples is conditioned as the record was (the default
:func:`liquidamp.analysis.measured.conditioning.condition`, ``harmonics`` for the
calibration record on request) before the NRMSE, as the diagnosis compares them.

Data: Coble, Huggins, Cao, Ricles, Downey (2022), Dataset-Friction-Damper-with-Backlash
(ARTS-Laboratory), CC BY-SA 4.0; the converted records in
``$LIQUIDAMP_SHARED/data/friction-damper-backlash``.

Usage (from the worktree root)::

    python runs/s9_fric_chain.py steady --fit Fc,rr,kf,g,zc --on 0.5Hz m=50 kc=1e7
    python runs/s9_fric_chain.py steady --fit Fc,rr --on 1Hz m=50 kc=9.5e6 ... --plot F.png
"""

from __future__ import annotations

import argparse
import os
import time
import warnings

import numpy as np
from numba import njit
from scipy.optimize import least_squares

from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.record_model import nrmse
from liquidamp.analysis.measured.records import read_record

NAMES = ("Fc", "rr", "kf", "g", "m", "kc", "zc", "c0", "u0")
START = {"Fc": 1.25e4, "rr": 0.7, "kf": 4.5e6, "g": 1.5e-3, "m": 50.0, "kc": 1e7,
         "zc": 0.05, "c0": 1.0, "u0": 1.0}
LOW = {"Fc": 1e3, "rr": 0.3, "kf": 1e5, "g": 1e-5, "m": 1e-2, "kc": 1e5, "zc": 1e-3,
       "c0": 1e-2, "u0": 1e-3}
HIGH = {"Fc": 1e5, "rr": 3.0, "kf": 1e9, "g": 5e-3, "m": 1e4, "kc": 1e10, "zc": 2.0,
        "c0": 1e6, "u0": 2.0}
RECORDS = ("0.5Hz", "1Hz", "0.25Hz")


@njit(cache=True)
def _rates(x, v, z, zd, s, p):
    Fc, rr, kf, g, m, kc, zc, c0 = p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]
    e = x - z
    d = e - g if e > g else (e + g if e < -g else 0.0)
    Fk = 0.0
    if d != 0.0:
        Fk = kc * d + 2.0 * zc * np.sqrt(kc * m) * (v - zd)
        if d * Fk < 0.0:  # the contact pushes only
            Fk = 0.0
    lev = Fc if s >= 0.0 else rr * Fc
    sg = 1.0 if zd >= 0.0 else -1.0
    return Fk, zd, (Fk - lev * s - c0 * zd) / m, kf / lev * zd * (1.0 - s * sg)


@njit(cache=True)
def chain_force(t, X, V, p, sub):
    """Load-cell force [N] of the chain at the samples t [s] of the stroke X [m], V [m/s]
    (classical Runge-Kutta, ``sub`` steps per sample, stroke linear between samples)."""
    n = t.size
    out = np.zeros(n)
    z = X[0] - p[3] + p[8] * p[3]  # the mass's start in the dead band
    zd = 0.0
    s = 0.0
    for i in range(n - 1):
        h = (t[i + 1] - t[i]) / sub
        dX = X[i + 1] - X[i]
        dV = V[i + 1] - V[i]
        for j in range(sub):
            a0, a1, a2 = j / sub, (j + 0.5) / sub, (j + 1.0) / sub
            _, k1z, k1v, k1s = _rates(X[i] + a0 * dX, V[i] + a0 * dV, z, zd, s, p)
            _, k2z, k2v, k2s = _rates(X[i] + a1 * dX, V[i] + a1 * dV, z + 0.5 * h * k1z,
                                      zd + 0.5 * h * k1v, s + 0.5 * h * k1s, p)
            _, k3z, k3v, k3s = _rates(X[i] + a1 * dX, V[i] + a1 * dV, z + 0.5 * h * k2z,
                                      zd + 0.5 * h * k2v, s + 0.5 * h * k2s, p)
            _, k4z, k4v, k4s = _rates(X[i] + a2 * dX, V[i] + a2 * dV, z + h * k3z,
                                      zd + h * k3v, s + h * k3s, p)
            z += h / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z)
            zd += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
            s = min(1.0, max(-1.0, s + h / 6.0 * (k1s + 2.0 * k2s + 2.0 * k3s + k4s)))
        out[i + 1] = _rates(X[i + 1], V[i + 1], z, zd, s, p)[0]
    return out


class Chain:
    """The three records of one kind, conditioned, and the chain's NRMSE on them."""

    def __init__(self, kind: str, harmonics: float = 30.0, fit_on: str = "0.5Hz",
                 sub: int = 8):
        shared = os.environ.get("LIQUIDAMP_SHARED", os.path.join(
            os.path.dirname(__file__), "..", "..", "shared"))
        d = os.path.join(shared, "data", "friction-damper-backlash")
        self.raw = {f: read_record(os.path.join(d, f"brfd30_{f}_0.5in_{kind}.csv"))
                    for f in RECORDS}
        self.cond = {f: condition(r, harmonics=harmonics if f in fit_on.split("+")
                                  else 30.0) for f, r in self.raw.items()}
        self.sub = sub

    def force(self, f: str, q: dict) -> np.ndarray:
        """Conditioned model force [N] on record ``f`` at parameters ``q``."""
        r = self.raw[f]
        F = chain_force(r.time, r.displacement, r.velocity,
                        np.array([q[k] for k in NAMES]), self.sub)
        return self.cond[f][1].model_force(F)

    def score(self, f: str, q: dict) -> float:
        """NRMSE of the chain on record ``f`` [-]."""
        return nrmse(self.force(f, q), self.cond[f][0].force)

    def fit(self, q0: dict, keys, on: str) -> tuple[dict, int]:
        """Least squares (log parameters) of ``keys`` on the records ``on`` ('a+b')."""
        recs = on.split("+")

        def res(x):
            q = dict(q0)
            q.update({k: np.exp(v) for k, v in zip(keys, x, strict=True)})
            return np.concatenate([
                (self.force(f, q) - self.cond[f][0].force)
                / (np.std(self.cond[f][0].force) * np.sqrt(self.cond[f][0].force.size))
                for f in recs])

        x0 = [np.log(min(max(q0[k], LOW[k] * 1.0001), HIGH[k] / 1.0001)) for k in keys]
        s = least_squares(res, x0, bounds=([np.log(LOW[k]) for k in keys],
                                           [np.log(HIGH[k]) for k in keys]),
                          diff_step=1e-3, max_nfev=200)
        q = dict(q0)
        q.update({k: float(np.exp(v)) for k, v in zip(keys, s.x, strict=True)})
        return q, s.nfev


def _plot(chain: Chain, q: dict, path: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(3, 2, figsize=(14, 11))
    for i, f in enumerate(RECORDS):
        r, (rc, _) = chain.raw[f], chain.cond[f]
        Fm = chain.force(f, q)
        ax[i, 0].plot(r.time, r.force / 1e3, color="0.7", lw=0.4, label="record as read")
        ax[i, 0].plot(rc.time, rc.force / 1e3, "k", lw=0.8, label="conditioned")
        ax[i, 0].plot(rc.time, Fm / 1e3, "r", lw=0.8, label="chain")
        ax[i, 0].set(title=f"{f}: NRMSE {nrmse(Fm, rc.force):.4f}", xlabel="t [s]",
                     ylabel="force [kN]")
        ax[i, 1].plot(r.displacement * 1e3, r.force / 1e3, color="0.7", lw=0.4)
        ax[i, 1].plot(rc.displacement * 1e3, Fm / 1e3, "r", lw=0.8)
        ax[i, 1].set(xlabel="stroke [mm]", ylabel="force [kN]")
    ax[0, 0].legend(loc="lower right")
    fig.suptitle("rack-backlash-mass-Dahl chain; data: Coble, Huggins, Cao, Ricles, Downey "
                 "2022, CC BY-SA 4.0")
    fig.tight_layout()
    fig.savefig(path, dpi=80)


def main(argv=None) -> None:
    """Command line (module docstring)."""
    warnings.filterwarnings("ignore")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kind", choices=("steady", "full"))
    ap.add_argument("values", nargs="*", help="NAME=VALUE starts/fixed values (SI)")
    ap.add_argument("--fit", default="", help="comma-separated parameters to fit")
    ap.add_argument("--on", default="0.5Hz", help="record(s) fitted, e.g. 0.5Hz or 1Hz")
    ap.add_argument("--harmonics", type=float, default=30.0,
                    help="harmonics kept by the fitted records' conditioning")
    ap.add_argument("--plot", default="", help="write a figure of the result")
    a = ap.parse_intermixed_args(argv)
    q = dict(START)
    for kv in a.values:
        k, v = kv.split("=")
        if k not in NAMES:
            raise SystemExit(f"unknown parameter {k!r}; valid: {', '.join(NAMES)}")
        q[k] = float(v)
    chain = Chain(a.kind, a.harmonics, a.on)
    t0 = time.time()
    nfev = 0
    if a.fit:
        q, nfev = chain.fit(q, a.fit.split(","), a.on)
    fn = np.sqrt(q["kc"] / q["m"]) / (2.0 * np.pi)
    print(f"{a.kind} fit {a.fit or '-'} on {a.on} (harmonics {a.harmonics:g}): "
          + " ".join(f"{k}={q[k]:.4g}" for k in NAMES)
          + f" f_contact={fn:.1f}Hz nfev={nfev} {time.time() - t0:.0f}s")
    print("  NRMSE " + " ".join(f"{f} {chain.score(f, q):.4f}" for f in RECORDS))
    if a.plot:
        _plot(chain, q, a.plot)


if __name__ == "__main__":
    main()
