"""``liquidamp map``: stability maps over two quantities, the boundary drawn as a contour.

``liquidamp map ground-resonance --rotor hammond1974 --rpm 100:400:201
(--degradation 0:1:50 [--blade K] | --lag-damping LIST | --arm LIST)
[--inoperative K] --json FILE [--plot FILE]`` writes the largest real part
of the Floquet exponents [1/s] of the rotor (periodic rotating-frame model,
viscous lag dampers) on the grid of rotor speeds x the damper parameter:
``--degradation`` the fraction of its damping that blade K's damper keeps
(0 failed, 1 healthy), ``--lag-damping`` every working damper's coefficient
[N m s/rad], ``--arm`` the mounting arm [m] of a linear damper of the
rotor's coefficient (lag damping c a^2).  The JSON holds the map, the
dampers at each value and the unstable rpm ranges per value (zero crossings
interpolated on the grid); the figure a filled map with the stability
boundary (largest real part = 0) as a contour.
"""

from __future__ import annotations

from liquidamp.commands._args import (
    Output,
    add_json_argument,
    add_plot_argument,
    add_quiet_argument,
    check_outputs,
    emit,
    file_inputs,
    json_path,
    progress_bar,
    save_figure,
    show_progress,
)
from liquidamp.commands._units import Bound, grid_type, name_type, preset_names
from liquidamp.errors import ParameterError

__all__ = ["register", "COST", "FLUTTER_COST", "MAX_SECONDS", "MAX_SILENT_SECONDS",
           "check_work"]

#: Measured cost of one map point [s] on this project's 2-core machine, both cores (idle,
#: warm compile cache): the compiled lane-blocked Floquet kernel, rounded up.
COST = 1.5e-3
#: Longest estimated run started with a progress bar shown [s].
MAX_SECONDS = 120.0
#: Longest estimated run started without progress (not a terminal, or ``--quiet``) [s].
MAX_SILENT_SECONDS = 30.0

_DEGRADATION = Bound(0.0, 1.0, low_open=False, why=" (a fraction of the damper's damping: "
                     "0 failed, 1 healthy)")
_DAMPING = Bound(0.0, 1e7, low_open=False, why=" (a damper far stiffer than the section)")
_LAG_DAMPING = Bound(0.0, 1e7, low_open=False, why=" (2500 times Hammond's damper)")


def check_work(count: int, progress: bool) -> None:
    """Refuse a map of ``count`` points whose estimated time exceeds the limit.

    The limit is :data:`MAX_SECONDS` when progress is shown, else
    :data:`MAX_SILENT_SECONDS`.

    Examples
    --------
    >>> check_work(10_050, progress=False)
    >>> check_work(100_000, progress=False)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: a map of 100000 points would take about 150 s (1.5 ms a \
point on a 2-core machine); at most 20000 points (30 s) without a progress bar (on a terminal, \
without --quiet: 120 s): use a coarser grid or split the range
    """
    est = count * COST
    top = MAX_SECONDS if progress else MAX_SILENT_SECONDS
    if est > top:
        raise ParameterError(
            f"a map of {count} points would take about {est:.0f} s ({1e3 * COST:g} ms a point "
            f"on a 2-core machine); at most {int(top / COST)} points ({top:g} s)"
            + ("" if progress else f" without a progress bar (on a terminal, without --quiet: "
                                   f"{MAX_SECONDS:g} s)")
            + ": use a coarser grid or split the range")


