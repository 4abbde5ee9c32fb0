"""``liquidamp params``: every parameter and derived quantity of a preset or device file.

``--json`` writes a report (keys ``"name [unit]"``, derived quantities
included) that is not a device file; ``--save-device`` writes a device file
(``.toml`` or ``.json``, the fields of
:class:`~liquidamp.device.params.DeviceParams` in SI) that ``--device``
reads back to the same parameters.
"""

from __future__ import annotations

import sys

from liquidamp.commands._args import Output, check_outputs, file_inputs, write_json


def add_device_arguments(parser, default: str = "reference") -> None:
    """Add the mutually exclusive ``--preset NAME`` / ``--device FILE`` options."""
    g = parser.add_mutually_exclusive_group()
    g.add_argument("--preset", default=None,
                   help=f"published parameter set (default {default}): {{presets}}")
    g.add_argument("--device", default=None,
                   help="TOML or JSON device file: DeviceParams fields in SI, or preset = "
                   "\"NAME\" plus overrides and a multipliers table")


def device_from_args(args, default: str = "reference"):
    """DeviceParams named by ``--preset`` or ``--device``."""
    from liquidamp.device import load_device, preset

    if getattr(args, "device", None):
        return load_device(args.device)
    return preset(args.preset or default)


def device_inputs(args) -> list:
    """``[("--device", path)]`` when a device file is given, else ``[]``."""
    return file_inputs(("--device", getattr(args, "device", None)))


def register(sub) -> None:
    """Add the ``params`` sub-command."""
    p = sub.add_parser("params", help="parameters and derived quantities as JSON",
                       description="Write every parameter and derived quantity, SI, keys "
                       "'name [unit]' (a report, not a device file), and with --save-device "
                       "a device file that --device reads back.")
    add_device_arguments(p)
    p.add_argument("--json", default=None,
                   help="report file .json (default: stdout); keys 'name [unit]' with derived "
                   "quantities: not readable by --device (use --save-device)")
    p.add_argument("--save-device", default=None, metavar="FILE",
                   help="write a device file (.toml or .json, DeviceParams fields in SI) that "
                   "--device reads back to the same parameters")
    p.set_defaults(func=run)


def device_file_data(params) -> dict:
    """The fields of ``params`` as a device-file table (SI; ``None`` fields left out).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> d = device_file_data(preset("reference"))
    >>> d["name"], d["bulk_law"], round(d["A_p"], 10)
    ('reference', 'gholizadeh', 0.0006911504)
    """
    import dataclasses

    out = {}
    for f in dataclasses.fields(params):
        value = getattr(params, f.name)
        if value is None:
            continue
        out[f.name] = value if isinstance(value, (str, bool)) else float(value)
    return out


def write_device_file(path, params) -> None:
    """Write ``params`` as a ``.toml`` or ``.json`` device file (see :func:`device_file_data`).

    Parameters
    ----------
    path : str or Path
        Output file; its suffix (``.json``, else TOML) chooses the format.
    params : DeviceParams
        Device; fields are written in SI and read back by
        :func:`liquidamp.device.presets.load_device` to equal parameters.

    Examples
    --------
    >>> import os, tempfile
    >>> from liquidamp.device import load_device, preset
    >>> f = os.path.join(tempfile.mkdtemp(), "dev.toml")
    >>> write_device_file(f, preset("inerter"))
    >>> load_device(f) == preset("inerter")
    True
    """
    from pathlib import Path

    path = Path(path)
    data = device_file_data(params)
    if path.suffix.lower() == ".json":
        write_json(path, data)
        return
    lines = ["# liquidamp device file (SI units); read with --device or load_device()"]
    for key, value in data.items():
        text = f'"{value}"' if isinstance(value, str) else repr(value)
        lines.append(f"{key} = {text}")
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text("\n".join(lines) + "\n")
    tmp.replace(path)


def run(args) -> int:
    """Write the parameter JSON (and the device file)."""
    import json

    check_outputs([Output("--json", args.json, "json"),
                   Output("--save-device", args.save_device, "device")], device_inputs(args))
    params = device_from_args(args)
    data = {"name": params.name, "bulk_law": params.bulk_law, **params.derived()}
    if args.save_device:
        write_device_file(args.save_device, params)
    if args.json:
        write_json(args.json, data)
    else:
        json.dump(data, sys.stdout, indent=2)
        print()
    return 0
