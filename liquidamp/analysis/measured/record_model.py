"""Drive a device model with a measured record; the force error against it.

:func:`simulate_record` runs any device model under a record's stroke
(:class:`~liquidamp.analysis.measured.records.Record`) about its mean (the LVDT
zero is arbitrary; the mean stroke is taken as the mid-position where the chambers
hold V01 and V02; an effect on the absolute stroke, ``gas_charge``, is given the mean
back and a gas-charged device's chambers follow the absolute stroke at the charge's level:
:func:`~liquidamp.device.effects_damper.on_absolute_stroke`); :func:`nrmse` is the
normalized RMS force error used by the calibration; :func:`integrate` is the synthetic
generator's LSODA march under any scalar stroke.

The periodic steady state, not a pre-roll: a periodic record
(:attr:`Record.periodic`) is simulated on the periodic orbit of its cycle.  Its stroke is
its Fourier series (:func:`record_stroke`: the averaged record's fit, or the least-squares
fit of the displacement with the fundamental refined), so velocity and acceleration are
exact (the 21-point Savitzky-Golay velocity is 1.3 % low at 40 samples per cycle); the
orbit comes from :func:`liquidamp.coupled.periodic.periodic_state` (march while it
converges, Newton shooting with the invariants of the device at rest where it stalls), on
the phases of the samples the record (or its conditioning) needs.  Before, the model was
pre-rolled over the first cycle a fixed number of times from rest: with the true
parameters of a slowly settling device (device_a, 5 Hz) NRMSE 0.044 against a noise floor
of 0.0017; now within 1.03x of the floor.  A warm start (``x0``, e.g. the previous
response's ``states[:, 0]``) is moved onto the invariants of rest and only shortens the
march.  A record whose stroke is not periodic (tapered or broadband) has no steady state
to approach: it runs from rest at its first sample under the Savitzky-Golay stroke
(:meth:`Record.stroke`; its start-up transient, a few relaxation times T_D, is part of
the fit), and the response states the filter's velocity gain at the record's frequency
(:func:`~liquidamp.analysis.measured.record_quality.velocity_gain`).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B-C.
.. [2] A. Savitzky, M. J. E. Golay, Anal. Chem. 36(8), 1964.
"""

from __future__ import annotations

import numpy as np

from liquidamp.analysis.measured.record_quality import velocity_gain
from liquidamp.analysis.measured.records import Record
from liquidamp.coupled.engines import TestRig, engine_for
from liquidamp.coupled.periodic import ROUTES, ShootingOptions, periodic_state
from liquidamp.coupled.testrig import DeviceResponse
from liquidamp.device.effects_damper import on_absolute_stroke
from liquidamp.device.models import DeviceModel, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError, check_choice
from liquidamp.options import SolverOptions, resolve_options
from liquidamp.structure.testmachine import FourierStroke, RecordedStroke

__all__ = ["simulate_record", "record_stroke", "integrate", "nrmse"]


#: Newton iterations the record simulation allows the shooting (the march's last cycle,
#: flagged, where it does not arrive: a fit must not stall on one hard point).
RECORD_SHOOTING_ITER = 12


