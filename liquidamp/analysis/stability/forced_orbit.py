"""The forced periodic response of a host with devices, and its Floquet multipliers.

A host driven by periodic inputs (:class:`~liquidamp.coupled.inputs.HarmonicInput`:
a blade's 1/rev lag moment in forward flight) settles on a periodic orbit
``x*(t + T) = x*(t)``.  The stability of the motion *on top of* that orbit
-- the damping of the lag mode while the damper carries the large 1/rev
stroke -- is the Floquet problem of the system linearized along the orbit,

.. math:: \\delta x' = J(t)\\, \\delta x, \\qquad
          J(t) = \\frac{\\partial f}{\\partial x}(t, x^*(t)),

whose coefficients are periodic through the orbit even when the host's are
constant.  Here:

Jacobian (:func:`coupled_jacobian`)
    The host is linear (``A(t)``, ``B(t)``); each device contributes its
    Jacobian ``d rhs/dz`` from the compiled ``model_jac`` of
    :mod:`liquidamp.device.kernels` (analytic, or central differences for
    compositions) and the derivatives of its right-hand side and force with
    respect to the stroke and stroke rate (and of the force with respect to
    its states) by central differences of the same compiled physics
    (increments 1e-6 of each quantity's magnitude), all in
    :func:`liquidamp.coupled._rotor_kernel.device_derivatives`, which the
    compiled variational equations run too.  The external inputs do not
    enter.

Orbit (:func:`forced_orbit`)
    Shooting: Newton's method on ``x(T; x0) - x0 = 0``, the state and the
    monodromy ``Phi(T)`` integrated together (state and variational
    equations): on the compiled second-order kernel for the blade and the
    rotor (:func:`liquidamp.coupled.fast_rotor.second_order_flow`, DOP853), or by
    :func:`scipy.integrate.solve_ivp` (DOP853) on the system's right-hand side
    and :func:`coupled_jacobian` for any host (the reference route; the two
    agree to 1e-7 in the scaled monodromy, tested).  A sealed
    device conserves its fluid mass and, per chamber, the relation between
    density and pressure (:func:`~liquidamp.coupled.invariants.invariants`):
    each invariant puts a multiplier at exactly 1, so the orbits form a
    family.  As in :func:`~liquidamp.coupled.periodic.periodic_state`,
    every iterate is projected onto the level set of the invariants of the
    start (the devices at rest) and the Newton equation
    ``(Phi - I) Z a = -(x(T) - x0)`` is solved on its tangent space ``Z``
    by least squares, in coordinates scaled by each state's magnitude;
    a step that does not reduce the residual is halved.

Floquet (:class:`ForcedOrbit`)
    The monodromy of the last iterate gives the multipliers
    (:func:`~liquidamp.analysis.stability.floquet.floquet_from_monodromy`);
    :func:`floquet_mode` picks the mode that belongs to the eigenvalue of the
    orbit-averaged Jacobian living most in given host states, with its
    exponent's frequency branch resolved against that eigenvalue.

Limits: devices whose force depends on the stroke acceleration and
effects without a small-signal model (Coulomb friction: a jump at every
stroke reversal, freeplay) are refused, since the variational equations
need a saltation matrix at the switching; the parameter set's own Coulomb
friction ``friction_N`` likewise.

References
----------
.. [1] R. Seydel, Practical Bifurcation and Stability Analysis, 3rd ed.,
   Springer 2010, Ch. 7 (shooting, monodromy matrix, Floquet multipliers).
.. [2] P. P. Friedmann, C. E. Hammond, T.-H. Woo, Int. J. Numer. Meth.
   Eng. 11, 1117-1136, 1977.
.. [3] B. Titurus, AIAA J. 56(10), 2018, eqs. (3), (10).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from liquidamp.analysis.stability.floquet import FloquetResult, floquet_from_monodromy
from liquidamp.coupled import kernels as RK
from liquidamp.coupled.assembly import CoupledSystem
from liquidamp.coupled.invariants import invariants, project_level_set
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, check_positive
from liquidamp.options import SolverOptions, resolve_options

__all__ = ["coupled_jacobian", "ForcedOrbit", "forced_orbit", "FloquetMode", "floquet_mode",
           "orbit_period"]

#: Relative increment of the central differences in stroke, rate and force states [-]
#: (the compiled kernel's, one value for both routes).
FD_REL = RK.FD_REL


def _check_smooth(system: CoupledSystem) -> None:
    """Refuse devices whose variational equations do not exist along a moving orbit."""
    for p, d in zip(system.ports, system.devices, strict=True):
        where = f"device {d.label!r} at port {p.name!r}"
        if d.model.uses_acceleration:
            raise ParameterError(f"{where}: model {d.model.name!r} uses the stroke "
                                 "acceleration; the forced-orbit analysis takes devices driven "
                                 "by stroke and stroke rate only")
        for e in d.model.effects:
            if e.small_signal_reason is not None:
                raise ParameterError(
                    f"{where}: effect {e.name!r} is not smooth ({e.small_signal_reason}); the "
                    "variational equations along the orbit need a saltation matrix at its "
                    "switching, not implemented; use a smooth law (e.g. smooth_friction)")
        if isinstance(d.params, DeviceParams) and d.params.friction_N > 0.0:
            raise ParameterError(
                f"{where}: the parameter set's Coulomb friction friction_N = "
                f"{d.params.friction_N:g} N jumps at every stroke reversal; the variational "
                "equations along the orbit need a saltation matrix there, not implemented; set "
                "friction_N = 0 or use the smooth_friction effect")


def _device_derivatives(d, t, z, y, v):
    """(dF/dz, dF/dy, dF/dv, df/dz, df/dy, df/dv) of one device at (z, y, v).

    The compiled :func:`liquidamp.coupled._rotor_kernel.device_derivatives`
    (the one copy the variational kernel runs too).
    """
    spec, prm, ep = d.model.packed(d.params)
    nz = z.size
    m = max(nz, 1)
    dFdz, dfdz = np.zeros(m), np.zeros((m, m))
    dfdy, dfdv = np.zeros(m), np.zeros(m)
    work = [np.empty(m) for _ in range(3)]
    dFdy, dFdv = RK.device_derivatives(spec, np.ascontiguousarray(z, dtype=float), float(y),
                                       float(v), prm, ep, float(d.stroke_limit), dFdz, dfdz,
                                       dfdy, dfdv, *work)
    return dFdz[:nz], dFdy, dFdv, dfdz[:nz, :nz], dfdy[:nz], dfdv[:nz]


def coupled_jacobian(system: CoupledSystem, t: float, x) -> np.ndarray:
    """Jacobian d(dx/dt)/dx of the coupled system at (t, x) [1/s, mixed units].

    Host rows ``A(t) + B_F(t) dF/dx``; device rows the device Jacobian
    (module notes).  External inputs do not enter.

    Parameters
    ----------
    system : CoupledSystem
        Devices driven by stroke and rate only (not the acceleration).
    t : float
        Time [s].
    x : array
        Coupled state (length ``system.n_states``).

    Returns
    -------
    ndarray, shape (n, n)

    Examples
    --------
    A viscous damper c on the blade's port: the lag row gets -c a^2 / I_b.

    >>> from liquidamp.coupled.assembly import blade_system, viscous
    >>> from liquidamp.structure.hostio import load_blade
    >>> b = load_blade("hammond1974").replace(lag_damping=0.0)
    >>> J = coupled_jacobian(blade_system(b, 26.0, viscous(2e4)), 0.0, np.zeros(2))
    >>> round(float(J[1, 1] / (-2e4 * 0.25**2 / b.inertia)), 9)
    1.0
    """
    _check_smooth(system)
    x = np.asarray(x, float)
    h = system.host
    nh = h.nstates
    A, B = h.AB(t) if h.AB is not None else (h.A(t), h.B(t))
    Bf = B[:, system.force_inputs]
    Cy, Cv = system.stroke_matrix, system.rate_matrix
    n = system.n_states
    J = np.zeros((n, n))
    J[:nh, :nh] = A
    xh = x[:nh]
    y, v = Cy @ xh, Cv @ xh
    for j, d in enumerate(system.devices):
        sl = system.device_slice(j)
        dFdz, dFdy, dFdv, dfdz, dfdy, dfdv = _device_derivatives(d, t, x[sl], float(y[j]),
                                                                  float(v[j]))
        J[:nh, :nh] += np.outer(Bf[:, j], dFdy * Cy[j] + dFdv * Cv[j])
        if dFdz.size:
            J[:nh, sl] += np.outer(Bf[:, j], dFdz)
            J[sl, :nh] += np.outer(dfdy, Cy[j]) + np.outer(dfdv, Cv[j])
            J[sl, sl] = dfdz
    return J


def orbit_period(system: CoupledSystem, period: float | None = None) -> float:
    """Period of the forced system [s]: ``period``, else from the inputs and the host.

    The inputs' frequencies must be integer multiples of one base frequency
    (the lowest non-zero one) and, for a periodic host (a rotor), the host's
    period a multiple of the inputs' (equal for 1/rev forcing).
    """
    if period is not None:
        return check_positive("orbit period", period, "s")
    ws = sorted({u.omega for u in system.inputs if u.omega > 0.0})
    Th = system.host.period
    if not ws:
        if Th is None:
            raise ParameterError("the system has no harmonic input and constant coefficients: "
                                 "give the period [s] of the orbit (e.g. 2 pi/Omega)")
        return float(Th)
    w0 = ws[0]
    for w in ws[1:]:
        if abs(w / w0 - round(w / w0)) > 1e-9:
            raise ParameterError(f"input frequencies {ws} rad/s are not integer multiples of "
                                 f"{w0:g} rad/s: the forced response is not periodic")
    T = 2.0 * math.pi / w0
    if Th is not None and abs(Th / T - round(Th / T)) > 1e-9 * max(1.0, Th / T):
        raise ParameterError(f"the host's period {Th:g} s is not a multiple of the input "
                             f"period {T:g} s: the forced response is not periodic")
    return max(T, Th or 0.0)


class _Level:
    """Invariants of every device as functions of the coupled state (module notes)."""

    def __init__(self, system: CoupledSystem, x_start, scale):
        self.system = system
        self.scale = scale
        self.rows = []  # (device j, slice, number of invariants)
        vals = []
        for j, d in enumerate(system.devices):
            if not isinstance(d.params, DeviceParams) or not d.n_states:
                continue
            v, _ = self._device(j, x_start)
            if v.size:
                self.rows.append(j)
                vals.append(v)
        self.target = np.concatenate(vals) if vals else np.zeros(0)
        self.norm = np.abs(self.target) + (self.target == 0.0)

    def _device(self, j, x):
        d = self.system.devices[j]
        sl = self.system.device_slice(j)
        nh = self.system.host.nstates
        y = float(self.system.stroke_matrix[j] @ x[:nh])
        return invariants(d.model, d.params, x[sl], y)

    def gap(self, x):
        """Relative gaps of the invariants and their gradient in scaled coordinates."""
        n = x.size
        nh = self.system.host.nstates
        g, G = [], []
        for j in self.rows:
            v, Gz = self._device(j, x)
            row = np.zeros((v.size, n))
            row[:, self.system.device_slice(j)] = Gz
            # the total mass depends on the stroke through the chamber volumes
            d = self.system.devices[j]
            sl = self.system.device_slice(j)
            y = float(self.system.stroke_matrix[j] @ x[:nh])
            hy = FD_REL * max(abs(y), 1e-3)
            vp, _ = invariants(d.model, d.params, x[sl], y + hy)
            vm, _ = invariants(d.model, d.params, x[sl], y - hy)
            row[:, :nh] = np.outer((vp - vm) / (2.0 * hy), self.system.stroke_matrix[j])
            g.append(v)
            G.append(row)
        if not g:
            return np.zeros(0), np.zeros((0, n))
        gv = (np.concatenate(g) - self.target) / self.norm
        Gs = np.vstack(G) * self.scale[None, :] / self.norm[:, None]
        return gv, Gs

    def project(self, x):
        """Nearest point (scaled minimum norm) with the device states only moved."""
        if not self.rows:
            return x
        return project_level_set(x, self.gap, self.scale,
                                 cols=slice(self.system.host.nstates, None))

    def tangent(self, x):
        """Orthonormal basis (scaled coordinates) of the level set's tangent space."""
        n = x.size
        _, Gs = self.gap(x)
        if Gs.shape[0] == 0:
            return np.eye(n)
        _, _, vt = np.linalg.svd(Gs)
        return vt[Gs.shape[0]:].T


