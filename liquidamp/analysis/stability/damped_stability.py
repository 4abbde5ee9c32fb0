"""Linear stability of hosts with devices: rotor ground resonance and wing flutter.

Each device is replaced by a linear time-invariant system from the port
signals u = (stroke [m], stroke_rate [m/s], stroke_acceleration [m/s^2]) to
the force F [N] (:class:`DeviceLTI`):

* small signal (:func:`device_lti` without an amplitude): the device model
  linearized at rest (:func:`liquidamp.analysis.response.linear.linearize`), reduced
  to its controllable and observable part (the full model's invariant modes
  at zero are removed); the quadratic loss drops out (zero slope at rest)
  and friction has no small-signal linearization;
* equivalent (``amplitude`` and ``frequency`` given): the describing
  function of :mod:`liquidamp.analysis.response.equivalent` -- the quadratic loss as
  c_eq = c1 + 8 c2 q_hat/(3 pi), Coulomb friction as 4 F_f/(pi omega Y),
  optionally the cycle-averaged bulk modulus -- realized as the linear
  eq. (18) (states dp [Pa], q [m^3/s]) or the Maxwell unit (models without
  inertance), plus the friction's viscous equivalent.

The closed loop with a host (:class:`~liquidamp.coupled.assembly.CoupledSystem`)
is formed two ways that agree to round-off (tested):
:func:`closed_loop_interconnect` joins the named systems with
:func:`control.interconnect` (a device's acceleration feed-through, an
inerter, is first moved into the host -- python-control does not solve
algebraic loops -- which is the inerter's b arm^2 added to the mass
matrix); :func:`closed_loop_matrix` builds the same matrix by blocks, fast
enough for Floquet integration and sweeps.

Rotor (:func:`rotor_device_eigenvalues`, :func:`device_ground_resonance_sweep`):
with the same device on every blade the multiblade (Coleman) transform of
the closed loop -- host coordinates and every blade's device states -- has
constant coefficients; with a failed damper the closed loop is periodic and
Floquet theory decides (a failed blade carries a "null" copy of the device,
uncoupled, so that the state layout stays symmetric for the frequency
resolution; its modes are the device's own stable modes).

Section (:func:`damped_flutter_analysis`): the p method with R. T. Jones'
finite-state aerodynamics and the device in the loop.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (16)-(20).
.. [2] C. E. Hammond, J. American Helicopter Society 19(4), 14-23, 1974.
.. [3] D. H. Hodges, G. A. Pierce, Introduction to Structural Dynamics and
   Aeroelasticity, 2nd ed., 2011, Ch. 5.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import control
import numpy as np
from scipy.optimize import brentq

from liquidamp._compat import renamed
from liquidamp.analysis.response.equivalent import equivalent_linearization
from liquidamp.analysis.response.linear import INPUT_NAMES, linearize
from liquidamp.analysis.stability.floquet import (
    FloquetOptions,
    floquet_analysis,
    resolve_frequencies,
)
from liquidamp.analysis.stability.flutter import FlutterResult, divergence_speed
from liquidamp.analysis.stability.ground_resonance import (
    GroundResonanceSweep,
    unstable_ranges,
)
from liquidamp.analysis.stability.modes import track_modes
from liquidamp.coupled.assembly import (
    CoupledSystem,
    Device,
    ViscousParams,
    rotor_system,
    section_system,
)
from liquidamp.device.effects import with_effects
from liquidamp.device.models import BASES, REGISTRY
from liquidamp.errors import ParameterError, check_positive
from liquidamp.structure.rotor import multiblade_basis

__all__ = [
    "DeviceLTI",
    "closed_loop_mbc_transform",
    "device_lti",
    "closed_loop_matrix",
    "closed_loop_interconnect",
    "coupled_eigenvalues",
    "rotor_closed_loop",
    "rotor_device_eigenvalues",
    "rotor_device_floquet",
    "device_ground_resonance_sweep",
    "section_device_eigenvalues",
    "damped_flutter_analysis",
]

_INERTIAL = ("full", "inertial", "inertial_2state")
_NO_INERTIA = ("no_inertia", "constant_bulk", "volumetric", "single_state")


@dataclass(frozen=True, eq=False)
class DeviceLTI:
    """Linear device: z' = A z + B u, F = C z + D u, u = (y [m], v [m/s], a [m/s^2]).

    Attributes
    ----------
    A, B, C, D : ndarray
        Shapes (n, n), (n, 3), (1, n), (1, 3).
    label : str
    kind : str
        ``small-signal`` or ``equivalent (Y = .. m, f = .. Hz)``.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    label: str = "device"
    kind: str = "small-signal"

    @property
    def n_states(self) -> int:
        """Number of states."""
        return self.A.shape[0]

    def system(self, port=None) -> control.StateSpace:
        """Named StateSpace; with a port, inputs/outputs carry the port's signal names."""
        if port is None:
            ins, out = list(INPUT_NAMES), ["force"]
        else:
            ins = [port.stroke_output, port.rate_output, _acc_name(port)]
            out = [port.force_input]
        return control.ss(self.A, self.B, self.C, self.D, inputs=ins, outputs=out,
                          states=[f"{self.label}[{i}]" for i in range(self.n_states)],
                          name=f"{self.label}" if port is None else f"{self.label}@{port.name}")

    def stiffness(self, frequency):
        """K(i w) = F/Y under y = Y e^{i w t} [N/m] at ``frequency`` [Hz].

        Scalar in, scalar out: a complex for a number, an array of the same
        shape for an array.

        Examples
        --------
        >>> from liquidamp.coupled.assembly import viscous
        >>> lti = device_lti(viscous(1e3))
        >>> lti.stiffness(1.0) == 2j * math.pi * 1e3
        True
        >>> lti.stiffness([1.0, 2.0]).shape
        (2,)
        """
        f_in = np.asarray(frequency, float)
        f = np.atleast_1d(f_in).ravel()
        out = np.empty(f.size, complex)
        for i, fi in enumerate(f):
            s = 2j * math.pi * fi
            u = np.array([1.0, s, s * s])
            val = self.D[0] @ u
            if self.n_states:
                val += self.C[0] @ np.linalg.solve(s * np.eye(self.n_states) - self.A,
                                                   self.B @ u)
            out[i] = val
        return complex(out[0]) if f_in.ndim == 0 else out.reshape(f_in.shape)

    def null(self) -> DeviceLTI:
        """Same states, no coupling (B = 0, C = 0, D = 0): a failed blade's placeholder."""
        return DeviceLTI(self.A, np.zeros_like(self.B), np.zeros_like(self.C),
                         np.zeros_like(self.D), f"{self.label}(null)", self.kind)


