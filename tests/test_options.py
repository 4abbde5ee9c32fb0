"""One options story (issue #11 item 4): named presets, one resolver, the same default in
the library and the command line, ``--rtol``/``--engine`` on every command that integrates.
"""

import importlib
import json

import numpy as np
import pytest

import liquidamp.options as options_module
from liquidamp.cli import build_parser, main
from liquidamp.errors import ParameterError
from liquidamp.options import (
    DEFAULT_ENGINE,
    DEFAULT_OPTIONS,
    ENGINES,
    PRESETS,
    SolverOptions,
    preset_names,
    resolve_options,
)

# ------------------------------------------------------------------ presets as data

EXPECTED = {  # preset -> (method, rtol, atol_scale, engine, compiled_method, max_steps)
    "default": ("Radau", 1e-8, 1e-9, DEFAULT_ENGINE, "auto", 5_000_000),
    "coupled": ("Radau", 1e-8, 1e-9, "scipy", "auto", 5_000_000),
    "fit": ("Radau", 1e-6, 1e-8, "compiled", "rodas4", 100_000),
    "rotor": ("DOP853", 1e-7, 1e-9, "compiled", "auto", 5_000_000),
    "section": ("Radau", 1e-6, 1e-9, "scipy", "auto", 5_000_000),
    "casestudy": ("Radau", 1e-8, 1e-9, "compiled", "auto", 5_000_000),
    "decay": ("DOP853", 1e-10, 1e-12, "compiled", "auto", 5_000_000),
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_each_preset_has_its_documented_values(name):
    o = SolverOptions.preset(name)
    assert (o.method, o.rtol, o.atol_scale, o.engine, o.compiled_method,
            o.max_steps) == EXPECTED[name]
    assert o is PRESETS[name] and resolve_options(None, name) is o
    # everything else is the reference's
    others = {f: getattr(DEFAULT_OPTIONS, f) for f in ("samples_per_period", "steady_tol",
                                                        "min_cycles", "max_cycles",
                                                        "pressure_floor", "vapour_pressure",
                                                        "max_step_fraction")}
    assert {f: getattr(o, f) for f in others} == others


def test_presets_are_read_only_and_listed():
    assert preset_names() == tuple(EXPECTED)
    with pytest.raises(TypeError):
        PRESETS["mine"] = SolverOptions()  # type: ignore[index]
    assert DEFAULT_OPTIONS is PRESETS["default"] == SolverOptions()
    from liquidamp.analysis.measured.calibration import FIT_OPTIONS

    assert FIT_OPTIONS is PRESETS["fit"]


def test_default_engine_is_one_constant():
    assert DEFAULT_ENGINE in ENGINES
    assert SolverOptions().engine == DEFAULT_ENGINE == PRESETS["default"].engine


def test_unknown_preset_and_unknown_keys_raise_listing_the_valid_ones():
    valid = "valid: default, coupled, fit, rotor, section, casestudy, decay"
    with pytest.raises(ParameterError, match=f"unknown solver preset 'fiting'; {valid}"):
        SolverOptions.preset("fiting")
    with pytest.raises(ParameterError, match=f"unknown solver preset 'stiff'; {valid}"):
        resolve_options(None, "stiff")
    with pytest.raises(ParameterError, match="unknown solver preset 'stiff'"):
        resolve_options(SolverOptions(), "stiff")  # a typo in a caller is caught either way
    keys = "valid: method, rtol, atol_scale, samples_per_period"
    for call in (lambda: SolverOptions.preset("fit", rtl=1e-6),
                 lambda: SolverOptions().replace(rtl=1e-6),
                 lambda: SolverOptions.from_mapping({"rtl": 1e-6})):
        with pytest.raises(ParameterError, match=f"unknown solver option 'rtl'; {keys}"):
            call()
    with pytest.raises(ParameterError, match="options must be a SolverOptions or None, got dict"):
        resolve_options({"rtol": 1e-6}, "fit")


def test_preset_changes_are_validated_and_do_not_touch_the_preset():
    o = SolverOptions.preset("fit", rtol=1e-7)
    assert o.rtol == 1e-7 and o.compiled_method == "rodas4"
    assert PRESETS["fit"].rtol == 1e-6
    with pytest.raises(ParameterError, match=r"rtol must lie in \[1e-14, 0.01\] \[-\], got 2"):
        SolverOptions.preset("rotor", rtol=2.0)


def test_python_is_an_alias_of_scipy():
    assert ENGINES == ("scipy", "compiled")
    a = SolverOptions(engine="python")
    assert a.engine == "scipy" and a == SolverOptions(engine="scipy")
    assert SolverOptions.preset("fit", engine="python").engine == "scipy"
    assert SolverOptions.from_mapping({"engine": "python"}).engine == "scipy"
    with pytest.raises(ParameterError,
                       match="unknown engine 'numba'; valid: scipy, compiled "
                             r"\(alias: python = scipy\)"):
        SolverOptions(engine="numba")


# ------------------------------------------------------- None -> the documented preset


class _Stop(Exception):
    pass


def _spy(monkeypatch, target, name="resolve_options"):
    """Replace ``target.resolve_options`` by a spy that records the call and stops."""
    seen = []
    real = options_module.resolve_options

    def spy(options, purpose="default"):
        seen.append((options, purpose, real(options, purpose)))
        raise _Stop

    monkeypatch.setattr(target, name, spy)
    return seen


def _record():
    from liquidamp.analysis.measured.records import Record

    t = np.arange(0.0, 1.0, 0.005)
    return Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), 100 * np.sin(2 * np.pi * 3 * t))


