"""Host plus device(s) as one system: :func:`couple`, :func:`rotor_system`, :func:`blade_system`.

The devices (:class:`Device`, :func:`viscous`), the host matrices and the
coupled system (:class:`CoupledSystem`) of :mod:`liquidamp.coupled.assembly`
(the public face, which re-exports every name and documents the equations);
the time domain (:func:`~liquidamp.coupled.assembly.simulate_coupled`) is
there.  This module knows nothing of the engines, so that the compiled
kernels (:mod:`liquidamp.coupled.fast`) can build systems without an import
circle.

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

from liquidamp.coupled.inputs import HarmonicInput, input_values
from liquidamp.device.models import VISCOUS, DeviceModel, ViscousParams, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import (
    ParameterError,
    check_positive,
)
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
        (:func:`liquidamp.coupled.fast_rotor.simulate_blade`).

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


def _compiled_origin(system: CoupledSystem, check_model) -> _KernelOrigin:
    """How ``system`` was built (:class:`_KernelOrigin`); ParameterError if not compiled.

    ``check_model(model)`` raises ParameterError for a device model the compiled
    kernel cannot run (:func:`liquidamp.coupled.fast.check_compiled`).
    """
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
    for p, d in zip(system.ports, system.devices, strict=True):
        where = f"device {d.label!r} at port {p.name!r}"
        if d.model.uses_acceleration:
            raise ParameterError(f"{head} does not integrate model {d.model.name!r} ({where}): "
                                 "its force depends on the stroke acceleration; "
                                 "use engine='scipy'")
        try:
            check_model(d.model)
        except ParameterError as exc:
            raise ParameterError(f"{where}: {exc}") from None
    return o