def _acc_name(port) -> str:
    return f"stroke_acceleration_{port.name}"


def _eq18(A_p, B, L_t, c, c_f) -> tuple:
    if L_t > 0.0:
        A = np.array([[0.0, -B], [1.0 / L_t, -c / L_t]])
        Bm = np.array([[0.0, B * A_p, 0.0], [0.0, 0.0, 0.0]])
        C = np.array([[A_p, 0.0]])
    else:
        A = np.array([[-B / c]])
        Bm = np.array([[0.0, B * A_p, 0.0]])
        C = np.array([[A_p]])
    return A, Bm, C, np.array([[0.0, c_f, 0.0]])


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def device_lti(device: Device, *, amplitude: float | None = None,
               frequency: float | None = None, bulk: str = "rest") -> DeviceLTI:
    """Linear model of a device: small-signal or equivalent at (Y, f).

    Parameters
    ----------
    device : Device
    amplitude, frequency : float, optional
        Stroke amplitude [m] and frequency [Hz] of the equivalent
        linearization (both or neither).
    bulk : {"rest", "averaged", "auto"}
        Bulk modulus of the equivalent linearization (see
        :func:`~liquidamp.analysis.response.equivalent.equivalent_linearization`);
        ``rest`` (default) keeps B at p0 like the small-signal model, so the
        amplitude dependence is the losses' alone.

    Returns
    -------
    DeviceLTI

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.coupled.assembly import Device
    >>> p = preset("reference")
    >>> lti = device_lti(Device("full", p))
    >>> lti.n_states                      # invariant modes removed
    2
    >>> k = lti.stiffness(7.0)
    >>> from liquidamp.analysis.response.linear import inertial_2state_tf
    >>> round(float(abs(k / complex(inertial_2state_tf(p)(2j * math.pi * 7.0)) - 1)), 9)
    0.0
    """
    m, p = device.model, device.params
    if (amplitude is None) != (frequency is None):
        raise ParameterError("give both amplitude [m] and frequency [Hz], or neither")
    if isinstance(p, ViscousParams):
        # F = c v + c2 v|v|: the quadratic part has zero slope at rest (small signal: c
        # alone) and the describing function 8 c2 w Y / (3 pi) at (Y, f)
        if not m.effects and (amplitude is None or p.c2 == 0.0):
            kind = "exact" if p.c2 == 0.0 else "small-signal (c2 v|v| has no slope at rest)"
            return DeviceLTI(np.zeros((0, 0)), np.zeros((0, 3)), np.zeros((1, 0)),
                             np.array([[0.0, p.c, 0.0]]), device.label, kind)
        if amplitude is None:  # the effects must be linear to hold at rest
            for e in m.effects:
                e.check_small_signal(p)
            raise ParameterError(
                f"no small-signal model of the viscous damper with effects "
                f"({', '.join(e.name for e in m.effects)}); give amplitude and frequency "
                "for the equivalent linearization")
        check_positive("amplitude", amplitude, "m")
        check_positive("frequency", frequency, "Hz")
        w = 2.0 * math.pi * frequency
        D = np.array([[0.0, p.describing_damping(amplitude, w), 0.0]])
        for e in m.effects:
            D = D + np.asarray(e.describing_function(amplitude, w, p, model=m))[None, :]
        return DeviceLTI(np.zeros((0, 0)), np.zeros((0, 3)), np.zeros((1, 0)), D,
                         device.label, f"equivalent (Y = {amplitude:.4g} m, f = "
                         f"{frequency:.4g} Hz)" + (" with " + ", ".join(
                             e.name for e in m.effects) if m.effects else ""))
    base = m.base
    if amplitude is None:
        # stateless parallel force effects (moving mass, offset) are exact parallel elements:
        # add their (k, c, b) to the feedthrough of the rest of the model
        parallel = [e for e in m.effects if e.kind == "force" and not e.state_names
                    and e.small_signal_reason is None and e.linear]
        if parallel:
            rest = with_effects(BASES[base], *[e for e in m.effects if e not in parallel])
            lti = device_lti(Device(rest, p, device.label))
            extra = sum(np.asarray(e.describing_function(1.0, 1.0, p, model=m))
                        for e in parallel)
            return DeviceLTI(lti.A, lti.B, lti.C, lti.D + extra[None, :], device.label,
                             lti.kind)
        lin = linearize(m, p)
        k = lin.output_names.index("force")
        if not lin.is_proper_in_stroke:  # a rate (dashpot) or acceleration feedthrough
            if lin.n_states and not m.effects:  # (kept by the unreduced form below)
                raise ParameterError(f"model {m.name!r}: improper with states; not supported")
            if not lin.n_states:
                return DeviceLTI(np.zeros((0, 0)), np.zeros((0, 3)), np.zeros((1, 0)),
                                 lin.D[k:k + 1].copy(), device.label, "small-signal")
        if not m.effects:
            mn = lin.minimal()
            Bm = np.zeros((mn.nstates, 3))
            Bm[:, 0] = np.asarray(mn.B, float)[:, 0]
            D = np.zeros((1, 3))
            D[0, 0] = float(mn.D[0, 0])
            return DeviceLTI(np.asarray(mn.A, float), Bm, np.asarray(mn.C, float), D,
                             device.label, "small-signal")
        return DeviceLTI(lin.A.copy(), lin.B.copy(), lin.C[k:k + 1].copy(),
                         lin.D[k:k + 1].copy(), device.label,
                         "small-signal (not reduced: model with effects)")
    check_positive("amplitude", amplitude, "m")
    check_positive("frequency", frequency, "Hz")
    if base not in REGISTRY:
        raise ParameterError(f"no equivalent linearization for model {m.name!r}")
    # each effect states its describing function (a parallel element) or raises naming itself
    w = 2.0 * math.pi * frequency
    extra = np.zeros(3)
    for e in m.effects:
        extra += e.describing_function(amplitude, w, p, model=m)
    eq = equivalent_linearization(p, frequency, amplitude, base, bulk=bulk)
    kind = f"equivalent (Y = {amplitude:.4g} m, f = {frequency:.4g} Hz)"
    if m.effects:
        kind += " with " + ", ".join(e.name for e in m.effects)
    cf = eq.c_friction
    if base in _INERTIAL:
        A, B, C, D = _eq18(p.A_p, eq.B, p.L_t, eq.c_eq, cf)
    elif base in _NO_INERTIA:
        A, B, C, D = _eq18(p.A_p, eq.B, 0.0, eq.c_eq, cf)
    else:
        lin = device_lti(Device(BASES[base], p, device.label))
        A, B, C, D = lin.A, lin.B, lin.C, lin.D.copy()
        D[0, 1] += cf
    D = D + extra[None, :]
    return DeviceLTI(A, B, C, D, device.label, kind)


