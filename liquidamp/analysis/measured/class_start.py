"""What every class start is built of (:mod:`~liquidamp.analysis.measured.device_class`,
:mod:`~liquidamp.analysis.measured.start_valved`): the start itself, a fluid device matched
to the records' complex stiffness, the chambers stretched to the stroke, and the viscous
starts' offset bounded by the records' force scale.

References
----------
.. [1] B. Titurus, "Generalized liquid-based damping device for passive vibration control",
   AIAA Journal 56(10), 2018 (eq. 16: the device's linear model).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.fit_spec import FitSpec, effect_bounds, record_scales
from liquidamp.analysis.measured.start import (
    linear_stiffness,
    physics_factors,
    similar_device,
    stroke_factor,
)
from liquidamp.device.effects import EFFECTS
from liquidamp.device.params import DeviceParams

#: Share of |K*| in K' of the viscous start's target (a dashpot, but its air cannot be
#: rigid), and least share in K'' [-].
VISCOUS_FLOOR = 0.05
#: Share of the quadratic loss in the viscous start's describing-function damping [-].
QUADRATIC_SHARE = 0.05

@dataclass(frozen=True)
class ClassStart:
    """A structurally different start: device, effects, what varies, what was read."""

    name: str
    params: DeviceParams
    effects: tuple
    spec: FitSpec | None
    reason: str


def fluid_matched(reference: DeviceParams, records, targets,
                  quadratic_share: float | None = None) -> tuple[DeviceParams, str]:
    """A device similar to ``reference`` whose linear model carries ``targets`` (one
    complex K [N/m] per record): the force factor rho matches |K| (geometric mean over
    the records, eq. 16 with inertia), then the air ratios and losses match K', K''
    (:func:`~liquidamp.analysis.measured.start.physics_factors`).  ``quadratic_share``
    sets c2 so that the quadratic loss is that share of the damping c_eq first; an
    inertance b_L beyond what the target allows (w^2 b_L > 1 / (2 |Im 1/K|), where the
    series spring-dashpot-inertance has no solution) is brought to half that bound."""
    Ys = [r.stroke_scale for r in records]
    ref = [linear_stiffness(reference, r.frequency, Y) for r, Y in zip(records, Ys,
                                                                      strict=True)]
    rho = float(np.exp(np.mean([math.log(abs(K) / abs(R))
                                for K, R in zip(targets, ref, strict=True)])))
    p, _ = similar_device(reference, force=rho)
    how = [f"force x{rho:.3g}"]
    if quadratic_share is not None:
        Q = float(np.mean([p.A_p * 2 * math.pi * r.frequency * Y
                           for r, Y in zip(records, Ys, strict=True)]))
        quad = 8.0 / (3.0 * math.pi) * p.c2 * Q
        if quad > 0:
            f2 = quadratic_share / (1 - quadratic_share) * p.c1 / quad
            p = p.scaled(c2=f2)
            how.append(f"c2 x{f2:.3g} (quadratic loss {quadratic_share:.0%} of c_eq)")
    # the channel's inertance in series makes K' negative beyond w^2 b_L = 1 / (2 |Im 1/K|)
    # (linear_fit has no solution there): a larger one is brought to half that bound
    f_in = min(1.0 / (2.0 * abs((1.0 / K).imag)) / ((2 * math.pi * r.frequency) ** 2 * p.b_L)
               for K, r in zip(targets, records, strict=True)) if p.b_L > 0 else math.inf
    if f_in < 1.0:
        p = p.scaled(S_t=0.5 * f_in)
        how.append(f"S_t x{0.5 * f_in:.3g} (inertance within K*)")
    f_air, f_loss = physics_factors(records, p, targets=targets)
    mult = {**(dict.fromkeys(("inv_gamma1", "inv_gamma2"), f_air) if f_air else {}),
            **(dict.fromkeys(("c1", "c2"), f_loss) if f_loss else {})}
    if mult:
        p = p.scaled(**mult)
    how += ([f"air x{f_air:.3g}"] if f_air else []) + ([f"losses x{f_loss:.3g}"]
                                                        if f_loss else [])
    return p, ", ".join(how)


def _reference(base: DeviceParams, records) -> DeviceParams:
    """The starting device with its chambers stretched so the stroke uses at most half."""
    return similar_device(base, stroke=stroke_factor(records, base))[0]


def _offset_spec(effs, records) -> FitSpec:
    """c1 and the effects' fit keys, the force offset bounded by the records' force scale
    (:func:`~liquidamp.analysis.measured.fit_spec.effect_bounds`: +-2 F_s, what the fit
    gives it anyway), so that a record's mean force beyond the catalogue's +-10 kN (a
    building damper's) is a start, not an error."""
    name = "force_offset.offset_N"
    cat_lo, cat_hi = EFFECTS["force_offset"].bounds["offset_N"]
    F0 = next(e.offset_N for e in effs if e.name == "force_offset")
    held = tuple(e.replace(offset_N=min(max(F0, cat_lo), cat_hi)) if e.name == "force_offset"
                 else e for e in effs)
    spec = FitSpec.default(vary=("c1",), effects=held)
    lo, hi = effect_bounds("force_offset", "offset_N", record_scales(records))
    return FitSpec(tuple(
        p.replace(value=F0, min=min(lo, F0), max=max(hi, F0), scale=max(abs(F0), 1.0))
        if p.name == name else p for p in spec.parameters))
