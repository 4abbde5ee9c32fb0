"""Heat (issue #20 item 5): the fluid warms by its own dissipation and its losses follow.

Part of the catalogue of :mod:`liquidamp.device.effects` (the public face); the compiled laws
are in :mod:`liquidamp.device.kernels_thermal` (:func:`~liquidamp.device.kernels.viscosity_ratio`,
:func:`~liquidamp.device.kernels.thermal_params`) and the dissipated power in
:func:`~liquidamp.device.kernels.dissipated_power`.

References
----------
.. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 7 (damper
   temperature, lumped heat balance, fade of about 1-2 %/K).
.. [2] C. J. Seeton, "Viscosity-temperature correlation for liquids", Tribology Letters
   22(1), 2006.
.. [3] ASTM D341-20, Viscosity-Temperature Equations and Charts for Liquid Petroleum
   Products (Walther's equation).
.. [4] H. Blasius, "Das Aehnlichkeitsgesetz bei Reibungsvorgaengen in Fluessigkeiten",
   Forschungsheft 131, VDI, 1913 (friction factor ~ Re^-1/4: the quadratic loss's weak
   viscosity dependence, gamma2 = 0.25).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.effects_base import Effect
from liquidamp.errors import ParameterError, check_finite, check_nonnegative, check_positive

__all__ = ["SelfHeating", "LAWS", "WATER_VOGEL", "WALTHER_VG32", "walther_constants",
           "ZERO_CELSIUS"]

#: 0 degC in kelvin.
ZERO_CELSIUS = 273.15
#: Viscosity laws (name -> compiled id, :mod:`liquidamp.device.kernels_thermal`).
LAWS = {"exponential": K.LAW_EXPONENTIAL, "water": K.LAW_WATER, "walther": K.LAW_WALTHER}
#: Vogel's water fit mu = 2.414e-5 Pa s 10^(247.8 K / (T - 140 K)): (B ln 10 [K], C [K]).
WATER_VOGEL = (247.8 * math.log(10.0), 140.0)


def walther_constants(nu1_mm2_per_s: float, T1_K: float, nu2_mm2_per_s: float, T2_K: float
                      ) -> tuple[float, float]:
    """Walther's (ASTM D341) A and B through two kinematic viscosities.

    log10 log10(nu + 0.7) = A - B log10 T, nu [mm^2/s], T [K].

    Examples
    --------
    >>> A, B = walther_constants(32.0, 313.15, 5.4, 373.15)    # ISO VG 32 mineral oil
    >>> round(A, 4), round(B, 4)
    (9.5308, 3.7466)
    """
    pts = []
    for name, nu, T in (("nu1", nu1_mm2_per_s, T1_K), ("nu2", nu2_mm2_per_s, T2_K)):
        check_positive(f"walther {name}", nu, "mm^2/s")
        check_positive(f"walther temperature of {name}", T, "K")
        if nu <= 0.3:
            raise ParameterError(f"walther {name} must be > 0.3 mm^2/s (the law's range), "
                                 f"got {nu:g}")
        pts.append((math.log10(math.log10(nu + 0.7)), math.log10(T)))
    if pts[0][1] == pts[1][1]:
        raise ParameterError("walther: the two temperatures must differ")
    B = (pts[0][0] - pts[1][0]) / (pts[1][1] - pts[0][1])
    return pts[0][0] + B * pts[0][1], B


#: Walther's constants of an ISO VG 32 mineral oil (32 mm^2/s at 40 C, 5.4 at 100 C).
WALTHER_VG32 = walther_constants(32.0, 313.15, 5.4, 373.15)


@dataclass(frozen=True)
class SelfHeating(Effect):
    """Self-heating: a lumped fluid temperature T warmed by what the flow paths dissipate.

    C_th dT/dt = P(t) - h_A (T - T_amb),  T(0) = T_0,

    P the power the channel's linear and quadratic losses dissipate (loss pressure drop times
    flow), with the leakage's and the valves' beside it
    (:func:`~liquidamp.device.kernels.dissipated_power`).  The viscosity follows T, and with
    it the losses: c1 (g1, c_L, the viscous c, T_D) is scaled by r = mu(T) / mu(T_ref), c2 by
    r^gamma2 (:func:`~liquidamp.device.kernels.thermal_params`); the parameter set's c1, c2
    are their values at T_ref; a ``gas_charge`` composed beside it is at the fluid's
    temperature (ideal gas at its reference volume: absolute charge x T / T_ref).  Laws
    (``law``): ``"exponential"`` exp(-beta (T - T_ref));
    ``"water"`` Vogel's fit of water (the paper's device); ``"walther"`` ASTM D341 for a
    mineral oil (constants ``law_a``, ``law_b``: :func:`walther_constants`).

    Closed forms: under a constant power P from T_0 = T_amb,
    T(t) = T_amb + P / h_A (1 - exp(-t h_A / C_th)); beta = 0 (exponential law) gives the
    device without the effect exactly; the heat stored plus the heat lost equals the energy
    dissipated.  The states' rate does not feed the force directly, so a periodic record of a
    warming device is not periodic: it is simulated by a march over the whole record
    (:func:`~liquidamp.analysis.measured.record_model.simulate_record`).  Without a measured
    temperature only the time constant C_th / h_A and beta / h_A can be told from a force
    record (T - T_amb, 1/beta, C_th and h_A scale together).

    Parameters
    ----------
    heat_capacity_J_per_K : float
        C_th > 0 [J/K] (inf: the temperature stays at T_0).
    conductance_W_per_K : float
        h_A >= 0 [W/K] to ambient.
    beta_per_K : float
        beta >= 0 [1/K] of the exponential law (water near 20 C: 0.024).
    c2_exponent : float
        gamma2 in [0, 1] [-]: the quadratic loss's power of the viscosity ratio (0.25:
        Blasius' friction factor).
    ambient_temperature_K, reference_temperature_K, initial_temperature_K : float
        T_amb, T_ref (where c1, c2 hold) and T_0 [K] (> 0).
    law_a, law_b : float
        The law's constants (water: Vogel's B ln 10 [K] and C [K]; walther: A and B [-]);
        unused by the exponential law.
    law : {"exponential", "water", "walther"}
        Composition field: the viscosity law.
    start : {"given", "record"}
        Composition field: where a record's start temperature comes from: T_0
        (``initial_temperature_K``), or each record's own, estimated from the force of its
        first cycles by :func:`~liquidamp.analysis.measured.record_model.simulate_record`
        (a record that starts warm, its temperature not measured).
    temperature : {"state", "measured"}
        Composition field: what the law reads: the thermal state, or the record's measured
        ``temperature`` channel (:attr:`input_channels`; the state then still integrates the
        heat balance, the model's own prediction beside the measurement).

    Examples
    --------
    >>> from liquidamp.device.models import VISCOUS, ViscousParams
    >>> from liquidamp.device.effects import with_effects
    >>> e = SelfHeating(heat_capacity_J_per_K=2.0, conductance_W_per_K=0.5, beta_per_K=0.03)
    >>> m = with_effects(VISCOUS, e)
    >>> m.state_names, m.state_units
    (('T_fluid',), ('K',))
    >>> x = np.array([e.reference_temperature_K + 10.0])
    >>> round(float(m.force(0.0, x, (0.0, 0.1, 0.0), ViscousParams(1000.0))), 6)
    74.081822
    >>> round(float(m.rhs(0.0, x, (0.0, 0.1, 0.0), ViscousParams(1000.0))[0]), 6)  # (P - hA dT)/C
    1.204091
    """

    heat_capacity_J_per_K: float = 10.0
    conductance_W_per_K: float = 1.0
    beta_per_K: float = 0.025
    c2_exponent: float = 0.25
    ambient_temperature_K: float = 293.15
    reference_temperature_K: float = 293.15
    initial_temperature_K: float = 293.15
    law_a: float = 0.0
    law_b: float = 0.0
    law: str = dataclasses.field(default="exponential",
                                 metadata={"composition": tuple(LAWS)})
    start: str = dataclasses.field(default="given",
                                   metadata={"composition": ("given", "record")})
    temperature: str = dataclasses.field(default="state",
                                         metadata={"composition": ("state", "measured")})
    name: ClassVar[str] = "self_heating"
    units: ClassVar[dict] = {"heat_capacity_J_per_K": "J/K", "conductance_W_per_K": "W/K",
                             "beta_per_K": "1/K", "c2_exponent": "-",
                             "ambient_temperature_K": "K", "reference_temperature_K": "K",
                             "initial_temperature_K": "K", "law_a": "-", "law_b": "-"}
    #: Fitted by default: the time constant's two halves (beta fixed: without a measured
    #: temperature only C_th / h_A and beta / h_A show); with a temperature channel the
    #: diagnosis frees beta instead (:attr:`fit_keys_measured`).
    fit_keys: ClassVar[tuple] = ("heat_capacity_J_per_K", "conductance_W_per_K")
    #: Fitted where a measured temperature drives the law (the thermal state is not used).
    fit_keys_measured: ClassVar[tuple] = ("beta_per_K",)
    bounds: ClassVar[dict] = {"heat_capacity_J_per_K": (1e-3, 1e7),
                              "conductance_W_per_K": (1e-5, 1e5),
                              "beta_per_K": (0.0, 0.2), "c2_exponent": (0.0, 1.0),
                              "ambient_temperature_K": (200.0, 500.0),
                              "reference_temperature_K": (200.0, 500.0),
                              "initial_temperature_K": (200.0, 500.0),
                              "law_a": (-1e4, 1e4), "law_b": (-1e4, 1e4)}
    order: ClassVar[int] = 60  # outermost: its state is the last one
    description: ClassVar[str] = ("self-heating: fluid temperature from the dissipated power; "
                                  "losses follow the viscosity")
    state_names: ClassVar[tuple] = ("T_fluid",)
    state_units: ClassVar[tuple] = ("K",)
    slot: ClassVar[int] = K.S_TH
    kind: ClassVar[str] = "fluid"
    #: A record of a warming device drifts: its simulation marches over the whole record
    #: from the state at its first sample, not the periodic orbit of one cycle.
    stationary: ClassVar[bool] = False
    #: What in a record proposes the effect to a diagnosis: a drift of its force from cycle
    #: to cycle, or a measured temperature.
    proposed_by: ClassVar[tuple] = ("drift", "temperature")
    small_signal_reason: ClassVar[str | None] = (
        "the temperature state's rate is quadratic in the flow (zero slope at rest)")
    describing_reason: ClassVar[str | None] = (
        "the temperature drifts with the dissipated power, so the response has no steady "
        "first harmonic; give the effect's parameters at a fixed temperature instead "
        "(heat_capacity_J_per_K = inf)")

    def __post_init__(self):
        c = self.heat_capacity_J_per_K
        if isinstance(c, bool) or not isinstance(c, (int, float)) or not c > 0:
            raise ParameterError(f"self_heating heat_capacity_J_per_K must be > 0 [J/K] (inf: "
                                 f"the temperature held), got {c!r}")
        check_nonnegative("self_heating conductance_W_per_K", self.conductance_W_per_K, "W/K")
        b = check_nonnegative("self_heating beta_per_K", self.beta_per_K, "1/K")
        if b > 1.0:
            raise ParameterError(f"self_heating beta_per_K must be in [0, 1] [1/K] (water 0.024"
                                 f", mineral oils about 0.03), got {b:g}")
        g = check_finite("self_heating c2_exponent", self.c2_exponent, "-")
        if not 0.0 <= g <= 1.0:
            raise ParameterError(f"self_heating c2_exponent must be in [0, 1] [-], got {g:g}")
        for key in ("ambient_temperature_K", "reference_temperature_K",
                    "initial_temperature_K"):
            check_positive(f"self_heating {key}", getattr(self, key), "K")
        check_finite("self_heating law_a", self.law_a, "-")
        check_finite("self_heating law_b", self.law_b, "-")
        self._check_composition()
        if self.law == "water" and (self.law_a, self.law_b) == (0.0, 0.0):
            object.__setattr__(self, "law_a", WATER_VOGEL[0])
            object.__setattr__(self, "law_b", WATER_VOGEL[1])
        if self.law == "walther" and (self.law_a, self.law_b) == (0.0, 0.0):
            object.__setattr__(self, "law_a", WALTHER_VG32[0])
            object.__setattr__(self, "law_b", WALTHER_VG32[1])
        if self.law == "water" and min(self.reference_temperature_K,
                                       self.initial_temperature_K) <= self.law_b + 50.0:
            raise ParameterError(f"self_heating: Vogel's water law holds above "
                                 f"{self.law_b + 50.0:g} K; got a temperature below it")

    @property
    def time_constant_s(self) -> float:
        """C_th / h_A [s] (inf without a conductance)."""
        h = self.conductance_W_per_K
        return math.inf if h == 0.0 else self.heat_capacity_J_per_K / h

    def viscosity_ratio(self, T_K):
        """mu(T) / mu(T_ref) [-] at fluid temperature(s) ``T_K`` [K].

        Examples
        --------
        >>> round(SelfHeating(law="water").viscosity_ratio(313.15), 3)    # 40 C vs 20 C
        0.65
        """
        law = LAWS[self.law]
        f = np.vectorize(lambda T: K.viscosity_ratio(float(T), self.reference_temperature_K,
                                                     law, self.beta_per_K, self.law_a,
                                                     self.law_b))
        out = f(np.asarray(T_K, float))
        return float(out) if np.ndim(out) == 0 else out

    def held(self, T_K: float | None = None) -> SelfHeating:
        """The effect with its temperature held at ``T_K`` (default T_0): infinite heat
        capacity, the state stays where it starts."""
        T = self.initial_temperature_K if T_K is None else float(T_K)
        return dataclasses.replace(self, heat_capacity_J_per_K=math.inf,
                                   initial_temperature_K=T)

    @property
    def input_channels(self) -> tuple:
        """``("temperature",)`` where the measured temperature drives the law, else ()."""
        return ("temperature",) if self.temperature == "measured" else ()

    def pack(self, ep):
        ep[K.E_TC], ep[K.E_THA] = self.heat_capacity_J_per_K, self.conductance_W_per_K
        ep[K.E_TAMB], ep[K.E_TREF] = self.ambient_temperature_K, self.reference_temperature_K
        ep[K.E_TBETA], ep[K.E_TG2] = self.beta_per_K, self.c2_exponent
        ep[K.E_TLAW], ep[K.E_TA], ep[K.E_TB] = LAWS[self.law], self.law_a, self.law_b
        ep[K.E_TSRC] = 1.0 if self.temperature == "measured" else 0.0

    def initial_state(self, params, y0):
        return np.array([self.initial_temperature_K])

    def state_scales(self, params):
        return np.array([max(self.initial_temperature_K, 1.0)])

    def check(self, model):
        if model.base in ("spring", "inerter"):
            raise ParameterError(
                f"effect {self.name!r} needs a flow path that dissipates: model "
                f"{model.name!r} has none")

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """A fluid that warms by 10 K over the record's own dissipation scale: h_A from the
        dissipated power estimate P = F_a Y w / 4 at 10 K rise, a time constant of 10 s,
        beta = 0.025 1/K (water near 20 C: 0.024).

        Examples
        --------
        >>> e = SelfHeating.probe(1000.0, 0.003, 2 * math.pi * 3, None)
        >>> round(e.conductance_W_per_K, 6), round(e.time_constant_s, 6)
        (1.413717, 10.0)
        """
        P = 0.25 * force_amplitude_N * amplitude * omega
        hA = P / 10.0
        return cls(heat_capacity_J_per_K=10.0 * hA, conductance_W_per_K=hA)
