"""Drive a device model with a measured record; the force error against it.

:func:`simulate_record` runs any device model under a record's stroke
(:class:`~liquidamp.analysis.measured.records.Record`) about its mean (the LVDT
zero is arbitrary; the mean stroke is taken as the mid-position where the chambers
hold V01 and V02; an effect on the absolute stroke, ``gas_charge``, is given the mean
back and a gas-charged device's chambers follow the absolute stroke at the charge's level:
:func:`~liquidamp.device.effects_damper.on_absolute_stroke`); :func:`nrmse` is the
normalized RMS force error used by the calibration; :func:`integrate` is the synthetic
generator's LSODA march under any scalar stroke.

The periodic steady state, not a pre-roll: a periodic record (:attr:`Record.periodic`) is
simulated on the periodic orbit of its cycle.  Its stroke is its Fourier series
(:func:`record_stroke`: the averaged record's fit, or the least-squares fit of the
displacement with the fundamental refined), so velocity and acceleration are exact (the
21-point Savitzky-Golay velocity is 1.3 % low at 40 samples per cycle); the orbit comes from
:func:`liquidamp.coupled.periodic.periodic_state` (march while it converges, Newton shooting
with the invariants of the device at rest where it stalls), on the phases of the samples the
record (or its conditioning) needs.  Before, the model was pre-rolled over the first cycle a
fixed number of times from rest: with the true parameters of a slowly settling device
(device_a, 5 Hz) NRMSE 0.044 against a noise floor of 0.0017; now within 1.03x of the floor.
A warm start (``x0``, e.g. the previous response's ``states[:, 0]``) is moved onto the
invariants of rest and only shortens the march (from three periods,
:data:`WARM_MIN_CYCLES`); one shooting may spend at most :data:`RECORD_SHOOTING_BUDGET`
periods' steps, so that one hard parameter point costs a fit seconds, not half a minute
(and one period at most ``options.max_steps`` steps, the fit preset's
:data:`~liquidamp.options.FIT_MAX_STEPS`; a run over a record that is not periodic that
many per period of its span, :meth:`~liquidamp.options.SolverOptions.over_periods`).  A
record whose stroke is not periodic (tapered or broadband) has no steady state to approach:
it runs under the Savitzky-Golay stroke (:meth:`Record.stroke`; a stroke of a few sinusoids
under its line-spectrum fit) from rest at the start of a lead-in
(:func:`~liquidamp.analysis.measured.lead_in.lead_in`: a tenth of the record or one period,
at most 1 s) in which the rod moves as the record moves into the state most like its first
sample's (the method of analogues, for a stroke of a few sinusoids; else a ramp at the first
sample's velocity), so that the model meets the first sample in the motion's own steady
flow, its yield, friction and pressure drops on the side the motion sets and its channel
flow settled; from rest at the first sample instead, a device whose yield holds 180 N (the
independent MR record d10 with its true parameters) left a 135 N RMS start-up error over the
first 50 ms.  Before, the lead-in was a ramp at the first sample's velocity no farther than
the stroke's RMS: on a two-tone stroke (4 Hz + 1.3 Hz, a rotorcraft lag-damper test) the
true model then left a 91 N error at the first sample (2 % NRMSE over the record, 5x the
noise).
The response states the filter's velocity gain at the record's frequency
(:func:`~liquidamp.analysis.measured.record_quality.velocity_gain`).

Measured input channels (issue #20): a model that reads channels
(:attr:`DeviceModel.input_channels`, e.g. ``field_yield`` the voltage) is driven by the
record's channels sample by sample, so it runs the record from its first sample (the
route of a record that is not periodic, whatever its stroke), the channels carried by the
stroke on its time grid (the record's samples as read, before any filter) and interpolated
at every stage on both engines; the effect states that follow an input start settled on
its first value (:meth:`Effect.input_state`).  A record without a channel the model reads
is refused before any work, naming the effect, the channel and the record's channels.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B-C.
.. [2] A. Savitzky, M. J. E. Golay, Anal. Chem. 36(8), 1964.
"""

from __future__ import annotations

import numpy as np

