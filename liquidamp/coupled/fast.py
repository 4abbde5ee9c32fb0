"""Compiled simulation core: the device models integrated by numba-compiled code.

This is the engine behind ``SolverOptions(engine="compiled")``:
:func:`liquidamp.coupled.testrig.simulate` and
:func:`~liquidamp.coupled.testrig.steady_state` dispatch here and return the
same :class:`~liquidamp.coupled.testrig.DeviceResponse` as the scipy
reference engine (``solve_ivp``), which is tested against this one.

Design
------
* No physics here: the right-hand side, Jacobian and force of every model
  and effect are those of :mod:`liquidamp.device.kernels`, the one copy
  that both engines run, on the arrays of
  :meth:`~liquidamp.device.models.DeviceModel.packed` (composition ``spec``,
  parameters ``prm``, effect parameters ``ep``), so one compiled
  specialisation (cached on disk, ``cache=True``) serves every model with
  any effects (:func:`supports`).
* Integrators: RODAS4 (Hairer & Wanner), an L-stable, stiffly accurate
  Rosenbrock method of order 4 with an embedded order-3 error estimate and a
  continuous extension for output between steps.  It needs one LU
  factorisation per step and no Newton iteration, which suits these small
  and very stiff systems (time constants from ~1e-5 s to seconds).  Many
  working points are not stiff at all (the reference design at 3 Hz: fluid
  mode near -127 +/- 133j 1/s against a 0.33 s period), and there the
  explicit Dormand-Prince 5(4) pair takes ~2.5x fewer steps at a fraction
  of the cost per step.  ``SolverOptions.compiled_method="auto"`` (default)
  therefore starts each span (each period in the steady-state loop) with
  Dormand-Prince and switches to RODAS4 when Hairer's stiffness test fires,
  the way LSODA switches from Adams to BDF; ``"rodas4"`` and ``"dopri5"``
  force one method.  The error is controlled on
  ``atol_i + rtol max(|x_i|, |x_new,i|)`` with the same ``rtol`` and
  ``atol = atol_scale * state_scales`` as the Python path, and the largest
  step is ``max_step_fraction`` of the period, as there.
* The harmonic stroke is evaluated analytically inside the compiled code; a
  recorded stroke by compiled linear interpolation of its arrays (ends held,
  as :func:`numpy.interp`); the integrator never steps across a sample time,
  where the interpolant has a kink, so each step sees a smooth input.
* The periodic-steady-state loop (march a period, compare the force
  waveform, stop on the same rule as the Python path) runs entirely in
  compiled code, in the periodic mode of the same compiled entry points as
  :func:`march`.  There are two, compiled from one source: the explicit-only
  kernel (``_kernels.integrate_explicit``) that a non-stiff ``"auto"`` call
  uses, so that its first call compiles about half the code, and the kernel
  with RODAS4 (``_kernels.integrate``), compiled when first needed: a stiff
  stretch makes the explicit kernel stop, and the call is rerun with the full
  kernel from the start (:func:`_run`), which gives the answer ``"auto"``
  would have given in one go.
* The rotor with a liquid device on each blade (:func:`simulate_rotor`,
  the nonlinear coupled system of :func:`liquidamp.coupled.assembly.rotor_system`)
  runs in one compiled kernel: the rotating-frame equations of
  :class:`~liquidamp.structure.rotor.GroundResonanceRotor` are assembled
  and solved (6 x 6 LU) inside the right-hand side, the device models are
  the same compiled ones, and the integrator is DOP853 with scipy's
  coefficients, error norm, step control and dense output (the coupled Hammond system is
  not stiff for these devices).  :func:`~liquidamp.coupled.assembly.simulate_coupled`
  dispatches here under ``SolverOptions(engine="compiled")``; its scipy route stays the
  reference.

``SolverOptions.method`` applies to the scipy engine only.  What the
compiled engine cannot run raises :class:`~liquidamp.errors.ParameterError`
naming why (:func:`supports`; no silent fall-back that could change an answer).

References
----------
.. [1] E. Hairer, G. Wanner, Solving Ordinary Differential Equations II, 2nd ed.,
   Springer 1996, Sec. IV.7.
.. [2] B. Titurus, AIAA J. 56(10), 2018, eqs. (10)-(18).
"""

