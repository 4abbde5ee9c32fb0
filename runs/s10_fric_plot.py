"""Session 10 (s10-fric): one cycle of the steady friction-damper records against a saved device.

Plots, for the 1 Hz, 0.5 Hz and 0.25 Hz steady records, the force as read (grey), as
conditioned (black dots), the device's force (red), the residual (blue) and the stroke rate
(green, scaled), over phases 0.9-2.1 of the record.

Data: Coble, Huggins, Cao, Ricles, Downey (2022), Dataset-Friction-Damper-with-Backlash
(ARTS-Laboratory), CC BY-SA 4.0; the figure derives from it and keeps that licence.

Usage: ``python runs/s10_fric_plot.py DEV.toml OUT.png``
"""

from __future__ import annotations

import os
import sys
import warnings

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from s10_fric_where import records  # noqa: E402

from liquidamp.analysis.measured.record_model import simulate_record  # noqa: E402
from liquidamp.analysis.measured.records import read_record  # noqa: E402
from liquidamp.device.effects import with_effects  # noqa: E402
from liquidamp.device.models import get_model  # noqa: E402
from liquidamp.device.presets import load_device_file  # noqa: E402


def main(argv) -> None:
    """Command line (module docstring)."""
    warnings.filterwarnings("ignore")
    dev = load_device_file(argv[0])
    model = with_effects(get_model("full"), *dev.effects)
    recs = records("steady")
    shared = os.environ.get("LIQUIDAMP_SHARED", "/work/shared")
    d = os.path.join(shared, "data", "friction-damper-backlash")
    fig, ax = plt.subplots(3, 1, figsize=(14, 11))
    for i, f in enumerate(("1Hz", "0.5Hz", "0.25Hz")):
        r = recs[f]
        o = simulate_record(model, dev.params, r)
        raw = read_record(os.path.join(d, f"brfd30_{f}_0.5in_steady.csv"))

        def ph(t, r=r):
            return (t - r.time[0]) * r.frequency

        ax[i].plot(ph(raw.time), raw.force / 1e3, color="0.7", lw=0.5, label="as read")
        ax[i].plot(ph(r.time), r.force / 1e3, "k.-", lw=0.8, ms=3, label="conditioned")
        ax[i].plot(ph(r.time), o.force / 1e3, "r", lw=1, label="model")
        ax[i].plot(ph(r.time), (o.force - r.force) / 1e3, "b", lw=0.8, label="residual")
        ax[i].plot(ph(r.time), r.velocity / np.max(r.velocity) * 5, "g", lw=0.6,
                   label="rate (scaled)")
        ax[i].set_xlim(0.9, 2.1)
        ax[i].grid()
        ax[i].set_title(f"steady {f} (data: Coble et al. 2022, CC BY-SA 4.0)")
        ax[i].set_ylabel("kN")
    ax[0].legend(fontsize=7)
    ax[-1].set_xlabel("cycles")
    fig.tight_layout()
    fig.savefig(argv[1], dpi=65)


if __name__ == "__main__":
    main(sys.argv[1:])
