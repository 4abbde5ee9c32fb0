"""The record file format's vocabulary: accepted columns, channels and units, and the
header, text and number parsing of :func:`~liquidamp.analysis.measured.records.read_record`
(the format itself is documented in :mod:`liquidamp.analysis.measured.records`).

References
----------
.. [1] NIST SP 811 (2008), Guide for the Use of the International System of Units,
   App. B: 1 in = 0.0254 m, 1 lbf = 4.4482216152605 N, 1 kgf = 9.80665 N (exact).
"""

from __future__ import annotations

import csv
import math
import re

from liquidamp.errors import DataFileError

__all__ = ["COLUMN_UNITS", "CHANNEL_UNITS", "CHANNEL_SI", "COLUMN_NAMES", "parse_header",
           "find_header", "decode_text", "delimiter_of", "split_row", "number_of"]


COLUMN_UNITS: dict[str, dict[str, float]] = {
    "time": {"s": 1.0, "ms": 1e-3, "sec": 1.0, "secs": 1.0, "msec": 1e-3},
    "displacement": {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "\u00b5m": 1e-6,
                     "\u03bcm": 1e-6, "in": 0.0254, "inch": 0.0254, "inches": 0.0254},
    "force": {"N": 1.0, "daN": 10.0, "kN": 1e3, "kgf": 9.80665, "lbf": 4.4482216152605,
              "kip": 4448.2216152605, "lb": 4.4482216152605, "lbs": 4.4482216152605,
              "kips": 4448.2216152605},
}
"""Accepted columns and units: name -> {unit: factor to SI} (``sec``, ``msec``, ``inch``,
and ``lb``, ``lbs``, ``kips`` for a force -- pound-force as test laboratories write it --
read as ``s``, ``ms``, ``in``, ``lbf``, ``kip``)."""

CHANNEL_UNITS: dict[str, dict[str, tuple[float, float]]] = {
    "temperature": {"K": (1.0, 0.0), "C": (1.0, 273.15), "\u00b0C": (1.0, 273.15),
                    "degC": (1.0, 273.15), "F": (5 / 9, 273.15 - 32 * 5 / 9),
                    "\u00b0F": (5 / 9, 273.15 - 32 * 5 / 9)},
    "voltage": {"V": (1.0, 0.0), "mV": (1e-3, 0.0)},
    "current": {"A": (1.0, 0.0), "mA": (1e-3, 0.0)},
    "pressure": {"Pa": (1.0, 0.0), "kPa": (1e3, 0.0), "MPa": (1e6, 0.0), "bar": (1e5, 0.0),
                 "psi": (6894.757293168361, 0.0)},
}
"""Optional measured channels: name -> {unit: (factor, offset)}, SI value = factor x value +
offset (temperature in K, voltage in V, current in A, pressure in Pa)."""

#: SI unit of each measured channel.
CHANNEL_SI = {"temperature": "K", "voltage": "V", "current": "A", "pressure": "Pa"}

#: Other names test laboratories give the columns (name -> column), beside the columns' own.
COLUMN_NAMES = {"stroke": "displacement", "position": "displacement", "disp": "displacement",
                "displ": "displacement", "travel": "displacement", "load": "force",
                "temp": "temperature"}

_HEADER = re.compile(r"^\s*([A-Za-z_ ]+?)\s*(?:\[\s*([^\]]*?)\s*\]|\(\s*([^)]*?)\s*\))\s*$")
_CELL = re.compile(r"[A-Za-z_][A-Za-z_ ]*?\s*(?:\[[^\]]*\]|\([^)]*\))")


def _column(name):
    """The column a header name reads as (its own name, a synonym, or its last word), or None.

    ``Load cell force`` and ``piston stroke`` read as force and displacement; ``stroke
    velocity`` reads as nothing (its last word names no column).
    """
    known = (*COLUMN_UNITS, *CHANNEL_UNITS)
    for key in (name, name.split()[-1] if name.split() else name):
        key = COLUMN_NAMES.get(key, key)
        if key in known:
            return key
    return None


