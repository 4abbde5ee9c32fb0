"""Fluid effects (leakage, relief valve, asymmetric loss, cavitation: on the chamber equations).

Part of the catalogue of :mod:`liquidamp.device.effects` (the public face: the
table, the composition order, :func:`~liquidamp.device.effects.with_effects`);
the :class:`~liquidamp.device.effects_base.Effect` base is in
:mod:`liquidamp.device.effects_base`.  References as in :mod:`liquidamp.device.effects`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.effects_base import (
    Effect,
    _check_harmonic,
)
from liquidamp.device.kernels import (
    cavity_width,
)
from liquidamp.errors import (
    ParameterError,
    check_finite,
    check_nonnegative,
    check_positive,
)


@dataclass(frozen=True)
class Leakage(Effect):
    """Laminar bypass past the piston: mass flow m_L = rho_l k (p1 - p2) from chamber 1 to 2.

    Added to the chamber equations as a second path in parallel with the
    channel: with density states (eqs. 10-11) dp_i/dt -/+= B_i/V_i m_L/rho_i
    and drho_i/dt -/+= m_L/V_i; with explicit constant-bulk densities
    (eqs. 13, 14, 17) dp_i/dt -/+= B0i/V_i m_L/r_i(p_i).  Either way the total
    mass is conserved exactly.  Needs chamber pressure states.  At small
    strokes it trades against c1 (both are laminar conductances); only the
    channel's inertance and quadratic loss, which the bypass skips, tell
    them apart.

    Parameters
    ----------
    coefficient_m3_per_s_Pa : float
        Volumetric leakage conductance k >= 0 [m^3/(s Pa)].
    """

    coefficient_m3_per_s_Pa: float = 0.0
    name: ClassVar[str] = "leakage"
    units: ClassVar[dict] = {"coefficient_m3_per_s_Pa": "m^3/(s Pa)"}
    fit_keys: ClassVar[tuple] = ("coefficient_m3_per_s_Pa",)
    bounds: ClassVar[dict] = {"coefficient_m3_per_s_Pa": (1e-16, 1e-7)}
    needs_pressures: ClassVar[bool] = True
    order: ClassVar[int] = 5
    description: ClassVar[str] = "laminar bypass past the piston"
    slot: ClassVar[int] = K.S_LEAK
    kind: ClassVar[str] = "fluid"

    def __post_init__(self):
        check_nonnegative("leakage coefficient_m3_per_s_Pa", self.coefficient_m3_per_s_Pa,
                          "m^3/(s Pa)")

    def pack(self, ep):
        ep[K.E_LEAK] = self.coefficient_m3_per_s_Pa


#: Stateless bases on which the flow effects act as a force law on the dashpot.
_DAMPERS = ("dashpot", "dashpot_inerter", "viscous")


def _damper(params, model) -> tuple[float, float]:
    """(c [N s/m], piston area [m^2]) of a stateless dashpot-type base (viscous: area 1)."""
    if model.base == "viscous":
        return float(params.c), 1.0
    return float(params.c_L), float(params.A_p)


def saturation_damping(c: float, c_open: float, force_r: float,
                       velocity_amplitude: float) -> float:
    """Equivalent damping of a relief-valve saturated dashpot at v = V cos(w t) [N s/m].

    The static law F(v) = sign(v) min(c |v|, F_r + c_o (|v| - F_r / c)) is
    c_o v plus (c - c_o) times a unit saturation at F_r / c, whose describing
    function is exact (Gelb and Vander Velde, 1968): with rho = F_r / (c V),

    c_eq = c_o + (c - c_o) (2 / pi) (arcsin(rho) + rho sqrt(1 - rho^2))

    for c V > F_r, and c otherwise.  (For a small second harmonic on top of
    a large motion the incremental damping is the time average of the slope,
    c_o + (c - c_o) (2 / pi) arcsin(rho), without the second term.)

    Parameters
    ----------
    c : float
        Damping below cracking > 0 [N s/m].
    c_open : float
        Slope above cracking, 0 <= c_open <= c [N s/m].
    force_r : float
        Cracking force F_r >= 0 [N].
    velocity_amplitude : float
        V > 0 [m/s].

    Returns
    -------
    float
        c_eq [N s/m]: the first harmonic of F is c_eq V cos(w t).

    Examples
    --------
    >>> saturation_damping(1e5, 1e4, 500.0, 0.004)     # below cracking: c
    100000.0
    >>> round(saturation_damping(1e5, 0.0, 0.0, 0.01), 12)   # Coulomb-like limit 0
    0.0
    """
    for name, v in (("c", c), ("c_open", c_open), ("force_r", force_r),
                    ("velocity_amplitude", velocity_amplitude)):
        check_nonnegative(f"saturation_damping {name}", v, "SI")
    if not c > 0 or not velocity_amplitude > 0 or c_open > c:
        raise ParameterError(f"saturation_damping needs c > 0, V > 0 and c_open <= c, got "
                             f"c = {c:g}, V = {velocity_amplitude:g}, c_open = {c_open:g}")
    rho = force_r / (c * velocity_amplitude)
    if rho >= 1.0:
        return float(c)
    return float(c_open + (c - c_open) * 2.0 / math.pi
                 * (math.asin(rho) + rho * math.sqrt(1.0 - rho * rho)))



def valve_damping(params, model, amplitude: float, omega: float, halves) -> float:
    """Equivalent damping a valve path adds to a dashpot-type model [N s/m].

    Each half cycle contributes half the first harmonic: in compression the dashpot c, in
    rebound r c (``asymmetric_loss``'s rebound ratio r, 1 without it), each saturated by its
    direction's valve (:func:`saturation_damping`: cracking force p_d A, conductance
    G / A^2 in parallel).  ``asymmetric_loss``'s own describing function holds the
    unsaturated average c (1 + r) / 2; this is the saturation on top.

    Parameters
    ----------
    params : ViscousParams or DeviceParams
        The dashpot-type model's parameters.
    model : DeviceModel
        A model whose base is a dashpot (``_DAMPERS``).
    amplitude, omega : float
        Stroke amplitude [m] and angular frequency [rad/s].
    halves : ((float, float), (float, float))
        (cracking pressure [Pa], conductance [m^3/(s Pa)]) in compression, then rebound.

    Returns
    -------
    float
        The added equivalent damping [N s/m] (0 where the dashpot has none).
    """
    c, area = _damper(params, model)
    if c == 0.0:
        return 0.0
    asym = model.effect("asymmetric_loss")
    r = 1.0 if asym is None else asym.rebound_ratio
    out = 0.0
    for ci, (p_d, G) in zip((c, c * r), halves, strict=True):
        out += saturation_damping(ci, 1.0 / (1.0 / ci + G / area**2), p_d * area,
                                  omega * amplitude) - ci
    return 0.5 * out


@dataclass(frozen=True)
class ReliefValve(Effect):
    """Relief (blow-off) valve: a pressure-limited second flow path beside the channel.

    No flow below the cracking pressure p_r; above it the valve passes
    q_r = sign(dp) G (|dp| - p_r) [m^3/s] in parallel with the channel
    (:func:`~liquidamp.device.kernels.relief_flow`, C1 over a pressure width
    0.01 p_r + 1 Pa so that stiff steppers keep their order).  On the models
    with chamber pressures the mass flow rho_l q_r joins the chamber balances
    like leakage's (mass conserved exactly); on the differential models
    (eqs. 15, 18) d(dp)/dt loses B q_r, on ``maxwell`` dF/dt loses
    k_D q_r(F / A_p) / A_p.  On the stateless dashpot-type bases it is the
    exact static force saturation (no regularisation: no state)

    F(v) = sign(v) min(c |v|, F_r + c_o (|v| - F_r / c)),

    F_r = p_r A_p, c_o = 1 / (1 / c + G / A_p^2), c = c_L (``dashpot``; the
    dashpot part of ``dashpot_inerter``): the channel's laminar loss with
    the valve path in parallel above cracking.  The ``viscous`` base F = c v
    is read as a dashpot of unit piston area: cracking force F_r [N] =
    cracking_pressure_Pa x 1 m^2 and c_o = 1 / (1 / c + G x 1 m^-4), i.e. give
    the relief as a force with :meth:`from_force`.  Its describing function
    there is exact (:func:`saturation_damping`).  Closed at rest, so the
    small-signal model at rest holds it (it has no effect there).

    Parameters
    ----------
    cracking_pressure_Pa : float
        p_r >= 0 [Pa] (viscous base: the cracking force in N).
    conductance_m3_per_s_Pa : float
        G >= 0 [m^3/(s Pa)] (viscous base: m/(N s)); 0 keeps the valve shut.

    References
    ----------
    .. [1] H. E. Merritt, Hydraulic Control Systems, Wiley, 1967, Ch. 5
       (pressure-relief valves).
    .. [2] A. Gelb, W. E. Vander Velde, Multiple-Input Describing Functions
       and Nonlinear System Design, McGraw-Hill, 1968 (saturation).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> from liquidamp.device.effects import with_effects
    >>> m = with_effects(get_model("dashpot"), ReliefValve(1e6, 1e-9))
    >>> F_r = 1e6 * p.A_p; v = 2 * F_r / p.c_L      # twice the cracking speed
    >>> c_o = 1 / (1 / p.c_L + 1e-9 / p.A_p**2)
    >>> bool(np.isclose(m.force(0.0, np.zeros(0), (0.0, v, 0.0), p), F_r + c_o * v / 2))
    True
    """

    cracking_pressure_Pa: float = 1.0e6
    conductance_m3_per_s_Pa: float = 0.0
    name: ClassVar[str] = "relief_valve"
    units: ClassVar[dict] = {"cracking_pressure_Pa": "Pa",
                             "conductance_m3_per_s_Pa": "m^3/(s Pa)"}
    fit_keys: ClassVar[tuple] = ("conductance_m3_per_s_Pa", "cracking_pressure_Pa")
    bounds: ClassVar[dict] = {"cracking_pressure_Pa": (1e2, 1e9),
                              "conductance_m3_per_s_Pa": (1e-15, 1e-1)}
    order: ClassVar[int] = 7
    description: ClassVar[str] = "pressure-limited bypass (blow-off valve)"
    slot: ClassVar[int] = K.S_RELIEF
    kind: ClassVar[str] = "fluid"
    screened: ClassVar[bool] = False  # a candidate on request (see the module notes)

    def __post_init__(self):
        check_nonnegative("relief_valve cracking_pressure_Pa", self.cracking_pressure_Pa, "Pa")
        check_nonnegative("relief_valve conductance_m3_per_s_Pa",
                          self.conductance_m3_per_s_Pa, "m^3/(s Pa)")

    @classmethod
    def from_force(cls, cracking_force_N: float, damping_N_s_per_m: float,
                   open_damping_N_s_per_m: float, area_m2: float = 1.0) -> ReliefValve:
        """The valve that saturates a dashpot c at F_r with slope c_o above it.

        p_r = F_r / A, G = A^2 (1 / c_o - 1 / c); A = 1 m^2 for the viscous
        base, A_p for ``dashpot``.

        Examples
        --------
        >>> r = ReliefValve.from_force(5000.0, 1e5, 2e4)
        >>> r.cracking_pressure_Pa, round(r.conductance_m3_per_s_Pa, 12)
        (5000.0, 4e-05)
        """
        c = check_positive("damping_N_s_per_m", damping_N_s_per_m, "N s/m")
        co = check_positive("open_damping_N_s_per_m", open_damping_N_s_per_m, "N s/m")
        A = check_positive("area_m2", area_m2, "m^2")
        if co > c:
            raise ParameterError(f"open_damping_N_s_per_m must be <= damping_N_s_per_m "
                                 f"({c:g} N s/m), got {co:g}")
        return cls(float(cracking_force_N) / A, A * A * (1.0 / co - 1.0 / c))

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """Cracking at 70 % of the peak pressure difference, a path of 0.3 x the channel's
        conductance at the record's flow (F_a / A_p for the peak; the viscous base: A = 1).

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> r = ReliefValve.probe(1000.0, 0.003, 6 * math.pi, preset("reference"))
        >>> round(r.cracking_pressure_Pa * preset("reference").A_p, 6)
        700.0
        """
        if hasattr(params, "A_p"):
            A = params.A_p
            Q = A * omega * amplitude
            c = params.c1 + 8.0 / (3.0 * math.pi) * params.c2 * Q
        else:
            A, c = 1.0, float(params.c)
        return cls(0.7 * force_amplitude_N / A, 0.3 / max(c, 1e-300))

    def check(self, model):
        if model.base in ("spring", "inerter"):
            raise ParameterError(
                f"effect {self.name!r} needs a flow path: model {model.name!r} has none "
                "(use a model with chamber pressures, a differential or Maxwell model, "
                "'dashpot', 'dashpot_inerter' or 'viscous')")

    describing_reason: ClassVar[str | None] = (
        "on a model with chamber states the valve changes the fluid equations; only on "
        "'dashpot', 'dashpot_inerter' and 'viscous' is it an exact force law")

    def pack(self, ep):
        ep[K.E_PR] = ep[K.E_PR2] = self.cracking_pressure_Pa
        ep[K.E_GR] = ep[K.E_GR2] = self.conductance_m3_per_s_Pa

    def describing_function(self, amplitude, omega, params, model=None):
        """Exact on the dashpot-type bases: (0, c_eq - c, 0) (:func:`saturation_damping`).

        Examples
        --------
        >>> from liquidamp.device.models import VISCOUS, ViscousParams
        >>> from liquidamp.device.effects import with_effects
        >>> m = with_effects(VISCOUS, ReliefValve.from_force(500.0, 1e5, 2e4))
        >>> k, dc, b = m.effects[0].describing_function(0.002, 5.0, ViscousParams(1e5), m)
        >>> round(1e5 + dc, 3) == round(saturation_damping(1e5, 2e4, 500.0, 0.01), 3)
        True
        """
        Y, w = _check_harmonic(amplitude, omega)
        if model is None or model.base not in _DAMPERS:
            return super().describing_function(amplitude, omega, params, model)
        valve = (self.cracking_pressure_Pa, self.conductance_m3_per_s_Pa)
        return 0.0, valve_damping(params, model, Y, w, (valve, valve)), 0.0


@dataclass(frozen=True)
class AsymmetricLoss(Effect):
    """Direction-dependent losses: rebound unlike compression.

    The channel's loss coefficients are multiplied by the rebound ratio r
    while the flow runs from chamber 2 to chamber 1 (rebound; compression,
    y increasing, drives it from 1 to 2): c1, c2 (volumetric models), g1, g2
    (mass-flow models), T_D = c1 / B (``maxwell``), c_L (``dashpot``,
    ``dashpot_inerter``) and the viscous c, where the direction is the
    channel flow's sign (a state, or the pressure difference it follows;
    :func:`~liquidamp.device.kernels.flow_direction`) or the piston
    velocity's on the stateless bases.  The force stays continuous (every
    loss vanishes at zero flow); the ratio is piecewise constant, so the
    analytic Jacobian holds off zero flow.  A relief valve's path is not
    scaled.  On the stateless bases F = c v (compression), r c v (rebound):
    the first harmonic's damping is the average c (1 + r) / 2 and the
    energy of the rebound half cycle is r times the compression half's.

    Parameters
    ----------
    rebound_ratio : float
        r > 0 [-]: rebound loss / compression loss (1: symmetric).

    References
    ----------
    .. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007,
       Ch. 1 and 5 (bump and rebound damping).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> from liquidamp.device.effects import with_effects
    >>> m = with_effects(get_model("dashpot"), AsymmetricLoss(2.5))
    >>> u = (np.zeros(2), np.array([0.01, -0.01]), np.zeros(2))
    >>> [round(float(f / (0.01 * p.c_L)), 12) for f in m.force(0.0, np.zeros((0, 2)), u, p)]
    [1.0, -2.5]
    """

    rebound_ratio: float = 1.0
    bare: ClassVar[dict] = {"rebound_ratio": 1.0}
    name: ClassVar[str] = "asymmetric_loss"
    units: ClassVar[dict] = {"rebound_ratio": "-"}
    fit_keys: ClassVar[tuple] = ("rebound_ratio",)
    bounds: ClassVar[dict] = {"rebound_ratio": (0.05, 20.0)}
    order: ClassVar[int] = 3
    description: ClassVar[str] = "rebound losses r times the compression losses"
    slot: ClassVar[int] = K.S_ASYM
    kind: ClassVar[str] = "fluid"
    screened: ClassVar[bool] = False  # a candidate on request (see the module notes)

    def __post_init__(self):
        r = check_finite("asymmetric_loss rebound_ratio", self.rebound_ratio, "-")
        if not r > 0:
            raise ParameterError(f"asymmetric_loss rebound_ratio must be > 0 [-], got {r:g}")

    def check(self, model):
        if model.base in ("spring", "inerter"):
            raise ParameterError(
                f"effect {self.name!r} needs a loss: model {model.name!r} has none")

    def check_small_signal(self, params) -> None:
        """The slope of the loss jumps at zero flow unless the ratio is 1."""
        if self.rebound_ratio != 1.0:
            raise ParameterError(
                f"effect {self.name!r} has no small-signal model at rest: the loss slope "
                f"jumps by the rebound ratio {self.rebound_ratio:g} at zero flow; give an "
                "amplitude and a frequency for an equivalent linearization, or use the time "
                "domain")

    describing_reason: ClassVar[str | None] = (
        "on a model with chamber states it changes the fluid equations; only on 'dashpot', "
        "'dashpot_inerter' and 'viscous' is it an exact force law")

    def pack(self, ep):
        ep[K.E_RR] = self.rebound_ratio

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """Rebound losses 20 % above compression's."""
        return cls(1.2)

    def describing_function(self, amplitude, omega, params, model=None):
        """Exact on the dashpot-type bases: (0, c (r - 1) / 2, 0) (the average damping).

        Examples
        --------
        >>> from liquidamp.device.models import VISCOUS, ViscousParams
        >>> from liquidamp.device.effects import with_effects
        >>> m = with_effects(VISCOUS, AsymmetricLoss(3.0))
        >>> m.effects[0].describing_function(1e-3, 10.0, ViscousParams(100.0), m)
        (0.0, 100.0, 0.0)
        """
        _check_harmonic(amplitude, omega)
        if model is None or model.base not in _DAMPERS:
            return super().describing_function(amplitude, omega, params, model)
        c = _damper(params, model)[0]
        return 0.0, 0.5 * c * (self.rebound_ratio - 1.0), 0.0


