"""Quantities with units, bounded options and value ranges, checked at parse time.

Every physical option of the command line takes a number in the option's
unit or a number with a unit suffix (``3Hz``, ``250rpm``, ``3mm``, ``2kN``,
``5%``); every one has a named bound; a list option takes ``a,b,c`` or a
range ``START:STOP:COUNT`` (linear), ``lin:START:STOP:COUNT`` or
``log:START:STOP:COUNT`` (geometric).  The conversions are argparse
``type=`` functions, so a bad value ends the command with one line and
exit code 2 before any numerical library is imported (well under 0.5 s).

The registries the parser checks names against (presets, models, effects)
are read here without importing the numerical modules; ``tests/test_cli_conventions.py``
holds them equal to the library's registries.

This module imports only the standard library.
"""

from __future__ import annotations

import argparse
import math
import re
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

__all__ = ["UNITS", "parse_quantity", "quantity_type", "Grid", "parse_grid", "grid_type",
           "name_type", "preset_names", "MODEL_NAMES", "EFFECT_UNITS", "EFFECT_CHOICES",
           "effect_type", "Bound", "BOUNDS"]

#: Units accepted per dimension: name -> factor to the option's base unit.
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6},
    "frequency": {"Hz": 1.0, "kHz": 1e3, "rpm": 1.0 / 60.0, "rad/s": 1.0 / (2.0 * math.pi)},
    "rotor_speed": {"rpm": 1.0, "Hz": 60.0, "rad/s": 60.0 / (2.0 * math.pi)},
    "force": {"N": 1.0, "kN": 1e3, "mN": 1e-3},
    "time": {"s": 1.0, "ms": 1e-3, "min": 60.0},
    "pressure": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "bar": 1e5, "psi": 6894.757293168},
    "mass": {"kg": 1.0, "g": 1e-3},
    "stiffness": {"N/m": 1.0, "N/mm": 1e3, "kN/m": 1e3, "kN/mm": 1e6},
    "damping": {"N s/m": 1.0, "Ns/m": 1.0, "kN s/m": 1e3, "kNs/m": 1e3},
    "velocity": {"m/s": 1.0, "mm/s": 1e-3},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0},
    "angular_speed": {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0, "Hz": 2.0 * math.pi},
    "ratio": {"-": 1.0, "%": 1e-2},
    "reduced": {"-": 1.0},
    "conductance": {"m^3/(s Pa)": 1.0},
    "lag_damping": {"N m s/rad": 1.0, "kN m s/rad": 1e3},
    "area": {"m^2": 1.0, "cm^2": 1e-4, "mm^2": 1e-6},
    "volume": {"m^3": 1.0, "l": 1e-3, "cm^3": 1e-6, "ml": 1e-6},
}
#: Base unit of each dimension (what a bare number means).
BASE = {"length": "m", "frequency": "Hz", "rotor_speed": "rpm", "force": "N", "time": "s",
        "pressure": "Pa", "mass": "kg", "stiffness": "N/m", "damping": "N s/m",
        "velocity": "m/s", "angle": "rad", "angular_speed": "rad/s", "ratio": "-",
        "reduced": "-", "conductance": "m^3/(s Pa)", "lag_damping": "N m s/rad", "area": "m^2",
        "volume": "m^3"}
#: Dimension of an effect parameter's unit (``Effect.units``).
_UNIT_DIMENSION = {"N": "force", "m": "length", "Pa": "pressure", "kg": "mass",
                   "N/m": "stiffness", "N s/m": "damping", "m/s": "velocity", "rad": "angle",
                   "rad/s": "angular_speed", "-": "ratio", "m^3/(s Pa)": "conductance",
                   "m^2": "area", "m^3": "volume"}

_NUMBER = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:inf|nan))"
                     r"\s*(.*?)\s*", re.IGNORECASE)


