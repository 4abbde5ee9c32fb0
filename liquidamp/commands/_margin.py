"""``liquidamp sweep ... --confidence/--degrade/--change``: stability answers with intervals.

The command-line edge of :mod:`liquidamp.analysis.stability.margins`: devices and their fit
covariance from the ``--device`` file, rpm at this edge, JSON and figures.
"""

from __future__ import annotations

from liquidamp.commands._args import emit, save_figure, working
from liquidamp.errors import ParameterError

__all__ = ["ground_resonance_margin_command", "flutter_margin_command"]


def _uncertainty(args, dev):
    """The device file's fit covariance when ``--confidence`` is given (else None)."""
    from liquidamp.analysis.stability.margins import FitUncertainty

    if args.confidence is None:
        return None
    if dev is None:
        raise ParameterError("--confidence needs --device FILE: a device file with the fit's "
                             "[fit] covariance (written by calibrate --save-device)")
    if dev.fit is None:
        raise ParameterError(f"--confidence: the device file {dev.source!r} has no [fit] table "
                             "(no covariance to carry); write it with calibrate --save-device")
    return FitUncertainty.from_fit(dev.fit, dev.source)


def _options(args):
    from liquidamp.analysis.stability.margins import MarginOptions

    return MarginOptions(confidence=args.confidence if args.confidence is not None else 0.95)


def _sampling(args, analysis, device, unc, margin, data: dict) -> None:
    """With ``--samples N``: percentile intervals over N draws, in ``data["sampling"]``."""
    if getattr(args, "samples", None) is None:
        return
    if unc is None:
        raise ParameterError("--samples needs --confidence and --device FILE with a [fit] "
                             "table")
    from liquidamp.analysis.stability.margin_sampling import sampled_margin

    with working(f"sampling: {args.samples} analyses", args.quiet):
        s = sampled_margin(analysis, device, unc, samples=args.samples,
                           confidence=margin.confidence)
    data["sampling"] = s.as_dict(margin.to_unit)


def _summary(label: str, m) -> str:
    u = m.speed_unit
    d = 1 if u == "rpm" else 4
    bands = "; ".join(
        f"{s.value:.{d}f} [{s.low:.{d}f}, {s.high:.{d}f}] to {e.value:.{d}f} "
        f"[{e.low:.{d}f}, {e.high:.{d}f}]" for s, e in m.band_edges()) or "none"
    z = m.min_damping_ratio
    out = (f"{label}: unstable ranges [{u}] (edge [interval]): {bands}; min damping ratio "
           f"{z.value:.4g} [{z.low:.4g}, {z.high:.4g}]")
    if m.flutter_speed is not None:
        f = m.flutter_speed
        out += f"; flutter speed {f.value:.4f} [{f.low:.4f}, {f.high:.4f}]"
    if m.possible_bands:
        out += f"; {len(m.possible_bands)} possible band(s) within the interval"
    return out + f" ({100 * m.confidence:g} %)"


