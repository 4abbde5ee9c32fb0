"""Drive a device model with a measured record; the force error against it.

:func:`simulate_record` runs any device model under a record's stroke
(:class:`~liquidamp.analysis.measured.records.Record`) about its mean (the LVDT
zero is arbitrary; the mean stroke is taken as the mid-position where the chambers
hold V01 and V02; an effect on the absolute stroke, ``gas_charge``, is given the mean
back: :func:`~liquidamp.device.effects.with_stroke_offset`); :func:`nrmse` is the
normalized RMS force error used by the calibration; :func:`integrate` is the synthetic
generator's LSODA march under any scalar stroke.

Start-up transients: :func:`simulate_record` pre-rolls the model over the
record's first cycle ``preroll`` times (each pass restarting at the record's
first sample from the state the previous pass ended with), then runs the
whole record.  Each pass is one excitation cycle of the periodic march of
:func:`liquidamp.coupled.testrig.steady_state`, driven by the measured
stroke, so the comparison starts close to the periodic steady state.  A record
whose stroke is not periodic (:attr:`Record.periodic`: tapered or broadband)
has no steady state to approach and its first cycle does not join its first
sample: it is run without pre-roll, from rest at its first sample (its
start-up transient, a few relaxation times T_D, is part of the fit).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B-C.
.. [2] A. Savitzky, M. J. E. Golay, Anal. Chem. 36(8), 1964.
"""

from __future__ import annotations

import math

import numpy as np

from liquidamp.analysis.measured.records import Record
from liquidamp.coupled.engines import TestRig, engine_for
from liquidamp.coupled.testrig import DeviceResponse
from liquidamp.device.effects import with_stroke_offset
from liquidamp.device.models import DeviceModel, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError
from liquidamp.options import SolverOptions, resolve_options
from liquidamp.structure.testmachine import RecordedStroke

__all__ = ["simulate_record", "integrate", "nrmse"]


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
                    options: SolverOptions | None = None, preroll: int = 2,
                    x0=None) -> DeviceResponse:
    """Drive ``model`` with the record's stroke; the model force at the record's samples.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model or one composed with :func:`liquidamp.device.effects.with_effects`.
    params : DeviceParams
        Device parameters.
    record : Record
        The measured record (its smoothed stroke about its mean, SG velocity
        and acceleration drive the model).
    options : SolverOptions, optional
        ``rtol``, ``atol_scale``, ``max_step_fraction`` and
        ``pressure_floor`` are used; the engine named by ``options.engine``
        runs the model with any effects (:mod:`liquidamp.coupled.engines`,
        the same driver as :func:`liquidamp.coupled.testrig.simulate`).
        Default: the ``"default"`` preset of :data:`liquidamp.options.PRESETS`
        (the fitting functions pass ``"fit"``).
    preroll : int
        Passes over the first cycle discarded before the record is run
        (module docstring; none for a record that is not periodic) [-].
    x0 : array, optional
        Initial state for the first pre-roll pass (default: rest at p0).

    Returns
    -------
    DeviceResponse
        ``time`` = record time, ``force`` the model's load-cell force [N] (for a record
        made by :func:`liquidamp.analysis.measured.conditioning.condition`: computed on
        the fine grid and conditioned as the record's force was),
        ``status = "completed"``; warnings for pressures below the vapour
        pressure.

    Raises
    ------
    PressureError
        A chamber pressure reached ``options.pressure_floor`` (models using
        the pressure-dependent bulk law), as in testrig.
    ConvergenceError
        The integration failed.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> t = np.arange(0, 1.0, 0.005)
    >>> rec = Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), 0 * t)
    >>> r = simulate_record("full", preset("paper_calibrated"), rec)
    >>> r.force.shape == rec.time.shape, bool(abs(r.force).max() > 300)
    (True, True)
    """
    # an effect on the absolute stroke (gas_charge) gets the record's mean stroke back
    model = with_stroke_offset(get_model(model), record.offset)
    options = resolve_options(options, "default")
    if not isinstance(params, DeviceParams):
        raise ParameterError(f"params must be DeviceParams, got {type(params).__name__}")
    model.check_params(params)
    cond = record.meta.get("conditioning")
    if cond is not None and not cond.changed:
        cond = None
    # a conditioned record (liquidamp.analysis.measured.conditioning) states the stroke the
    # model is driven by: the record's over its whole span, ends and all, or the periodic
    # fit of one averaged cycle
    stroke = record.stroke() if cond is None else RecordedStroke(*cond.model_stroke())
    if stroke.max_abs >= params.stroke_limit:
        raise ParameterError(
            f"record stroke reaches |y| = {stroke.max_abs:.4g} m about its mean, past the "
            f"chamber end at {params.stroke_limit:.4g} m (V0/A_p)")
    t = record.time
    n_cycle = min(int(math.ceil(record.period * record.sampling_rate)) + 1, t.size)
    y0 = float(stroke.displacement[0])
    x = model.initial_state(params, y0) if x0 is None else np.asarray(x0, float)
    # one driver for both engines (liquidamp.coupled.engines): the device on the test machine
    # under the recorded stroke.  A bounded step: a state that rests while the input moves
    # (freeplay in its gap, a closed cavity) gives zero derivatives at the start, and an
    # unbounded first step could jump over the whole record without seeing the contact
    rig = TestRig(model, params, stroke)
    engine = engine_for(rig, options)
    max_step = max(options.max_step_fraction, 1e-4) * record.period
    stats: dict = {}

    def run(t_eval, xs):
        if not model.n_states:
            return np.zeros((0, t_eval.size))
        return engine.march(rig, xs, float(t_eval[0]), float(t_eval[-1]), t_eval, options,
                            max_step, stats)

    t_cycle = np.append(t[:n_cycle - 1], t[0] + record.period)  # exactly one period
    if cond is not None:
        # the model runs over the times the record's conditioning needs (module
        # conditioning, "like with like"), pre-rolled over its first period
        tf, at_record = cond.model_times(t)
        t_cycle = np.append(tf[tf < tf[0] + record.period], tf[0] + record.period)
    for _ in range(preroll if model.n_states and record.periodic else 0):
        x = run(t_cycle, x)[:, -1]
    if cond is not None:
        # the model force conditioned as the record's was
        Xf = run(tf, x)
        uf = cond.model_inputs() or stroke(tf)
        ff = np.broadcast_to(np.asarray(model.force(tf, Xf, uf, params), float), tf.shape)
        X = np.ascontiguousarray(Xf[:, at_record])
        return _response(model, params, t, X, stroke(t), options, stats,
                         force=cond.model_force(ff))
    X = run(t, x)
    u = (stroke.displacement, stroke.velocity, stroke.acceleration)
    return _response(model, params, t, X, u, options, stats)


def _response(model, params, t, X, u, options, stats=None, force=None) -> DeviceResponse:
    if force is None:
        force = np.broadcast_to(np.asarray(model.force(t, X, u, params), float), t.shape)
    force = np.array(force, float)
    p1 = p2 = None
    warn = []
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
        message=f"driven by the recorded stroke over {t[-1] - t[0]:.4g} s",
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
