"""Flutter speed of the Hodges & Pierce section against the device's parameters.

The reference design on the plunge port, sized by
:func:`liquidamp.analysis.stability.sizing.size_flutter_damper` (damping ratio
``--zeta`` of the plunge at the bare section's flutter frequency), then
one parameter at a time multiplied: the air ratios 1/gamma (compliance),
the laminar loss c1 and the channel inertance S_t.  p method with
R. T. Jones' aerodynamics and the small-signal device in the loop.  Writes
``flutter_map.png`` and ``flutter_map.json`` to ``--out`` (well under a
minute; ``--dask ADDRESS`` for a cluster).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from liquidamp.atomic import save_figure, write_text

PARAMETERS = {"air ratio 1/gamma": ("inv_gamma1", "inv_gamma2"), "c1": ("c1",),
              "S_t": ("S_t",)}


def _point(item):
    """Flutter speed U_F/(b omega_theta) for one (parameter, multiplier) [-]."""
    from liquidamp.analysis.stability.damped_stability import damped_flutter_analysis
    from liquidamp.analysis.stability.sizing import flutter_damper_device
    from liquidamp.coupled.assembly import Device
    from liquidamp.structure.hostio import load_section

    keys, mult, zeta, port = item
    s = load_section("hodges-pierce")
    dev, _ = flutter_damper_device("reference", s, port=port, zeta=zeta)
    d = Device("full", dev.params.scaled(**{k: mult for k in keys}), "reference")
    r = damped_flutter_analysis(s, {port: d}, speeds=np.linspace(0.05, 4.0, 80))
    return r.flutter_speed


def main(argv=None) -> int:
    """Command-line entry point: parse ``argv``, run the sweep, write PNG and JSON; 0 on success."""
    from liquidamp.analysis.stability.damped_stability import damped_flutter_analysis
    from liquidamp.analysis.stability.parallel import map_batched
    from liquidamp.analysis.stability.sizing import flutter_damper_device
    from liquidamp.structure.hostio import load_section

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out")
    ap.add_argument("--zeta", type=float, default=0.2, help="sizing damping ratio [-]")
    ap.add_argument("--port", default="plunge", help="plunge or pitch")
    ap.add_argument("--dask", default=None, help="Dask scheduler address (optional)")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    mults = np.geomspace(0.1, 10.0, 5 if args.quick else 25)
    executor = None
    if args.dask:
        from dask.distributed import Client

        executor = Client(args.dask)
    items = [(keys, float(m), args.zeta, args.port) for keys in PARAMETERS.values()
             for m in mults]
    vals = map_batched(_point, items, executor=executor)
    s = load_section("hodges-pierce")
    dv, _ = flutter_damper_device("viscous", s, port=args.port, zeta=args.zeta)
    v_visc = damped_flutter_analysis(s, {args.port: dv}).flutter_speed
    from liquidamp.analysis.stability.flutter import flutter_analysis

    v_bare = flutter_analysis(s, "jones", "p").flutter_speed
    table = np.array([np.nan if v is None else v for v in vals]).reshape(len(PARAMETERS), -1)
    data = {"multiplier": mults.tolist(), "bare_flutter_speed": v_bare,
            "viscous_flutter_speed": v_visc, "zeta": args.zeta, "port": args.port,
            "speed_unit": "U/(b omega_theta)",
            "flutter_speed": {name: [None if not np.isfinite(v) else float(v) for v in row]
                              for name, row in zip(PARAMETERS, table, strict=True)}}
    write_text(out / "flutter_map.json", json.dumps(data, indent=1))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name, row in zip(PARAMETERS, table, strict=True):
        ax.semilogx(mults, row, marker="o", ms=3, label=f"{name} x m")
    ax.axhline(v_bare, color="k", ls=":", label="no device")
    ax.axhline(v_visc, color="k", ls="--", label="viscous, same sizing")
    ax.set_xlabel("parameter multiplier m [-]")
    ax.set_ylabel("flutter speed U_F/(b omega_theta) [-]")
    ax.set_title(f"Hodges & Pierce section, reference design on {args.port} "
                 f"(zeta = {args.zeta:g})")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, out / "flutter_map.png", dpi=120)
    print(f"bare {v_bare:.4f}, viscous {v_visc:.4f}; device: "
          + "; ".join(f"{n}: {np.nanmin(r):.3f}-{np.nanmax(r):.3f}"
                      for n, r in zip(PARAMETERS, table, strict=True)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