def _rotor_device():
    from liquidamp.analysis.stability.sizing import size_lag_damper
    from liquidamp.coupled.assembly import Device
    from liquidamp.device import preset
    from liquidamp.structure.hostio import load_rotor

    rotor = load_rotor("hammond1974")
    return rotor, Device("full", size_lag_damper(preset("device_a"), rotor).params, "device_a")


def _blade_system():
    from liquidamp.coupled.assembly import blade_system, viscous
    from liquidamp.structure.hostio import load_blade

    return blade_system(load_blade("hammond1974"), 26.0, viscous(1e4))


class _Result:
    """What lag_decay_check reads before it resolves its options."""

    class orbit:  # noqa: N801 - attribute access only
        system = None
        period = 0.25

    mode = None


def _fn(path):
    module, attr = path.rsplit(".", 1)
    return getattr(importlib.import_module(f"liquidamp.{module}"), attr)


def _calls():
    """name -> (module whose resolve_options is spied on, preset, call with options=None)."""
    from liquidamp.device import preset
    from liquidamp.structure.testmachine import HarmonicStroke

    p, s = preset("reference"), HarmonicStroke(0.001, 3.0)
    W = 230 * np.pi / 30
    return {
        "testrig.simulate": ("coupled.testrig", "default",
                             lambda: _fn("coupled.testrig.simulate")("full", p, s, 0.1)),
        "testrig.steady_state": ("coupled.testrig", "default",
                                 lambda: _fn("coupled.testrig.steady_state")("full", p, s)),
        "periodic_orbit": ("coupled.testrig", "default",
                           lambda: _fn("analysis.response.periodic.periodic_orbit")("full", p, s)),
        "simulate_coupled": ("coupled.assembly", "coupled",
                             lambda: _fn("coupled.assembly.simulate_coupled")(None, 1.0)),
        "simulate_record": ("analysis.measured.record_model", "default", lambda: _fn(
            "analysis.measured.record_model.simulate_record")("full", p, _record())),
        "equivalent_linearization": ("analysis.response.equivalent", "default", lambda: _fn(
            "analysis.response.equivalent.equivalent_linearization")(p, 3.0, 1e-3)),
        "run_case_study": ("analysis.reports.casestudy", "casestudy",
                           lambda: _fn("analysis.reports.casestudy.run_case_study")()),
        "predict": ("analysis.measured.fit_objective", "fit",
                    lambda: _fn("analysis.measured.calibration.predict")("full", p, (), [])),
        "calibrate": ("analysis.measured.calibration", "fit",
                      lambda: _fn("analysis.measured.calibration.calibrate")([_record()])),
        "diagnose": ("analysis.measured.diagnosis_options", "fit",
                     lambda: _fn("analysis.measured.diagnosis.diagnose")([_record()], [_record()])),
        "simulate_rotor": ("options", "rotor", lambda: _fn("coupled.fast_rotor.simulate_rotor")(
            *_rotor_device()[:1], W, _rotor_device()[1], 1.0)),
        "simulate_lco": ("analysis.stability.lco", "rotor", lambda: _fn(
            "analysis.stability.lco.simulate_lco")(
            *_rotor_device()[:1], W, _rotor_device()[1], mode=object())),
        "forced_orbit": ("analysis.stability.forced_orbit", "decay", lambda: _fn(
            "analysis.stability.forced_orbit.forced_orbit")(_blade_system(), period=1.0)),
        "lag_decay_check": ("analysis.stability.forced_lag", "decay", lambda: _fn(
            "analysis.stability.forced_lag.lag_decay_check")(_Result())),
        "second_order_flow": ("options", "decay", lambda: _fn(
            "coupled.fast_rotor.second_order_flow")(_blade_system(), [0.0, 0.0], 1.0)),
        "simulate_section_lco": ("analysis.stability.lco", "section", lambda: _fn(
            "analysis.stability.lco.simulate_section_lco")(None, 1.0, None, mode=object())),
    }