from __future__ import annotations

import numpy as np

from liquidamp.coupled import _kernels as K
from liquidamp.device import kernels as DK
from liquidamp.device.models import BASES, DeviceModel
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError
from liquidamp.structure.testmachine import (
    FourierStroke,
    HarmonicStroke,
    RecordedStroke,
    TwoFrequencyStroke,
)

__all__ = ["COMPILED_MODELS", "supports", "check_compiled", "march", "steady_loop",
           "march_cycles", "step_period", "warm_up"]

#: Registry names of the base models the compiled engine runs: all of them, with any
#: add-on effects (the physics is :mod:`liquidamp.device.kernels`, shared with scipy).
COMPILED_MODELS = tuple(BASES)

#: Largest number of integration steps (accepted and rejected) in one call of the rotor
#: kernels; the device kernels take ``SolverOptions.max_steps`` (the same by default).
MAX_STEPS = 5_000_000

#: Length of the ``info`` vector of ``_kernels.integrate``.
N_INFO = 10

_METHOD_CODES = {"auto": K.METH_AUTO, "rodas4": K.METH_RODAS4, "dopri5": K.METH_DOPRI5}

_DUMMY = np.zeros(2)
_DUMMY.flags.writeable = False

#: Positions of the integrators' arguments they only read (spec, ep, the stroke arrays,
#: t_eval): always passed read-only, the others (prm too: the laws make modified copies of
#: it, which are writable) always writable, so that one compiled signature serves every call
#: (numba types read-only arrays apart and compiles each anew).
_READ_ONLY_ARGS = frozenset((0, 2, 4, 5, 6, 7, 8, 12))


def _one_signature(args: tuple) -> tuple:
    """``args`` with the read-only flags of :data:`_READ_ONLY_ARGS` (views or copies)."""
    out = list(args)
    for i, a in enumerate(out):
        if isinstance(a, np.ndarray):
            if i in _READ_ONLY_ARGS:
                if a.flags.writeable:
                    a = a.view()
                    a.flags.writeable = False
            elif not a.flags.writeable:
                a = a.copy()
            out[i] = a
    return tuple(out)


def supports(model) -> str | None:
    """Why the compiled engine cannot integrate ``model`` on the test machine, or None.

    Every DeviceModel is supported: its base equation is one of the compiled
    ones (checked when the model is built) and every add-on effect is compiled.

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> supports(get_model("inerter")) is None
    True
    """
    if not isinstance(model, DeviceModel):
        return f"not a DeviceModel: {type(model).__name__}"
    return None


def check_compiled(model: DeviceModel) -> DeviceModel:
    """Return ``model`` or raise ParameterError naming why the compiled engine cannot run it.

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> check_compiled(get_model("full")).name
    'full'
    """
    reason = supports(model)
    if reason is not None:
        raise ParameterError(f"engine 'compiled' cannot run this model: {reason}")
    return model


def _stroke_arrays(stroke):
    if isinstance(stroke, HarmonicStroke):
        sp = np.array([stroke.amplitude, stroke.omega, stroke.offset, stroke.phase])
        return 0, sp, _DUMMY, _DUMMY, _DUMMY, _DUMMY
    if isinstance(stroke, RecordedStroke):
        sa = stroke.acceleration
        if stroke.channels:  # measured input channels: one block per slot after a
            n = stroke.time.size  # (_stroke_kernels.channel_eval)
            blocks = [stroke.channels.get(c, np.zeros(n)) for c in DK.CHANNELS]
            sa = np.concatenate([sa] + blocks)
        return (1, np.zeros(4), stroke.time, stroke.displacement, stroke.velocity, sa)
    if isinstance(stroke, TwoFrequencyStroke):
        sp = np.array([stroke.offset, stroke.amplitude1, stroke.omega1, stroke.phase1,
                       stroke.amplitude2, stroke.omega2, stroke.phase2])
        return 2, sp, _DUMMY, _DUMMY, _DUMMY, _DUMMY
    if isinstance(stroke, FourierStroke):
        return 3, stroke.packed(), _DUMMY, _DUMMY, _DUMMY, _DUMMY
    raise ParameterError(
        f"engine 'compiled' needs a TwoFrequencyStroke, FourierStroke, HarmonicStroke or "
        f"RecordedStroke, got "
        f"{type(stroke).__name__}; use engine='scipy' for another stroke callable"
    )


