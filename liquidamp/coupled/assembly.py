"""The device inside the structure: host + device(s) as one nonlinear system.

A *host* is a linear state-space structure with named signals and device
ports (:mod:`liquidamp.structure.port`): constant (a wing section,
:class:`control.StateSpace`) or periodic (a rotor in the rotating frame,
:class:`~liquidamp.structure.port.PeriodicStateSpace`).  A *device* is any
:class:`~liquidamp.device.models.DeviceModel` (every registered variant, with
or without add-on effects) with its parameters.  :func:`couple` joins them by
port name; the coupled state is the host state followed by each device's
states::

    x_h' = A(t) x_h + B_F(t) F + B_u(t) u(t)   (host, forces F at its ports, inputs u)
    y_j  = C_y,j x_h,  v_j = C_v,j x_h          (stroke [m] and rate [m/s] of port j)
    a_j  = C_v,j (A x_h + B_F F)                (stroke acceleration [m/s^2])
    z_j' = f_j(t, z_j, (y_j, v_j, a_j))         (device j, full nonlinear model)
    F_j  = F_j(t, z_j, (y_j, v_j, a_j))         (device force, host convention of the port)

External inputs
    ``u(t)``: known harmonic signals on host inputs that take no device
    force (:class:`~liquidamp.coupled.inputs.HarmonicInput`, given to
    :func:`couple`, :func:`rotor_system`, :func:`blade_system` or
    :meth:`CoupledSystem.with_inputs`): a blade's lag moment, a hub force.

Algebraic loop of the acceleration
    Devices with ``uses_acceleration`` (``dashpot_inerter``, ``inerter``, a
    moving-mass effect) have a force that depends on the stroke
    acceleration, which in turn depends on the force through the host's
    input matrix.  Every model is affine in the acceleration, so
    F = F0 + b a with b = F(a = 1) - F(a = 0) [kg] evaluated at each call,
    and the loop is solved exactly each time:

    .. math:: (I - \\mathrm{diag}(b) C_v B_F) F = F_0 + \\mathrm{diag}(b) C_v A x_h .

    For a rotor this is the same as adding ``b arm^2`` [kg m^2] to the
    blade's lag inertia (the inerter is a mass seen through the arm): the
    second-order form M q'' = G u - C q' - K q with u containing b arm q_k''
    gives (M + arm^2 b e_k e_k^T) q'' = ...

Viscous damper as a device
    :func:`viscous` makes F = c v + c2 v|v| a device (a stateless
    :class:`~liquidamp.device.models.DeviceModel` with :class:`ViscousParams`),
    so the host's own dampers come back through the coupled path.

Time domain
    :func:`simulate_coupled` integrates the coupled system with
    :func:`scipy.integrate.solve_ivp` (the Python engine, the reference) or,
    with ``SolverOptions(engine="compiled")``, the compiled second-order
    kernel (:func:`liquidamp.coupled.fast_rotor.simulate_rotor`,
    :func:`~liquidamp.coupled.fast_rotor.simulate_blade`) for a :func:`rotor_system`
    or :func:`blade_system` with compiled device models (other
    configurations raise ParameterError),
    stops at a chamber end or at the pressure floor (status, not NaN), and
    returns a :class:`CoupledResponse` with strokes, forces, device states
    and, for a host with second-order mechanics (the rotor), the energy
    balance :class:`EnergyBalance`.

References
----------
.. [1] B. Titurus, "Generalized Liquid-Based Damping Device for Passive
   Vibration Control", AIAA J. 56(10), 4134-4145, 2018, eqs. (10)-(20).
.. [2] C. E. Hammond, J. American Helicopter Society 19(4), 14-23, 1974.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_simpson, solve_ivp

from liquidamp.coupled.compiled_route import compiled_support
from liquidamp.coupled.engines import engine_for
from liquidamp.coupled.inputs import input_values
from liquidamp.coupled.system import (
    VISCOUS,
    CoupledSystem,
    Device,
    HostMatrices,
    ViscousParams,
    _compiled_origin,
    blade_system,
    couple,
    rotor_system,
    section_system,
    viscous,
)
from liquidamp.device.models import DeviceModel
from liquidamp.errors import (
    ConvergenceError,
    ParameterError,
    PressureError,
    check_positive,
)
from liquidamp.options import SolverOptions, resolve_options

__all__ = [
    "VISCOUS",
    "ViscousParams",
    "Device",
    "viscous",
    "HostMatrices",
    "CoupledSystem",
    "couple",
    "rotor_system",
    "blade_system",
    "section_system",
    "EnergyBalance",
    "CoupledResponse",
    "simulate_coupled",
    "compiled_support",
]


# ---------------------------------------------------------------------------
# time domain


@dataclass(frozen=True, eq=False)
class EnergyBalance:
    """Energy of a second-order host and the work done on it (cumulative, from t = 0).

    With E = T + V, T = q'^T M q'/2, V = q^T K_s q/2 (K_s the symmetric part
    of K):

    .. math:: E(t) - E(0) = -\\sum_k W_k - D + W_{drive} + W_{in}

    where W_k = int F_k v_k dt is the work the host does on device k [J],
    D = int q'^T C_s q' dt the host's own dissipation [J], W_drive =
    int (q'^T M' q'/2 + q^T K_s' q/2 - q'^T K_a q) dt the work of the
    time-varying (rotating) coefficients, supplied by the rotor drive [J],
    and W_in = int q'^T G u dt the work of the external inputs
    (:class:`~liquidamp.coupled.inputs.HarmonicInput`, G u = M B_u u) [J].

    Attributes
    ----------
    kinetic, potential : ndarray
        T and V [J].
    device_work : ndarray, shape (n_ports, N)
        W_k [J].
    host_dissipation, drive_work : ndarray
        D and W_drive [J].
    residual : ndarray
        E - E(0) + sum W_k + D - W_drive - W_in [J] (zero up to quadrature error).
    input_work : ndarray or None
        W_in [J]; None for a system without external inputs.
    """

    kinetic: np.ndarray
    potential: np.ndarray
    device_work: np.ndarray
    host_dissipation: np.ndarray
    drive_work: np.ndarray
    residual: np.ndarray
    input_work: np.ndarray | None = None

    @property
    def relative_residual(self) -> float:
        """max |residual| / max(E, sum |W_k|, D, |W_drive|) [-]."""
        E = self.kinetic + self.potential
        scale = max(float(np.max(np.abs(E))), float(np.max(np.abs(self.device_work))),
                    float(np.max(np.abs(self.host_dissipation))),
                    float(np.max(np.abs(self.drive_work))),
                    0.0 if self.input_work is None else float(np.max(np.abs(self.input_work))),
                    1e-300)
        return float(np.max(np.abs(self.residual)) / scale)


@dataclass(frozen=True, eq=False)
class CoupledResponse:
    """Time history of a coupled run.

    Attributes
    ----------
    name : str
    time : ndarray
        [s].
    host_state_names : tuple of str
    host_states : ndarray, shape (n_host, N)
        Host states [host units].
    port_names : tuple of str
    device_labels : tuple of str
    device_state_names : tuple of tuple of str
    device_states : tuple of ndarray
        Per port, shape (n_states_j, N) [model units].
    strokes, stroke_rates, stroke_accelerations : ndarray, shape (n_ports, N)
        [m], [m/s], [m/s^2].
    forces : ndarray, shape (n_ports, N)
        Device forces [N] (positive resisting a positive stroke).
    energy : EnergyBalance or None
        Where the host has second-order mechanics.
    status : str
        ``completed``, ``stroke_limit`` or ``pressure_floor``.
    message : str
    warnings : tuple of str
    """

    name: str
    time: np.ndarray
    host_state_names: tuple[str, ...]
    host_states: np.ndarray
    port_names: tuple[str, ...]
    device_labels: tuple[str, ...]
    device_state_names: tuple[tuple[str, ...], ...]
    device_states: tuple[np.ndarray, ...]
    strokes: np.ndarray
    stroke_rates: np.ndarray
    stroke_accelerations: np.ndarray
    forces: np.ndarray
    energy: EnergyBalance | None
    status: str
    message: str
    warnings: tuple[str, ...] = ()

    def host_state(self, name: str) -> np.ndarray:
        """Host state ``name`` over time."""
        if name not in self.host_state_names:
            raise ParameterError(f"unknown host state {name!r}; valid: "
                                 f"{', '.join(self.host_state_names)}")
        return self.host_states[self.host_state_names.index(name)]

    def device_state(self, port: str, name: str) -> np.ndarray:
        """State ``name`` of the device at ``port`` over time."""
        if port not in self.port_names:
            raise ParameterError(f"unknown port {port!r}; valid: {', '.join(self.port_names)}")
        j = self.port_names.index(port)
        names = self.device_state_names[j]
        if name not in names:
            raise ParameterError(f"device at {port!r} has no state {name!r}; valid: "
                                 f"{', '.join(names) or 'none'}")
        return self.device_states[j][names.index(name)]


def _pressure_indices(model: DeviceModel):
    if model.pressures is None or not model.uses_bulk_law:
        return None
    names = model.state_names
    if "p1" in names and "p2" in names:
        return names.index("p1"), names.index("p2")
    return None


def _energy(system: CoupledSystem, t, xh, F, v) -> EnergyBalance:
    mech = system.host.mechanics
    n = xh.shape[0] // 2
    q, qd = xh[:n], xh[n:2 * n]
    N = t.size
    T = np.empty(N)
    V = np.empty(N)
    Pd = np.empty(N)
    Pw = np.empty(N)
    Pu = np.zeros(N)
    Bu = system.input_matrix if system.inputs else None
    h = 1e-6 * (system.host.period or 1.0)
    for i in range(N):
        M, C, K = mech(t[i])
        if Bu is not None:  # generalized forces of the inputs, G u = M (B_u u)[rates]
            Pu[i] = qd[:, i] @ (M @ (Bu(t[i])[n:2 * n] @ input_values(system.inputs, t[i])))
        Mp, _, Kp = mech(t[i] + h)
        Mm, _, Km = mech(t[i] - h)
        Ks, Ka = 0.5 * (K + K.T), 0.5 * (K - K.T)
        Cs = 0.5 * (C + C.T)
        Md, Kd = (Mp - Mm) / (2 * h), 0.5 * ((Kp + Kp.T) - (Km + Km.T)) / (2 * h)
        a, b = q[:, i], qd[:, i]
        T[i] = 0.5 * b @ M @ b
        V[i] = 0.5 * a @ Ks @ a
        Pd[i] = b @ Cs @ b
        Pw[i] = 0.5 * b @ Md @ b + 0.5 * a @ Kd @ a - b @ Ka @ a
    W = cumulative_simpson(F * v, x=t, initial=0.0, axis=-1)
    D = cumulative_simpson(Pd, x=t, initial=0.0)
    Wd = cumulative_simpson(Pw, x=t, initial=0.0)
    Wu = cumulative_simpson(Pu, x=t, initial=0.0) if Bu is not None else None
    E = T + V
    res = E - E[0] + W.sum(axis=0) + D - Wd - (0.0 if Wu is None else Wu)
    return EnergyBalance(T, V, W, D, Wd, res, Wu)


def _resolve_x0(system: CoupledSystem, x0) -> np.ndarray:
    """Coupled initial state from ``x0`` (see :func:`simulate_coupled`)."""
    n = system.n_states
    if x0 is None or isinstance(x0, Mapping) or np.size(x0) == system.host.nstates:
        if x0 is not None and np.size(x0) == n and not isinstance(x0, Mapping):
            X0 = np.asarray(x0, float).reshape(-1)
        else:
            X0 = system.initial_state(x0)
    else:
        X0 = np.asarray(x0, float).reshape(-1)
        if X0.size != n:
            raise ParameterError(f"x0 needs {n} values (coupled) or {system.host.nstates} "
                                 f"(host), got {X0.size}")
    if not np.all(np.isfinite(X0)):
        raise ParameterError("x0 must be finite")
    return X0


def _stop_conditions(system: CoupledSystem, floor: float) -> list:
    """``[(kind, port index, g)]`` in the order they are checked; ``g(x) > 0`` while running.

    ``g`` takes a coupled state or a matrix of them (columns): the margin to
    the chamber end [m] (``stroke_limit``) or the lowest chamber pressure
    above ``floor`` [Pa] (``pressure_floor``).
    """
    nh = system.host.nstates
    conds = []
    for j, d in enumerate(system.devices):
        C_y = system.stroke_matrix[j]
        lim = d.stroke_limit
        if math.isfinite(lim):
            def g(x, C_y=C_y, lim=lim):
                return lim - np.abs(C_y @ x[:nh])
            conds.append(("stroke_limit", j, g))
        pi = _pressure_indices(d.model)
        if pi is not None:
            sl = system.device_slice(j)

            def gp(x, sl=sl, pi=pi):
                z = x[sl]
                return np.minimum(z[pi[0]], z[pi[1]]) - floor
            conds.append(("pressure_floor", j, gp))
    return conds


def _stop_reason(system: CoupledSystem, kind: str, j: int, floor: float) -> str:
    port = system.ports[j].name
    if kind == "stroke_limit":
        return (f"stroke at port {port!r} reached the chamber end "
                f"{system.devices[j].stroke_limit:g} m")
    return f"a chamber pressure of the device at port {port!r} reached the floor {floor:g} Pa"


def _stop_message(system: CoupledSystem, kind: str, j: int, t_stop: float, floor: float) -> str:
    return f"stopped at t = {t_stop:.6g} s: {_stop_reason(system, kind, j, floor)}"


def _run_python(system, T_end, X0, t_eval, opts, max_step, conds):
    """scipy ``solve_ivp`` route: (time, states, status, message)."""
    nh = system.host.nstates
    host_scale = max(float(np.max(np.abs(X0[:nh]))), 1e-12)
    atol = [np.full(nh, opts.atol_scale * host_scale)]
    for d in system.devices:
        if d.n_states:
            atol.append(opts.atol_scale * np.asarray(d.model.state_scales(d.params), float))
    atol = np.concatenate(atol)
    events = []
    for _, _, g in conds:
        def ev(t, x, g=g):
            return g(x)
        ev.terminal = True
        events.append(ev)
    sol = solve_ivp(system.rhs, (0.0, T_end), X0, method=opts.method, t_eval=t_eval,
                    rtol=opts.rtol, atol=atol, max_step=max_step, events=events or None)
    if sol.status == -1:
        raise ConvergenceError(f"coupled integration failed: {sol.message}")
    status, message = "completed", "integrated to t_end"
    if sol.status == 1:
        for k, te in enumerate(sol.t_events):
            if te.size:
                kind, j, _ = conds[k]
                status = kind
                message = _stop_message(system, kind, j, float(te[0]), opts.pressure_floor)
                break
    return sol.t, sol.y, status, message


def _run_compiled(system, T_end, X0, t_eval, opts, max_step, conds):
    """Compiled route (the runner of the system's origin in :mod:`liquidamp.coupled.fast`,
    :func:`~liquidamp.coupled.fast_rotor.simulate_rotor` or
    :func:`~liquidamp.coupled.fast_rotor.simulate_blade`): as :func:`_run_python`.

    The kernel stops at the end of the step in which a stop condition is
    met; the samples after the crossing are dropped and the crossing is
    located on the same trajectory (the step sequence does not depend on
    the output times) by re-running with output grids that close in on it,
    so the result has the samples, status and message of the Python route.
    """
    from liquidamp.coupled import fast, fast_rotor

    o = _compiled_origin(system, fast.check_compiled)

    def run(times):
        runner = getattr(fast_rotor, o.runner)
        r = runner(*o.args, T_end, X0, inputs=o.inputs, **o.kwargs, t_eval=times, options=opts,
                   max_step=max_step)
        if r.system.state_names != system.state_names:  # pragma: no cover - guard
            raise ParameterError("engine 'compiled': the kernel's state layout differs from "
                                 f"{system.name!r}; use engine='scipy'")
        return r

    def margins(X):
        return np.array([np.atleast_1d(g(X)) for _, _, g in conds]).reshape(len(conds), -1)

    r = run(t_eval)
    t, X = r.time, r.states
    if r.status == "completed":
        if t.size != t_eval.size:  # pragma: no cover - guard
            raise ConvergenceError("compiled rotor integration ended before the last output time")
        return t, X, "completed", "integrated to t_end"
    bad = np.any(margins(X) <= 0.0, axis=0) if conds else np.zeros(t.size, bool)
    keep = t.size
    while keep and bad[keep - 1]:
        keep -= 1
    lo = float(t[keep - 1]) if keep else 0.0
    hi = (float(t[keep]) if keep < t.size else
          float(t_eval[t.size]) if t.size < t_eval.size else T_end)
    tol = 1e-5 * (system.host.period or T_end)
    k_ev, t_ev = None, hi
    for _ in range(16):
        grid = np.linspace(lo, hi, 257)
        rf = run(grid)
        G = margins(rf.states)
        hit = np.flatnonzero(np.any(G <= 0.0, axis=0))
        if hit.size:
            i = int(hit[0])
            k_ev = int(np.flatnonzero(G[:, i] <= 0.0)[0])
            if i == 0:  # pragma: no cover - x0 is checked before the run
                t_ev = float(grid[0])
                break
            g0, g1 = G[k_ev, i - 1], G[k_ev, i]
            lo, hi = float(grid[i - 1]), float(grid[i])
            t_ev = lo + (hi - lo) * float(g0 / (g0 - g1))
            if hi - lo <= tol:
                break
        else:
            # the step ended (and stopped) between two grid times: close in on its end
            mf = rf.time.size
            if mf in (0, grid.size):  # pragma: no cover - nothing left to bracket
                break
            lo, hi = float(grid[mf - 1]), float(grid[mf])
            t_ev = hi
            last = G[:, -1]
            if hi - lo <= 4.0 * np.finfo(float).eps * max(abs(hi), 1.0):
                # crossing and step end closer than round-off: the condition the kernel
                # stopped on with the least margin at the last sample
                cand = [k for k, c in enumerate(conds) if c[0] == rf.status]
                k_ev = min(cand or range(len(conds)), key=lambda k: last[k])
                break
    if k_ev is None:  # pragma: no cover - the crossing eluded every grid
        cand = [k for k, c in enumerate(conds) if c[0] == r.status]
        last = margins(X[:, keep - 1:keep] if keep else X0[:, None])[:, 0]
        k_ev = min(cand or range(len(conds)), key=lambda k: last[k])
    kind, j, _ = conds[k_ev]
    return (t[:keep], X[:, :keep], kind,
            _stop_message(system, kind, j, t_ev, opts.pressure_floor))


def _response(system, t, X, status, message, opts, energy) -> CoupledResponse:
    """Port signals, warnings and energy of a run: the CoupledResponse."""
    nh = system.host.nstates
    m = len(system.devices)
    N = t.size
    Y = np.empty((m, N))
    Vv = np.empty((m, N))
    Aa = np.empty((m, N))
    Fo = np.empty((m, N))
    for i in range(N):
        ev_ = system.evaluate(t[i], X[:, i])
        Y[:, i], Vv[:, i], Aa[:, i], Fo[:, i] = (ev_["stroke"], ev_["rate"],
                                                 ev_["acceleration"], ev_["force"])
    warns = []
    dstates = []
    for j, d in enumerate(system.devices):
        z = X[system.device_slice(j)]
        dstates.append(z)
        if d.model.pressures is not None and d.n_states and N:
            p1, p2 = d.model.pressures(z, (Y[j], Vv[j], Aa[j]), d.params)
            pmin = float(min(np.min(p1), np.min(p2)))
            if pmin < opts.vapour_pressure:
                warns.append(f"port {system.ports[j].name!r}: lowest chamber pressure "
                             f"{pmin:.4g} Pa is below the vapour pressure "
                             f"{opts.vapour_pressure:g} Pa (cavitation not modelled)")
    eb = None
    if energy and system.host.mechanics is not None and N >= 3:
        eb = _energy(system, t, X[:nh], Fo, Vv)
    return CoupledResponse(
        name=system.name, time=t, host_state_names=system.host.state_names,
        host_states=X[:nh], port_names=system.port_names,
        device_labels=tuple(d.label for d in system.devices),
        device_state_names=tuple(d.model.state_names for d in system.devices),
        device_states=tuple(dstates), strokes=Y, stroke_rates=Vv, stroke_accelerations=Aa,
        forces=Fo, energy=eb, status=status, message=message, warnings=tuple(warns))


def simulate_coupled(system: CoupledSystem, t_end: float, x0=None, *, t_eval=None,
                     samples_per_second: float | None = None,
                     options: SolverOptions | None = None, strict: bool = True,
                     energy: bool = True, max_step: float | None = None) -> CoupledResponse:
    """Integrate the coupled nonlinear system from 0 to ``t_end`` [s].

    Parameters
    ----------
    system : CoupledSystem
    t_end : float
        End time > 0 [s].
    x0 : array or mapping, optional
        Coupled initial state (length ``system.n_states``) or a host state
        (array or ``{name: value}``) with the devices at rest.
    t_eval : array, optional
        Output times [s], strictly increasing within [0, ``t_end``]
        (default: uniform, ``samples_per_second``).
    samples_per_second : float, optional
        Default output rate [1/s] (default 200, or 64 per host period).
    options : SolverOptions, optional
        ``engine``, ``method``, ``rtol``, ``atol_scale`` (atol = atol_scale x
        state scale: the device's ``state_scales``, the host's largest
        initial state), ``pressure_floor``, ``vapour_pressure``; default the
        ``"coupled"`` preset of :data:`liquidamp.options.PRESETS` (scipy).
        ``engine="scipy"``: :func:`scipy.integrate.solve_ivp`
        with ``method``.  ``engine="compiled"``: the compiled rotor kernel
        :func:`liquidamp.coupled.fast_rotor.simulate_rotor` (DOP853 with scipy's
        coefficients, step control and dense output, whatever ``method``;
        see Notes).
    strict : bool
        Raise (PressureError, ParameterError) when a chamber pressure reaches
        the floor or a stroke reaches a chamber end; else stop and return
        with that ``status``.
    energy : bool
        Compute the :class:`EnergyBalance` where the host has mechanics.
    max_step : float, optional
        Largest step > 0 [s] (default 1/20 of the host period, else unbounded).

    Returns
    -------
    CoupledResponse
        The same fields from either engine.

    Raises
    ------
    ParameterError
        Bad input; a stroke at a chamber end with ``strict``; under
        ``engine="compiled"``, a configuration the compiled kernel does not
        integrate (the message names it and says ``use engine='scipy'``).
    PressureError
        A chamber pressure at the floor with ``strict``.
    ConvergenceError
        The integration failed.

    Notes
    -----
    ``engine="compiled"`` integrates the system of :func:`rotor_system` (a
    :class:`~liquidamp.structure.rotor.GroundResonanceRotor`, the built-in
    lag damper kept on blades without a device) or of :func:`blade_system`
    (an :class:`~liquidamp.structure.blade.ArticulatedBlade`), with their
    external inputs, and devices of any model of
    :data:`liquidamp.coupled.fast.COMPILED_MODELS` (with any add-on
    effects) or the viscous damper (:func:`compiled_support`).  It raises
    ParameterError, with no fall-back, for any other host (a section, a
    system from :func:`couple`) and models driven by the stroke
    acceleration.  Every argument
    maps one to one: the same ``x0``, output times, ``rtol``, ``atol``,
    ``max_step``, ``pressure_floor`` and stop conditions; the strokes,
    forces, warnings and energy balance are computed from its states by the
    same code as for the Python route.  With ``method="DOP853"`` the two
    routes take the same steps and agree to round-off (~1e-13 relative);
    with another method, to the tolerances.  A stop (chamber end or
    pressure floor) is detected at the end of a step, as scipy's events,
    and its time located on the same trajectory.

    Examples
    --------
    >>> from liquidamp.options import SolverOptions
    >>> from liquidamp.structure.hostio import load_section
    >>> sec = section_system(load_section("hodges-pierce"), 5.0, {"pitch": viscous(10.0)})
    >>> simulate_coupled(sec, 0.1, options=SolverOptions(engine="compiled"))
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: engine 'compiled' (simulate_coupled) integrates only the \
ground-resonance rotor and the blade with devices built by rotor_system() or blade_system(); \
host ... has constant coefficients (a typical section or another linear StateSpace); use \
engine='scipy'
    """
    opts = resolve_options(options, "coupled")
    T_end = check_positive("t_end", t_end, "s")
    X0 = _resolve_x0(system, x0)
    period = system.host.period
    if t_eval is None:
        rate = samples_per_second or (64.0 / period if period else 200.0)
        t_eval = np.linspace(0.0, T_end, int(math.ceil(T_end * rate)) + 1)
    t_eval = np.asarray(t_eval, float)
    if t_eval.ndim != 1 or not np.all(np.isfinite(t_eval)) or np.any(np.diff(t_eval) <= 0.0) \
            or (t_eval.size and (t_eval[0] < 0.0 or t_eval[-1] > T_end)):
        raise ParameterError(f"t_eval must be a strictly increasing 1-D array of times within "
                             f"[0, {T_end:g}] s")
    if max_step is None:
        max_step = period / 20.0 if period else np.inf
    elif not float(max_step) > 0.0:
        raise ParameterError(f"max_step must be > 0 [s], got {max_step!r}")
    max_step = float(max_step)
    conds = _stop_conditions(system, opts.pressure_floor)
    for kind, j, g in conds:
        if not float(g(X0)) > 0.0:
            raise ParameterError("x0 is at a stop condition already: "
                                 + _stop_reason(system, kind, j, opts.pressure_floor))
    engine = engine_for(system, opts)  # the engine contract: supported, or a clear error
    route = _run_compiled if engine.name == "compiled" else _run_python
    t, X, status, message = route(system, T_end, X0, t_eval, opts, max_step, conds)
    if status != "completed" and strict:
        raise (PressureError if status == "pressure_floor" else ParameterError)(message)
    return _response(system, t, X, status, message, opts, energy)
