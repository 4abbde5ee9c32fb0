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
    kernel (:func:`liquidamp.coupled.fast.simulate_rotor`,
    :func:`~liquidamp.coupled.fast.simulate_blade`) for a :func:`rotor_system`
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
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import control
import numpy as np
from scipy.integrate import cumulative_simpson, solve_ivp

from liquidamp.coupled.engines import engine_for
from liquidamp.coupled.inputs import HarmonicInput, input_values
from liquidamp.device.models import VISCOUS, DeviceModel, ViscousParams, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import (
    ConvergenceError,
    ParameterError,
    PressureError,
    check_positive,
)
from liquidamp.options import SolverOptions, resolve_options
from liquidamp.structure.port import DevicePort, PeriodicStateSpace, find_port

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
# devices


@dataclass(frozen=True)
class Device:
    """A device model with its parameters, ready to attach to a port.

    Parameters
    ----------
    model : str or DeviceModel
        Registered name or any DeviceModel (e.g. from ``with_effects``).
    params : DeviceParams or ViscousParams
        Its parameters (checked against ``model.requires``).
    label : str
        Name for reports (default: the model name).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> d = Device("full", preset("reference"))
    >>> d.model.name, d.n_states, d.label
    ('full', 5, 'full')
    """

    model: DeviceModel
    params: object
    label: str = ""

    def __post_init__(self) -> None:
        model = get_model(self.model)
        object.__setattr__(self, "model", model)
        if isinstance(self.params, DeviceParams):
            model.check_params(self.params)
        elif not isinstance(self.params, ViscousParams):
            raise ParameterError(
                f"device params must be DeviceParams or ViscousParams, got "
                f"{type(self.params).__name__}")
        if not self.label:
            object.__setattr__(self, "label", model.name)

    @property
    def n_states(self) -> int:
        """Number of device states."""
        return self.model.n_states

    @property
    def stroke_limit(self) -> float:
        """Largest stroke before a chamber end [m] (inf for the viscous damper)."""
        return getattr(self.params, "stroke_limit", math.inf)

    def acceleration_gain(self, t: float, x, y: float, v: float) -> float:
        """b = dF/da [kg] (0 unless ``uses_acceleration``; the models are affine in a)."""
        if not self.model.uses_acceleration:
            return 0.0
        f1 = self.model.force(t, x, (y, v, 1.0), self.params)
        f0 = self.model.force(t, x, (y, v, 0.0), self.params)
        return float(f1 - f0)


def viscous(c: float, label: str = "", *, c2: float = 0.0) -> Device:
    """The viscous damper F = c v + c2 v|v| [N], c [N s/m], c2 [N s^2/m^2], as a :class:`Device`.

    Examples
    --------
    >>> d = viscous(65080.0)
    >>> float(d.model.force(0.0, np.zeros(0), (0.0, 0.01, 0.0), d.params))
    650.8
    >>> q = viscous(0.0, c2=1e4)                  # quadratic: 1e4 x 0.1 x |0.1|
    >>> float(q.model.force(0.0, np.zeros(0), (0.0, -0.1, 0.0), q.params)), q.label
    (-100.0, 'viscous(0 N s/m, 10000 N s^2/m^2)')
    """
    if not label:
        label = f"viscous({c:g} N s/m" + (f", {c2:g} N s^2/m^2)" if c2 else ")")
    return Device(VISCOUS, ViscousParams(float(c), float(c2)), label)


# ---------------------------------------------------------------------------
# host matrices


@dataclass(frozen=True, eq=False)
class HostMatrices:
    """A host in one form: A(t), B(t), constant C, named signals, ports.

    Attributes
    ----------
    A, B : callable
        ``t [s] -> ndarray``; constant for a time-invariant host.
    C : ndarray
        Output matrix (the port outputs must not feed through the inputs).
    state_names, input_names, output_names : tuple of str
    ports : tuple of DevicePort
    period : float or None
        Period of A and B [s]; None for a constant host.
    name : str
    mechanics : callable or None
        ``t -> (M, C, K)`` of the second-order form ``M q'' + C q' + K q =
        G u`` with host state ``[q, q']`` (for the energy balance).
    AB : callable or None
        ``t -> (A(t), B(t))`` in one call (faster where both come from one
        factorization, e.g. the rotor's mass matrix); optional.
    """

    A: Callable[[float], np.ndarray]
    B: Callable[[float], np.ndarray]
    C: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    ports: tuple[DevicePort, ...]
    period: float | None = None
    name: str = "host"
    mechanics: Callable | None = None
    AB: Callable | None = None

    @property
    def nstates(self) -> int:
        """Number of host states."""
        return len(self.state_names)


