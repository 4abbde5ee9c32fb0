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
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

from liquidamp.errors import ParameterError

#: Largest number of points a sweep option (``START:STOP:COUNT`` or a comma
#: list) may hold; a larger grid is a typo, not a job for one command.
MAX_POINTS = 100_000

_LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6}


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
    >>> parse_length("0.002")
    0.002
    """
    m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*([a-z]*)\s*", str(text))
    if not m:
        raise ParameterError(f"{name} must be a number with an optional unit (m, mm), got {text!r}")
    unit = m.group(2) or "m"
    if unit not in _LENGTH_UNITS:
        raise ParameterError(
            f"{name} has unknown unit {unit!r} in {text!r}; valid: {', '.join(_LENGTH_UNITS)}"
        )
    try:
        value = float(m.group(1)) * _LENGTH_UNITS[unit]
    except ValueError:
        raise ParameterError(f"{name} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise ParameterError(f"{name} must be finite, got {text!r}")
    return value


def _number(item, text: str, name: str, what: str) -> float:
    """``item(text)``; a ParameterError naming ``name`` and ``what`` if it fails."""
    try:
        value = item(text.strip())
    except ParameterError:
        raise
    except (ValueError, TypeError):
        raise ParameterError(f"{name} {what} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise ParameterError(f"{name} {what} must be finite, got {text!r}")
    return value


def parse_list(text: str, name: str, *, log: bool = False, item=float,
               max_count: int = MAX_POINTS):
    """Parse ``a,b,c`` or ``START:STOP:COUNT`` (log-spaced when ``log``, else linear).

    Parameters
    ----------
    text : str
        Comma list or range.
    name : str
        Name of the option in error messages.
    log : bool
        ``START:STOP:COUNT`` is geometric (``numpy.geomspace``) when True,
        linear (``numpy.linspace``) otherwise.
    item : callable
        Converts one entry (default ``float``).
    max_count : int
        Largest number of values (default :data:`MAX_POINTS`).

    Returns
    -------
    numpy.ndarray
        The values, in the option's unit (``item`` converts).

    Raises
    ------
    ParameterError
        Naming the option, the entry at fault and what is allowed.

    Examples
    --------
    >>> parse_list("1,2,4", "frequency").tolist()
    [1.0, 2.0, 4.0]
    >>> parse_list("1:100:3", "frequency", log=True).tolist()
    [1.0, 10.0, 100.0]
    >>> parse_list("100:400:10000000", "rpm")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: rpm COUNT must lie in [1, 100000] (points of one sweep), \
