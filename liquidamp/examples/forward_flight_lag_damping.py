"""Lag damping in forward flight: lag-mode damping against the 1/rev damper stroke.

The Hammond (1974) blade (hub fixed, own damper removed, arm 0.25 m) at
Omega = 2 pi 4.2 rad/s with a lag damper of two parallel copies of a preset
(``scale_device(preset, 2)``, ``full`` model): ``damper``,
``paper_calibrated`` and a smooth-friction damper of the same single-frequency
lag damping as ``paper_calibrated`` at the lag frequency and 0.5 mm
(:func:`liquidamp.analysis.stability.lag_sweep.friction_damper`).  For each
1/rev stroke amplitude: the lag damping ratio by Floquet about the forced
orbit (points) and its prediction from the dual-frequency K_lag (lines, one
per lag amplitude); written to ``--out`` as ``forward_flight_lag_damping.png``
and ``.json``.

Run ``python -m liquidamp.examples.forward_flight_lag_damping --out DIR`` (about
half a minute once numba has compiled; ``--points 3`` for a smoke test).
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from liquidamp.atomic import save_figure, write_text

#: Rotor speed [rad/s] (Hammond 1974: 4.2 Hz).
OMEGA = 2.0 * math.pi * 4.2
#: Lag amplitude at which the friction damper matches ``paper_calibrated`` [m].
MATCH_AMPLITUDE = 5e-4


def devices(names=("damper", "paper_calibrated"), friction_reference="paper_calibrated"):
    """The blade, the rotor speed and the devices: label -> Device, plus the friction force.

    Parameters
    ----------
    names : sequence of str
        Presets, each scaled x2 in the ``full`` model.
    friction_reference : str or None
        Preset (x2) whose single-frequency lag damping at the blade's lag frequency and
        :data:`MATCH_AMPLITUDE` the friction damper matches (None: no friction damper).

    Returns
    -------
    blade : ArticulatedBlade
    devices : dict
    friction_force : float or None
        Fc [N].
    """
    from liquidamp.analysis.stability.lag_sweep import friction_damper
    from liquidamp.analysis.stability.sizing import scale_device
    from liquidamp.coupled.assembly import Device
    from liquidamp.device import preset
    from liquidamp.structure.hostio import load_blade

    blade = load_blade("hammond1974").replace(lag_damping=0.0)
    devs = {f"{n} x2": Device("full", scale_device(preset(n), 2.0)) for n in names}
    Fc = None
    if friction_reference is not None:
        ref = Device("full", scale_device(preset(friction_reference), 2.0))
        dev, Fc = friction_damper(ref, blade.lag_frequency(OMEGA), MATCH_AMPLITUDE)
        devs[f"smooth friction {Fc:.3g} N"] = dev
    return blade, devs, Fc


def main(argv=None) -> int:
    """Command-line entry point: parse ``argv``, run the sweep, write PNG and JSON; 0 on success."""
    from liquidamp.analysis.reports.lag_plots import plot_lag_sweep
    from liquidamp.analysis.stability.lag_sweep import lag_damping_sweep

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out", help="output directory")
    ap.add_argument("--max-stroke", type=float, default=3.0,
                    help="largest 1/rev stroke amplitude [mm] (default %(default)s)")
    ap.add_argument("--points", type=int, default=7, help="strokes from 0 (default %(default)s)")
    ap.add_argument("--lag-amplitude", default="0.1,0.5",
                    help="lag amplitudes of the K_lag prediction [mm], comma separated")
    args = ap.parse_args(argv)
    if args.points < 2 or not args.max_stroke > 0.0:
        ap.error(f"--points must be >= 2 and --max-stroke > 0 mm, got {args.points} and "
                 f"{args.max_stroke}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    strokes = np.linspace(0.0, 1e-3 * args.max_stroke, args.points)
    A2 = [1e-3 * float(a) for a in args.lag_amplitude.split(",")]
    blade, devs, Fc = devices()
    data = lag_damping_sweep(blade, OMEGA, devs, strokes, lag_amplitudes=A2, progress=print)
    data["note"] = ("Hammond (1974) blade, own damper removed; devices scaled x2 in the full "
                    "model; friction damper (dashpot c_L = 1 N s/m + smooth_friction) sized by "
                    "4 Fc / (pi omega Y) to paper_calibrated x2 at the lag frequency and "
                    f"{1e3 * MATCH_AMPLITUDE:g} mm; Floquet = infinitesimal lag motion")
    data["friction_force [N]"] = Fc
    write_text(out / "forward_flight_lag_damping.json", json.dumps(data, indent=1))
    fig = plot_lag_sweep(data, title="Hammond blade, 4.2 Hz: lag damping under 1/rev motion")
    save_figure(fig, out / "forward_flight_lag_damping.png", dpi=120)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