def _as_host(system, ports=None, mechanics=None) -> tuple[HostMatrices, np.ndarray]:
    """(HostMatrices, D) from a StateSpace, a PeriodicStateSpace or a HostMatrices."""
    if isinstance(system, HostMatrices):
        return system, np.zeros((len(system.output_names), len(system.input_names)))
    if isinstance(system, PeriodicStateSpace):
        return HostMatrices(system.A, system.B, np.asarray(system.C, float),
                            tuple(system.state_names), tuple(system.input_names),
                            tuple(system.output_names),
                            tuple(ports if ports is not None else system.ports),
                            float(system.period), system.name, mechanics), \
            np.asarray(system.D, float)
    if isinstance(system, control.StateSpace):
        A = np.array(system.A, float)
        B = np.array(system.B, float)
        host = HostMatrices(lambda t: A, lambda t: B, np.array(system.C, float),
                            tuple(system.state_labels), tuple(system.input_labels),
                            tuple(system.output_labels), tuple(ports or ()), None,
                            system.name or "host", mechanics)
        return host, np.array(system.D, float)
    raise ParameterError(
        f"host must be a control.StateSpace or PeriodicStateSpace, got {type(system).__name__}")


# ---------------------------------------------------------------------------
# the coupled system


@dataclass(frozen=True, eq=False)
class _KernelOrigin:
    """How :func:`rotor_system` or :func:`blade_system` built a system: the compiled
    runner of :mod:`liquidamp.coupled.fast` that integrates it and that runner's arguments.

    ``runner(*args, t_end, x0, inputs=inputs, **kwargs)`` (looked up by name at
    call time) integrates the same system; ``structure`` is the
    :class:`~liquidamp.structure.rotor.GroundResonanceRotor` (its lag dampers
    as in the host) or :class:`~liquidamp.structure.blade.ArticulatedBlade`
    whose equations the kernel runs, at rotor speed ``Omega`` [rad/s].
    """

    runner: str
    structure: object
    Omega: float
    args: tuple
    kwargs: Mapping
    host: HostMatrices
    devices: tuple[Device, ...]
    inputs: tuple