def parse_quantity(text: str, dimension: str, name: str) -> float:
    """A number with an optional unit suffix, in the base unit of ``dimension``.

    Parameters
    ----------
    text : str
        E.g. ``"3"``, ``"3mm"``, ``"250 rpm"``, ``"-2kN"``.
    dimension : str
        A key of :data:`UNITS`.
    name : str
        Quantity name for the error message.

    Returns
    -------
    float
        The value in ``BASE[dimension]`` (may be infinite or NaN: bounds are
        checked by :func:`quantity_type`).

    Raises
    ------
    ValueError
        Not a number, or a unit of another dimension; the message names the
        quantity, the text and the valid units.

    Examples
    --------
    >>> parse_quantity("3mm", "length", "amplitude")
    0.003
    >>> parse_quantity("4.2Hz", "rotor_speed", "rpm")
    252.0
    >>> parse_quantity("3parsecs", "length", "amplitude")
    Traceback (most recent call last):
    ...
    ValueError: amplitude has unknown unit 'parsecs' in '3parsecs'; valid: m, mm, cm, um
    """
    units = UNITS[dimension]
    m = _NUMBER.fullmatch(str(text))
    if not m:
        raise ValueError(f"{name} must be a number with an optional unit "
                         f"({', '.join(units)}), got {text!r}")
    unit = m.group(2) or BASE[dimension]
    if unit not in units:
        raise ValueError(f"{name} has unknown unit {unit!r} in {text!r}; valid: "
                         f"{', '.join(units)}")
    return float(m.group(1)) * units[unit]


@dataclass(frozen=True)
class Bound:
    """Allowed range of an option, in its base unit, with the reason.

    Attributes
    ----------
    low, high : float
        Ends of the range.
    low_open, high_open : bool
        Exclude that end.
    why : str
        Why the bound is there (shown in the error).
    """

    low: float = 0.0
    high: float = math.inf
    low_open: bool = True
    high_open: bool = False
    why: str = ""

    def holds(self, value: float) -> bool:
        """True if ``value`` is finite and inside the range."""
        if not math.isfinite(value):
            return False
        lo = value > self.low if self.low_open else value >= self.low
        hi = value < self.high if self.high_open else value <= self.high
        return lo and hi

    def text(self, unit: str) -> str:
        """``'> 0 and at most 10000 [Hz]'`` style description."""
        u = f" [{unit}]" if unit and unit != "-" else ""
        lo = f"{'>' if self.low_open else '>='} {self.low:g}" if math.isfinite(self.low) else ""
        if math.isinf(self.high):
            return f"{lo}{u}"
        hi = f"{'below' if self.high_open else 'at most'} {self.high:g}"
        return f"{lo} and {hi}{u}" if lo else f"{hi}{u}"


#: The named bounds of the command line (base units of their dimension).
BOUNDS = {
    "frequency": Bound(0.0, 1e4, why=" (the highest frequency of a lumped device model)"),
    "amplitude": Bound(0.0, 1.0, why=" (longer than any device's stroke)"),
    "offset": Bound(-1.0, 1.0, low_open=False, why=" (longer than any device's stroke)"),
    "rpm": Bound(0.0, 1e4, why=" (167 Hz: faster than any rotor)"),
    "arm": Bound(0.0, 10.0, why=" (a damper arm is a fraction of the blade radius)"),
    "zeta": Bound(0.0, 1.0, why=" (a damping ratio to size for; 1 is critical)"),
    "reduced_speed": Bound(0.0, 100.0, why=" (reduced speed U/(b omega_theta))"),
    "reduced_frequency": Bound(0.0, 100.0, why=" (reduced frequency k = omega b / U)"),
    "t_end": Bound(0.0, 600.0, why=" (the run keeps every sample, at least 200 per second; "
                   "a limit cycle settles in 10-60 s)"),
    "filter": Bound(0.0, 1e5, why=" (above any record's sampling rate)"),
    "harmonics": Bound(2.0, 1e4, low_open=False),
    "rtol": Bound(1e-14, 1e-2, low_open=False),
}


def quantity_type(flag: str, dimension: str, bound: Bound | str):
    """argparse ``type=``: a quantity with an optional unit, inside ``bound``.

    Parameters
    ----------
    flag : str
        Option name, e.g. ``"--frequency"`` (its name without dashes names
        the quantity in the message).
    dimension : str
        Key of :data:`UNITS`.
    bound : Bound or str
        The bound, or a key of :data:`BOUNDS`.

    Returns
    -------
    callable
        ``str -> float`` in the base unit; raises ``argparse.ArgumentTypeError``.

    Examples
    --------
    >>> quantity_type("--frequency", "frequency", "frequency")("250rpm")
    4.166666666666667
    >>> quantity_type("--rpm", "rotor_speed", "rpm")("1e300")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: rpm must be > 0 and at most 10000 [rpm] (167 Hz: faster than \
any rotor), got '1e300'
    """
    b = BOUNDS[bound] if isinstance(bound, str) else bound
    name = flag.lstrip("-")
    unit = BASE[dimension]

    def convert(text: str) -> float:
        try:
            value = parse_quantity(text, dimension, name)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None
        if not b.holds(value):
            raise argparse.ArgumentTypeError(
                f"{name} must be {b.text(unit)}{b.why}, got {text!r}")
        return value

    convert.__name__ = flag
    return convert


