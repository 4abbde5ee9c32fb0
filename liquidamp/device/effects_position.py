"""Position-dependent channel losses (``bypass_groove``): damping that is softer over part of
the stroke, as a bypass groove in the pressure tube or a tapered metering pin makes it.

Part of the catalogue of :mod:`liquidamp.device.effects` (the public face: the table, the
composition order, :func:`~liquidamp.device.effects.with_effects`); the compiled law is
:mod:`liquidamp.device.kernels_position`.

Hardware: a groove cut into the pressure tube lets oil bypass the piston while the piston's
land is over it, in parallel with the channel, so the channel's losses are lower over that
band of the stroke; a tapered metering pin does the same by opening a channel's orifice
with the stroke.  The bypass area seen through a land of finite width, with chamfered groove
edges, rises and falls smoothly; the profile here is the Gaussian bump
phi(xi) = exp(-xi^2), xi = (y - y_c) / w: the smoothest one-parameter band (C-infinity, so
that the analytic Jacobian, the time derivative along the stroke and the stiff steppers'
order hold across the edges), of 1/e half-width w; it has no flat bottom (a long groove
with short edge ramps would need a second shape parameter, not built).

References
----------
.. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5
   (position-sensitive damping: bypass grooves, tapered metering pins).
.. [2] B. Titurus, AIAA J. 56(10), 2018, eqs. (5), (10)-(20) (the losses scaled).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.effects_base import Effect, _check_harmonic
from liquidamp.errors import ParameterError, check_finite, check_positive

#: Stateless bases on which the channel's loss is a force law on the stroke rate.
_DAMPERS = ("dashpot", "dashpot_inerter", "viscous")
#: Effects whose exact force laws on those bases compose with the loss scale
#: multiplicatively (their describing functions assume the unscaled loss).
_FLOW_LAWS = ("relief_valve", "digressive_valve", "asymmetric_loss")


def groove_profile(y, centre_m: float, half_width_m: float):
    """Profile phi((y - y_c) / w) = exp(-((y - y_c) / w)^2) of a bypass groove [-].

    Parameters
    ----------
    y : float or array
        Piston stroke [m].
    centre_m, half_width_m : float
        Groove centre y_c [m] and 1/e half-width w > 0 [m].

    Examples
    --------
    >>> groove_profile(0.0, 0.0, 1e-3), round(groove_profile(1e-3, 0.0, 1e-3), 12)
    (1.0, 0.367879441171)
    """
    w = check_positive("bypass_groove half_width_m", half_width_m, "m")
    xi = (np.asarray(y, float) - float(centre_m)) / w
    out = np.exp(-xi * xi)
    return float(out) if out.ndim == 0 else out


def groove_averages(amplitude: float, centre_m: float, half_width_m: float,
                    n: int = 256) -> tuple[float, float]:
    """Profile averages over a harmonic stroke y = Y sin(t) weighted as the first harmonic
    of a linear and of a quadratic loss: (a1, a2) [-].

    a1 = (1 / pi) int_0^{2 pi} phi(Y sin t) cos^2 t dt,
    a2 = (3 / 8) int_0^{2 pi} phi(Y sin t) |cos t|^3 dt,

    both 1 for a groove wider than the stroke (phi = 1), computed by the trapezoidal rule
    on n points (spectrally accurate for this smooth periodic integrand).

    Examples
    --------
    >>> a1, a2 = groove_averages(1e-3, 0.0, 1e3)     # uniform: the whole loss scaled
    >>> round(a1, 9), round(a2, 9)
    (1.0, 1.0)
    """
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    phi = groove_profile(float(amplitude) * np.sin(t), centre_m, half_width_m)
    c = np.cos(t)
    a1 = float(np.mean(phi * c * c) * 2.0)
    a2 = float(np.mean(phi * np.abs(c) ** 3) * 2.0 * math.pi * 3.0 / 8.0)
    return a1, a2


@dataclass(frozen=True)
class BypassGroove(Effect):
    """Bypass groove: the channel's losses scaled by s(y) = 1 - d phi((y - y_c) / w).

    Over a band of the piston stroke y the channel has a path in parallel (a groove in the
    pressure tube, a metering pin), so its loss coefficients are multiplied by
    s(y) = 1 - d exp(-((y + y_0 - y_c) / w)^2) (module docstring: the profile and why), the
    centre y_c on the absolute stroke (the groove is cut at a fixed place in the tube; y_0 =
    ``stroke_offset_m``, the absolute stroke of the model's zero, a record's mean): c1, c2
    (volumetric models), g1, g2 (mass-flow models), T_D = c1 / B (``maxwell``), c_L
    (``dashpot``, ``dashpot_inerter``) and the viscous c and c2, where y is the stroke the
    fluid sees (behind the kinematic effects).  With a rigid fluid at a fixed stroke the
    steady channel law becomes dp = s(y) (c1 q + c2 q|q|).  s does not depend on the states,
    so the analytic Jacobian is the base one at the scaled coefficients, and the time
    derivative along the stroke gains (d rhs / d ln s) s'(y) / s dy/dt
    (:func:`~liquidamp.device.kernels_position.groove_rate_terms`).  Composes with
    ``asymmetric_loss`` multiplicatively; a relief valve's path is not scaled.

    Small signal at rest: exact from the composed equations (at rest the scale is the
    constant s(y_0) and its slope multiplies a zero flow).  Equivalent linearization: on
    the stateless dashpot-type bases F = s(y) (c v + c2 v|v|) has the exact first harmonic
    (0, -d (c a1 + 8 c2 w Y a2 / (3 pi)), 0) added to the base's (:func:`groove_averages`;
    no stiffness at any centre: the force's sine component integrates to zero, as
    t -> pi - t keeps the stroke and reverses the rate); refused on the models with chamber
    states (the channel's equivalent damping then depends on where in the cycle the flow
    peaks) and beside another flow law.

    Parameters
    ----------
    depth : float
        d in [0, 1) [-]: the loss at the groove's centre is (1 - d) times the channel's.
    centre_m : float
        y_c [m]: the stroke at the groove's middle (in the stroke the fluid sees).
    half_width_m : float
        w > 0 [m]: the 1/e half-width of the band.
    stroke_offset_m : float
        y_0 [m]: absolute stroke at the model's y = 0 (set per record by
        :func:`~liquidamp.device.effects.with_stroke_offset`; not fitted).

    References
    ----------
    .. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5.

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.effects import with_effects
    >>> p = preset("reference")
    >>> m = with_effects(get_model("dashpot"), BypassGroove(0.4, 0.0, 1e-3))
    >>> f = m.force(0.0, np.zeros(0), (0.0, 0.01, 0.0), p)      # at the centre: 0.6 c v
    >>> round(float(f / (0.01 * p.c_L)), 12)
    0.6
    """

    depth: float = 0.0
    centre_m: float = 0.0
    half_width_m: float = 1.0e-3
    stroke_offset_m: float = 0.0
    name: ClassVar[str] = "bypass_groove"
    units: ClassVar[dict] = {"depth": "-", "centre_m": "m", "half_width_m": "m",
                             "stroke_offset_m": "m"}
    fit_keys: ClassVar[tuple] = ("depth", "half_width_m", "centre_m")
    bounds: ClassVar[dict] = {"depth": (0.0, 0.95), "centre_m": (-1e-1, 1e-1),
                              "half_width_m": (1e-6, 1e-1), "stroke_offset_m": (-1.0, 1.0)}
    #: The groove sits at a fixed place in the tube: its centre is on the absolute stroke,
    #: the model's y + ``stroke_offset_m`` (set to a record's mean stroke by
    #: :func:`~liquidamp.device.effects.with_stroke_offset`, as ``simulate_record`` does).
    absolute_stroke: ClassVar[bool] = True
    order: ClassVar[int] = 4
    description: ClassVar[str] = "channel losses softer over a band of the stroke"
    slot: ClassVar[int] = K.S_GROOVE
    kind: ClassVar[str] = "fluid"

    def __post_init__(self):
        d = check_finite("bypass_groove depth", self.depth, "-")
        if not 0.0 <= d < 1.0:
            raise ParameterError(f"bypass_groove depth must be in [0, 1) [-] (the loss at "
                                 f"the centre is 1 - depth times the channel's), got {d:g}")
        check_finite("bypass_groove centre_m", self.centre_m, "m")
        check_positive("bypass_groove half_width_m", self.half_width_m, "m")
        check_finite("bypass_groove stroke_offset_m", self.stroke_offset_m, "m")

    def check(self, model):
        if model.base in ("spring", "inerter"):
            raise ParameterError(
                f"effect {self.name!r} scales the channel's losses: model {model.name!r} "
                "has none")

    def pack(self, ep):
        ep[K.E_GD], ep[K.E_GC], ep[K.E_GW] = self.depth, self.centre_m, self.half_width_m
        ep[K.E_GY0] = self.stroke_offset_m

    def scale(self, y):
        """Loss scale s(y) = 1 - d phi((y + y_0 - y_c) / w) at the model's piston stroke y [m]
        (y_0 = ``stroke_offset_m``) [-]."""
        return 1.0 - self.depth * groove_profile(np.asarray(y, float) + self.stroke_offset_m,
                                                 self.centre_m, self.half_width_m)

    describing_reason: ClassVar[str | None] = (
        "on a model with chamber states the scaled losses change the fluid equations and "
        "the channel's equivalent damping depends on where in the cycle the flow peaks; only "
        "on 'dashpot', 'dashpot_inerter' and 'viscous' is it an exact force law")

    def describing_function(self, amplitude, omega, params, model=None):
        """Exact on the dashpot-type bases alone: (0, -d (c a1 + 8 c2 w Y a2 / (3 pi)), 0).

        Examples
        --------
        >>> from liquidamp.device.models import VISCOUS, ViscousParams
        >>> from liquidamp.device.effects import with_effects
        >>> m = with_effects(VISCOUS, BypassGroove(0.5, 0.0, 1.0))     # 1 m wide: uniform
        >>> k, dc, b = m.effects[0].describing_function(1e-3, 10.0, ViscousParams(100.0), m)
        >>> round(dc, 6)
        -50.0
        """
        Y, w = _check_harmonic(amplitude, omega)
        if model is None or model.base not in _DAMPERS:
            return super().describing_function(amplitude, omega, params, model)
        other = [e.name for e in model.effects if e.name in _FLOW_LAWS]
        if other:
            raise ParameterError(
                f"effect {self.name!r} has no equivalent linearization beside "
                f"{', '.join(other)}: the loss scale multiplies their force law, whose "
                "describing function is written for the unscaled loss; use the time domain "
                "(liquidamp.analysis.response.stiffness.nonlinear_stiffness)")
        if model.base == "viscous":
            c, c2 = float(params.c), float(getattr(params, "c2", 0.0))
        else:
            c, c2 = float(params.c_L), 0.0
        a1, a2 = groove_averages(Y, self.centre_m - self.stroke_offset_m, self.half_width_m)
        dc = -self.depth * (c * a1 + 8.0 * c2 * w * Y * a2 / (3.0 * math.pi))
        return 0.0, float(dc), 0.0

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """A groove a fifth deep at mid-stroke, half as wide as the stroke amplitude (the
        diagnosis places it from the residual: ``candidates.groove_band``)."""
        return cls(0.2, 0.0, 0.5 * amplitude)
