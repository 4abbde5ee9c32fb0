"""Integration engines behind one small numbered contract.

Two engines integrate the same equations (the compiled physics of
:mod:`liquidamp.device.kernels`): ``"scipy"`` (:func:`scipy.integrate.solve_ivp`,
the reference) and ``"compiled"`` (the numba steppers of
:mod:`liquidamp.coupled.fast`).  :data:`ENGINES` holds them by the name
``SolverOptions.engine`` gives; the drivers (:func:`liquidamp.coupled.testrig.simulate`,
:func:`~liquidamp.coupled.testrig.steady_state`,
:func:`~liquidamp.coupled.assembly.simulate_coupled`) pick one there and
nowhere else.

The contract every engine keeps (``tests/coupled/test_engines.py`` checks
1-5 over the whole model registry, with every effect that applies):

1. ``name`` is its key in :data:`ENGINES` and the ``SolverOptions.engine``
   value that selects it.
2. ``supports(system) -> str | None``: None where it can run ``system`` (a
   :class:`TestRig` or a :class:`~liquidamp.coupled.assembly.CoupledSystem`),
   otherwise one line saying why; it never raises for a well-formed system.
3. ``march(rig, x0, t0, t1, t_eval, options, max_step, stats) -> X``: the
   states of a :class:`TestRig` at the sorted times ``t_eval`` within
   [t0, t1] [s], shape (n_states, len(t_eval)), with the error controlled on
   ``atol_i + rtol |x_i|`` (``atol = options.atol_scale * state_scales``)
   and steps no longer than ``max_step``; ``stats`` (a dict) receives the
   work counts.
4. ``march_cycles(rig, x0, options, stats) -> (X, cycles, residual, change,
   converged)``: whole cycles of a rig under a periodic stroke marched until
   the estimated remaining relative change of the force waveform is below
   ``options.steady_tol`` twice in a row (or the change is at the round-off
   floor 50 rtol) after at least ``options.min_cycles``, or
   ``options.max_cycles`` have passed (``converged`` False, no error); ``X``
   the last period at ``options.samples_per_period`` + 1 samples, both ends
   included (or at the sorted times ``grid`` within a period, ending at its
   end, where given).  ``steady`` (the base class) is the march alone, raising when it
   does not converge; the route that always arrives (march, then shooting)
   is :func:`liquidamp.coupled.periodic.periodic_state`.
5. Failures raise, never return NaN: :class:`~liquidamp.errors.PressureError`
   when a chamber pressure reaches ``options.pressure_floor`` (models on the
   pressure-dependent bulk law), :class:`~liquidamp.errors.ConvergenceError`
   when the stepper fails or no steady state comes within
   ``options.max_cycles``, and :class:`~liquidamp.errors.ParameterError`
   with the reason of (2) for a system it does not support (no silent
   fall-back to another engine).

References
----------
.. [1] E. Hairer, G. Wanner, Solving Ordinary Differential Equations II, 2nd ed.,
   Springer 1996 (RODAS4; the stiff reference Radau IIA).
.. [2] P. Virtanen et al., SciPy 1.0, Nature Methods 17, 2020 (``solve_ivp``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from liquidamp.coupled._kernels import steady_rule
from liquidamp.device.models import DeviceModel
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError, check_choice
from liquidamp.structure.port import DevicePort
from liquidamp.structure.testmachine import (
    FourierStroke,
    HarmonicStroke,
    RecordedStroke,
    TwoFrequencyStroke,
)

__all__ = ["TestRig", "Engine", "ScipyEngine", "CompiledEngine", "ENGINES", "get_engine",
           "engine_for",
           "TEST_MACHINE_PORT", "stroke_inputs"]

#: The test machine's one port: it prescribes the rod stroke and reads the load-cell force.
TEST_MACHINE_PORT = DevicePort("rod", "stroke", "stroke_rate", "force", 1.0, "rod")


@dataclass(frozen=True, eq=False)
class TestRig:
    """A device on the test machine: the host that prescribes the stroke at its port.

    Parameters
    ----------
    model : DeviceModel
        The device model (any effects).
    params : DeviceParams
        Its parameters.
    stroke : callable
        ``stroke(t) -> (y [m], v [m/s], a [m/s^2])`` with ``max_abs``: a
        :class:`~liquidamp.structure.testmachine.HarmonicStroke`, a
        :class:`~liquidamp.structure.testmachine.TwoFrequencyStroke`, a
        :class:`~liquidamp.structure.testmachine.RecordedStroke` or another
        callable (the scipy engine only).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> rig = TestRig(get_model("full"), preset("reference"), HarmonicStroke(0.001, 3.0))
    >>> rig.ports[0].name, ENGINES["compiled"].supports(rig) is None
    ('rod', True)
    """

    __test__ = False  # not a pytest test class

    model: DeviceModel
    params: object
    stroke: object

    def __post_init__(self) -> None:
        # a model that reads measured channels needs their series with the stroke: refused
        # before any work otherwise (liquidamp.device.effects_base.Effect)
        if getattr(self.model, "input_channels", ()):
            from liquidamp.device.effects_base import check_input_channels

            chans = getattr(self.stroke, "channels", None) or {}
            where = (f"the {type(self.stroke).__name__}" if not chans
                     else "the recorded stroke")
            check_input_channels(self.model, tuple(chans), where)

    @property
    def ports(self) -> tuple[DevicePort, ...]:
        """The test machine's single port ``rod``."""
        return (TEST_MACHINE_PORT,)