def register(subparsers) -> None:
    """Add the ``map`` command and its ``ground-resonance`` and ``flutter`` kinds."""
    p = subparsers.add_parser(
        "map", help="stability maps: rotor speed x a damper parameter, boundary as a contour",
        description=__doc__.split("\n\n", 1)[1])
    sub = p.add_subparsers(dest="map_kind", metavar="KIND", required=True)
    g = sub.add_parser("ground-resonance",
                       help="rotor on its landing gear: rotor speed x a lag-damper parameter")
    g.add_argument("--rotor", default="hammond1974",
                   type=name_type("--rotor", lambda: preset_names("rotor"), "rotor preset",
                                  files=True),
                   help="rotor preset name ({rotors}) or .toml/.json file (default hammond1974)")
    g.add_argument("--rpm", required=True, metavar="LIST",
                   type=grid_type("--rpm", "rotor_speed", "rpm"),
                   help="rotor speeds, rpm or with a unit (4Hz): comma list or START:STOP:COUNT "
                   "(COUNT points linearly spaced; log:START:STOP:COUNT log-spaced)")
    what = g.add_mutually_exclusive_group(required=True)
    what.add_argument("--degradation", metavar="LIST",
                      type=grid_type("--degradation", "ratio", _DEGRADATION),
                      help="fractions of its damping that blade --blade's damper keeps, in "
                      "[0, 1] or in percent: comma list or START:STOP:COUNT (COUNT points "
                      "linearly spaced; 0%%:100%%:50)")
    what.add_argument("--lag-damping", metavar="LIST",
                      type=grid_type("--lag-damping", "lag_damping", _LAG_DAMPING),
                      help="lag damper of every working blade, N m s/rad or with a unit "
                      "(4kN m s/rad), at most 1e7")
    what.add_argument("--arm", metavar="LIST", type=grid_type("--arm", "length", "arm"),
                      help="damper arms, metres or with a unit (250mm), at most 10 m: a linear "
                      "damper of the rotor's coefficient (lag damping c arm^2)")
    g.add_argument("--blade", type=_blade, default=1, metavar="K",
                   help="the degraded blade for --degradation (1-based, default 1)")
    g.add_argument("--inoperative", action="append", default=[], metavar="K", type=_blade,
                   help="blade whose lag damper has failed at every value (1-based; repeat)")
    g.add_argument("--dask", default=None, metavar="ADDRESS",
                   help="Dask scheduler address (tcp://HOST:PORT): rows of the map are sent "
                   "there in batches of 0.1 s or more (pip install liquidamp[dask]); the "
                   "numbers are the same as local")
    add_json_argument(g, "map")
    add_plot_argument(g, "filled map with the stability boundary")
    add_quiet_argument(g)
    g.set_defaults(func=_ground_resonance, command_name="map ground-resonance")

    f = sub.add_parser("flutter", help="typical section: reduced speed x a damper coefficient")
    f.add_argument("--section", default="hodges-pierce",
                   type=name_type("--section", lambda: preset_names("section"), "section preset",
                                  files=True),
                   help="section preset name ({sections}) or .toml/.json file (default "
                   "hodges-pierce)")
    f.add_argument("--speeds", default="0.5:3.5:61", metavar="LIST",
                   type=grid_type("--speeds", "reduced", "reduced_speed"),
                   help="reduced speeds U/(b omega_theta): comma list or START:STOP:COUNT "
                   "(COUNT points linearly spaced; default 0.5:3.5:61)")
    f.add_argument("--damping", required=True, metavar="LIST",
                   type=grid_type("--damping", "damping", _DAMPING),
                   help="coefficients of the viscous damper on --port, N s/m or with a unit "
                   "(2kN s/m), at most 1e7")
    f.add_argument("--port", default="plunge",
                   type=name_type("--port", ("plunge", "pitch"), "port"),
                   help="plunge (default) or pitch")
    f.add_argument("--aero", default="jones",
                   type=name_type("--aero", ("jones", "quasi-steady", "steady"), "aerodynamics"),
                   help="state-space aerodynamics: jones (default), quasi-steady or steady")
    add_json_argument(f, "map")
    add_plot_argument(f, "filled map with the flutter boundary")
    add_quiet_argument(f)
    f.set_defaults(func=_flutter, command_name="map flutter")


def _blade(text: str) -> int:
    """argparse type of a blade number >= 1."""
    import argparse

    try:
        k = int(text)
    except ValueError:
        k = 0
    if k < 1:
        raise argparse.ArgumentTypeError(f"must be a blade number >= 1, got {text!r}")
    return k


