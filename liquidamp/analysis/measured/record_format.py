"""The record file format's vocabulary: accepted columns, channels and units, and the
header, text and number parsing of :func:`~liquidamp.analysis.measured.records.read_record`
(the format itself is documented in :mod:`liquidamp.analysis.measured.records`).

References
----------
.. [1] NIST SP 811 (2008), Guide for the Use of the International System of Units,
   App. B: 1 in = 0.0254 m, 1 lbf = 4.4482216152605 N (exact).
"""

from __future__ import annotations

import re

from liquidamp.errors import DataFileError

__all__ = ["COLUMN_UNITS", "CHANNEL_UNITS", "CHANNEL_SI", "parse_header", "decode_text",
           "delimiter_of", "number_of"]


COLUMN_UNITS: dict[str, dict[str, float]] = {
    "time": {"s": 1.0, "ms": 1e-3},
    "displacement": {"m": 1.0, "mm": 1e-3, "um": 1e-6, "in": 0.0254},
    "force": {"N": 1.0, "kN": 1e3, "lbf": 4.4482216152605, "kip": 4448.2216152605},
}
"""Accepted columns and units: name -> {unit: factor to SI}."""

CHANNEL_UNITS: dict[str, dict[str, tuple[float, float]]] = {
    "temperature": {"K": (1.0, 0.0), "C": (1.0, 273.15)},
    "voltage": {"V": (1.0, 0.0), "mV": (1e-3, 0.0)},
    "current": {"A": (1.0, 0.0), "mA": (1e-3, 0.0)},
    "pressure": {"Pa": (1.0, 0.0), "kPa": (1e3, 0.0), "MPa": (1e6, 0.0), "bar": (1e5, 0.0),
                 "psi": (6894.757293168361, 0.0)},
}
"""Optional measured channels: name -> {unit: (factor, offset)}, SI value = factor x value +
offset (temperature in K, voltage in V, current in A, pressure in Pa)."""

#: SI unit of each measured channel.
CHANNEL_SI = {"temperature": "K", "voltage": "V", "current": "A", "pressure": "Pa"}

_HEADER = re.compile(r"^\s*([A-Za-z_ ]+?)\s*(?:\[\s*([^\]]*?)\s*\]|\(\s*([^)]*?)\s*\))\s*$")


def parse_header(row, where):
    """The columns a record's header row names, with their conversion to SI.

    Parameters
    ----------
    row : sequence of str
        The header's cells, each ``name [unit]`` or ``name (unit)`` (name case-insensitive;
        :data:`COLUMN_UNITS` required, :data:`CHANNEL_UNITS` optional).
    where : str
        The file, for messages.

    Returns
    -------
    dict
        name -> (column index, factor, offset): SI value = factor x value + offset.

    Raises
    ------
    DataFileError
        Naming the column and what is accepted: a cell not of that form, an unknown column
        or unit, a column given twice, a required column missing.

    Examples
    --------
    >>> cols = parse_header(["Time (s)", "displacement [in]", "force [kip]"], "r.csv")
    >>> cols["displacement"], round(cols["force"][1], 4)
    ((1, 0.0254, 0.0), 4448.2216)
    """
    cols = {}
    valid = ", ".join((*COLUMN_UNITS, *CHANNEL_UNITS))
    for j, cell in enumerate(row):
        m = _HEADER.match(cell)
        if not m:
            raise DataFileError(
                f"{where}, line 1, column {j + 1}: header {cell!r} must read 'name [unit]' "
                f"(or 'name (unit)') with name one of {valid}")
        name = m.group(1).strip().lower()
        unit = (m.group(2) if m.group(2) is not None else m.group(3)).strip()
        if name not in COLUMN_UNITS and name not in CHANNEL_UNITS:
            raise DataFileError(
                f"{where}, line 1, column {j + 1}: unknown column {name!r}; valid: {valid}")
        units = ({u: (k, 0.0) for u, k in COLUMN_UNITS[name].items()} if name in COLUMN_UNITS
                 else CHANNEL_UNITS[name])
        if unit not in units:
            raise DataFileError(
                f"{where}, line 1, column {j + 1} ({name}): unknown unit [{unit}]; valid: "
                + ", ".join(f"[{u}]" for u in units))
        if name in cols:
            raise DataFileError(f"{where}, line 1, column {j + 1}: column {name!r} given twice")
        cols[name] = (j, *units[unit])
    missing = [c for c in COLUMN_UNITS if c not in cols]
    if missing:
        raise DataFileError(f"{where}: missing column(s) {', '.join(missing)}; the header must "
                            "name time [s], displacement [mm], [m] or [in], "
                            "force [N], [kN], [lbf] or [kip]")
    return cols


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


def delimiter_of(header: str) -> str:
    """Column separator of a record: ',' unless the header is separated by ';' or tabs.

    Parameters
    ----------
    header : str
        The header row as read (units in brackets or parentheses may hold anything).

    Returns
    -------
    str
        ``","``, ``";"`` or ``"\t"``.

    Examples
    --------
    >>> delimiter_of("time [s];displacement [mm];force [N]")
    ';'
    """
    outside = re.sub(r"\[[^\]]*\]|\([^)]*\)", "", header)  # units may hold anything
    counts = {d: outside.count(d) for d in (",", ";", "\t")}
    if counts[","] == 0 and (counts[";"] or counts["\t"]):
        return ";" if counts[";"] >= counts["\t"] else "\t"
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