@pytest.mark.parametrize("name", sorted(_calls()))
def test_none_resolves_to_the_documented_preset(monkeypatch, name):
    """Each public function that integrates resolves options=None through its preset."""
    target, purpose, call = _calls()[name]
    seen = _spy(monkeypatch, importlib.import_module(f"liquidamp.{target}"))
    with pytest.raises(_Stop):
        call()
    assert [(o, p) for o, p, _ in seen] == [(None, purpose)]
    assert seen[0][2] is PRESETS[purpose]


def test_steady_state_default_runs_the_default_preset_end_to_end():
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.device import preset
    from liquidamp.structure.testmachine import HarmonicStroke

    r = steady_state("maxwell", preset("reference"), HarmonicStroke(0.001, 3.0))
    assert r.solver_stats["engine"] == PRESETS["default"].engine
    assert r.solver_stats["method"] == (PRESETS["default"].method if DEFAULT_ENGINE == "scipy"
                                        else PRESETS["default"].compiled_method)
    fit = steady_state("maxwell", preset("reference"), HarmonicStroke(0.001, 3.0),
                       options=SolverOptions.preset("fit"))
    assert fit.solver_stats["engine"] == "compiled" and fit.solver_stats["method"] == "rodas4"


# ------------------------------------------------------------------ the command line

INTEGRATING = {  # command -> (minimal argv after the command name, preset)
    "simulate": (["--frequency", "3", "--amplitude", "1mm"], "default"),
    "stiffness": (["--frequency", "1", "--amplitude", "1mm", "--out", "OUT"], "default"),
    "lco": (["--damper", "device_a", "--rpm", "230", "--json", "OUT/x.json"], "rotor"),
    "calibrate": (["missing.csv", "--json", "OUT/x.json"], "fit"),
    "diagnose": (["missing.csv", "--validate", "missing.csv", "--json", "OUT/x.json"], "fit"),
    "demo": (["--out", "OUT", "--quiet"], "casestudy"),
}


def _subparsers():
    return build_parser()._subparsers._group_actions[0].choices


def test_every_integrating_command_has_the_solver_flags_and_others_do_not():
    subs = _subparsers()
    for name, (_, purpose) in INTEGRATING.items():
        flags = subs[name]._option_string_actions
        for flag in ("--rtol", "--engine", "--compiled-method"):
            assert flag in flags, (name, flag)
        assert f"default {PRESETS[purpose].rtol:g}" in flags["--rtol"].help, name
    # bench times fixed configurations; params and sweep do not integrate with SolverOptions
    for name in ("bench", "params", "sweep"):
        assert "--rtol" not in subs[name]._option_string_actions, name


