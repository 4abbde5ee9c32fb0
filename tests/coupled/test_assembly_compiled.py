"""simulate_coupled with SolverOptions(engine="compiled"): dispatch to the compiled rotor
kernel (liquidamp.coupled.fast_rotor.simulate_rotor), the same CoupledResponse as the Python route,
and ParameterError (no fall-back) for what the kernel does not integrate."""

import dataclasses
import math

import numpy as np
import pytest

from liquidamp.analysis.stability.sizing import size_lag_damper
from liquidamp.coupled import fast_rotor
from liquidamp.coupled.assembly import (
    CoupledResponse,
    Device,
    couple,
    rotor_system,
    section_system,
    simulate_coupled,
    viscous,
)
from liquidamp.device import preset
from liquidamp.device.effects import Cavitation, with_effects
from liquidamp.errors import ParameterError, PressureError
from liquidamp.options import SolverOptions
from liquidamp.structure.hostio import load_rotor, load_section
from liquidamp.structure.rotor import GroundResonanceRotor

ROTOR = load_rotor("hammond1974")
W260 = 260.0 * 2.0 * math.pi / 60.0  # [rad/s]
OPTS = SolverOptions(method="DOP853", rtol=1e-7, engine="scipy")
COMPILED = OPTS.replace(engine="compiled")


def _rel(a, b):
    """Largest difference relative to each row's largest magnitude in ``b``."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    scale = np.maximum(np.max(np.abs(b), axis=-1, keepdims=True), 1e-300)
    return float(np.max(np.abs(a - b) / scale))


@pytest.fixture(scope="module")
def hammond_four_full():
    """Hammond rotor, a sized `full` reference device on each of the 4 blades (as the bench)."""
    params = size_lag_damper(preset("reference"), ROTOR).params
    return rotor_system(ROTOR, W260, Device("full", params))


def test_compiled_engine_equals_python_route_hammond_four_full_devices(hammond_four_full,
                                                                        monkeypatch):
    system = hammond_four_full
    x0 = {"zeta_1": 1e-3, "hub_x": 1e-4}
    calls = []
    real = fast_rotor.simulate_rotor

    def spy(*args, **kwargs):
        calls.append(kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(fast_rotor, "simulate_rotor", spy)
    ref = simulate_coupled(system, 1.0, x0, options=OPTS)
    assert not calls  # the default engine is the Python one
    run = simulate_coupled(system, 1.0, x0, options=COMPILED)
    assert len(calls) == 1 and calls[0]["options"] is COMPILED
    assert calls[0]["max_step"] == pytest.approx(2.0 * math.pi / W260 / 20.0, rel=1e-15)

    assert type(run) is CoupledResponse and run.status == ref.status == "completed"
    assert run.message == ref.message and run.warnings == ref.warnings
    assert run.name == ref.name and run.port_names == ref.port_names
    assert run.port_names == ("blade_1", "blade_2", "blade_3", "blade_4")
    assert run.host_state_names == ref.host_state_names
    assert run.device_state_names == ref.device_state_names
    assert run.device_labels == ref.device_labels
    # 64 samples per rotor period over 1 s, the same times
    assert run.time.size == ref.time.size == math.ceil(64.0 * W260 / (2.0 * math.pi)) + 1
    assert np.array_equal(run.time, ref.time)
    # same DOP853 steps: round-off agreement (bench: ~1e-13)
    assert _rel(run.host_states, ref.host_states) < 1e-11
    for z, zr in zip(run.device_states, ref.device_states, strict=True):
        assert z.shape == zr.shape == (5, run.time.size)
        assert _rel(z, zr) < 1e-11
    assert _rel(run.forces, ref.forces) < 1e-10
    assert _rel(run.strokes, ref.strokes) < 1e-11
    assert _rel(run.stroke_rates, ref.stroke_rates) < 1e-11
    assert _rel(run.stroke_accelerations, ref.stroke_accelerations) < 1e-10
    assert _rel(run.energy.device_work, ref.energy.device_work) < 1e-9
    assert run.energy.relative_residual == pytest.approx(ref.energy.relative_residual,
                                                         rel=1e-6)
    # the run is not trivial: blade 1 starts at 1 mrad (0.25 mm stroke) and the devices work
    assert run.strokes[0, 0] == pytest.approx(0.25e-3, rel=1e-12)
    assert np.max(np.abs(run.forces)) > 10.0
    assert np.all(run.energy.device_work[:, -1] > 0.0)


def test_compiled_engine_failed_blade_mixed_models_and_kept_builtin_damper(hammond_four_full):
    """Blade 1 failed, devices of two models on blades 2-3, blade 4 keeps its own damper."""
    full = hammond_four_full.devices[0]
    devices = {2: Device("no_inertia", full.params), 3: full}
    system = rotor_system(ROTOR, W260, devices, inoperative=iter([1]))
    devices[3] = Device("spring", full.params)  # changing the mapping afterwards changes nothing
    assert system.port_names == ("blade_2", "blade_3")
    x0 = {"zeta_1": 2e-3, "hub_x": 2e-4}
    ref = simulate_coupled(system, 0.4, x0, options=OPTS)
    run = simulate_coupled(system, 0.4, x0, options=COMPILED)
    assert np.array_equal(run.time, ref.time)
    assert _rel(run.host_states, ref.host_states) < 1e-11
    assert _rel(run.forces, ref.forces) < 1e-10
    assert [z.shape[0] for z in run.device_states] == [4, 5]
    for z, zr in zip(run.device_states, ref.device_states, strict=True):
        assert _rel(z, zr) < 1e-11
    # host dissipation (hub dampers and the built-in damper of blade 4) from the same states
    assert run.energy.host_dissipation[-1] == pytest.approx(ref.energy.host_dissipation[-1],
                                                            rel=1e-9)
    assert run.energy.host_dissipation[-1] > 0.0


def test_compiled_engine_ignores_method_and_keeps_to_tolerance(hammond_four_full):
    """``method`` is the Python engine's: the compiled route is DOP853 whatever it says."""
    x0 = {"zeta_1": 1e-3, "hub_x": 1e-4}
    t_eval = np.linspace(0.0, 0.3, 31)
    a = simulate_coupled(hammond_four_full, 0.3, x0, t_eval=t_eval, options=COMPILED,
                         energy=False)
    b = simulate_coupled(hammond_four_full, 0.3, x0, t_eval=t_eval,
                         options=COMPILED.replace(method="Radau"), energy=False)
    assert np.array_equal(a.host_states, b.host_states)
    assert np.array_equal(a.time, t_eval)


