"""The ``liquidamp`` command.

Every sub-command lives in its own module of :mod:`liquidamp.commands` and
exposes ``register(subparsers)``; this module only discovers and dispatches
them, so adding a command never touches another one.  Sub-commands convert
units at the edge (``3mm``, Hz) and call the library in SI.

Building the parser imports no numerical library (numpy, scipy,
matplotlib, numba, python-control): a command imports what it needs inside
its run function, so that ``--help``, ``--version`` and argument errors
answer at once.  Help texts may name registries as ``{presets}``,
``{models}``, ``{effects}``, ``{rotors}`` and ``{sections}``; they are
filled in only when help is shown.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import re
import sys
import textwrap
from functools import cache

from liquidamp import __version__
from liquidamp.errors import LiquidampError

__all__ = ["build_parser", "main", "registry_names"]


@cache
def registry_names(kind: str) -> str:
    """Comma list of the names of registry ``kind``, for help texts.

    ``kind`` is one of ``presets``, ``models``, ``effects``, ``rotors``,
    ``sections``.

    Examples
    --------
    >>> registry_names("presets").split(", ")[:2]
    ['paper_initial', 'paper_calibrated']
    """
    if kind == "presets":
        from liquidamp.device.presets import preset_names

        names = preset_names()
    elif kind == "models":
        from liquidamp.device.models import model_names

        names = model_names()
    elif kind == "effects":
        from liquidamp.device.effects import effect_names

        names = effect_names()
    elif kind in ("rotors", "sections"):
        from liquidamp.structure.hostio import preset_names

        names = preset_names(kind[:-1])
    else:
        raise KeyError(kind)
    return ", ".join(names)


_PLACEHOLDER = re.compile(r"\{(presets|models|effects|rotors|sections)\}")
_ROLE = re.compile(r":(?:func|class|mod|meth|attr|data|obj|ref):`~?([^`<]*?)(?:\s*<[^>]*>)?`")


def plain_text(text: str) -> str:
    """Help text without reST markup, with the registry placeholders filled in.

    Examples
    --------
    >>> plain_text("by :func:`liquidamp.analysis.stability.sizing.size_lag_damper` (``--arm``)")
    'by liquidamp.analysis.stability.sizing.size_lag_damper (--arm)'
    """
    text = _ROLE.sub(r"\1", text)
    text = text.replace("``", "")
    text = re.sub(r"(?<![\w`])`([^`]+)`(?!\w)", r"\1", text)
    return _PLACEHOLDER.sub(lambda m: registry_names(m.group(1)), text)


class HelpFormatter(argparse.HelpFormatter):
    """Plain help: reST markup stripped, registries filled in, paragraphs kept."""

    def _get_help_string(self, action):
        return plain_text(action.help or "")

    def _format_text(self, text):
        text = plain_text(text)
        if "%(prog)" in text:
            text = text % {"prog": self._prog}
        text = text.replace("%%", "%")
        width = max(self._width - self._current_indent, 11)
        indent = " " * self._current_indent
        paragraphs = [p for p in re.split(r"\n\s*\n", text.strip()) if p.strip()]
        out = []
        for para in paragraphs:
            lines = para.splitlines()
            if all(line.startswith("    ") for line in lines[1:]) and len(lines) > 1 \
                    and lines[0].rstrip().endswith(":"):
                out.append(indent + lines[0].strip())
                out += [indent + line for line in lines[1:]]
            else:
                out.append(textwrap.fill(" ".join(para.split()), width, initial_indent=indent,
                                         subsequent_indent=indent))
        return "\n\n".join(out) + "\n\n"


_USAGE_ERRORS = ("required", "unrecognized", "expected", "invalid choice", "not allowed",
                 "ignored explicit")


class ArgumentParser(argparse.ArgumentParser):
    """argparse parser with :class:`HelpFormatter` for itself and its sub-parsers.

    A value that starts with ``-`` and a digit (``--amplitude -3mm``,
    ``--offset -.5mm``, ``--rpm -5:3:4``) is a value, never an option; an
    argument error is one line ``liquidamp COMMAND: error: ...`` on stderr
    (exit 2), with a pointer to ``--help`` for a usage error.
    """

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message):
        hint = f" (see '{self.prog} --help')" if any(w in message for w in _USAGE_ERRORS) \
            else ""
        self.exit(2, f"{self.prog}: error: {message}{hint}\n")

    def _check_help(self, action):  # Python >= 3.13 formats help at definition time
        pass


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser with every sub-command registered.

    Examples
    --------
    >>> parser = build_parser()
    >>> "demo" in parser._subparsers._group_actions[0].choices
    True
    """
    import liquidamp.commands as commands

    parser = ArgumentParser(
        prog="liquidamp",
        description="Liquid-based damping device (Titurus 2018) and the structures it damps. "
        "Run 'liquidamp COMMAND --help' for the options of a command. Exit codes: 0 done, "
        "1 done but not converged (calibrate), 2 bad input or an error stated on stderr.",
    )
    parser.add_argument("--version", action="version", version=f"liquidamp {__version__}")
    parser.add_argument("--traceback", action="store_true",
                        help="show the Python traceback of an error (for bug reports)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True,
                                parser_class=ArgumentParser)
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"liquidamp.commands.{info.name}")
        module.register(sub)
    return parser