def parse_header(row, where, line: int = 1):
    """The columns a record's header row names, with their conversion to SI.

    Parameters
    ----------
    row : sequence of str
        The header's cells, each ``name [unit]`` or ``name (unit)``; the name is
        case-insensitive and reads as a column by its own name, a name of
        :data:`COLUMN_NAMES` (``stroke``, ``position``, ``load``, ...) or its last word
        (``load cell force``).  :data:`COLUMN_UNITS` are required, :data:`CHANNEL_UNITS`
        optional; any other column is not read (listed in the result's ``"unused"``).
    where : str
        The file, for messages.
    line : int
        The header's line in the file (1 = first), for messages.

    Returns
    -------
    dict
        column -> (column index, factor, offset): SI value = factor x value + offset; and
        ``"unused"`` -> list of (column index, header cell) of the columns not read.

    Raises
    ------
    DataFileError
        Naming the line, column and what is accepted: a required column missing (with the
        columns that were not read), a column named twice, a known column's unit unknown or
        its cell not of the ``name [unit]`` form.

    Examples
    --------
    >>> cols = parse_header(["Time (s)", "displacement [in]", "force [kip]"], "r.csv")
    >>> cols["displacement"], round(cols["force"][1], 4)
    ((1, 0.0254, 0.0), 4448.2216)
    >>> cols = parse_header(["time [s]", "stroke [mm]", "velocity [mm/s]", "load [kN]"], "r")
    >>> cols["displacement"][0], cols["force"][:2], cols["unused"]
    (1, (3, 1000.0), [(2, 'velocity [mm/s]')])
    """
    cols, unused = {}, []
    valid = ", ".join((*COLUMN_UNITS, *CHANNEL_UNITS))
    for j, cell in enumerate(row):
        m = _HEADER.match(cell)
        lead = re.match(r"\s*([A-Za-z_ ]*)", cell).group(1).strip().lower()
        key = _column(m.group(1).strip().lower() if m else lead)
        if key is None:
            unused.append((j, cell))
            continue
        if not m:
            raise DataFileError(
                f"{where}, line {line}, column {j + 1}: header {cell!r} must read "
                f"'name [unit]' (or 'name (unit)') with name one of {valid}")
        unit = (m.group(2) if m.group(2) is not None else m.group(3)).strip()
        units = ({u: (k, 0.0) for u, k in COLUMN_UNITS[key].items()} if key in COLUMN_UNITS
                 else CHANNEL_UNITS[key])
        if unit not in units:
            raise DataFileError(
                f"{where}, line {line}, column {j + 1} ({key}): unknown unit [{unit}]; valid: "
                + ", ".join(f"[{u}]" for u in units))
        if key in cols:
            raise DataFileError(
                f"{where}, line {line}, column {j + 1}: {cell!r} reads as column {key!r}, "
                f"which column {cols[key][0] + 1} ({row[cols[key][0]]!r}) already gives; "
                "keep one of them")
        cols[key] = (j, *units[unit])
    missing = [c for c in COLUMN_UNITS if c not in cols]
    if missing:
        extra = ("; columns not read: " + ", ".join(f"{j + 1} {c!r}" for j, c in unused)
                 if unused else "")
        raise DataFileError(f"{where}, line {line}: missing column(s) {', '.join(missing)}; the "
                            "header must name time [s], displacement [mm], [m] or [in], "
                            f"force [N], [kN], [lbf] or [kip]{extra}")
    cols["unused"] = unused
    return cols