def _scales(system: CoupledSystem, x, omega: float) -> np.ndarray:
    """Magnitudes of the states [state units].

    Devices: their ``state_scales``.  Host: the peak ``x`` of each state
    (floored at 1e-3 of the largest); a host at rest takes 1 mm of stroke
    and 1 mm x ``omega`` [rad/s] of stroke rate through the port maps (1 where
    no port reads the state).
    """
    nh = system.host.nstates
    xh = np.abs(np.asarray(x, float)[:nh])
    top = float(np.max(xh)) if nh else 0.0
    if top > 0.0:
        host = np.maximum(xh, 1e-3 * top)
    else:
        host = np.full(nh, np.inf)
        for rows, size in ((system.stroke_matrix, 1e-3), (system.rate_matrix, 1e-3 * omega)):
            for row in rows:
                nz = row != 0.0
                host[nz] = np.minimum(host[nz], size / np.abs(row[nz]))
        host[~np.isfinite(host)] = 1.0
    parts = [host]
    for d in system.devices:
        if d.n_states:
            parts.append(np.asarray(d.model.state_scales(d.params), float))
    return np.concatenate(parts)


#: Absolute tolerance of the monodromy in scaled coordinates [-].
PHI_ATOL = 1e-12


def _flow(system, x0, T, scale, opts, compiled, monodromy=True, samples=None):
    """x(T), the monodromy Phi(T) (unscaled, or None) and the states at ``samples`` times.

    ``compiled``: the kernel of :func:`liquidamp.coupled.fast_rotor.second_order_flow`;
    else :func:`scipy.integrate.solve_ivp` (DOP853) on the system's right-hand
    side and :func:`coupled_jacobian`, Phi integrated in scaled coordinates.
    """
    n = system.n_states
    S = scale
    T = float(T)
    if compiled:
        from liquidamp.coupled.fast_rotor import second_order_flow

        r = second_order_flow(system, x0, T, t_eval=samples, monodromy=monodromy, scales=S,
                              options=opts, phi_atol=PHI_ATOL, max_step=T / 20.0)
        if r.status != "completed":
            raise ConvergenceError(f"forced orbit: the run over one period stopped "
                                   f"({r.status}): the forcing drives a device to a chamber "
                                   "end or its pressure to the floor")
        return r.x_end, r.monodromy, r.states if samples is not None else None
    ratio = S[None, :] / S[:, None]

    def f(t, w):
        x = w[:n]
        xd = system.rhs(t, x)
        if not monodromy:
            return xd
        Js = coupled_jacobian(system, t, x) * ratio
        return np.concatenate([xd, (Js @ w[n:].reshape(n, n)).ravel()])

    x0 = np.asarray(x0, float)
    w0 = np.concatenate([x0, np.eye(n).ravel()]) if monodromy else x0
    atol = np.concatenate([opts.atol_scale * S, np.full(n * n if monodromy else 0, PHI_ATOL)])
    sol = solve_ivp(f, (0.0, T), w0, method="DOP853", rtol=opts.rtol, atol=atol,
                    dense_output=samples is not None, max_step=T / 20.0)
    if not sol.success:
        raise ConvergenceError(f"forced orbit: integration over one period failed: "
                               f"{sol.message}")
    w = sol.y[:, -1]
    if not np.all(np.isfinite(w)):
        raise ConvergenceError("forced orbit: non-finite state over one period")
    Phi = w[n:].reshape(n, n) * (S[:, None] / S[None, :]) if monodromy else None
    X = sol.sol(samples)[:n] if samples is not None else None
    return w[:n], Phi, X


