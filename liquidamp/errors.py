"""Errors and input checks shared by every part of liquidamp.

Every check raises before any work starts and names the quantity, the value
it was given, its unit and the allowed range, so that a user can correct the
input without reading the source.
"""

from __future__ import annotations

import math

__all__ = [
    "LiquidampError",
    "ParameterError",
    "ConvergenceError",
    "PressureError",
    "DataFileError",
    "LiquidampWarning",
    "check_positive",
    "check_nonnegative",
    "check_finite",
    "check_in_range",
    "check_choice",
]


class LiquidampError(ValueError):
    """Base class of every error liquidamp raises on purpose."""


class ParameterError(LiquidampError):
    """A parameter or an option lies outside its allowed range."""


class ConvergenceError(LiquidampError, RuntimeError):
    """An iterative solver (time integration, periodic steady state, fit) failed."""


class PressureError(LiquidampError, RuntimeError):
    """A chamber pressure reached zero: the fluid model is no longer valid there."""


class DataFileError(LiquidampError):
    """A measured-data file cannot be read honestly (row or column named)."""


class LiquidampWarning(UserWarning):
    """A result liquidamp returns carries a warning (also listed in the result and its JSON).

    Filter it with ``warnings.simplefilter("ignore", LiquidampWarning)`` or
    turn it into an error with ``"error"``.
    """


def _fmt(value) -> str:
    try:
        return f"{float(value):.6g}"
    except (TypeError, ValueError):
        return repr(value)


def check_finite(name: str, value: float, unit: str = "-") -> float:
    """Return ``float(value)`` or raise if it is not a finite real number.

    Parameters
    ----------
    name : str
        Name of the quantity, as the user knows it.
    value : float
        Value to check.
    unit : str
        Unit shown in the message, e.g. ``"m"``.

    Returns
    -------
    float
        The value as a float.

    Raises
    ------
    ParameterError
        If the value is not a finite real number.

    Examples
    --------
    >>> check_finite("A_p", 1e-3, "m^2")
    0.001
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a real number [{unit}], got {value!r}") from None
    if not math.isfinite(v):
        raise ParameterError(f"{name} must be finite [{unit}], got {value!r}")
    return v


def check_positive(name: str, value: float, unit: str = "-") -> float:
    """Return ``float(value)`` or raise unless it is finite and > 0.

    Examples
    --------
    >>> check_positive("V_01", 0.0, "m^3")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: V_01 must be > 0 [m^3], got 0
    """
    v = check_finite(name, value, unit)
    if v <= 0.0:
        raise ParameterError(f"{name} must be > 0 [{unit}], got {_fmt(value)}")
    return v


def check_nonnegative(name: str, value: float, unit: str = "-") -> float:
    """Return ``float(value)`` or raise unless it is finite and >= 0.

    Examples
    --------
    >>> check_nonnegative("friction_N", -1.0, "N")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: friction_N must be >= 0 [N], got -1
    """
    v = check_finite(name, value, unit)
    if v < 0.0:
        raise ParameterError(f"{name} must be >= 0 [{unit}], got {_fmt(value)}")
    return v


def check_in_range(
    name: str,
    value: float,
    low: float,
    high: float,
    unit: str = "-",
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """Return ``float(value)`` or raise unless ``low <= value <= high``.

    ``low_open`` / ``high_open`` make the bounds strict.

    Examples
    --------
    >>> check_in_range("n", 1.35, 1.0, 1.4)
    1.35
    >>> check_in_range("n", 2.0, 1.0, 1.4)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: n must lie in [1, 1.4] [-], got 2
    """
    v = check_finite(name, value, unit)
    bad_low = v <= low if low_open else v < low
    bad_high = v >= high if high_open else v > high
    if bad_low or bad_high:
        lb = "(" if low_open else "["
        hb = ")" if high_open else "]"
        raise ParameterError(
            f"{name} must lie in {lb}{_fmt(float(low))}, {_fmt(float(high))}{hb} [{unit}], "
            f"got {_fmt(value)}"
        )
    return v


def check_choice(name: str, value: str, choices) -> str:
    """Return ``value`` or raise listing the valid choices.

    Examples
    --------
    >>> check_choice("model", "fulll", ["full", "inerter"])
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown model 'fulll'; valid: full, inerter
    """
    choices = list(choices)
    if value not in choices:
        raise ParameterError(f"unknown {name} {value!r}; valid: {', '.join(choices)}")
    return value
