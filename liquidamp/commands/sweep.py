"""``liquidamp sweep``: stability sweeps of the hosts (ground resonance, flutter).

``liquidamp sweep ground-resonance --rotor hammond1974 --rpm 100:400:61
[--inoperative K] [--method coleman|floquet] --json FILE [--plot FILE]``
writes, per rotor speed, the largest real part of the eigenvalues (or
Floquet exponents) and the fixed-frame modal frequencies, and the unstable
rpm ranges with ends found by Brent's method.  A rotor with dissimilar
blades (``--inoperative``) has periodic coefficients and is analysed with
Floquet theory whatever ``--method`` says (noted in the JSON and on stderr).

With ``--damper PRESET`` (a device preset, a device file or ``maxwell``;
default ``viscous``, the rotor's own dampers) the liquid device, sized by
:func:`liquidamp.analysis.stability.sizing.size_lag_damper` through the arm
``--arm`` (default the rotor's), replaces every blade's lag damper and the
small-signal closed loop is analysed (Coleman, or Floquet with
``--inoperative``).

``liquidamp sweep flutter --section hodges-pierce --aero theodorsen
--method pk --json FILE [--plot FILE]`` writes the flutter speed
U_F/(b omega_theta), the flutter frequency omega_F/omega_theta, the
divergence speed and the V-g / V-f data per mode.  With ``--damper PRESET
[--port plunge|pitch] [--zeta Z]`` the sized device (or ``viscous``) sits
on the port and the p method with Jones' aerodynamics (or the state-space
model given by ``--aero``) is used with the linearized device in the loop.
"""

from __future__ import annotations

import sys

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
    working,
)
from liquidamp.commands._units import (
    MODEL_NAMES,
    grid_type,
    name_type,
    preset_names,
    quantity_type,
)
from liquidamp.commands.params import (
    add_measured_device_argument,
    measured_device,
    measured_entries,
)
from liquidamp.errors import ParameterError, check_choice

__all__ = ["register", "COST", "MAX_SECONDS"]

#: Measured cost of one point [s] on this project's 2-core CI machine (idle, warm caches),
#: by kind of sweep; a grid whose estimate exceeds :data:`MAX_SECONDS` is refused.
COST = {"coleman": 1e-3, "floquet": 6e-3, "device coleman": 3e-3, "device floquet": 2e-2,
        "flutter pk": 2e-3, "flutter k": 1e-3, "flutter p": 1e-2}
#: Longest estimated run a sweep starts [s]; longer grids are refused with their estimate.
MAX_SECONDS = 60.0
#: Kinds whose library call reports progress (a tqdm bar); the others run silent, so they
#: are held to :data:`MAX_SILENT_SECONDS`.
WITH_PROGRESS = ("device coleman", "device floquet")
MAX_SILENT_SECONDS = 30.0


def check_work(count: int, kind: str, what: str) -> None:
    """Refuse a grid of ``count`` points whose estimated time exceeds :data:`MAX_SECONDS`.

    Examples
    --------
    >>> check_work(100_000, "flutter pk", "reduced speeds")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: 100000 reduced speeds (flutter pk) would take about \
200 s (2 ms a point on a 2-core machine); at most 15000 points (30 s): use a coarser grid or \
split the range
    """
    est = count * COST[kind]
    top = MAX_SECONDS if kind in WITH_PROGRESS else MAX_SILENT_SECONDS
    if est > top:
        limit = int(top / COST[kind])
        raise ParameterError(
            f"{count} {what} ({kind}) would take about {est:.0f} s ({1e3 * COST[kind]:g} ms a "
            f"point on a 2-core machine); at most {limit} points ({top:g} s): use a "
            "coarser grid or split the range")


def _damper_names():
    return ("viscous", "maxwell") + preset_names()


