"""Plausibility of a fitted device: geometry the records cannot support is flagged.

A least-squares fit can draw a loop with a device that the loop does not
support: a friction damper's rectangle drawn by a fluid device sized to 130
times the paper's piston with its air ratios and losses at their bounds, a
series spring softer than the loop's own turn, a dead band as wide as the
stroke.  :func:`plausibility_flags` states each such finding with its numbers;
:func:`~liquidamp.analysis.measured.calibration.calibrate` puts them in
``CalibrationResult.plausibility``, the JSON, the summary and the fit report.

The rules, each from what the record shows
    ``fluid_unsupported`` (a piston larger than the force and stroke warrant)
        The record fixes only the force level of a fluid device of the paper's
        family, not its size: a similar device scaled by a force factor a holds
        the same pressures under the same relative stroke and gives a times the
        force (:func:`~liquidamp.analysis.measured.start.similar_device`).  A
        device sized to the record by more than
        :data:`~liquidamp.analysis.measured.start.NEAR_FORCE_RATIO` (4) away
        from its preset is therefore a claim that a fluid device of that piston
        makes this loop; the claim is supported only where the fitted air
        ratios and losses stay inside their bounds.  Flagged when the piston
        was sized by more than 4x and a fluid parameter (air ratio or loss
        factor) ends at a bound: the loop is not a fluid device's of that size.
        Also flagged, whatever the sizing: a piston so large that the measured
        force amplitude F_a needs a pressure difference F_a / A_p below
        :data:`PRESSURE_SHARE` (5 %) of the fill pressure p0.  The air's
        stiffness follows the chamber pressure (eq. 2), so below a 5 % swing
        the device is linear to within the record's typical noise and neither
        the air ratios nor the quadratic loss are determined by the record.
    ``series_softer_than_loop``
        A series spring k_s carries the whole force, F = k_s (y - y_piston):
        the force can turn faster than k_s per unit of stroke only while the
        piston runs backwards (the fluid relaxing behind the spring).  The
        loop's own turn stiffness k_turn is read off the record: after each
        stroke reversal, the force change F_a (half the loop's peak-to-peak
        force, 1st-99th percentile) over the stroke it takes; the median over
        reversals.  Flagged when k_s < k_turn and k_s < 2 |K*| (more than half
        of the stroke is the spring's deflection, |K*| / k_s > 1/2): the spring
        then draws the loop's turn, a part of the record it is not (a dead band
        or a friction element's pre-sliding).  A dashpot-like device behind a
        stiff rig spring (|K*| well below k_s) is not flagged.
    ``gap_comparable_to_stroke``
        A dead band of half-width g under a stroke of amplitude Y leaves the
        device still over 2g of every 2Y swing; at g >= Y / 2 more than half of
        each swing moves nothing and the contact part of the loop rests on few
        samples.  Flagged at g >= Y / 2 (Y the largest first-harmonic amplitude
        of the records).
    ``end_stops_unsupported``
        End stops whose clearance is past the chamber end (V0 / A_p) or past
        the largest stroke of the records are never touched by the record:
        their stiffness is not determined.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (2), (10), (16).
.. [2] E. Buckingham, Phys. Rev. 4(4), 345-376, 1914 (similarity).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.measured.start import NEAR_FORCE_RATIO, first_harmonic_stiffness
from liquidamp.device.params import DeviceParams

__all__ = ["PlausibilityFlag", "plausibility_flags", "turn_stiffness", "PRESSURE_SHARE"]

#: Least pressure difference F_a / A_p, as a share of p0, that supports a fluid device [-].
PRESSURE_SHARE = 0.05
_FLUID = ("inv_gamma1", "inv_gamma2", "c1", "c2")


@dataclass(frozen=True)
class PlausibilityFlag:
    """One finding: its kind, a sentence with its numbers, the numbers [SI].

    Examples
    --------
    >>> f = PlausibilityFlag("gap_comparable_to_stroke", "freeplay gap 6 mm ...",
    ...                      {"gap [m]": 0.006})
    >>> f.as_dict()["kind"]
    'gap_comparable_to_stroke'
    """

    kind: str
    message: str
    values: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """JSON-ready."""
        return {"kind": self.kind, "message": self.message, "values": dict(self.values)}


def _force_amplitude(records) -> float:
    F = np.concatenate([r.force for r in records])
    return 0.5 * float(np.percentile(F, 99) - np.percentile(F, 1))


def turn_stiffness(records) -> float:
    """k_turn [N/m]: median over the stroke reversals of F_a / (stroke for a force change
    F_a after the reversal) (module docstring); nan where no reversal completes it.

    Examples
    --------
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 3.0, 0.001)
    >>> y = 0.01 * np.sin(2 * np.pi * t)
    >>> r = Record.from_arrays(t, y, 3e4 * y)           # a spring turns at its stiffness
    >>> round(turn_stiffness([r]) / 3e4, 1)
    1.0
    """
    Fa = _force_amplitude(records)
    out = []
    for r in records:
        y, F, s = r.displacement, r.force, np.sign(r.velocity)
        for i in np.flatnonzero(s[1:] * s[:-1] < 0) + 1:
            j = i
            while j < y.size and abs(F[j] - F[i - 1]) < Fa:
                j += 1
            if j < y.size and abs(y[j] - y[i - 1]) > 0:
                out.append(Fa / abs(y[j] - y[i - 1]))
    return float(np.median(out)) if out else math.nan


def plausibility_flags(params: DeviceParams, effects, records, *, force_scale: float = 1.0,
                       at_bound=()) -> tuple[PlausibilityFlag, ...]:
    """Geometry of a fitted device that ``records`` cannot support (module docstring).

    Parameters
    ----------
    params : DeviceParams
        The fitted device.
    effects : sequence of Effect
        Its fitted effects.
    records : sequence of Record
        The calibration records.
    force_scale : float
        Force factor a of the sizing the fit started from (1: as given) [-].
    at_bound : collection of str
        Fitted parameters at a bound.

    Returns
    -------
    tuple of PlausibilityFlag
        Empty when nothing is implausible.
    """
    records = tuple(records)
    if not records:
        return ()
    out = []
    Fa = _force_amplitude(records)
    d_mm = 2e3 * math.sqrt(params.A_p / math.pi)
    Y = max(r.stroke_scale for r in records)
    edge = [n for n in _FLUID if n in set(at_bound)]
    if force_scale > NEAR_FORCE_RATIO and edge:
        out.append(PlausibilityFlag(
            "fluid_unsupported",
            f"piston {d_mm:.3g} mm across (area x{force_scale:.3g} of the device it was sized "
            f"from, for a force amplitude of {Fa:.4g} N at {Y * 1e3:.3g} mm) with "
            f"{', '.join(edge)} at a bound: a fluid device of this size does not draw this "
            "loop", {"piston_diameter [m]": d_mm / 1e3, "force_scale": force_scale,
                     "at_bound": edge, "force_amplitude [N]": Fa}))
    dp = Fa / params.A_p
    if dp < PRESSURE_SHARE * params.p0:
        out.append(PlausibilityFlag(
            "piston_too_large",
            f"piston {d_mm:.3g} mm across: the force amplitude {Fa:.4g} N needs a pressure "
            f"difference of {dp:.3g} Pa, {dp / params.p0:.2%} of the fill pressure (below "
            f"{PRESSURE_SHARE:.0%}): the air ratios and losses are not determined",
            {"piston_diameter [m]": d_mm / 1e3, "pressure_swing [Pa]": dp,
             "fill_pressure [Pa]": params.p0}))
    by = {e.name: e for e in effects}
    comp = by.get("series_compliance")
    if comp is not None and math.isfinite(comp.stiffness_N_per_m):
        ks = comp.stiffness_N_per_m
        kt = turn_stiffness(records)
        K = max(abs(first_harmonic_stiffness(r)) for r in records)
        if math.isfinite(kt) and ks < kt and ks < 2 * K:
            out.append(PlausibilityFlag(
                "series_softer_than_loop",
                f"series stiffness {ks:.3g} N/m below the loop's own turn stiffness "
                f"{kt:.3g} N/m, with |K*| {K:.3g} N/m ({K / ks:.0%} of the stroke in the "
                "spring): the spring draws the loop's turn (a dead band or pre-sliding?)",
                {"series_stiffness [N/m]": ks, "turn_stiffness [N/m]": kt,
                 "|K*| [N/m]": K}))
    for name in ("freeplay", "floating_freeplay"):
        fp = by.get(name)
        if fp is not None and fp.gap_m >= 0.5 * Y:
            out.append(PlausibilityFlag(
                "gap_comparable_to_stroke",
                f"{name} gap {fp.gap_m * 1e3:.3g} mm against a stroke amplitude of "
                f"{Y * 1e3:.3g} mm (at least half): most of each swing moves nothing",
                {"gap [m]": fp.gap_m, "stroke_amplitude [m]": Y}))
    stops = by.get("end_stops")
    if stops is not None:
        peak = max(float(np.max(np.abs(r.displacement - r.offset))) for r in records)
        c = stops.clearance_m
        if c >= params.stroke_limit or c >= peak:
            where = "the chamber end" if c >= params.stroke_limit else "the largest stroke"
            out.append(PlausibilityFlag(
                "end_stops_unsupported",
                f"end-stop clearance {c * 1e3:.3g} mm beyond {where} ({peak * 1e3:.3g} mm "
                f"stroke, chamber {params.stroke_limit * 1e3:.3g} mm): the record never "
                "touches them", {"clearance [m]": c, "peak_stroke [m]": peak,
                                 "chamber_length [m]": params.stroke_limit}))
    return tuple(out)
