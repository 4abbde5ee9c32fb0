"""What real dampers have (issue #20): a gas charge on the absolute stroke, digressive valves.

Part of the catalogue of :mod:`liquidamp.device.effects` (the public face: the table,
the composition order, :func:`~liquidamp.device.effects.with_effects`); the
:class:`~liquidamp.device.effects_base.Effect` base is in
:mod:`liquidamp.device.effects_base`.  The compiled laws are
:func:`~liquidamp.device.kernels.gas_pressure`, :func:`~liquidamp.device.kernels.gas_force`
and :func:`~liquidamp.device.kernels.valve_flow`.

References
----------
.. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5
   (gas pressure force, digressive valves) and Ch. 8 (valve knees).
.. [2] H. E. Merritt, Hydraulic Control Systems, Wiley, 1967, Ch. 5
   (spring-loaded valves) and Ch. 8 (gas-charged accumulators).
.. [3] A. Gelb, W. E. Vander Velde, Multiple-Input Describing Functions and
   Nonlinear System Design, McGraw-Hill, 1968 (saturation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.effects_base import Effect, _check_harmonic
from liquidamp.device.effects_fluid import _DAMPERS, valve_damping
from liquidamp.device.kernels import gas_force
from liquidamp.errors import ParameterError, check_finite, check_nonnegative, check_positive

#: Allowed polytropic index of the gas charge [-]: isothermal (1) to adiabatic diatomic (1.4)
#: and a little beyond (monatomic gas 5/3).
POLYTROPIC_BOUNDS = (1.0, 5.0 / 3.0)


@dataclass(frozen=True)
class GasCharge(Effect):
    """Gas charge of a single-rod device: preload and gas spring on the absolute stroke.

    The rod (area A_r) entering the body by y_abs displaces A_r y_abs of liquid
    into an accumulator whose gas, charged to p_c above the ambient p_a at volume
    V_g, is compressed polytropically (index n); the ambient pressure acts on the
    rod's outer end.  The rod carries

    F_gas = A_r ((p_c + p_a) (V_g / (V_g - A_r y_abs))^n - p_a)
    (:func:`~liquidamp.device.kernels.gas_force`),

    the preload p_c A_r at y_abs = 0 and the gas spring k_g = n (p_c + p_a) A_r^2 / V_g
    about it; at the stroke ends +/- Y the static force is
    A_r ((p_c + p_a) (V_g / (V_g -/+ A_r Y))^n - p_a).  ``y_abs = y + stroke_offset_m``: the
    force depends on where the rod is, not only on how it moves, so the
    record's mean stroke (which :func:`~liquidamp.analysis.measured.record_model.simulate_record`
    takes off the stroke that drives the chambers) is given back to this effect:
    ``simulate_record`` sets ``stroke_offset_m`` to the record's mean stroke
    (:attr:`Record.offset`), the reading of the record's displacement channel at the
    model's zero; the record's own zero is then the gas reference V_g.

    The charge also raises both chambers' pressure level: the model's pressure
    states are about the filling pressure p0, the chambers sit p_g(y) above them, so
    a vapour cavity (``cavitation``) opens only where p_i + p_g(y) reaches p_v
    (cavitation margins move with the charge).  The chamber bulk moduli stay those
    of the states (a stiffer liquid under the charge is not modelled).

    A zero rod area gives no force at all (the sealed device's force exactly); the
    level is then p_c, so with a zero charge too the device is the sealed one in
    every respect.

    On a measured record the record's zero is the stroke datum:
    :func:`~liquidamp.device.effects.on_absolute_stroke` (called by
    :func:`~liquidamp.analysis.measured.record_model.simulate_record`) places the chambers
    on the absolute stroke (V01, V02 at y_abs = 0) and fills them at the charge's absolute
    pressure p_c + p_a (a gas-charged damper's liquid sits at its gas pressure), so the fitted
    charge sets both the preload and the chambers' level.  From one record the charge, the rod
    area and the gas volume trade off; the gas force and the gas rate at the record's mean
    stroke are what it identifies
    (:func:`~liquidamp.analysis.reports.damper_characteristics.gas_charge_characteristics`).
    On a record at one frequency the gas rate is also one in-phase stiffness with the
    fluid's inertance, k_g - w^2 rho_l S_t A_p^2: only records at two frequencies (or a
    known channel) tell them apart.

    Parameters
    ----------
    rod_area_m2 : float
        A_r >= 0 [m^2] (a 7.6 mm rod: 4.5e-5 m^2).
    charge_pressure_Pa : float
        p_c >= 0 [Pa], gauge: above the ambient (100 psi = 6.895e5 Pa).
    gas_volume_m3 : float
        V_g > 0 [m^3] at y_abs = 0.
    polytropic_index : float
        n in [1, 5/3] [-] (1: isothermal, slow strokes; 1.4: adiabatic nitrogen).
    stroke_offset_m : float
        Absolute stroke at the model's y = 0 [m] (set from a record's mean stroke
        by :func:`~liquidamp.analysis.measured.record_model.simulate_record`; not fitted).
    ambient_pressure_Pa : float
        p_a >= 0 [Pa] on the rod's outer end (101325 Pa; 0: the charge is absolute).

    References
    ----------
    .. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Sec. 5.9
       (gas force p_c A_r, gas spring).

    Examples
    --------
    >>> g = GasCharge(4.5e-5, 6.894757e5, 1e-4, 1.0)
    >>> round(g.force(0.0), 3), round(g.stiffness(0.0) / 1e3, 6)     # N, N/mm
    (31.026, 0.016014)
    >>> round(g.force(0.05) - g.force(-0.05), 3)   # the gas spring over 100 mm of stroke
    1.602
    """

    rod_area_m2: float = 0.0
    charge_pressure_Pa: float = 1.0e6
    gas_volume_m3: float = 1.0e-4
    polytropic_index: float = 1.0
    stroke_offset_m: float = 0.0
    ambient_pressure_Pa: float = 101325.0
    name: ClassVar[str] = "gas_charge"
    units: ClassVar[dict] = {"rod_area_m2": "m^2", "charge_pressure_Pa": "Pa",
                             "gas_volume_m3": "m^3", "polytropic_index": "-",
                             "stroke_offset_m": "m", "ambient_pressure_Pa": "Pa"}
    #: the charge (the lead: it sets the preload and, on a record, the chambers' level),
    #: the rod area (the preload at a given charge) and the gas volume (the gas spring)
    fit_keys: ClassVar[tuple] = ("charge_pressure_Pa", "rod_area_m2", "gas_volume_m3")
    bounds: ClassVar[dict] = {"rod_area_m2": (1e-7, 1e-2), "charge_pressure_Pa": (1e3, 1e8),
                              "gas_volume_m3": (1e-8, 1e-1),
                              "polytropic_index": POLYTROPIC_BOUNDS,
                              "stroke_offset_m": (-1.0, 1.0),
                              "ambient_pressure_Pa": (0.0, 2e5)}
    order: ClassVar[int] = 48
    description: ClassVar[str] = "gas charge: preload p_c A_r and gas spring (absolute stroke)"
    slot: ClassVar[int] = K.S_GAS
    #: The effect's force depends on the absolute stroke: a record's mean stroke is given
    #: to it (``stroke_offset_m``) instead of being lost.
    absolute_stroke: ClassVar[bool] = True

    def __post_init__(self):
        check_nonnegative("gas_charge rod_area_m2", self.rod_area_m2, "m^2")
        check_nonnegative("gas_charge charge_pressure_Pa", self.charge_pressure_Pa, "Pa")
        check_positive("gas_charge gas_volume_m3", self.gas_volume_m3, "m^3")
        n = check_finite("gas_charge polytropic_index", self.polytropic_index, "-")
        lo, hi = POLYTROPIC_BOUNDS
        if not lo <= n <= hi:
            raise ParameterError(f"gas_charge polytropic_index must be in [{lo:g}, {hi:.4g}] "
                                 f"[-] (1: isothermal, 1.4: adiabatic nitrogen), got {n:g}")
        check_finite("gas_charge stroke_offset_m", self.stroke_offset_m, "m")
        check_nonnegative("gas_charge ambient_pressure_Pa", self.ambient_pressure_Pa, "Pa")

    def pack(self, ep):
        ep[K.E_AR], ep[K.E_PCH] = self.rod_area_m2, self.charge_pressure_Pa
        ep[K.E_VG], ep[K.E_NG] = self.gas_volume_m3, self.polytropic_index
        ep[K.E_Y0G], ep[K.E_PAT] = self.stroke_offset_m, self.ambient_pressure_Pa

    @property
    def travel_m(self) -> float:
        """Absolute stroke at which the gas would be compressed to nothing, V_g / A_r [m]."""
        return math.inf if self.rod_area_m2 == 0.0 else self.gas_volume_m3 / self.rod_area_m2

    def force(self, y):
        """Gas force at model stroke ``y`` [m] (absolute: y + stroke_offset_m) [N]."""
        ya = np.asarray(y, float) + self.stroke_offset_m
        args = (self.rod_area_m2, self.charge_pressure_Pa, self.gas_volume_m3,
                self.polytropic_index, self.ambient_pressure_Pa)
        out = np.vectorize(lambda q: gas_force(q, *args))(ya)
        return float(out) if np.ndim(out) == 0 else out

    def stiffness(self, y=0.0):
        """Gas spring dF/dy = n (p_g + p_a) A_r^2 / (V_g - A_r y_abs) at model stroke ``y``
        [N/m]."""
        ya = np.asarray(y, float) + self.stroke_offset_m
        V = self.gas_volume_m3 - self.rod_area_m2 * ya
        A = self.rod_area_m2
        out = self.polytropic_index * (self.force(y) + A * self.ambient_pressure_Pa) * A / V
        return float(out) if np.ndim(out) == 0 else out

    def check(self, model):
        if model.base == "viscous":
            raise ParameterError(
                f"effect {self.name!r} needs a device with a rod: the viscous damper "
                "F = c v has none; use 'dashpot' or a model with chamber pressures")

    def check_with(self, effects):
        pass

    small_signal_reason: ClassVar[str | None] = None
    describing_reason: ClassVar[str | None] = None

    def describing_function(self, amplitude, omega, params, model=None):
        """(k_eq, 0, 0): first harmonic of F_gas(y0 + Y sin t) over Y (Gauss on 256 points).

        The mean force (the preload at the mean stroke) has no first harmonic; a
        stroke-only force dissipates nothing, so c = 0.  Small amplitudes give the
        gas spring :meth:`stiffness`.

        Examples
        --------
        >>> g = GasCharge(5e-4, 1e6, 1e-4, 1.4)
        >>> k, c, b = g.describing_function(1e-5, 10.0, None)
        >>> bool(abs(k / g.stiffness(0.0) - 1) < 1e-6), c, b
        (True, 0.0, 0.0)
        """
        Y, _ = _check_harmonic(amplitude, omega)
        if Y * self.rod_area_m2 >= self.gas_volume_m3 - self.rod_area_m2 * self.stroke_offset_m:
            raise ParameterError(
                f"gas_charge: stroke amplitude {Y:g} m reaches the end of the gas volume "
                f"(V_g / A_r = {self.travel_m:g} m)")
        th = (np.arange(256) + 0.5) * (2.0 * math.pi / 256)
        F = self.force(Y * np.sin(th))
        return float(2.0 / 256 * np.sum(F * np.sin(th)) / Y), 0.0, 0.0

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """A charge whose preload is 5 % of the record's force amplitude, on a rod of 5 % of
        the piston area (1e-4 m^2 on the viscous base), its gas spring 5 % of F_a / Y.

        Examples
        --------
        >>> g = GasCharge.probe(1000.0, 0.003, 6 * math.pi, None)
        >>> round(g.force(0.0), 9), round(g.stiffness(0.0) * 0.003, 6)
        (50.0, 50.0)
        """
        A_r = 0.05 * params.A_p if hasattr(params, "A_p") else 1e-4
        p_c = 0.05 * force_amplitude_N / A_r
        k = 0.05 * force_amplitude_N / amplitude
        return cls(A_r, p_c, (p_c + 101325.0) * A_r * A_r / k, 1.0)


@dataclass(frozen=True)
class DigressiveValve(Effect):
    """Digressive valves, one per direction: each direction has its own knee.

    A spring-loaded valve for compression (flow from chamber 1 to chamber 2,
    pressure difference dp = p1 - p2 > 0) and one for rebound (dp < 0), each in
    parallel with the channel (the bleed): shut below its cracking pressure, then
    a conductance, q_v = sign(dp) G_d R(|dp| - p_d), d the flow's direction
    (:func:`~liquidamp.device.kernels.valve_flow`, R the C1 ramp of
    :func:`~liquidamp.device.kernels.relief_flow`).  It enters every model as
    ``relief_valve`` does (mass conserved on the chamber models), and cannot be
    composed with it.

    In the rigid-fluid limit (``dashpot``: the channel's laminar loss c = c_L on
    the piston area A_p) the force-velocity curve has two slopes per direction,
    with the knee at v_d = p_d A_p / c:

    F(v) = c v for |v| <= v_d, sign(v) (p_d A_p + c_d (|v| - v_d)) above,
    c_d = 1 / (1 / c + G_d / A_p^2);

    the ``viscous`` base is read as a dashpot of unit area (p_d in N, G_d in
    m/(N s)), see :meth:`from_knees`.  Its describing function there is exact
    (half a cycle per valve, :func:`~liquidamp.device.effects_fluid.saturation_damping`).

    Parameters
    ----------
    compression_cracking_Pa : float
        p_c >= 0 [Pa], compression valve's cracking pressure.
    compression_conductance_m3_per_s_Pa : float
        G_c >= 0 [m^3/(s Pa)] (0: the compression valve stays shut).
    rebound_cracking_Pa : float
        p_r >= 0 [Pa], rebound valve's cracking pressure.
    rebound_conductance_m3_per_s_Pa : float
        G_r >= 0 [m^3/(s Pa)] (0: the rebound valve stays shut).

    References
    ----------
    .. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 8.

    Examples
    --------
    >>> d = DigressiveValve.from_knees(2200.0, 0.025, 1100.0, 1200.0, 0.025, 1000.0)
    >>> from liquidamp.device.models import VISCOUS, ViscousParams
    >>> from liquidamp.device.effects import AsymmetricLoss, with_effects
    >>> m = with_effects(VISCOUS, d, AsymmetricLoss(1200.0 / 2200.0))   # rebound bleed 1.2 kN s/m
    >>> u = (np.zeros(2), np.array([0.1, -0.1]), np.zeros(2))
    >>> [round(float(f), 6) for f in m.force(0.0, np.zeros((0, 2)), u, ViscousParams(2200.0))]
    [137.5, -105.0]
    """

    compression_cracking_Pa: float = 1.0e6
    compression_conductance_m3_per_s_Pa: float = 0.0
    rebound_cracking_Pa: float = 1.0e6
    rebound_conductance_m3_per_s_Pa: float = 0.0
    name: ClassVar[str] = "digressive_valve"
    units: ClassVar[dict] = {"compression_cracking_Pa": "Pa",
                             "compression_conductance_m3_per_s_Pa": "m^3/(s Pa)",
                             "rebound_cracking_Pa": "Pa",
                             "rebound_conductance_m3_per_s_Pa": "m^3/(s Pa)"}
    fit_keys: ClassVar[tuple] = ("compression_cracking_Pa", "compression_conductance_m3_per_s_Pa",
                                 "rebound_cracking_Pa", "rebound_conductance_m3_per_s_Pa")
    bounds: ClassVar[dict] = {"compression_cracking_Pa": (1e2, 1e9),
                              "compression_conductance_m3_per_s_Pa": (1e-15, 1e-1),
                              "rebound_cracking_Pa": (1e2, 1e9),
                              "rebound_conductance_m3_per_s_Pa": (1e-15, 1e-1)}
    order: ClassVar[int] = 7  # where relief_valve sits (the same compiled slot)
    description: ClassVar[str] = "spring-loaded valves per direction (two knees)"
    slot: ClassVar[int] = K.S_RELIEF
    kind: ClassVar[str] = "fluid"
    #: A candidate on request, like relief_valve: at a low cracking pressure the valves
    #: are a laminar bypass, and screened by default they take a leakage record's place
    #: (test_diagnosis.py's leakage case); the diagnosis's selection rule decides (issue
    #: #20 item 7).
    screened: ClassVar[bool] = False

    def __post_init__(self):
        for key, unit in (("compression_cracking_Pa", "Pa"),
                          ("compression_conductance_m3_per_s_Pa", "m^3/(s Pa)"),
                          ("rebound_cracking_Pa", "Pa"),
                          ("rebound_conductance_m3_per_s_Pa", "m^3/(s Pa)")):
            check_nonnegative(f"digressive_valve {key}", getattr(self, key), unit)

    @classmethod
    def from_knees(cls, low_damping_N_s_per_m: float, compression_knee_m_per_s: float,
                   compression_high_N_s_per_m: float, rebound_low_N_s_per_m: float,
                   rebound_knee_m_per_s: float, rebound_high_N_s_per_m: float,
                   area_m2: float = 1.0) -> DigressiveValve:
        """The valves that give a dashpot's two-slope curves (viscous base: ``area_m2`` = 1).

        The bleed (the base's c) sets the low-speed slope of compression; a
        rebound low-speed slope ``rebound_low_N_s_per_m`` unlike it needs
        ``asymmetric_loss`` with rebound_ratio = rebound_low / low beside the valves
        (which scales the bleed in rebound).  Each knee
        v_d gives p_d = c v_d / A and each high-speed slope c_d gives
        G_d = A^2 (1 / c_d - 1 / c).

        Examples
        --------
        >>> d = DigressiveValve.from_knees(2200.0, 0.025, 1100.0, 2200.0, 0.05, 1000.0)
        >>> d.compression_cracking_Pa, round(d.rebound_cracking_Pa, 9)
        (55.0, 110.0)
        """
        A = check_positive("area_m2", area_m2, "m^2")
        out = {}
        for side, c, v_d, c_d in (("compression", low_damping_N_s_per_m,
                                   compression_knee_m_per_s, compression_high_N_s_per_m),
                                  ("rebound", rebound_low_N_s_per_m, rebound_knee_m_per_s,
                                   rebound_high_N_s_per_m)):
            c = check_positive(f"{side} low-speed damping", c, "N s/m")
            v_d = check_nonnegative(f"{side} knee velocity", v_d, "m/s")
            c_d = check_positive(f"{side} high-speed damping", c_d, "N s/m")
            if c_d > c:
                raise ParameterError(f"{side} high-speed damping must be <= the low-speed "
                                     f"damping {c:g} N s/m (digressive), got {c_d:g}")
            out[f"{side}_cracking_Pa"] = c * v_d / A
            out[f"{side}_conductance_m3_per_s_Pa"] = A * A * (1.0 / c_d - 1.0 / c)
        return cls(**out)

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """Knees at 60 % (compression) and 70 % (rebound) of the peak pressure difference,
        paths of 0.3 and 0.2 x the channel's conductance (the relief valve's probe rule).

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> d = DigressiveValve.probe(1000.0, 0.003, 6 * math.pi, preset("reference"))
        >>> round(d.compression_cracking_Pa * preset("reference").A_p, 6)
        600.0
        """
        if hasattr(params, "A_p"):
            A = params.A_p
            c = params.c1 + 8.0 / (3.0 * math.pi) * params.c2 * A * omega * amplitude
        else:
            A, c = 1.0, float(params.c)
        g = 1.0 / max(c, 1e-300)
        return cls(0.6 * force_amplitude_N / A, 0.3 * g, 0.7 * force_amplitude_N / A, 0.2 * g)

    def check(self, model):
        if model.base in ("spring", "inerter"):
            raise ParameterError(
                f"effect {self.name!r} needs a flow path: model {model.name!r} has none "
                "(use a model with chamber pressures, a differential or Maxwell model, "
                "'dashpot', 'dashpot_inerter' or 'viscous')")

    def check_with(self, effects):
        if any(e.name == "relief_valve" for e in effects):
            raise ParameterError(
                "effect 'digressive_valve' cannot be composed with 'relief_valve': both are "
                "the valve path beside the channel; give the relief's cracking pressure and "
                "conductance to both directions of the digressive valve")

    describing_reason: ClassVar[str | None] = (
        "on a model with chamber states the valves change the fluid equations; only on "
        "'dashpot', 'dashpot_inerter' and 'viscous' are they an exact force law")

    def pack(self, ep):
        ep[K.E_PR], ep[K.E_GR] = (self.compression_cracking_Pa,
                                  self.compression_conductance_m3_per_s_Pa)
        ep[K.E_PR2], ep[K.E_GR2] = self.rebound_cracking_Pa, self.rebound_conductance_m3_per_s_Pa

    def describing_function(self, amplitude, omega, params, model=None):
        """Exact on the dashpot-type bases: (0, c_eq - c, 0), half a cycle per valve.

        Examples
        --------
        >>> from liquidamp.device.models import VISCOUS, ViscousParams
        >>> from liquidamp.device.effects import with_effects
        >>> from liquidamp.device.effects_fluid import saturation_damping
        >>> d = DigressiveValve.from_knees(1e5, 0.005, 2e4, 1e5, 0.005, 2e4)
        >>> m = with_effects(VISCOUS, d)
        >>> k, dc, b = m.effects[0].describing_function(0.002, 5.0, ViscousParams(1e5), m)
        >>> round(1e5 + dc, 3) == round(saturation_damping(1e5, 2e4, 500.0, 0.01), 3)
        True
        """
        Y, w = _check_harmonic(amplitude, omega)
        if model is None or model.base not in _DAMPERS:
            return super().describing_function(amplitude, omega, params, model)
        halves = ((self.compression_cracking_Pa, self.compression_conductance_m3_per_s_Pa),
                  (self.rebound_cracking_Pa, self.rebound_conductance_m3_per_s_Pa))
        return 0.0, valve_damping(params, model, Y, w, halves), 0.0