def _floor_indices(model: DeviceModel, params: DeviceParams) -> tuple[int, int]:
    """Indices of the chamber pressures watched against the floor (as the Python path)."""
    if model.uses_bulk_law and params.bulk_law == "gholizadeh" and model.pressures is not None:
        names = model.state_names
        return names.index("p1"), names.index("p2")
    return -1, -1


def _atol(model, params, options) -> np.ndarray:
    return np.ascontiguousarray(options.atol_scale * model.state_scales(params), dtype=float)


def _method_code(options) -> int:
    """Kernel code of ``options.compiled_method``."""
    return _METHOD_CODES[options.compiled_method]


def _run(options, args: tuple, out: np.ndarray, info: np.ndarray) -> tuple[np.ndarray, bool]:
    """Run the compiled integrator on ``args`` (all but method, out, info).

    ``"auto"`` and ``"dopri5"`` run the explicit-only kernel first (half the
    compile time of the first call); if ``"auto"`` meets a stiff stretch
    there, the whole call is rerun with the kernel that holds RODAS4 too,
    which starts identically, so the answer does not depend on the route.
    Where the full kernel is already loaded in this process and the explicit
    one is not, ``"auto"`` runs the full kernel at once (the same answer,
    and no second kernel compiled on a first run).
    Returns the final state and whether the rerun happened.
    """
    meth = _method_code(options)
    args = _one_signature(args)
    plain = args[0][DK.S_EFFECTS] == 0  # spec: no effects, the base equation alone
    full = K.integrate_plain if plain else K.integrate
    explicit = K.integrate_explicit_plain if plain else K.integrate_explicit
    if meth == K.METH_RODAS4 or (meth == K.METH_AUTO and full.signatures
                                 and not explicit.signatures):
        # the full kernel is loaded and the explicit one is not: it gives the same answer
        # in one go, without compiling a second kernel (the first run's cost)
        return full(*args, meth, out, info), False
    x = explicit(*args, meth, out, info)
    if int(info[0]) != K.ST_STIFF:
        return x, False
    return full(*args, meth, out, info), True


def _fill_stats(stats: dict | None, options, info, rerun: bool) -> None:
    """Write the step counts of ``info`` into ``stats`` (if given)."""
    if stats is None:
        return
    steps = int(info[3])
    explicit = int(info[8])
    stats.update({"engine": "compiled", "method": options.compiled_method,
                  "steps": steps, "explicit_steps": explicit,
                  "rodas4_steps": steps - explicit, "switches_to_rodas4": int(info[9]),
                  "rerun_with_rodas4": rerun})


def _raise_status(model, options, info, t0, t1, max_steps: int) -> None:
    status = int(info[0])
    if status == K.ST_PRESSURE:
        raise PressureError(
            f"model {model.name!r}: a chamber pressure fell to the floor "
            f"{options.pressure_floor:g} Pa at t = {info[1]:.6g} s; the liquid-air law (eq. 2) "
            "is singular at p = 0. The device cavitates: reduce the stroke or frequency, raise "
            "the filling pressure p0, or add the 'cavitation' effect"
        )
    if status == K.ST_STEP_TOO_SMALL:
        raise ConvergenceError(
            f"model {model.name!r}: time integration failed between t = {t0:.6g} s and "
            f"{t1:.6g} s: step size fell below the round-off limit at t = {info[1]:.6g} s "
            f"(compiled engine, method {options.compiled_method!r})"
        )
    if status == K.ST_TOO_MANY_STEPS:
        raise ConvergenceError(
            f"model {model.name!r}: time integration failed between t = {t0:.6g} s and "
            f"{t1:.6g} s: more than {max_steps} steps (SolverOptions.max_steps "
            f"{options.max_steps}; compiled engine, method {options.compiled_method!r}, "
            f"stopped at t = {info[1]:.6g} s)"
        )