@pytest.mark.parametrize("command", sorted(INTEGRATING))
def test_bad_rtol_exits_2_naming_rtol_value_and_range(command, tmp_path, capsys):
    argv, _ = INTEGRATING[command]
    argv = [a.replace("OUT", str(tmp_path / "out")) for a in argv]
    assert main([command] + argv + ["--rtol", "2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"liquidamp {command}: error: rtol must lie in [1e-14, 0.01] [-], got 2"]
    assert not (tmp_path / "out").exists()  # raised before any work


def test_unknown_engine_is_an_argparse_error(capsys):
    # argument errors return 2 from main (exit 2 on the command line)
    assert main(["simulate", "--frequency", "3", "--amplitude", "1mm", "--engine", "numba"]) == 2
    assert "invalid choice: 'numba'" in capsys.readouterr().err


def test_compiled_method_needs_the_compiled_engine(capsys):
    argv = ["simulate", "--frequency", "3", "--amplitude", "1mm", "--compiled-method", "rodas4"]
    if DEFAULT_ENGINE == "compiled":
        argv += ["--engine", "scipy"]
    assert main(argv) == 2
    assert "add --engine compiled" in capsys.readouterr().err


def _simulate(tmp_path, name, *extra):
    out = tmp_path / f"{name}.json"
    assert main(["simulate", "--preset", "reference", "--frequency", "3", "--amplitude", "1mm",
                 *extra, "--json", str(out)]) == 0
    return json.loads(out.read_text())


def test_cli_default_is_the_library_default(tmp_path):
    from liquidamp.analysis.response.harmonics import dynamic_stiffness
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.device import preset
    from liquidamp.structure.testmachine import HarmonicStroke

    d = _simulate(tmp_path, "default", "--model", "maxwell")
    lib = steady_state("maxwell", preset("reference"), HarmonicStroke(0.001, 3.0))
    assert d["solver"] == dict(lib.solver_stats)
    assert d["solver"]["engine"] == DEFAULT_ENGINE
    assert d["dynamic_stiffness"]["magnitude [N/m]"] == dynamic_stiffness(lib).magnitude


def test_rtol_reaches_the_scipy_integrator(tmp_path):
    tight = _simulate(tmp_path, "tight", "--model", "maxwell", "--engine", "scipy")
    loose = _simulate(tmp_path, "loose", "--model", "maxwell", "--engine", "scipy",
                      "--rtol", "1e-3")
    assert tight["solver"]["engine"] == loose["solver"]["engine"] == "scipy"
    assert loose["solver"]["nfev"] < tight["solver"]["nfev"]
    Kt, Kl = (d["dynamic_stiffness"]["magnitude [N/m]"] for d in (tight, loose))
    assert Kl == pytest.approx(Kt, rel=1e-2) and Kl != Kt


def test_rtol_reaches_the_compiled_integrator(tmp_path):
    tight = _simulate(tmp_path, "tight", "--engine", "compiled")
    loose = _simulate(tmp_path, "loose", "--engine", "compiled", "--rtol", "1e-3")
    assert tight["solver"]["engine"] == loose["solver"]["engine"] == "compiled"
    assert loose["solver"]["steps"] < tight["solver"]["steps"]


def test_fit_commands_without_flags_run_the_library_defaults():
    """``liquidamp diagnose CAL`` with no knob builds ``DiagnoseOptions()`` exactly, and
    ``liquidamp calibrate CAL`` fits with ``calibrate``'s own budget: the command a new
    user types is the library's default, and ``liquidamp bench`` (which calls the library)
    times it.  Session 18: the command fitted with max_nfev 80, the library and the bench
    with 60, and an independent digressive-valve record read differently through each."""
    import inspect

    from liquidamp.analysis.measured.calibration import calibrate
    from liquidamp.analysis.measured.diagnosis_options import DiagnoseOptions
    from liquidamp.commands.diagnose import diagnose_config

    parser = build_parser()
    assert diagnose_config(parser.parse_args(["diagnose", "cal.csv"])) == DiagnoseOptions()
    cal = parser.parse_args(["calibrate", "cal.csv"])
    assert cal.max_nfev == inspect.signature(calibrate).parameters["max_nfev"].default
    # and a flag still reaches the options
    flagged = diagnose_config(parser.parse_args(["diagnose", "cal.csv", "--max-nfev", "7"]))
    assert flagged.budget.max_nfev == 7 and flagged != DiagnoseOptions()
