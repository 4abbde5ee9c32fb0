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

from dataclasses import dataclass

import numpy as np

from liquidamp.coupled import _kernels as K
from liquidamp.coupled import _rotor_kernel as RK
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

__all__ = ["COMPILED_MODELS", "supports", "check_compiled", "march", "RotorRun",
           "simulate_rotor", "simulate_blade", "FlowRun", "second_order_flow", "steady_loop",
           "march_cycles",
           "step_period", "warm_up"]

#: Registry names of the base models the compiled engine runs: all of them, with any
#: add-on effects (the physics is :mod:`liquidamp.device.kernels`, shared with scipy).
COMPILED_MODELS = tuple(BASES)

#: Largest number of integration steps (accepted and rejected) in one call.
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
        return (1, np.zeros(4), stroke.time, stroke.displacement, stroke.velocity,
                stroke.acceleration)
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


def _raise_status(model, options, info, t0, t1) -> None:
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
            f"{t1:.6g} s: more than {MAX_STEPS} steps (compiled engine, method "
            f"{options.compiled_method!r}, stopped at "
            f"t = {info[1]:.6g} s)"
        )


def march(model: DeviceModel, params: DeviceParams, stroke, x0, t0: float, t1: float, t_eval,
          options, max_step: float, *, h0: float = 0.0,
          stats: dict | None = None) -> tuple[np.ndarray, np.ndarray, float]:
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
    out = np.empty((n, t_eval.size))
    info = np.zeros(N_INFO)
    x_end, rerun = _run(options, (spec, prm, ep, kind, sp, st, sy, sv, sa, x0,
                                  float(t0), float(t1), t_eval, float(options.rtol),
                                  _atol(model, params, options), float(max_step), float(h0), fi1,
                                  fi2, float(options.pressure_floor), MAX_STEPS, 0.0, 0, 0),
                        out, info)
    _fill_stats(stats, options, info, rerun)
    _raise_status(model, options, info, t0, t1)
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
                              float(options.pressure_floor), MAX_STEPS,
                              float(options.steady_tol), int(options.min_cycles),
                              max(int(options.max_cycles), 1)), out, info)
    _fill_stats(stats, options, info, rerun)
    status = int(info[0])
    cycles = int(info[5])
    converged = status != K.ST_NOT_CONVERGED
    if converged:
        _raise_status(model, options, info, cycles * T, (cycles + 1) * T)
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


# ------------------------------------------------------- rotor + devices
@dataclass(frozen=True, eq=False)
class RotorRun:
    """Time response of the rotor with devices from :func:`simulate_rotor`.

    Attributes
    ----------
    time : ndarray
        Output times reached [s].
    states : ndarray, shape (n_states, n_time)
        Coupled states, layout of ``system`` (host then each device).
    system : CoupledSystem
        The coupled system (layout, names, ports).
    status : str
        ``completed``, ``stroke_limit`` or ``pressure_floor`` (stopped at the
        end of the step where it happened).
    steps, rhs_evaluations : int
        Accepted and rejected steps; right-hand-side evaluations.
    """

    time: np.ndarray
    states: np.ndarray
    system: object
    status: str
    steps: int
    rhs_evaluations: int

    @property
    def host_states(self) -> np.ndarray:
        """Rotor states (``rotor.state_names``) [rad, m, rad/s, m/s]."""
        return self.states[: self.system.host.nstates]


def _dop853_tables():
    from liquidamp.coupled._dop853 import tables

    return tables()


def simulate_rotor(rotor, Omega: float, device, t_end: float, x0=None, *, inoperative=(),
                   inputs=(), t_eval=None, samples_per_second: float | None = None,
                   options=None, max_step: float | None = None,
                   max_steps: int = MAX_STEPS) -> RotorRun:
    """Compiled time response of a rotor with a device on each blade (rotating frame).

    The same system and conventions as
    ``simulate_coupled(rotor_system(rotor, Omega, device, inoperative=..., inputs=...), t_end,
    x0, strict=False, energy=False)``, integrated by compiled DOP853 (scipy's
    coefficients and step-size control, same ``rtol``, same ``atol``:
    ``atol_scale`` times the largest initial host state for the rotor and
    times the device ``state_scales`` for the devices, same largest step
    ``period/20``).  Output between steps by DOP853's 7th-order continuous
    extension, as scipy's dense output.

    Parameters
    ----------
    rotor : GroundResonanceRotor
    Omega : float
        Rotor speed > 0 [rad/s].
    device : Device or mapping
        As :func:`~liquidamp.coupled.assembly.rotor_system`; the models must
        be compiled ones (:data:`COMPILED_MODELS`) without acceleration input.
    t_end : float
        End time [s].
    x0 : array or mapping, optional
        As :func:`~liquidamp.coupled.assembly.simulate_coupled`.
    inputs : sequence of HarmonicInput
        External inputs (``moment_k`` [N m], hub forces [N]), as
        :func:`~liquidamp.coupled.assembly.rotor_system`.
    options : SolverOptions, optional
        ``rtol``, ``atol_scale``, ``pressure_floor`` (default: the ``"rotor"``
        preset of :data:`liquidamp.options.PRESETS`, rtol 1e-7; ``method`` and
        ``engine`` are ignored).

    Returns
    -------
    RotorRun
    """
    from liquidamp.coupled.system import rotor_system

    system = rotor_system(rotor, Omega, device, inoperative=inoperative, inputs=inputs)
    # the origin's rotor has the blades' own lag dampers removed where a device is attached
    # or failed, as the host
    return _simulate_second_order(system.origin.structure, Omega, system, t_end, x0,
                                  t_eval, samples_per_second, options, max_step, max_steps)