# ---------------------------------------------------------------------------
# closed loops


def _ltis(system: CoupledSystem, ltis):
    if ltis is None:
        ltis = [device_lti(d) for d in system.devices]
    ltis = list(ltis)
    if len(ltis) != len(system.devices):
        raise ParameterError(f"need one DeviceLTI per port ({len(system.devices)}), "
                             f"got {len(ltis)}")
    return ltis


def closed_loop_matrix(system: CoupledSystem, ltis=None, t: float = 0.0) -> np.ndarray:
    """Closed-loop A of host and linear devices at time ``t`` [s] (block formula).

    State: host states, then each device's linear states in port order.
    The acceleration loop is solved exactly (module notes).
    """
    ltis = _ltis(system, ltis)
    A = system.host.A(t)
    Bf = system.force_matrix(t)
    Cy, Cv = system.stroke_matrix, system.rate_matrix
    m = len(ltis)
    nz = [lt.n_states for lt in ltis]
    offs = np.concatenate([[0], np.cumsum(nz)]).astype(int)
    Nz = int(offs[-1])
    Dy = np.diag([lt.D[0, 0] for lt in ltis])
    Dv = np.diag([lt.D[0, 1] for lt in ltis])
    Da = np.diag([lt.D[0, 2] for lt in ltis])
    Cz = np.zeros((m, Nz))
    Az = np.zeros((Nz, Nz))
    By = np.zeros((Nz, m))
    Bv = np.zeros((Nz, m))
    Ba = np.zeros((Nz, m))
    for j, lt in enumerate(ltis):
        s = slice(offs[j], offs[j + 1])
        Cz[j, s] = lt.C[0]
        Az[s, s] = lt.A
        By[s, j], Bv[s, j], Ba[s, j] = lt.B[:, 0], lt.B[:, 1], lt.B[:, 2]
    L = np.linalg.inv(np.eye(m) - Da @ Cv @ Bf)
    Fx = L @ (Dy @ Cy + Dv @ Cv + Da @ Cv @ A)
    Fz = L @ Cz
    Ahh = A + Bf @ Fx
    Ahz = Bf @ Fz
    ax, az = Cv @ Ahh, Cv @ Ahz
    Azh = By @ Cy + Bv @ Cv + Ba @ ax
    Azz = Az + Ba @ az
    return np.block([[Ahh, Ahz], [Azh, Azz]]) if Nz else Ahh