def integrate(model: DeviceModel, params: DeviceParams, stroke, t_eval, x0, *,
              rtol: float, atol_scale: float, hmax: float = 0.0) -> np.ndarray:
    """Integrate ``model`` under any scalar ``stroke(t) -> (y, v, a)`` with LSODA (odeint).

    The synthetic-record generator's integrator
    (:func:`liquidamp.analysis.measured.synthetic.synthetic_record`): a third
    algorithm (LSODA's Adams/BDF switching) on the same compiled equations,
    for a stroke callable neither engine takes (harmonic distortion, noise);
    records made with it test the fitting, which runs on the engines
    (:func:`simulate_record`).  Returns the states at ``t_eval``, shape
    (n_states, len(t_eval)).

    Parameters
    ----------
    model : DeviceModel
        The model (any effects).
    params : DeviceParams
        Its parameters.
    stroke : callable
        ``stroke(t) -> (y [m], v [m/s], a [m/s^2])`` for scalar t [s].
    t_eval : array
        Output times [s].
    x0 : array
        Initial state.
    rtol, atol_scale : float
        Relative tolerance and absolute tolerance per state scale [-].
    hmax : float
        Largest step [s] (0: unbounded).

    Raises
    ------
    ConvergenceError
        If LSODA reports failure or the states are not finite.
    """
    from scipy.integrate import odeint

    rhs = model.rhs
    jac = model.jacobian
    t_eval = np.asarray(t_eval, float)
    if model.n_states == 0:
        return np.zeros((0, t_eval.size))

    def f(t, x):
        return rhs(t, x, stroke(t), params)

    dfun = None
    if jac is not None:
        def dfun(t, x):
            return jac(t, x, stroke(t), params)

    atol = atol_scale * np.asarray(model.state_scales(params), float)
    X, info = odeint(f, np.asarray(x0, float), t_eval, Dfun=dfun, tfirst=True, rtol=rtol,
                     atol=atol, hmax=hmax, mxstep=50000, full_output=True)
    if info.get("message") != "Integration successful." or not np.all(np.isfinite(X)):
        raise ConvergenceError(
            f"model {model.name!r}: time integration failed between t = {t_eval[0]:.6g} s and "
            f"{t_eval[-1]:.6g} s: {info.get('message')}")
    return X.T


