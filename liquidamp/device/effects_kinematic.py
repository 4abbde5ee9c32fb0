"""Kinematic effects (series compliance, freeplay: between the measured rod stroke and the piston).

Part of the catalogue of :mod:`liquidamp.device.effects` (the public face: the
table, the composition order, :func:`~liquidamp.device.effects.with_effects`);
the :class:`~liquidamp.device.effects_base.Effect` base is in
:mod:`liquidamp.device.effects_base`.  References as in :mod:`liquidamp.device.effects`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.effects_base import (
    _COMPOSITION,
    Effect,
)
from liquidamp.errors import (
    ParameterError,
    check_nonnegative,
)


@dataclass(frozen=True)
class SeriesCompliance(Effect):
    """Rig or attachment elasticity k between the measured stroke and the piston.

    The piston position ``y_piston`` is a state.  The piston is massless, so
    the spring carries the fluid force, k (y - y_piston) = F_fluid; the
    piston velocity follows from the time derivative of that balance, which
    is affine in it because the chamber equations are (see
    :func:`compliance_rate`).  The fluid model sees the piston stroke; the
    load cell reads the spring force.  Needs a model whose force is a linear
    function of its states (every model with pressure states and
    ``maxwell``); k = inf reproduces the bare model.  Like air in the
    chambers it is a spring in series with the channel, so at small strokes
    it trades against the air ratios (only the pressure dependence of the
    air's stiffness tells them apart).

    Parameters
    ----------
    stiffness_N_per_m : float
        Series stiffness k > 0 [N/m] (math.inf: rigid).
    """

    stiffness_N_per_m: float = math.inf
    bare: ClassVar[dict] = {"stiffness_N_per_m": math.inf}
    name: ClassVar[str] = "series_compliance"
    units: ClassVar[dict] = {"stiffness_N_per_m": "N/m"}
    fit_keys: ClassVar[tuple] = ("stiffness_N_per_m",)
    bounds: ClassVar[dict] = {"stiffness_N_per_m": (1e3, 1e10)}
    order: ClassVar[int] = 20
    description: ClassVar[str] = "spring in series between stroke and piston"
    state_names: ClassVar[tuple] = ("y_piston",)
    state_units: ClassVar[tuple] = ("m",)
    slot: ClassVar[int] = K.S_IC
    kind: ClassVar[str] = "kinematic"

    def __post_init__(self):
        k = float(self.stiffness_N_per_m)
        if not k > 0 or math.isnan(k):
            raise ParameterError(
                f"series_compliance stiffness_N_per_m must be > 0 [N/m] (inf: rigid), got {k:g}")

    def check(self, model):
        if model.n_base_states == 0 or model.uses_acceleration:
            raise ParameterError(
                f"effect {self.name!r} needs a model whose force is carried by its states; "
                f"model {model.name!r} has {model.n_base_states} states"
                + (" and uses the acceleration" if model.uses_acceleration else "")
                + "; for a dashpot behind a spring use 'maxwell'")

    describing_reason: ClassVar[str | None] = (
        "a spring in series with the fluid; its equivalent is 1/(1/K_fluid + 1/k), not a "
        "parallel element")

    def pack(self, ep):
        ep[K.E_KC] = float(self.stiffness_N_per_m)

    def initial_state(self, params, y0):
        return np.array([y0])

    def state_scales(self, params):
        return np.array([1e-4])


@dataclass(frozen=True)
class Freeplay(Effect):
    """Dead band of half-width ``gap_m`` in the attachment (play operator).

    The driven side ``y_fp`` (a state) stays put while the rod crosses the
    gap and follows it once in contact (:func:`play_rate`); the piston is
    assumed held by its seals while in the gap, so the fluid keeps relaxing
    through the channel there.  The fluid model sees ``y_fp``.  gap 0
    reproduces the bare model.

    What the dead band drives is a composition choice (``drives``):
    ``"piston"`` (default) the piston with the fluid and any friction at
    ``location="piston"``; ``"friction"`` only the friction at
    ``location="piston"``, the fluid staying on the rod (a friction element
    -- a clamped band, a second seal -- coupled to the rod through its own
    play, beside a fluid piston fixed to the rod).  With ``"friction"`` the
    load cell reads the fluid force at the rod stroke plus the friction
    passed through the contact, so a fluid device keeps its Floquet
    invariants of the rod stroke; without friction at the piston such a dead
    band drives nothing (ParameterError).

    Parameters
    ----------
    gap_m : float
        Half-width of the dead band >= 0 [m].
    drives : {"piston", "friction"}
        What sits behind the dead band (a composition choice, not fitted).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device.effects import with_effects, CoulombFriction
    >>> m = with_effects(get_model("dashpot"), Freeplay(1e-3, drives="friction"),
    ...                  CoulombFriction(30.0, location="piston"))
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> # in the gap: the dashpot on the rod, no friction; in contact: both
    >>> f_gap = m.force(0.0, np.array([0.0]), (0.5e-3, 0.01, 0.0), p)
    >>> f_contact = m.force(0.0, np.array([0.0]), (1.5e-3, 0.01, 0.0), p)
    >>> round(float(f_gap - 0.01 * p.c_L), 9), round(float(f_contact - 0.01 * p.c_L), 9)
    (0.0, 30.0)
    """

    gap_m: float = 0.0
    drives: str = dataclasses.field(default="piston",
                                    metadata={_COMPOSITION: ("piston", "friction")})
    name: ClassVar[str] = "freeplay"
    units: ClassVar[dict] = {"gap_m": "m"}
    fit_keys: ClassVar[tuple] = ("gap_m",)
    bounds: ClassVar[dict] = {"gap_m": (1e-7, 1e-2)}
    order: ClassVar[int] = 30
    description: ClassVar[str] = "dead band in the attachment"
    state_names: ClassVar[tuple] = ("y_fp",)
    state_units: ClassVar[tuple] = ("m",)
    slot: ClassVar[int] = K.S_IFP
    kind: ClassVar[str] = "kinematic"

    def __post_init__(self):
        check_nonnegative("freeplay gap_m", self.gap_m, "m")
        self._check_composition()

    def spec_flags(self):
        return {K.S_FPFRIC: int(self.drives == "friction")}

    def check_with(self, effects):
        if self.drives == "friction" and not any(
                getattr(e, "location", "rod") == "piston" for e in effects):
            raise ParameterError(
                "freeplay drives='friction' needs friction at location 'piston' behind it "
                "(coulomb_friction or smooth_friction with location='piston'); got "
                f"{', '.join(str(e) for e in effects)}")

    @property
    def fluid_behind(self) -> bool:
        """Whether the fluid piston sits behind the dead band (``drives == "piston"``)."""
        return self.drives == "piston"

    small_signal_reason: ClassVar[str | None] = (
        "inside the dead band the piston does not move at all")
    describing_reason: ClassVar[str | None] = (
        "a dead band in series with the fluid")

    def pack(self, ep):
        ep[K.E_GAP] = self.gap_m

    def initial_state(self, params, y0):
        return np.array([y0])

    def state_scales(self, params):
        return np.array([1e-4])


@dataclass(frozen=True)
class FloatingFreeplay(Effect):
    """Dead band of half-width ``gap_m`` between the rod and a floating piston.

    The rod meets the piston through a contact of stiffness ``contact_stiffness_N_per_m``
    at either end of the band; the piston itself is massless and free (no seal holds it),
    so it carries the fluid force only through that contact, k_c(e) = F_fluid, e = y -
    y_piston, with k_c the contact's force law: 0 inside the band, k (|e| - gap) sign(e)
    beyond it (C1 onset, :func:`~liquidamp.device.kernels_laws.float_contact`).  Its rate
    follows as a series spring's (:func:`compliance_rate`) with the contact's engaged
    stiffness: in contact it follows the rod (stiffly), inside the band the fluid force
    is held at zero and the piston drifts with the channel's flow.  So the rod loses the
    piston not where it reverses but where the chambers have unloaded (the fluid pushes
    the piston back after the rod), and meets it again after crossing the band with no
    force in between; ``freeplay``'s piston, held by its seals, stays put in the band
    while the force it reads relaxes through the channel.  A piston with light seals or a
    rod-end clearance before a free piston reads so.

    ``gap_m`` 0 is the bare model (a rigid attachment; the contact stiffness then
    unused); a positive gap needs a finite contact stiffness.  It occupies the series
    spring's slot (``y_piston``), so it cannot be composed with ``series_compliance``.

    Parameters
    ----------
    gap_m : float
        Half-width of the dead band >= 0 [m].
    contact_stiffness_N_per_m : float
        Stiffness of the contact at the band's ends > 0 [N/m].

    References
    ----------
    .. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. II (the piston and chamber equations).
    .. [2] R. I. Leine, H. Nijmeijer, Dynamics and Bifurcations of Non-Smooth Mechanical
       Systems, Springer, 2004, Ch. 1 (unilateral contact with a backlash, regularized).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device.effects import with_effects
    >>> from liquidamp.coupled.testrig import HarmonicStroke, steady_state
    >>> fp = FloatingFreeplay(gap_m=5e-4, contact_stiffness_N_per_m=2e7)
    >>> m = with_effects(get_model("full"), fp)
    >>> r = steady_state(m, preset("device_b"), HarmonicStroke(0.002, 3.0))
    >>> # the rod crosses the band with the fluid force held at zero: a flat stretch of the
    >>> # loop about each reversal's end, 2 x 0.5 mm of its 8 mm of travel per cycle
    >>> bool(np.mean(np.abs(r.force) < 1e-3 * np.max(np.abs(r.force))) > 0.05)
    True
    """

    gap_m: float = 0.0
    contact_stiffness_N_per_m: float = 1e8
    bare: ClassVar[dict] = {"gap_m": 0.0}
    name: ClassVar[str] = "floating_freeplay"
    units: ClassVar[dict] = {"gap_m": "m", "contact_stiffness_N_per_m": "N/m"}
    fit_keys: ClassVar[tuple] = ("gap_m", "contact_stiffness_N_per_m")
    bounds: ClassVar[dict] = {"gap_m": (1e-7, 1e-2), "contact_stiffness_N_per_m": (1e3, 1e10)}
    order: ClassVar[int] = 20  # the series spring's place (the same compiled slot)
    description: ClassVar[str] = "dead band before a floating (unsealed) piston"
    state_names: ClassVar[tuple] = ("y_piston",)
    state_units: ClassVar[tuple] = ("m",)
    slot: ClassVar[int] = K.S_IC
    kind: ClassVar[str] = "kinematic"

    def __post_init__(self):
        check_nonnegative("floating_freeplay gap_m", self.gap_m, "m")
        k = float(self.contact_stiffness_N_per_m)
        if not (k > 0 and math.isfinite(k)):
            raise ParameterError("floating_freeplay contact_stiffness_N_per_m must be a finite "
                                 f"number > 0 [N/m], got {k:g}")

    check = SeriesCompliance.check

    def check_with(self, effects):
        if any(e.name == "series_compliance" for e in effects):
            raise ParameterError(
                "effect 'floating_freeplay' cannot be composed with 'series_compliance': "
                "both are the element between the rod and the piston (the contact stiffness "
                "is the floating freeplay's series spring)")

    small_signal_reason: ClassVar[str | None] = (
        "inside the dead band the piston floats and the device carries no force")
    describing_reason: ClassVar[str | None] = (
        "a dead band in series with the fluid, the piston free inside it")

    def pack(self, ep):
        # gap 0: the rigid attachment (the bare model), whatever the contact stiffness
        ep[K.E_KC] = float(self.contact_stiffness_N_per_m) if self.gap_m > 0 else math.inf
        ep[K.E_KCG] = float(self.gap_m)

    def initial_state(self, params, y0):
        return np.array([y0])

    def state_scales(self, params):
        return np.array([1e-4])
