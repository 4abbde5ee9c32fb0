"""Periodic steady state without marching through the transient: shooting.

:func:`periodic_orbit` solves for the initial state ``x0`` of the periodic
orbit under a harmonic stroke directly, by a Gauss-Newton iteration on the
one-period map, ``x(T; x0) - x0 = 0``, instead of marching cycles until the
transient has died out (:func:`liquidamp.coupled.testrig.steady_state`).
Slow transients (air-rich chambers, a large inertance) need tens of cycles
to march out but only a few Newton steps to jump over.

The sealed device has invariants (Titurus 2018, eq. 10; DESIGN.md): the
total fluid mass, and in each chamber the relation between density and
pressure (``ln rho_i - integral dp / B_i(p)`` is constant, i.e.
``rho_i = r_i(p_i)`` from the rest state).  Each invariant puts a Floquet
multiplier at exactly 1, so the periodic orbits form a family and
``x(T) - x0`` has a singular Jacobian.  The iteration therefore solves the
bordered, over-determined system

.. math:: \\begin{bmatrix} M - I \\\\ G \\end{bmatrix} \\Delta x =
          -\\begin{bmatrix} x(T) - x_0 \\\\ g(x_0) \\end{bmatrix}

in the least-squares sense, where ``M`` is the monodromy matrix (finite
differences of the one-period map, one run per state) and ``g`` the
invariants measured against those of the starting state, which selects the
orbit that the time-domain march from the same start converges to.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (3), (10).
.. [2] R. Seydel, Practical Bifurcation and Stability Analysis, 3rd ed.,
   Springer 2010, Ch. 7 (shooting for periodic solutions).
"""

from __future__ import annotations

import math

import numpy as np

from liquidamp.coupled.testrig import DeviceResponse, _march, _prepare, _response, steady_state
from liquidamp.device.fluid import density_gholizadeh
from liquidamp.device.models import DeviceModel
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, check_choice
from liquidamp.structure.testmachine import HarmonicStroke

__all__ = ["periodic_orbit", "invariants", "METHODS"]

#: Solution methods of :func:`periodic_orbit`.
METHODS = ("shooting",)


def _chamber_density(p, chamber: int, params: DeviceParams) -> tuple[float, float]:
    """r_i(p) on the rest-state curve and its slope r_i / B_i(p) [kg/m^3, kg/(m^3 Pa)]."""
    X0 = params.X01 if chamber == 1 else params.X02
    B = params.bulk_modulus_at(max(p, 1.0), chamber)
    if params.bulk_law == "constant":
        r = params.rho0 * math.exp((p - params.p0) / B)
    else:
        r = float(density_gholizadeh(max(p, 1.0), params.rho0, params.B_l, X0, params.p0,
                                     params.n))
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
        to that state's scale (``model.state_scales``), is below ``tol`` [-].
        Default ``options.steady_tol``.
    max_iter : int
        Largest number of Newton iterations.

    Returns
    -------
    DeviceResponse
        One period (``options.samples_per_period`` samples, end point
        excluded, time from 0), ``status = "steady"``, ``residual`` the
        periodicity residual max_i |x_i(T) - x_i(0)| / scale_i, ``cycles``
        the one-period runs spent (Newton and finite differences).

    Raises
    ------
    ConvergenceError
        If the iteration does not reach ``tol`` within ``max_iter`` steps.
    ParameterError, PressureError
        As :func:`~liquidamp.coupled.testrig.steady_state`.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.options import SolverOptions
    >>> r = periodic_orbit("full", preset("reference"), HarmonicStroke(0.003, 3.0),
    ...                    SolverOptions(engine="compiled"))
    >>> r.status, r.residual < 1e-6, r.mass_error < 1e-9
    ('steady', True, True)
    """
    model, options = _prepare(model, params, stroke, options)
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
    n = model.n_states
    grid = np.arange(N + 1) * (T / N)
    y0 = float(stroke(0.0)[0])
    x = model.initial_state(params, y0) if x0 is None else np.asarray(x0, float).copy()
    scale = np.asarray(model.state_scales(params), float)
    inv_target, _ = invariants(model, params, x, y0)
    inv_scale = np.abs(inv_target) + (inv_target == 0.0)
    max_step = options.max_step_fraction * T
    runs = 0

    if options.engine == "compiled":
        from liquidamp.coupled.fast import march as fast_march

        def period(xs, t_eval=None):
            nonlocal runs
            runs += 1
            te = grid[-1:] if t_eval is None else t_eval
            X, xe, _ = fast_march(model, params, stroke, xs, 0.0, T, te, options, max_step)
            return xe, X
    else:
        def period(xs, t_eval=None):
            nonlocal runs
            runs += 1
            te = grid[-1:] if t_eval is None else t_eval
            sol = _march(model, params, stroke, xs, 0.0, T, te, options, max_step)
            return sol.y[:, -1], sol.y

    # one marched period removes the fast (stiff) part of the transient
    x, _ = period(x)
    xT, _ = period(x)
    history = []
    for it in range(max_iter + 1):
        r = (xT - x) / scale
        g_val, G = invariants(model, params, x, y0)
        g = (g_val - inv_target) / inv_scale
        res = float(np.max(np.abs(r)))
        history.append(res)
        if res < tol and (g.size == 0 or float(np.max(np.abs(g))) < tol):
            break
        if it == max_iter:
            raise ConvergenceError(
                f"model {model.name!r}: shooting did not converge in {max_iter} Newton "
                f"iterations at {stroke.frequency:g} Hz, {stroke.amplitude:g} m; periodicity "
                f"residual {res:.2e} (allowed {tol:g}); history "
                f"{', '.join(f'{h:.1e}' for h in history[-5:])}"
            )
        # monodromy matrix by forward differences, in scaled coordinates
        M = np.empty((n, n))
        for j in range(n):
            d = 1e-5 * scale[j]
            xp = x.copy()
            xp[j] += d
            xTp, _ = period(xp)
            M[:, j] = (xTp - xT) / scale / (d / scale[j])
        A = np.vstack([M - np.eye(n), G * scale / inv_scale[:, None]])
        b = -np.concatenate([r, g])
        dz, *_ = np.linalg.lstsq(A, b, rcond=None)
        # damped update: halve until the residual does not grow much
        lam = 1.0
        for _ in range(8):
            x_new = x + lam * dz * scale
            try:
                xT_new, _ = period(x_new)
            except ConvergenceError:
                lam *= 0.5
                continue
            if np.max(np.abs((xT_new - x_new) / scale)) < max(2.0 * res, 10 * tol):
                break
            lam *= 0.5
        else:
            raise ConvergenceError(
                f"model {model.name!r}: shooting step failed at {stroke.frequency:g} Hz "
                f"(periodicity residual {res:.2e})"
            )
        x, xT = x_new, xT_new
    xe, X = period(x, grid)
    res = float(np.max(np.abs((xe - x) / scale)))
    msg = (f"periodic orbit by shooting: {len(history) - 1} Newton iterations, "
           f"{runs} one-period runs; periodicity residual {res:.2e} of the state scales")
    return _response(model, params, stroke, grid[:N], X[:, :N], options, status="steady",
                     message=msg, residual=res, cycles=runs)