def simulate_record(model, params: DeviceParams, record: Record, *,
                    options: SolverOptions | None = None, preroll: int | None = None,
                    x0=None, route: str = "auto") -> DeviceResponse:
    """Drive ``model`` with the record's stroke; the model force at the record's samples.

    A periodic record (:attr:`Record.periodic`) is simulated on the periodic
    steady state of its cycle (module docstring): its stroke is its Fourier
    series (:class:`~liquidamp.structure.testmachine.FourierStroke`: the
    averaged record's fit, or the least-squares fit of the record's
    displacement), the orbit comes from
    :func:`liquidamp.coupled.testrig.steady_state` (march while it converges,
    Newton shooting with the invariants of the device at rest where it stalls),
    and the force at every sample is the orbit's at that sample's phase.  A
    record that is not periodic runs from rest at its first sample under the
    Savitzky-Golay stroke (:meth:`Record.stroke`), whose velocity gain the
    response states.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model or one composed with :func:`liquidamp.device.effects.with_effects`.
    params : DeviceParams
        Device parameters.
    record : Record
        The measured record.
    options : SolverOptions, optional
        ``rtol``, ``atol_scale``, ``max_step_fraction``, ``pressure_floor``,
        ``steady_tol``, ``min_cycles``, ``max_cycles``; the engine named by
        ``options.engine`` runs the model with any effects
        (:mod:`liquidamp.coupled.engines`).  Default: the ``"default"`` preset of
        :data:`liquidamp.options.PRESETS` (the fitting functions pass ``"fit"``).
    preroll : int, optional
        Deprecated and ignored: a periodic record starts on its periodic orbit, one
        that is not periodic from rest (kept so that existing calls run).
    x0 : array, optional
        Periodic record: a first guess of the orbit's state at the record's first
        sample (e.g. ``previous.states[:, 0]`` of a response for nearby parameters;
        it is first moved onto the invariants of the device at rest, which select
        the orbit).  Otherwise: the initial state (default rest at p0).
    route : {"auto", "march", "shooting"}
        Route to the periodic orbit (:func:`liquidamp.coupled.periodic.periodic_state`).

    Returns
    -------
    DeviceResponse
        ``time`` = record time, ``force`` the model's load-cell force [N] (for a record
        made by :func:`liquidamp.analysis.measured.conditioning.condition`: computed at
        the times its conditioning needs and conditioned as the record's force was),
        ``states[:, 0]`` the state at the record's first sample, ``status =
        "completed"``; ``message`` and ``solver_stats`` state the drive (``"stroke"``:
        ``"fourier"`` with ``"harmonics"``, or ``"savitzky-golay"``; ``"velocity_gain"``
        [-]: 1 for the Fourier series,
        :func:`~liquidamp.analysis.measured.record_quality.velocity_gain`
        at the record's frequency for the Savitzky-Golay velocity) and, for a periodic
        record, the route to the orbit (``"route"``, ``"march_cycles"``,
        ``"shooting_runs"``); warnings for pressures below the vapour pressure.

    Raises
    ------
    PressureError
        A chamber pressure reached ``options.pressure_floor`` (models using
        the pressure-dependent bulk law), as in testrig.
    ConvergenceError
        The integration failed, or no periodic orbit was found.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> t = np.arange(0, 1.0, 0.005)
    >>> rec = Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), 0 * t)
    >>> r = simulate_record("full", preset("paper_calibrated"), rec)
    >>> r.force.shape == rec.time.shape, bool(abs(r.force).max() > 300)
    (True, True)
    >>> r.solver_stats["stroke"], r.solver_stats["velocity_gain"]
    ('fourier', 1.0)
    """
    options = resolve_options(options, "default")
    if not isinstance(params, DeviceParams):
        raise ParameterError(f"params must be DeviceParams, got {type(params).__name__}")
    # an effect on the absolute stroke (gas_charge) gets the record's mean stroke back, and
    # a gas-charged device's chambers sit on the absolute stroke at the charge's level
    model, params = on_absolute_stroke(get_model(model), params, record.offset)
    check_choice("periodic-orbit route", route, ROUTES)
    model.check_params(params)
    cond = record.meta.get("conditioning")
    if cond is not None and not cond.changed:
        cond = None
    if record.periodic:
        return _simulate_periodic(model, params, record, cond, options, x0, route)
    # a conditioned record (liquidamp.analysis.measured.conditioning) states the stroke the
    # model is driven by: the record's over its whole span, ends and all
    stroke = record.stroke() if cond is None else RecordedStroke(*cond.model_stroke())
    _check_reach(stroke.max_abs, params)
    t = record.time
    y0 = float(stroke.displacement[0])
    x = model.initial_state(params, y0) if x0 is None else np.asarray(x0, float)
    # one driver for both engines (liquidamp.coupled.engines): the device on the test machine
    # under the recorded stroke.  A bounded step: a state that rests while the input moves
    # (freeplay in its gap, a closed cavity) gives zero derivatives at the start, and an
    # unbounded first step could jump over the whole record without seeing the contact
    rig = TestRig(model, params, stroke)
    engine = engine_for(rig, options)
    max_step = max(options.max_step_fraction, 1e-4) * record.period
    gain = velocity_gain(record.frequency, record.sampling_rate, record.window, record.order)
    stats: dict = {"stroke": "savitzky-golay", "velocity_gain": gain}
    note = (f"Savitzky-Golay velocity ({record.window} points, order {record.order}), gain "
            f"{gain:.4f} at {record.frequency:.4g} Hz")

    def run(t_eval, xs):
        if not model.n_states:
            return np.zeros((0, t_eval.size))
        return engine.march(rig, xs, float(t_eval[0]), float(t_eval[-1]), t_eval, options,
                            max_step, stats)

    if cond is not None:
        # the model force conditioned as the record's was
        tf, at_record = cond.model_times(t)
        Xf = run(tf, x)
        uf = stroke(tf)
        ff = np.broadcast_to(np.asarray(model.force(tf, Xf, uf, params), float), tf.shape)
        X = np.ascontiguousarray(Xf[:, at_record])
        return _response(model, params, t, X, stroke(t), options, stats,
                         force=cond.model_force(ff), note=note)
    X = run(t, x)
    u = (stroke.displacement, stroke.velocity, stroke.acceleration)
    return _response(model, params, t, X, u, options, stats, note=note)


def _check_reach(reach: float, params: DeviceParams) -> None:
    if reach >= params.stroke_limit:
        raise ParameterError(
            f"record stroke reaches |y| = {reach:.4g} m about its mean, past the "
            f"chamber end at {params.stroke_limit:.4g} m (V0/A_p)")