from liquidamp.analysis.measured.conditioning import stroke_threshold
from liquidamp.analysis.measured.lead_in import lead_in as _lead_in
from liquidamp.analysis.measured.record_quality import velocity_gain
from liquidamp.analysis.measured.records import Record
from liquidamp.coupled.engines import TestRig, engine_for, stroke_inputs
from liquidamp.coupled.invariants import onto_invariants
from liquidamp.coupled.periodic import ROUTES, ShootingOptions, periodic_state
from liquidamp.coupled.testrig import DeviceResponse
from liquidamp.device.effects import on_absolute_stroke
from liquidamp.device.effects_base import check_input_channels, initial_state_with_inputs
from liquidamp.device.models import DeviceModel, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError, check_choice
from liquidamp.options import SolverOptions, resolve_options
from liquidamp.structure.testmachine import FourierStroke, RecordedStroke, harmonics_tested

__all__ = ["simulate_record", "record_stroke", "integrate", "nrmse", "stationary",
           "NOT_PERIODIC", "RECORD_SHOOTING_BUDGET", "WARM_MIN_CYCLES"]


#: ``solver_stats["route"]`` of a periodic record's response that is NOT on a periodic
#: orbit: neither the march nor the shooting arrived, the last marched cycle is returned (its
#: force then depends on where the march started, not on the parameters alone).
NOT_PERIODIC = "march (not converged)"

#: Newton iterations the record simulation allows the shooting (the march's last cycle,
#: flagged, where it does not arrive: a fit must not stall on one hard point).
RECORD_SHOOTING_ITER = 12

#: Periodicity residual (of the state scales: p0 for a chamber pressure) at which the record
#: simulation takes a shooting whose iterations ran out as arrived
#: (:class:`~liquidamp.coupled.periodic.ShootingOptions` ``accept``) [-].  The fit preset
#: integrates at rtol 1e-6, so a one-period run carries an error of that order and a
#: shooting held to steady_tol 1e-6 stalls at 2e-6 to 1e-5 on stiff valved devices (the
#: refits of a vehicle damper's record with rig ringing: 8 of its first 21 shootings failed
#: there after 120-175 one-period runs each, a failure from a warm start was shot again from
#: rest, and the diagnosis ran past 900 s; with this figure it ends in 303 s).  1e-5 of p0
#: is 1 Pa, a force of 1e-5 A_p p0: below a hundredth of the best record's noise floor
#: (NRMSE 1e-3 of a force amplitude A_p dp with dp of 0.3 bar or more).
RECORD_SHOOTING_ACCEPT = 1e-5

#: ``min_cycles`` of the march from a warm start (``x0``: another parameter point's orbit,
#: as a fit's evaluations and Jacobian columns run) [-].  The march accepts after two cycles
#: in a row that count (:func:`liquidamp.coupled._kernels.steady_rule`), the first that may
#: count being cycle ``min_cycles``: from rest the first cycles' large changes do not count
#: anyway, and from a warm start the default 3 marches a fourth period whatever the
#: distance.  With 1 the orbit is accepted after three periods where the change per cycle
#: is below the tolerance and the third's extrapolation (change x rho / (1 - rho), rho the
#: ratio of the last two changes) too.  Measured (session 16): 93 % of a 200 Hz elastomer
#: record's diagnosis's simulations are warm marches of 4 periods.
WARM_MIN_CYCLES = 1

#: Integrator steps the record simulation allows one shooting, in first periods
#: (:class:`~liquidamp.coupled.periodic.ShootingOptions` ``budget``) [-].  The shooting is
#: there to be cheaper than marching on: 200 periods is half the fit preset's march budget
#: (400 cycles).  Measured (session 16) in the diagnosis of a pressurised device's records:
#: nine shootings at 35-91 first periods; two parameter points of the valved start's refits
#: (a digressive valve opening at 108 Pa with a conductance 1e8 x the channel's, chattering
#: at the integration's noise) held the residual above the tolerance while the stall rule
#: tightened the runs to rtol 1e-8: 2051 first periods (25 s, accepted) and one past a run's
#: step limit (28 s, then marched from rest in 0.2 s): half the diagnosis's 107 s.
RECORD_SHOOTING_BUDGET = 200.0

