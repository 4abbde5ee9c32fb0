"""The periodic steady state that always arrives: march while it converges, then shoot.

:func:`periodic_state` is the one route to the periodic steady state of a device on
the test machine under a periodic stroke (harmonic, commensurate two-frequency, or a
Fourier series); :func:`liquidamp.coupled.testrig.steady_state` (and through it
``simulate``, ``stiffness``, the dual-frequency time route and the record simulation)
goes through it.

1. **March** (``engine.march_cycles``): whole cycles, accepted on the force-waveform
   rule of :func:`~liquidamp.coupled.testrig.steady_state` (the estimated remaining
   change ``d_k rho / (1 - rho)`` below ``steady_tol`` twice).  The march runs in
   chunks; after each, the contraction ratio ``rho`` per cycle is estimated (across
   chunks from the change per cycle at their ends, within the first from the rule's
   own estimate) and with it the cycles still to go,
   ``log(tol (1 - rho) / (d rho)) / log rho``.
2. **Shoot** when the march stalls (``rho >= RHO_STALL``, or a chunk of at least 10
   cycles that does not reduce the change per cycle by 30 %: the change sits at the
   integration noise, as for a 1 um stroke, whose force is a small difference of two
   large pressures) or converges too slowly (cycles to go beyond what is left of
   ``options.max_cycles``): Newton on the one-period map from the last marched state,
   with the sealed device's invariants held (below).
3. If both fail, :class:`~liquidamp.errors.ConvergenceError` gives both routes'
   figures: cycles marched and the last change per cycle; Newton iterations and the
   periodicity residual.

**Shooting with the invariants.**  The sealed device has invariants (Titurus 2018,
eq. 10): the total fluid mass, and in each chamber the relation between density
and pressure (``rho_i = r_i(p_i)`` from the rest state).  Each puts a Floquet
multiplier at exactly 1, so the periodic orbits form a family and ``x(T) - x0``
has a singular Jacobian.  The iteration holds the invariants of the march's start
exactly (every iterate is projected onto their level set, which selects the orbit
the march converges to; an invariant that the composed model does not conserve to
1e-6, over the march so far or over one period, is dropped; with vapour cavities the
chamber rows count the liquid in the chamber less its cavity, which the cavity
equations conserve exactly) and solves

.. math:: (M - I)\\, Z\\, a = -(x(T) - x_0), \\qquad \\Delta x = Z a,

in the least-squares sense, ``Z`` spanning the tangent space of the level set and
``M Z`` from central differences of the one-period map, in coordinates scaled by
how far each state swings over one period (with the nominal state scales an almost
air-free chamber, B ~ 1.4 GPa, has nearly dependent invariant rows; an earlier
bordered least-squares form stalled there).  A Newton step is taken only if it
reduces the residual (step halving), otherwise one marched period.  A residual
that stalls at the integration error of a one-period run tightens the runs tenfold
(down to ``MIN_RTOL``).  Where the iterations run out above the tolerance the shooting
raises, unless the residual is below ``ShootingOptions.accept`` (a caller that tolerates
an orbit periodic to the one-period runs' integration error: the record simulation,
whose fit preset integrates at rtol 1e-6), where the orbit is returned with
``stats["accepted"]`` True and its message says so.  ``ShootingOptions.budget`` bounds
the integrator steps of all one-period runs together (in first periods; the cost is
``stats["shooting_cost"]``): past it the shooting stops as when its iterations run out.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (3), (10).
.. [2] R. Seydel, Practical Bifurcation and Stability Analysis, 3rd ed.,
   Springer 2010, Ch. 7 (shooting for periodic solutions).
.. [3] J. E. Dennis, R. B. Schnabel, Numerical Methods for Unconstrained
   Optimization and Nonlinear Equations, SIAM 1996, Sec. 5.4, 6.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from liquidamp.coupled.invariants import invariants, project_level_set
from liquidamp.errors import ConvergenceError, ParameterError, PressureError, check_choice

__all__ = ["periodic_state", "PeriodicState", "ShootingOptions", "ROUTES", "state_swing",
           "FD_STEP", "STEP_LENGTHS", "STALL_RATIO", "MIN_RTOL", "RHO_STALL", "FIRST_CHUNK",
           "FINE_GRID_FACTOR", "RUN_STEPS"]

#: Routes of :func:`periodic_state`: march then shoot, march alone, shoot alone, and the
#: auto route's march without its shooting (``"no_shooting"``: where the march stalls or
#: is too slow, the ConvergenceError of a failed shooting, with the last marched period).
ROUTES = ("auto", "march", "shooting", "no_shooting")

#: Half-step of the central differences of the monodromy matrix, as a fraction
#: of each state's swing over one period [-].
FD_STEP = 1e-4

#: Step lengths tried for a Newton step before the iteration falls back to
#: one marched period [-].
STEP_LENGTHS = (1.0, 0.5, 0.25)

#: A residual above this fraction of its value two iterations before counts as stalled.
STALL_RATIO = 0.7

#: Tightest relative tolerance the one-period runs are tightened to [-].
MIN_RTOL = 1e-12

#: A march whose contraction ratio per cycle is at or above this has stalled [-].
RHO_STALL = 0.98

#: Cycles of the first march chunk (at most ``options.max_cycles``) [-]; later chunks are
#: sized by the estimated cycles to go.
FIRST_CHUNK = 40

#: Largest relative drift of an invariant over one period for it to be held [-].
INVARIANT_DRIFT = 1e-6

#: A one-period run of the shooting is refused (ConvergenceError, like any failed run)
#: past this many times the first period's integrator steps (scaled by rtol^(-1/4) where the
#: runs were tightened; 1000 steps more for very short periods): a perturbed state that
#: runs into a much harder stretch than the orbit (a friction contact chattering behind a
#: dead band: 986 000 steps, 5 s, against 1 800 for the orbit's period) says nothing the
#: Newton step can use [-].
RUN_STEPS = 25

#: A ``grid`` of more than this many times ``options.samples_per_period`` points is not
#: marched on: the march compares the force waveforms on the uniform grid and the states at
#: ``grid`` come from one run of the final period from its start (a record at 3 kHz
#: conditioned by decimation and averaging needs the model at all its 60 000 raw phases,
#: and the force at every one of them after every marched cycle cost 25x the
#: integration) [-].
FINE_GRID_FACTOR = 4


@dataclass(frozen=True)
class ShootingOptions:
    """Knobs of the Newton shooting of :func:`periodic_state`.

    Parameters
    ----------
    tol : float, optional
        Accept when the largest change of a state over one period, relative to
        that state's scale (``model.state_scales``), is below ``tol`` [-] and the
        invariants match the start's to ``tol``.  Default ``options.steady_tol``.
    max_iter : int
        Largest number of iterations (Newton steps and marched periods) [-].
    budget : float, optional
        Most integrator steps (right-hand-side evaluations on the scipy engine) all
        one-period runs together may take, in units of the first period's [-] (a run
        tightened by the stall rule, or refused at its step limit, counts the steps it
        took).  Checked before each run; past it the shooting stops as when its iterations
        run out (raises ConvergenceError, or returns the last iterate below ``accept``; the
        final output run is not charged).  Default None: no limit beyond ``max_iter``.  For
        a caller to whom one orbit is one of hundreds (the record simulation inside a fit),
        a bound on what one hard point costs: a nearly discontinuous device (a valve
        chattering at the integration's noise) holds the residual above the tolerance while
        the stall rule tightens the runs, each tenfold tightening costing several times the
        steps.
    accept : float, optional
        Where the iterations run out with the periodicity residual below ``accept``
        (and above ``tol``), the orbit is returned as converged at the one-period runs'
        integration error, said so in its message (``PeriodicState.stats["accepted"]``
        True), instead of raising [-].  Default None: ``tol`` (raise).  For a caller
        whose use of the orbit tolerates it (the record simulation: a residual of 1e-5 of
        the chamber pressure scale p0 moves the force by 1e-5 A_p p0, a hundredth of the
        best record's noise floor), it saves the marched fallback and a second shooting
        from rest.

    Examples
    --------
    >>> ShootingOptions(max_iter=0)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: max_iter must be an integer >= 1, got 0
    >>> ShootingOptions(tol=1e-6, accept=1e-7)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: accept must lie in [tol, 1) [-], got 1e-07 (tol 1e-06)
    """

    tol: float | None = None
    max_iter: int = 40
    accept: float | None = None
    budget: float | None = None

    def __post_init__(self) -> None:
        if not (isinstance(self.max_iter, int) and not isinstance(self.max_iter, bool)
                and self.max_iter >= 1):
            raise ParameterError(f"max_iter must be an integer >= 1, got {self.max_iter!r}")
        if self.tol is not None:
            tol = float(self.tol)
            if not 0.0 < tol < 1.0:
                raise ParameterError(f"tol must lie in (0, 1) [-], got {tol:g}")
        if self.accept is not None:
            acc = float(self.accept)
            if self.tol is None and not 0.0 < acc < 1.0:
                raise ParameterError(f"accept must lie in (0, 1) [-], got {acc:g}")
            if self.tol is not None and not float(self.tol) <= acc < 1.0:
                raise ParameterError(f"accept must lie in [tol, 1) [-], got {acc:g} "
                                     f"(tol {float(self.tol):g})")
        if self.budget is not None and not float(self.budget) >= 1.0:
            raise ParameterError(f"budget must be at least 1 first-period run [-], got "
                                 f"{float(self.budget):g}")


@dataclass(frozen=True, eq=False)
class PeriodicState:
    """What :func:`periodic_state` found.

    Attributes
    ----------
    states : ndarray
        One period at ``options.samples_per_period`` uniform samples from t = 0, end
        point excluded, shape (n_states, N).
    route : str
        ``"march"`` or ``"shooting"`` (the route that arrived).
    cycles : int
        Cycles marched [-].
    runs : int
        One-period runs of the shooting (iterations and finite differences) [-].
    iterations : int
        Shooting iterations [-] (0 when the march arrived).
    residual : float
        March: estimated remaining relative change of the force waveform [-];
        shooting: periodicity residual max_i |x_i(T) - x_i(0)| / scale_i [-].
    message : str
        The route and its figures, in words.
    stats : dict
        Solver work counts, with ``route``, ``march_cycles``, ``shooting_runs``,
        ``newton_iterations``; a shot orbit also ``accepted`` (True where the iterations
        or the budget ran out below ``ShootingOptions.accept``, not below the tolerance)
        and ``shooting_cost`` (integrator work of all its one-period runs, in first
        periods [-]; :attr:`ShootingOptions.budget`).
    """

    states: np.ndarray
    route: str
    cycles: int
    runs: int
    iterations: int
    residual: float
    message: str
    stats: dict = field(default_factory=dict)


class _Manifold:
    """The level set ``g(x) = g(x_start)`` of the held invariants, in swing coordinates."""

    def __init__(self, model, params, y0, target, swing, rows):
        self.model, self.params, self.y0 = model, params, y0
        self.rows = rows
        self.target = target[rows]
        self.inv_scale = np.abs(self.target) + (self.target == 0.0)
        self.swing = swing
        self.m = self.target.size

    def gap(self, x):
        """Relative invariant gap and its gradient in swing coordinates."""
        val, G = invariants(self.model, self.params, x, self.y0)
        val, G = val[self.rows], G[self.rows]
        return (val - self.target) / self.inv_scale, G * self.swing / self.inv_scale[:, None]

    def project(self, x):
        """Nearest point of the level set (minimum-norm Gauss-Newton in swing coordinates)."""
        if self.m == 0:
            return x
        return project_level_set(x, self.gap, self.swing)

    def tangent(self, x):
        """Orthonormal basis of the tangent space at ``x`` (swing coordinates), n x (n - m)."""
        n = x.size
        if self.m == 0:
            return np.eye(n)
        _, Gs = self.gap(x)
        _, _, vt = np.linalg.svd(Gs)
        return vt[self.m:].T


def state_swing(X, scale):
    """Peak-to-peak of every state over one period, floored at 1e-6 of the largest relative
    swing times ``scale`` (same units as the states); ``scale`` where nothing swings.

    Examples
    --------
    >>> state_swing(np.array([[0.0, 2.0], [1.0, 1.0]]), np.ones(2)).tolist()
    [2.0, 2e-06]
    """
    swing = np.ptp(X, axis=1)
    rel = swing / scale
    top = float(np.max(rel)) if rel.size else 0.0
    if not np.isfinite(top) or top <= 0.0:
        return scale.copy()
    return np.maximum(swing, 1e-6 * top * scale)


# ------------------------------------------------------------------ routes
def _to_go(change: float, rho: float, tol: float) -> float:
    """Cycles until the estimated remaining change d rho / (1 - rho) falls below ``tol``."""
    if not (0.0 < rho < 1.0) or not math.isfinite(change):
        return math.inf
    if change <= 0.0:
        return 0.0
    need = tol * (1.0 - rho) / (change * rho)
    return max(math.log(need) / math.log(rho), 0.0) if need < 1.0 else 0.0


def _march(rig, engine, x0, options, stats, grid=None):
    """March in chunks while the march converges fast enough (module step 1).

    Returns ``(X, cycles, residual, change, converged, rho, why)``: the last period
    (both ends), the cycles, the rule's figures and, if not converged, why the
    march was left.
    """
    budget = int(options.max_cycles)
    chunk = min(budget, max(FIRST_CHUNK, options.min_cycles + 2))
    x = np.asarray(x0, float)
    marched = 0
    last = None  # (cycles marched, change) at the end of the previous chunk
    first = True
    while True:
        run_opts = options.replace(max_cycles=chunk,
                                   min_cycles=min(options.min_cycles, chunk) if first else 1)
        X, c, residual, change, ok = engine.march_cycles(rig, x, run_opts, stats, grid)
        marched += c
        if ok:
            return X, marched, residual, change, True, math.nan, ""
        x = X[:, -1]
        if last is not None and change > STALL_RATIO * last[1]:
            # a whole chunk (>= 10 cycles) without the change falling by 30 %: it sits at
            # the integration noise or converges slower than shooting would
            rho = (change / last[1]) ** (1.0 / (marched - last[0])) if last[1] > 0 else 1.0
            return X, marched, residual, change, False, rho, (
                f"stalled (change per cycle {last[1]:.2e} -> {change:.2e} over "
                f"{marched - last[0]} cycles)")
        if last is not None and last[1] > 0.0 and change > 0.0:
            rho = (change / last[1]) ** (1.0 / (marched - last[0]))
        elif math.isfinite(residual) and residual + change > 0.0 and residual < change:
            rho = residual / (residual + change)  # the rule's residual = change rho / (1 - rho)
        else:
            # residual >= change: the rule saw the change grow, or fall by less than half
            # per cycle after a whole chunk: taken as stalled
            rho = 1.0
        last = (marched, change)
        first = False
        left = budget - marched
        if left <= 0:
            return X, marched, residual, change, False, rho, "cycle budget spent"
        if rho >= RHO_STALL:
            return X, marched, residual, change, False, rho, (
                f"stalled (contraction {rho:.3f} per cycle)")
        to_go = _to_go(change, rho, options.steady_tol)
        if to_go > left:
            return X, marched, residual, change, False, rho, (
                f"too slow (contraction {rho:.3f} per cycle, about {to_go:.0f} cycles to "
                f"go, {left} left)")
        chunk = int(min(left, max(math.ceil(1.5 * to_go) + 3, 10), 5 * FIRST_CHUNK))


def _work(stats: dict) -> int:
    """The integrator work a run's ``stats`` count: steps on the compiled engine,
    right-hand-side evaluations on the scipy engine (the unit of ``ShootingOptions.budget``)."""
    return int(stats.get("steps", stats.get("nfev", 0)))


class _BudgetSpent(Exception):
    """Raised by a one-period run of :func:`_shoot` past ``ShootingOptions.budget``."""


def _shoot(rig, engine, x, target, options, shooting: ShootingOptions, out_grid=None):
    """Newton shooting from ``x`` with the invariant values ``target`` held (module notes).

    Returns ``(X, runs, iterations, newton, marched, residual, tightened_rtol, accepted,
    cost)`` on success (``accepted``: the iterations or the budget ran out below
    ``shooting.accept``; ``cost``: the integrator steps of all runs in first periods); raises
    ConvergenceError with the iterations and residual otherwise.
    """
    model, params, stroke = rig.model, rig.params, rig.stroke
    tol = options.steady_tol if shooting.tol is None else float(shooting.tol)
    max_iter = shooting.max_iter
    T = stroke.period
    N = options.samples_per_period
    grid = np.arange(N + 1) * (T / N)
    y0 = float(stroke(0.0)[0])
    scale = np.asarray(model.state_scales(params), float)
    from liquidamp.coupled.fast import step_period

    max_step = options.max_step_fraction * step_period(stroke)
    runs = 0
    run_opts = options  # tightened when the residual stalls at the integration error
    first = {}  # the first period's integrator steps (RUN_STEPS)
    spent = 0  # integrator steps of all runs (ShootingOptions.budget)
    charge = True

    def period(xs, t_eval=None):
        nonlocal runs, spent
        runs += 1
        te = grid[-1:] if t_eval is None else t_eval  # ends at T either way
        limit = None
        if first.get("steps"):  # a 4th-order pair's steps grow as rtol^(-1/4)
            limit = int(RUN_STEPS * first["steps"]
                        * (options.rtol / run_opts.rtol) ** 0.25) + 1000
        if (charge and shooting.budget is not None and _work(first)
                and spent > shooting.budget * _work(first)):
            raise _BudgetSpent  # not a ConvergenceError: a Newton step's trial must not eat it
        run_stats = first if limit is None else {}
        try:
            X = engine.march(rig, xs, 0.0, T, te, run_opts, max_step, run_stats,
                             max_steps=limit)
        finally:
            spent += _work(run_stats)
        return X[:, -1], X

    # one marched period removes the fast (stiff) part of the transient and shows how
    # far each state swings, and which invariants the (composed) model conserves
    x_end, X = period(x, grid)
    swing = state_swing(X, scale)
    v_start, _ = invariants(model, params, x, y0)
    v_end, _ = invariants(model, params, x_end, y0)
    size = np.abs(target) + (target == 0.0)
    # held: conserved by this (composed) model over the march so far and over one period
    held = ((np.abs(v_end - v_start) <= INVARIANT_DRIFT * size)
            & (np.abs(v_start - target) <= INVARIANT_DRIFT * size))
    rows = np.flatnonzero(held)
    level = _Manifold(model, params, y0, target, swing, rows)
    x = level.project(x_end)
    xT, _ = period(x)
    history = []
    newton = marched = tightened = since = 0
    accepted = False
    res = gap = math.inf
    it, x_at = 0, x
    try:
        for it in range(max_iter + 1):
            res = float(np.max(np.abs((xT - x) / scale)))
            g, _ = level.gap(x)
            gap = float(np.max(np.abs(g))) if g.size else 0.0
            history.append(res)
            x_at = x  # the state res and gap belong to
            if res < tol and gap < tol:
                break
            if it == max_iter:
                if shooting.accept is not None and res < shooting.accept and gap < tol:
                    accepted = True
                    break
                raise ConvergenceError(
                    f"shooting did not converge in {max_iter} iterations ({newton} Newton "
                    f"steps, {marched} marched periods, {runs} one-period runs): periodicity "
                    f"residual {res:.2e}, invariant gap {gap:.1e} (allowed {tol:g} for both); "
                    f"last residuals {', '.join(f'{h:.1e}' for h in history[-5:])}")
            if (len(history) - since >= 3 and min(history[-2:]) > STALL_RATIO * history[-3]
                    and run_opts.rtol > MIN_RTOL):
                # stalled for two iterations: the residual sits at the integration error of
                # a one-period run (tens of rtol over a period), so tighten the runs tenfold
                run_opts = run_opts.replace(rtol=max(run_opts.rtol / 10.0, MIN_RTOL))
                tightened += 1
                since = len(history)
                xT, _ = period(x)
                continue
            w = (xT - x) / swing
            Z = level.tangent(x)
            J = np.empty((x.size, Z.shape[1]))
            for k in range(Z.shape[1]):
                dx = FD_STEP * Z[:, k] * swing
                xp, _ = period(level.project(x + dx))
                xm, _ = period(level.project(x - dx))
                J[:, k] = (xp - xm) / (2.0 * FD_STEP * swing)
            J -= Z
            step = Z @ np.linalg.lstsq(J, -w, rcond=None)[0]
            norm_w = float(np.linalg.norm(w))
            for lam in STEP_LENGTHS:
                x_try = level.project(x + lam * step * swing)
                try:
                    xT_try, _ = period(x_try)
                except (ConvergenceError, PressureError):
                    continue
                if np.linalg.norm((xT_try - x_try) / swing) < (1.0 - 1e-4 * lam) * norm_w:
                    x, xT = x_try, xT_try
                    newton += 1
                    break
            else:
                # no Newton step improves: march one period (converges as marching does)
                x = level.project(xT)
                xT, _ = period(x)
                marched += 1
    except _BudgetSpent:
        if not (shooting.accept is not None and res < shooting.accept and gap < tol):
            raise ConvergenceError(
                f"shooting spent its budget in iteration {it} ({newton} Newton steps, "
                f"{marched} marched periods, {runs} one-period runs): integrator work "
                f"{spent} ({engine.name} engine: steps or right-hand-side evaluations), "
                f"more than {shooting.budget:g} x the first period's {_work(first)}; "
                f"periodicity residual {res:.2e}, invariant gap {gap:.1e} "
                f"(allowed {tol:g} for both)") from None
        x, accepted = x_at, True
    charge = False  # the output run is not charged to the budget
    xe, X = period(x, grid if out_grid is None else out_grid)
    res = float(np.max(np.abs((xe - x) / scale)))
    cost = spent / _work(first) if _work(first) else math.nan
    return (X, runs, len(history) - 1, newton, marched, res,
            run_opts.rtol if tightened else None, accepted, cost)


def periodic_state(rig, engine, x0, options, *, route: str = "auto",
                   shooting: ShootingOptions | None = None,
                   invariants_of=None, grid=None) -> PeriodicState:
    """Periodic steady state of a device on the test machine (module steps 1-3).

    Parameters
    ----------
    rig : TestRig
        The device and its periodic stroke (attribute ``period`` [s]:
        :class:`~liquidamp.structure.testmachine.HarmonicStroke`, a commensurate
        :class:`~liquidamp.structure.testmachine.TwoFrequencyStroke` or a
        :class:`~liquidamp.structure.testmachine.FourierStroke`).
    engine : Engine
        The integration engine (:func:`liquidamp.coupled.engines.engine_for`).
    x0 : array
        Initial state (a first guess); its invariants select the orbit.
    options : SolverOptions
        Tolerances, ``steady_tol``, ``min_cycles``, ``max_cycles`` (the march's
        budget) and ``samples_per_period``.
    route : {"auto", "march", "shooting", "no_shooting"}
        ``"auto"``: march, then shoot where the march stalls or is too slow;
        ``"march"``: the march alone (raises after ``max_cycles``);
        ``"shooting"``: one marched period, then Newton;
        ``"no_shooting"``: the auto route's march, and where it stalls or is too slow the
        error a failed shooting raises (with ``marched``), without shooting: for a caller
        that treats a state not reached by the march as not periodic anyway (a ranking
        screen), the Newton iterations it would spend.
    shooting : ShootingOptions, optional
        Tolerance and iterations of the Newton shooting.
    invariants_of : array, optional
        A state whose invariants select the orbit (default ``x0``; give the rest
        state when ``x0`` is a warm start whose invariants are already those).
    grid : array, optional
        Sorted times within one period [s] from 0, the last at the period's end,
        at which the states are returned (and the march's force waveforms
        compared); default ``options.samples_per_period`` uniform samples.

    Returns
    -------
    PeriodicState

    Raises
    ------
    ConvergenceError
        Neither route arrived (both routes' figures in the message; with route
        ``"auto"`` or ``"no_shooting"`` its attribute ``marched`` holds (last marched
        period on ``grid``, cycles, last change per cycle)).
    PressureError
        A chamber pressure at the floor during the march.

    Examples
    --------
    >>> from liquidamp.coupled.engines import TestRig, engine_for
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.options import SolverOptions
    >>> from liquidamp.structure.testmachine import HarmonicStroke
    >>> m, p, o = get_model("full"), preset("spring"), SolverOptions(engine="compiled")
    >>> rig = TestRig(m, p, HarmonicStroke(1e-6, 4.0))  # the march stalls at the noise
    >>> s = periodic_state(rig, engine_for(rig, o), m.initial_state(p, 0.0), o)
    >>> s.route, s.residual < 1e-6
    ('shooting', True)
    """
    check_choice("periodic-state route", route, ROUTES)
    shooting = ShootingOptions() if shooting is None else shooting
    model, params, stroke = rig.model, rig.params, rig.stroke
    x0 = np.asarray(x0, float)
    y0 = float(stroke(0.0)[0])
    ref = x0 if invariants_of is None else np.asarray(invariants_of, float)
    target, _ = invariants(model, params, ref, y0)
    stats: dict = {}
    where = stroke.describe() if hasattr(stroke, "describe") else "this stroke"
    name = f"model {model.name!r}"
    fine = None
    if grid is not None:
        grid = np.asarray(grid, float)
        T = stroke.period
        if (grid.ndim != 1 or grid.size < 2 or grid[0] < 0.0 or np.any(np.diff(grid) <= 0.0)
                or abs(grid[-1] - T) > 1e-12 * T):
            raise ParameterError(f"grid must be increasing times in [0, {T:g}] s ending at the "
                                 "period's end")
        if grid.size > FINE_GRID_FACTOR * options.samples_per_period + 1:
            # march on the uniform grid; the fine grid from the final period (FINE_GRID_FACTOR)
            fine, grid = grid, None

    def on_grid(X):
        """The last marched period ``X`` (both ends, on the march's grid) at ``fine``."""
        if fine is None:
            return X
        from liquidamp.coupled.fast import step_period

        return engine.march(rig, X[:, 0], 0.0, stroke.period, fine, options,
                            options.max_step_fraction * step_period(stroke), {})
    if route == "march":
        X, cycles, residual, change, ok = engine.march_cycles(rig, x0, options, stats, grid)
        if not ok:
            raise ConvergenceError(
                f"{name}: no periodic steady state after {options.max_cycles} cycles at "
                f"{where}; last relative change per cycle {change:.2e}, estimated remaining "
                f"{residual:.2e} (allowed {options.steady_tol:g}); raise max_cycles or "
                "steady_tol")
        X = on_grid(X)[:, :-1]
        stats.update(route="march", march_cycles=cycles, shooting_runs=0, newton_iterations=0)
        msg = (f"periodic steady state after {cycles} cycles (march); estimated remaining "
               f"change {residual:.2e} of peak force ({engine.name} engine)")
        return PeriodicState(X, "march", cycles, 0, 0, residual, msg, stats)
    cycles, change, why, x = 0, math.nan, "", x0
    if route in ("auto", "no_shooting"):
        X, cycles, residual, change, ok, rho, why = _march(rig, engine, x0, options, stats,
                                                           grid)
        if ok:
            stats.update(route="march", march_cycles=cycles, shooting_runs=0,
                         newton_iterations=0)
            msg = (f"periodic steady state after {cycles} cycles (march); estimated remaining "
                   f"change {residual:.2e} of peak force ({engine.name} engine)")
            return PeriodicState(on_grid(X)[:, :-1], "march", cycles, 0, 0, residual, msg,
                                 stats)
        x = X[:, -1]
        if route == "no_shooting":
            err = ConvergenceError(
                f"{name}: no periodic steady state at {where}: the march {why} after {cycles} "
                f"cycles, last relative change per cycle {change:.2e} (allowed "
                f"{options.steady_tol:g} remaining); not shot (route 'no_shooting')")
            err.marched = (on_grid(X)[:, :-1], cycles, change)
            raise err
    try:
        X, runs, iters, newton, marched, res, rtol, accepted, cost = _shoot(
            rig, engine, x, target, options, shooting, grid if fine is None else fine)
    except ConvergenceError as exc:
        if route == "shooting":
            raise ConvergenceError(f"{name} at {where}: {exc}") from None
        err = ConvergenceError(
            f"{name}: no periodic steady state at {where}: the march {why} after {cycles} "
            f"cycles, last relative change per cycle {change:.2e} (allowed "
            f"{options.steady_tol:g} remaining); then {exc}; raise max_cycles, steady_tol "
            "or the shooting's max_iter")
        # the last marched period (on ``grid``, end point excluded), for a caller that can
        # use a state that is not periodic and says so
        err.marched = (on_grid(X)[:, :-1], cycles, change)
        raise err from None
    stats.update(route="shooting", march_cycles=cycles, shooting_runs=runs,
                 newton_iterations=iters, accepted=accepted, shooting_cost=cost)
    msg = (f"periodic orbit by shooting: {iters} iterations ({newton} Newton steps, "
           f"{marched} marched periods), {runs} one-period runs; periodicity residual "
           f"{res:.2e} of the state scales")
    if rtol is not None:
        msg += f"; one-period runs tightened to rtol {rtol:g} (residual stalled)"
    if accepted:
        tol = options.steady_tol if shooting.tol is None else shooting.tol
        msg += (f"; accepted after {iters} iterations below {shooting.accept:g}, not "
                f"below the tolerance {tol:g}")
    if route == "auto":
        msg = (f"march {why} after {cycles} cycles (last change per cycle {change:.2e}); "
               + msg)
    msg += f" ({engine.name} engine)"
    return PeriodicState(X[:, :-1], "shooting", cycles, runs, iters, res, msg, stats)