class Engine:
    """An integration engine (see the module's numbered contract)."""

    name = ""

    def supports(self, system) -> str | None:  # pragma: no cover - abstract
        """None where the engine runs ``system``, otherwise why not (contract item 2)."""
        raise NotImplementedError

    def check(self, system) -> None:
        """Raise ParameterError with the reason of :meth:`supports` (contract item 5)."""
        reason = self.supports(system)
        if reason is not None:
            head = f"engine {self.name!r}"
            raise ParameterError(reason if reason.startswith(head)
                                 else f"{head} cannot run this system: {reason}")

    def march(self, rig: TestRig, x0, t0: float, t1: float, t_eval, options, max_step: float,
              stats: dict, max_steps: int | None = None) -> np.ndarray:  # pragma: no cover
        """States of ``rig`` at ``t_eval`` (contract item 3); ``max_steps``: the most
        integrator steps before ConvergenceError, where the engine counts steps (None: the
        engine's own limit)."""
        raise NotImplementedError

    def march_cycles(self, rig: TestRig, x0, options, stats: dict, grid=None
                     ) -> tuple[np.ndarray, int, float, float, bool]:  # pragma: no cover
        """Whole cycles marched until the steady-state rule accepts (contract item 4);
        ``grid``: sorted sample times within a period ending at its end (default uniform)."""
        raise NotImplementedError

    def steady(self, rig: TestRig, x0, options, stats: dict) -> tuple[np.ndarray, int, float]:
        """Periodic steady state of ``rig`` by marching alone (contract item 4): the last
        period (end point excluded), the cycles and the estimated remaining change; raises
        ConvergenceError after ``options.max_cycles``.  (The route that always arrives,
        marching then shooting, is :func:`liquidamp.coupled.periodic.periodic_state`.)"""
        X, cycles, residual, change, converged = self.march_cycles(rig, x0, options, stats)
        if not converged:
            raise ConvergenceError(
                f"model {rig.model.name!r}: no periodic steady state after "
                f"{options.max_cycles} cycles at {rig.stroke.describe()}; last relative change "
                f"per cycle {change:.2e}, estimated remaining {residual:.2e} (allowed "
                f"{options.steady_tol:g}); raise max_cycles or steady_tol")
        return X[:, :-1], cycles, residual


