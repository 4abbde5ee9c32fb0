"""Published host parameter sets and host files (TOML or JSON).

The presets live in ``data/blades.toml``, ``data/rotors.toml`` and
``data/sections.toml`` beside this module; this module only reads them.  A
user's own host comes from a ``.toml`` or ``.json`` file holding one host
with the same keys as a preset table (the dataclass fields; a rotor has a
``blade`` sub-table), optionally ``preset = "NAME"`` to start from a preset
and change only some keys.  ``description``, ``reference`` and ``notes`` are
kept out of the parameters; any other unknown key raises.

References
----------
.. [1] C. E. Hammond, J. American Helicopter Society 19(4), 14-23, 1974.
.. [2] D. H. Hodges, G. A. Pierce, *Introduction to Structural Dynamics and
   Aeroelasticity*, 2nd ed., Cambridge University Press, 2011, Ch. 5.
"""

from __future__ import annotations

import dataclasses
import json
import tomllib
from functools import lru_cache
from importlib import resources
from pathlib import Path

from liquidamp.errors import DataFileError, ParameterError, check_choice
from liquidamp.structure.blade import ArticulatedBlade
from liquidamp.structure.rotor import GroundResonanceRotor
from liquidamp.structure.section import TypicalSection

__all__ = [
    "preset_names",
    "preset_description",
    "load_blade",
    "load_rotor",
    "load_section",
]

_FILES = {"blade": "blades.toml", "rotor": "rotors.toml", "section": "sections.toml"}
_META = ("description", "reference", "notes")


@lru_cache(maxsize=None)
def _table(kind: str) -> dict:
    text = resources.files("liquidamp.structure").joinpath(f"data/{_FILES[kind]}").read_text()
    return tomllib.loads(text)


def preset_names(kind: str) -> tuple[str, ...]:
    """Names of the published ``kind`` presets (``blade``, ``rotor`` or ``section``).

    Examples
    --------
    >>> preset_names("rotor"), preset_names("section")
    (('hammond1974',), ('hodges-pierce',))
    """
    check_choice("host kind", kind, tuple(_FILES))
    return tuple(_table(kind))


def preset_description(kind: str, name: str) -> str:
    """One-line description and reference of a preset."""
    check_choice(f"{kind} preset", name, preset_names(kind))
    entry = _table(kind)[name]
    return f"{entry.get('description', name)} ({entry.get('reference', 'no reference')})"


def _read_file(path: Path) -> dict:
    try:
        if path.suffix.lower() == ".toml":
            return tomllib.loads(path.read_text())
        if path.suffix.lower() == ".json":
            data = json.loads(path.read_text())
            if not isinstance(data, dict):
                raise DataFileError(f"{path}: the top level must be an object")
            return data
    except (tomllib.TOMLDecodeError, json.JSONDecodeError) as exc:
        raise DataFileError(f"{path}: cannot parse: {exc}") from None
    except OSError as exc:
        raise DataFileError(f"{path}: cannot read: {exc}") from None
    raise DataFileError(f"{path}: host files must end in .toml or .json")


def _raw(kind: str, spec: str | Path) -> tuple[dict, str]:
    """Raw mapping and a name for a preset name or a file path."""
    text = str(spec)
    path = Path(text)
    if path.suffix.lower() in (".toml", ".json") or path.exists():
        if not path.is_file():
            raise DataFileError(f"{kind} file {text!r} does not exist")
        raw = dict(_read_file(path))
        base = raw.pop("preset", None)
        if base is not None:
            check_choice(f"{kind} preset", base, preset_names(kind))
            merged = _deep_copy(_table(kind)[base])
            for key, value in raw.items():
                if isinstance(value, dict) and isinstance(merged.get(key), dict):
                    merged[key].update(value)
                else:
                    merged[key] = value
            raw = merged
        return raw, raw.get("name", path.stem)
    check_choice(f"{kind} preset", text, preset_names(kind))
    return _deep_copy(_table(kind)[text]), text


def _deep_copy(d: dict) -> dict:
    return {k: (_deep_copy(v) if isinstance(v, dict) else v) for k, v in d.items()}


def _build(cls, raw: dict, source: str, **extra):
    raw = {k: v for k, v in raw.items() if k not in _META}
    fields = {f.name for f in dataclasses.fields(cls)}
    unknown = sorted(set(raw) - fields)
    if unknown:
        raise ParameterError(
            f"{source}: unknown key(s) {', '.join(unknown)}; valid: {', '.join(sorted(fields))}"
        )
    raw.update(extra)
    try:
        return cls(**raw)
    except TypeError as exc:
        raise ParameterError(f"{source}: {exc}") from None


def load_blade(spec: str | Path = "hammond1974") -> ArticulatedBlade:
    """A blade preset by name, or a blade from a TOML/JSON file.

    Examples
    --------
    >>> load_blade("hammond1974").inertia
    1084.7
    """
    raw, _ = _raw("blade", spec)
    return _build(ArticulatedBlade, raw, f"blade {spec}")


def load_rotor(spec: str | Path = "hammond1974") -> GroundResonanceRotor:
    """A rotor preset by name, or a rotor from a TOML/JSON file.

    Examples
    --------
    >>> rotor = load_rotor("hammond1974")
    >>> rotor.hub_mass_x, rotor.blade.static_moment
    (8026.6, 289.1)
    """
    raw, name = _raw("rotor", spec)
    blade_raw = raw.pop("blade", None)
    if not isinstance(blade_raw, dict):
        raise ParameterError(f"rotor {spec}: a [blade] table is missing")
    blade = _build(ArticulatedBlade, blade_raw, f"rotor {spec} blade")
    if "lag_damping" in raw and raw["lag_damping"] is not None:
        raw["lag_damping"] = tuple(raw["lag_damping"])
    raw.setdefault("name", name)
    return _build(GroundResonanceRotor, raw, f"rotor {spec}", blade=blade)


def load_section(spec: str | Path = "hodges-pierce") -> TypicalSection:
    """A typical-section preset by name, or a section from a TOML/JSON file.

    Examples
    --------
    >>> s = load_section("hodges-pierce")
    >>> s.a, s.e, s.mu, s.r2, s.sigma
    (-0.2, -0.1, 20.0, 0.24, 0.4)
    """
    raw, name = _raw("section", spec)
    raw.setdefault("name", name)
    return _build(TypicalSection, raw, f"section {spec}")
