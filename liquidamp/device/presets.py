"""The paper's parameter sets (Tables 1-3) and device files.

The published numbers live in ``data/presets.toml`` beside this module; this
module only reads them.  A preset's multipliers of ``c1``, ``c2``, ``S_t``
become the factors ``c1_factor``, ``c2_factor``, ``S_t_factor`` on the
geometric estimates (see :mod:`liquidamp.device.params`), so changing ``mu``,
``l_t`` or ``A_t`` of a preset changes its loss coefficients and inertance.

A user's own device comes from a TOML or JSON *device file*
(:func:`load_device_file`, format in its docstring): the keys of
:class:`~liquidamp.device.params.DeviceParams` in SI (``A_p`` directly, or
``bore_m`` and ``rod_m``), optionally ``preset = "NAME"`` to start from a
preset, ``multipliers = {...}`` applied last and ``[effects.NAME]`` tables of
add-on effects.  :func:`device_file_dict` / :func:`write_device_file` write
the same format, so a written file reads back to equal parameters.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Tables 1-3.
"""

from __future__ import annotations

import json
import math
import re
import tomllib
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from pathlib import Path

from liquidamp.device.params import DERIVABLE, INPUT_NAMES, SCALABLE, DeviceParams
from liquidamp.errors import DataFileError, ParameterError, check_choice

__all__ = ["preset", "preset_names", "preset_description", "load_device", "load_device_file",
           "DeviceFile", "device_file_dict", "device_file_text", "write_device_file"]


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


# ---------------------------------------------------------------------------
# device files

#: Units of the device-file keys (for messages).
_UNITS = {
    "mu": "Pa s", "rho_l": "kg/m^3", "B_l": "Pa", "V01": "m^3", "V02": "m^3", "A_p": "m^2",
    "A_t": "m^2", "l_t": "m", "p0": "Pa", "n": "-", "inv_gamma1": "-", "inv_gamma2": "-",
    "c1": "kg m^-4 s^-1", "c2": "kg m^-7", "S_t": "1/m", "c1_factor": "-", "c2_factor": "-",
    "S_t_factor": "-", "friction_N": "N", "bore_m": "m", "rod_m": "m",
}
_TEXT_KEYS = ("name", "bulk_law", "preset")
#: Top-level keys of a device file besides the :data:`INPUT_NAMES`.
FILE_KEYS = ("preset", "multipliers", "effects", "derived", "fit", "bore_m", "rod_m")
_REQUIRED = ("mu", "rho_l", "B_l", "V01", "V02", "A_p", "A_t", "l_t", "p0", "n",
             "inv_gamma1", "inv_gamma2")


@dataclass(frozen=True)
class DeviceFile:
    """What a device file declares: parameters, add-on effects and where they came from.

    Attributes
    ----------
    params : DeviceParams
        Device parameters (SI).
    effects : tuple of Effect
        Add-on effects of the file's ``[effects.NAME]`` tables, in file order
        (compose them with :func:`liquidamp.device.effects.with_effects`).
    source : str
        Path of the file.
    fit : dict or None
        The ``[fit]`` table of a fitted device (written by ``liquidamp
        calibrate/diagnose --save-device``): ``varied`` (names of the varied
        parameters: multipliers [-] or ``effect.key`` [SI]), ``values``,
        ``stderr`` and ``covariance`` (a list of rows, same order), plus
        free-form text such as ``source`` and numbers such as ``nrmse``.
        Read and checked, never applied to the parameters.
    """

    params: DeviceParams
    effects: tuple = ()
    source: str = ""
    fit: dict | None = None


def _type_error(where: str, key: str, value, allowed: str) -> DataFileError:
    return DataFileError(
        f"{where}: {key} = {value!r} is a {type(value).__name__}; allowed: {allowed}"
    )