def march(model: DeviceModel, params: DeviceParams, stroke, x0, t0: float, t1: float, t_eval,
          options, max_step: float, *, h0: float = 0.0,
          stats: dict | None = None,
          max_steps: int | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Integrate one span with the compiled engine.

    Parameters
    ----------
    model, params, stroke
        As for :func:`liquidamp.coupled.testrig.simulate` (``model`` resolved).
    x0 : array
        Initial state.
    t0, t1 : float
        Time span [s].
    t_eval : array
        Sorted output times within [t0, t1] [s].
    options : SolverOptions
        ``rtol``, ``atol_scale``, ``pressure_floor``.
    max_step : float
        Largest step [s].
    h0 : float
        First step [s]; 0 picks one from the right-hand side.
    stats : dict, optional
        Filled in place with the step counts: ``steps`` (accepted and
        rejected), ``explicit_steps`` (Dormand-Prince), ``rodas4_steps``,
        ``switches_to_rodas4``, ``rerun_with_rodas4`` (the explicit-only
        kernel met a stiff stretch and the call was rerun) and the
        ``method`` used.
    max_steps : int, optional
        Most integrator steps (accepted and rejected) before the run is refused with
        ConvergenceError; the smaller of this and ``options.max_steps`` (default: the
        latter).

    Returns
    -------
    X : ndarray
        States at ``t_eval``, shape (n_states, len(t_eval)).
    x_end : ndarray
        State at ``t1``.
    h_last : float
        Step size the integrator would take next [s].

    Raises
    ------
    PressureError, ConvergenceError
        As the Python path.
    """
    spec, prm, ep = check_compiled(model).packed(params)
    kind, sp, st, sy, sv, sa = _stroke_arrays(stroke)
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    if t_eval.size and (t_eval[0] < t0 or t_eval[-1] > t1 or np.any(np.diff(t_eval) < 0)):
        raise ParameterError(f"t_eval must be sorted within [{t0:g}, {t1:g}] s")
    x0 = np.ascontiguousarray(x0, dtype=float)
    n = model.n_states
    if x0.shape != (n,):
        raise ParameterError(f"x0 must have {n} entries for model {model.name!r}, got "
                             f"shape {x0.shape}")
    fi1, fi2 = _floor_indices(model, params)
    limit = int(options.max_steps) if max_steps is None else min(int(max_steps),
                                                                int(options.max_steps))
    out = np.empty((n, t_eval.size))
    info = np.zeros(N_INFO)
    x_end, rerun = _run(options, (spec, prm, ep, kind, sp, st, sy, sv, sa, x0,
                                  float(t0), float(t1), t_eval, float(options.rtol),
                                  _atol(model, params, options), float(max_step), float(h0), fi1,
                                  fi2, float(options.pressure_floor), limit, 0.0, 0, 0),
                        out, info)
    _fill_stats(stats, options, info, rerun)
    _raise_status(model, options, info, t0, t1, limit)
    if not (np.all(np.isfinite(out)) and np.all(np.isfinite(x_end))):
        raise ConvergenceError(f"model {model.name!r}: non-finite state in time integration")
    return out, x_end, float(info[2])


def steady_loop(model: DeviceModel, params: DeviceParams, stroke: HarmonicStroke, x0, options,
                *, stats: dict | None = None):
    """Periodic steady state by marching cycles in compiled code (the march alone).

    Returns ``(X, cycles, residual)``: the last period at
    ``options.samples_per_period`` samples (end point excluded), the cycles marched and
    the estimated remaining relative change of the force; raises ConvergenceError after
    ``options.max_cycles`` (:func:`march_cycles` does not; the route that always arrives
    is :func:`liquidamp.coupled.periodic.periodic_state`).
    """
    X, cycles, residual, change, converged = march_cycles(model, params, stroke, x0, options,
                                                          stats=stats)
    if not converged:
        raise ConvergenceError(
            f"model {model.name!r}: no periodic steady state after {options.max_cycles} cycles "
            f"at {stroke.describe()}; last relative change per "
            f"cycle {change:.2e}, estimated remaining {residual:.2e} (allowed "
            f"{options.steady_tol:g}); raise max_cycles or steady_tol"
        )
    return X[:, :-1], cycles, residual


def march_cycles(model: DeviceModel, params: DeviceParams, stroke, x0, options, *,
                 stats: dict | None = None, grid=None):
    """March whole cycles in compiled code until the steady-state rule accepts or
    ``options.max_cycles`` have passed; never raises for non-convergence.

    ``grid`` (optional): sorted times within one period [s], the last at the
    period's end, at which the states are returned and the force waveforms
    compared (default ``options.samples_per_period`` + 1 uniform samples).

    Returns
    -------
    X : ndarray
        States over the last period marched at ``grid``, both ends included,
        shape (n_states, len(grid)).
    cycles : int
        Cycles marched.
    residual : float
        Estimated remaining relative change of the force waveform [-] (inf before
        two cycles).
    change : float
        Last relative change of the force waveform per cycle [-].
    converged : bool
        Whether the rule of :func:`liquidamp.coupled.testrig.steady_state` accepted.

    Raises
    ------
    PressureError, ConvergenceError
        A pressure at the floor or a failed step (as :func:`march`).
    """
    spec, prm, ep = check_compiled(model).packed(params)
    T = stroke.period
    N = options.samples_per_period
    n = model.n_states
    grid = (np.arange(N + 1) * (T / N) if grid is None
            else np.ascontiguousarray(grid, dtype=float))
    out = np.empty((n, grid.size))
    info = np.zeros(N_INFO)
    kind, sp, st, sy, sv, sa = _stroke_arrays(stroke)
    fi1, fi2 = _floor_indices(model, params)
    # the same compiled entry points as march, in their periodic mode
    _, rerun = _run(options, (spec, prm, ep, kind, sp, st, sy, sv, sa,
                              np.ascontiguousarray(x0, dtype=float), 0.0, float(T), grid,
                              float(options.rtol), _atol(model, params, options),
                              float(options.max_step_fraction * step_period(stroke)), 0.0,
                              fi1, fi2,
                              float(options.pressure_floor), int(options.max_steps),
                              float(options.steady_tol), int(options.min_cycles),
                              max(int(options.max_cycles), 1)), out, info)
    _fill_stats(stats, options, info, rerun)
    status = int(info[0])
    cycles = int(info[5])
    converged = status != K.ST_NOT_CONVERGED
    if converged:
        _raise_status(model, options, info, cycles * T, (cycles + 1) * T,
                      int(options.max_steps))
    if not np.all(np.isfinite(out)):
        raise ConvergenceError(f"model {model.name!r}: non-finite state in time integration")
    return out, cycles, float(info[6]), float(info[7]), converged


def step_period(stroke) -> float:
    """The period that sizes the largest step of a run under ``stroke`` [s].

    The faster component's period for a :class:`TwoFrequencyStroke`, the
    period of a harmonic stroke.

    Examples
    --------
    >>> step_period(TwoFrequencyStroke(0.002, 4.2, 0.0005, 1.26)) == 1 / 4.2
    True
    """
    if isinstance(stroke, TwoFrequencyStroke):
        return stroke.shortest_period
    return stroke.period


def warm_up() -> float:
    """Compile (or load from the cache) the device kernels; return the seconds it took.

    Both integrator kernels are prepared: the explicit-only one that a
    non-stiff ``"auto"`` run uses and the one with RODAS4.

    Examples
    --------
    >>> warm_up() >= 0.0
    True
    """
    import time

    from liquidamp.device.models import get_model
    from liquidamp.device.params import DeviceParams  # noqa: F401  (type only)
    from liquidamp.device.presets import preset
    from liquidamp.options import DEFAULT_OPTIONS

    t = time.perf_counter()
    model = get_model("full")
    p = preset("reference")
    s = HarmonicStroke(0.001, 3.0)
    for method in ("auto", "rodas4"):  # the explicit-only kernel and the full one
        march(model, p, s, model.initial_state(p, 0.0), 0.0, 0.01, np.array([0.01]),
              DEFAULT_OPTIONS.replace(compiled_method=method), 0.01)
    opts = DEFAULT_OPTIONS.replace(samples_per_period=16, min_cycles=1, max_cycles=2,
                                   steady_tol=1e-1)
    try:
        steady_loop(model, p, s, model.initial_state(p, 0.0), opts)
    except ConvergenceError:
        pass
    return time.perf_counter() - t
