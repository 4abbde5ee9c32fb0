"""The objective a fit minimises: the model built from fit values, its force on the records,
and the residual, with the least-squares Jacobian's columns run on several threads.

:func:`build` turns fit values (multipliers and effect parameters) into a device and its
effects; :func:`predict` runs the model over records (periodic records from their periodic
orbit, warm-started from the last one); :class:`FitObjective` is the scaled residual that
:func:`~liquidamp.analysis.measured.calibration.calibrate` hands to
:func:`scipy.optimize.least_squares`.

Finite-difference Jacobian on threads
-------------------------------------
Each column of the forward-difference Jacobian is one more run of the model over every
record; in a fit they are most of the runs (3843 of 4994 in the series-compliance bench
record of session 8).  The columns are independent, and the compiled integrators release
the GIL (``nogil``, :mod:`liquidamp.coupled._kernels`), so :meth:`FitObjective.columns`,
passed to ``least_squares(workers=...)``, runs them on :func:`fit_threads` threads.  Every
column starts its periodic orbits from the orbits at the base point (a private copy per
column; the records' memory between runs likewise), never from another column's, so the
Jacobian does not depend on the number of threads or on the order in which the columns
finish: one thread and two give the same numbers to the last bit (a drifting record's start
temperature, kept in ``record.meta`` as the next estimate's first guess, made d07's fit vary
from run to run on two threads before the records were copied too).  The steps are scipy's
own (``diff_step``, bounds respected).

The thread count is the usable cores (``os.sched_getaffinity``), at most
:data:`MAX_THREADS`, or the environment variable ``LIQUIDAMP_THREADS`` (1 turns it off).

References
----------
.. [1] SciPy ``least_squares``: ``workers`` (map-like callable for the finite-difference
   Jacobian), SciPy 1.16 release notes.
.. [2] Numba, "Releasing the GIL" (``nogil=True``).
"""

from __future__ import annotations

import contextvars
import dataclasses
import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from liquidamp.analysis.measured.fit_spec import FitSpec, check_spec_uses
from liquidamp.analysis.measured.progress import current_progress
from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.device.effects import EFFECTS, Effect, with_effects
from liquidamp.device.models import get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError
from liquidamp.options import resolve_options

__all__ = ["build", "predict", "FitObjective", "fit_threads", "column_pool", "MAX_THREADS"]

#: Most threads the Jacobian's columns use (more cores than this are left to the caller).
MAX_THREADS = 8


def fit_threads() -> int:
    """Threads for a fit's finite-difference Jacobian columns (1 = sequential).

    ``LIQUIDAMP_THREADS`` (a whole number from 1 to 64) when set, else the cores this
    process may use, at most :data:`MAX_THREADS`.

    Returns
    -------
    int

    Raises
    ------
    ParameterError
        ``LIQUIDAMP_THREADS`` is set to something other than a whole number from 1 to 64.

    Examples
    --------
    >>> import os
    >>> before = os.environ.pop("LIQUIDAMP_THREADS", None)
    >>> os.environ["LIQUIDAMP_THREADS"] = "1"; fit_threads()
    1
    >>> del os.environ["LIQUIDAMP_THREADS"]; 1 <= fit_threads() <= MAX_THREADS
    True
    >>> if before is not None: os.environ["LIQUIDAMP_THREADS"] = before
    """
    env = os.environ.get("LIQUIDAMP_THREADS")
    if env is not None and env.strip():
        try:
            n = int(env)
        except ValueError:
            n = 0
        if not 1 <= n <= 64:
            raise ParameterError(f"LIQUIDAMP_THREADS = {env!r}: allowed a whole number "
                                 "from 1 to 64 (threads of a fit's Jacobian columns)")
        return n
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    return max(1, min(cores, MAX_THREADS))


_POOLS: dict = {}  # (process id, threads) -> ThreadPoolExecutor (column_pool)
_POOLS_LOCK = threading.Lock()