def register(subparsers) -> None:
    """Add the ``sweep`` command and its ``ground-resonance`` and ``flutter`` kinds."""
    p = subparsers.add_parser(
        "sweep",
        help="stability sweeps: ground resonance against rpm, flutter against airspeed",
        description=__doc__.split("\n\n", 1)[1],
    )
    sub = p.add_subparsers(dest="sweep_kind", metavar="KIND", required=True)

    g = sub.add_parser("ground-resonance", help="rotor on its landing gear against rotor speed")
    g.add_argument("--rotor", default="hammond1974",
                   type=name_type("--rotor", lambda: preset_names("rotor"), "rotor preset",
                                  files=True),
                   help="rotor preset name ({rotors}) or .toml/.json file (default hammond1974)")
    g.add_argument("--rpm", required=True, metavar="LIST",
                   type=grid_type("--rpm", "rotor_speed", "rpm"),
                   help="rotor speeds, rpm or with a unit (4Hz): comma list or START:STOP:COUNT "
                   "(COUNT points linearly spaced; log:START:STOP:COUNT log-spaced)")
    g.add_argument("--inoperative", action="append", default=[], metavar="K",
                   type=_blade,
                   help="blade whose lag damper has failed (1-based; repeat for several)")
    g.add_argument("--method", default="coleman",
                   type=name_type("--method", ("coleman", "floquet"), "method"),
                   help="coleman (default) or floquet")
    g.add_argument("--damper", default="viscous",
                   type=name_type("--damper", _damper_names, "damper", files=True),
                   help="viscous (default: the rotor's own dampers), maxwell, a device preset "
                   "({presets}) or a device file (sized to replace the lag damper)")
    add_measured_device_argument(g)
    g.add_argument("--arm", default=None, metavar="LEN",
                   type=quantity_type("--arm", "length", "arm"),
                   help="damper arm, metres or with unit (250mm), at most 10 m; default the "
                   "rotor's")
    g.add_argument("--model", default="full", type=name_type("--model", MODEL_NAMES, "model"),
                   help="device model (default full): {models}")
    add_json_argument(g, "sweep")
    add_plot_argument(g, "Coleman diagram")
    add_quiet_argument(g)
    g.set_defaults(func=_ground_resonance, command_name="sweep ground-resonance")

    f = sub.add_parser("flutter", help="typical section against airspeed")
    f.add_argument("--section", default="hodges-pierce",
                   type=name_type("--section", lambda: preset_names("section"), "section preset",
                                  files=True),
                   help="section preset name ({sections}) or .toml/.json file (default "
                   "hodges-pierce)")
    f.add_argument("--aero", default=None,
                   type=name_type("--aero", ("steady", "quasi-steady", "theodorsen", "jones"),
                                  "aerodynamics"),
                   help="steady, quasi-steady, theodorsen (default) or jones (default with "
                   "--damper)")
    f.add_argument("--method", default=None, type=name_type("--method", ("pk", "k", "p"),
                                                            "method"),
                   help="pk (default), k or p (p with --damper)")
    f.add_argument("--damper", default=None,
                   type=name_type("--damper", _damper_names, "damper", files=True),
                   help="device on the section: viscous, maxwell, a device preset ({presets}) "
                   "or a device file")
    add_measured_device_argument(f)
    f.add_argument("--port", default="plunge",
                   type=name_type("--port", ("plunge", "pitch"), "port"),
                   help="plunge (default) or pitch")
    f.add_argument("--zeta", default=0.05, metavar="RATIO",
                   type=quantity_type("--zeta", "ratio", "zeta"),
                   help="damping ratio the device is sized for, in (0, 1] or in percent (5%%) "
                   "(default 0.05)")
    f.add_argument("--model", default="full", type=name_type("--model", MODEL_NAMES, "model"),
                   help="device model (default full): {models}")
    f.add_argument("--speeds", default="0.05:3.5:70", metavar="LIST",
                   type=grid_type("--speeds", "reduced", "reduced_speed"),
                   help="reduced speeds U/(b omega_theta) for pk and p: comma list or "
                   "START:STOP:COUNT (COUNT points linearly spaced; default 0.05:3.5:70)")
    f.add_argument("--k", dest="reduced_frequencies", default=None, metavar="LIST",
                   type=grid_type("--k", "reduced", "reduced_frequency"),
                   help="reduced frequencies for the k method: comma list or START:STOP:COUNT "
                   "(COUNT points linearly spaced; default 80 log-spaced, 3 to 0.03)")
    add_json_argument(f, "sweep")
    add_plot_argument(f, "V-g and V-f figure")
    add_quiet_argument(f)
    f.set_defaults(func=_flutter, command_name="sweep flutter")


def _blade(text: str) -> int:
    """argparse type of --inoperative: a blade number >= 1."""
    import argparse

    try:
        k = int(text)
    except ValueError:
        k = 0
    if k < 1:
        raise argparse.ArgumentTypeError(f"must be a blade number >= 1, got {text!r}")
    return k