def find_header(lines, where, scan: int = 100):
    """The header row of a record: its line index and cells, past comments and a preamble.

    Lines starting with ``#`` and blank lines are comments.  The header is the first other
    line that names the time, displacement and force columns; a test machine's preamble
    before it (``Specimen: ...``, ``Date: ...``) is passed over, among the first ``scan``
    lines.

    Parameters
    ----------
    lines : list of str
        The file's lines.
    where : str
        The file, for messages.
    scan : int
        How many lines may precede the header.

    Returns
    -------
    index : int
        The header's index in ``lines`` (0 = the file's first line).
    delimiter : str or None
        ``","``, ``";"``, tab, or None for columns separated by spaces.
    cells : list of str
        The header's cells, stripped.

    Raises
    ------
    DataFileError
        Where no line is a header: the message is the one the first non-comment line
        raises (its unknown column, unit or missing column).

    Examples
    --------
    >>> find_header(["# rig 3", "Date: 2026-11-26", "time [s] stroke [mm] load [N]", "0 1 2"],
    ...             "r.csv")
    (2, None, ['time [s]', 'stroke [mm]', 'load [N]'])
    """
    first = None
    for i, text in enumerate(lines[:scan]):
        if not text.strip() or text.lstrip().startswith("#"):
            continue
        delim = delimiter_of(text)
        cells = split_row(text, delim, header=True)
        if first is None:
            first = (i, cells)
        try:
            parse_header(cells, where, i + 1)
        except DataFileError:
            continue
        return i, delim, cells
    if first is None:
        raise DataFileError(f"{where} holds no header row (only comments or blank lines)")
    parse_header(first[1], where, first[0] + 1)  # raises the first line's own complaint
    raise AssertionError("unreachable")  # pragma: no cover


def split_row(text: str, delimiter, header: bool = False):
    """The cells of one line of a record.

    Parameters
    ----------
    text : str
        The line.
    delimiter : str or None
        From :func:`delimiter_of`; None splits on runs of spaces (a header's cells are
        then its ``name [unit]`` groups, which may hold spaces).
    header : bool
        Whether the line is the header.

    Returns
    -------
    list of str
        The cells, stripped.

    Examples
    --------
    >>> split_row("load cell force [kN]  time [s]", None, header=True)
    ['load cell force [kN]', 'time [s]']
    """
    if delimiter is None:
        if header:
            return [c.strip() for c in _CELL.findall(text)] or text.split()
        return text.split()
    return [c.strip() for c in next(csv.reader([text], delimiter=delimiter))]


def read_rows(body, first_line: int, delimiter, columns: dict, ncol: int, where: str):
    """The values of a record's columns, row after row, in SI.

    Parameters
    ----------
    body : list of str
        The lines after the header.
    first_line : int
        The file's line number of ``body[0]`` (1 = the file's first line).
    delimiter : str or None
        From :func:`delimiter_of` (None: runs of spaces); with ``;`` or tabs a decimal
        comma is read.
    columns : dict
        ``{name: (column index, factor, offset)}`` from :func:`parse_header` (the value in
        SI is ``cell x factor + offset``).
    ncol : int
        The header's cell count; every row must have as many.
    where : str
        The file, for messages.

    Returns
    -------
    data : dict
        ``{name: list of float}`` [SI].
    lines : list of int
        The file's line number of each row read (blank and ``#`` lines skipped).

    Raises
    ------
    DataFileError
        Naming the line and column at fault (a wrong cell count, a cell that is not a
        finite number, a decimal comma in a comma-separated file, a thousands separator).

    Examples
    --------
    >>> data, lines = read_rows(["0;1,5", "# note", "0,01;2"], 2, ";",
    ...                         {"time": (0, 1.0, 0.0), "force": (1, 1e3, 0.0)}, 2, "x.csv")
    >>> data["force"], lines
    ([1500.0, 2000.0], [2, 4])
    """
    decimal_comma = delimiter not in (",", None)
    data = {name: [] for name in columns}
    line_of = []
    sep = {",": "','", ";": "';'", "\t": "tab", None: "spaces"}[delimiter]
    rows = (csv.reader(body, delimiter=delimiter) if delimiter is not None
            else (text.split() for text in body))
    for i, row in enumerate(rows, start=first_line):
        row = [c.strip() for c in row]
        if not any(row) or row[0].startswith("#"):
            continue
        line_of.append(i)
        if len(row) != ncol:
            hint = ""
            if delimiter == "," and len(row) == 2 * ncol and all(
                    re.fullmatch(r"[+-]?\d*([eE][+-]?\d+)?", c) for c in row):
                hint = ("; the values seem to use a decimal comma, which needs the columns "
                        "separated by ';' (or tabs), as in the header")
            raise DataFileError(f"{where}, line {i}: {len(row)} fields separated by {sep}, "
                                f"the header has {ncol}{hint}")
        for name, (j, factor, offset) in columns.items():
            cell = row[j]
            try:
                value = number_of(cell, decimal_comma)
            except ValueError:
                why = "is not a number"
                if "," in cell and "." in cell:
                    why = ("is not a number (it holds both '.' and ','; write numbers without "
                           "a thousands separator)")
                raise DataFileError(
                    f"{where}, line {i}, column {j + 1} ({name}): {cell!r} {why}") from None
            if not math.isfinite(value):
                raise DataFileError(
                    f"{where}, line {i}, column {j + 1} ({name}): {cell!r} is not finite")
            data[name].append(value * factor + offset)
    return data, line_of


