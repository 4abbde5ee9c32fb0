"""The paper's parameter sets (Tables 1-3) and device files.

The published numbers live in ``data/presets.toml`` beside this module; this
module only reads them.  A user's own device comes from a TOML or JSON file
with the same keys as :class:`~liquidamp.device.params.DeviceParams`
(``A_p`` directly, or ``bore_m`` and ``rod_m``), optionally with
``preset = "NAME"`` to start from a preset and ``multipliers = {...}``.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Tables 1-3.
"""

from __future__ import annotations

import json
import math
import tomllib
from functools import lru_cache
from importlib import resources
from pathlib import Path

from liquidamp.device.params import DeviceParams
from liquidamp.errors import DataFileError, ParameterError, check_choice

__all__ = ["preset", "preset_names", "preset_description", "load_device"]


@lru_cache(maxsize=1)
def _table() -> dict:
    text = resources.files("liquidamp.device").joinpath("data/presets.toml").read_text()
    return tomllib.loads(text)


def _geometry(raw: dict, source: str) -> dict:
    """Turn bore/rod diameters into A_p; pass every other key through."""
    raw = dict(raw)
    if "bore_m" in raw or "rod_m" in raw:
        if "A_p" in raw:
            raise DataFileError(f"{source}: give either A_p or bore_m and rod_m, not both")
        try:
            bore, rod = float(raw.pop("bore_m")), float(raw.pop("rod_m"))
        except KeyError as exc:
            raise DataFileError(
                f"{source}: {exc.args[0]} is missing (bore_m needs rod_m)"
            ) from None
        if not 0.0 <= rod < bore:
            raise ParameterError(
                f"{source}: rod_m must lie in [0, bore_m) [m], got rod_m={rod}, bore_m={bore}"
            )
        raw["A_p"] = math.pi / 4.0 * (bore**2 - rod**2)
    return raw


def preset_names() -> tuple[str, ...]:
    """Names of the published parameter sets.

    Examples
    --------
    >>> preset_names()
    ('paper_initial', 'paper_calibrated', 'reference', 'spring', 'damper', 'inerter', \
'device_a', 'device_b')
    """
    return tuple(_table()["presets"])


def preset_description(name: str) -> str:
    """One-line description of preset ``name`` (table and figure of the paper)."""
    check_choice("preset", name, preset_names())
    return _table()["presets"][name]["description"]


def _apply(base: DeviceParams, base_set: str, multipliers: dict, name: str) -> DeviceParams:
    table = _table()
    alpha1 = table["multiplier_sets"][base_set] if base_set else {}
    keys = set(alpha1) | set(multipliers)
    factors = {k: alpha1.get(k, 1.0) * multipliers.get(k, 1.0) for k in keys}
    return base.scaled(**factors).replace(name=name)


@lru_cache(maxsize=None)
def preset(name: str) -> DeviceParams:
    """Return the published parameter set ``name``.

    Parameters
    ----------
    name : str
        One of :func:`preset_names`: ``paper_initial`` (Tables 1-2 initial),
        ``paper_calibrated`` (Table 2 multipliers), and Table 3's
        ``reference``, ``spring``, ``damper``, ``inerter``, ``device_a``,
        ``device_b`` (final value = alpha2 * alpha1 * initial value).

    Returns
    -------
    DeviceParams
        Frozen parameters in SI.

    Raises
    ------
    ParameterError
        For an unknown name (the message lists the valid ones).

    Examples
    --------
    >>> p = preset("paper_calibrated")
    >>> round(p.inv_gamma1, 3), round(p.inv_gamma2, 3), f"{p.c1:.4e}"
    (0.075, 0.122, '3.7327e+09')
    >>> round(preset("inerter").S_t / preset("reference").S_t, 6)
    7.0
    """
    check_choice("preset", name, preset_names())
    table = _table()
    base = DeviceParams(**_geometry(table["table1"], "presets.toml [table1]"), name="table1")
    entry = table["presets"][name]
    return _apply(base, entry["base_multipliers"], entry["multipliers"], name)


def load_device(path: str | Path) -> DeviceParams:
    """Read a device from a TOML or JSON file.

    The file holds :class:`DeviceParams` fields in SI (``A_p`` or
    ``bore_m`` + ``rod_m``), or ``preset = "NAME"`` plus any fields to
    override and an optional ``multipliers`` table applied last.

    Parameters
    ----------
    path : str or Path
        ``.toml`` or ``.json`` file.

    Returns
    -------
    DeviceParams

    Raises
    ------
    DataFileError
        Unreadable file, unknown keys or missing fields (named).

    Examples
    --------
    >>> import tempfile, os
    >>> d = tempfile.mkdtemp()
    >>> f = os.path.join(d, "dev.toml")
    >>> _ = open(f, "w").write('preset = "reference"\\nl_t = 1.5\\nS_t = 375000.0\\n')
    >>> load_device(f).l_t
    1.5
    """
    path = Path(path)
    if not path.exists():
        raise DataFileError(f"device file {str(path)!r} does not exist")
    try:
        if path.suffix.lower() == ".json":
            raw = json.loads(path.read_text())
        elif path.suffix.lower() == ".toml":
            raw = tomllib.loads(path.read_text())
        else:
            raise DataFileError(f"device file {path.name!r}: suffix must be .toml or .json")
    except (tomllib.TOMLDecodeError, json.JSONDecodeError) as exc:
        raise DataFileError(f"device file {path.name!r} cannot be parsed: {exc}") from None
    if not isinstance(raw, dict):
        raise DataFileError(f"device file {path.name!r} must hold a table of parameters")
    raw = dict(raw)
    multipliers = raw.pop("multipliers", {})
    base_name = raw.pop("preset", None)
    raw = _geometry(raw, path.name)
    fields = set(DeviceParams.__dataclass_fields__)
    unknown = sorted(set(raw) - fields)
    if unknown:
        raise DataFileError(
            f"device file {path.name!r}: unknown key(s) {', '.join(unknown)}; "
            f"valid: {', '.join(sorted(fields | {'preset', 'multipliers', 'bore_m', 'rod_m'}))}"
        )
    raw.setdefault("name", path.stem)
    if base_name is not None:
        params = preset(str(base_name)).replace(**raw)
    else:
        missing = [
            f for f, spec in DeviceParams.__dataclass_fields__.items()
            if spec.default is spec.default_factory is __import__("dataclasses").MISSING
            and f not in raw
        ]
        if missing:
            raise DataFileError(f"device file {path.name!r}: missing key(s) {', '.join(missing)}")
        params = DeviceParams(**raw)
    return params.scaled(**multipliers) if multipliers else params
