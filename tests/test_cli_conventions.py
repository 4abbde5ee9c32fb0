"""One set of command-line conventions, held over every command by introspecting the parsers.

README, section "Command-line conventions": ``--json FILE`` (``-`` for standard
output) optional everywhere, ``--plot`` optional, ``--quiet`` everywhere,
``--overwrite`` (hidden alias ``--force``), ranges ``START:STOP:COUNT`` linear
with ``lin:``/``log:`` prefixes, units on every physical quantity, negative values
without ``=``, the same option with the same meaning everywhere.  No numerics.
"""

import argparse

import pytest

from liquidamp.cli import build_parser
from liquidamp.commands import _units

#: Every value-taking option of every command, by kind.  A new option must be added
#: here: a physical quantity with a sample value carrying a unit, anything else by kind.
PHYSICAL = {  # option -> (a value with a unit, its value in the option's base unit)
    "--frequency": ("250rpm", 250 / 60),
    "--amplitude": ("3mm", 3e-3),
    "--rev-frequency": ("4.2Hz", 4.2),
    "--lag-frequency": ("75.6rpm", 1.26),
    "--rev-amplitude": ("1mm", 1e-3),
    "--lag-amplitude": ("500um", 5e-4),
    "--offset": ("-1mm", -1e-3),
    "--rpm": ("4Hz", 240.0),
    "--arm": ("250mm", 0.25),
    "--t-end": ("1min", 60.0),
    "--force-filter": ("0.03kHz", 30.0),
    "--zeta": ("5%", 0.05),
    "--confidence": ("95%", 0.95),
    "--degradation": ("50%", 0.5),
    "--lag-damping": ("4.0675kN m s/rad", 4067.5),
    "--damping": ("2kN s/m", 2000.0),
}
DIMENSIONLESS = {"--speeds", "--k", "--harmonics", "--rtol", "--degrade", "--change"}
NAMES = {"--preset", "--model", "--effect", "--engine", "--compiled-method", "--method",
         "--rotor", "--damper", "--section", "--aero", "--port", "--candidate", "--sizing",
         "--average", "--vary", "--cases", "--decimate", "--outliers", "--dask",
         "--force-sign"}
FILES = {"--json", "--plot", "--out", "--report", "--save-device", "--device", "--validate"}
COUNTS = {"--window", "--order", "--max-nfev", "--max-steps", "--top", "--repeats",
          "--inoperative", "--samples", "--blade"}


def parsers() -> dict:
    """Every command's parser, sweep kinds included (``"sweep flutter"``)."""
    out = {}
    for name, p in build_parser()._subparsers._group_actions[0].choices.items():
        if p._subparsers is not None:
            for kind, q in p._subparsers._group_actions[0].choices.items():
                out[f"{name} {kind}"] = q
        else:
            out[name] = p
    return out


def options(p) -> dict:
    return {s: a for a in p._actions for s in a.option_strings if s.startswith("--")}


def test_every_value_option_is_known_and_every_physical_one_takes_units():
    for name, p in parsers().items():
        for flag, action in options(p).items():
            if action.nargs == 0 or flag in ("--help", "--version"):
                continue
            known = PHYSICAL.keys() | DIMENSIONLESS | NAMES | FILES | COUNTS
            assert flag in known, f"{name} {flag}: add it to a kind in this test"
            if flag in PHYSICAL:
                text, value = PHYSICAL[flag]
                got = action.type(text)
                got = got[0] if isinstance(got, tuple) else got
                assert got == pytest.approx(value, rel=1e-12), (name, flag, got)


def test_quiet_everywhere_json_and_plot_optional_with_stdout():
    for name, p in parsers().items():
        opts = options(p)
        assert "--quiet" in opts, name
        assert opts["--quiet"].help == parsers()["simulate"]._option_string_actions[
            "--quiet"].help, name
        if "--json" in opts:
            a = opts["--json"]
            assert not a.required, name
            assert "'-'" in a.help and "standard output" in a.help, name
        if "--plot" in opts:
            assert not opts["--plot"].required, name