def closed_loop_interconnect(system: CoupledSystem, ltis=None, t: float = 0.0
                             ) -> control.StateSpace:
    """The closed loop by :func:`control.interconnect`, joined by signal names.

    The host (frozen at ``t`` [s]) gets one more output per port, the stroke
    acceleration ``stroke_acceleration_PORT`` = C_v (A x + B u); a device's
    acceleration feed-through (inerter) is moved into the host first, since
    python-control does not solve algebraic loops.  External host inputs
    stay inputs; outputs are the host's.
    """
    ltis = _ltis(system, ltis)
    h = system.host
    A = h.A(t).copy()
    B = h.B(t).copy()
    C = h.C
    iF = system.force_inputs
    Cv = system.rate_matrix
    m = len(ltis)
    Da = np.diag([lt.D[0, 2] for lt in ltis])
    # absorb the acceleration feed-through: u_F = F' + Da a, a = Cv (A x + B u)
    if np.any(Da):
        Bf = B[:, iF]
        L = np.linalg.inv(np.eye(m) - Da @ Cv @ Bf)
        # F = L (F' + Da Cv A x + Da Cv B_other u_other)
        other = [i for i in range(B.shape[1]) if i not in set(iF)]
        Bo = B[:, other]
        A = A + Bf @ L @ Da @ Cv @ A
        Bnew = B.copy()
        Bnew[:, iF] = Bf @ L
        Bnew[:, other] = Bo + Bf @ L @ Da @ Cv @ Bo
        B = Bnew
    Cacc = Cv @ A
    Dacc = Cv @ B
    Caug = np.vstack([C, Cacc])
    Daug = np.vstack([np.zeros((C.shape[0], B.shape[1])), Dacc])
    outs = list(h.output_names) + [_acc_name(p) for p in system.ports]
    host = control.ss(A, B, Caug, Daug, states=list(h.state_names), inputs=list(h.input_names),
                      outputs=outs, name="host")
    devs = []
    for lt, port in zip(ltis, system.ports, strict=True):
        D = lt.D.copy()
        D[0, 2] = 0.0
        devs.append(DeviceLTI(lt.A, lt.B, lt.C, D, lt.label, lt.kind).system(port))
    forces = {p.force_input for p in system.ports}
    ext = [n for n in h.input_names if n not in forces]
    return control.interconnect([host] + devs, inplist=ext, outlist=list(h.output_names),
                                name=system.name)