def column_pool(threads: int) -> ThreadPoolExecutor:
    """The thread pool of ``threads`` workers that runs the Jacobian's columns.

    One per process and thread count, started on first use and kept (the workers idle
    between Jacobians): a pool started and joined per Jacobian cost 4-9 % of a 200 Hz
    record's diagnosis (measured, session 16: 3.29 -> 3.10 s, two cores).  Keyed by the
    process id too, so a forked child starts its own (a parent's workers do not exist
    there).  The workers run only model evaluations, never a fit, so the pool cannot wait
    on itself; fits in several threads share it.

    Parameters
    ----------
    threads : int
        Workers [-] (:func:`fit_threads`), at least 2.

    Returns
    -------
    concurrent.futures.ThreadPoolExecutor

    Examples
    --------
    >>> column_pool(2) is column_pool(2), column_pool(2)._max_workers
    (True, 2)
    """
    key = (os.getpid(), int(threads))
    with _POOLS_LOCK:
        pool = _POOLS.get(key)
        if pool is None:
            pool = _POOLS[key] = ThreadPoolExecutor(max_workers=key[1],
                                                    thread_name_prefix="liquidamp-jac")
        return pool


def build(base_params: DeviceParams, effects: tuple[Effect, ...], spec: FitSpec,
          values: dict) -> tuple[DeviceParams, tuple[Effect, ...]]:
    """Parameters and effects for fit ``values`` (name -> value); inputs untouched.

    Multipliers apply through :meth:`DeviceParams.scaled`: on ``c1``, ``c2``,
    ``S_t`` they scale the loss/inertance factor (or the explicit value), on
    ``mu``, ``l_t``, ``A_t`` the geometry the derived coefficients follow.
    """
    check_spec_uses(base_params, spec)
    mult = {p.name: values.get(p.name, p.value) for p in spec.parameters
            if p.kind == "multiplier"}
    params = base_params.scaled(**mult) if mult else base_params
    by_name = {e.name: e for e in effects}
    for name in spec.effect_names():
        if name not in by_name:
            by_name[name] = EFFECTS[name]()
    changes: dict[str, dict] = {}
    for p in spec.parameters:
        if p.kind == "effect":
            eff, key = p.name.split(".", 1)
            changes.setdefault(eff, {})[key] = values.get(p.name, p.value)
    out = []
    for name, e in by_name.items():
        out.append(e.replace(**changes[name]) if name in changes else e)
    return params, tuple(out)


def predict(model, params: DeviceParams, effects, records, *, options=None,
            preroll: int | None = None, warm: dict | None = None,
            responses: list | None = None, route: str = "auto") -> list[np.ndarray]:
    """Model force [N] for each record (driven by its stroke).

    ``warm`` (optional dict, updated in place): the orbit state at each periodic record's
    first sample from the previous call, by record index, as the first guess of the next
    periodic orbit (:func:`~liquidamp.analysis.measured.record_model.simulate_record`,
    ``x0``); ``preroll`` is ignored (kept for existing calls).  ``responses`` (optional
    list): receives each record's :class:`~liquidamp.coupled.testrig.DeviceResponse`.
    ``route``: the route to each periodic orbit (:func:`~liquidamp.analysis.measured.
    record_model.simulate_record`).
    """
    m = with_effects(get_model(model), *effects)
    opts = resolve_options(options, "fit")
    out = []
    for i, r in enumerate(records):
        x0 = None if warm is None else warm.get(i)
        if x0 is not None and x0.shape != (m.n_states,):
            x0 = None
        resp = simulate_record(m, params, r, options=opts, x0=x0, route=route)
        if warm is not None and r.periodic and m.n_states:
            warm[i] = np.array(resp.states[:, 0])
        if responses is not None:
            responses.append(resp)
        out.append(resp.force)
    return out


