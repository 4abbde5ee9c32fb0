"""Periodic steady state without marching through the transient: shooting.

:func:`periodic_orbit` solves for the initial state ``x0`` of the periodic
orbit under a harmonic stroke directly, by a Gauss-Newton iteration on the
one-period map, ``x(T; x0) - x0 = 0``, instead of marching cycles until the
transient has died out (:func:`liquidamp.coupled.testrig.steady_state`).
Slow transients (air-rich chambers, a large inertance) need tens of cycles
to march out but only a few Newton steps to jump over.

The sealed device has invariants (Titurus 2018, eq. 10): the
total fluid mass, and in each chamber the relation between density and
pressure (``ln rho_i - integral dp / B_i(p)`` is constant, i.e.
``rho_i = r_i(p_i)`` from the rest state).  Each invariant puts a Floquet
multiplier at exactly 1, so the periodic orbits form a family and
``x(T) - x0`` has a singular Jacobian.  The iteration therefore holds
the invariants of the starting state exactly (every iterate is projected
onto their level set, which selects the orbit that the time-domain march
from the same start converges to) and solves the Newton equation

.. math:: (M - I)\\, Z\\, a = -(x(T) - x_0), \\qquad \\Delta x = Z a,

in the least-squares sense, where ``Z`` spans the tangent space of the
level set and ``M Z`` (the monodromy matrix on it) comes from central
differences of the one-period map.  All of this is done in coordinates
scaled by how far each state swings over one period: with the nominal
state scales (``rho_l`` for a density) an almost air-free chamber
(``inerter`` preset, B ~ 1.4 GPa) has invariant rows whose pressure
entries are only p0 / B ~ 7e-5 of their density entries, so the three rows
are nearly dependent, and an earlier bordered least-squares form
``[M - I; G] dx = -[x(T) - x0; g]`` in those coordinates (smallest
singular value ~1e-4) traded an invariant gap of 4e-5 (half a bar of
pressure) against the periodicity residual and stalled.  A Newton step is
taken only if it reduces the residual (with step halving); otherwise one
marched period is taken, so, given enough iterations, the iteration
converges wherever marching does.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (3), (10).
.. [2] R. Seydel, Practical Bifurcation and Stability Analysis, 3rd ed.,
   Springer 2010, Ch. 7 (shooting for periodic solutions).
"""

from __future__ import annotations

import math

import numpy as np

from liquidamp.coupled.engines import TestRig, engine_for
from liquidamp.coupled.testrig import DeviceResponse, build_response, prepare_run, steady_state
from liquidamp.device.fluid import density_gholizadeh
from liquidamp.device.models import DeviceModel
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError, check_choice
from liquidamp.structure.testmachine import HarmonicStroke

__all__ = ["periodic_orbit", "invariants", "METHODS"]

#: Solution methods of :func:`periodic_orbit`.
METHODS = ("shooting",)


def _chamber_density(p, chamber: int, params: DeviceParams) -> tuple[float, float]:
    """r_i(p) on the rest-state curve and its slope r_i / B_i(p) [kg/m^3, kg/(m^3 Pa)].

    The Gholizadeh curve is the integral of eq. (3) with eq. (2)
    (:func:`liquidamp.device.fluid.density_gholizadeh`).
    """
    X0 = params.X01 if chamber == 1 else params.X02
    p = max(p, 1.0)
    B = params.bulk_modulus_at(p, chamber)
    if params.bulk_law == "constant":
        r = params.rho0 * math.exp((p - params.p0) / B)
    else:
        r = density_gholizadeh(p, params.rho0, params.B_l, X0, params.p0, params.n)
    return r, r / B