def _check_paths(args, host_flag: str, host: str) -> None:
    """Check --json and --plot against the host and damper files, before any work."""
    inputs = file_inputs((host_flag, host), ("--damper", getattr(args, "damper", None)),
                         ("--device", getattr(args, "device", None)))
    if getattr(args, "device", None) and getattr(args, "damper", None) not in (None,
                                                                               "viscous"):
        raise ParameterError("give either --device FILE (used as measured) or --damper "
                             "(sized to the host), not both")
    check_outputs([Output("--json", json_path(args), "json"),
                   Output("--plot", args.plot, "plot")], inputs)


def _ground_resonance(args) -> int:
    _check_paths(args, "--rotor", args.rotor)
    rpm = list(args.rpm)
    if any(b <= a for a, b in zip(rpm, rpm[1:], strict=False)):
        raise ParameterError(f"rpm values must be strictly increasing, got {args.rpm.text!r}")
    device = args.damper != "viscous" or args.arm is not None or args.device is not None
    used = "floquet" if args.inoperative else args.method
    check_work(len(rpm), ("device " if device else "") + used, "rotor speeds")
    import numpy as np

    rpm = np.asarray(rpm, float)
    from liquidamp.analysis.reports.stability_plots import plot_ground_resonance
    from liquidamp.analysis.stability.ground_resonance import (
        METHODS,
        ground_resonance_sweep,
        rpm_to_rad_s,
    )
    from liquidamp.structure.hostio import load_rotor

    method = check_choice("method", args.method, METHODS)
    rotor = load_rotor(args.rotor)
    blades = [rotor.check_blade(k) for k in args.inoperative]
    damper = getattr(args, "damper", "viscous")
    arm = getattr(args, "arm", None)
    if damper != "viscous" or arm is not None or args.device:
        return _ground_resonance_device(args, rotor, rpm, blades, method)
    for k in blades:
        rotor = rotor.with_inoperative_damper(k)
    with working(f"sweep ground-resonance: {len(rpm)} rotor speeds", args.quiet):
        sweep = ground_resonance_sweep(rotor, rpm_to_rad_s(rpm), method)
    if sweep.method != method:
        print(f"liquidamp sweep ground-resonance: note: {sweep.note}", file=sys.stderr)
    data = sweep.to_dict()
    data["inoperative_blades"] = [int(t) for t in args.inoperative]
    data["lag_damping [N m s/rad]"] = list(rotor.blade_damping)
    return _write_outputs(args, data, plot_ground_resonance, sweep,
                          _ground_resonance_summary(rotor.name, sweep))


def _ground_resonance_device(args, rotor, rpm, blades, method) -> int:
    from liquidamp.analysis.reports.stability_plots import plot_ground_resonance
    from liquidamp.analysis.stability.damped_stability import device_ground_resonance_sweep
    from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    from liquidamp.analysis.stability.sizing import lag_damper_device

    if args.device:
        device, dev = measured_device(args)
        if args.arm is not None:
            rotor = rotor.replace(blade=rotor.blade.replace(damper_arm=args.arm))
        sizing = None
    else:
        device, rotor, sizing = lag_damper_device(args.damper, rotor, arm=args.arm,
                                                  model=args.model)
    used = "floquet" if blades else method
    with progress_bar(len(rpm), "rotor speeds", args.quiet) as bar:
        sweep = device_ground_resonance_sweep(
            rotor, rpm_to_rad_s(rpm), device, inoperative=blades, method=used,
            executor="serial", progress=bar.update if show_progress(args.quiet) else False)
    if sweep.method != method:
        print(f"liquidamp sweep ground-resonance: note: {sweep.note}", file=sys.stderr)
    data = sweep.to_dict()
    data["inoperative_blades"] = [int(k) for k in blades]
    data["damper_arm [m]"] = rotor.blade.damper_arm
    if args.device:
        data["damper"] = args.device
        data.update(measured_entries(dev))
    else:
        data["damper"] = args.damper
        _add_device_entries(data, device, sizing)
    return _write_outputs(args, data, plot_ground_resonance, sweep,
                          _ground_resonance_summary(f"{rotor.name} + {device.label}", sweep))