@dataclass(frozen=True, eq=False)
class CoupledSystem:
    """A host with devices on some of its ports (see the module notes).

    Attributes
    ----------
    host : HostMatrices
    ports : tuple of DevicePort
        The ports that carry a device, in order.
    devices : tuple of Device
        One per port.
    name : str
    inputs : tuple of HarmonicInput
        External inputs on host inputs that take no device force (module
        notes); empty for the free system.
    origin : object or None
        Set by :func:`rotor_system` and :func:`blade_system` only (how they
        built it, for ``SolverOptions(engine="compiled")`` in
        :func:`simulate_coupled`).
    """

    host: HostMatrices
    ports: tuple[DevicePort, ...]
    devices: tuple[Device, ...]
    name: str = "coupled"
    inputs: tuple[HarmonicInput, ...] = ()
    _idx: dict = field(default_factory=dict, repr=False)
    #: How :func:`rotor_system` / :func:`blade_system` built it (the compiled
    #: engine's route); None otherwise.  ``init=False``: a ``dataclasses.replace``
    #: copy drops it.
    origin: _KernelOrigin | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        h = self.host
        out = {n: i for i, n in enumerate(h.output_names)}
        inp = {n: i for i, n in enumerate(h.input_names)}
        iy, iv, iF = [], [], []
        for p in self.ports:
            for sig, table in ((p.stroke_output, out), (p.rate_output, out),
                               (p.force_input, inp)):
                if sig not in table:
                    raise ParameterError(f"port {p.name!r}: host {h.name!r} has no signal "
                                         f"{sig!r}")
            iy.append(out[p.stroke_output])
            iv.append(out[p.rate_output])
            iF.append(inp[p.force_input])
        object.__setattr__(self, "inputs", tuple(self.inputs))
        iu = []
        forces = {p.force_input: p.name for p in self.ports}
        for u in self.inputs:
            if not isinstance(u, HarmonicInput):
                raise ParameterError(f"inputs must be HarmonicInput, got {type(u).__name__}")
            if u.input not in inp:
                free = [n for n in h.input_names if n not in forces]
                raise ParameterError(f"host {h.name!r} has no input {u.input!r}; inputs "
                                     f"without a device: {', '.join(free) or 'none'}")
            if u.input in forces:
                raise ParameterError(f"host input {u.input!r} takes the force of the device "
                                     f"at port {forces[u.input]!r}; drive another input")
            iu.append(inp[u.input])
        if len(set(iu)) != len(iu):
            raise ParameterError("each host input may be driven by one HarmonicInput only, "
                                 f"got {[u.input for u in self.inputs]}")
        offs = [h.nstates]
        for d in self.devices:
            offs.append(offs[-1] + d.n_states)
        self._idx.update(iy=np.array(iy, int), iv=np.array(iv, int), iF=np.array(iF, int),
                         iu=np.array(iu, int), offs=offs,
                         acc=any(d.model.uses_acceleration for d in self.devices))

    def with_inputs(self, inputs) -> CoupledSystem:
        """The same host and devices driven by ``inputs`` (sequence of HarmonicInput).

        Replaces the inputs (an empty sequence gives the free system); a
        system built by :func:`rotor_system` or :func:`blade_system` keeps its
        compiled route.

        Examples
        --------
        >>> from liquidamp.structure.hostio import load_rotor
        >>> free = blade_system(load_rotor("hammond1974").blade, 26.0, viscous(1e4))
        >>> forced = free.with_inputs([HarmonicInput("moment", 26.0, sin_amplitude=500.0)])
        >>> [u.input for u in forced.inputs], free.inputs
        (['moment'], ())
        """
        new = CoupledSystem(self.host, self.ports, self.devices, self.name, tuple(inputs))
        o = self.origin
        if o is not None:
            object.__setattr__(new, "origin", _KernelOrigin(
                o.runner, o.structure, o.Omega, o.args, o.kwargs, o.host, o.devices, new.inputs))
        return new

    @property
    def input_matrix(self):
        """``t -> B_u(t)``: columns of B(t) taking the external inputs [state rate per unit]."""
        iu = self._idx["iu"]
        return lambda t: self.host.B(t)[:, iu]

    # ----------------------------------------------------------- layout
    @property
    def port_names(self) -> tuple[str, ...]:
        """Names of the ports with a device."""
        return tuple(p.name for p in self.ports)

    @property
    def n_states(self) -> int:
        """Host states plus all device states."""
        return self._idx["offs"][-1]

    @property
    def state_names(self) -> tuple[str, ...]:
        """Host state names, then ``PORT.STATE`` for each device state."""
        names = list(self.host.state_names)
        for p, d in zip(self.ports, self.devices, strict=True):
            names += [f"{p.name}.{s}" for s in d.model.state_names]
        return tuple(names)

    def device_slice(self, j: int) -> slice:
        """Slice of device ``j``'s states in the coupled state vector."""
        offs = self._idx["offs"]
        return slice(offs[j], offs[j + 1])

    @property
    def stroke_matrix(self) -> np.ndarray:
        """Rows of C giving the strokes of the device ports [m per state unit]."""
        return self.host.C[self._idx["iy"]]

    @property
    def rate_matrix(self) -> np.ndarray:
        """Rows of C giving the stroke rates [m/s per state unit]."""
        return self.host.C[self._idx["iv"]]

    @property
    def force_inputs(self) -> np.ndarray:
        """Indices of the host inputs (columns of B) that take the device forces, one per port."""
        return self._idx["iF"]

    def force_matrix(self, t: float) -> np.ndarray:
        """Columns of B(t) taking the device forces [state rate per N]."""
        return self.host.B(t)[:, self._idx["iF"]]

    def initial_state(self, host_state=None) -> np.ndarray:
        """Coupled state with the host at ``host_state`` and each device at rest.

        Parameters
        ----------
        host_state : array or mapping, optional
            Host state (array in ``host.state_names`` order, or
            ``{name: value}``; missing names are 0) [host units].  Each device
            starts at rest (``model.initial_state(params, y0)``) at its
            initial stroke.
        """
        h = self.host
        xh = np.zeros(h.nstates)
        if isinstance(host_state, Mapping):
            for k, v in host_state.items():
                if k not in h.state_names:
                    raise ParameterError(f"unknown host state {k!r}; valid: "
                                         f"{', '.join(h.state_names)}")
                xh[h.state_names.index(k)] = float(v)
        elif host_state is not None:
            xh = np.asarray(host_state, float).reshape(-1)
            if xh.size != h.nstates:
                raise ParameterError(f"host state needs {h.nstates} values, got {xh.size}")
        y = self.stroke_matrix @ xh
        parts = [xh]
        for j, d in enumerate(self.devices):
            if abs(y[j]) >= d.stroke_limit:
                raise ParameterError(f"initial stroke {y[j]:g} m at port {self.ports[j].name!r}"
                                     f" is beyond the chamber end {d.stroke_limit:g} m")
            parts.append(np.asarray(d.model.initial_state(d.params, float(y[j])), float))
        return np.concatenate(parts)

    # ----------------------------------------------------------- dynamics
    def evaluate(self, t: float, x):
        """Port signals and state derivative at (t, x).

        Returns
        -------
        dict
            ``xdot`` (coupled state rate), ``stroke`` [m], ``rate`` [m/s],
            ``acceleration`` [m/s^2], ``force`` [N] (arrays over the ports).
        """
        idx = self._idx
        x = np.asarray(x, float)
        nh = self.host.nstates
        xh = x[:nh]
        if self.host.AB is not None:
            A, B = self.host.AB(t)
        else:
            A, B = self.host.A(t), self.host.B(t)
        Bf = B[:, idx["iF"]]
        Cv = self.rate_matrix
        y = self.stroke_matrix @ xh
        v = Cv @ xh
        m = len(self.devices)
        F0 = np.empty(m)
        b = np.zeros(m)
        zs = [x[self.device_slice(j)] for j in range(m)]
        for j, d in enumerate(self.devices):
            F0[j] = d.model.force(t, zs[j], (y[j], v[j], 0.0), d.params)
            if idx["acc"]:
                b[j] = d.acceleration_gain(t, zs[j], y[j], v[j])
        Axh = A @ xh
        if self.inputs:  # external inputs: part of the host's rate before the device forces
            Axh = Axh + B[:, idx["iu"]] @ input_values(self.inputs, t)
        if idx["acc"] and np.any(b != 0.0):
            CvB = Cv @ Bf
            F = np.linalg.solve(np.eye(m) - b[:, None] * CvB, F0 + b * (Cv @ Axh))
        else:
            F = F0
        xhd = Axh + Bf @ F
        a = Cv @ xhd
        parts = [xhd]
        for j, d in enumerate(self.devices):
            if d.n_states:
                parts.append(np.asarray(d.model.rhs(t, zs[j], (y[j], v[j], a[j]), d.params),
                                        float))
        return {"xdot": np.concatenate(parts), "stroke": y, "rate": v, "acceleration": a,
                "force": F}

    def rhs(self, t: float, x) -> np.ndarray:
        """d x / d t of the coupled system [state units / s]."""
        return self.evaluate(t, x)["xdot"]


