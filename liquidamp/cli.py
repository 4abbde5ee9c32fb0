"""The ``liquidamp`` command.

Every sub-command lives in its own module of :mod:`liquidamp.commands` and
exposes ``register(subparsers)``; this module only discovers and dispatches
them, so adding a command never touches another one.  Sub-commands convert
units at the edge (``3mm``, Hz) and call the library in SI.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

from liquidamp.errors import LiquidampError

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser with every sub-command registered.

    Examples
    --------
    >>> parser = build_parser()
    >>> "demo" in parser._subparsers._group_actions[0].choices
    True
    """
    import liquidamp.commands as commands

    parser = argparse.ArgumentParser(
        prog="liquidamp",
        description="Liquid-based damping device (Titurus 2018) and the structures it damps.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"liquidamp.commands.{info.name}")
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the process exit code.

    Errors that liquidamp raises on purpose (bad input, a solver that did not
    converge) are printed as one line on stderr with exit code 2; anything
    else is a bug and keeps its traceback.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code = args.func(args)
    except LiquidampError as exc:
        print(f"liquidamp {args.command}: error: {exc}", file=sys.stderr)
        return 2
    return int(code or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