def coupled_eigenvalues(system: CoupledSystem, ltis=None, t: float = 0.0) -> np.ndarray:
    """Eigenvalues [1/s] of the closed loop frozen at ``t`` (exact for a constant host)."""
    return np.linalg.eigvals(closed_loop_matrix(system, ltis, t))


# ---------------------------------------------------------------------------
# rotor


def closed_loop_mbc_transform(N: int, nz: int, Omega: float, psi: float):
    """Multiblade (Coleman) transformation of the closed-loop rotor state and its time derivative.

    The closed-loop state is [zeta, hub, zeta', hub', z_1..z_N]: N blade lag angles and the two
    hub displacements, their rates, then the ``nz`` states of each blade's device.  The blade
    coordinates (and each device's states, blade by blade) go to multiblade coordinates with
    :func:`liquidamp.structure.rotor.multiblade_basis`; the hub coordinates are unchanged.

    Parameters
    ----------
    N : int
        Number of blades.
    nz : int
        States of one device.
    Omega : float
        Rotor speed [rad/s].
    psi : float
        Azimuth of blade 1 [rad].

    Returns
    -------
    P, Pdot : ndarray
        x = P x_mbc, and dP/dt = Omega dP/dpsi [1/s]; square, of size 4 + 2 N + N nz.

    Examples
    --------
    >>> P, Pd = closed_loop_mbc_transform(3, 1, 20.0, 0.0)
    >>> P.shape, Pd.shape
    ((13, 13), (13, 13))
    """
    Tb, Tb1, Tb2 = multiblade_basis(N, psi)
    n = N + 2
    T, T1, T2 = np.eye(n), np.zeros((n, n)), np.zeros((n, n))
    T[:N, :N], T1[:N, :N], T2[:N, :N] = Tb, Tb1, Tb2
    Z = np.zeros((n, n))
    Ph = np.block([[T, Z], [Omega * T1, T]])
    Pdh = Omega * np.block([[T1, Z], [Omega * T2, T1]])
    Pz = np.kron(Tb, np.eye(nz))
    Pdz = Omega * np.kron(Tb1, np.eye(nz))
    nh, Nz = 2 * n, N * nz
    P = np.zeros((nh + Nz, nh + Nz))
    Pd = np.zeros_like(P)
    P[:nh, :nh], Pd[:nh, :nh] = Ph, Pdh
    P[nh:, nh:], Pd[nh:, nh:] = Pz, Pdz
    return P, Pd


