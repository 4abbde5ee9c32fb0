"""Kinematic effects (series compliance, freeplay: between the measured rod stroke and the piston).

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

    Parameters
    ----------
    gap_m : float
        Half-width of the dead band >= 0 [m].
    """

    gap_m: float = 0.0
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
