"""The engine contract (liquidamp.coupled.engines, items 1-5) over the whole model registry."""

import numpy as np
import pytest

from liquidamp.analysis.response.harmonics import dynamic_stiffness
from liquidamp.coupled.engines import ENGINES, TestRig, get_engine
from liquidamp.coupled.testrig import simulate, steady_state
from liquidamp.device import preset
from liquidamp.device.effects import (
    Cavitation,
    CoulombFriction,
    RotatingFrame,
    SmoothFriction,
    with_effects,
)
from liquidamp.device.models import REGISTRY, get_model
from liquidamp.device.rotating import ROTATING_BASES
from liquidamp.errors import ParameterError, PressureError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

P = preset("reference")
S = HarmonicStroke(0.001, 3.0)


def test_item1_names_are_the_option_values():
    assert set(ENGINES) == {"scipy", "compiled"}
    for name, engine in ENGINES.items():
        assert engine.name == name and get_engine(name) is engine
        assert SolverOptions(engine=name).engine == name


@pytest.mark.parametrize("engine", list(ENGINES))
@pytest.mark.parametrize("name", list(REGISTRY))
def test_items2_to_4_every_model_runs_on_every_engine_to_the_same_steady_state(engine, name):
    """supports() is None for every model (with friction effects); the steady states of
    both engines agree on K* (each against the other route)."""
    model = get_model(name)
    if model.n_states:
        model = with_effects(model, SmoothFriction(10.0, 1e6), CoulombFriction(2.0))
    rig = TestRig(model, P, S)
    assert ENGINES[engine].supports(rig) is None
    if not model.n_states:
        return  # algebraic: no integration (the force is evaluated at once)
    opts = SolverOptions(engine=engine, rtol=1e-9)
    other = "scipy" if engine == "compiled" else "compiled"
    a = steady_state(model, P, S, options=opts)
    b = steady_state(model, P, S, options=opts.replace(engine=other))
    assert a.status == "steady" and a.solver_stats["engine"] == engine
    assert a.time.shape == (opts.samples_per_period,)
    ka, kb = dynamic_stiffness(a).value, dynamic_stiffness(b).value
    assert abs(ka - kb) < 1e-5 * abs(kb)


def test_item2_reasons_and_item5_no_silent_fallback():
    class Odd:
        max_abs = 0.001
        period = 1 / 3

        def __call__(self, t):
            return S(t)

    rig = TestRig(get_model("full"), P, Odd())
    assert ENGINES["scipy"].supports(rig) is None
    reason = ENGINES["compiled"].supports(rig)
    assert "HarmonicStroke or RecordedStroke" in reason
    with pytest.raises(ParameterError, match="HarmonicStroke or RecordedStroke"):
        ENGINES["compiled"].check(rig)


@pytest.mark.parametrize("engine", list(ENGINES))
def test_item5_pressure_floor_raises_on_every_engine(engine):
    with pytest.raises(PressureError, match="fell to the floor 5000 Pa"):
        steady_state("full", preset("inerter"), HarmonicStroke(0.003, 3.0),
                     options=SolverOptions(engine=engine, pressure_floor=5000.0))


def test_item3_march_shapes_and_stats():
    rig = TestRig(get_model("maxwell"), P, S)
    t = np.linspace(0.0, 0.2, 21)
    for name, engine in ENGINES.items():
        stats = {}
        X = engine.march(rig, np.zeros(1), 0.0, 0.2, t, SolverOptions(engine=name), 0.01,
                         stats)
        assert X.shape == (1, 21) and np.all(np.isfinite(X))
        assert stats["engine"] == name
        # closed form of the Maxwell unit from rest under y = Y sin(w t)
        w, Y, kD, TD = S.omega, S.amplitude, P.k_D, P.T_D
        iwt = 1j * w * TD
        F_ss = np.imag(kD * iwt / (1 + iwt) * Y * np.exp(1j * w * t))
        F0 = -np.imag(kD * iwt / (1 + iwt) * Y)
        exact = F_ss + F0 * np.exp(-t / TD)
        assert np.max(np.abs(X[0] - exact)) < 1e-6 * np.max(np.abs(exact))


@pytest.mark.parametrize("name", [b for b in ROTATING_BASES if b != "volumetric"])
def test_rotating_frame_runs_alike_on_every_engine(name):
    """The rotating frame (with cavitation composed where there are chamber pressures) on
    both engines: the same steady K*, and different from the non-rotating device's by more
    than the engines differ (volumetric drifts for hundreds of cycles; its compositions are
    compared over a fixed span in test_fast)."""
    model = with_effects(get_model(name), RotatingFrame(60.0, 0.5, 0.0))
    if "p1" in model.state_names:
        model = with_effects(model, Cavitation(2339.0))
    opts = SolverOptions(rtol=1e-9)
    k = [dynamic_stiffness(steady_state(model, P, S, options=opts.replace(engine=e))).value
         for e in ENGINES]
    assert abs(k[0] - k[1]) < 1e-6 * abs(k[1])
    if name not in ("single_state", "inertial_2state"):  # there only the stroke term acts
        k0 = dynamic_stiffness(steady_state(name, P, S, options=opts)).value
        assert abs(k[1] - k0) > 100 * abs(k[0] - k[1])


@pytest.mark.parametrize("name", ["full", "inertial", "constant_bulk"])
def test_rotating_frame_with_open_cavities_runs_alike_on_every_engine(name):
    """p_v above the inboard ends' lowest pressure: cavities open in both chambers (the
    inboard-end switch of the composition), and the engines give the same force history."""
    model = with_effects(get_model(name), RotatingFrame(60.0, 0.5, 0.0), Cavitation(7.0e4))
    opts = SolverOptions(rtol=1e-9)
    a, b = (simulate(model, P, S, 0.6, options=opts.replace(engine=e)) for e in ENGINES)
    assert a.status == b.status == "completed"
    assert min(a.state("Vc1").max(), a.state("Vc2").max()) > 5e-8  # [m^3]
    assert np.max(np.abs(a.force - b.force)) < 1e-6 * np.max(np.abs(a.force))
