"""``liquidamp params``: every parameter and derived quantity of a preset or device file.

``--json`` writes a report (keys ``"name [unit]"``, derived quantities
included) that is not a device file; ``--save-device`` writes a device file
(``.toml`` or ``.json``, the fields of
:class:`~liquidamp.device.params.DeviceParams` in SI) that ``--device``
reads back to the same parameters.
"""

from __future__ import annotations

from liquidamp.commands._args import (
    Output,
    add_json_argument,
    add_quiet_argument,
    check_outputs,
    emit,
    file_inputs,
    json_path,
)
from liquidamp.commands._units import name_type, preset_names


def add_device_arguments(parser, default: str = "reference") -> None:
    """Add the mutually exclusive ``--preset NAME`` / ``--device FILE`` options."""
    g = parser.add_mutually_exclusive_group()
    g.add_argument("--preset", default=None, type=name_type("--preset", preset_names, "preset"),
                   help=f"published parameter set (default {default}): {{presets}}")
    g.add_argument("--device", default=None, metavar="FILE",
                   help="TOML or JSON device file: DeviceParams fields in SI, or preset = "
                   "\"NAME\" plus overrides and a multipliers table; its [effects.NAME] "
                   "tables are used (e.g. a file written by calibrate --save-device)")


def device_from_args(args, default: str = "reference"):
    """DeviceParams named by ``--preset`` or ``--device`` (see :func:`device_and_effects`)."""
    return device_and_effects(args, default)[0]


def device_and_effects(args, default: str = "reference"):
    """Parameters and effects: the ``--device`` file's ``[effects.NAME]`` tables, then
    the ``--effect`` options.

    Parameters
    ----------
    args : argparse.Namespace
    default : str
        Preset used without ``--preset`` and ``--device``.

    Returns
    -------
    params : DeviceParams
    effects : tuple of Effect
        The file's effects, then those of ``--effect``.

    Raises
    ------
    ParameterError
        An effect both in the file and in ``--effect``.
    """
    from liquidamp.commands._args import effects_from_args
    from liquidamp.device import load_device_file, preset
    from liquidamp.errors import ParameterError

    if getattr(args, "device", None):
        dev = load_device_file(args.device)
        params, file_effects = dev.params, tuple(dev.effects)
    else:
        params, file_effects = preset(args.preset or default), ()
    extra = effects_from_args(args)
    names = {e.name for e in file_effects}
    for e in extra:
        if e.name in names:
            raise ParameterError(
                f"--effect {e.name}: the device file {args.device!r} already has "
                f"[effects.{e.name}]; give it once (edit the file or leave out --effect)")
    effects = file_effects + extra
    from liquidamp.commands._args import warn_once

    for text in plausibility(params, effects, getattr(args, "amplitude", None)):
        warn_once(getattr(args, "command_name", None) or args.command, text)
    return params, effects


def plausibility(params, effects, amplitude=None) -> list[str]:
    """Warnings for effect geometry the device (or the stroke) cannot have.

    A freeplay half-gap (seal-held or floating) or an end stop's reach (centre +
    clearance) beyond the chamber's stroke limit min(V01, V02)/A_p, and a freeplay
    half-gap at least the stroke amplitude (the stroke never closes the gap).

    Parameters
    ----------
    params : DeviceParams
    effects : sequence of Effect
    amplitude : float or sequence of float, optional
        Stroke amplitude(s) [m] of the run.

    Returns
    -------
    list of str

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.effects import make_effect
    >>> print(plausibility(preset("reference"), [make_effect("freeplay", gap_m=0.1)])[0])
    freeplay gap_m = 0.1 m is beyond the chamber: the stroke limit min(V01, V02)/A_p is 0.025 m
    """
    lim = params.stroke_limit
    out = []
    if amplitude is None:
        amps = []
    elif isinstance(amplitude, (int, float)):
        amps = [float(amplitude)]
    else:
        amps = [float(a) for a in amplitude]
    for e in effects:
        d = e.as_dict()
        if e.name in ("freeplay", "floating_freeplay"):
            gap = d["gap_m"]
            if gap > lim:
                out.append(f"{e.name} gap_m = {gap:g} m is beyond the chamber: the stroke "
                           f"limit min(V01, V02)/A_p is {lim:.4g} m")
            elif amps and gap >= max(amps):
                out.append(f"{e.name} gap_m = {gap:g} m (half-width) is at least the stroke "
                           f"amplitude {max(amps):g} m: the stroke never closes the gap")
        elif e.name == "end_stops":
            reach = abs(d.get("centre_m", 0.0)) + d["clearance_m"]
            if reach > lim:
                out.append(f"end_stops centre_m + clearance_m = {reach:g} m lies beyond the "
                           f"chamber: the stroke limit min(V01, V02)/A_p is {lim:.4g} m, so "
                           "the stops are never reached")
    return out


def add_measured_device_argument(parser) -> None:
    """Add ``--device FILE``: a device used as measured (not sized), effects included."""
    parser.add_argument("--device", default=None, metavar="FILE",
                        help="device file used as measured, not sized (e.g. written by "
                        "calibrate --save-device; its [effects.NAME] tables included), one per "
                        "damper position, through --arm; instead of --damper")


def measured_device(args, default_model: str = "full"):
    """The ``--device`` file as a :class:`~liquidamp.coupled.assembly.Device` (not sized).

    The file's effects are composed with ``--model`` (``with_effects``); the
    label is the file's stem.
    """
    from pathlib import Path

    from liquidamp.coupled.assembly import Device
    from liquidamp.device import load_device_file
    from liquidamp.device.effects import with_effects

    dev = load_device_file(args.device)
    model = getattr(args, "model", None) or default_model
    if dev.effects:
        model = with_effects(model, *dev.effects)
    return Device(model, dev.params, Path(args.device).stem), dev


def measured_entries(dev) -> dict:
    """JSON entries of a device used as measured: file, effects, fit table (if any)."""
    out = {"device_file": dev.source, "sized": False,
           "effects": {e.name: e.as_dict() for e in dev.effects}}
    if dev.fit is not None:
        out["device_fit"] = {k: dev.fit[k] for k in ("source", "varied", "values", "stderr")
                             if k in dev.fit}
    return out


def device_inputs(args) -> list:
    """``[("--device", path)]`` when a device file is given, else ``[]``."""
    return file_inputs(("--device", getattr(args, "device", None)))


def register(sub) -> None:
    """Add the ``params`` sub-command."""
    p = sub.add_parser("params", help="parameters and derived quantities as JSON",
                       description="Write every parameter and derived quantity, SI, keys "
                       "'name [unit]' (a report, not a device file), and with --save-device "
                       "a device file that --device reads back (effects included).")
    add_device_arguments(p)
    add_json_argument(p, "report (keys 'name [unit]' with derived quantities: not readable "
                      "by --device, use --save-device)")
    p.add_argument("--save-device", default=None, metavar="FILE",
                   help="write a device file (.toml or .json, DeviceParams fields in SI and "
                   "the device file's effects) that --device reads back to the same device")
    add_quiet_argument(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """Write the parameter JSON (and the device file)."""
    check_outputs([Output("--json", json_path(args), "json"),
                   Output("--save-device", args.save_device, "device")], device_inputs(args))
    from liquidamp.device import write_device_file

    params, effects = device_and_effects(args)
    data = {"name": params.name, "bulk_law": params.bulk_law, **params.derived()}
    if effects:
        data["effects"] = {e.name: e.as_dict() for e in effects}
    if args.save_device:
        write_device_file(args.save_device, params, effects)
    emit(args, "params", data, None, "save_device")
    return 0