@dataclass(frozen=True, eq=False)
class ForcedOrbit:
    """The periodic orbit of a forced coupled system and its Floquet multipliers.

    Attributes
    ----------
    system : CoupledSystem
        The forced system (its ``inputs``).
    period : float
        T [s].
    x0 : ndarray
        Orbit state at t = 0 [state units].
    time : ndarray
        Sample times over one period, end excluded [s].
    states : ndarray, shape (n, N)
        Orbit states at ``time`` [state units].
    scales : ndarray
        State magnitudes of the scaled coordinates [state units].
    monodromy : ndarray, shape (n, n)
        Phi(T) of the variational equations along the orbit (unscaled) [-].
    floquet : FloquetResult
        Multipliers and principal exponents [1/s].
    averaged_jacobian : ndarray, shape (n, n)
        The Jacobian averaged over the orbit, in scaled coordinates [1/s]
        (its eigenvalues resolve the exponents' frequency branches).
    residual : float
        Periodicity residual max |x(T) - x0| / scale [-].
    iterations : int
        Newton iterations.
    message : str
    """

    system: CoupledSystem
    period: float
    x0: np.ndarray
    time: np.ndarray
    states: np.ndarray
    scales: np.ndarray
    monodromy: np.ndarray
    floquet: FloquetResult
    averaged_jacobian: np.ndarray
    residual: float
    iterations: int
    message: str

    def host_state(self, name: str) -> np.ndarray:
        """Host state ``name`` over the period."""
        names = self.system.host.state_names
        if name not in names:
            raise ParameterError(f"unknown host state {name!r}; valid: {', '.join(names)}")
        return self.states[names.index(name)]

    def strokes(self) -> np.ndarray:
        """Device strokes over the period [m], shape (n_ports, N)."""
        return self.system.stroke_matrix @ self.states[:self.system.host.nstates]

    def first_harmonic(self, signal) -> complex:
        """Complex amplitude c of ``signal`` ~ Re(c e^{i w t}) at w = 2 pi/T over the period."""
        s = np.asarray(signal, float)
        return complex(2.0 * np.mean(s * np.exp(-2j * math.pi * self.time / self.period)))


