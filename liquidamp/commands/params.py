"""``liquidamp params``: every parameter and derived quantity of a preset or device file."""

from __future__ import annotations

import sys

from liquidamp.commands._args import write_json


def add_device_arguments(parser) -> None:
    """Add the mutually exclusive ``--preset NAME`` / ``--device FILE`` options."""
    g = parser.add_mutually_exclusive_group()
    g.add_argument("--preset", default=None, help="published parameter set (default reference)")
    g.add_argument("--device", default=None, help="TOML or JSON device file")


def device_from_args(args, default: str = "reference"):
    """DeviceParams named by ``--preset`` or ``--device``."""
    from liquidamp.device import load_device, preset

    if getattr(args, "device", None):
        return load_device(args.device)
    return preset(args.preset or default)


def register(sub) -> None:
    """Add the ``params`` sub-command."""
    p = sub.add_parser("params", help="parameters and derived quantities as JSON",
                       description="Write every parameter and derived quantity, SI, keys "
                       "named 'name [unit]'.")
    add_device_arguments(p)
    p.add_argument("--json", default=None, help="output file (default: stdout)")
    p.set_defaults(func=run)


def run(args) -> int:
    """Write the parameter JSON."""
    import json

    params = device_from_args(args)
    data = {"name": params.name, "bulk_law": params.bulk_law, **params.derived()}
    if args.json:
        write_json(args.json, data)
    else:
        json.dump(data, sys.stdout, indent=2)
        print()
    return 0
