"""Force effects (friction, offset, moving mass, elastomer, end stops: on the load-cell force).

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
    REVERSE_RATIO_BOUNDS,
    Effect,
    _check_harmonic,
    _check_location,
    _check_reverse_ratio,
    _location_field,
)
from liquidamp.device.kernels import (
    lugre_rate,
)
from liquidamp.errors import (
    ParameterError,
    check_finite,
    check_nonnegative,
    check_positive,
)


@dataclass(frozen=True)
class CoulombFriction(Effect):
    """Coulomb seal friction F += F_c sign(v) (the paper's |F_f|, Sec. IV.C).

    At ``location="piston"`` the friction element sits behind the kinematic
    effects, in series with a dead band (``freeplay``) like the fluid: the
    kinematic chain rod -> dead band -> friction element of a friction
    damper with backlash.  The contact is massless: inside the gap no force
    is transmitted and the element stays put; in contact it moves with the
    rod and transmits F_c sign(v), so F = F_c sign(v) C with C the dead
    band's C1 contact factor (:func:`~liquidamp.device.kernels.play_contact`,
    0 in the gap, 1 in contact).  Under y = A sin(w t) with A > g the loop
    is flat while the rod crosses the gap 2g after each reversal and the
    energy dissipated per cycle is 2 F_c (2A - 2g).  Without freeplay the
    piston moves with the rod and both locations agree.  Not behind
    ``series_compliance`` (a stick-slip element: ParameterError).

    A band or seal that grips harder one way slides at F_c forward (v > 0)
    and q F_c in reverse (``reverse_ratio`` q,
    :func:`~liquidamp.device.kernels.friction_level`): the loop's levels
    +F_c / -q F_c, whose mean (1 - q) F_c / 2 acts only while sliding, not
    inside a dead band as a ``force_offset`` would.

    Parameters
    ----------
    force_N : float
        Friction force level F_c >= 0 [N] (paper: 30 N), forward (v > 0).
    reverse_ratio : float
        Reverse-to-forward level ratio q in [0.1, 10] [-] (1: symmetric).
    location : {"rod", "piston"}
        Where the friction sits (a composition choice, not fitted).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device.effects import with_effects
    >>> m = with_effects(get_model("dashpot"), CoulombFriction(30.0))
    >>> from liquidamp.device import preset
    >>> float(m.force(0.0, np.zeros(0), (0.0, 0.01, 0.0), preset("reference")) - 0.01 *
    ...       preset("reference").c_L)
    30.0
    """

    force_N: float = 0.0
    reverse_ratio: float = 1.0
    location: str = _location_field()
    name: ClassVar[str] = "coulomb_friction"
    units: ClassVar[dict] = {"force_N": "N", "reverse_ratio": "-"}
    fit_keys: ClassVar[tuple] = ("force_N",)
    bounds: ClassVar[dict] = {"force_N": (1e-2, 1e4), "reverse_ratio": REVERSE_RATIO_BOUNDS}
    order: ClassVar[int] = 40
    description: ClassVar[str] = "Coulomb seal friction F_c sign(v)"
    slot: ClassVar[int] = K.S_COUL

    def __post_init__(self):
        check_nonnegative("coulomb_friction force_N", self.force_N, "N")
        _check_reverse_ratio(self)
        self._check_composition()

    def spec_flags(self):
        return {K.S_CPIST: int(self.location == "piston")}

    def check_with(self, effects):
        _check_location(self, effects)

    small_signal_reason: ClassVar[str | None] = (
        "Coulomb friction sticks at rest (infinite slope of sign(v))")
    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_CF], ep[K.E_CRQ] = self.force_N, self.reverse_ratio

    def describing_function(self, amplitude, omega, params, model=None):
        """Equivalent damping 2 (1 + q) F_c / (pi w Y) [N s/m] (no stiffness, no inertance).

        The first harmonic of the square wave +F_c / -q F_c; its mean
        (1 - q) F_c / 2 is not part of a describing function.

        Examples
        --------
        >>> k, c, b = CoulombFriction(30.0).describing_function(1e-3, 2 * math.pi, None)
        >>> round(c * 2 * math.pi * 1e-3 * math.pi / 4, 12)   # = F_c
        30.0
        >>> k, c2, b = CoulombFriction(30.0, 0.5).describing_function(1e-3, 2 * math.pi, None)
        >>> round(c2 / c, 12)   # (1 + q) / 2
        0.75
        """
        Y, w = _check_harmonic(amplitude, omega)
        return 0.0, 2.0 * (1.0 + self.reverse_ratio) * self.force_N / (math.pi * w * Y), 0.0


@dataclass(frozen=True)
class ForceOffset(Effect):
    """Load-cell bias: F += offset [N] (the paper removes it before the fit, Sec. IV.B).

    Parameters
    ----------
    offset_N : float
        Constant force added to the model's load-cell force [N] (any sign).
    """

    offset_N: float = 0.0
    name: ClassVar[str] = "force_offset"
    units: ClassVar[dict] = {"offset_N": "N"}
    fit_keys: ClassVar[tuple] = ("offset_N",)
    bounds: ClassVar[dict] = {"offset_N": (-1e4, 1e4)}
    order: ClassVar[int] = 50
    description: ClassVar[str] = "constant load-cell bias"
    slot: ClassVar[int] = K.S_OFF
    linear: ClassVar[bool] = True

    def __post_init__(self):
        check_finite("force_offset offset_N", self.offset_N, "N")

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_OFF] = self.offset_N

    def describing_function(self, amplitude, omega, params, model=None):
        """A constant force has no first harmonic: (0, 0, 0)."""
        _check_harmonic(amplitude, omega)
        return 0.0, 0.0, 0.0


@dataclass(frozen=True)
class MovingMass(Effect):
    """Piston and rod inertia: F += m a (Sec. IV.C: about 1.8 N peak at 0.5 Hz).

    Parameters
    ----------
    mass_kg : float
        Moving mass m >= 0 [kg].
    """

    mass_kg: float = 0.0
    name: ClassVar[str] = "moving_mass"
    units: ClassVar[dict] = {"mass_kg": "kg"}
    fit_keys: ClassVar[tuple] = ("mass_kg",)
    bounds: ClassVar[dict] = {"mass_kg": (1e-3, 1e3)}
    order: ClassVar[int] = 45
    description: ClassVar[str] = "piston and rod inertia m a"
    slot: ClassVar[int] = K.S_MASS
    uses_acceleration: ClassVar[bool] = True
    linear: ClassVar[bool] = True

    def __post_init__(self):
        check_nonnegative("moving_mass mass_kg", self.mass_kg, "kg")

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_MASS] = self.mass_kg

    def describing_function(self, amplitude, omega, params, model=None):
        """An inertance m [kg] in parallel (exact: F = m a is linear)."""
        _check_harmonic(amplitude, omega)
        return 0.0, 0.0, self.mass_kg


@dataclass(frozen=True)
class SmoothFriction(Effect):
    """Seal friction with pre-sliding and Stribeck behaviour (LuGre without bristle damping).

    F += F_c z with dz/dt = (sigma0 / F_c)(v - |v| z / g(v)),
    g(v) = 1 + (r - 1) exp(-(v / v_s)^2) (:func:`lugre_rate`).  Around each
    reversal the force changes gradually over a pre-sliding stroke of about
    F_c / sigma0 (the gradual transitions of Figs. 5-6 and the pre-slide
    stage of Fig. 4); with r > 1 the sliding force falls from r F_c to F_c
    as |v| passes v_s (the Stribeck region of Fig. 4).  sigma0 -> infinity
    with r = 1 is Coulomb friction.  Extra state ``z_friction`` [-],
    starting at 0, driven by the measured rod velocity.

    At ``location="piston"`` the seal sits behind a dead band (``freeplay``):
    the bristles are driven by the piston velocity (the dead band's output
    rate) and the load cell reads the bristle force F_c z, which the
    massless piston can only pass through the contact.  Derived rather than
    scaled: when the rod backs off, the loaded bristles keep the piston
    pressed against it (its elastic spring-back, a stroke of at most about
    F_c / sigma0) until their force has gone, and only then does the gap
    open (:func:`~liquidamp.device.kernels.piston_contact`); inside the gap
    the piston and its bristles stay put, unloaded (the force there is below
    about 1 % of F_c, the regularisation ``Z_HOLD``).  The freeplay state
    ``y_fp`` is the piston position including that spring-back.  Not behind
    ``series_compliance`` (ParameterError).

    The transition exponent n (Bouc-Wen's) shapes the pre-sliding: n = 1
    is the exponential approach above; a large n keeps the bristle stiff
    (slope sigma0) up to the sliding level and then slips sharply, the
    elastic-plastic (Jenkins) element of a clamped band.

    Direction-dependent level (``reverse_ratio`` q): F = F_c z for z >= 0
    and q F_c z for z < 0 (:func:`~liquidamp.device.kernels.friction_level`),
    sliding at +r F_c ... F_c forward and -q F_c in reverse, and zero where
    the bristles are unloaded (inside a dead band).

    Parameters
    ----------
    force_N : float
        Sliding (Coulomb) level F_c >= 0 [N].
    stiffness_N_per_m : float
        Bristle (pre-sliding) stiffness sigma0 > 0 [N/m].
    stribeck_velocity_m_per_s : float
        Stribeck velocity v_s > 0 [m/s].
    static_ratio : float
        Static-to-sliding force ratio r >= 1 [-] (1: no Stribeck dip, Dahl-like).
    reverse_ratio : float
        Reverse-to-forward level ratio q in [0.1, 10] [-] (1: symmetric).
    transition_exponent : float
        Pre-sliding transition exponent n in [1, 20] [-] (1: LuGre/Dahl).
    location : {"rod", "piston"}
        Where the seal sits (a composition choice, not fitted).
    """

    force_N: float = 0.0
    stiffness_N_per_m: float = 1.0e5
    stribeck_velocity_m_per_s: float = 0.005
    static_ratio: float = 1.0
    reverse_ratio: float = 1.0
    transition_exponent: float = 1.0
    location: str = _location_field()
    name: ClassVar[str] = "smooth_friction"
    units: ClassVar[dict] = {"force_N": "N", "stiffness_N_per_m": "N/m",
                             "stribeck_velocity_m_per_s": "m/s", "static_ratio": "-",
                             "reverse_ratio": "-", "transition_exponent": "-"}
    fit_keys: ClassVar[tuple] = ("force_N", "stiffness_N_per_m")
    bounds: ClassVar[dict] = {"force_N": (1e-2, 1e4), "stiffness_N_per_m": (1e2, 1e9),
                              "stribeck_velocity_m_per_s": (1e-5, 1.0),
                              "static_ratio": (1.0, 5.0), "reverse_ratio": REVERSE_RATIO_BOUNDS,
                              "transition_exponent": (1.0, 20.0)}
    order: ClassVar[int] = 35
    description: ClassVar[str] = "LuGre/Dahl friction: gradual reversal, Stribeck"
    state_names: ClassVar[tuple] = ("z_friction",)
    state_units: ClassVar[tuple] = ("-",)
    slot: ClassVar[int] = K.S_IZ

    def __post_init__(self):
        check_nonnegative("smooth_friction force_N", self.force_N, "N")
        for key, unit in (("stiffness_N_per_m", "N/m"), ("stribeck_velocity_m_per_s", "m/s")):
            v = check_finite(f"smooth_friction {key}", getattr(self, key), unit)
            if not v > 0:
                raise ParameterError(f"smooth_friction {key} must be > 0 [{unit}], got {v:g}")
        r = check_finite("smooth_friction static_ratio", self.static_ratio, "-")
        if r < 1.0:
            raise ParameterError(f"smooth_friction static_ratio must be >= 1 [-], got {r:g}")
        _check_reverse_ratio(self)
        n = check_finite("smooth_friction transition_exponent", self.transition_exponent, "-")
        if not 1.0 <= n <= 20.0:
            raise ParameterError("smooth_friction transition_exponent must be in [1, 20] [-] "
                                 f"(1: LuGre/Dahl, large: elastic-plastic), got {n:g}")
        self._check_composition()

    def spec_flags(self):
        return {K.S_ZPIST: int(self.location == "piston")}

    def check_with(self, effects):
        _check_location(self, effects)

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_SFC], ep[K.E_SIG] = self.force_N, self.stiffness_N_per_m
        ep[K.E_VS], ep[K.E_SR] = self.stribeck_velocity_m_per_s, self.static_ratio
        ep[K.E_FRQ], ep[K.E_FEX] = self.reverse_ratio, self.transition_exponent

    def describing_function(self, amplitude, omega, params, model=None):
        """Equivalent (k, c, 0) from the first harmonic of F_c z on its periodic orbit.

        The bristle state is driven by the stroke alone, so its describing
        function is exact: z is integrated (Radau, rtol 1e-10) over cycles
        of y = Y sin(w t) until one period repeats to 1e-9, and
        k + i w c = F1 / Y.  Large amplitudes tend to Coulomb's
        (0, 4 F_c / (pi w Y)); small ones to the bristle spring (sigma0, 0).

        Examples
        --------
        >>> f = SmoothFriction(30.0, 1e7)
        >>> k, c, b = f.describing_function(1e-3, 2 * math.pi, None)
        >>> c_coulomb = CoulombFriction(30.0).describing_function(1e-3, 2 * math.pi, None)[1]
        >>> bool(abs(c / c_coulomb - 1) < 0.01), bool(0 < k < 0.05 * 1e7)
        (True, True)
        """
        from scipy.integrate import solve_ivp

        Y, w = _check_harmonic(amplitude, omega)
        if self.force_N == 0.0:
            return 0.0, 0.0, 0.0
        args = (self.force_N, self.stiffness_N_per_m, self.stribeck_velocity_m_per_s,
                self.static_ratio, self.transition_exponent)
        T = 2.0 * math.pi / w
        N = 512
        z0 = 0.0
        for _ in range(50):
            sol = solve_ivp(lambda t, z: [lugre_rate(Y * w * math.cos(w * t), z[0], *args)],
                            (0.0, T), [z0], method="Radau", rtol=1e-10, atol=1e-12,
                            t_eval=np.arange(N + 1) * (T / N), max_step=T / 64)
            z = sol.y[0]
            if abs(z[-1] - z0) < 1e-9:
                break
            z0 = z[-1]
        level = np.where(z[:N] >= 0.0, z[:N], self.reverse_ratio * z[:N])
        F1 = 2.0 / N * np.sum(self.force_N * level * np.exp(-1j * w * sol.t[:N]))
        K = 1j * F1 / Y  # y = Y sin(w t) = Im(Y e^{iwt}): K = F1 / (-i Y)
        return float(K.real), float(K.imag / w), 0.0


@dataclass(frozen=True)
class SlipWeakening(Effect):
    """Slip-weakening smooth friction: a breakaway level that decays over a slip distance.

    The force of the model's ``smooth_friction`` is multiplied by
    1 + beta (1 - w sign(z)) / 2 (:func:`~liquidamp.device.kernels.weakening`), w the slip
    memory, dw/dt = |v| (sign(v) - w) / D (:func:`~liquidamp.device.kernels.slip_memory_rate`),
    driven by the velocity that drives the bristles (the rod's, or the piston's behind a dead
    band).  After each reversal the friction builds up over its pre-sliding stroke to a
    breakaway level of about (1 + beta) F_c and falls to the sliding level F_c as the slip
    since the reversal, s, passes D: F ~ F_c z (1 + beta exp(-s / D)).  The peak sits at the
    same slip at any rate (a slip-distance law, unlike the Stribeck rise of
    ``static_ratio``, which is a velocity law): a clamped band or a seal whose static grip
    is lost over a characteristic slip distance (Ida's and Palmer and Rice's slip-weakening
    friction; the state of Ruina's rate-and-state friction also evolves over a slip
    distance).  beta = 0 is the smooth friction alone; D -> 0 too.  Extra state ``w_slip``
    [-], 0 at rest (its first reversals settle it, as the bristles').

    Needs ``smooth_friction`` in the model (ParameterError otherwise).

    Parameters
    ----------
    ratio : float
        beta >= 0, the breakaway level's excess over the sliding level [-].
    distance_m : float
        D > 0, the weakening (slip) distance [m].

    References
    ----------
    .. [1] Y. Ida, "Cohesive force across the tip of a longitudinal-shear crack and
       Griffith's specific surface energy", J. Geophys. Res. 77(20), 1972.
    .. [2] A. C. Palmer and J. R. Rice, "The growth of slip surfaces in the progressive
       failure of over-consolidated clay", Proc. R. Soc. Lond. A 332, 1973.
    .. [3] A. Ruina, "Slip instability and state variable friction laws", J. Geophys. Res.
       88(B12), 1983.

    Examples
    --------
    >>> from liquidamp.device.effects import with_effects
    >>> from liquidamp.device.models import get_model
    >>> m = with_effects(get_model("dashpot"), SmoothFriction(100.0, 1e6),
    ...                  SlipWeakening(0.3, 1e-3))
    >>> m.state_names
    ('z_friction', 'w_slip')
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> # bristles loaded forward, slip memory still backward: the breakaway level
    >>> f = m.force(0.0, np.array([1.0, -1.0]), (0.0, 0.0, 0.0), p)
    >>> round(float(f), 6)
    130.0
    """

    ratio: float = 0.0
    distance_m: float = 1e-3
    name: ClassVar[str] = "slip_weakening"
    units: ClassVar[dict] = {"ratio": "-", "distance_m": "m"}
    fit_keys: ClassVar[tuple] = ("ratio", "distance_m")
    bounds: ClassVar[dict] = {"ratio": (0.0, 5.0), "distance_m": (1e-7, 1.0)}
    order: ClassVar[int] = 36
    description: ClassVar[str] = ("slip-weakening friction: a breakaway level decaying over "
                                  "a slip distance")
    state_names: ClassVar[tuple] = ("w_slip",)
    state_units: ClassVar[tuple] = ("-",)
    slot: ClassVar[int] = K.S_IW
    small_signal_reason: ClassVar[str | None] = (
        "its slip memory follows |v|, which has no linearization at rest")
    describing_reason: ClassVar[str | None] = (
        "it scales the smooth friction's force by the slip history; the friction's first "
        "harmonic then depends on both")

    def __post_init__(self):
        b = check_nonnegative("slip_weakening ratio", self.ratio, "-")
        if b > 5.0:
            raise ParameterError(f"slip_weakening ratio must be in [0, 5] [-], got {b:g}")
        check_positive("slip_weakening distance_m", self.distance_m, "m")

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """A breakaway 10 % above the sliding level, lost over a tenth of the stroke."""
        return cls(ratio=0.1, distance_m=0.1 * float(amplitude))

    def check_with(self, effects):
        if not any(e.name == "smooth_friction" for e in effects):
            raise ParameterError(
                "slip_weakening weakens smooth_friction, which the model does not hold; got "
                + (", ".join(str(e) for e in effects) or "no effects"))

    def pack(self, ep):
        ep[K.E_WB], ep[K.E_WD] = self.ratio, self.distance_m


@dataclass(frozen=True)
class Elastomer(Effect):
    """Elastomer branch in parallel on the rod: the standard linear solid.

    A spring k0 in parallel with a spring k1 in series with a dashpot c1
    (a Zener / standard linear solid, e.g. an elastomeric lead-lag element
    beside the fluid device), acting on the measured rod stroke:
    F += k0 y + F_e, dF_e/dt = k1 v - F_e / tau, tau = c1 / k1
    (:func:`~liquidamp.device.kernels.elastomer_rate`).  One state
    ``F_elastomer`` [N], 0 at rest.  Linear, so its small-signal model and
    its describing function are exact and equal:

    K(i w) = k0 + k1 i w tau / (1 + i w tau).

    Parameters
    ----------
    parallel_stiffness_N_per_m : float
        k0 >= 0 [N/m].
    branch_stiffness_N_per_m : float
        k1 >= 0 [N/m].
    branch_damping_N_s_per_m : float
        c1 > 0 [N s/m].

    References
    ----------
    .. [1] C. Zener, Elasticity and Anelasticity of Metals, Univ. of Chicago
       Press, 1948 (the standard linear solid).
    .. [2] D. L. Kunz, "Nonlinear analysis of helicopter ground resonance",
       Nonlinear Dyn. 2002 (elastomeric lag dampers).

    Examples
    --------
    >>> e = Elastomer(1e5, 4e5, 4e5 / (2 * math.pi * 3.0))   # w tau = 1 at 3 Hz
    >>> k, c, b = e.describing_function(1e-3, 2 * math.pi * 3.0, None)
    >>> round(k), round(c * 2 * math.pi * 3.0)               # k0 + k1/2, k1/2
    (300000, 200000)
    """

    parallel_stiffness_N_per_m: float = 0.0
    branch_stiffness_N_per_m: float = 0.0
    branch_damping_N_s_per_m: float = 1.0
    name: ClassVar[str] = "elastomer"
    units: ClassVar[dict] = {"parallel_stiffness_N_per_m": "N/m",
                             "branch_stiffness_N_per_m": "N/m",
                             "branch_damping_N_s_per_m": "N s/m"}
    fit_keys: ClassVar[tuple] = ("branch_stiffness_N_per_m", "branch_damping_N_s_per_m",
                                 "parallel_stiffness_N_per_m")
    bounds: ClassVar[dict] = {"parallel_stiffness_N_per_m": (1.0, 1e9),
                              "branch_stiffness_N_per_m": (1.0, 1e9),
                              "branch_damping_N_s_per_m": (1e-2, 1e8)}
    order: ClassVar[int] = 42
    description: ClassVar[str] = "parallel elastomer (standard linear solid) on the rod"
    state_names: ClassVar[tuple] = ("F_elastomer",)
    state_units: ClassVar[tuple] = ("N",)
    slot: ClassVar[int] = K.S_IEL
    linear: ClassVar[bool] = True
    screened: ClassVar[bool] = False  # a candidate on request (see the module notes)

    def __post_init__(self):
        check_nonnegative("elastomer parallel_stiffness_N_per_m",
                          self.parallel_stiffness_N_per_m, "N/m")
        check_nonnegative("elastomer branch_stiffness_N_per_m",
                          self.branch_stiffness_N_per_m, "N/m")
        check_positive("elastomer branch_damping_N_s_per_m", self.branch_damping_N_s_per_m,
                       "N s/m")

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_K0] = self.parallel_stiffness_N_per_m
        ep[K.E_K1] = self.branch_stiffness_N_per_m
        ep[K.E_C1E] = self.branch_damping_N_s_per_m

    def state_scales(self, params):
        return np.array([max(self.branch_stiffness_N_per_m * 1e-4, 1.0)])

    def stiffness(self, omega: float) -> complex:
        """K(i w) = k0 + k1 i w tau / (1 + i w tau) [N/m] at w [rad/s]."""
        k1, c1 = self.branch_stiffness_N_per_m, self.branch_damping_N_s_per_m
        iwc = 1j * float(omega) * c1
        branch = 0j if k1 == 0.0 else k1 * iwc / (k1 + iwc)
        return self.parallel_stiffness_N_per_m + branch

    def describing_function(self, amplitude, omega, params, model=None):
        """Exact (linear): (Re K, Im K / w, 0)."""
        _, w = _check_harmonic(amplitude, omega)
        K_ = self.stiffness(w)
        return float(K_.real), float(K_.imag / w), 0.0

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """A branch of 5 % of the record's force amplitude at w tau = 1, k0 = k1 / 2."""
        k1 = 0.05 * force_amplitude_N / amplitude
        return cls(0.5 * k1, k1, k1 / omega)


def _contact_fraction(rho: float) -> float:
    """First-harmonic share of one one-sided stop with threshold rho = a / Y [-]."""
    if rho >= 1.0:
        return 0.0
    if rho <= -1.0:
        return 1.0
    return (0.5 * math.pi - math.asin(rho) - rho * math.sqrt(1.0 - rho * rho)) / math.pi


@dataclass(frozen=True)
class EndStops(Effect):
    """Stiff end stops: contact when the rod stroke leaves centre +/- clearance.

    F += sign(u) (k (|u| - clearance) + c v) beyond the clearance,
    u = y - centre, nothing inside; the onset is C1 over a width
    w = 0.01 clearance + 1e-7 m (:func:`~liquidamp.device.kernels.stop_force`:
    the elastic force is exact beyond it).  The elastic part is a force of
    the stroke alone, so it does no net work over a cycle; the damping is
    Kelvin-Voigt.  Describing function (exact up to the onset width): with
    rho_+ = (clearance + centre) / Y, rho_- = (clearance - centre) / Y and
    n(rho) = (pi/2 - arcsin rho - rho sqrt(1 - rho^2)) / pi per stop
    (0 for rho >= 1, 1 for rho <= -1), (k, c) = (k_s, c_s) (n(rho_+) + n(rho_-));
    a centre off zero also gives a mean force, which has no first harmonic.

    Parameters
    ----------
    stiffness_N_per_m : float
        Contact stiffness k >= 0 [N/m].
    clearance_m : float
        Free stroke on either side of the centre >= 0 [m].
    damping_N_s_per_m : float
        Contact damping c >= 0 [N s/m].
    centre_m : float
        Stroke at the middle of the free travel [m].

    References
    ----------
    .. [1] A. Gelb, W. E. Vander Velde, Multiple-Input Describing Functions
       and Nonlinear System Design, McGraw-Hill, 1968 (dead zone).

    Examples
    --------
    >>> k, c, b = EndStops(1e6, 1e-3).describing_function(2e-3, 10.0, None)
    >>> round(k / 1e6, 6)          # 1 - (2/pi)(pi/6 + sqrt(3)/4)
    0.391002
    """

    stiffness_N_per_m: float = 0.0
    clearance_m: float = 1.0e-2
    damping_N_s_per_m: float = 0.0
    centre_m: float = 0.0
    name: ClassVar[str] = "end_stops"
    units: ClassVar[dict] = {"stiffness_N_per_m": "N/m", "clearance_m": "m",
                             "damping_N_s_per_m": "N s/m", "centre_m": "m"}
    fit_keys: ClassVar[tuple] = ("stiffness_N_per_m", "clearance_m")
    bounds: ClassVar[dict] = {"stiffness_N_per_m": (1e2, 1e10), "clearance_m": (1e-6, 1e-1),
                              "damping_N_s_per_m": (1e-1, 1e6), "centre_m": (-1e-1, 1e-1)}
    order: ClassVar[int] = 47
    description: ClassVar[str] = "stiff contact beyond a clearance"
    slot: ClassVar[int] = K.S_STOP
    screened: ClassVar[bool] = False  # a candidate on request (see the module notes)

    def __post_init__(self):
        check_nonnegative("end_stops stiffness_N_per_m", self.stiffness_N_per_m, "N/m")
        check_nonnegative("end_stops clearance_m", self.clearance_m, "m")
        check_nonnegative("end_stops damping_N_s_per_m", self.damping_N_s_per_m, "N s/m")
        check_finite("end_stops centre_m", self.centre_m, "m")

    describing_reason: ClassVar[str | None] = None

    def pack(self, ep):
        ep[K.E_KS], ep[K.E_CS] = self.stiffness_N_per_m, self.damping_N_s_per_m
        ep[K.E_CLR], ep[K.E_CTR] = self.clearance_m, self.centre_m

    def describing_function(self, amplitude, omega, params, model=None):
        """(k_s N, c_s N, 0), N = n(rho_+) + n(rho_-) (class docstring)."""
        Y, _ = _check_harmonic(amplitude, omega)
        N = (_contact_fraction((self.clearance_m + self.centre_m) / Y)
             + _contact_fraction((self.clearance_m - self.centre_m) / Y))
        return self.stiffness_N_per_m * N, self.damping_N_s_per_m * N, 0.0

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """Stops at 90 % of the stroke, 5 x the record's force over the stroke."""
        return cls(5.0 * force_amplitude_N / amplitude, 0.9 * amplitude)