@dataclass(frozen=True, eq=False)
class _RotorLoop:
    system: CoupledSystem
    ltis: tuple
    symmetric: bool

    def A(self, t):
        return closed_loop_matrix(self.system, self.ltis, t)


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def rotor_closed_loop(rotor, Omega: float, device: Device, *, inoperative=(),
                      amplitude: float | None = None, frequency: float | None = None,
                      lti: DeviceLTI | None = None, blade_ltis=None) -> _RotorLoop:
    """Rotor with a linear device on every blade; failed blades carry a null copy.

    ``blade_ltis`` (one :class:`DeviceLTI` per blade, all with the same
    states, e.g. one damper degraded) replaces ``lti`` and ``inoperative``.
    Returns an object with ``system`` (the CoupledSystem: the device on every
    blade, placeholders included), ``ltis`` and ``A(t)`` (closed loop).
    """
    sys_ = rotor_system(rotor, Omega, device)
    if blade_ltis is not None:
        ltis = tuple(blade_ltis)
        if len(ltis) != rotor.n_blades or len({lt.n_states for lt in ltis}) != 1:
            raise ParameterError(f"blade_ltis must hold {rotor.n_blades} DeviceLTI with the "
                                 f"same states, got {len(ltis)}")
        return _RotorLoop(sys_, ltis, False)
    lti = lti or device_lti(device, amplitude=amplitude, frequency=frequency)
    failed = {rotor.check_blade(k) for k in inoperative}
    ltis = tuple(lti.null() if k in failed else lti for k in range(1, rotor.n_blades + 1))
    return _RotorLoop(sys_, ltis, not failed)


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def rotor_device_floquet(rotor, Omega: float, device: Device, *, inoperative=(),
                         amplitude=None, frequency=None, lti=None,
                         options: FloquetOptions | None = None, blade_ltis=None):
    """Floquet exponents [1/s] of the rotor with devices (resolved frequencies).

    ``blade_ltis``: one linear device per blade (see :func:`rotor_closed_loop`).

    Returns
    -------
    resolved : ndarray of complex
        Exponents with the frequency branch matched to the eigenvalues of the
        revolution-averaged multiblade closed loop.
    result : FloquetResult
    """
    loop = rotor_closed_loop(rotor, Omega, device, inoperative=inoperative,
                             amplitude=amplitude, frequency=frequency, lti=lti,
                             blade_ltis=blade_ltis)
    T = 2.0 * math.pi / Omega
    n = loop.A(0.0).shape[0]
    res = floquet_analysis(loop.A, T, n, options)
    nz = loop.ltis[0].n_states
    N = rotor.n_blades
    if N >= 3:
        ref = []
        for psi in 2.0 * np.pi * np.arange(32) / 32:
            P, Pd = closed_loop_mbc_transform(N, nz, Omega, psi)
            ref.append(np.linalg.solve(P, loop.A(psi / Omega) @ P - Pd))
        ref = np.linalg.eigvals(np.mean(ref, axis=0))
        return resolve_frequencies(res.exponents, ref, Omega), res
    return res.exponents.copy(), res


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def rotor_device_eigenvalues(rotor, Omega: float, device: Device, *, inoperative=(),
                             method: str = "auto", amplitude=None, frequency=None,
                             lti=None, options: FloquetOptions | None = None,
                             vectors: bool = False):
    """Eigenvalues (Coleman) or resolved Floquet exponents [1/s] of rotor + devices.

    ``method``: ``coleman`` (same device on every blade: multiblade closed
    loop, constant), ``floquet``, or ``auto`` (coleman when no blade is
    inoperative).  With ``vectors`` (coleman only) also the eigenvectors.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.coupled.assembly import viscous
    >>> rotor = load_rotor("hammond1974")
    >>> from liquidamp.analysis.stability.ground_resonance import coleman_eigenvalues
    >>> lam = rotor_device_eigenvalues(rotor, 25.0, viscous(4067.5 / 0.25**2))
    >>> ref = coleman_eigenvalues(rotor, 25.0)
    >>> float(np.max(np.abs(np.sort_complex(lam) - np.sort_complex(ref)))) < 1e-8
    True
    """
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    if method == "auto":
        method = "floquet" if inoperative else "coleman"
    if method == "coleman":
        if inoperative:
            raise ParameterError("the multiblade (Coleman) closed loop needs a device on every "
                                 "blade; use method='floquet' with inoperative dampers")
        loop = rotor_closed_loop(rotor, W, device, amplitude=amplitude,
                                 frequency=frequency, lti=lti)
        P, Pd = closed_loop_mbc_transform(rotor.n_blades, loop.ltis[0].n_states, W, 0.0)
        Am = np.linalg.solve(P, loop.A(0.0) @ P - Pd)
        return np.linalg.eig(Am) if vectors else np.linalg.eigvals(Am)
    if method != "floquet":
        raise ParameterError(f"unknown method {method!r}; valid: auto, coleman, floquet")
    return rotor_device_floquet(rotor, W, device, inoperative=inoperative,
                                amplitude=amplitude, frequency=frequency, lti=lti,
                                options=options)[0]