def _ground_resonance(args) -> int:
    check_outputs([Output("--json", json_path(args), "json"), Output("--plot", args.plot,
                                                                      "plot")],
                  file_inputs(("--rotor", args.rotor)))
    for flag, grid in (("--rpm", args.rpm), ("--degradation", args.degradation),
                       ("--lag-damping", args.lag_damping), ("--arm", args.arm)):
        if grid is not None and any(b <= a for a, b in zip(grid, grid[1:], strict=False)):
            raise ParameterError(f"{flag} values must be strictly increasing, got "
                                 f"{grid.text!r}")
    if args.rpm[0] <= 0.0:
        raise ParameterError(f"--rpm must be > 0 for Floquet analysis, got {args.rpm[0]:g}")
    parameter, values = next((name, v) for name, v in (
        ("degradation", args.degradation), ("lag_damping", args.lag_damping),
        ("arm", args.arm)) if v is not None)
    count = len(args.rpm) * len(values)
    progress = show_progress(args.quiet)
    check_work(count, progress)
    import numpy as np

    from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    from liquidamp.analysis.stability.maps import MapOptions, ground_resonance_map
    from liquidamp.structure.hostio import load_rotor

    rotor = load_rotor(args.rotor)
    blades = [rotor.check_blade(k) for k in args.inoperative]
    blade = rotor.check_blade(args.blade)
    if parameter == "degradation" and blade in blades:
        raise ParameterError(f"--blade {blade} is also --inoperative: degrade a working damper")
    client = None
    if args.dask:
        try:
            from dask.distributed import Client
        except ImportError:
            raise ParameterError("--dask needs dask.distributed: pip install "
                                 "'liquidamp[dask]'") from None
        try:
            client = Client(args.dask, timeout=10)
        except (OSError, TimeoutError, ValueError) as exc:
            raise ParameterError(f"--dask {args.dask}: cannot reach the scheduler ({exc})"
                                 ) from None
    try:
        with progress_bar(count, "map points", args.quiet) as bar:
            result = ground_resonance_map(
                rotor, rpm_to_rad_s(np.asarray(args.rpm, float)), parameter,
                np.asarray(values, float), blade=blade, inoperative=tuple(blades),
                options=MapOptions(progress=bar.update if progress else False,
                                   executor=client))
    finally:
        if client is not None:
            client.close()
    data = result.to_dict()
    data["inoperative_blades"] = blades
    if parameter == "degradation":
        data["degraded_blade"] = blade
    data["damper_arm [m]"] = rotor.blade.damper_arm
    unstable = [v for v, r in zip(result.values, result.unstable_ranges_rpm(), strict=True) if r]
    summary = (f"{rotor.name}: map of {count} points ({len(values)} {parameter} x "
               f"{len(args.rpm)} rpm) in {result.seconds:.1f} s; unstable somewhere at "
               f"{len(unstable)} of {len(values)} values")
    emit(args, args.command_name, data, summary, "plot")
    if args.plot:
        from liquidamp.analysis.reports.map_plots import plot_stability_map

        save_figure(plot_stability_map(result), args.plot, dpi=120)
    return 0


#: Measured cost of one flutter-map point [s] (one closed-loop eigenvalue problem), rounded up.
FLUTTER_COST = 2e-3


def _flutter(args) -> int:
    check_outputs([Output("--json", json_path(args), "json"), Output("--plot", args.plot,
                                                                      "plot")],
                  file_inputs(("--section", args.section)))
    for flag, grid in (("--speeds", args.speeds), ("--damping", args.damping)):
        if any(b <= a for a, b in zip(grid, grid[1:], strict=False)):
            raise ParameterError(f"{flag} values must be strictly increasing, got "
                                 f"{grid.text!r}")
    count = len(args.speeds) * len(args.damping)
    progress = show_progress(args.quiet)
    check_work(int(count * FLUTTER_COST / COST), progress)
    import numpy as np

    from liquidamp.analysis.stability.flutter_maps import flutter_map
    from liquidamp.structure.hostio import load_section

    section = load_section(args.section)
    with progress_bar(count, "map points", args.quiet) as bar:
        result = flutter_map(section, np.asarray(args.speeds, float),
                             np.asarray(args.damping, float), port=args.port, aero=args.aero,
                             progress=bar.update if progress else False)
    data = result.to_dict()
    speeds = result.flutter_speeds()
    known = [v for v in speeds if v is not None]
    summary = (f"{section.name} + viscous damper on {args.port}: map of {count} points in "
               f"{result.seconds:.1f} s; flutter speed U/(b omega_theta) "
               + (f"{min(known):.4f} to {max(known):.4f}" if known else "none in range"))
    emit(args, args.command_name, data, summary, "plot")
    if args.plot:
        from liquidamp.analysis.reports.map_plots import plot_stability_map

        save_figure(plot_stability_map(result), args.plot, dpi=120)
    return 0