#: The shooting of every record simulation (the three figures above).
RECORD_SHOOTING = ShootingOptions(max_iter=RECORD_SHOOTING_ITER, accept=RECORD_SHOOTING_ACCEPT,
                                  budget=RECORD_SHOOTING_BUDGET)


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
    route : {"auto", "march", "shooting", "no_shooting"}
        Route to the periodic orbit (:func:`liquidamp.coupled.periodic.periodic_state`;
        ``"no_shooting"``: where the march does not arrive, the last marched cycle,
        flagged as not periodic, as where the shooting fails).

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
    chans = model.input_channels
    if chans:  # measured input channels: refused before any work where the record lacks one
        check_input_channels(model, tuple(record.channels), f"record {record.label!r}")
        if cond is not None and cond.cycles_averaged > 1:
            raise ParameterError(
                f"{record.label}: model {model.name!r} reads the measured channel(s) "
                f"{', '.join(chans)}, which drive it sample by sample from the record's "
                "start; a record averaged into one cycle has no such series (condition it "
                "with average=False)")
    if record.periodic and not stationary(model):  # a warming device: no periodic orbit
        if cond is not None and cond.cycles_averaged > 1:
            raise ParameterError(
                f"{record.label}: model {model.name!r} drifts (it holds a thermal state) and "
                "is marched over the whole record; a record averaged into one cycle has lost "
                "its drift (condition it with average=False)")
        return _simulate_drifting(model, params, record, cond, options, route, chans)
    if record.periodic and not chans:
        return _simulate_periodic(model, params, record, cond, options, x0, route)
    # a conditioned record (liquidamp.analysis.measured.conditioning) states the stroke the
    # model is driven by: the record's over its whole span, ends and all
    stroke = record.stroke() if cond is None else RecordedStroke(*cond.model_stroke())
    if chans:
        stroke = _with_channels(stroke, record, cond, chans)
    _check_reach(stroke.max_abs, params)
    t = record.time
    # a lead-in before the first sample (the record's own motion into its nearest analogue,
    # _lead_in) so that the model meets the first sample in motion, not from rest
    t_first = t_start = float(stroke.time[0])
    tones = record.tones  # a few sinusoids (Record.stroke), else None
    if x0 is None:
        stroke = _lead_in(stroke, LEAD_IN_SHARE, LEAD_IN_MAX, record.period,
                          analogue=tones is not None)
        t_start = float(stroke.time[0])
    y0 = float(stroke.displacement[0])
    if x0 is not None:
        x = np.asarray(x0, float)
    elif chans:  # effect states on a measured input start settled on its first value
        x = initial_state_with_inputs(model, params, y0,
                                      {c: float(v[0]) for c, v in stroke.channels.items()})
    else:
        x = model.initial_state(params, y0)
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
    if tones is not None:  # Record.stroke: a few sinusoids, exact derivatives
        stats = {"stroke": f"line spectrum ({len(tones.frequencies)} lines)",
                 "velocity_gain": 1.0}
        note = (f"stroke: its {len(tones.frequencies)}-line spectrum fit (exact derivatives; "
                f"residual {tones.residual_rms:.3g} m, white noise {tones.noise_std:.3g} m)")
    if t_start < t_first:
        stats["lead_in"] = t_first - t_start
        note += f"; lead-in {t_first - t_start:.3g} s before the first sample"

    def run(t_eval, xs):
        if not model.n_states:
            return np.zeros((0, t_eval.size))
        ta, tb = min(t_start, float(t_eval[0])), float(t_eval[-1])
        return engine.march(rig, xs, ta, tb, t_eval,
                            options.over_periods((tb - ta) / record.period), max_step, stats)

    if cond is not None:
        # the model force conditioned as the record's was
        tf, at_record = cond.model_times(t)
        Xf = run(tf, x)
        uf = _inputs_too(stroke(tf), stroke, tf, chans)
        ff = np.broadcast_to(np.asarray(model.force(tf, Xf, uf, params), float), tf.shape)
        X = np.ascontiguousarray(Xf[:, at_record])
        return _response(model, params, t, X, stroke(t), options, stats,
                         force=cond.model_force(ff), note=note)
    X = run(t, x)
    u = tuple(np.asarray(q, float) for q in stroke(t))  # the samples (after any lead-in)
    force = None
    if chans:
        force = model.force(t, X, _inputs_too(u, stroke, t, chans), params)
    return _response(model, params, t, X, u, options, stats, note=note, force=force)


#: Lead-in of a record that is not periodic, as a share of its span [-], and at most [s]
#: (:func:`~liquidamp.analysis.measured.lead_in.lead_in`).
LEAD_IN_SHARE = 0.1
LEAD_IN_MAX = 1.0


