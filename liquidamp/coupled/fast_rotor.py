"""Compiled time integration of a rotor or a blade with devices (second-order hosts).

The driver of the DOP853 kernel of :mod:`liquidamp.coupled._rotor_kernel` for a
periodic second-order host (the rotor on its landing gear, a blade in lead-lag)
with liquid devices on its ports: :func:`simulate_rotor`, :func:`simulate_blade`,
and the flow (with its monodromy) of :func:`second_order_flow` used by the
forced-orbit Floquet analysis.  The device-on-a-test-machine driver is
:mod:`liquidamp.coupled.fast`.

References
----------
.. [1] E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential
   Equations I, 2nd ed., Springer 1993, Sec. II.5 (DOP853).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from liquidamp.coupled import _kernels as K
from liquidamp.coupled import _rotor_kernel as RK
from liquidamp.coupled.fast import MAX_STEPS, check_compiled
from liquidamp.device import kernels as DK
from liquidamp.errors import ConvergenceError, ParameterError

__all__ = ["RotorRun", "simulate_rotor", "simulate_blade", "FlowRun", "second_order_flow"]


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
    PRM = np.zeros((nd, DK.N_PRM_ALL))  # the parameters and the input channel slots
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