got 10000000
    """
    import numpy as np

    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise ParameterError(f"{name} range must be START:STOP:COUNT, got {text!r}")
        start = _number(item, parts[0], name, "START")
        stop = _number(item, parts[1], name, "STOP")
        try:
            count = int(parts[2])
        except ValueError:
            raise ParameterError(
                f"{name} COUNT must be an integer in [1, {max_count}], got {parts[2]!r}"
            ) from None
        if not 1 <= count <= max_count:
            raise ParameterError(
                f"{name} COUNT must lie in [1, {max_count}] (points of one sweep), got {count}")
        if log:
            if start <= 0 or stop <= 0:
                raise ParameterError(
                    f"{name} START:STOP:COUNT is log-spaced and needs START, STOP > 0, "
                    f"got {text!r}")
            return np.geomspace(start, stop, count)
        return np.linspace(start, stop, count)
    entries = [v for v in text.split(",") if v.strip()]
    if not entries:
        raise ParameterError(f"{name} is empty: {text!r}")
    if len(entries) > max_count:
        raise ParameterError(f"{name} holds {len(entries)} values; at most {max_count}")
    values = [_number(item, v, name, "entry") for v in entries]
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
            "refusing to replace it: give a new folder or --force")


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


def add_force_argument(parser) -> None:
    """Add ``--force`` to ``parser``: allow replacing the files of an existing output folder."""
    parser.add_argument("--force", action="store_true",
                        help="replace the files of an existing output folder (without it an "
                        "existing report or index is never overwritten)")


def add_quiet_argument(parser) -> None:
    """Add ``--quiet``: no progress bar."""
    parser.add_argument("--quiet", action="store_true",
                        help="no progress bar (there is none when stderr is not a terminal)")


# ---------------------------------------------------------------------------
# effects


def add_effect_argument(parser, extra: str = "") -> None:
    """Add the repeatable ``--effect NAME[:key=value,...]`` option."""
    parser.add_argument(
        "--effect", action="append", default=[], metavar="NAME[:KEY=VALUE,...]",
        help="add a catalogue effect to the device model; repeatable, values in SI, e.g. "
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


# ---------------------------------------------------------------------------
# stderr: warnings and progress


def collect_warnings(data) -> list[str]:
    """Every string of every ``"warnings"`` list in a nested JSON-ready ``data``, in order.

    Parameters
    ----------
    data : dict or list
        JSON-ready result (dicts, lists, scalars).

    Returns
    -------
    list of str
        Each warning once, in the order met.

    Examples
    --------
    >>> collect_warnings({"warnings": ["a"], "steps": [{"warnings": ["b", "a"]}]})
    ['a', 'b']
    """
    out: list[str] = []

    def walk(obj):
        if isinstance(obj, dict):
            for key, value in obj.items():
                if key == "warnings" and isinstance(value, (list, tuple)):
                    out.extend(str(w) for w in value if str(w) not in out)
                else:
                    walk(value)
        elif isinstance(obj, (list, tuple)):
            for value in obj:
                walk(value)

    walk(data)
    return list(dict.fromkeys(out))


def print_warnings(command: str, data) -> None:
    """Print each warning of ``data`` (see :func:`collect_warnings`) as one stderr line.

    Parameters
    ----------
    command : str
        Command name for the ``liquidamp COMMAND: warning: ...`` prefix.
    data : dict
        JSON-ready result.
    """
    for w in collect_warnings(data):
        print(f"liquidamp {command}: warning: {w}", file=sys.stderr)


class _NoBar:
    def update(self, n: int = 1) -> None:
        pass

    def set_postfix_str(self, text: str) -> None:
        pass

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def progress_bar(total: int, desc: str, quiet: bool = False):
    """A tqdm progress bar on stderr, or a do-nothing bar.

    The bar is shown only when stderr is a terminal, ``quiet`` is False and
    tqdm is installed.  Use as a context manager; ``update(n)`` advances it.

    Parameters
    ----------
    total : int
        Number of steps.
    desc : str
        Label of the bar.
    quiet : bool
        Never show the bar (``--quiet``).

    Returns
    -------
    tqdm.tqdm or a do-nothing object with the same ``update``/``close``

    Examples
    --------
    >>> with progress_bar(3, "points", quiet=True) as bar:
    ...     bar.update()
    """
    tty = bool(getattr(sys.stderr, "isatty", lambda: False)())
    if quiet or not tty:
        return _NoBar()
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        return _NoBar()
    return tqdm(total=total, desc=desc, file=sys.stderr, leave=False, dynamic_ncols=True)


# ---------------------------------------------------------------------------
# JSON


def write_json(path: str | Path, data: dict) -> Path:
    """Write ``data`` as indented JSON (numpy arrays and scalars converted).

    The text is built first and written to a temporary file beside ``path``,
    then renamed, so a failure never leaves a half-written file or destroys
    the previous one.

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

    def default(o):
        import numpy as np

        if isinstance(o, np.ndarray):
            return o.tolist()
        if isinstance(o, np.generic):
            return o.item()
        if isinstance(o, Path):
            return str(o)
        raise TypeError(f"cannot write {type(o).__name__} to JSON")

    path = Path(path)
    text = json.dumps(data, indent=2, default=default, allow_nan=False) + "\n"
    if str(path.parent) and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(text)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path