def invariants(model: DeviceModel, params: DeviceParams, x, y: float):
    """Conserved quantities of ``model`` at state ``x`` and stroke ``y`` and their gradients.

    Parameters
    ----------
    model : DeviceModel
        Device model.
    params : DeviceParams
        Parameters.
    x : array
        State.
    y : float
        Stroke [m] (the chamber volumes enter the total mass).

    Returns
    -------
    values : ndarray
        ``[rho1 / r1(p1), rho2 / r2(p2), M]`` for eqs. (10)-(11) (the density
        ratios are 1 on the rest-state curve; M the total mass [kg]),
        ``[M]`` for eqs. (13), (17), empty for the others.
    gradient : ndarray
        d values / dx, shape (len(values), n_states).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> p = preset("reference")
    >>> v, G = invariants(get_model("full"), p, get_model("full").initial_state(p, 0.0), 0.0)
    >>> bool(abs(v[0] - 1) < 1e-12), bool(abs(v[2] / (p.rho_l * (p.V01 + p.V02)) - 1) < 1e-12)
    (True, True)
    """
    x = np.asarray(x, float)
    n = model.n_states
    V1, V2 = params.V01 - params.A_p * y, params.V02 + params.A_p * y
    if model.name in ("full", "no_inertia"):
        G = np.zeros((3, n))
        vals = np.zeros(3)
        for k, (ip, ir) in enumerate(((0, 1), (2, 3))):
            r, dr = _chamber_density(x[ip], k + 1, params)
            vals[k] = x[ir] / r
            G[k, ir] = 1.0 / r
            G[k, ip] = -x[ir] * dr / (r * r)
        vals[2] = x[1] * V1 + x[3] * V2
        G[2, 1], G[2, 3] = V1, V2
        return vals, G
    if model.name in ("constant_bulk", "inertial"):
        r1 = params.rho0 * math.exp((x[0] - params.p0) / params.B01)
        r2 = params.rho0 * math.exp((x[1] - params.p0) / params.B02)
        G = np.zeros((1, n))
        G[0, 0], G[0, 1] = r1 / params.B01 * V1, r2 / params.B02 * V2
        return np.array([r1 * V1 + r2 * V2]), G
    return np.zeros(0), np.zeros((0, n))


#: Half-step of the central differences of the monodromy matrix, as a fraction
#: of each state's swing over one period [-] (see :func:`periodic_orbit`).
FD_STEP = 1e-4

#: Step lengths tried for a Newton step before the iteration falls back to
#: one marched period [-].
STEP_LENGTHS = (1.0, 0.5, 0.25)


#: A residual above this fraction of its value two iterations before counts as stalled.
STALL_RATIO = 0.7
#: Tightest relative tolerance the one-period runs are tightened to [-].
MIN_RTOL = 1e-12


class _Manifold:
    """The level set ``g(x) = g(x_start)`` of the invariants, in swing coordinates.

    Coordinates are ``z = x / swing`` (``swing``: how much each state moves
    over one period), in which the density of an almost air-free chamber and
    its pressure weigh alike; with ``model.state_scales`` (``rho_l`` for a
    density) a density change that moves the pressure by a full scale is
    ``B / p0`` (about 1e4 for the ``inerter`` preset) times smaller than a
    pressure change of one scale, and the invariant rows of the bordered
    system become nearly dependent.
    """

    def __init__(self, model, params, y0, target, swing):
        self.model, self.params, self.y0 = model, params, y0
        self.target = target
        self.inv_scale = np.abs(target) + (target == 0.0)
        self.swing = swing
        self.m = target.size

    def gap(self, x):
        """Relative invariant gap and its gradient in swing coordinates."""
        val, G = invariants(self.model, self.params, x, self.y0)
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


def project_level_set(x, gap, scale, cols=slice(None)):
    """Nearest point of a level set g(x) = 0 by minimum-norm Gauss-Newton, states ``cols``
    moved only.

    Parameters
    ----------
    x : ndarray
        Start state (units of the states).
    gap : callable
        ``gap(x) -> (g, Gs)``: scaled residuals [-] and their Jacobian in the scaled
        coordinates x / ``scale``.
    scale : ndarray
        State scales (units of the states).
    cols : slice or index array
        States the projection may move (default: all).

    Returns
    -------
    ndarray
        At most 12 steps, stopped once |g| < 1e-15 or a step fails to halve it.
    """
    x = np.array(x, float)
    last = math.inf
    for _ in range(12):
        g, Gs = gap(x)
        size = float(np.max(np.abs(g)))
        if size < 1e-15 or size >= 0.5 * last:
            break
        last = size
        step = np.zeros_like(x)
        step[cols] = np.linalg.lstsq(Gs[:, cols], g, rcond=None)[0]
        x = x - scale * step
    return x