def _number(where: str, key: str, value, what: str = "") -> float:
    """``value`` if it is an int or float (not bool); else a DataFileError naming all."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        unit = _UNITS.get(key, "SI")
        raise _type_error(where, key, value, what or f"a number [{unit}]")
    return value


def _no_duplicates(pairs):
    out = {}
    for k, v in pairs:
        if k in out:
            raise DataFileError(f"key {k!r} given twice")
        out[k] = v
    return out


def _read_table(path: Path) -> dict:
    if not path.exists():
        raise DataFileError(f"device file {str(path)!r} does not exist")
    suffix = path.suffix.lower()
    if suffix not in (".toml", ".json"):
        raise DataFileError(f"device file {path.name!r}: suffix must be .toml or .json")
    try:
        if suffix == ".json":
            raw = json.loads(path.read_text(), object_pairs_hook=_no_duplicates)
        else:
            raw = tomllib.loads(path.read_text())
    except (tomllib.TOMLDecodeError, json.JSONDecodeError, DataFileError) as exc:
        raise DataFileError(f"device file {path.name!r} cannot be parsed: {exc}") from None
    if not isinstance(raw, dict):
        raise DataFileError(f"device file {path.name!r} must hold a table of parameters")
    return dict(raw)


def _check_inputs(where: str, raw: dict) -> None:
    valid = sorted(set(INPUT_NAMES) | set(FILE_KEYS))
    unknown = sorted(set(raw) - set(valid))
    if unknown:
        raise DataFileError(f"{where}: unknown key(s) {', '.join(unknown)}; "
                            f"valid: {', '.join(valid)}")
    for key, value in raw.items():
        if key in _TEXT_KEYS:
            if not isinstance(value, str):
                raise _type_error(where, key, value, "a string")
        elif key in DERIVABLE and value is None:
            continue  # JSON null: derive it (clears a preset's explicit value)
        elif key not in ("multipliers", "effects", "derived", "fit"):
            _number(where, key, value)


def _fit(where: str, raw) -> dict | None:
    """Check a ``[fit]`` table: names, values, standard errors, a square covariance."""
    if raw is None:
        return None
    if not isinstance(raw, dict):
        raise _type_error(where, "fit", raw, "a table with varied, values, stderr, covariance")
    varied = raw.get("varied", [])
    if not isinstance(varied, list) or not all(isinstance(v, str) for v in varied):
        raise _type_error(where, "fit.varied", varied, "a list of parameter names")
    n = len(varied)
    for key in ("values", "stderr"):
        vals = raw.get(key, [])
        if not isinstance(vals, list) or len(vals) != n:
            raise DataFileError(f"{where}: fit.{key} must be a list of {n} numbers (one per "
                                f"fit.varied name), got {vals!r}")
        for v in vals:
            _number(where, f"fit.{key}", v, "a number")
    cov = raw.get("covariance", [])
    if not isinstance(cov, list) or len(cov) != n or any(
            not isinstance(r, list) or len(r) != n for r in cov):
        raise DataFileError(f"{where}: fit.covariance must be a {n} x {n} list of rows "
                            "(one per fit.varied name)")
    for i, row in enumerate(cov):
        for j, v in enumerate(row):
            _number(where, "fit.covariance", v, "a number")
            if math.isfinite(v) and math.isfinite(cov[j][i]) and not math.isclose(
                    v, cov[j][i], rel_tol=1e-9, abs_tol=1e-300):
                raise DataFileError(f"{where}: fit.covariance is not symmetric at "
                                    f"({varied[i]}, {varied[j]})")
    return dict(raw)


def _multipliers(where: str, raw) -> dict:
    allowed = f"a table of name = number, names from: {', '.join(SCALABLE)}"
    if not isinstance(raw, dict):
        raise _type_error(where, "multipliers", raw, allowed)
    for key, value in raw.items():
        if key not in SCALABLE:
            raise DataFileError(f"{where}: multipliers: cannot scale {key!r}; "
                                f"scalable: {', '.join(SCALABLE)}")
        _number(where, f"multipliers.{key}", value, "a number >= 0 [-]")
    return dict(raw)


def _effects(where: str, raw) -> tuple:
    from liquidamp.device.effects import EFFECTS, effect_names, make_effect

    allowed = f"a table of [effects.NAME] tables, NAME from: {', '.join(effect_names())}"
    if not isinstance(raw, dict):
        raise _type_error(where, "effects", raw, allowed)
    out = []
    for name, pars in raw.items():
        if not isinstance(pars, dict):
            raise _type_error(where, f"effects.{name}", pars,
                              "a table of the effect's parameters (key = number, SI)")
        comp = EFFECTS[name].composition_keys() if name in EFFECTS else {}
        for key, value in pars.items():
            if key in comp:  # a composition choice (e.g. location = "piston")
                if not isinstance(value, str):
                    raise _type_error(where, f"effects.{name}.{key}", value,
                                      f"one of {', '.join(map(repr, comp[key]))}")
                continue
            _number(where, f"effects.{name}.{key}", value, "a number (SI)")
        try:
            out.append(make_effect(name, **pars))
        except ParameterError as exc:
            raise ParameterError(f"{where}: effects.{name}: {exc}") from None
    return tuple(out)


def _check_derived(where: str, table, params: DeviceParams) -> None:
    """A ``derived`` table (output of :meth:`DeviceParams.derived`) must match the inputs."""
    if not isinstance(table, dict):
        raise _type_error(where, "derived", table, "a table of 'name [unit]' = number")
    ours = params.derived()
    differ = []
    for key, value in table.items():
        if key not in ours:
            raise DataFileError(f"{where}: derived: unknown quantity {key!r}; "
                                f"valid: {', '.join(ours)}")
        if key == "unused":
            if value != ours[key]:
                raise DataFileError(f"{where}: derived.unused = {value!r} does not match the "
                                    f"file's inputs, which leave unused: {ours[key]!r}")
            continue
        _number(where, f"derived.{key}", value, "a number (output only)")
        if not math.isclose(value, ours[key], rel_tol=1e-9, abs_tol=0.0):
            differ.append(f"{key} = {value!r} (inputs give {ours[key]!r})")
    if differ:
        raise DataFileError(
            f"{where}: the derived table is output only and disagrees with the file's inputs: "
            f"{'; '.join(differ)}; change the inputs (or set c1, c2, S_t explicitly) and "
            f"delete or regenerate the derived table"
        )


def load_device_file(path: str | Path) -> DeviceFile:
    """Read a device and its add-on effects from a TOML or JSON file.

    File format (SI units; TOML shown, JSON holds the same tables)::

        preset = "reference"          # optional: start from a preset
        name = "my damper"            # optional (default: the file's stem)
        mu = 1.0e-3                   # any DeviceParams input: mu, rho_l, B_l, V01,
        l_t = 1.5                     #   V02, A_p (or bore_m + rod_m), A_t, l_t, p0, n,
                                      #   inv_gamma1, inv_gamma2, c1_factor, c2_factor,
                                      #   S_t_factor, friction_N, bulk_law
        S_t = 3.0e5                   # explicit c1, c2, S_t override the geometry
        multipliers = { c1 = 2.0 }    # applied last (DeviceParams.scaled)

        [effects.smooth_friction]     # add-on effects: make_effect(NAME, **table)
        force_N = 30.0

        [derived]                     # optional, output only: checked, never used
        "b_L [kg]" = 89.4

    Without ``preset`` the twelve inputs mu ... inv_gamma2 are required.
    ``c1``, ``c2``, ``S_t`` left out are derived from the geometry (module
    :mod:`liquidamp.device.params`), so setting ``mu``, ``l_t`` or ``A_t``
    changes them.  A file written by :func:`write_device_file` (and the
    output of :func:`device_file_dict`) reads back to equal parameters.

    Parameters
    ----------
    path : str or Path
        ``.toml`` or ``.json`` file.

    Returns
    -------
    DeviceFile
        ``.params``, ``.effects``, ``.source``.

    Raises
    ------
    DataFileError
        Unreadable file, unknown or duplicate keys, missing fields, a value
        of the wrong type (a string or boolean where a number belongs, a
        number where a table belongs: the key, value, type and what is
        allowed are named), a ``derived`` table that disagrees with the inputs.
    ParameterError
        A value outside its range, an unknown effect or effect parameter,
        a multiplier on an input the file leaves unused.

    Examples
    --------
    >>> import os, tempfile
    >>> f = os.path.join(tempfile.mkdtemp(), "dev.toml")
    >>> _ = open(f, "w").write('preset = "reference"\\nmultipliers = { l_t = 2.0 }\\n'
    ...                        '[effects.smooth_friction]\\nforce_N = 30.0\\n')
    >>> dev = load_device_file(f)
    >>> round(dev.params.b_L / preset("reference").b_L, 12), [e.name for e in dev.effects]
    (2.0, ['smooth_friction'])
    >>> dev.effects[0].force_N
    30.0
    """
    path = Path(path)
    where = f"device file {path.name!r}"
    raw = _read_table(path)
    _check_inputs(where, raw)
    multipliers = _multipliers(where, raw.pop("multipliers", {}))
    effects = _effects(where, raw.pop("effects", {}))
    fit = _fit(where, raw.pop("fit", None))
    derived_table = raw.pop("derived", None)
    base_name = raw.pop("preset", None)
    raw = _geometry(raw, path.name)
    raw.setdefault("name", path.stem)
    try:
        if base_name is not None:
            params = preset(base_name).replace(**raw)
        else:
            missing = [k for k in _REQUIRED if k not in raw]
            if missing:
                raise DataFileError(f"{where}: missing key(s) {', '.join(missing)}")
            params = DeviceParams(**raw)
        params = params.scaled(**multipliers) if multipliers else params
    except ParameterError as exc:
        raise ParameterError(f"{where}: {exc}") from None
    if derived_table is not None:
        _check_derived(where, derived_table, params)
    return DeviceFile(params=params, effects=effects, source=str(path), fit=fit)


def load_device(path: str | Path) -> DeviceParams:
    """Read the device parameters of a TOML or JSON device file.

    Same file format and errors as :func:`load_device_file`, which also
    returns the file's ``[effects.NAME]`` add-on effects; this function
    returns the parameters only (the effects are read and validated, not
    returned: use :func:`load_device_file` to get them).

    Parameters
    ----------
    path : str or Path
        ``.toml`` or ``.json`` file.

    Returns
    -------
    DeviceParams

    Examples
    --------
    >>> import tempfile, os
    >>> d = tempfile.mkdtemp()
    >>> f = os.path.join(d, "dev.toml")
    >>> _ = open(f, "w").write('preset = "reference"\\nl_t = 1.5\\nS_t = 375000.0\\n')
    >>> p = load_device(f)
    >>> p.l_t, p.explicit, round(p.c1 / preset("reference").c1, 12)   # c1 follows l_t
    (1.5, ('S_t',), 2.0)
    """
    return load_device_file(path).params


def device_file_dict(params: DeviceParams, effects=(), *, derived: bool = False,
                     fit: dict | None = None) -> dict:
    """A device file's table for ``params`` and ``effects``: what :func:`load_device_file` reads.

    Every input of :class:`DeviceParams` is written in SI (no preset), the
    factors always, ``c1``, ``c2``, ``S_t`` only where they are explicit (so
    the others stay derived when the file is edited).

    Parameters
    ----------
    params : DeviceParams
    effects : sequence of Effect
        Written as ``effects = {NAME: {key: value}}``.
    derived : bool
        Add ``derived = params.derived()`` (output for readers; checked
        against the inputs when the file is read back).
    fit : dict, optional
        The ``[fit]`` table (:class:`DeviceFile`): the fit's varied
        parameters with their values, standard errors and covariance.

    Returns
    -------
    dict
        JSON-ready; ``json.dumps`` it, or write it with :func:`write_device_file`.

    Examples
    --------
    >>> d = device_file_dict(preset("reference").replace(S_t=1.0e5))
    >>> d["c1_factor"], d["S_t"], "c1" in d
    (3.56, 100000.0, False)
    """
    from liquidamp.device.effects import Effect

    if not isinstance(params, DeviceParams):
        raise ParameterError(f"device_file_dict takes DeviceParams, got "
                             f"{type(params).__name__}")
    out: dict = {}
    if params.name:
        out["name"] = params.name
    for key in INPUT_NAMES:
        if key == "name" or (key in DERIVABLE and key not in params.explicit):
            continue
        out[key] = getattr(params, key)
    tables = {}
    for e in effects:
        if not isinstance(e, Effect):
            raise ParameterError(f"device_file_dict takes Effect objects, got "
                                 f"{type(e).__name__}")
        if e.name in tables:
            raise ParameterError(f"effect {e.name!r} given twice")
        tables[e.name] = e.as_dict()
    if tables:
        out["effects"] = tables
    if derived:
        out["derived"] = params.derived()
    if fit is not None:
        out["fit"] = dict(fit)
    return out


def _toml_str(s: str) -> str:
    return json.dumps(s, ensure_ascii=False).replace("\x7f", "\\u007f")


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _toml_str(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise ParameterError(f"cannot write {type(v).__name__} {v!r} to TOML")


def _toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else _toml_str(k)


def _toml_lines(table: dict, prefix: str, lines: list) -> None:
    for k, v in table.items():
        if not isinstance(v, dict):
            lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
    for k, v in table.items():
        if isinstance(v, dict):
            name = prefix + _toml_key(k)
            lines += ["", f"[{name}]"]
            _toml_lines(v, name + ".", lines)


def device_file_text(params: DeviceParams, effects=(), *, fmt: str = "toml",
                     derived: bool = False, fit: dict | None = None) -> str:
    """:func:`device_file_dict` as TOML or JSON text (no dependency beyond the stdlib).

    Examples
    --------
    >>> print("\\n".join(device_file_text(preset("paper_initial")).splitlines()[:4]))
    name = "paper_initial"
    mu = 0.00089
    rho_l = 998.2
    B_l = 1551300000.0
    """
    check_choice("device file format", fmt, ("toml", "json"))
    data = device_file_dict(params, effects, derived=derived, fit=fit)
    if fmt == "json":
        return json.dumps(data, indent=2) + "\n"  # inf (e.g. a rigid compliance) as Infinity
    lines: list = []
    _toml_lines(data, "", lines)
    return "\n".join(lines) + "\n"


def write_device_file(path: str | Path, params: DeviceParams, effects=(), *,
                      derived: bool = False, fit: dict | None = None) -> Path:
    """Write ``params`` and ``effects`` as a device file (``.toml`` or ``.json`` by suffix).

    :func:`load_device_file` reads it back to equal parameters and effects
    (and the ``fit`` table, see :class:`DeviceFile`).  The file is written
    atomically (:func:`liquidamp.atomic.write_text`): a failure leaves the
    previous file.

    Examples
    --------
    >>> import os, tempfile
    >>> f = os.path.join(tempfile.mkdtemp(), "ref.json")
    >>> p = preset("reference")
    >>> load_device_file(write_device_file(f, p, derived=True)).params == p
    True
    """
    path = Path(path)
    suffix = path.suffix.lower().lstrip(".")
    if suffix not in ("toml", "json"):
        raise ParameterError(f"device file {path.name!r}: suffix must be .toml or .json")
    from liquidamp.atomic import write_text

    return write_text(path, device_file_text(params, effects, fmt=suffix, derived=derived,
                                             fit=fit))