def record_stroke(record: Record):
    """The exact periodic stroke of a periodic record about its mean: a
    :class:`~liquidamp.structure.testmachine.FourierStroke` in the record's own time.

    An averaged record (:func:`liquidamp.analysis.measured.conditioning.condition`)
    gives the fit its conditioning made; otherwise the displacement is fitted
    (:meth:`FourierStroke.fit`, the harmonics above 4 standard errors, the
    fundamental refined), once per record (kept in ``record.meta``).

    Raises
    ------
    ParameterError
        For a record that is not periodic.

    Examples
    --------
    >>> t = np.arange(0, 2.0, 0.005)
    >>> s = record_stroke(Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), 0 * t))
    >>> round(s.amplitude * 1e3, 6), s.offset, s.harmonics
    (3.0, 0.0, 1)
    """
    if not record.periodic:
        raise ParameterError(f"{record.label}: a stroke that is not periodic has no Fourier "
                             "series; use Record.stroke() (Savitzky-Golay)")
    cond = record.meta.get("conditioning")
    s = cond.fourier_stroke() if cond is not None else None
    if s is None:
        key = ("fourier_stroke", float(record.time[0]), record.time.size, record.frequency)
        cached = record.meta.get("_fourier_stroke")
        if cached is not None and cached[0] == key:
            return cached[1]
        s = FourierStroke.fit(record.time, record.displacement, record.frequency,
                              refine_frequency=True)
        s = FourierStroke(s.frequency, s.sine, s.cosine, 0.0, s.t0)
        record.meta["_fourier_stroke"] = (key, s)  # fitted once per record
    return s


def _simulate_periodic(model, params, record, cond, options, x0, route):
    """The periodic record on its periodic orbit (see :func:`simulate_record`)."""
    from liquidamp.coupled.testrig import prepare_run

    stroke = record_stroke(record)
    _check_reach(stroke.max_abs, params)
    t = record.time
    T = stroke.period
    origin = stroke.t0
    # the rig runs in time from the series' origin (t = origin is rig time 0)
    rig_stroke = FourierStroke(stroke.frequency, stroke.sine, stroke.cosine, 0.0, 0.0)
    model, options = prepare_run(model, params, rig_stroke, options)
    y0 = float(rig_stroke(0.0)[0])
    rest = model.initial_state(params, y0)
    guess = rest if x0 is None else _onto_invariants(model, params, np.asarray(x0, float), rest,
                                                     y0)
    if cond is not None:
        tq, at_record = cond.model_times(t)
    else:
        tq, at_record = t, np.arange(t.size)
    phase = np.mod(tq - origin, T)
    phase[phase >= T * (1.0 - 1e-12)] = 0.0
    uniq, inverse = np.unique(phase, return_inverse=True)
    warn = []
    if model.n_states:
        # the orbit is found on the phases the record needs (no extra period to sample it)
        grid = np.append(uniq, T)
        rig = TestRig(model, params, rig_stroke)
        engine = engine_for(rig, options)
        try:
            orbit = periodic_state(rig, engine, guess, options, route=route,
                                   invariants_of=rest, grid=grid,
                                   shooting=ShootingOptions(max_iter=RECORD_SHOOTING_ITER))
        except ConvergenceError as exc:
            if getattr(exc, "marched", None) is None:
                raise
            # neither route arrived (e.g. vapour cavities that close ever more slowly): the
            # last marched cycle, said so
            states, cycles, change = exc.marched
            Xq = np.ascontiguousarray(states[:, inverse])
            stats = {"route": "march (not converged)", "march_cycles": cycles}
            how = (f"NOT on a periodic orbit: the last of {cycles} marched cycles (change per "
                   f"cycle {change:.2e}; shooting did not converge)")
            warn.append(f"{record.label}: {how}")
        else:
            Xq = np.ascontiguousarray(orbit.states[:, inverse])
            stats = dict(orbit.stats)
            how = f"on the periodic orbit of its cycle ({orbit.message})"
    else:
        Xq = np.zeros((0, phase.size))
        stats, how = {"route": "algebraic"}, "by a model without states (no orbit needed)"
    uq = rig_stroke(phase)
    fq = np.broadcast_to(np.asarray(model.force(phase, Xq, uq, params), float), phase.shape)
    X = np.ascontiguousarray(Xq[:, at_record])
    u = tuple(np.asarray(q)[at_record] for q in uq)
    force = cond.model_force(fq) if cond is not None else None
    stats.update(stroke="fourier", harmonics=stroke.harmonics, velocity_gain=1.0)
    note = (f"{how}; stroke: Fourier series of {stroke.harmonics} harmonic(s), exact "
            "derivatives")
    return _response(model, params, t, X, u, options, stats, force=force, note=note,
                     warnings=warn)


