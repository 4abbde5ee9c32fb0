"""The valved viscous start: the dyno's two-slope map drawn by the family's own device.

A building's fluid-viscous damper (F = C |v|^a sgn v, a < 1), a vehicle damper (bleed below
the knee, blow-off above it) and a Bingham damper at constant field (a yield, then a viscous
slope) all draw a force-velocity curve that bends: steep at low speed, flatter above a
knee, per direction.  The fluid start draws it with a device sized to the loop whose
channel loss is linear and quadratic (a curve that steepens), the viscous start with one
slope, the friction start with a step; none has a knee.  The two-slope map
(:func:`~liquidamp.analysis.measured.reference_models.fit_two_slope`) that the physics model
must beat has.

The family draws it too: the fluid device with a stiff air spring (the viscous start's
device) is a dashpot of laminar loss c = c1 A_p^2, and a ``digressive_valve`` beside its
channel (:class:`~liquidamp.device.effects_damper.DigressiveValve`) opens at a cracking
pressure p_d per direction, so the force-velocity curve has two slopes per direction with
the knee at v_d = p_d A_p / c (:meth:`DigressiveValve.from_knees`, the dashpot limit);
``asymmetric_loss`` gives rebound its own bleed (rebound_ratio r = c_lo- / c_lo+).  So the
``valved`` start is the map's seven numbers in the family's terms:

* the map fitted on the calibration records (least squares, knees on the speed quantiles):
  F0, c_lo+, c_hi+, v_k+, c_lo-, c_hi-, v_k-;
* the device of the viscous start (:func:`~liquidamp.analysis.measured.device_class.
  fluid_matched`) carrying the bleed: K'' = c_lo+ w, its air stiff (K' at
  :data:`~liquidamp.analysis.measured.device_class.VISCOUS_FLOOR` of that |K|: a dashpot's
  loop has no stiffness, but its air cannot be rigid), the quadratic loss at
  :data:`~liquidamp.analysis.measured.device_class.QUADRATIC_SHARE` of its damping;
* the valves from the knees and slopes on the device's own laminar loss and piston area, the
  rebound bleed by ``asymmetric_loss``, and a ``force_offset`` at F0.

A digressive valve only lowers the slope above its knee: where the map's high slope is the
steeper (a progressive curve: the quadratic loss's, which the fluid start has), that
direction's valve starts shut (its conductance at the catalogue's least).  Varied: c1, the
offset, the rebound ratio and the valves' four parameters (seven, the map's count); the air
and the quadratic loss held (the start is the map, not a fluid device in disguise).  It is
one of the structurally different starts of
:func:`~liquidamp.analysis.measured.device_class.calibrate_by_class` and competes on the
data as they do (held-out records, then the effective-sample BIC with its seven parameters
paid for), so where the loop is a fluid device's or a friction damper's, their starts win.

References
----------
.. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5 and 8 (bleed,
   blow-off valves, knees).
.. [2] M. D. Symans et al., "Energy dissipation systems for seismic applications", J.
   Struct. Eng. 134(1), 2008 (fluid-viscous dampers, F = C |v|^a).
.. [3] B. F. Spencer Jr., S. J. Dyke, M. K. Sain, J. D. Carlson, "Phenomenological model of a
   magnetorheological damper", J. Eng. Mech. 123(3), 1997 (Bingham model).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.class_start import (
    QUADRATIC_SHARE,
    VISCOUS_FLOOR,
    ClassStart,
    _offset_spec,
    _reference,
    fluid_matched,
)
from liquidamp.analysis.measured.loop_reading import LoopReading
from liquidamp.analysis.measured.reference_models import fit_two_slope
from liquidamp.device.effects import EFFECTS
from liquidamp.device.effects_damper import DigressiveValve
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError

__all__ = ["MapReading", "read_map", "valved_start"]


def _stiff(p: DeviceParams, rate: float) -> tuple[DeviceParams, str]:
    """``p`` with its air stiff and its channel inertance small at ``rate`` [rad/s]: the
    Maxwell unit's K' = (w c)^2 / k_D at VISCOUS_FLOOR of w c there (k_D = c w / VISCOUS_FLOOR,
    c = c1 A_p^2 the bleed; the air ratios scaled together, the liquid's own compressibility
    the stiffest), and the channel inertance's b_L w at most VISCOUS_FLOOR of the bleed's c
    there (its force b_L w^2 Y at reversal at most that share of the knee's c v_k; S_t scaled
    down where it is larger).  Returns the device and what was done."""
    c = p.c1 * p.A_p ** 2
    k_target = c * rate / VISCOUS_FLOOR
    how = ""
    if p.k_D < k_target:
        lo, hi = 1e-9, 1.0  # factors on both air ratios (k_D falls as the air grows)
        if p.scaled(inv_gamma1=lo, inv_gamma2=lo).k_D < k_target:
            f = lo
        else:
            for _ in range(80):
                mid = math.sqrt(lo * hi)
                if p.scaled(inv_gamma1=mid, inv_gamma2=mid).k_D > k_target:
                    lo = mid
                else:
                    hi = mid
            f = math.sqrt(lo * hi)
        p = p.scaled(inv_gamma1=f, inv_gamma2=f)
        how += f", air x{f:.3g} (k_D {p.k_D:.3g} N/m)"
    b_max = VISCOUS_FLOOR * c / rate
    if p.b_L > b_max > 0:
        f = b_max / p.b_L
        p = p.scaled(S_t=f)
        how += f", S_t x{f:.3g} (inertance small at {rate:.3g} rad/s)"
    return p, how


@dataclass(frozen=True)
class MapReading:
    """The two-slope map of the calibration records (:func:`read_map`), in SI.

    Attributes
    ----------
    offset : float
        F0 [N].
    low_compression, high_compression : float
        Slopes below and above the compression knee (v > 0) [N s/m].
    knee_compression : float
        The compression knee [m/s].
    low_rebound, high_rebound, knee_rebound : float
        The same for rebound (v < 0) [N s/m], [N s/m], [m/s].
    """

    offset: float
    low_compression: float
    high_compression: float
    knee_compression: float
    low_rebound: float
    high_rebound: float
    knee_rebound: float


def read_map(records) -> MapReading:
    """The two-slope force-velocity map of ``records`` (least squares, knees on the speed
    quantiles; :func:`~liquidamp.analysis.measured.reference_models.fit_two_slope`).

    Parameters
    ----------
    records : sequence of Record
        The calibration records.

    Returns
    -------
    MapReading
        F0 [N], low and high slopes [N s/m] and knee [m/s] of compression (v > 0) and of
        rebound (v < 0).

    Raises
    ------
    ParameterError
        Where a slope is not positive (no bleed a valve could sit beside, or a force that
        falls with the speed) or a knee is not finite; the start cannot be built.

    Examples
    --------
    >>> import numpy as np
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 2, 0.001)
    >>> y = 0.01 * np.sin(2 * np.pi * 2 * t)
    >>> v = np.gradient(y, t)
    >>> F = np.where(v > 0, 4e4 * np.minimum(v, 0.05) + 1e4 * np.maximum(v - 0.05, 0),
    ...              3e4 * np.maximum(v, -0.05) + 5e3 * np.minimum(v + 0.05, 0))
    >>> m = read_map([Record.from_arrays(t, y, F)])
    >>> round(m.low_compression, -3), round(m.knee_compression, 2)  # knees on a speed grid
    (41000.0, 0.05)
    """
    p = fit_two_slope(tuple(records)).parameters
    m = MapReading(*(float(p[k]) for k in (
        "F0 [N]", "c_low_compression [N s/m]", "c_high_compression [N s/m]",
        "knee_compression [m/s]", "c_low_rebound [N s/m]", "c_high_rebound [N s/m]",
        "knee_rebound [m/s]")))
    for side in ("compression", "rebound"):
        c, v_k = getattr(m, f"low_{side}"), getattr(m, f"knee_{side}")
        if not (math.isfinite(c) and c > 0):
            raise ParameterError(f"valved start: the map's {side} low-speed slope is "
                                 f"{c:.4g} N s/m, not positive (no bleed to set a valve "
                                 "beside)")
        c_hi = getattr(m, f"high_{side}")
        if not (math.isfinite(c_hi) and c_hi > 0):
            raise ParameterError(f"valved start: the map's {side} high-speed slope is "
                                 f"{c_hi:.4g} N s/m, not positive (a force that falls with "
                                 "the speed: no valve opens so)")
        if not (math.isfinite(v_k) and v_k >= 0):
            raise ParameterError(f"valved start: the map's {side} knee is {v_k!r} m/s "
                                 "(too few samples that way to place one)")
    return m


def valved_start(base: DeviceParams, effects, records, reading: LoopReading) -> ClassStart:
    """The valved viscous start (module docstring): the viscous start's device carrying the
    map's bleed, ``digressive_valve`` from the map's knees and slopes, ``asymmetric_loss``
    for the rebound bleed and ``force_offset`` at the map's F0.

    Parameters
    ----------
    base : DeviceParams
        The device given (stretched to the stroke, then similar-sized to the bleed).
    effects : sequence of Effect
        The caller's effects (a valve, rebound ratio or offset among them is replaced).
    records : sequence of Record
        The calibration records.
    reading : LoopReading
        :func:`~liquidamp.analysis.measured.device_class.read_loop` of ``records`` (the
        first-harmonic K* per record).

    Returns
    -------
    ClassStart
        ``name`` 'valved'; its spec varies c1, the offset, the rebound ratio and the valves.

    Raises
    ------
    ParameterError
        Where the map has no positive bleed (:func:`read_map`) or the caller's effects hold a
        ``relief_valve`` (the same flow path).
    """
    records = tuple(records)
    if any(e.name == "relief_valve" for e in effects):
        raise ParameterError("valved start: the effects hold a relief_valve, the path the "
                             "digressive valves take")
    m = read_map(records)
    c_lo = m.low_compression
    # the bleed's reversal lasts about 2 v_k / (w^2 Y): a steep bleed turns within a small
    # share of the cycle, and an air spring or a channel inertance that lags there draws a
    # loop the map has not; so the device is the viscous start's carrying the bleed, its
    # air stiff and its inertance small at the reversal rate w_r = w v_peak / v_k
    targets, rates = [], []
    knee = min(m.knee_compression, m.knee_rebound)
    for r in records:
        w = 2 * math.pi * r.frequency
        v_peak = float(np.max(np.abs(r.velocity)))
        rates.append(w * max(1.0, v_peak / knee) if knee > 0 else w)
        targets.append(complex(VISCOUS_FLOOR * c_lo * w, c_lo * w))
    p, how = fluid_matched(_reference(base, records), records, targets,
                           quadratic_share=QUADRATIC_SHARE)
    # the bleed is the map's low slope: c1 A_p^2 = c_lo+ (the linear match above shares the
    # first harmonic's damping with the quadratic loss and the inertance)
    f_c = c_lo / (p.c1 * p.A_p ** 2)
    p = p.scaled(c1=f_c)
    p, stiff = _stiff(p, max(rates))
    stiff = f", c1 x{f_c:.3g} (bleed {c_lo:.4g} N s/m)" + stiff
    p = p.replace(name=f"{base.name or 'device'} valved start ({how}{stiff})")
    c = p.c1 * p.A_p ** 2  # the device's laminar bleed [N s/m]
    lo_r, hi_r = EFFECTS["asymmetric_loss"].bounds["rebound_ratio"]
    ratio = min(max(m.low_rebound / c_lo, lo_r), hi_r)
    scale = c / c_lo  # the map's slopes on the device's bleed
    c_r = c * ratio  # the rebound bleed; a progressive side's valve starts shut (G = 0)
    valve = DigressiveValve.from_knees(
        c, m.knee_compression, min(m.high_compression * scale, c),
        c_r, m.knee_rebound, min(m.high_rebound * scale, c_r), area_m2=p.A_p)
    present = {e.name: e for e in effects}
    made = {"force_offset": (present.get("force_offset") or EFFECTS["force_offset"]()).replace(
                offset_N=m.offset),
            "asymmetric_loss": EFFECTS["asymmetric_loss"](ratio),
            "digressive_valve": valve}
    effs = tuple(made.get(e.name, e) for e in effects) + tuple(
        e for n, e in made.items() if n not in present)
    why = (f"the two-slope map read: compression c {c_lo:.4g} -> {m.high_compression:.4g} "
           f"N s/m at {m.knee_compression:.3g} m/s, rebound c {m.low_rebound:.4g} -> "
           f"{m.high_rebound:.4g} N s/m at {m.knee_rebound:.3g} m/s, F0 {m.offset:.4g} N; "
           f"bleed {c:.4g} N s/m (rebound x{ratio:.3g}), digressive valves cracking at "
           f"{valve.compression_cracking_Pa:.3g} / {valve.rebound_cracking_Pa:.3g} Pa "
           f"({how}{stiff})")
    # the map's seven numbers: c1, the offset, the rebound ratio, the valves; air and c2 held
    return ClassStart("valved", p, effs, _offset_spec(effs, records), why)