def _flutter(args) -> int:
    _check_paths(args, "--section", args.section)
    method = args.method or ("p" if args.damper or args.device else "pk")
    grid = args.reduced_frequencies if method == "k" and args.reduced_frequencies else \
        args.speeds
    check_work(len(grid), f"flutter {method}", "reduced speeds" if method != "k" else
               "reduced frequencies")
    import numpy as np

    speeds = np.asarray(args.speeds, float)
    kvals = None
    if args.reduced_frequencies is not None:
        kvals = np.asarray(args.reduced_frequencies, float)
    if getattr(args, "damper", None) or args.device:
        return _flutter_device(args, speeds)
    from liquidamp.analysis.reports.stability_plots import plot_flutter
    from liquidamp.analysis.stability.flutter import check_combination, flutter_analysis
    from liquidamp.structure.hostio import load_section

    args.aero = args.aero or "theodorsen"
    args.method = args.method or "pk"
    check_combination(args.aero, args.method)
    section = load_section(args.section)
    with working(f"sweep flutter: {args.method}", args.quiet):
        result = flutter_analysis(section, args.aero, args.method, speeds=speeds,
                                  reduced_frequencies=kvals)
    return _write_outputs(args, result.to_dict(), plot_flutter, result,
                          _flutter_summary(section.name, args.aero, args.method, result))


def _flutter_device(args, speeds) -> int:
    from liquidamp.analysis.reports.stability_plots import plot_flutter
    from liquidamp.analysis.stability.damped_stability import damped_flutter_analysis
    from liquidamp.analysis.stability.flutter import check_combination
    from liquidamp.analysis.stability.sizing import flutter_damper_device
    from liquidamp.structure.hostio import load_section

    aero = args.aero or "jones"
    method = args.method or "p"
    if method != "p":
        raise ParameterError(f"{'--device' if args.device else '--damper'} needs the p method "
                             f"(the device is in the state-space loop), got --method {method}")
    check_combination(aero, method)
    check_choice("port", args.port, ("plunge", "pitch"))
    section = load_section(args.section)
    if args.device:
        device, dev = measured_device(args)
        sizing = None
    else:
        device, sizing = flutter_damper_device(args.damper, section, port=args.port,
                                               zeta=args.zeta, model=args.model)
    with working(f"sweep flutter: {method} with {device.label}", args.quiet):
        result = damped_flutter_analysis(section, {args.port: device}, speeds=speeds,
                                         aero=aero)
    data = result.to_dict()
    data["port"] = args.port
    if args.device:
        data["damper"] = args.device
        data.update(measured_entries(dev))
    else:
        data["damper"] = args.damper
        _add_device_entries(data, device, sizing)
    return _write_outputs(args, data, plot_flutter, result,
                          _flutter_summary(f"{section.name} + {device.label} on {args.port}",
                                           aero, method, result))


def _add_device_entries(data: dict, device, sizing) -> None:
    """Add the device's sizing (or, unsized, its coefficient [N s/m]) to ``data``."""
    if sizing is not None:
        data["sizing"] = sizing.as_dict()
    else:
        data["damper_coefficient [N s/m]"] = device.params.c


def _ground_resonance_summary(label: str, sweep) -> str:
    """One line: ``label``, the method used and the unstable rpm ranges [rpm]."""
    ranges = ", ".join(f"{a:.1f}-{b:.1f}" for a, b in sweep.unstable_ranges_rpm) or "none"
    return f"{label}: {sweep.method}; unstable ranges [rpm]: {ranges}"


def _flutter_summary(label: str, aero: str, method: str, result) -> str:
    """One line: ``label``, aerodynamics, method, flutter and divergence speeds [-]."""
    vf = "none in range" if result.flutter_speed is None else (
        f"{result.flutter_speed:.4f} (frequency ratio {result.flutter_frequency:.4f})")
    return (f"{label}: {aero}, {method}: flutter speed U/(b omega_theta) = {vf}; "
            f"divergence {result.divergence_speed:.4f}")


def _write_outputs(args, data: dict, plot, result, summary: str) -> int:
    """Write ``data`` to ``--json``, print ``summary``, then ``plot(result)`` to ``--plot``.

    The figure is saved at 120 dpi; returns the exit code 0.
    """
    emit(args, args.command_name, data, summary, "plot")
    if args.plot:
        save_figure(plot(result), args.plot, dpi=120)
    return 0