def state_swing(X, scale):
    """Peak-to-peak of every state over one period, floored at 1e-6 of the largest relative
    swing times ``scale`` (same units as the states); ``scale`` where nothing swings."""
    swing = np.ptp(X, axis=1)
    rel = swing / scale
    top = float(np.max(rel)) if rel.size else 0.0
    if not np.isfinite(top) or top <= 0.0:
        return scale.copy()
    return np.maximum(swing, 1e-6 * top * scale)


def periodic_orbit(model, params: DeviceParams, stroke: HarmonicStroke, options=None,
                   method: str = "shooting", *, x0=None, tol: float | None = None,
                   max_iter: int = 25) -> DeviceResponse:
    """Periodic steady state under a harmonic stroke by shooting (no transient march).

    Parameters
    ----------
    model : str or DeviceModel
        Registered model.
    params : DeviceParams
        Device parameters.
    stroke : HarmonicStroke
        Excitation.
    options : SolverOptions, optional
        Tolerances and engine of every one-period run
        (``engine="compiled"`` makes the solve take milliseconds).
    method : {"shooting"}
        Solution method.
    x0 : array, optional
        Starting state; its invariants (total mass, density-pressure
        relation) select the orbit.  Default: rest at ``p0``, as
        :func:`~liquidamp.coupled.testrig.steady_state`.
    tol : float, optional
        Accept when the largest change of a state over one period, relative
        to that state's scale (``model.state_scales``), is below ``tol`` [-],
        and the invariants match those of the start to ``tol`` (relative).
        Default ``options.steady_tol``.
    max_iter : int
        Largest number of iterations (Newton steps and marched periods).

    Returns
    -------
    DeviceResponse
        One period (``options.samples_per_period`` samples, end point
        excluded, time from 0), ``status = "steady"``, ``residual`` the
        periodicity residual max_i |x_i(T) - x_i(0)| / scale_i, ``cycles``
        the one-period runs spent (iterations and finite differences).

    Raises
    ------
    ConvergenceError
        If the iteration does not reach ``tol`` within ``max_iter`` steps
        (the message gives the iterations, the last residual and ``tol``);
        also for a model without a periodic state (``volumetric``, eq. 14,
        whose mean pressures drift every cycle).
    ParameterError, PressureError
        As :func:`~liquidamp.coupled.testrig.steady_state`.

    Notes
    -----
    The iteration, after one marched period from the start:

    1. Coordinates ``z_i = x_i / s_i`` with ``s_i`` the swing (peak to peak)
       of state ``i`` over that first period [units of the state].
    2. Every iterate is projected onto the level set of the invariants of
       the start (minimum-norm Gauss-Newton in ``z``, no integration), so the
       invariants are held exactly instead of being traded against the
       periodicity residual.
    3. The monodromy matrix ``M`` is needed only on the tangent space of that
       level set (``n - m`` directions for ``m`` invariants, orthonormal in
       ``z``, where the Floquet multipliers at 1 are absent); it is formed
       by central differences with half-step ``FD_STEP`` swings, well
       above the integration error of a one-period run (relative
       ``options.rtol``) and well below the nonlinearity.
    4. The Newton step solves ``(M - I) Z a = -(x(T) - x_0) / s`` in the
       least-squares sense; it is taken with the lengths ``STEP_LENGTHS``
       until the periodicity residual (2-norm in ``z``) decreases, and if
       none does, one marched period ``x_0 <- x(T)`` is taken instead, which
       converges wherever :func:`~liquidamp.coupled.testrig.steady_state`
       does (far from the orbit the one-period map of an almost air-free
       device is strongly nonlinear: multipliers of several hundred were
       seen where the orbit's are below 0.2).
    5. When the residual has not fallen below ``STALL_RATIO`` of its value
       two iterations before, it sits at the integration error of a
       one-period run (the global error of a period is tens of ``rtol``;
       inerter preset at 7 Hz, 2 mm: 1.7e-6 with Dormand-Prince at rtol
       1e-8), and the one-period runs are tightened tenfold, down to
       ``MIN_RTOL``.

    References
    ----------
    .. [1] B. Titurus, AIAA J. 56(10), 2018, eq. (10).
    .. [2] R. Seydel, Practical Bifurcation and Stability Analysis, 3rd ed.,
       Springer 2010, Sec. 7.1-7.3 (shooting, monodromy matrix).
    .. [3] J. E. Dennis, R. B. Schnabel, Numerical Methods for Unconstrained
       Optimization and Nonlinear Equations, SIAM 1996, Sec. 6.3 (line
       search), Sec. 5.4 (finite-difference Jacobians).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.options import SolverOptions
    >>> r = periodic_orbit("full", preset("reference"), HarmonicStroke(0.003, 3.0),
    ...                    SolverOptions(engine="compiled"))
    >>> r.status, r.residual < 1e-6, r.mass_error < 1e-9
    ('steady', True, True)

    Almost air-free chambers (bulk modulus ~1.4 GPa):

    >>> r = periodic_orbit("full", preset("inerter"), HarmonicStroke(0.001, 3.0),
    ...                    SolverOptions(engine="compiled"))
    >>> r.residual < 1e-6, r.cycles < 40  # one-period runs (a march needs 12 cycles)
    (True, True)
    """
    model, options = prepare_run(model, params, stroke, options)
    check_choice("periodic-orbit method", method, METHODS)
    if not isinstance(stroke, HarmonicStroke):
        raise ParameterError("periodic_orbit needs a HarmonicStroke")
    if not (isinstance(max_iter, int) and max_iter >= 1):
        raise ParameterError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    tol = options.steady_tol if tol is None else float(tol)
    if not 0.0 < tol < 1.0:
        raise ParameterError(f"tol must lie in (0, 1) [-], got {tol:g}")
    if model.n_states == 0:
        return steady_state(model, params, stroke, options=options)
    T = stroke.period
    N = options.samples_per_period
    grid = np.arange(N + 1) * (T / N)
    y0 = float(stroke(0.0)[0])
    x = model.initial_state(params, y0) if x0 is None else np.asarray(x0, float).copy()
    scale = np.asarray(model.state_scales(params), float)
    inv_target, _ = invariants(model, params, x, y0)
    max_step = options.max_step_fraction * T
    runs = 0
    run_opts = options  # tightened when the residual stalls at the integration error

    rig = TestRig(model, params, stroke)
    engine = engine_for(rig, options)

    def period(xs, t_eval=None):
        nonlocal runs
        runs += 1
        te = grid[-1:] if t_eval is None else t_eval  # ends at T either way
        X = engine.march(rig, xs, 0.0, T, te, run_opts, max_step, {})
        return X[:, -1], X

    # one marched period removes the fast (stiff) part of the transient and
    # shows how far each state swings
    x, X = period(x, grid)
    swing = state_swing(X, scale)
    level = _Manifold(model, params, y0, inv_target, swing)
    x = level.project(x)
    xT, _ = period(x)
    history = []
    newton = marched = tightened = since = 0
    for it in range(max_iter + 1):
        res = float(np.max(np.abs((xT - x) / scale)))
        g, _ = level.gap(x)
        gap = float(np.max(np.abs(g))) if g.size else 0.0
        history.append(res)
        if res < tol and gap < tol:
            break
        if (len(history) - since >= 3 and min(history[-2:]) > STALL_RATIO * history[-3]
                and run_opts.rtol > MIN_RTOL):
            # stalled for two iterations: the residual sits at the integration error of a
            # one-period run (tens of rtol over a period), so tighten the runs tenfold
            run_opts = run_opts.replace(rtol=max(run_opts.rtol / 10.0, MIN_RTOL))
            tightened += 1
            since = len(history)
            xT, _ = period(x)
            continue
        if it == max_iter:
            raise ConvergenceError(
                f"model {model.name!r}: shooting did not converge in {max_iter} iterations "
                f"({newton} Newton steps, {marched} marched periods) at "
                f"{stroke.frequency:g} Hz, {stroke.amplitude:g} m: periodicity residual "
                f"{res:.2e}, invariant gap {gap:.1e} (allowed {tol:g} for both); last "
                f"residuals {', '.join(f'{h:.1e}' for h in history[-5:])}"
            )
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
    xe, X = period(x, grid)
    res = float(np.max(np.abs((xe - x) / scale)))
    msg = (f"periodic orbit by shooting: {len(history) - 1} iterations ({newton} Newton steps, "
           f"{marched} marched periods), {runs} one-period runs; periodicity residual "
           f"{res:.2e} of the state scales")
    if tightened:
        msg += f"; one-period runs tightened to rtol {run_opts.rtol:g} (residual stalled)"
    return build_response(model, params, stroke, grid[:N], X[:, :N], options, status="steady",
                     message=msg, residual=res, cycles=runs)