class ScipyEngine(Engine):
    """The reference: :func:`scipy.integrate.solve_ivp` (``options.method``, Radau by default)
    on the compiled right-hand side and Jacobian of the model."""

    name = "scipy"

    def supports(self, system) -> str | None:
        """Every test rig and every coupled system."""
        if isinstance(system, TestRig) and not isinstance(system.model, DeviceModel):
            return f"not a DeviceModel: {type(system.model).__name__}"
        return None

    def march(self, rig, x0, t0, t1, t_eval, options, max_step, stats, max_steps=None):
        sol = _solve_span(rig.model, rig.params, rig.stroke, x0, t0, t1, t_eval, options, max_step)
        _add_scipy_stats(stats, options, sol)
        return sol.y

    def march_cycles(self, rig, x0, options, stats, grid=None):
        model, params, stroke = rig.model, rig.params, rig.stroke
        T = stroke.period
        grid = (np.arange(options.samples_per_period + 1) * (T / options.samples_per_period)
                if grid is None else np.asarray(grid, float))
        N = grid.size - 1
        x = np.asarray(x0, float)
        prev_force = None
        prev_change = math.inf
        hits = 0
        residual = math.inf
        from liquidamp.coupled.fast import step_period

        h_max = options.max_step_fraction * step_period(stroke)
        X = None
        for k in range(options.max_cycles):
            t0 = k * T
            X = self.march(rig, x, t0, t0 + T, t0 + grid, options, h_max, stats)
            x = X[:, -1]
            t = t0 + grid[:N]
            force = np.asarray(model.force(t, X[:, :N], stroke(t), params), float)
            if prev_force is not None:
                change, residual, hits = steady_rule(force, prev_force, prev_change, residual,
                                                     hits, k, options.rtol, options.steady_tol,
                                                     options.min_cycles)
                if hits >= 2:
                    return X, k + 1, min(residual, change), change, True
                prev_change = change
            prev_force = force
        return X, options.max_cycles, residual, prev_change, False


class CompiledEngine(Engine):
    """The numba steppers (Dormand-Prince 5(4) switching to RODAS4; DOP853 for the rotor)."""

    name = "compiled"

    def supports(self, system) -> str | None:
        """Test rigs with a harmonic, two-frequency or recorded stroke; the rotor built by
        ``rotor_system``."""
        from liquidamp.coupled import fast

        if isinstance(system, TestRig):
            if not isinstance(system.stroke, (HarmonicStroke, TwoFrequencyStroke,
                                              FourierStroke, RecordedStroke)):
                return (f"the compiled engine needs a TwoFrequencyStroke, FourierStroke, "
                        f"HarmonicStroke or RecordedStroke, got "
                        f"{type(system.stroke).__name__}; use engine='scipy' for another "
                        "stroke callable")
            return fast.supports(system.model)
        from liquidamp.coupled.compiled_route import compiled_support

        return compiled_support(system)

    def march(self, rig, x0, t0, t1, t_eval, options, max_step, stats, max_steps=None):
        from liquidamp.coupled import fast

        X, _, _ = fast.march(rig.model, rig.params, rig.stroke, x0, t0, t1, t_eval, options,
                             max_step, stats=stats, max_steps=max_steps)
        return X

    def march_cycles(self, rig, x0, options, stats, grid=None):
        from liquidamp.coupled import fast

        return fast.march_cycles(rig.model, rig.params, rig.stroke, x0, options, stats=stats,
                                 grid=grid)


def _events(model: DeviceModel, params: DeviceParams, stroke, options):
    if model.pressures is None or not model.uses_bulk_law or params.bulk_law != "gholizadeh":
        return None

    def low_pressure(t, x):
        u = stroke(t)
        p1, p2 = model.pressures(x, u, params)
        return min(p1, p2) - options.pressure_floor

    low_pressure.terminal = True
    low_pressure.direction = -1
    return [low_pressure]