# ---------------------------------------------------------------------------
# lists and ranges


class Grid(tuple):
    """Values of a list or range option (a tuple of floats in the base unit), with its text.

    Examples
    --------
    >>> g = parse_grid("log:1:100:3", "frequency", "frequency", "frequency")
    >>> list(g), g.spacing
    ([1.0, 10.0, 100.0], 'log')
    """

    text: str = ""
    spacing: str = "list"

    def __new__(cls, values, text: str = "", spacing: str = "list"):
        obj = super().__new__(cls, values)
        obj.text, obj.spacing = text, spacing
        return obj


#: Largest number of points one list or range may hold.
MAX_POINTS = 100_000


def parse_grid(text: str, name: str, dimension: str, bound: Bound | str | None = None, *,
               max_count: int = MAX_POINTS) -> Grid:
    """Parse ``a,b,c``, ``START:STOP:COUNT`` (linear), ``lin:...`` or ``log:...``.

    Parameters
    ----------
    text : str
        The option's value.
    name : str
        Quantity name in messages.
    dimension : str
        Key of :data:`UNITS`; each entry may carry a unit.
    bound : Bound or str, optional
        Every value must lie in it.
    max_count : int
        Most values.

    Returns
    -------
    Grid

    Raises
    ------
    ValueError
        Naming the quantity, the part at fault and what is allowed.

    Examples
    --------
    >>> list(parse_grid("0:2mm:3", "amplitude", "length"))
    [0.0, 0.001, 0.002]
    >>> parse_grid("1:10:0", "frequency", "frequency")
    Traceback (most recent call last):
    ...
    ValueError: frequency COUNT must lie in [1, 100000] (points of one sweep), got 0
    """
    b = BOUNDS[bound] if isinstance(bound, str) else bound
    raw = str(text).strip()
    spacing, body = "lin", raw
    low = raw.lower()
    for prefix in ("log:", "lin:"):
        if low.startswith(prefix):
            spacing, body = prefix[:-1], raw[len(prefix):]
            break
    unit = BASE[dimension]

    def one(part: str, what: str) -> float:
        try:
            value = parse_quantity(part.strip(), dimension, f"{name} {what}")
        except ValueError as exc:
            if "unknown unit" in str(exc):
                raise
            raise ValueError(f"{name} {what} must be a number, got {part.strip()!r}") from None
        if not math.isfinite(value):
            raise ValueError(f"{name} {what} must be finite, got {part.strip()!r}")
        if b is not None and not b.holds(value):
            raise ValueError(f"{name} {what} must be {b.text(unit)}{b.why}, got {part.strip()!r}")
        return value

    if ":" in body or spacing != "lin" or low.startswith("lin:"):
        parts = body.split(":")
        if len(parts) != 3:
            raise ValueError(f"{name} range must be START:STOP:COUNT (linear), "
                             f"lin:START:STOP:COUNT or log:START:STOP:COUNT, got {raw!r}")
        start, stop = one(parts[0], "START"), one(parts[1], "STOP")
        try:
            count = int(parts[2])
        except ValueError:
            raise ValueError(f"{name} COUNT must be an integer in [1, {max_count}], "
                             f"got {parts[2]!r}") from None
        if not 1 <= count <= max_count:
            raise ValueError(f"{name} COUNT must lie in [1, {max_count}] (points of one "
                             f"sweep), got {count}")
        if count == 1:
            return Grid([start], raw, spacing)
        if spacing == "log":
            if start <= 0 or stop <= 0:
                raise ValueError(f"{name} log:START:STOP:COUNT is log-spaced and needs "
                                 f"START, STOP > 0, got {raw!r}")
            r = math.log(stop / start) / (count - 1)
            vals = [start * math.exp(r * i) for i in range(count)]
        else:
            step = (stop - start) / (count - 1)
            vals = [start + step * i for i in range(count)]
        vals[-1] = stop
        return Grid(vals, raw, spacing)
    entries = [v for v in body.split(",") if v.strip()]
    if not entries:
        raise ValueError(f"{name} is empty: {raw!r}")
    if len(entries) > max_count:
        raise ValueError(f"{name} holds {len(entries)} values; at most {max_count}")
    return Grid([one(v, "entry") for v in entries], raw, "list")