def _with_channels(stroke, record, cond, chans):
    """``stroke`` carrying the record's measured channels ``chans`` on its time grid: the
    samples of the record as given (before any filter: a step in a control input stays a
    step), interpolated linearly where the grids differ."""
    src = cond.record if cond is not None and cond.record is not None else record
    ch = {c: np.interp(stroke.time, src.time, src.channels[c]) for c in chans}
    return RecordedStroke(stroke.time, stroke.displacement, stroke.velocity,
                          stroke.acceleration, channels=ch)


def _inputs_too(u, stroke, t, chans):
    """``u = (y, v, a)`` with the channel values at ``t`` as its fourth entry where the model
    reads channels (:meth:`DeviceModel.force`)."""
    if not chans:
        return u
    return tuple(u) + (stroke_inputs(stroke, t),)


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
    (:meth:`FourierStroke.fit`, the harmonics above the family-wise level of
    :func:`~liquidamp.analysis.measured.conditioning.stroke_threshold` for the harmonics
    tested, as the averaged stroke keeps them; the fundamental refined), once per record
    (kept in ``record.meta``).

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
        tested = max(1, harmonics_tested(record.sampling_rate, record.frequency))
        s = FourierStroke.fit(record.time, record.displacement, record.frequency,
                              max_harmonics=64, threshold=stroke_threshold(tested),
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
    guess = rest if x0 is None else onto_invariants(model, params, np.asarray(x0, float), rest,
                                                     y0)
    phase, uniq, inverse, at_record, uq = _phases(record, cond, t, rig_stroke, origin)
    warn = []
    if model.n_states:
        # the orbit is found on the phases the record needs (no extra period to sample it)
        grid = np.append(uniq, T)
        rig = TestRig(model, params, rig_stroke)
        engine = engine_for(rig, options)

        def orbit_from(first, opts=options):
            return periodic_state(rig, engine, first, opts, route=route,
                                  invariants_of=rest, grid=grid,
                                  shooting=RECORD_SHOOTING)
        try:
            try:
                orbit = orbit_from(guess, options if x0 is None else options.replace(
                    min_cycles=min(options.min_cycles, WARM_MIN_CYCLES)))
            except ConvergenceError:
                if x0 is None:
                    raise
                # a warm start (another parameter point's orbit) can sit on a slow branch
                # the rest state does not (a friction contact behind a dead band: 40 cycles
                # creeping, then the shooting's runs past their step limit, against 4
                # cycles from rest)
                orbit = orbit_from(rest)
        except ConvergenceError as exc:
            if getattr(exc, "marched", None) is None:
                raise
            # neither route arrived (e.g. vapour cavities that close ever more slowly): the
            # last marched cycle, said so
            states, cycles, change = exc.marched
            Xq = np.ascontiguousarray(states[:, inverse])
            stats = {"route": NOT_PERIODIC, "march_cycles": cycles}
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
    fq = np.broadcast_to(np.asarray(model.force(phase, Xq, uq, params), float), phase.shape)
    X = np.ascontiguousarray(Xq[:, at_record])
    u = tuple(np.asarray(q)[at_record] for q in uq)
    force = cond.model_force(fq) if cond is not None else None
    stats.update(stroke="fourier", harmonics=stroke.harmonics, velocity_gain=1.0)
    note = (f"{how}; stroke: Fourier series of {stroke.harmonics} harmonic(s), exact "
            "derivatives")
    return _response(model, params, t, X, u, options, stats, force=force, note=note,
                     warnings=warn)


def stationary(model) -> bool:
    """Whether ``model`` has a periodic steady state under a periodic stroke: False where
    an effect drifts by design (``Effect.stationary`` False: ``self_heating``)."""
    return all(e.stationary for e in getattr(model, "effects", ()))


def _held_model(model, params, T0):
    """The model with its drifting states held at their start: the thermal effect removed and
    the loss coefficients at the start temperature ``T0`` [K] (c1 x r, c2 x r^gamma2), the
    device whose periodic orbit a warming record starts on."""
    from liquidamp.device.effects import with_effects

    th = next(e for e in model.effects if not e.stationary)
    others = tuple(e for e in model.effects if e is not th)
    bare = get_model(model.base) if model.base != "viscous" else None
    if bare is None:
        raise ParameterError("a drifting record needs a model with chamber or dashpot physics")
    r = th.viscosity_ratio(T0)
    held = params.scaled(c1=r, c2=r ** th.c2_exponent)
    return with_effects(bare, *others), held, th


def _simulate_drifting(model, params, record, cond, options, route, chans=()):
    """A periodic stroke on a device that drifts (self-heating): the whole record marched.

    The record starts on the periodic orbit of the device held at its start temperature T_0
    (the loss coefficients at T_0, no thermal state: :func:`_held_model`), and the whole
    record is marched from there with the thermal state free, under the record's Fourier
    stroke (exact derivatives); a conditioned record's force is conditioned as the record's
    was.  T_0 is the effect's ``initial_temperature_K`` (``start="given"``) or, with
    ``start="record"``, the record's own: the start temperature whose march best matches
    the force of the record's first two cycles (an initial state estimated from the record
    it starts, one number; Ljung, System Identification, 2nd ed., 1999, Sec. 16.6).
    """
    from liquidamp.coupled.testrig import prepare_run

    stroke = record_stroke(record)
    _check_reach(stroke.max_abs, params)
    t = record.time
    origin = stroke.t0
    rig_stroke = FourierStroke(stroke.frequency, stroke.sine, stroke.cosine, 0.0, 0.0)
    if cond is not None:
        tq, at_record = cond.model_times(t)
    else:
        tq, at_record = t, np.arange(t.size)
    th = next(e for e in model.effects if not e.stationary)
    _, options = prepare_run(model, params, rig_stroke, options)
    stats: dict = {}
    s = tq - origin
    drive = rig_stroke
    if chans:  # measured channels ride on the stroke: the Fourier series sampled 4x finer
        src = cond.record if cond is not None and cond.record is not None else record
        dt = 0.25 / record.sampling_rate
        grid = np.arange(s[0], s[-1] + 0.5 * dt, dt)
        grid[-1] = max(grid[-1], s[-1])
        drive = RecordedStroke(grid, *rig_stroke(grid),
                               channels={c: np.interp(grid + origin, src.time, src.channels[c])
                                         for c in chans})
    if getattr(th, "temperature", "state") == "measured":
        T0 = float(np.interp(s[0], drive.time, drive.channels["temperature"]))
    elif getattr(th, "start", "given") == "record":
        T0 = _estimate_start(model, params, record, rig_stroke, origin, options, route)
        stats["start_temperature [K]"] = T0
    else:
        T0 = float(th.initial_temperature_K)
    X = _march_from(model, params, rig_stroke, T0, s, options, route, stats, drive)
    uq = rig_stroke(s)
    fq = np.broadcast_to(np.asarray(model.force(s, X, _inputs_too(uq, drive, s, chans),
                                                params), float), s.shape)
    force = cond.model_force(fq) if cond is not None else None
    Xr = np.ascontiguousarray(X[:, at_record])
    u = tuple(np.asarray(q)[at_record] for q in uq)
    stats.update(stroke="fourier", harmonics=stroke.harmonics, velocity_gain=1.0,
                 route="march over the record")
    how = ("measured" if th.temperature == "measured" else
           "estimated from its first cycles" if th.start == "record" else "given")
    note = (f"marched over the whole record from the periodic orbit of the device held at "
            f"{T0 - 273.15:.4g} C ({how}; it drifts: {th.name}); stroke: Fourier series of "
            f"{stroke.harmonics} harmonic(s), exact derivatives")
    return _response(model, params, t, Xr, u, options, stats, force=force, note=note)


def _march_from(model, params, rig_stroke, T0, s, options, route, stats, drive=None):
    """States at rig times ``s`` [s] (sorted) of the drifting ``model`` started at ``s[0]`` on
    the periodic orbit of the device held at ``T0`` [K]; marched under ``drive`` (default
    ``rig_stroke``; a RecordedStroke carrying measured channels)."""
    T = rig_stroke.period
    base, held, _ = _held_model(model, params, T0)
    ph0 = float(np.mod(s[0], T))
    rest = base.initial_state(held, float(rig_stroke(0.0)[0]))
    if base.n_states:
        grid = np.append(np.unique(np.array([0.0, min(ph0, T * (1.0 - 1e-9))])), T)
        rig0 = TestRig(base, held, rig_stroke)
        try:
            orbit = periodic_state(rig0, engine_for(rig0, options), rest, options, route=route,
                                   invariants_of=rest, grid=grid,
                                   shooting=RECORD_SHOOTING)
            xb = orbit.states[:, grid.size - 2]
            stats.update({f"start_{k}": v for k, v in orbit.stats.items()})
        except ConvergenceError as exc:
            if getattr(exc, "marched", None) is None:
                raise
            xb = exc.marched[0][:, grid.size - 2]
    else:
        xb = np.zeros(0)
    x = np.concatenate([xb, [T0]])
    rig = TestRig(model, params, rig_stroke if drive is None else drive)
    max_step = max(options.max_step_fraction, 1e-4) * T
    return engine_for(rig, options).march(rig, x, float(s[0]), float(s[-1]), s,
                                          options.over_periods(float(s[-1] - s[0]) / T),
                                          max_step, stats)


#: Whole stroke cycles from a record's start whose force fixes its start temperature [-].
START_CYCLES = 2.0


def _estimate_start(model, params, record, rig_stroke, origin, options, route) -> float:
    """The start temperature [K] whose march best matches (least squares) the force of the
    record's first :data:`START_CYCLES` cycles, within T_amb - 30 K and T_amb + 120 K.

    The first estimate for a record is a bounded scalar search (to 0.02 K), polished by
    Newton steps on the misfit (central differences); later calls (a fit's next parameters)
    start the Newton steps from the record's last estimate (the misfit is quadratic in T_0
    near its minimum: two or three steps).
    """
    from scipy.optimize import minimize_scalar

    th = next(e for e in model.effects if not e.stationary)
    t = record.time
    m = t <= t[0] + START_CYCLES * rig_stroke.period
    s = t[m] - origin
    F = record.force[m]
    u = rig_stroke(s)

    def sse(T0):
        X = _march_from(model, params, rig_stroke, float(T0), s, options, route, {})
        f = np.asarray(model.force(s, X, u, params), float)
        return float(np.sum((f - F) ** 2))

    Ta = th.ambient_temperature_K
    lo = max(Ta - 30.0, th.law_b + 51.0 if th.law == "water" else 1.0)
    hi = Ta + 120.0
    key = ("_start_temperature", Ta, lo, hi)
    T = record.meta.get(key)
    if T is None:
        T = float(minimize_scalar(sse, bounds=(lo, hi), method="bounded",
                                  options={"xatol": 0.02}).x)
    # Newton on the misfit by central differences (+/- 0.05 K) to 1e-4 K: the estimate a
    # smooth function of the fit's parameters, whatever the call before (the fit's
    # difference Jacobian moves T_0 by about 0.03 K)
    h = 0.05
    for _ in range(8):
        fm, f0, fp = sse(T - h), sse(T), sse(T + h)
        curv = (fp - 2.0 * f0 + fm) / (h * h)
        if not curv > 0.0:
            T = float(minimize_scalar(sse, bounds=(lo, hi), method="bounded",
                                      options={"xatol": 0.02}).x)
            break
        step = -0.5 * (fp - fm) / h / curv
        T = min(max(T + max(min(step, 5.0), -5.0), lo), hi)
        if abs(step) < 1e-4:
            break
    record.meta[key] = T
    return T


def _start_temperature(model) -> float:
    """The drifting effect's start temperature [K]."""
    th = next(e for e in model.effects if not e.stationary)
    return float(th.initial_temperature_K)


def _phases(record, cond, t, rig_stroke, origin):
    """The phases [s] of the times the record needs in the rig's time, their sorted unique
    values and the inverse map, the record's samples among them and the stroke there: the
    same for every run of one record, so kept in ``record.meta`` (a conditioned 3 kHz
    record needs 60 000 phases; their stroke series cost as much as the orbit)."""
    T = rig_stroke.period
    key = (float(T), float(origin), float(t[0]), float(t[-1]), t.size, rig_stroke.sine.tobytes(),
           rig_stroke.cosine.tobytes(), id(cond))
    cached = record.meta.get("_phases")
    if cached is not None and cached[0] == key and cached[2] is cond:
        return cached[1]
    if cond is not None:
        tq, at_record = cond.model_times(t)
    else:
        tq, at_record = t, np.arange(t.size)
    phase = np.mod(tq - origin, T)
    phase[phase >= T * (1.0 - 1e-12)] = 0.0
    uniq, inverse = np.unique(phase, return_inverse=True)
    uq = rig_stroke(phase)
    out = (phase, uniq, inverse, at_record, uq)
    for a in (phase, uniq, inverse, at_record, *uq):
        a.setflags(write=False)
    record.meta["_phases"] = (key, out, cond)  # cond kept: its id cannot be reused
    return out


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
