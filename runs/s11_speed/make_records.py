"""Larger records than the tuned ones, for timing the default diagnosis (s11-speed).

    PYTHONPATH=. python runs/s11_speed/make_records.py OUTDIR [NAME ...]

Writes OUTDIR/NAME_cal.csv and OUTDIR/NAME_val.csv (with JSON recipe sidecars) with the
library's own simulator (:func:`liquidamp.analysis.measured.synthetic.write_synthetic`):

- ``long5k``: reference preset, Coulomb friction 30 N; cal 60 s at 5 kHz, 2 Hz, 3 mm
  (120 cycles, 300 001 samples); val 40 s at 5 kHz, 3 Hz, 2 mm.
- ``bb2k``: reference preset, leakage 3e-12 m^3/(s Pa); cal 30 s at 2 kHz of a broadband
  random-phase multisine 0.1-20 Hz (RMS 2 mm / sqrt 2, repeats every 10 s); val 20 s of
  another draw.
- ``short100``: device_b preset (light channel), Coulomb friction 20 N; cal 4 cycles of
  100 Hz at 1 mm, 10 kHz; val 4 cycles of 80 Hz at 1.2 mm.
"""
import sys
import time
from pathlib import Path

from liquidamp.analysis.measured.synthetic import write_synthetic

COMMON = {"force_noise": 1.5, "displacement_noise": 2e-6, "distortion": (0.0, 0.01)}

CASES = {
    "long5k": ({"preset": "reference", "effects": {"coulomb_friction": {"force_N": 30.0}}},
               {"frequency": 2.0, "amplitude": 0.003, "cycles": 120, "sampling_rate": 5000.0,
                "seed": 11},
               {"frequency": 3.0, "amplitude": 0.002, "cycles": 120, "sampling_rate": 5000.0,
                "seed": 12}),
    "bb2k": ({"preset": "reference",
              "effects": {"leakage": {"coefficient_m3_per_s_Pa": 3e-12}}},
             {"frequency": 1.0, "cycles": 30, "band": (0.1, 20.0), "amplitude": 0.002,
              "sampling_rate": 2000.0, "seed": 21},
             {"frequency": 1.0, "cycles": 20, "band": (0.1, 20.0), "amplitude": 0.002,
              "sampling_rate": 2000.0, "seed": 22}),
    "short100": ({"preset": "device_b",
                  "effects": {"coulomb_friction": {"force_N": 20.0}}},
                 {"frequency": 100.0, "amplitude": 0.001, "cycles": 4,
                  "sampling_rate": 10000.0, "seed": 31},
                 {"frequency": 80.0, "amplitude": 0.0012, "cycles": 4,
                  "sampling_rate": 10000.0, "seed": 32}),
}


def main(out: Path, names) -> None:
    out.mkdir(parents=True, exist_ok=True)
    for name in names:
        base, cal, val = CASES[name]
        for role, kw in (("cal", cal), ("val", val)):
            t0 = time.perf_counter()
            p = write_synthetic(out / f"{name}_{role}.csv", **COMMON, **base, **kw)
            print(f"{p} {time.perf_counter() - t0:.1f} s", flush=True)


if __name__ == "__main__":
    main(Path(sys.argv[1]), sys.argv[2:] or list(CASES))
