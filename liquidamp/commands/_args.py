"""Argument parsing shared by the sub-commands.

Lists, ranges and lengths with units; counts checked at parse time; the
output-path check every command runs before any work (:func:`check_outputs`);
``--effect NAME[:key=value,...]``; warnings and progress on stderr.

Nothing here imports numpy, scipy, matplotlib or numba at module level: the
parser must build (and reject bad arguments) in well under a second.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

from liquidamp.commands._units import MAX_POINTS, parse_grid, parse_quantity
from liquidamp.errors import ParameterError


def parse_length(text: str, name: str = "length") -> float:
    """Parse a length in SI or with a unit suffix, return metres.

    Parameters
    ----------
    text : str
        ``"0.003"`` [m] or a number with a unit: ``m``, ``mm``, ``cm``, ``um``.
    name : str
        Name of the quantity in the error message.

    Returns
    -------
    float
        The length [m].

    Examples
    --------
    >>> parse_length("3mm")
    0.003
    >>> parse_length("-0.002")
    -0.002
    """
    if isinstance(text, (int, float)):
        return float(text)
    try:
        value = parse_quantity(text, "length", name)
    except ValueError as exc:
        raise ParameterError(str(exc)) from None
    if not math.isfinite(value):
        raise ParameterError(f"{name} must be finite, got {text!r}")
    return value


def parse_list(text, name: str, *, dimension: str = "reduced", bound=None,
               max_count: int = MAX_POINTS):
    """Values of a list option: ``a,b,c``, ``START:STOP:COUNT`` (linear), ``lin:``/``log:``.

    Parameters
    ----------
    text : str or sequence of float
        The option's text (or values already parsed by
        :func:`liquidamp.commands._units.grid_type`, returned as they are).
    name : str
        Name of the option in error messages.
    dimension : str
        Unit dimension of the entries (:data:`liquidamp.commands._units.UNITS`).
    bound : Bound or str, optional
        Allowed range of every value.
    max_count : int
        Largest number of values (default 100 000).

    Returns
    -------
    numpy.ndarray
        The values in the base unit of ``dimension``.

    Raises
    ------
    ParameterError
        Naming the option, the entry at fault and what is allowed.

    Examples
    --------
    >>> parse_list("1,2,4", "frequency", dimension="frequency").tolist()
    [1.0, 2.0, 4.0]
    >>> parse_list("log:1:100:3", "frequency", dimension="frequency").tolist()
    [1.0, 10.0, 100.0]
    >>> parse_list("100:400:10000000", "rpm")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: rpm COUNT must lie in [1, 100000] (points of one sweep), \
got 10000000
    """
    import numpy as np

    if not isinstance(text, str):
        return np.asarray(list(text), dtype=float)
    try:
        values = parse_grid(text, name, dimension, bound, max_count=max_count)
    except ValueError as exc:
        raise ParameterError(str(exc)) from None
    return np.asarray(values, dtype=float)


def count_type(name: str, low: int, high: int, meaning: str):
    """argparse ``type=`` for an integer in ``[low, high]``; the message says what it counts.

    Parameters
    ----------
    name : str
        Option name (shown by argparse for other failures).
    low, high : int
        Allowed range, both ends included [-].
    meaning : str
        What the integer counts, with its unit if any, e.g. ``"model evaluations per fit"``.

    Returns
    -------
    callable
        ``str -> int``; raises ``argparse.ArgumentTypeError`` (exit 2 at parse time).

    Examples
    --------
    >>> count_type("--top", 1, 50, "candidates refitted per step")("3")
    3
    >>> count_type("--top", 1, 50, "candidates refitted per step")("0")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: must be an integer in [1, 50] (candidates refitted per step), \