def forced_orbit(system: CoupledSystem, *, period: float | None = None, x0=None,
                 options: SolverOptions | None = None, tol: float = 1e-8,
                 max_iter: int = 20, samples: int = 64) -> ForcedOrbit:
    """Periodic orbit of ``system`` under its inputs by shooting, with its monodromy.

    Parameters
    ----------
    system : CoupledSystem
        Host, devices and :class:`~liquidamp.coupled.inputs.HarmonicInput`
        (none: the orbit is the rest state, or whatever ``x0`` starts).
    period : float, optional
        Orbit period [s] (default :func:`orbit_period`).
    x0 : array, optional
        Starting state (default the devices at rest, host at zero); its
        device invariants select the orbit (module notes).
    options : SolverOptions, optional
        ``engine``, ``rtol`` and ``atol_scale`` of the state and variational
        integration (default the ``"decay"`` preset: rtol 1e-10 on the compiled
        kernel, :func:`liquidamp.coupled.fast_rotor.second_order_flow`, for systems
        from ``blade_system``/``rotor_system``; ``engine="scipy"`` integrates
        ``system.rhs`` and :func:`coupled_jacobian` with ``solve_ivp``'s DOP853,
        the reference, and takes any host).  The monodromy's absolute
        tolerance is ``PHI_ATOL`` in scaled coordinates.
    tol : float
        Accept when max |x(T) - x0| / scale < ``tol`` [-].
    max_iter : int
        Largest number of Newton iterations.
    samples : int
        Samples of the orbit over one period (and of the averaged Jacobian).

    Returns
    -------
    ForcedOrbit

    Raises
    ------
    ConvergenceError
        No periodic orbit within ``max_iter`` (names the input amplitudes and
        the residual).
    ParameterError
        Bad input, a device the analysis does not take (module notes).

    Examples
    --------
    A linear blade-damper system under a 1/rev moment: the orbit is the
    harmonic response, found in one Newton step.

    >>> from liquidamp.coupled.assembly import blade_system, viscous
    >>> from liquidamp.coupled.inputs import HarmonicInput
    >>> from liquidamp.structure.hostio import load_blade
    >>> b = load_blade("hammond1974").replace(lag_damping=0.0)
    >>> W = 26.0
    >>> sys_ = blade_system(b, W, viscous(2e4), inputs=[HarmonicInput("moment", W, 0, 1e3)])
    >>> orb = forced_orbit(sys_)
    >>> Z = abs(orb.first_harmonic(orb.host_state("zeta")))
    >>> round(Z * abs(b.lag_stiffness(W) - b.inertia * W**2 + 1j * W * 2e4 * 0.0625) / 1e3, 7)
    1.0
    >>> orb.iterations <= 2
    True
    """
    from liquidamp.coupled.assembly import compiled_support

    if not isinstance(system, CoupledSystem):
        raise ParameterError(f"system must be a CoupledSystem, got {type(system).__name__}")
    _check_smooth(system)
    opts = resolve_options(options, "decay")
    compiled = opts.engine == "compiled"
    if compiled:
        why = compiled_support(system)
        if why is not None:
            raise ParameterError(f"{why} (forced_orbit: pass options with engine='scipy')")
    T = orbit_period(system, period)
    if not (isinstance(max_iter, int) and max_iter >= 1):
        raise ParameterError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if not 0.0 < tol < 1e-2:
        raise ParameterError(f"tol must lie in (0, 1e-2) [-], got {tol!r}")
    if not (isinstance(samples, int) and samples >= 8):
        raise ParameterError(f"samples must be an integer >= 8, got {samples!r}")
    x = system.initial_state() if x0 is None else np.asarray(x0, float).reshape(-1).copy()
    if x.size != system.n_states or not np.all(np.isfinite(x)):
        raise ParameterError(f"x0 needs {system.n_states} finite values")
    tt = np.arange(samples) * (T / samples)
    # scales from a first (plain) period: how large each host state gets
    w = 2.0 * math.pi / T
    _, _, X = _flow(system, x, T, _scales(system, x, w), opts, compiled, monodromy=False,
                    samples=tt)
    scale = _scales(system, np.max(np.abs(X), axis=1), w)
    level = _Level(system, x, scale)
    x = level.project(x)
    history = []
    it = 0
    while True:
        xT, Phi, X = _flow(system, x, T, scale, opts, compiled, samples=tt)
        r = (xT - x) / scale
        res = float(np.max(np.abs(r)))
        history.append(res)
        if res < tol:
            break
        if it >= max_iter:
            amps = ", ".join(f"{u.input} {u.amplitude:g}" for u in system.inputs) or "none"
            raise ConvergenceError(
                f"forced orbit of {system.name!r} did not converge in {max_iter} Newton "
                f"iterations (input amplitudes: {amps}): periodicity residual {res:.2e} of "
                f"the state scales (allowed {tol:g}); last residuals "
                f"{', '.join(f'{h:.1e}' for h in history[-5:])}")
        it += 1
        Z = level.tangent(x)
        Phis = Phi * (scale[None, :] / scale[:, None])
        a = np.linalg.lstsq((Phis - np.eye(x.size)) @ Z, -r, rcond=None)[0]
        step = scale * (Z @ a)
        for lam in (1.0, 0.5, 0.25, 0.125):
            x_try = level.project(x + lam * step)
            try:
                xT_try, _, _ = _flow(system, x_try, T, scale, opts, compiled, monodromy=False)
            except ConvergenceError:
                continue
            if np.max(np.abs((xT_try - x_try) / scale)) < res * (1.0 - 1e-4 * lam) \
                    or lam == 0.125:
                x = x_try
                break
    S = scale
    ratio = S[None, :] / S[:, None]
    Jbar = np.mean([coupled_jacobian(system, tt[k], X[:, k]) * ratio for k in range(samples)],
                   axis=0)
    flo = floquet_from_monodromy(Phi, T)
    route = ("compiled kernel (fast_rotor.second_order_flow)" if compiled else
             "scipy DOP853 on coupled_jacobian")
    msg = (f"periodic orbit by shooting: {it} Newton iterations, periodicity residual "
           f"{res:.2e}; monodromy of the variational equations along it, {route}, rtol "
           f"{opts.rtol:g}")
    return ForcedOrbit(system, T, x.copy(), tt, X, scale, Phi, flo, Jbar, res, it, msg)