def simulate_blade(blade, Omega: float, device, t_end: float, x0=None, *, inputs=(),
                   t_eval=None, samples_per_second: float | None = None, options=None,
                   max_step: float | None = None, max_steps: int = MAX_STEPS) -> RotorRun:
    """Compiled time response of a blade in lead-lag with a device on its port.

    The system of :func:`~liquidamp.coupled.assembly.blade_system` (same
    arguments), integrated by the kernel of :func:`simulate_rotor` (the
    blade is a second-order host with constant coefficients): the same
    conventions, default options (the ``"rotor"`` preset) and largest step
    (1/20 of the revolution 2 pi/Omega).

    Parameters
    ----------
    blade : ArticulatedBlade
    Omega : float
        Rotor speed > 0 [rad/s].
    device : Device
    t_end : float
        End time [s].
    x0 : array or mapping, optional
        As :func:`~liquidamp.coupled.assembly.simulate_coupled`.
    inputs : sequence of HarmonicInput
        External inputs (``moment`` [N m]).

    Returns
    -------
    RotorRun

    Examples
    --------
    >>> import math
    >>> from liquidamp.coupled.assembly import viscous
    >>> from liquidamp.coupled.inputs import HarmonicInput
    >>> from liquidamp.structure.hostio import load_blade
    >>> b = load_blade("hammond1974").replace(lag_damping=0.0)
    >>> W, M = 26.0, HarmonicInput("moment", 26.0, sin_amplitude=1000.0)
    >>> r = simulate_blade(b, W, viscous(2e4), 30.0, inputs=[M], t_eval=[30.0])
    >>> zeta, rate = r.host_states[:, -1]
    >>> # 1/rev response once the transient is gone: |zeta| = M / |K - I W^2 + i W c a^2|
    >>> z = M.amplitude / abs(b.lag_stiffness(W) - b.inertia * W**2 + 1j * W * 2e4 * 0.25**2)
    >>> round(math.hypot(zeta, rate / W) / z, 6)
    1.0
    """
    from liquidamp.coupled.system import blade_system

    system = blade_system(blade, Omega, device, inputs=inputs)
    return _simulate_second_order(blade, Omega, system, t_end, x0, t_eval, samples_per_second,
                                  options, max_step, max_steps)