def couple(host, devices: Mapping[str, Device], ports=None, *, mechanics=None,
           name: str = "", inputs=()) -> CoupledSystem:
    """Join devices to a host's ports by port name.

    Parameters
    ----------
    host : control.StateSpace, PeriodicStateSpace or HostMatrices
        The structure (constant or periodic coefficients).
    devices : mapping
        ``{port name: Device}``.
    ports : sequence of DevicePort, optional
        The host's ports (default ``host.ports``; a plain StateSpace has none).
    mechanics : callable, optional
        ``t -> (M, C, K)`` for the energy balance (see :class:`HostMatrices`).
    name : str
    inputs : sequence of HarmonicInput
        External inputs on host inputs that take no device force (module notes).

    Returns
    -------
    CoupledSystem

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> s = load_section("hodges-pierce")
    >>> sys = couple(s.statespace(10.0, "jones"), {"plunge": viscous(20.0)}, s.ports)
    >>> sys.port_names, sys.n_states
    (('plunge',), 6)
    """
    h, D = _as_host(host, ports, mechanics)
    if np.any(D != 0.0):
        raise ParameterError("the host must not feed its inputs through to its outputs "
                             "(D != 0): strokes must be functions of the host state")
    if not devices:
        raise ParameterError("give at least one {port: Device}")
    ps, ds = [], []
    for pname, dev in devices.items():
        if not isinstance(dev, Device):
            raise ParameterError(f"port {pname!r}: expected a Device, got {type(dev).__name__}")
        ps.append(find_port(h.ports, pname))
        ds.append(dev)
    return CoupledSystem(h, tuple(ps), tuple(ds), name or h.name, tuple(inputs))