def test_compiled_stop_matches_python_samples_status_and_message():
    """Pressure floor in blade 1's device: same kept samples, status and located time."""
    system = rotor_system(ROTOR, 25.0, Device("full", preset("reference")))
    opts = SolverOptions(method="DOP853", rtol=1e-6)
    x0 = {"zeta_dot_1": 2.0}
    for t_eval in (None, np.array([0.0, 0.5])):
        ref = simulate_coupled(system, 0.5, x0, t_eval=t_eval, options=opts, strict=False,
                               energy=False)
        run = simulate_coupled(system, 0.5, x0, t_eval=t_eval, options=opts.replace(
            engine="compiled"), strict=False, energy=False)
        assert run.status == ref.status == "pressure_floor"
        assert run.message == ref.message
        assert ref.message.startswith("stopped at t = 0.0602164 s: a chamber pressure of the "
                                      "device at port 'blade_1'")
        assert np.array_equal(run.time, ref.time)
        assert _rel(run.host_states, ref.host_states) < 1e-10
    assert run.time.tolist() == [0.0]
    for opt in (opts, opts.replace(engine="compiled")):
        with pytest.raises(PressureError, match=r"stopped at t = 0\.0602164 s: a chamber "):
            simulate_coupled(system, 0.5, x0, options=opt)


def test_compiled_engine_refuses_what_it_does_not_integrate(hammond_four_full):
    dev = hammond_four_full.devices[0]
    x0 = {"zeta_1": 1e-3}

    def run(system, **kw):
        return simulate_coupled(system, 0.05, x0 if system.host.period else None,
                                options=COMPILED, **kw)

    sec = section_system(load_section("hodges-pierce"), 5.0, {"pitch": viscous(10.0)})
    with pytest.raises(ParameterError, match=r"host .* has constant coefficients \(a typical "
                                             r"section.*use engine='scipy'$"):
        run(sec)
    hand = couple(ROTOR.with_inoperative_damper(1).periodic_statespace(W260), {"blade_1": dev})
    with pytest.raises(ParameterError, match=r"was not built by rotor_system\(\).*"
                                             r"use engine='scipy'$"):
        run(hand)
    with pytest.raises(ParameterError, match="was not built by rotor_system"):
        run(dataclasses.replace(hammond_four_full))
    with pytest.raises(ParameterError, match=r"model 'inerter' \(device 'inerter' at port "
                                             r"'blade_1'\): its force depends on the stroke "
                                             r"acceleration; use engine='scipy'$"):
        run(rotor_system(ROTOR, W260, Device("inerter", preset("inerter"))))
    # the viscous damper, a composed model and the spring are compiled base models (one copy
    # of the physics): they run on the compiled rotor kernel and agree with the scipy route
    cav = Device(with_effects("full", Cavitation(2339.0)), preset("reference"))
    for system in (rotor_system(ROTOR, W260, {1: viscous(1e4), 2: dev}),
                   rotor_system(ROTOR, W260, cav),
                   rotor_system(ROTOR, W260, Device("spring", preset("reference")))):
        a = run(system)
        b = simulate_coupled(system, 0.05, x0, t_eval=a.time, options=OPTS)
        assert a.status == b.status == "completed"
        assert _rel(a.host_states, b.host_states) < 1e-9

    @dataclasses.dataclass(frozen=True)
    class OtherRotor(GroundResonanceRotor):
        pass

    other = OtherRotor(**{f.name: getattr(ROTOR, f.name) for f in dataclasses.fields(ROTOR)})
    with pytest.raises(ParameterError, match=r"GroundResonanceRotor equations only, got a "
                                             r"OtherRotor; use engine='scipy'$"):
        run(rotor_system(other, W260, dev))


def test_arguments_are_checked_for_both_engines(hammond_four_full):
    x0 = {"zeta_1": 1e-3}
    for opt in (OPTS, COMPILED):
        with pytest.raises(ParameterError, match=r"t_eval must be a strictly increasing 1-D "
                                                 r"array of times within \[0, 0.1\] s"):
            simulate_coupled(hammond_four_full, 0.1, x0, t_eval=[0.0, 0.2], options=opt)
        with pytest.raises(ParameterError, match="t_eval must be a strictly increasing"):
            simulate_coupled(hammond_four_full, 0.1, x0, t_eval=[0.05, 0.01], options=opt)
        with pytest.raises(ParameterError, match=r"max_step must be > 0 \[s\], got 0"):
            simulate_coupled(hammond_four_full, 0.1, x0, max_step=0.0, options=opt)
        X0 = hammond_four_full.initial_state(x0)
        X0[hammond_four_full.host.nstates + 2] = 0.5  # p2 of blade 1's device [Pa]
        with pytest.raises(ParameterError, match=r"x0 is at a stop condition already: a "
                                                 r"chamber pressure of the device at port "
                                                 r"'blade_1' reached the floor 1 Pa"):
            simulate_coupled(hammond_four_full, 0.1, X0, options=opt)