def _message(exc: BaseException) -> str:
    """One line for an exception: an OSError names its file."""
    if isinstance(exc, OSError) and exc.strerror:
        where = f"{exc.filename}: " if exc.filename else ""
        return f"{where}{exc.strerror}"
    if isinstance(exc, UnicodeDecodeError):
        return f"not a text file ({exc.reason} at byte {exc.start})"
    text = str(exc).strip() or type(exc).__name__
    return " ".join(text.split()) if "\n" not in text else text


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the process exit code.

    Argument errors (a bad value, unit, bound or name, found at parse time
    before any numerical import) print one line ``liquidamp COMMAND: error:
    ...`` and return 2; ``--help`` and ``--version`` return 0.  Errors found
    while running (bad input the library rejects, an unreadable or
    unwritable file, a solver that did not converge) are printed as
    ``liquidamp COMMAND: error: ...`` on stderr with exit code 2; an
    interrupt exits with 130; anything else is a bug and is reported in
    one line with exit code 3.  ``--traceback`` shows
    the traceback instead.

    Parameters
    ----------
    argv : list of str, optional
        Arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit code.
    """
    parser = build_parser()
    try:
        args, extra = parser.parse_known_args(argv)
        if extra:  # named by the command's own parser
            sub = parser._subparsers._group_actions[0].choices[args.command]
            if getattr(args, "sweep_kind", None):
                sub = sub._subparsers._group_actions[0].choices[args.sweep_kind]
            sub.error(f"unrecognized arguments: {' '.join(extra)}")
    except SystemExit as exc:  # argument errors (2), --help and --version (0)
        return exc.code if isinstance(exc.code, int) else 2
    name = getattr(args, "command_name", None) or args.command
    if not getattr(args, "quiet", False):  # say what numba compiles while it does
        from liquidamp._numba_cache import compile_notices

        compile_notices(lambda msg: print(f"liquidamp {name}: {msg}", file=sys.stderr,
                                          flush=True))
    from liquidamp.commands import route_warnings

    try:
        with route_warnings(name):
            code = args.func(args)
    except KeyboardInterrupt:
        if args.traceback:
            raise
        print(f"liquidamp {name}: interrupted", file=sys.stderr)
        return 130
    except (LiquidampError, ValueError, OSError, MemoryError) as exc:
        if args.traceback:
            raise
        print(f"liquidamp {name}: error: {_message(exc)}", file=sys.stderr)
        return 2
    except Exception as exc:  # a bug: one line, the traceback on request
        if args.traceback:
            raise
        print(f"liquidamp {name}: internal error (a bug; run again with --traceback and "
              f"report it): {type(exc).__name__}: {_message(exc)}", file=sys.stderr)
        return 3
    return int(code or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