def rotor_system(rotor, Omega: float, device, *, inoperative=(), inputs=()) -> CoupledSystem:
    """A rotor with a device on each blade's port (rotating frame, periodic).

    The rotor's own lag damper is removed on every blade that gets a device
    and on every ``inoperative`` blade (failed damper: no device there
    either).

    Parameters
    ----------
    rotor : GroundResonanceRotor
    Omega : float
        Rotor speed > 0 [rad/s].
    device : Device or mapping
        The same device on every operative blade, or ``{blade k (1-based): Device}``.
    inoperative : sequence of int
        Blades whose damper has failed.
    inputs : sequence of HarmonicInput
        External inputs (``moment_k`` [N m], ``hub_force_x``, ``hub_force_y`` [N]).

    Returns
    -------
    CoupledSystem
        With ``host.mechanics`` set (energy balance available).

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> sys = rotor_system(load_rotor("hammond1974"), 25.0, viscous(65080.0), inoperative=[1])
    >>> sys.port_names
    ('blade_2', 'blade_3', 'blade_4')
    """
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    inoperative = tuple(inoperative)
    failed = {rotor.check_blade(k) for k in inoperative}
    if isinstance(device, Device):
        mapping = {k: device for k in range(1, rotor.n_blades + 1) if k not in failed}
    else:
        mapping = {rotor.check_blade(k): d for k, d in dict(device).items()}
        bad = failed & set(mapping)
        if bad:
            raise ParameterError(f"blades {sorted(bad)} are inoperative and also have a device")
    c = list(rotor.blade_damping)
    for k in set(mapping) | failed:
        c[k - 1] = 0.0
    host = rotor.with_lag_dampers(c)
    pss = host.periodic_statespace(W)

    def mechanics(t, host=host, W=W):
        return host.second_order(W, W * t)

    def AB(t, host=host, W=W):
        return host.first_order(W, W * t)

    h = HostMatrices(pss.A, pss.B, np.asarray(pss.C, float), tuple(pss.state_names),
                     tuple(pss.input_names), tuple(pss.output_names), tuple(pss.ports),
                     float(pss.period), pss.name, mechanics, AB)
    system = couple(h, {f"blade_{k}": mapping[k] for k in sorted(mapping)},
                    name=f"{rotor.name}@{W:.4g}rad/s", inputs=inputs)
    # record the route for the compiled engine (the object is fresh, not yet shared)
    object.__setattr__(system, "origin", _KernelOrigin(
        "simulate_rotor", host, W, (rotor, W, MappingProxyType(dict(mapping))),
        MappingProxyType({"inoperative": inoperative}), h, system.devices, system.inputs))
    return system


def blade_system(blade, Omega: float, device: Device, *, inputs=()) -> CoupledSystem:
    """A blade in lead-lag (rotating frame, hub fixed) with a device on its port ``lag``.

    The blade's own lag damper stays (set ``lag_damping=0`` on the blade for
    the device alone).  The coefficients are constant; with harmonic
    ``inputs`` (the lag moment ``moment`` [N m]) the forced system is periodic.

    Parameters
    ----------
    blade : ArticulatedBlade
    Omega : float
        Rotor speed > 0 [rad/s] (centrifugal lag stiffness).
    device : Device
    inputs : sequence of HarmonicInput
        External inputs (``moment`` [N m]).

    Returns
    -------
    CoupledSystem
        With ``host.mechanics`` set (energy balance) and the compiled route
        (:func:`liquidamp.coupled.fast.simulate_blade`).

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> sys = blade_system(load_rotor("hammond1974").blade.replace(lag_damping=0.0), 26.0,
    ...                    viscous(1e4))
    >>> sys.state_names, sys.host.input_names
    (('zeta', 'zeta_dot'), ('force', 'moment'))
    """
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    if not isinstance(device, Device):
        raise ParameterError(f"device must be a Device, got {type(device).__name__}")
    ss = blade.statespace(W)

    def mechanics(t, blade=blade, W=W):
        return blade.second_order(W)

    h, _ = _as_host(ss, blade.ports, mechanics)
    system = couple(h, {"lag": device}, name=f"blade@{W:.4g}rad/s", inputs=inputs)
    object.__setattr__(system, "origin", _KernelOrigin(
        "simulate_blade", blade, W, (blade, W, device), MappingProxyType({}), h, system.devices,
        system.inputs))
    return system