def test_overwrite_replaces_force_which_stays_a_hidden_alias():
    for name, p in parsers().items():
        opts = options(p)
        if "--overwrite" not in opts and "--force" not in opts:
            continue
        assert opts["--force"].dest == opts["--overwrite"].dest == "overwrite", name
        assert opts["--force"].help == argparse.SUPPRESS, name
        assert "--force " not in p.format_help() and "--overwrite" in p.format_help(), name
        assert opts["--force"].const is True and opts["--overwrite"].const is True


def test_same_option_same_meaning():
    """An option shared by several commands takes the same values and says the same."""
    seen: dict = {}
    for name, p in parsers().items():
        for flag, action in options(p).items():
            if flag in ("--model", "--preset", "--effect", "--rpm", "--arm", "--amplitude",
                        "--frequency", "--rtol", "--engine", "--overwrite", "--quiet"):
                key = (getattr(action.type, "__name__", None), action.choices)
                seen.setdefault(flag, {})[name] = key
    for flag, by_command in seen.items():
        kinds = set(by_command.values())
        if flag in ("--frequency", "--amplitude"):  # one value (simulate) or a list (stiffness)
            assert all(k[0] == flag for k in kinds), (flag, by_command)
            continue
        assert len(kinds) == 1, (flag, by_command)
    # every registry option checks its names at parse time
    for name, p in parsers().items():
        for flag in ("--model", "--preset", "--effect", "--rotor", "--damper", "--section"):
            if flag in options(p):
                assert options(p)[flag].type is not None, (name, flag)


def test_ranges_are_linear_unless_prefixed():
    grid = _units.parse_grid
    assert list(grid("1:3:3", "f", "frequency")) == [1.0, 2.0, 3.0]
    assert list(grid("lin:1:3:3", "f", "frequency")) == [1.0, 2.0, 3.0]
    assert grid("log:1:100:3", "f", "frequency") == pytest.approx([1.0, 10.0, 100.0])
    assert list(grid("1Hz:3Hz:2", "f", "frequency")) == [1.0, 3.0]
    with pytest.raises(ValueError, match="log-spaced and needs START, STOP > 0"):
        grid("log:-1:3:3", "x", "length")
    # stiffness keeps its log default grid through the prefix; every help says the spacing
    stiff = options(parsers()["stiffness"])["--frequency"]
    assert stiff.default.startswith("log:")
    values = stiff.type(stiff.default)
    assert values[0] == pytest.approx(0.5) and values[-1] == pytest.approx(20.0)
    assert values[1] / values[0] == pytest.approx(values[-1] / values[-2])
    for name, p in parsers().items():
        for flag, action in options(p).items():
            if action.help and "START:STOP:COUNT" in action.help:
                assert "linearly spaced" in action.help, (name, flag)


def test_negative_values_without_equals():
    p = parsers()["dual-frequency"]
    ns = p.parse_args(["--rev-frequency", "4.2", "--lag-frequency", "1.26", "--rev-amplitude",
                       "0,1mm", "--lag-amplitude", "1mm", "--offset", "-1.5mm"])
    assert ns.offset == pytest.approx(-1.5e-3)
    ns = p.parse_args(["--rev-frequency", "4.2", "--lag-frequency", "1.26", "--rev-amplitude",
                       "0", "--lag-amplitude", "1mm", "--offset", "-.5mm"])
    assert ns.offset == pytest.approx(-5e-4)


def test_registries_read_without_numerics_equal_the_library():
    from liquidamp.device.effects import EFFECTS
    from liquidamp.device.models import model_names
    from liquidamp.device.presets import preset_names
    from liquidamp.structure.hostio import preset_names as host_names

    assert _units.MODEL_NAMES == model_names()
    assert _units.EFFECT_UNITS == {k: dict(v.units) for k, v in EFFECTS.items()}
    assert _units.EFFECT_CHOICES == {k: dict(v.composition_keys()) for k, v in EFFECTS.items()
                                     if v.composition_keys()}
    from liquidamp.analysis.measured.candidates import COMPOSITES

    assert _units.COMPOSITE_NAMES == tuple(COMPOSITES)
    assert _units.preset_names() == preset_names()
    assert _units.preset_names("rotor") == host_names("rotor")
    assert _units.preset_names("section") == host_names("section")