def _onto_invariants(model, params, x, rest, y=0.0):
    """``x`` moved (minimum-norm, in state scales) onto the invariants of ``rest``, both at
    stroke ``y`` [m] (the total mass depends on the chamber volumes there)."""
    from liquidamp.coupled.periodic import invariants, project_level_set

    if x.shape != rest.shape:
        raise ParameterError(f"x0 must hold the {rest.size} states of model {model.name!r}, "
                             f"got shape {x.shape}")
    target, _ = invariants(model, params, rest, y)
    if not target.size:
        return x
    scale = np.asarray(model.state_scales(params), float)
    size = np.abs(target) + (target == 0.0)

    def gap(z):
        v, G = invariants(model, params, z, y)
        return (v - target) / size, G * scale / size[:, None]

    return project_level_set(x, gap, scale)


def _response(model, params, t, X, u, options, stats=None, force=None,
              note: str = "", warnings=()) -> DeviceResponse:
    if force is None:
        force = np.broadcast_to(np.asarray(model.force(t, X, u, params), float), t.shape)
    force = np.array(force, float)
    p1 = p2 = None
    warn = list(warnings)
    if model.pressures is not None:
        p1, p2 = (np.broadcast_to(np.asarray(q, float), t.shape).copy()
                  for q in model.pressures(X, u, params))
        pmin = float(min(p1.min(), p2.min()))
        if (model.uses_bulk_law and params.bulk_law == "gholizadeh"
                and pmin <= options.pressure_floor):
            raise PressureError(
                f"model {model.name!r}: a chamber pressure fell to {pmin:.4g} Pa, at or below "
                f"the floor {options.pressure_floor:g} Pa; the liquid-air law (eq. 2) is "
                "singular at p = 0: the device cavitates (add the 'cavitation' effect)")
        if pmin <= 0.0:
            warn.append(f"absolute chamber pressure went negative (lowest {pmin:.4g} Pa): "
                        "non-physical for this model")
        elif pmin < options.vapour_pressure and model.effect("cavitation") is None:
            warn.append(f"lowest chamber pressure {pmin:.4g} Pa is below the vapour pressure "
                        f"{options.vapour_pressure:g} Pa (add the 'cavitation' effect)")
    mass_error = None
    if model.mass is not None:
        M = np.asarray(model.mass(X, u, params), float)
        mass_error = float(np.max(np.abs(M - M[0])) / M[0])
    X.setflags(write=False)
    return DeviceResponse(
        model=model.name, params=params, time=t, stroke=np.array(u[0]),
        stroke_rate=np.array(u[1]), stroke_acceleration=np.array(u[2]), force=force, states=X,
        state_names=model.state_names, state_units=model.state_units, p1=p1, p2=p2,
        mass_error=mass_error, status="completed",
        message=f"driven by the recorded stroke over {t[-1] - t[0]:.4g} s"
                + (f"; {note}" if note else ""),
        warnings=tuple(warn), solver_stats=dict(stats or {}))


# ---------------------------------------------------------------------------
# error measures and the noise floor


def nrmse(model_force, measured_force) -> float:
    """RMS(model - measured) / RMS(measured - mean(measured)) [-], pooled over sequences.

    Give arrays or equal-length sequences of arrays (one per record of a
    set); the means are pooled over the whole set.

    Raises
    ------
    ParameterError
        If either argument holds NaN or inf (the argument, the first bad index
        of the pooled samples and the count are named), if they differ in
        length, or if the measured force is constant.

    Examples
    --------
    >>> nrmse(np.array([1.0, -1.0]), np.array([2.0, -2.0]))
    0.5
    """
    from liquidamp.analysis.response.harmonics import check_samples

    m = np.concatenate([np.ravel(a) for a in _as_list(model_force)])
    d = np.concatenate([np.ravel(a) for a in _as_list(measured_force)])
    m = check_samples("model_force", m, "N", where="nrmse")
    d = check_samples("measured_force", d, "N", where="nrmse")
    if m.shape != d.shape:
        raise ParameterError(f"nrmse: model has {m.size} samples, measurement {d.size}")
    den = float(np.sqrt(np.mean((d - d.mean()) ** 2)))
    if den == 0:
        raise ParameterError("nrmse: the measured force is constant")
    return float(np.sqrt(np.mean((m - d) ** 2)) / den)


def _as_list(x):
    if isinstance(x, np.ndarray) and x.ndim == 1:
        return [x]
    return list(x)