def grid_type(flag: str, dimension: str, bound: Bound | str | None = None, *,
              max_count: int = MAX_POINTS):
    """argparse ``type=`` of :func:`parse_grid` (values in the base unit of ``dimension``).

    Examples
    --------
    >>> list(grid_type("--amplitude", "length", "amplitude")("1mm,2mm"))
    [0.001, 0.002]
    """
    name = flag.lstrip("-")

    def convert(text: str) -> Grid:
        try:
            return parse_grid(text, name, dimension, bound, max_count=max_count)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    convert.__name__ = flag
    return convert


# ---------------------------------------------------------------------------
# registry names without the numerical imports

_ROOT = Path(__file__).resolve().parents[1]


@cache
def preset_names(kind: str = "device") -> tuple[str, ...]:
    """Names of the device (``device``), ``rotor`` or ``section`` presets, from the data files.

    Examples
    --------
    >>> preset_names()[:2], preset_names("rotor")
    (('paper_initial', 'paper_calibrated'), ('hammond1974',))
    """
    path = {"device": _ROOT / "device" / "data" / "presets.toml",
            "rotor": _ROOT / "structure" / "data" / "rotors.toml",
            "section": _ROOT / "structure" / "data" / "sections.toml"}[kind]
    table = tomllib.loads(path.read_text())
    if kind == "device":
        table = table.get("presets", table)
    return tuple(table)


#: Names of :func:`liquidamp.device.models.model_names` (held equal by a test).
MODEL_NAMES = ("full", "no_inertia", "constant_bulk", "volumetric", "single_state", "inertial",
               "inertial_2state", "maxwell", "dashpot", "spring", "dashpot_inerter", "inerter")
#: Units of every effect's parameters, ``EFFECTS[name].units`` (held equal by a test).
EFFECT_UNITS = {
    "coulomb_friction": {"force_N": "N", "reverse_ratio": "-"},
    "smooth_friction": {"force_N": "N", "stiffness_N_per_m": "N/m",
                        "stribeck_velocity_m_per_s": "m/s", "static_ratio": "-",
                        "reverse_ratio": "-", "transition_exponent": "-"},
    "force_offset": {"offset_N": "N"},
    "moving_mass": {"mass_kg": "kg"},
    "series_compliance": {"stiffness_N_per_m": "N/m"},
    "freeplay": {"gap_m": "m"},
    "floating_freeplay": {"gap_m": "m", "contact_stiffness_N_per_m": "N/m"},
    "leakage": {"coefficient_m3_per_s_Pa": "m^3/(s Pa)"},
    "cavitation": {"vapour_pressure_Pa": "Pa"},
    "relief_valve": {"cracking_pressure_Pa": "Pa", "conductance_m3_per_s_Pa": "m^3/(s Pa)"},
    "asymmetric_loss": {"rebound_ratio": "-"},
    "elastomer": {"parallel_stiffness_N_per_m": "N/m", "branch_stiffness_N_per_m": "N/m",
                  "branch_damping_N_s_per_m": "N s/m"},
    "end_stops": {"stiffness_N_per_m": "N/m", "clearance_m": "m", "damping_N_s_per_m": "N s/m",
                  "centre_m": "m"},
    "rotating_frame": {"rotor_speed_rad_per_s": "rad/s", "mounting_radius_m": "m",
                       "axis_angle_rad": "rad"},
    "gas_charge": {"rod_area_m2": "m^2", "charge_pressure_Pa": "Pa", "gas_volume_m3": "m^3",
                   "polytropic_index": "-", "stroke_offset_m": "m", "ambient_pressure_Pa": "Pa"},
    "digressive_valve": {"compression_cracking_Pa": "Pa",
                         "compression_conductance_m3_per_s_Pa": "m^3/(s Pa)",
                         "rebound_cracking_Pa": "Pa",
                         "rebound_conductance_m3_per_s_Pa": "m^3/(s Pa)"},
    "field_yield": {"yield_pressure_Pa": "Pa", "yield_pressure_per_input": "Pa/V",
                    "lag_rate_per_s": "1/s", "smoothing_flow_kg_per_s": "kg/s"},
    "slip_weakening": {"ratio": "-", "distance_m": "m"},
    "self_heating": {"heat_capacity_J_per_K": "J/K", "conductance_W_per_K": "W/K",
                     "beta_per_K": "1/K", "c2_exponent": "-", "ambient_temperature_K": "K",
                     "reference_temperature_K": "K", "initial_temperature_K": "K",
                     "law_a": "-", "law_b": "-"},
    "bypass_groove": {"depth": "-", "centre_m": "m", "half_width_m": "m",
                      "stroke_offset_m": "m"},
}
#: Composite candidates of :data:`liquidamp.analysis.measured.candidates.COMPOSITES`
#: (held equal by a test).
COMPOSITE_NAMES = ("backlash", "friction_asymmetry", "friction_transition")
#: Composition choices of the effects (``Effect.composition_keys()``; held equal by a test).
EFFECT_CHOICES = {"coulomb_friction": {"location": ("rod", "piston")},
                  "smooth_friction": {"location": ("rod", "piston")},
                  "field_yield": {"input": ("voltage", "current")},
                  "freeplay": {"drives": ("piston", "friction")},
                  "self_heating": {"law": ("exponential", "water", "walther"),
                                   "start": ("given", "record"),
                                   "temperature": ("state", "measured")}}