_DECIMAL_COMMA = re.compile(r"^[+-]?(\d+,\d*|,\d+)([eE][+-]?\d+)?$")


def decode_text(raw: bytes, where: str) -> str:
    """Text of a record file.

    Parameters
    ----------
    raw : bytes
        The file's content.
    where : str
        The file, for messages.

    Returns
    -------
    str
        UTF-8 (a byte-order mark, as Excel writes it, dropped), UTF-16 with its mark, or
        Latin-1 for a text file that is not UTF-8.

    Raises
    ------
    DataFileError
        For binary content (a NUL byte or more than 5 % control bytes in the first 4 kB).

    Examples
    --------
    >>> decode_text("\ufefftime [s]".encode("utf-8"), "r.csv")
    'time [s]'
    """
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError:
            pass
    head = raw[:4096]
    nul = head.find(b"\x00")
    control = sum(1 for c in head if c < 32 and c not in (9, 10, 13))
    if nul >= 0 or (head and control > 0.05 * len(head)):
        at = f"NUL byte at offset {nul}" if nul >= 0 else f"{control} control bytes"
        raise DataFileError(
            f"{where} is not a text CSV file (binary content: {at} in its first "
            f"{len(head)} bytes); a record is a CSV text file whose header row names "
            "time [s], displacement [mm], [m] or [in], force [N], [kN], [lbf] or [kip]")
    try:
        return raw.decode("utf-8-sig")  # a UTF-8 byte-order mark (Excel) is dropped
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def delimiter_of(header: str):
    """Column separator of a record: ',' unless the header is separated by ';', tabs or spaces.

    Parameters
    ----------
    header : str
        The header row as read (units in brackets or parentheses may hold anything).

    Returns
    -------
    str or None
        ``","``, ``";"``, ``"\t"``, or None where the header holds none of them and several
        ``name [unit]`` groups (columns separated by spaces).

    Examples
    --------
    >>> delimiter_of("time [s];displacement [mm];force [N]")
    ';'
    >>> delimiter_of("time[s]  displacement[mm]  force[N]") is None
    True
    """
    outside = re.sub(r"\[[^\]]*\]|\([^)]*\)", "", header)  # units may hold anything
    counts = {d: outside.count(d) for d in (",", ";", "\t")}
    if counts[","] == 0 and (counts[";"] or counts["\t"]):
        return ";" if counts[";"] >= counts["\t"] else "\t"
    if not any(counts.values()) and len(_CELL.findall(header)) > 1:
        return None
    return ","


def number_of(cell: str, decimal_comma: bool):
    """The number a record's cell holds.

    Parameters
    ----------
    cell : str
        The cell, stripped.
    decimal_comma : bool
        Whether ``0,005`` reads as 0.005 (columns not separated by commas).

    Returns
    -------
    float

    Raises
    ------
    ValueError
        Where the cell is not a number (the reader names line and column).

    Examples
    --------
    >>> number_of("0,005", True), number_of("1e-3", False)
    (0.005, 0.001)
    """
    try:
        return float(cell)
    except ValueError:
        if decimal_comma and _DECIMAL_COMMA.match(cell):
            return float(cell.replace(",", "."))
        raise