@dataclass(frozen=True)
class Cavitation(Effect):
    """Vapour cavities: a chamber's pressure cannot fall below p_v.

    One cavity-volume state per chamber (``Vc1``, ``Vc2`` [m^3], starting at
    0).  When a chamber's pressure reaches p_v while it still expands, the
    pressure is held at p_v and the cavity opens and takes the volume
    change; the pressure rises again only after the cavity has refilled
    (:func:`cavity_rates`: a regularised switch over a pressure width of
    0.05 p_v + 500 Pa, :func:`cavity_width`, so that the equations stay
    integrable).  Mass is untouched (vapour mass neglected), so a
    mass-conserving model stays so, and the liquid fills the chamber less
    its cavity at its own pressure curve, rho_i V_i = r_i(p_i) (V_i - Vc_i),
    exactly (the switch splits the compression of the liquid's volume), so
    the periodic orbits keep the sealed device's invariants
    (:func:`liquidamp.coupled.invariants.invariants`).  Needs chamber pressure
    states.  In this
    model family a little more entrained air (a softer low-pressure
    chamber) can mimic a cavity closely: report ties.

    Parameters
    ----------
    vapour_pressure_Pa : float
        p_v > 0 [Pa] (water at 20 C: 2339 Pa; dissolved-air release makes
        the effective value higher).
    """

    vapour_pressure_Pa: float = 2339.0
    name: ClassVar[str] = "cavitation"
    units: ClassVar[dict] = {"vapour_pressure_Pa": "Pa"}
    fit_keys: ClassVar[tuple] = ("vapour_pressure_Pa",)
    bounds: ClassVar[dict] = {"vapour_pressure_Pa": (1.0, 5e5)}
    needs_pressures: ClassVar[bool] = True
    order: ClassVar[int] = 10
    description: ClassVar[str] = "pressure held at p_v while a vapour cavity is open"
    state_names: ClassVar[tuple] = ("Vc1", "Vc2")
    state_units: ClassVar[tuple] = ("m^3", "m^3")
    slot: ClassVar[int] = K.S_ICAV
    kind: ClassVar[str] = "fluid"

    def __post_init__(self):
        v = check_finite("cavitation vapour_pressure_Pa", self.vapour_pressure_Pa, "Pa")
        if not v > 0:
            raise ParameterError(f"cavitation vapour_pressure_Pa must be > 0 [Pa], got {v:g}")

    describing_reason: ClassVar[str | None] = (
        "cavities open on part of the cycle and change the chamber stiffness")

    def pack(self, ep):
        ep[K.E_PV] = self.vapour_pressure_Pa

    def check_small_signal(self, params) -> None:
        """At rest the cavities are closed (p0 above p_v plus the switch width): no effect."""
        if params.p0 <= self.vapour_pressure_Pa + cavity_width(self.vapour_pressure_Pa):
            raise ParameterError(
                f"effect 'cavitation' has no small-signal model at rest: the filling pressure "
                f"p0 = {params.p0:g} Pa is within the cavity switch "
                f"(p_v = {self.vapour_pressure_Pa:g} Pa + "
                f"{cavity_width(self.vapour_pressure_Pa):g} Pa)")

    def state_scales(self, params):
        return np.full(2, params.A_p * 1e-4)
