"""Session 20: a dyno-style record nobody tuned for: one continuous stroke at 3 Hz whose
amplitude steps 1 -> 2 -> 4 mm (half-cycle smooth ramps, from rest), made by liquidamp's own
model (reference preset + 15 N Coulomb friction) through the record simulation's
non-periodic route, plus 1 N force and 2 um displacement noise; held out: a periodic 5 Hz,
3 mm record of the same truth (synthetic_record).

usage: python runs/s20_lead/stepped.py OUTDIR
"""
import math
import sys
from pathlib import Path

import numpy as np

from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.analysis.measured.records import Record, write_record
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.device.effects import EFFECTS, with_effects
from liquidamp.device.presets import preset

out = Path(sys.argv[1])
out.mkdir(parents=True, exist_ok=True)
fs, f = 500.0, 3.0
amps = (1e-3, 2e-3, 4e-3)
n_cyc = 4
t = np.arange(int(round((len(amps) * n_cyc + 0.5) * fs / f))) / fs
# amplitude envelope: smooth (half-cycle cosine) ramps between the steps, from zero
env = np.zeros_like(t)
for k, a in enumerate(amps):
    prev = amps[k - 1] if k else 0.0
    t0 = k * n_cyc / f
    s = np.clip((t - t0) * 2 * f, 0.0, 1.0)
    env = np.where(t >= t0, prev + (a - prev) * 0.5 * (1 - np.cos(math.pi * s)), env)
y = env * np.sin(2 * math.pi * f * t)
truth = with_effects("full", EFFECTS["coulomb_friction"](force_N=15.0))
p = preset("reference")
rng = np.random.default_rng(20)
rec = Record.from_arrays(t, y, np.zeros_like(t))
F = simulate_record(truth, p, rec).force  # at the record's samples (its ends trimmed)
t, y = rec.time, rec.displacement
write_record(out / "stepped_cal.csv", time=t, displacement=y + rng.normal(0, 2e-6, t.size),
             force=F + rng.normal(0, 1.0, t.size))
val = synthetic_record(frequency=5.0, amplitude=0.003, cycles=6, seed=7, sampling_rate=500.0,
                       effects={"coulomb_friction": {"force_N": 15.0}}, preset="reference")
write_record(out / "stepped_val.csv", val)
print("wrote", out)