def _solve_span(model, params, stroke, x0, t0, t1, t_eval, options, max_step):
    """Integrate one span; raise clear errors on failure or on zero pressure."""
    scales = model.state_scales(params)
    atol = options.atol_scale * scales if scales.size else options.atol_scale
    rhs, jac = model.rhs, model.jacobian
    drive = stroke
    if getattr(model, "input_channels", ()):  # u = (y, v, a, channel values in slot order)
        def drive(t):
            return tuple(stroke(t)) + (stroke_inputs(stroke, t),)

    def f(t, x):
        return rhs(t, x, drive(t), params)

    kwargs = {}
    if jac is not None and options.method in ("Radau", "BDF", "LSODA"):
        kwargs["jac"] = lambda t, x: jac(t, x, drive(t), params)
    # scipy's Radau step predictor divides by the previous step, which is zero after a
    # step rejected down to zero width at a contact (freeplay, end stops); scipy guards the
    # next line with errstate(divide='ignore') and the quotient only enters min(1, .), so
    # the division by zero is harmless: silence it here, not in the user's filters
    with np.errstate(divide="ignore"):
        sol = solve_ivp(
            f, (t0, t1), x0, method=options.method, t_eval=t_eval, rtol=options.rtol,
            atol=atol, events=_events(model, params, stroke, options), max_step=max_step,
            **kwargs,
        )
    if sol.status == 1:
        tz = float(sol.t_events[0][0])
        raise PressureError(
            f"model {model.name!r}: a chamber pressure fell to the floor "
            f"{options.pressure_floor:g} Pa at t = {tz:.6g} s; the liquid-air law (eq. 2) is "
            "singular at p = 0. The device cavitates: reduce the stroke or frequency, raise the "
            "filling pressure p0, or add the 'cavitation' effect"
        )
    if sol.status != 0:
        raise ConvergenceError(
            f"model {model.name!r}: time integration failed between t = {t0:.6g} s and "
            f"{t1:.6g} s: {sol.message}"
        )
    if not np.all(np.isfinite(sol.y)):
        raise ConvergenceError(f"model {model.name!r}: non-finite state in time integration")
    return sol


def stroke_inputs(stroke, t):
    """The measured input channels a stroke carries at ``t`` [s], in the slot order of
    :data:`liquidamp.device.kernels.CHANNELS` (shape (N_CH,) or (N_CH, len(t)); zeros for
    channels it lacks), or None for a stroke without channels: the fourth entry of
    ``u = (y, v, a, c)`` of :meth:`DeviceModel.rhs` and :meth:`DeviceModel.force`.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> s = RecordedStroke(t, 0 * t, 0 * t, 0 * t, channels={"voltage": 2 * t})
    >>> stroke_inputs(s, 0.5).tolist()
    [0.0, 1.0, 0.0, 0.0]
    """
    from liquidamp.device.kernels import CHANNELS

    chans = getattr(stroke, "channels", None)
    if not chans:
        return None
    vals = stroke.channel_values(t)
    zero = np.zeros(np.shape(t))
    return np.array([vals.get(c, zero) for c in CHANNELS], float)


def _add_scipy_stats(stats: dict, options, sol) -> None:
    """Accumulate the work counts of a ``solve_ivp`` span into ``stats``."""
    stats["engine"] = "scipy"
    stats["method"] = options.method
    for key in ("nfev", "njev", "nlu"):
        stats[key] = stats.get(key, 0) + int(getattr(sol, key, 0))


#: The engines by name (``SolverOptions.engine``).
ENGINES: dict[str, Engine] = {e.name: e for e in (ScipyEngine(), CompiledEngine())}


def engine_for(system, options) -> Engine:
    """The engine ``options.engine`` names, checked against ``system`` (contract item 5).

    Parameters
    ----------
    system : TestRig or CoupledSystem
        What is to be integrated.
    options : SolverOptions
        Gives the engine name.

    Returns
    -------
    Engine

    Raises
    ------
    ParameterError
        An unknown engine, or one that does not support ``system`` (with its reason).
    """
    engine = get_engine(options.engine)
    engine.check(system)
    return engine


def get_engine(name: str) -> Engine:
    """The engine called ``name`` (``"scipy"`` or ``"compiled"``; ``"python"`` is ``"scipy"``).

    Examples
    --------
    >>> get_engine("python").name
    'scipy'
    >>> get_engine("fortran")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown engine 'fortran'; valid: scipy, compiled
    """
    name = {"python": "scipy"}.get(name, name)
    check_choice("engine", name, ENGINES)
    return ENGINES[name]
