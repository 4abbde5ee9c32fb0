"""Ground-resonance stability map of the Hammond rotor with liquid lag dampers.

Two products, written to ``--out`` as PNG and JSON:

1. ``dampers``: largest real part against rotor speed for the viscous damper
   (Hammond's), the reference design, Device A (large inertance), Device B
   (small inertance) and an ideal Maxwell unit of the reference's stiffness,
   each sized by :func:`liquidamp.analysis.stability.sizing.size_lag_damper`, with all
   dampers working (Coleman) and with damper 1 failed (Floquet).
2. ``map``: largest real part over (rotor speed, channel-inertance multiplier
   S_t x m) for the sized reference design, healthy and failed; the inertance
   is the paper's frequency-selective ingredient.

Run ``python -m liquidamp.examples.ground_resonance_map --out DIR`` (a few minutes on
two cores).  ``--dask tcp://HOST:PORT`` sends the points to a Dask cluster
(``pip install liquidamp[dask]``); the default is local processes.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from liquidamp.atomic import save_figure, write_text


def _point(item):
    """Largest real part [1/s] of one (device spec, multiplier, rpm, inoperative) point."""
    from liquidamp.analysis.stability.damped_stability import rotor_device_eigenvalues
    from liquidamp.analysis.stability.sizing import lag_damper_device
    from liquidamp.coupled.assembly import Device
    from liquidamp.structure.hostio import load_rotor

    spec, mult, rpm, inop = item
    rotor = load_rotor("hammond1974")
    dev, rotor, _ = lag_damper_device(spec, rotor)
    if mult != 1.0:
        dev = Device(dev.model, dev.params.scaled(S_t=mult), dev.label)
    lam = rotor_device_eigenvalues(rotor, rpm * math.pi / 30, dev, inoperative=inop)
    return float(np.max(lam.real))


def main(argv=None) -> int:
    """Command-line entry point: parse ``argv``, run the sweep, write PNG and JSON; 0 on success."""
    from liquidamp.analysis.stability.parallel import map_batched

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out", help="output directory")
    ap.add_argument("--rpm", default="120:400:36", help="START:STOP:COUNT [rpm]")
    ap.add_argument("--dask", default=None, help="Dask scheduler address (optional)")
    ap.add_argument("--quick", action="store_true", help="coarse grids (smoke test)")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    a, b, n = args.rpm.split(":")
    rpm = np.linspace(float(a), float(b), 8 if args.quick else int(n))
    mults = np.geomspace(0.1, 10.0, 4 if args.quick else 13)
    executor = None
    if args.dask:
        from dask.distributed import Client

        executor = Client(args.dask)
    specs = ["viscous", "reference", "device_a", "device_b", "maxwell"]
    cases = {"healthy": (), "damper 1 failed": (1,)}
    items = [(s, 1.0, r, inop) for s in specs for inop in cases.values() for r in rpm]
    items += [("reference", m, r, inop) for inop in cases.values() for m in mults for r in rpm]
    vals = map_batched(_point, items, executor=executor)
    k = len(specs) * len(cases) * rpm.size
    curves = np.array(vals[:k]).reshape(len(specs), len(cases), rpm.size)
    grid = np.array(vals[k:]).reshape(len(cases), mults.size, rpm.size)

    def ranges(v):
        s = v > 1e-6
        out_, start = [], None
        for i, u in enumerate(s):
            if u and start is None:
                start = rpm[i]
            if not u and start is not None:
                out_.append([float(start), float(rpm[i - 1])])
                start = None
        if start is not None:
            out_.append([float(start), float(rpm[-1])])
        return out_

    data = {"rpm": rpm.tolist(), "S_t_multiplier": mults.tolist(),
            "note": "largest real part [1/s]; small-signal devices sized at 250 rpm "
                    "(size_lag_damper); unstable ranges on the grid [rpm]",
            "dampers": {s: {c: {"max_real_part [1/s]": curves[i, j].tolist(),
                                "unstable_ranges [rpm]": ranges(curves[i, j])}
                            for j, c in enumerate(cases)} for i, s in enumerate(specs)},
            "map": {c: {"max_real_part [1/s]": grid[j].tolist()} for j, c in enumerate(cases)}}
    write_text(out / "ground_resonance_map.json", json.dumps(data, indent=1))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    for j, c in enumerate(cases):
        ax = axes[0, j]
        for i, s in enumerate(specs):
            ax.plot(rpm, curves[i, j], label=s)
        ax.axhline(0, color="k", lw=0.6)
        ax.set_title(f"dampers, {c}")
        ax.set_xlabel("rotor speed [rpm]")
        ax.set_ylabel("largest real part [1/s]")
        ax.legend(fontsize=8)
        ax = axes[1, j]
        lim = np.max(np.abs(grid[j]))
        cs = ax.pcolormesh(rpm, mults, grid[j], cmap="RdBu_r", vmin=-lim, vmax=lim,
                           shading="auto")
        ax.contour(rpm, mults, grid[j], levels=[0.0], colors="k")
        ax.set_yscale("log")
        ax.set_xlabel("rotor speed [rpm]")
        ax.set_ylabel("S_t multiplier (inertance) [-]")
        ax.set_title(f"reference design, {c}")
        fig.colorbar(cs, ax=ax, label="largest real part [1/s]")
    fig.tight_layout()
    save_figure(fig, out / "ground_resonance_map.png", dpi=120)
    for s in specs:
        print(s, {c: data["dampers"][s][c]["unstable_ranges [rpm]"] for c in cases})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