def _kernel_arrays(structure, W, system, X0, opts):
    """The kernel's arrays for ``system`` (host ``structure`` at speed ``W``) from ``X0``."""
    nh = system.host.nstates
    # the host's equations come from structure/: M, C, K as first harmonics of the azimuth
    MH = np.stack(structure.harmonic_second_order(W))
    G, Cout = structure.force_matrix(), structure.output_matrix()
    ins, outs = structure.input_names, structure.output_names
    # sparse triplets: the kernel visits the non-zero entries only
    HI = np.ascontiguousarray(np.argwhere(MH != 0.0), dtype=np.int64).reshape(-1, 3)
    HV = np.ascontiguousarray(MH[MH != 0.0])
    trip = []
    for j, port in enumerate(system.ports):
        for kind, row in ((0, Cout[outs.index(port.stroke_output)]),
                          (1, Cout[outs.index(port.rate_output)]),
                          (2, G[:, ins.index(port.force_input)])):
            trip += [(kind, j, int(i), float(row[i])) for i in np.flatnonzero(row)]
    PI = np.array([t[:3] for t in trip], dtype=np.int64).reshape(-1, 3)
    PV = np.array([t[3] for t in trip], dtype=float)
    # external inputs as harmonic generalized forces: coordinate, (mean, cos, sin, omega)
    ext = []
    for u in system.inputs:
        col = G[:, ins.index(u.input)]
        ext += [(int(i), col[i] * u.mean, col[i] * u.cos_amplitude, col[i] * u.sin_amplitude,
                 u.omega) for i in np.flatnonzero(col)]
    UI = np.array([e[0] for e in ext], dtype=np.int64)
    UV = np.array([e[1:] for e in ext], dtype=float).reshape(-1, 4)
    nd = len(system.devices)
    doff = np.zeros(nd + 1, np.int64)
    DSPEC = np.zeros((nd, DK.N_SPEC), np.int64)
    PRM = np.zeros((nd, DK.N_PRM))
    DEP = np.zeros((nd, DK.N_EP + max([d.n_states for d in system.devices] + [0])))
    fi = np.full((nd, 2), -1, np.int64)
    lim = np.empty(nd)
    atol = [np.full(nh, opts.atol_scale * max(float(np.max(np.abs(X0[:nh]))), 1e-12))]
    for j, d in enumerate(system.devices):
        if d.model.uses_acceleration:
            raise ParameterError(
                f"simulate_rotor: device {d.label!r} ({d.model.name}) uses the stroke "
                "acceleration, which the compiled rotor kernel does not couple; use the scipy "
                "engine (simulate_coupled)")
        spec, prm, ep = check_compiled(d.model).packed(d.params)
        DSPEC[j], PRM[j], DEP[j, :ep.size] = spec, prm, ep
        doff[j + 1] = doff[j] + d.n_states
        lim[j] = d.stroke_limit
        names = d.model.state_names
        if d.model.pressures is not None and d.model.uses_bulk_law and "p1" in names \
                and "p2" in names and d.params.bulk_law == "gholizadeh":
            fi[j] = names.index("p1"), names.index("p2")
        atol.append(opts.atol_scale * np.asarray(d.model.state_scales(d.params), float))
    atol = np.ascontiguousarray(np.concatenate(atol))
    for a in (DSPEC, DEP):  # read-only as packed()'s: one signature of the device kernels
        a.flags.writeable = False
    return (HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP, fi, lim), atol


def _integrate(W, arrays, pfloor, X0, nx, T_end, t_eval, rtol, atol, hmax, max_steps):
    out = np.zeros((X0.size, t_eval.size))
    info = np.zeros(5)
    RK.rotor_integrate(W, *arrays, float(pfloor), X0, int(nx), float(T_end), t_eval,
                       float(rtol), atol, float(hmax), int(max_steps), *_dop853_tables(), out,
                       info)
    status = int(info[0])
    if status in (K.ST_STEP_TOO_SMALL, K.ST_TOO_MANY_STEPS):
        raise ConvergenceError(
            f"compiled rotor integration failed at t = {info[1]:.6g} s ("
            + ("step size below round-off" if status == K.ST_STEP_TOO_SMALL else
               f"more than {max_steps} steps") + ")")
    name = {K.ST_OK: "completed", RK.ST_STROKE_LIMIT: "stroke_limit",
            K.ST_PRESSURE: "pressure_floor"}[status]
    return out, name, int(info[2]), int(info[3]), int(info[4])


def _simulate_second_order(structure, Omega, system, t_end, x0, t_eval, samples_per_second,
                           options, max_step, max_steps) -> RotorRun:
    """Run ``system`` (host ``structure``: its harmonic second-order form) on the kernel."""
    import math

    from liquidamp.options import resolve_options

    opts = resolve_options(options, "rotor")
    T_end = float(t_end)
    if not T_end > 0.0:
        raise ParameterError(f"t_end must be > 0 [s], got {t_end!r}")
    W = float(Omega)
    if x0 is not None and not isinstance(x0, dict) and np.size(x0) == system.n_states:
        X0 = np.asarray(x0, float).reshape(-1).copy()
    else:
        X0 = np.asarray(system.initial_state(x0), float)
    arrays, atol = _kernel_arrays(structure, W, system, X0, opts)
    period = 2.0 * math.pi / W
    if t_eval is None:
        rate = samples_per_second or 64.0 / period
        t_eval = np.linspace(0.0, T_end, int(math.ceil(T_end * rate)) + 1)
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    hmax = period / 20.0 if max_step is None else float(max_step)
    out, name, steps, nfev, m = _integrate(W, arrays, opts.pressure_floor, X0, X0.size, T_end,
                                           t_eval, opts.rtol, atol, hmax, max_steps)
    return RotorRun(t_eval[:m], out[:, :m], system, name, steps, nfev)


@dataclass(frozen=True, eq=False)
class FlowRun:
    """One compiled run of a second-order host with devices, optionally with Phi.

    Attributes
    ----------
    time : ndarray
        Output times [s].
    states : ndarray, shape (n, len(time))
        Coupled states there.
    x_end : ndarray
        State at ``t_end``.
    monodromy : ndarray or None
        Phi(t_end) of the variational equations, Phi(0) = I (unscaled) [-].
    status : str
        ``completed``, ``stroke_limit`` or ``pressure_floor``.
    steps, rhs_evaluations : int
    """

    time: np.ndarray
    states: np.ndarray
    x_end: np.ndarray
    monodromy: np.ndarray | None
    status: str
    steps: int
    rhs_evaluations: int