def section_system(section, U: float, devices: Mapping[str, Device], aero: str = "jones"
                   ) -> CoupledSystem:
    """A typical section at airspeed ``U`` [m/s] with devices on ``plunge``/``pitch``.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> sys = section_system(load_section("hodges-pierce"), 5.0, {"pitch": viscous(10.0)})
    >>> sys.state_names[:4]
    ('h', 'theta', 'h_dot', 'theta_dot')
    """
    return couple(section.statespace(U, aero), devices, section.ports,
                  name=f"{section.name}@{U:.4g}m/s")


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


def _compiled_origin(system: CoupledSystem) -> _KernelOrigin:
    """How ``system`` was built (:class:`_KernelOrigin`); ParameterError if not compiled."""
    from liquidamp.structure.blade import ArticulatedBlade
    from liquidamp.structure.rotor import GroundResonanceRotor

    head = "engine 'compiled' (simulate_coupled)"
    o = system.origin
    if o is None:
        what = (f"host {system.host.name!r} has constant coefficients (a typical section or "
                "another linear StateSpace)" if system.host.period is None else
                f"system {system.name!r} was not built by rotor_system() (couple() on periodic "
                "matrices, or a dataclasses.replace copy)")
        raise ParameterError(f"{head} integrates only the ground-resonance rotor and the blade "
                             "with devices built by rotor_system() or blade_system(); "
                             f"{what}; use engine='scipy'")
    if system.host is not o.host or len(system.devices) != len(o.devices) or any(
            a is not b for a, b in zip(system.devices, o.devices, strict=True)) \
            or system.inputs != o.inputs:
        raise ParameterError(f"{head}: system {system.name!r} no longer matches the "
                             f"{o.runner.replace('simulate_', '')}_system() call that built it; "
                             "use engine='scipy'")
    if type(o.structure) not in (GroundResonanceRotor, ArticulatedBlade):
        raise ParameterError(f"{head} integrates the ArticulatedBlade and "
                             "GroundResonanceRotor equations only, got a "
                             f"{type(o.structure).__name__}; use engine='scipy'")
    from liquidamp.coupled import fast

    for p, d in zip(system.ports, system.devices, strict=True):
        where = f"device {d.label!r} at port {p.name!r}"
        if d.model.uses_acceleration:
            raise ParameterError(f"{head} does not integrate model {d.model.name!r} ({where}): "
                                 "its force depends on the stroke acceleration; "
                                 "use engine='scipy'")
        try:
            fast.check_compiled(d.model)
        except ParameterError as exc:
            raise ParameterError(f"{where}: {exc}") from None
    return o


def compiled_support(system: CoupledSystem) -> str | None:
    """Why ``SolverOptions(engine="compiled")`` cannot run ``system``, or None if it can.

    The compiled route of :func:`simulate_coupled` takes a ground-resonance
    rotor built by :func:`rotor_system` or a blade built by
    :func:`blade_system` (with any external inputs) whose devices do not use
    the stroke acceleration (every model of the family, with any add-on
    effects, and the viscous damper are compiled); it integrates with DOP853
    and agrees with the Python route run with ``method="DOP853"`` to
    round-off (about 1e-13 relative).

    Parameters
    ----------
    system : CoupledSystem
        Host with devices.

    Returns
    -------
    str or None
        The reason, as the ParameterError :func:`simulate_coupled` would raise.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.device import preset
    >>> rotor = load_rotor("hammond1974")
    >>> compiled_support(rotor_system(rotor, 27.2, Device("full", preset("reference")))) is None
    True
    >>> "acceleration" in compiled_support(rotor_system(rotor, 27.2,
    ...                                                 Device("inerter", preset("inerter"))))
    True
    """
    try:
        _compiled_origin(system)
    except ParameterError as exc:
        return str(exc)
    return None


def _run_compiled(system, T_end, X0, t_eval, opts, max_step, conds):
    """Compiled route (the runner of the system's origin in :mod:`liquidamp.coupled.fast`,
    :func:`~liquidamp.coupled.fast.simulate_rotor` or
    :func:`~liquidamp.coupled.fast.simulate_blade`): as :func:`_run_python`.

    The kernel stops at the end of the step in which a stop condition is
    met; the samples after the crossing are dropped and the crossing is
    located on the same trajectory (the step sequence does not depend on
    the output times) by re-running with output grids that close in on it,
    so the result has the samples, status and message of the Python route.
    """
    from liquidamp.coupled import fast

    o = _compiled_origin(system)

    def run(times):
        runner = getattr(fast, o.runner)
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
        :func:`liquidamp.coupled.fast.simulate_rotor` (DOP853 with scipy's
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
