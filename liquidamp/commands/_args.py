"""Argument parsing shared by the sub-commands: lists, ranges and lengths with units."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np

from liquidamp.errors import ParameterError

_LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6}


def parse_length(text: str, name: str = "length") -> float:
    """Parse a length in SI or with a unit suffix, return metres.

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


def parse_list(text: str, name: str, *, log: bool = False, item=float) -> np.ndarray:
    """Parse ``a,b,c`` or ``start:stop:count`` (log-spaced when ``log``).

    Examples
    --------
    >>> parse_list("1,2,4", "frequency").tolist()
    [1.0, 2.0, 4.0]
    >>> parse_list("1:100:3", "frequency", log=True).tolist()
    [1.0, 10.0, 100.0]
    """
    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise ParameterError(f"{name} range must be START:STOP:COUNT, got {text!r}")
        start, stop = item(parts[0]), item(parts[1])
        try:
            count = int(parts[2])
        except ValueError:
            raise ParameterError(f"{name} COUNT must be an integer, got {parts[2]!r}") from None
        if count < 1:
            raise ParameterError(f"{name} COUNT must be >= 1, got {count}")
        if log:
            if start <= 0 or stop <= 0:
                raise ParameterError(f"{name} log range needs positive ends, got {text!r}")
            return np.geomspace(start, stop, count)
        return np.linspace(start, stop, count)
    try:
        values = [item(v) for v in text.split(",") if v.strip()]
    except (ValueError, ParameterError) as exc:
        raise ParameterError(
            f"{name} must be a comma list of numbers, got {text!r}: {exc}"
        ) from None
    if not values:
        raise ParameterError(f"{name} is empty: {text!r}")
    return np.asarray(values, dtype=float)


def write_json(path: str | Path, data: dict) -> Path:
    """Write ``data`` as indented JSON (numpy arrays and scalars converted)."""

    def default(o):
        if isinstance(o, np.ndarray):
            return o.tolist()
        if isinstance(o, np.generic):
            return o.item()
        if isinstance(o, Path):
            return str(o)
        raise TypeError(f"cannot write {type(o).__name__} to JSON")

    path = Path(path)
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2, default=default, allow_nan=False) + "\n")
    return path