def ground_resonance_margin_command(args, rotor, rpm, blades) -> int:
    """``sweep ground-resonance`` with ``--confidence``, ``--degrade`` or ``--change``."""
    import numpy as np

    from liquidamp.analysis.reports.stability_plots import plot_degradation, plot_margin
    from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    from liquidamp.analysis.stability.margins import (
        changed_device,
        degradation_comparison,
        ground_resonance_margin,
        host_viscous_device,
    )
    from liquidamp.analysis.stability.sizing import lag_damper_device
    from liquidamp.commands.params import measured_device, measured_entries

    if args.degrade is not None and (blades or args.change is not None):
        raise ParameterError("--degrade compares one degraded damper with its smeared "
                             "equivalent; give it without --inoperative and --change")
    dev = None
    if args.device:
        device, dev = measured_device(args)
        if args.arm is not None:
            rotor = rotor.replace(blade=rotor.blade.replace(damper_arm=args.arm))
        sizing = None
    elif args.damper != "viscous" or args.arm is not None:
        device, rotor, sizing = lag_damper_device(args.damper, rotor, arm=args.arm,
                                                  model=args.model)
    else:
        device, sizing = host_viscous_device(rotor), None
    unc = _uncertainty(args, dev)
    opts = _options(args)
    W = rpm_to_rad_s(np.asarray(rpm, float))
    data = {"rpm": [float(v) for v in rpm]}
    comp = changed = None
    with working(f"sweep ground-resonance: margins over {len(rpm)} rotor speeds", args.quiet):
        if args.degrade is not None:
            k, f = args.degrade
            comp = degradation_comparison(rotor, W, device, unc, blade=k, fraction=f,
                                          options=opts)
            margin = comp.floquet
        else:
            if args.change is not None:
                k, name, value = args.change
                changed = (k, changed_device(device, name, value))
            margin = ground_resonance_margin(rotor, W, device, unc, inoperative=blades,
                                             changed=changed, options=opts)
    data["max_real_part [1/s]"] = margin.max_real_part.tolist()
    data["min_damping_ratio_per_speed"] = margin.damping_ratio.tolist()
    data["margin"] = margin.to_dict()
    if comp is not None:
        data["degradation"] = comp.to_dict()
    if comp is None:
        _sampling(args, lambda d: ground_resonance_margin(
            rotor, W, d, inoperative=blades, changed=changed, options=opts), device, unc,
            margin, data)
    elif args.samples is not None:
        raise ParameterError("--samples is not taken with --degrade (three analyses per draw)")
    data["inoperative_blades"] = [int(k) for k in blades]
    data["change"] = (None if args.change is None else
                      {"blade": args.change[0], "name": args.change[1], "value": args.change[2]})
    data["damper_arm [m]"] = rotor.blade.damper_arm
    if args.device:
        data["damper"] = args.device
        data.update(measured_entries(dev))
    else:
        data["damper"] = args.damper
        if sizing is not None:
            data["sizing"] = sizing.as_dict()
    label = f"{rotor.name} + {device.label}"
    summary = _summary(label, margin)
    if comp is not None and comp.loss_ratio is not None:
        summary += (f"; blade {comp.blade} at {1 - comp.fraction:g} of its force: smeared/"
                    f"Floquet damping loss {comp.loss_ratio:.3f}")
    emit(args, args.command_name, data, summary, "plot")
    if args.plot:
        fig = plot_degradation(comp) if comp is not None else plot_margin(margin)
        save_figure(fig, args.plot, dpi=120)
    return 0


def flutter_margin_command(args, speeds) -> int:
    """``sweep flutter --confidence C --device FILE``: the p method with intervals."""
    from liquidamp.analysis.reports.stability_plots import plot_margin
    from liquidamp.analysis.stability.flutter import check_combination
    from liquidamp.analysis.stability.margins import flutter_margin
    from liquidamp.commands.params import measured_device, measured_entries
    from liquidamp.structure.hostio import load_section

    if not args.device:
        raise ParameterError("--confidence needs --device FILE: a device file with the fit's "
                             "[fit] covariance (written by calibrate --save-device)")
    aero = args.aero or "jones"
    if (args.method or "p") != "p":
        raise ParameterError(f"--confidence uses the p method (the device in the state-space "
                             f"loop), got --method {args.method}")
    check_combination(aero, "p")
    section = load_section(args.section)
    device, dev = measured_device(args)
    unc = _uncertainty(args, dev)
    with working(f"sweep flutter: margins over {len(speeds)} speeds", args.quiet):
        margin = flutter_margin(section, speeds, device, unc, port=args.port, aero=aero,
                                options=_options(args))
    data = {"reduced_speeds": [float(v) for v in speeds],
            "max_real_part [-]": margin.max_real_part.tolist(),
            "min_damping_ratio_per_speed": margin.damping_ratio.tolist(),
            "margin": margin.to_dict(), "port": args.port, "aero": aero,
            "damper": args.device, **measured_entries(dev)}
    _sampling(args, lambda d: flutter_margin(section, speeds, d, port=args.port, aero=aero,
                                             options=_options(args)), device, unc, margin, data)
    emit(args, args.command_name, data,
         _summary(f"{section.name} + {device.label} on {args.port}", margin), "plot")
    if args.plot:
        save_figure(plot_margin(margin), args.plot, dpi=120)
    return 0
