"""The device on a test machine: time-domain runs and the periodic steady state.

The host is the test machine of :mod:`liquidamp.structure.testmachine`, which
prescribes the stroke; the device is any registered model of
:mod:`liquidamp.device.models`.  :func:`simulate` marches over a time span;
:func:`steady_state` finds the periodic steady state by the route that always
arrives (:mod:`liquidamp.coupled.periodic`): whole excitation cycles marched
until the force waveform stops changing, judged by the change between
successive cycles and the rate at which it shrinks (an estimate of the
distance still to go, not a guessed cycle count), and Newton shooting with the
sealed device's invariants where the march stalls or is too slow.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from liquidamp.coupled.engines import TestRig, engine_for
from liquidamp.coupled.periodic import ROUTES, ShootingOptions, periodic_state
from liquidamp.device.effects import least_pressures
from liquidamp.device.models import get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, check_choice
from liquidamp.options import SolverOptions, resolve_options
from liquidamp.structure.testmachine import FourierStroke, HarmonicStroke, TwoFrequencyStroke

__all__ = ["DeviceResponse", "simulate", "steady_state", "check_stroke", "prepare_run",
           "build_response"]


@dataclass(frozen=True, eq=False)
class DeviceResponse:
    """Named, immutable result of a device run on the test machine.

    Attributes
    ----------
    model : str
        Registry name of the device model.
    params : DeviceParams
        Parameters used.
    time : ndarray
        Sample times [s].
    stroke, stroke_rate, stroke_acceleration : ndarray
        Prescribed piston displacement [m], velocity [m/s], acceleration [m/s^2].
    force : ndarray
        Load-cell force, friction included [N].
    states : ndarray
        States, shape (n_states, n_samples).
    state_names, state_units : tuple of str
        Names and units of the rows of ``states``.
    p1, p2 : ndarray or None
        Chamber pressures [Pa] where the model has them.
    mass_error : float or None
        Largest relative change of the total fluid mass over the run [-].
    status : str
        ``"steady"`` (periodic steady state reached), ``"completed"`` (a
        plain run finished).
    message : str
        What happened, in words.
    residual : float
        For a steady state: estimated remaining change of the force waveform
        relative to its peak [-]; NaN-free, 0 for a plain run.
    cycles : int
        Excitation cycles marched (0 for a plain run).
    warnings : tuple of str
        Conditions outside the model's validity (e.g. cavitation).
    frequency : float or None
        Excitation frequency of a harmonic stroke [Hz].
    amplitude : float or None
        Excitation amplitude of a harmonic stroke [m].
    solver_stats : Mapping
        How the integration went: ``engine``, ``method`` and step counts
        (compiled engine: ``steps``, ``explicit_steps``, ``rodas4_steps``,
        ``switches_to_rodas4``, ``rerun_with_rodas4``, see
        :func:`liquidamp.coupled.fast.march`; Python engine: ``nfev``,
        ``njev``, ``nlu`` summed over the spans).  Read-only.
    """

    model: str
    params: DeviceParams
    time: np.ndarray
    stroke: np.ndarray
    stroke_rate: np.ndarray
    stroke_acceleration: np.ndarray
    force: np.ndarray
    states: np.ndarray
    state_names: tuple[str, ...]
    state_units: tuple[str, ...]
    p1: np.ndarray | None
    p2: np.ndarray | None
    mass_error: float | None
    status: str
    message: str
    residual: float = 0.0
    cycles: int = 0
    warnings: tuple[str, ...] = field(default=())
    frequency: float | None = None
    amplitude: float | None = None
    solver_stats: Mapping = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "solver_stats", MappingProxyType(dict(self.solver_stats)))
        for name in ("time", "stroke", "stroke_rate", "stroke_acceleration", "force", "states",
                     "p1", "p2"):
            arr = getattr(self, name)
            if arr is not None:
                arr.setflags(write=False)

    @property
    def min_pressure(self) -> float | None:
        """Lowest chamber pressure over the run [Pa] (None if not modelled)."""
        if self.p1 is None:
            return None
        return float(min(self.p1.min(), self.p2.min()))

    def state(self, name: str) -> np.ndarray:
        """Samples of the state called ``name``."""
        if name not in self.state_names:
            raise ParameterError(
                f"model {self.model!r} has no state {name!r}; states: {', '.join(self.state_names)}"
            )
        return self.states[self.state_names.index(name)]


def check_stroke(stroke, params: DeviceParams) -> None:
    """Raise before any work if the stroke reaches a chamber end (|y| >= V0i/A_p).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> check_stroke(HarmonicStroke(0.03, 3.0), preset("reference"))
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: stroke reaches |y| = 0.03 m, past the chamber end at \
0.025 m (V0/A_p); allowed: |y| < 0.025 m
    """
    y_max = stroke.max_abs
    limit = params.stroke_limit
    if y_max >= limit:
        raise ParameterError(
            f"stroke reaches |y| = {y_max:.4g} m, past the chamber end at {limit:.4g} m "
            f"(V0/A_p); allowed: |y| < {limit:.4g} m"
        )


def prepare_run(model, params, stroke, options):
    """Resolve and check the inputs of a test-machine run.

    Parameters
    ----------
    model : str or DeviceModel
        A registered model name or a model.
    params : DeviceParams
        Device parameters (checked against the model).
    stroke : callable
        The stroke, ``stroke(t) -> (y [m], v [m/s], a [m/s^2])`` (checked).
    options : SolverOptions or None
        None resolves to the ``"default"`` preset.

    Returns
    -------
    model : DeviceModel
    options : SolverOptions

    Raises
    ------
    ParameterError
        If ``params`` is not a :class:`~liquidamp.device.params.DeviceParams` or fails the
        model's or the stroke's checks.
    """
    model = get_model(model)
    if not isinstance(params, DeviceParams):
        raise ParameterError(f"params must be DeviceParams, got {type(params).__name__}")
    model.check_params(params)
    check_stroke(stroke, params)
    return model, resolve_options(options, "default")


def build_response(model, params, stroke, t, X, options, *, status, message, residual=0.0,
                   cycles=0, warnings=(), stats=None):
    """The :class:`DeviceResponse` of states ``X`` at times ``t``: force, pressures, checks.

    Parameters
    ----------
    model : DeviceModel
        The resolved model.
    params : DeviceParams
        Device parameters.
    stroke : callable
        ``stroke(t) -> (y [m], v [m/s], a [m/s^2])``.
    t : ndarray
        Times [s], shape (n,).
    X : ndarray
        States at ``t``, shape (n_states, n).
    options : SolverOptions
        Gives ``vapour_pressure`` [Pa] for the cavitation warning.
    status, message : str
        Copied to the response.
    residual : float
        Periodicity residual of a steady state [-].
    cycles : int
        Excitation cycles marched.
    warnings : sequence of str
        Warnings so far (pressure warnings are appended).
    stats : dict, optional
        Solver work counts.

    Returns
    -------
    DeviceResponse
    """
    y, v, a = stroke(t)
    y, v, a = (np.broadcast_to(np.asarray(q, float), t.shape).copy() for q in (y, v, a))
    u = (y, v, a)
    force = np.asarray(model.force(t, X, u, params), dtype=float)
    force = np.broadcast_to(force, t.shape).copy()
    p1 = p2 = None
    warn = list(warnings)
    if model.pressures is not None:
        p1, p2 = (np.asarray(q, float).copy() for q in model.pressures(X, u, params))
        pmin = float(min(p1.min(), p2.min()))
        if pmin <= 0.0:
            warn.append(
                f"absolute chamber pressure went negative (lowest {pmin:.4g} Pa): non-physical; "
                f"model {model.name!r} with a constant bulk modulus is outside its validity "
                "here (use 'full', eq. 10)"
            )
        else:
            # the cavitation margin: with a rotating frame, at the chambers' inboard ends
            q1, q2 = least_pressures(model, X, u, params)
            pmin = float(min(np.min(q1), np.min(q2)))
            where = " (inboard end, rotating frame)" if model.effect("rotating_frame") else ""
            if pmin < options.vapour_pressure and model.effect("cavitation") is None:
                warn.append(
                    f"lowest chamber pressure{where} {pmin:.4g} Pa is below the vapour pressure "
                    f"{options.vapour_pressure:g} Pa: the liquid would cavitate, which this "
                    "model does not represent (add the 'cavitation' effect)"
                )
    mass_error = None
    if model.mass is not None:
        M = np.asarray(model.mass(X, u, params), float)
        mass_error = float(np.max(np.abs(M - M[0])) / M[0])
    freq = amp = None
    if isinstance(stroke, HarmonicStroke):
        freq, amp = stroke.frequency, stroke.amplitude
    return DeviceResponse(
        model=model.name, params=params, time=t, stroke=y, stroke_rate=v, stroke_acceleration=a,
        force=force, states=X, state_names=model.state_names, state_units=model.state_units,
        p1=p1, p2=p2, mass_error=mass_error, status=status, message=message,
        residual=float(residual), cycles=cycles, warnings=tuple(warn), frequency=freq,
        amplitude=amp, solver_stats=stats or {},
    )


def simulate(model, params: DeviceParams, stroke, t_end: float, *, t_start: float = 0.0,
             x0=None, t_eval=None, options: SolverOptions | None = None) -> DeviceResponse:
    """Run ``model`` under a prescribed stroke from ``t_start`` to ``t_end``.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model name (see :func:`liquidamp.device.models.model_names`).
    params : DeviceParams
        Device parameters.
    stroke : callable
        ``stroke(t) -> (y, v, a)`` [m, m/s, m/s^2] with attribute ``max_abs``
        (a :class:`HarmonicStroke`, :class:`TwoFrequencyStroke` or
        :class:`RecordedStroke`).
    t_end : float
        End time [s].
    t_start : float
        Start time [s].
    x0 : array, optional
        Initial state; default the model's rest state at ``p0``.
    t_eval : array, optional
        Output times [s]; default 200 samples per second or 512 in all,
        whichever is more.
    options : SolverOptions, optional
        Tolerances and the engine (``options.engine = "compiled"`` runs the
        numba core of :mod:`liquidamp.coupled.fast` for a HarmonicStroke or
        RecordedStroke).  Default: the ``"default"`` preset
        (:data:`liquidamp.options.PRESETS`).

    Returns
    -------
    DeviceResponse
        With ``status = "completed"``.

    Raises
    ------
    ParameterError
        Stroke past the chamber end, parameters outside the model's domain.
    PressureError
        A chamber pressure reached ``options.pressure_floor``.
    ConvergenceError
        The integrator failed.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> r = simulate("maxwell", preset("reference"), HarmonicStroke(0.001, 3.0), 0.5)
    >>> r.status, r.force.shape == r.time.shape
    ('completed', True)
    """
    model, options = prepare_run(model, params, stroke, options)
    t_end = float(t_end)
    if not t_end > t_start:
        raise ParameterError(f"t_end must be > t_start = {t_start:g} s, got {t_end:g} s")
    if t_eval is None:
        t_eval = np.linspace(t_start, t_end, max(512, int(200 * (t_end - t_start)) + 1))
    t_eval = np.asarray(t_eval, float)
    x = model.initial_state(params, float(stroke(t_start)[0])) if x0 is None else np.asarray(
        x0, float)
    if isinstance(stroke, TwoFrequencyStroke):
        period = stroke.shortest_period
    else:
        period = getattr(stroke, "period", t_end - t_start)
    stats = {}
    if model.n_states == 0:
        X = np.zeros((0, t_eval.size))
    else:
        rig = TestRig(model, params, stroke)
        engine = engine_for(rig, options)
        X = engine.march(rig, x, t_start, t_end, t_eval, options,
                         options.max_step_fraction * period, stats)
    return build_response(model, params, stroke, t_eval, X, options, status="completed",
                     message=f"integrated {t_end - t_start:.4g} s", stats=stats)


def steady_state(model, params: DeviceParams, stroke, *,
                 options: SolverOptions | None = None, x0=None, route: str = "auto",
                 shooting: ShootingOptions | None = None,
                 invariants_of=None) -> DeviceResponse:
    """Periodic steady state of ``model`` under a periodic stroke: one period of samples.

    The route that always arrives (:func:`liquidamp.coupled.periodic.periodic_state`):
    cycles are marched one at a time.  After each, the change of the force
    waveform against the previous cycle, relative to the force peak, is
    ``d_k``; with the contraction ratio ``rho = d_k / d_{k-1}`` the distance
    still to go is estimated as ``d_k rho / (1 - rho)``.  The march stops when
    that estimate (or ``d_k`` itself once the change is at round-off level)
    is below ``options.steady_tol`` for two cycles in a row.  Where the march
    stalls (the change sits at the integration noise) or would need more
    cycles than ``options.max_cycles`` leaves, Newton shooting with the sealed
    device's invariants held takes over from the last marched state.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model.
    params : DeviceParams
        Device parameters.
    stroke : HarmonicStroke, TwoFrequencyStroke or FourierStroke
        Excitation; a two-frequency stroke must have a common period
        (commensurate frequencies, :attr:`TwoFrequencyStroke.common_period`),
        which is then the cycle.
    options : SolverOptions, optional
        Tolerances, cycle limits and the engine (``"compiled"``: the whole
        cycle loop runs in the numba core of :mod:`liquidamp.coupled.fast`).
        Default: the ``"default"`` preset (:data:`liquidamp.options.PRESETS`).
    x0 : array, optional
        Initial state, a first guess (default: rest at ``p0``); its invariants
        (total mass, density-pressure relations) select the orbit.
    route : {"auto", "march", "shooting"}
        ``"auto"`` (default): march, then shoot where needed; ``"march"``:
        marching alone; ``"shooting"``: Newton from the first period.
    shooting : ShootingOptions, optional
        Tolerance and iterations of the shooting.
    invariants_of : array, optional
        A state whose invariants select the orbit (default ``x0``): with a warm
        start ``x0`` from a nearby orbit, the rest state.

    Returns
    -------
    DeviceResponse
        The last period (``options.samples_per_period`` samples, the end
        point excluded, time from 0), ``status = "steady"``; ``residual``
        the march's estimated remaining relative change of the force or the
        shooting's periodicity residual (state scales); ``cycles`` the cycles
        marched plus the shooting's one-period runs; ``message`` and
        ``solver_stats["route"]`` (``"march"`` or ``"shooting"``) say which
        route arrived (``solver_stats`` also holds ``march_cycles``,
        ``shooting_runs``, ``newton_iterations``).

    Raises
    ------
    ConvergenceError
        If neither route arrives (the march's cycles and last change, the
        shooting's iterations and residual).
    PressureError, ParameterError
        As for :func:`simulate`.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> r = steady_state("full", preset("reference"), HarmonicStroke(0.003, 3.0))
    >>> r.status, r.residual < 1e-6, r.mass_error < 1e-9, r.solver_stats["route"]
    ('steady', True, True, 'march')
    """
    model, options = prepare_run(model, params, stroke, options)
    if not isinstance(stroke, (HarmonicStroke, TwoFrequencyStroke, FourierStroke)):
        raise ParameterError("steady_state needs a HarmonicStroke, a TwoFrequencyStroke or a "
                             "FourierStroke; use simulate() for a record")
    check_choice("periodic-state route", route, ROUTES)
    T = stroke.period  # a two-frequency stroke without a common period raises here
    N = options.samples_per_period
    x = model.initial_state(params, float(stroke(0.0)[0])) if x0 is None else np.asarray(
        x0, float)
    if x.shape != (model.n_states,):
        raise ParameterError(f"x0 must hold the {model.n_states} states of model "
                             f"{model.name!r}, got shape {x.shape}")
    grid = np.arange(N + 1) * (T / N)
    if model.n_states == 0:
        return build_response(model, params, stroke, grid[:N], np.zeros((0, N)), options,
                         status="steady", message="algebraic model: steady at once", cycles=1,
                         stats={"route": "algebraic"})
    rig = TestRig(model, params, stroke)
    engine = engine_for(rig, options)
    sol = periodic_state(rig, engine, x, options, route=route, shooting=shooting,
                         invariants_of=invariants_of)
    return build_response(model, params, stroke, grid[:N], sol.states, options,
                          status="steady", message=sol.message, residual=sol.residual,
                          cycles=sol.cycles + sol.runs, stats=sol.stats)