def _unknown(what: str, value: str, valid) -> str:
    return f"unknown {what} {value!r}; valid: {', '.join(valid)}"


def name_type(flag: str, names, what: str, *, files: bool = False):
    """argparse ``type=``: a name from ``names()`` (or, with ``files``, a .toml/.json file).

    Examples
    --------
    >>> name_type("--preset", preset_names, "preset")("damper")
    'damper'
    >>> name_type("--preset", preset_names, "preset")("dampr")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: unknown preset 'dampr'; valid: paper_initial, \
paper_calibrated, reference, spring, damper, inerter, device_a, device_b
    """

    def convert(text: str) -> str:
        valid = names() if callable(names) else tuple(names)
        if text in valid:
            return text
        if files and Path(text).suffix.lower() in (".toml", ".json"):
            return text
        extra = " or a .toml/.json file" if files else ""
        raise argparse.ArgumentTypeError(_unknown(what, text, valid) + extra)

    convert.__name__ = flag
    return convert


def effect_type(text: str) -> str:
    """argparse ``type=`` of ``--effect NAME[:KEY=VALUE,...]``: checked, values made SI.

    Each value may carry a unit of its parameter's dimension (``force_N=30N``,
    ``gap_m=0.1mm``); the result is the same text with SI numbers, which
    :func:`liquidamp.commands._args.parse_effect` builds the effect from.

    Examples
    --------
    >>> effect_type("freeplay:gap_m=0.1mm")
    'freeplay:gap_m=0.0001'
    >>> effect_type("coulomb_friction:force_N=30,location=piston")
    'coulomb_friction:force_N=30.0,location=piston'
    >>> effect_type("gas_charge:rod_area_m2=45mm^2,charge_pressure_Pa=100psi,gas_volume_m3=0.1l")
    'gas_charge:rod_area_m2=4.5e-05,charge_pressure_Pa=689475.7293168,gas_volume_m3=0.0001'
    >>> effect_type("freeplay:gap_m=wide")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: --effect freeplay: gap_m must be a number [m], got 'wide'
    """
    name, _, rest = str(text).partition(":")
    name = name.strip()
    if name not in EFFECT_UNITS:
        raise argparse.ArgumentTypeError(_unknown("effect", name, EFFECT_UNITS))
    units, choices = EFFECT_UNITS[name], EFFECT_CHOICES.get(name, {})
    out, seen = [], set()
    for entry in (e for e in rest.split(",") if e.strip()):
        key, eq, value = entry.partition("=")
        key, value = key.strip(), value.strip()
        if not eq or not key:
            raise argparse.ArgumentTypeError(
                f"--effect {name}: entries must be KEY=VALUE, got {entry!r}")
        if key not in units and key not in choices:
            raise argparse.ArgumentTypeError(
                _unknown(f"{name} parameter", key, list(units) + list(choices)))
        if key in seen:
            raise argparse.ArgumentTypeError(f"--effect {name}: {key} given twice")
        seen.add(key)
        if key in choices:
            if value not in choices[key]:
                raise argparse.ArgumentTypeError(
                    f"--effect {name}: {_unknown(key, value, choices[key])}")
            out.append(f"{key}={value}")
            continue
        unit = units[key]
        dim = _UNIT_DIMENSION.get(unit, "ratio")
        try:
            number = parse_quantity(value, dim, f"--effect {name}: {key}")
        except ValueError as exc:
            if "unknown unit" in str(exc):
                raise argparse.ArgumentTypeError(str(exc)) from None
            number = math.nan
        if not math.isfinite(number):
            raise argparse.ArgumentTypeError(
                f"--effect {name}: {key} must be a number [{unit}], got {value!r}")
        out.append(f"{key}={number!r}")
    return name + (":" + ",".join(out) if out else "")
