"""The device on a test machine: time-domain runs and the periodic steady state.

The host is the test machine of :mod:`liquidamp.structure.testmachine`, which
prescribes the stroke; the device is any registered model of
:mod:`liquidamp.device.models`.  :func:`simulate` marches over a time span;
:func:`steady_state` marches whole excitation cycles until the force waveform
stops changing, judged by the change between successive cycles and the rate
at which it shrinks (an estimate of the distance still to go, not a guessed
cycle count).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
from scipy.integrate import solve_ivp

from liquidamp.device.models import DeviceModel, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError
from liquidamp.options import SolverOptions, resolve_options
from liquidamp.structure.testmachine import HarmonicStroke

__all__ = ["DeviceResponse", "simulate", "steady_state", "check_stroke", "prepare_run",
           "march_span", "build_response"]


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


def _events(model: DeviceModel, params: DeviceParams, stroke, options: SolverOptions):
    if model.pressures is None or not model.uses_bulk_law or params.bulk_law != "gholizadeh":
        return None

    def low_pressure(t, x):
        u = stroke(t)
        p1, p2 = model.pressures(x, u, params)
        return min(p1, p2) - options.pressure_floor

    low_pressure.terminal = True
    low_pressure.direction = -1
    return [low_pressure]


def march_span(model, params, stroke, x0, t0, t1, t_eval, options, max_step):
    """Integrate one span with scipy's ``solve_ivp``; clear errors on failure or zero pressure.

    Parameters
    ----------
    model : DeviceModel
        The resolved model (see :func:`prepare_run`).
    params : DeviceParams
        Device parameters.
    stroke : callable
        ``stroke(t) -> (y [m], v [m/s], a [m/s^2])``.
    x0 : array
        Initial state (units of ``model.state_units``).
    t0, t1 : float
        Time span [s].
    t_eval : array or None
        Output times within [t0, t1] [s].
    options : SolverOptions
        ``method``, ``rtol``, ``atol_scale`` (times the model's state scales),
        ``pressure_floor`` [Pa].
    max_step : float
        Largest step [s].

    Returns
    -------
    scipy.integrate.OdeResult
        The ``solve_ivp`` solution (``t`` [s], ``y`` states).

    Raises
    ------
    PressureError
        If a chamber pressure reaches the floor (eq. 2 singular at p = 0).
    ConvergenceError
        If the integration fails or a state is not finite.
    """
    scales = model.state_scales(params)
    atol = options.atol_scale * scales if scales.size else options.atol_scale
    rhs, jac = model.rhs, model.jacobian

    def f(t, x):
        return rhs(t, x, stroke(t), params)

    kwargs = {}
    if jac is not None and options.method in ("Radau", "BDF", "LSODA"):
        kwargs["jac"] = lambda t, x: jac(t, x, stroke(t), params)
    sol = solve_ivp(
        f, (t0, t1), x0, method=options.method, t_eval=t_eval, rtol=options.rtol, atol=atol,
        events=_events(model, params, stroke, options), max_step=max_step, **kwargs,
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


def _add_stats(stats: dict, options, sol) -> None:
    """Accumulate the work counts of a ``solve_ivp`` span into ``stats``."""
    stats["engine"] = "scipy"
    stats["method"] = options.method
    for key in ("nfev", "njev", "nlu"):
        stats[key] = stats.get(key, 0) + int(getattr(sol, key, 0))


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
        elif pmin < options.vapour_pressure:
            warn.append(
                f"lowest chamber pressure {pmin:.4g} Pa is below the vapour pressure "
                f"{options.vapour_pressure:g} Pa: the liquid would cavitate, which this model "
                "does not represent (add the 'cavitation' effect)"
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
        (a :class:`HarmonicStroke` or :class:`RecordedStroke`).
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
    period = getattr(stroke, "period", t_end - t_start)
    stats = {}
    if model.n_states == 0:
        X = np.zeros((0, t_eval.size))
    elif options.engine == "compiled":
        from liquidamp.coupled.fast import march

        X, _, _ = march(model, params, stroke, x, t_start, t_end, t_eval, options,
                        options.max_step_fraction * period, stats=stats)
    else:
        sol = march_span(model, params, stroke, x, t_start, t_end, t_eval, options,
                     options.max_step_fraction * period)
        X = sol.y
        _add_stats(stats, options, sol)
    return build_response(model, params, stroke, t_eval, X, options, status="completed",
                     message=f"integrated {t_end - t_start:.4g} s", stats=stats)


def steady_state(model, params: DeviceParams, stroke: HarmonicStroke, *,
                 options: SolverOptions | None = None, x0=None) -> DeviceResponse:
    """Periodic steady state of ``model`` under a harmonic stroke: one period of samples.

    Cycles are marched one at a time.  After each, the change of the force
    waveform against the previous cycle, relative to the force peak, is
    ``d_k``; with the contraction ratio ``rho = d_k / d_{k-1}`` the distance
    still to go is estimated as ``d_k rho / (1 - rho)``.  The run stops when
    that estimate (or ``d_k`` itself once the change is at round-off level)
    is below ``options.steady_tol`` for two cycles in a row.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model.
    params : DeviceParams
        Device parameters.
    stroke : HarmonicStroke
        Excitation.
    options : SolverOptions, optional
        Tolerances, cycle limits and the engine (``"compiled"``: the whole
        cycle loop runs in the numba core of :mod:`liquidamp.coupled.fast`).
        Default: the ``"default"`` preset (:data:`liquidamp.options.PRESETS`).
    x0 : array, optional
        Initial state (default: rest at ``p0``).

    Returns
    -------
    DeviceResponse
        The last period (``options.samples_per_period`` samples, the end
        point excluded), ``status = "steady"``, ``residual`` the estimated
        remaining relative change, ``cycles`` the cycles marched.

    Raises
    ------
    ConvergenceError
        If ``options.max_cycles`` pass without convergence.
    PressureError, ParameterError
        As for :func:`simulate`.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> r = steady_state("full", preset("reference"), HarmonicStroke(0.003, 3.0))
    >>> r.status, r.residual < 1e-6, r.mass_error < 1e-9
    ('steady', True, True)
    """
    model, options = prepare_run(model, params, stroke, options)
    if not isinstance(stroke, HarmonicStroke):
        raise ParameterError("steady_state needs a HarmonicStroke; use simulate() for a record")
    T = stroke.period
    N = options.samples_per_period
    x = model.initial_state(params, float(stroke(0.0)[0])) if x0 is None else np.asarray(
        x0, float)
    grid = np.arange(N + 1) * (T / N)
    if model.n_states == 0:
        return build_response(model, params, stroke, grid[:N], np.zeros((0, N)), options,
                         status="steady", message="algebraic model: steady at once", cycles=1)
    if options.engine == "compiled":
        from liquidamp.coupled.fast import steady_loop

        stats = {}
        Xp, cycles, residual = steady_loop(model, params, stroke, x, options, stats=stats)
        msg = (f"periodic steady state after {cycles} cycles; estimated remaining "
               f"change {residual:.2e} of peak force (compiled engine)")
        return build_response(model, params, stroke, grid[:N], Xp, options, status="steady",
                         message=msg, residual=residual, cycles=cycles, stats=stats)
    stats = {}
    prev_force = None
    prev_change = math.inf
    hits = 0
    residual = math.inf
    for k in range(options.max_cycles):
        t0 = k * T
        sol = march_span(model, params, stroke, x, t0, t0 + T, t0 + grid, options,
                     options.max_step_fraction * T)
        _add_stats(stats, options, sol)
        x = sol.y[:, -1]
        u = stroke(sol.t[:N])
        force = np.asarray(model.force(sol.t[:N], sol.y[:, :N], u, params), float)
        if prev_force is not None:
            scale = max(float(np.max(np.abs(force))), 1e-30)
            change = float(np.sqrt(np.mean((force - prev_force) ** 2))) / scale
            rho = change / prev_change if prev_change > 0 else 0.0
            if rho < 1.0:
                residual = change * rho / (1.0 - rho) if k > 1 else change
            else:
                residual = max(change, residual if math.isfinite(residual) else change)
            residual = max(residual, 0.0)
            floor = 50.0 * options.rtol
            if (residual < options.steady_tol or change < floor) and k + 1 >= options.min_cycles:
                hits += 1
            else:
                hits = 0
            if hits >= 2:
                Xp = sol.y[:, :N]
                msg = (f"periodic steady state after {k + 1} cycles; estimated remaining "
                       f"change {residual:.2e} of peak force")
                return build_response(model, params, stroke, sol.t[:N] - t0, Xp, options,
                                 status="steady", message=msg, residual=min(residual, change),
                                 cycles=k + 1, stats=stats)
            prev_change = change
        prev_force = force
    raise ConvergenceError(
        f"model {model.name!r}: no periodic steady state after {options.max_cycles} cycles at "
        f"{stroke.frequency:g} Hz, {stroke.amplitude:g} m; last relative change per cycle "
        f"{prev_change:.2e}, estimated remaining {residual:.2e} (allowed {options.steady_tol:g}); "
        "raise max_cycles or steady_tol"
    )