def second_order_flow(system, x0, t_end: float, *, t_eval=None, monodromy: bool = False,
                      scales=None, options=None, phi_atol: float = 1e-12,
                      max_step: float | None = None, max_steps: int = MAX_STEPS) -> FlowRun:
    """Flow of a system built by ``rotor_system``/``blade_system`` on the compiled kernel.

    With ``monodromy`` the variational equations Phi' = J(t, x) Phi, Phi(0) = I,
    are integrated with the state (the kernel's
    ``rotor_variation``: the host's matrices and force map, each device's
    Jacobian from the compiled ``model_jac`` and central differences of its
    compiled force and right-hand side in stroke and rate); the external
    inputs do not enter J.

    Parameters
    ----------
    system : CoupledSystem
        From :func:`~liquidamp.coupled.assembly.rotor_system` or
        :func:`~liquidamp.coupled.assembly.blade_system` (``compiled_support``
        None).
    x0 : array
        Coupled state at t = 0 (length ``system.n_states``).
    t_end : float
        End time > 0 [s].
    t_eval : array, optional
        Output times within [0, t_end] [s] (default: the end only).
    monodromy : bool
        Integrate Phi too.
    scales : array, optional
        State magnitudes; Phi_ik has the absolute tolerance ``phi_atol`` scales_i /
        scales_k (default: the state tolerances over ``atol_scale``).
    options : SolverOptions, optional
        ``rtol``, ``atol_scale``, ``pressure_floor`` (default the ``"decay"`` preset).
    phi_atol : float
        Absolute tolerance of Phi in scaled coordinates [-].
    max_step : float, optional
        Largest step [s] (default 1/20 of 2 pi/Omega).

    Returns
    -------
    FlowRun

    Examples
    --------
    >>> import math
    >>> from liquidamp.coupled.assembly import blade_system, viscous
    >>> from liquidamp.structure.hostio import load_blade
    >>> b = load_blade("hammond1974").replace(lag_damping=0.0)
    >>> sys_ = blade_system(b, 26.0, viscous(2e4))
    >>> r = second_order_flow(sys_, [0.01, 0.0], 0.5, monodromy=True)
    >>> A = sys_.host.A(0.0) + sys_.force_matrix(0.0) * 2e4 @ sys_.rate_matrix
    >>> from scipy.linalg import expm
    >>> bool(np.allclose(r.monodromy, expm(A * 0.5), rtol=0, atol=1e-9))
    True
    """
    import math

    from liquidamp.coupled.system import _compiled_origin
    from liquidamp.options import resolve_options

    o = _compiled_origin(system, check_compiled)
    opts = resolve_options(options, "decay")
    T_end = float(t_end)
    if not T_end > 0.0:
        raise ParameterError(f"t_end must be > 0 [s], got {t_end!r}")
    X0 = np.asarray(x0, float).reshape(-1)
    n = system.n_states
    if X0.size != n or not np.all(np.isfinite(X0)):
        raise ParameterError(f"x0 needs {n} finite values")
    arrays, atol = _kernel_arrays(o.structure, o.Omega, system, X0, opts)
    t_eval = np.ascontiguousarray([T_end] if t_eval is None else t_eval, dtype=float)
    if t_eval.size and (t_eval[0] < 0.0 or t_eval[-1] > T_end or np.any(np.diff(t_eval) < 0)):
        raise ParameterError(f"t_eval must be sorted within [0, {T_end:g}] s")
    hmax = 2.0 * math.pi / o.Omega / 20.0 if max_step is None else float(max_step)
    if monodromy:
        S = atol / opts.atol_scale if scales is None else np.asarray(scales, float)
        X0 = np.concatenate([X0, np.eye(n).ravel()])
        atol = np.concatenate([atol, (phi_atol * S[:, None] / S[None, :]).ravel()])
    X0 = np.ascontiguousarray(X0)
    te = np.ascontiguousarray(np.union1d(t_eval, [T_end]))
    out, name, steps, nfev, m = _integrate(o.Omega, arrays, opts.pressure_floor, X0, n, T_end,
                                           te, opts.rtol, np.ascontiguousarray(atol), hmax,
                                           max_steps)
    keep = np.isin(te[:m], t_eval)
    x_end = out[:n, m - 1].copy()
    Phi = out[n:, m - 1].reshape(n, n).copy() if monodromy and name == "completed" else None
    if not np.all(np.isfinite(out[:, :m])):
        raise ConvergenceError("compiled flow: non-finite state")
    return FlowRun(te[:m][keep], out[:n, :m][:, keep], x_end, Phi, name, steps, nfev)
