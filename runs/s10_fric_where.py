"""Session 10 (s10-fric): where the friction-damper residual sits, for a saved device.

Evaluates a device file (``liquidamp diagnose ... --save-device DEV.toml``) on the three
steady and the three tapered records, each conditioned as the diagnosis conditions it, and
splits the residual's mean square by cycle of the record (tapered: ramp-up, plateau,
ramp-down cycles) and by region of the cycle (dead band crossing, sliding).

Data: Coble, Huggins, Cao, Ricles, Downey (2022), Dataset-Friction-Damper-with-Backlash
(ARTS-Laboratory), CC BY-SA 4.0 (``$LIQUIDAMP_SHARED/data/friction-damper-backlash``).

Usage: ``python runs/s10_fric_where.py DEV.toml [steady|full ...]``
"""

from __future__ import annotations

import os
import sys
import warnings

import numpy as np

from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.analysis.measured.records import Record, read_record
from liquidamp.device.effects import with_effects
from liquidamp.device.models import get_model
from liquidamp.device.presets import load_device_file

RATES = ("0.5Hz", "1Hz", "0.25Hz")

#: Where the steady record starts in the tapered one [s] (the steady files are the tapered
#: ones' three full-amplitude cycles, sample for sample).
STEADY_START = {"0.25Hz": 8.02832, "0.5Hz": 4.030273, "1Hz": 2.033203}


def shifted(record, lag: float):
    """The record with its force read ``lag`` [s] later than its stroke, F'(t) = F(t + lag)
    (linear interpolation; the samples whose shifted time leaves the record are dropped)."""
    if lag == 0.0:
        return record
    t = record.time
    keep = (t + lag >= t[0]) & (t + lag <= t[-1])
    f = np.interp(t[keep] + lag, t, record.force)
    return Record.from_arrays(t[keep], record.displacement[keep], f, source=record.source)


def records(kind: str, lag: float = 0.0) -> dict:
    """The conditioned records of one kind (steady or full), by rate; force read ``lag`` [s]
    after the stroke (:func:`shifted`)."""
    shared = os.environ.get("LIQUIDAMP_SHARED", os.path.join(
        os.path.dirname(__file__), "..", "..", "shared"))
    d = os.path.join(shared, "data", "friction-damper-backlash")
    return {f: condition(shifted(read_record(os.path.join(d, f"brfd30_{f}_0.5in_{kind}.csv")),
                                 lag))[0] for f in RATES}


def split(rec, force) -> str:
    """Residual mean square shares by cycle and by region (text)."""
    r = force - rec.force
    den = float(np.var(rec.force))
    cyc = np.floor((rec.time - rec.time[0]) * rec.frequency + 1e-9).astype(int)
    by_cycle = " ".join(f"c{c}:{np.sqrt(np.mean(r[cyc == c] ** 2) / den):.3f}"
                        for c in np.unique(cyc))
    # region: sliding (|v| above 30 % of its peak) vs the rest (reversal / dead band)
    v = rec.velocity
    slide = np.abs(v) > 0.3 * np.max(np.abs(v))
    share = (np.sum(r[slide] ** 2) / np.sum(r ** 2))
    fwd, rev = slide & (v > 0), slide & (v < 0)
    ms = np.sum(r ** 2)
    # the part of the residual a constant level per sliding direction would remove
    level = (np.sum(fwd) * np.mean(r[fwd]) ** 2 + np.sum(rev) * np.mean(r[rev]) ** 2) / ms
    detail = (f"; sliding forward bias {np.mean(r[fwd]):+.0f} N, reverse {np.mean(r[rev]):+.0f} N"
              f" (levels {level:.2f} of the residual); forward share "
              f"{np.sum(r[fwd] ** 2) / ms:.2f}, reverse {np.sum(r[rev] ** 2) / ms:.2f}")
    text = ""
    if not rec.periodic:  # tapered: the steady record's window against the ramps
        f = rec.frequency
        lab = next(k for k in STEADY_START if f"_{k}_" in rec.label)
        t0 = STEADY_START[lab]
        w = (rec.time >= t0) & (rec.time <= t0 + 3.0 / round(f * 4) * 4)
        wd = float(np.var(rec.force[w]))
        text = (f"; plateau window NRMSE {np.sqrt(np.mean(r[w] ** 2) / wd):.4f}, ramps "
                f"{np.sqrt(np.mean(r[~w] ** 2) / den):.4f} (share of the residual "
                f"{np.sum(r[~w] ** 2) / np.sum(r ** 2):.2f}, of the samples {np.mean(~w):.2f})")
    return (f"by cycle (cycle NRMSE) {by_cycle}; sliding share of the residual "
            f"{share:.2f} ({np.mean(slide):.2f} of the samples)" + detail + text)


def main(argv) -> None:
    """Command line (module docstring)."""
    warnings.filterwarnings("ignore")
    dev = load_device_file(argv[0])
    model = with_effects(get_model("full"), *dev.effects)
    for kind in argv[1:] or ("steady", "full"):
        recs = records(kind)
        for f, rec in recs.items():
            out = simulate_record(model, dev.params, rec)
            print(f"{kind} {f}: NRMSE {nrmse(out.force, rec.force):.4f}; "
                  + split(rec, out.force), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