def _gr_point(args):
    rotor, W, device, inoperative, lti, method, options = args
    return rotor_device_eigenvalues(rotor, W, device, inoperative=inoperative, lti=lti,
                                    method=method, options=options)


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def device_ground_resonance_sweep(rotor, Omega, device: Device, *, inoperative=(),
                                  method: str = "auto", amplitude=None, frequency=None,
                                  options: FloquetOptions | None = None, executor="serial",
                                  progress: bool | None = False, neutral_tol: float = 1e-6
                                  ) -> GroundResonanceSweep:
    """Ground-resonance sweep of a rotor whose lag dampers are ``device``.

    Parameters
    ----------
    rotor : GroundResonanceRotor
    Omega : array
        Increasing rotor speeds > 0 [rad/s].
    device : Device
        On every blade except ``inoperative`` ones (host dampers removed).
    method : {"auto", "coleman", "floquet"}
    amplitude, frequency : float, optional
        Equivalent linearization of the device (default small signal).
    executor : "serial", None or executor
        Passed to :func:`liquidamp.analysis.stability.parallel.map_batched`.

    Returns
    -------
    GroundResonanceSweep
        (same object as the host sweep; plot with
        :func:`~liquidamp.analysis.reports.stability_plots.plot_ground_resonance`).
    """
    from liquidamp.analysis.stability.parallel import map_batched

    W = np.atleast_1d(np.asarray(Omega, float))
    if W.size == 0 or np.any(~np.isfinite(W)) or np.any(W <= 0) or np.any(np.diff(W) <= 0):
        raise ParameterError(f"rotor speeds must be finite, > 0 and increasing [rad/s], got "
                             f"{W.tolist()}")
    inop = tuple(rotor.check_blade(k) for k in inoperative)
    used = ("floquet" if inop else "coleman") if method == "auto" else method
    lti = device_lti(device, amplitude=amplitude, frequency=frequency)
    items = [(rotor, float(w), device, inop, lti, used, options) for w in W]
    lams = map_batched(_gr_point, items, executor=executor, progress=progress)
    tracked = track_modes(W, lams).eigenvalues
    maxre = tracked.real.max(axis=1)

    def f(w):
        return float(np.max(_gr_point((rotor, w, device, inop, lti, used, options)).real))

    ranges = unstable_ranges(f, W, maxre, threshold=neutral_tol)
    note = (f"device {device.label} ({lti.kind}) on blades "
            f"{[k for k in range(1, rotor.n_blades + 1) if k not in inop]}, host lag dampers "
            f"removed; inoperative {list(inop)}; "
            + ("multiblade (Coleman) closed loop" if used == "coleman"
               else "Floquet exponents of the periodic closed loop"))
    return GroundResonanceSweep(f"{rotor.name}+{device.label}", W, used, method, tracked,
                                maxre, ranges, note)


# ---------------------------------------------------------------------------
# section