got '0'
    """

    def convert(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or not low <= value <= high:
            raise argparse.ArgumentTypeError(
                f"must be an integer in [{low}, {high}] ({meaning}), got {text!r}")
        return value

    convert.__name__ = name
    return convert


def float_type(name: str, unit: str, *, low: float = 0.0, high: float = math.inf,
               low_open: bool = True, why: str = ""):
    """argparse ``type=`` for a finite float in ``(low, high]`` (``[low`` if not ``low_open``).

    argparse puts ``argument NAME:`` before the message; ``why`` explains the bound.

    Parameters
    ----------
    name : str
        Option name.
    unit : str
        Unit of the value, shown in the message, e.g. ``"s"``.
    low, high : float
        Allowed range in ``unit``.
    low_open : bool
        Exclude ``low`` (default True).
    why : str
        Reason for the bound, appended to the message.

    Returns
    -------
    callable
        ``str -> float``; raises ``argparse.ArgumentTypeError`` (exit 2 at parse time).

    Examples
    --------
    >>> float_type("--rpm", "rpm")("230")
    230.0
    >>> float_type("--rpm", "rpm")("-5")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: must be a finite number > 0 [rpm], got '-5'
    """
    lo = ">" if low_open else ">="
    rng = f"{lo} {low:g}" if math.isinf(high) else \
        f"in {'(' if low_open else '['}{low:g}, {high:g}]"

    def convert(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        ok = math.isfinite(value) and (value > low if low_open else value >= low) \
            and value <= high
        if not ok:
            raise argparse.ArgumentTypeError(
                f"must be a finite number {rng} [{unit}]{why}, got {text!r}")
        return value

    convert.__name__ = name
    return convert


# ---------------------------------------------------------------------------
# output paths: checked before any work


@dataclass(frozen=True)
class Output:
    """One output a command will write.

    Attributes
    ----------
    flag : str
        Option that names it, e.g. ``"--json"``.
    path : str or None
        The path given (None: not requested).
    kind : str
        ``"json"``, ``"csv"``, ``"device"`` (``.toml`` or ``.json``),
        ``"plot"`` (a format matplotlib writes) or ``"dir"`` (a folder the
        command fills).
    writes : tuple of str
        For ``"dir"``: the files the command writes into it; if one of them
        exists the command refuses unless ``--force``.
    """

    flag: str
    path: str | None
    kind: str
    writes: tuple = field(default=())


_SUFFIXES = {"json": (".json",), "csv": (".csv",), "device": (".toml", ".json")}


def plot_formats() -> tuple[str, ...]:
    """File suffixes matplotlib can write (``png``, ``pdf``, ``svg``, ...).

    Examples
    --------
    >>> {"png", "pdf", "svg"} <= set(plot_formats())
    True
    """
    from matplotlib.backend_bases import FigureCanvasBase

    return tuple(sorted(FigureCanvasBase.get_supported_filetypes()))


def _same(a: Path, b: Path) -> bool:
    if a.resolve() == b.resolve():
        return True
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _check_parent(flag: str, path: Path) -> None:
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.exists():
        raise ParameterError(f"{flag} {str(path)!r}: folder {str(parent)!r} does not exist "
                             "(create it first)")
    if not parent.is_dir():
        raise ParameterError(f"{flag} {str(path)!r}: {str(parent)!r} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ParameterError(f"{flag} {str(path)!r}: folder {str(parent)!r} is not writable")


def check_outputs(outputs, inputs=(), *, force: bool = False) -> None:
    """Check every output path before any work; raise a ParameterError on the first bad one.

    A file output must have an existing, writable parent folder, must not be
    a folder itself, must have a suffix of its ``kind`` (``.json``,
    ``.csv``, or a format matplotlib writes for plots) and must not be (the
    same resolved file as) an input.  A folder output must be a folder or
    not exist yet with an existing, writable parent; if it already holds
    one of the files the command writes there, it is refused unless
    ``force``.  Two outputs may not name the same file.

    Parameters
    ----------
    outputs : iterable of Output
        The outputs (those with ``path`` None are skipped).
    inputs : iterable of (str, str or None)
        ``(flag, path)`` of the input files (records, device files, ...).
    force : bool
        Allow replacing the files of an existing folder output.

    Raises
    ------
    ParameterError
        Naming the option, the path and what is wrong.

    Examples
    --------
    >>> import tempfile, os
    >>> d = tempfile.mkdtemp()
    >>> rec = os.path.join(d, "cal.csv")
    >>> _ = open(rec, "w").write("time [s],displacement [mm],force [N]\\n")
    >>> check_outputs([Output("--json", os.path.join(d, "out.json"), "json")], [("RECORD", rec)])
    >>> check_outputs([Output("--json", rec, "json")], [("RECORD", rec)])
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: --json ...cal.csv' is the input RECORD ...cal.csv'; writing \
it would destroy the input: give another file name
    >>> check_outputs([Output("--json", os.path.join(d, "no", "x.json"), "json")])
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: --json ...: folder ... does not exist (create it first)
    """
    inputs = [(flag, Path(p)) for flag, p in inputs if p]
    seen: list[tuple[str, Path]] = []
    for out in outputs:
        if out.path is None:
            continue
        path = Path(out.path)
        if str(out.path).strip() == "":
            raise ParameterError(f"{out.flag} is empty; give a file name")
        if out.kind == "dir":
            _check_dir(out, path, inputs, force)
            seen += [(out.flag, path / name) for name in out.writes]
            continue
        if path.is_dir():
            raise ParameterError(f"{out.flag} {str(path)!r} is a folder; give a file name")
        for flag, p in inputs:
            if _same(path, p):
                raise ParameterError(
                    f"{out.flag} {str(path)!r} is the input {flag} {str(p)!r}; writing it would "
                    "destroy the input: give another file name")
        suffix = path.suffix.lower()
        if out.kind == "plot":
            formats = plot_formats()
            if suffix.lstrip(".") not in formats:
                raise ParameterError(
                    f"{out.flag} {str(path)!r}: unknown figure format {suffix or '(none)'!r}; "
                    f"valid: {', '.join('.' + f for f in formats)}")
        elif suffix not in _SUFFIXES[out.kind]:
            raise ParameterError(f"{out.flag} {str(path)!r} has suffix {suffix or '(none)'!r}; "
                                 f"valid: {', '.join(_SUFFIXES[out.kind])}")
        _check_parent(out.flag, path)
        if path.exists() and not os.access(path, os.W_OK):
            raise ParameterError(f"{out.flag} {str(path)!r} exists and is not writable")
        for flag, p in seen:
            if _same(path, p):
                raise ParameterError(f"{out.flag} {str(path)!r} is also the output of {flag}; "
                                     "give each output its own file")
        seen.append((out.flag, path))


def _check_dir(out: Output, path: Path, inputs, force: bool) -> None:
    if path.exists():
        if not path.is_dir():
            raise ParameterError(f"{out.flag} {str(path)!r} is a file, not a folder")
        if not os.access(path, os.W_OK | os.X_OK):
            raise ParameterError(f"{out.flag} folder {str(path)!r} is not writable")
    else:
        _check_parent(out.flag, path)
    for name in out.writes:
        target = path / name
        for flag, p in inputs:
            if _same(target, p):
                raise ParameterError(
                    f"{out.flag} {str(path)!r} would overwrite the input {flag} {str(p)!r}")
    existing = [n for n in out.writes if (path / n).exists()]
    if existing and not force:
        raise ParameterError(
            f"{out.flag} {str(path)!r} already holds {', '.join(existing)}; "
            "refusing to replace it: give a new folder or --overwrite")


def file_inputs(*pairs) -> list:
    """``(flag, path)`` pairs of the inputs that are files (preset names are skipped).

    Parameters
    ----------
    *pairs : (str, str or list or None)
        Option and its value; a list gives one pair per entry.  A value that
        ends in ``.toml``, ``.json`` or ``.csv`` or names an existing path is
        a file.

    Returns
    -------
    list of (str, str)

    Examples
    --------
    >>> file_inputs(("--device", None), ("--rotor", "hammond1974"), ("--rotor", "r.toml"))
    [('--rotor', 'r.toml')]
    """
    out = []
    for flag, value in pairs:
        if not value:
            continue
        if isinstance(value, (list, tuple)):
            out += [(flag, v) for v in value]
        elif Path(value).suffix.lower() in (".toml", ".json", ".csv") or Path(value).exists():
            out.append((flag, value))
    return out


def add_overwrite_argument(parser) -> None:
    """Add ``--overwrite`` (old spelling ``--force`` kept as a hidden alias).

    Allows replacing an existing output folder's files.
    """
    parser.add_argument("--overwrite", action="store_true", dest="overwrite",
                        help="replace an existing output folder's report (without it an "
                        "existing report or index is never overwritten); the new folder is "
                        "built beside it and swapped in whole")
    parser.add_argument("--force", action="store_true", dest="overwrite",
                        help=argparse.SUPPRESS)


add_force_argument = add_overwrite_argument  # the old name


def add_quiet_argument(parser) -> None:
    """Add ``--quiet``: no progress bar or progress lines on stderr."""
    parser.add_argument("--quiet", action="store_true",
                        help="no progress bar or progress lines (there is no bar when stderr is "
                        "not a terminal); warnings and errors are still printed")


def add_json_argument(parser, what: str = "results") -> None:
    """Add ``--json FILE`` (``-``: standard output)."""
    parser.add_argument("--json", default=None, metavar="FILE",
                        help=f"write the {what} as JSON to FILE (.json), or to standard output "
                        "with '-' (the default when no other output is asked for)")


def add_plot_argument(parser, what: str) -> None:
    """Add the optional ``--plot FILE``."""
    parser.add_argument("--plot", default=None, metavar="FILE",
                        help=f"{what} (.png, .pdf, .svg, ...; optional, written after the JSON)")


def json_path(args) -> str | None:
    """The ``--json`` file to check and write (None: standard output or none)."""
    j = getattr(args, "json", None)
    return None if j in (None, "-") else j


def json_to_stdout(args, *others: str) -> bool:
    """True if the JSON goes to standard output: ``--json -``, or no output option at all.

    ``others`` are the names of the command's other output options
    (``"plot"``, ``"report"``, ``"save_device"``, ``"out"``).
    """
    j = getattr(args, "json", None)
    if j == "-":
        return True
    return j is None and not any(getattr(args, o, None) for o in others)


def emit(args, command: str, data: dict, summary: str | None = None, *others: str) -> None:
    """Write ``data`` where ``--json`` says, print the warnings once, then ``summary``.

    The summary goes to standard output, or to stderr when the JSON does (so
    that standard output stays one JSON document).
    """
    if json_to_stdout(args, *others):
        sys.stdout.write(json.dumps(data, indent=2, default=_json_default, allow_nan=False)
                         + "\n")
        stream = sys.stderr
    else:
        if json_path(args):
            write_json(args.json, data)
        stream = sys.stdout
    print_warnings(command, data)
    if summary:
        print(summary, file=stream)


# ---------------------------------------------------------------------------
# effects


def add_effect_argument(parser, extra: str = "") -> None:
    """Add the repeatable ``--effect NAME[:key=value,...]`` option (checked at parse time)."""
    from liquidamp.commands._units import effect_type

    parser.add_argument(
        "--effect", action="append", default=[], metavar="NAME[:KEY=VALUE,...]",
        type=effect_type,
        help="add a catalogue effect to the device model (beside those of a --device "
        "file); repeatable, values in SI or with a unit (force_N=30N, gap_m=0.1mm), e.g. "
        "cavitation, coulomb_friction:force_N=30 or coulomb_friction:force_N=30,"
        "location=piston (friction behind freeplay). Effects: {effects}." + extra)


def parse_effect(text: str):
    """Build an Effect from ``NAME[:key=value,...]`` (values in SI).

    Parameters
    ----------
    text : str
        E.g. ``"coulomb_friction:force_N=30"``, ``"cavitation"`` or
        ``"coulomb_friction:force_N=30,location=piston"`` (a composition
        choice is a word, every other value a number).

    Returns
    -------
    liquidamp.device.effects.Effect

    Raises
    ------
    ParameterError
        Unknown effect or key (the registry's message), a malformed entry or
        a value that is not a number.

    Examples
    --------
    >>> parse_effect("freeplay:gap_m=1e-4").parameters
    {'gap_m': 0.0001}
    >>> parse_effect("coulomb_friction:force_N=100,location=piston").as_dict()
    {'force_N': 100.0, 'reverse_ratio': 1.0, 'location': 'piston'}
    >>> parse_effect("freeplay:gap_m=wide")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: --effect freeplay: gap_m must be a number [m], got 'wide'
    """
    from liquidamp.device.effects import EFFECTS, make_effect
    from liquidamp.errors import check_choice

    name, _, rest = str(text).partition(":")
    name = name.strip()
    effect = make_effect(name)  # the registry names an unknown effect
    keys = list(effect.as_dict())
    composition = effect.composition_keys()
    params = {}
    for entry in (e for e in rest.split(",") if e.strip()):
        key, eq, value = entry.partition("=")
        key = key.strip()
        if not eq or not key:
            raise ParameterError(f"--effect {name}: entries must be KEY=VALUE, got {entry!r}")
        check_choice(f"{name} parameter", key, keys)
        if key in params:
            raise ParameterError(f"--effect {name}: {key} given twice")
        if key in composition:  # a composition choice (e.g. location=piston), not a number
            params[key] = value.strip()
            continue
        try:
            params[key] = float(value)
        except ValueError:
            raise ParameterError(
                f"--effect {name}: {key} must be a number "
                f"[{EFFECTS[name].units.get(key, '-')}], got {value.strip()!r}") from None
    return make_effect(name, **params)


def effects_from_args(args) -> tuple:
    """The Effect objects of the ``--effect`` options (empty tuple if none).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments; ``args.effect`` is the list of ``NAME[:key=value,...]``.

    Returns
    -------
    tuple of liquidamp.device.effects.Effect
    """
    return tuple(parse_effect(t) for t in getattr(args, "effect", None) or ())


from liquidamp.commands._stderr import (  # noqa: E402,F401  (re-exported)
    collect_warnings,
    print_warnings,
    progress_bar,
    progress_lines,
    route_warnings,
    show_progress,
    warn_once,
    working,
)

# ---------------------------------------------------------------------------
# JSON


def _json_default(o):
    import numpy as np

    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"cannot write {type(o).__name__} to JSON")


def write_json(path: str | Path, data: dict) -> Path:
    """Write ``data`` as indented JSON (numpy arrays and scalars converted), atomically.

    The text is built first and written to a temporary file beside ``path``,
    then renamed (:func:`liquidamp.atomic.write_text`), so a failure never
    leaves a half-written file or destroys the previous one.

    Parameters
    ----------
    path : str or Path
        Output file.
    data : dict
        JSON-ready data; NaN and infinities are refused.

    Returns
    -------
    Path
        ``path``.
    """
    from liquidamp.atomic import write_text

    path = Path(path)
    text = json.dumps(data, indent=2, default=_json_default, allow_nan=False) + "\n"
    if str(path.parent) and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    return write_text(path, text)


def save_figure(fig, path, dpi: int = 110) -> None:
    """Save ``fig`` to ``path`` atomically (:func:`liquidamp.atomic.save_figure`)."""
    from liquidamp.atomic import save_figure as _save

    _save(fig, path, dpi=dpi)