@dataclass(frozen=True)
class FloquetMode:
    """One Floquet mode of a forced orbit.

    Attributes
    ----------
    exponent : complex
        Floquet exponent with the resolved frequency branch [1/s].
    multiplier : complex
        Its multiplier exp(exponent T) [-].
    damping_ratio : float
        -Re(exponent) / |exponent| [-].
    frequency : float
        Im(exponent) [rad/s] (damped frequency).
    vector : ndarray of complex
        Eigenvector of the monodromy (unscaled state units, largest host
        entry 1).
    participation : float
        Share of the mode in the selected host states (scaled 2-norm) [-].
    reference : complex
        Eigenvalue of the orbit-averaged Jacobian the branch was resolved
        against [1/s].
    """

    exponent: complex
    multiplier: complex
    damping_ratio: float
    frequency: float
    vector: np.ndarray
    participation: float
    reference: complex


def floquet_mode(orbit: ForcedOrbit, host_states, *, what: str = "mode") -> FloquetMode:
    """The Floquet mode of ``orbit`` that lives most in ``host_states`` (names).

    The reference is the eigenvalue (positive frequency) of the
    orbit-averaged Jacobian with the largest share in ``host_states``
    (scaled coordinates); among the multipliers off the positive real axis
    (complex, or real negative) the mode is the one whose exponent, moved to
    its branch ``+ i k 2 pi/T`` nearest the reference, lies nearest it.

    Raises
    ------
    ConvergenceError
        No oscillating mode lives in ``host_states`` (the message says why:
        all multipliers real, or the mode found is more than half a branch
        spacing from the reference).
    """
    sys_ = orbit.system
    names = list(sys_.host.state_names)
    idx = []
    for s in host_states:
        if s not in names:
            raise ParameterError(f"unknown host state {s!r}; valid: {', '.join(names)}")
        idx.append(names.index(s))
    w_branch = 2.0 * math.pi / orbit.period
    S = orbit.scales

    def share(V):
        return np.sum(np.abs(V[idx]) ** 2, axis=0) / np.sum(np.abs(V) ** 2, axis=0)

    lam, Vj = np.linalg.eig(orbit.averaged_jacobian)
    up = np.flatnonzero(lam.imag > 1e-9 * np.maximum(np.abs(lam), 1e-300))
    if up.size == 0:
        raise ConvergenceError(f"{what} not identified: the orbit-averaged Jacobian has no "
                               "oscillating eigenvalue (every mode is overdamped)")
    ref = complex(lam[up[np.argmax(share(Vj[:, up]))]])
    rho, Vs = np.linalg.eig(orbit.monodromy * (S[None, :] / S[:, None]))
    osc = np.flatnonzero((np.abs(rho.imag) > 1e-9 * np.abs(rho)) | (rho.real < 0.0))
    if osc.size == 0:
        raise ConvergenceError(
            f"{what} not identified: every Floquet multiplier is real and positive "
            f"({', '.join(f'{r.real:.4g}' for r in rho)}); the mode's frequency is an integer "
            f"multiple of 2 pi/T = {w_branch:.4g} rad/s or it is overdamped")
    part = share(Vs[:, osc])
    chosen = None
    for k in osc:
        eta = complex(np.log(complex(rho[k])) / orbit.period)
        eta = eta + 1j * round((ref.imag - eta.imag) / w_branch) * w_branch
        if chosen is None or abs(eta - ref) < abs(chosen[1] - ref):
            chosen = (k, eta)
    k, eta = chosen
    if abs(eta.imag - ref.imag) > 0.5 * w_branch:
        raise ConvergenceError(
            f"{what} not identified: the Floquet exponent nearest the averaged system's mode "
            f"in {', '.join(host_states)} is {eta:.4g} 1/s, more than half the branch "
            f"spacing {w_branch:.4g} rad/s from the averaged system's {ref:.4g} 1/s")
    v = Vs[:, k] * S
    hmax = idx[int(np.argmax(np.abs(v[idx])))]
    v = v / v[hmax]
    return FloquetMode(eta, complex(rho[k]), float(-eta.real / abs(eta)), float(eta.imag), v,
                       float(part[list(osc).index(k)]), ref)