def section_device_eigenvalues(section, U: float, devices: dict, *, aero: str = "jones",
                               ltis=None, vectors: bool = False):
    """Eigenvalues [1/s] of the section at airspeed ``U`` [m/s] with linear devices.

    ``devices`` is ``{"plunge"|"pitch": Device}``; ``ltis`` optionally their
    :class:`DeviceLTI` in the same order.
    """
    sys_ = section_system(section, U, devices, aero)
    A = closed_loop_matrix(sys_, ltis)
    return np.linalg.eig(A) if vectors else np.linalg.eigvals(A)


def _structural_pair(lam, vec, nstruct=4):
    part = np.sum(np.abs(vec[:nstruct]) ** 2, axis=0) / np.sum(np.abs(vec) ** 2, axis=0)
    up = np.flatnonzero(lam.imag > 1e-9)
    order = list(up[np.argsort(-part[up])][:2])
    if len(order) < 2:
        rest = [i for i in np.argsort(-part) if i not in order and lam[i].imag >= -1e-9]
        order += rest[: 2 - len(order)]
    return lam[order], vec[:nstruct, order]


def damped_flutter_analysis(section, devices: dict, *, speeds=None, aero: str = "jones",
                            ltis=None, neutral: float = 1e-9) -> FlutterResult:
    """p-method flutter analysis of the section with linear devices in the loop.

    Parameters
    ----------
    section : TypicalSection
    devices : dict
        ``{"plunge"|"pitch": Device}``.
    speeds : array, optional
        Increasing reduced speeds U/(b omega_theta) > 0 [-] (default 0.05 to
        3.5, 70 points).
    aero : {"jones", "quasi-steady", "steady"}
        State-space aerodynamics (the p method).
    ltis : list of DeviceLTI, optional
        Linear device models (default small signal).

    Returns
    -------
    FlutterResult
        ``damping`` = Re(p) of the two structural modes (p in units of
        omega_theta), flutter speed from the largest real part of *all*
        closed-loop eigenvalues.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> from liquidamp.coupled.assembly import viscous
    >>> s = load_section("hodges-pierce")
    >>> r = damped_flutter_analysis(s, {"plunge": viscous(1e-9)})
    >>> round(r.flutter_speed, 4)     # Jones, no device: 2.17036
    2.1704
    """
    V = np.asarray(speeds if speeds is not None else np.linspace(0.05, 3.5, 70), float)
    if V.size < 2 or np.any(~np.isfinite(V)) or np.any(V <= 0) or np.any(np.diff(V) <= 0):
        raise ParameterError("speeds must hold at least two finite, strictly increasing reduced "
                             f"speeds > 0 [U/(b omega_theta)], got {V.tolist()}")
    wt = section.omega_theta
    ports = list(devices)
    if ltis is None:
        ltis = [device_lti(devices[k]) for k in ports]

    def eig(v):
        sys_ = section_system(section, section.speed(v), devices, aero)
        lam, vec = np.linalg.eig(closed_loop_matrix(sys_, ltis))
        return lam / wt, vec

    lams, vecs, maxre = [], [], []
    for v in V:
        lam, vec = eig(v)
        s, sv = _structural_pair(lam, vec)
        lams.append(s)
        vecs.append(sv)
        maxre.append(float(lam.real.max()))
    tr = track_modes(V, lams, vecs)
    P = tr.eigenvalues.T
    maxre = np.asarray(maxre)
    VF = wF = None
    for i in range(V.size - 1):
        if maxre[i] <= neutral < maxre[i + 1]:
            def f(v):
                return float(eig(v)[0].real.max()) - neutral
            VF = brentq(f, V[i], V[i + 1], xtol=1e-12)
            lam = eig(VF)[0]
            wF = float(abs(lam[np.argmax(lam.real)].imag))
            break
    labels = ", ".join(f"{devices[k].label} on {k}" for k in ports)
    note = f"p method, {aero} aerodynamics, devices: {labels} ({ltis[0].kind})"
    if VF is None:
        note += "; no flutter crossing in the range"
    return FlutterResult(section.name, aero, "p", np.tile(V, (2, 1)), np.abs(P.imag), P.real,
                         "Re(p) [-] (decay rate / omega_theta)", VF, wF,
                         divergence_speed(section), note)