class FitObjective:
    """Scaled residual of a fit: ``(model force - measured force) / (RMS x sqrt(N))``.

    Parameters
    ----------
    model : str or DeviceModel
        Base model (name or object).
    base_params : DeviceParams
        The device the multipliers scale.
    effects : tuple of Effect
        Effects of the model (their parameters as started).
    spec : FitSpec
        What is varied, its bounds and transforms.
    records : sequence of Record
        Calibration records (SI), fitted together.
    options : SolverOptions
        Integration options.
    preroll : int
        Ignored (kept for existing calls).
    keep : sequence of ndarray of bool, optional
        Per record, the samples fitted (False at dropped outliers).

    Raises
    ------
    ParameterError
        Records of constant force, or ``LIQUIDAMP_THREADS`` not a whole number from 1 to 64
        (:func:`fit_threads`), before any model run.

    Notes
    -----
    Calling it runs the model over every record (:func:`predict`), counts the run in
    ``nfev`` and reports it to :func:`~liquidamp.analysis.measured.progress.current_progress`;
    a point where the model cannot run returns a flat residual of NRMSE 3 and is counted in
    ``failures``.  :meth:`columns` is the ``workers`` map of the least-squares Jacobian
    (module docstring).  Counters are updated under a lock: the columns run on threads.
    """

    def __init__(self, model, base_params, effects, spec, records, options, preroll,
                 keep=None):
        self.model = get_model(model)
        self.base, self.effects, self.spec = base_params, tuple(effects), spec
        self.records, self.options, self.preroll = tuple(records), options, preroll
        self.var = [p for p in spec.parameters if p.vary]
        self.fixed = {p.name: p.value for p in spec.parameters}
        meas = np.concatenate([r.force for r in self.records])
        self.meas = meas
        self.keep = (np.ones(meas.size, bool) if keep is None
                     else np.concatenate(keep).astype(bool))
        kept = meas[self.keep]
        self.den = float(np.sqrt(np.mean((kept - kept.mean()) ** 2)))
        if self.den == 0:
            raise ParameterError("calibration records hold a constant force")
        self.scale = self.den * math.sqrt(kept.size)
        self.nfev = 0
        self.failures = 0
        self.last_error = ""
        self.warm: dict = {}  # the last periodic orbits, first guesses of the next
        self.threads = fit_threads()  # checked before any model run
        self._lock = threading.Lock()
        self._local = threading.local()  # a Jacobian column's own orbits

    def values(self, x) -> dict:
        """Fit values (name -> value) at the optimiser's point ``x`` (transformed)."""
        v = dict(self.fixed)
        for p, xi in zip(self.var, x, strict=True):
            v[p.name] = p.from_x(float(xi))
        return v

    def forces(self, values):
        """``(params, effects, forces)`` of the model at fit ``values`` [N per record]."""
        warm = getattr(self._local, "warm", None)
        records = getattr(self._local, "records", None)
        params, effects = build(self.base, self.effects, self.spec, values)
        return params, effects, predict(self.model, params, effects,
                                        self.records if records is None else records,
                                        options=self.options,
                                        warm=self.warm if warm is None else warm)

    def count(self, failure: Exception | None = None) -> None:
        """Count one model run (and its failure, if any) under the lock."""
        with self._lock:
            if failure is None:
                self.nfev += 1
            else:
                self.failures += 1
                self.last_error = str(failure)

    def __call__(self, x):
        self.count()
        report = current_progress()
        if report is not None:
            report(1)
        try:
            _, _, F = self.forces(self.values(x))
        except (PressureError, ConvergenceError, ParameterError) as exc:
            self.count(exc)
            return np.where(self.keep, 3.0 / math.sqrt(self.keep.sum()), 0.0)
        return np.where(self.keep, np.concatenate(F) - self.meas, 0.0) / self.scale

    def columns(self, fun, points):
        """``map(fun, points)`` for the Jacobian's columns, on :func:`fit_threads` threads.

        Each call starts its periodic orbits from a private copy of the orbits at the base
        point (the last point evaluated before the Jacobian) and runs on copies of the
        records whose ``meta`` (the memory a record simulation keeps between runs) is the
        base point's, so the result is the same for any thread count; ``self.warm`` and the
        records keep the base point's.

        Parameters
        ----------
        fun : callable
            scipy's wrapper of this objective.
        points : iterable of ndarray
            The perturbed points, one per column.

        Returns
        -------
        list of ndarray
            ``fun`` at each point, in order.
        """
        points = list(points)
        base = self.warm  # read only here: the caller waits for the columns

        def one(x):
            self._local.warm = {k: v.copy() for k, v in base.items()}
            # the records' own memory (record.meta: e.g. a drifting record's last start
            # temperature, the first guess of the next estimate) as at the base point too,
            # a column's writes kept to itself
            self._local.records = tuple(dataclasses.replace(r, meta=dict(r.meta))
                                        for r in self.records)
            try:
                return fun(x)
            finally:
                self._local.warm = self._local.records = None

        n = min(self.threads, len(points))
        if n <= 1:
            return [one(x) for x in points]
        contexts = [contextvars.copy_context() for _ in points]  # the progress callable
        return list(column_pool(n).map(lambda c, x: c.run(one, x), contexts, points))
