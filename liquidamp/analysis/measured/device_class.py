"""Starts that find the device class: fluid, friction, viscous or valved, chosen on the data.

A calibration that starts from the fluid device alone can only explain a loop
by the fluid: a friction damper's 13 kN rectangle is then drawn by a sized
fluid device of a 338 mm piston, air ratios and losses at their bounds, and
nothing afterwards finds the friction.  :func:`calibrate_by_class` therefore
calibrates four structurally different starts cheaply, chooses one on the
data (:func:`choose_start`) and continues only that one.

The starts (every number read off the records, :func:`read_loop`)
    ``fluid``
        The device sized to the records and its air ratios and losses matched
        to the first-harmonic K', K'' (:mod:`~liquidamp.analysis.measured.start`;
        the calibration as it always was).
    ``friction``
        A friction damper: smooth friction (LuGre/Dahl,
        :class:`~liquidamp.device.effects.SmoothFriction`) with the loop's
        friction level F_c, pre-sliding stiffness sigma0 = F_c / dy0 and a
        parallel spring k read off the loop by least squares,
        F ~ F0 + k (y - mean y) + F_c z(t), z the Dahl/LuGre (n = 1) bristle
        state of pre-sliding stroke dy0 driven by the recorded stroke, dy0 on a
        log grid (:func:`read_loop`: a slanted reversal is pre-sliding, a
        sloped loop a spring, read but not part of the start: a parallel
        spring is the ``elastomer`` effect's, which the diagnosis adds where
        the residual asks for it).
        Little fluid: the fluid device, similar to the sized one, is matched to
        K' = K'' = the record's noise floor
        (:func:`~liquidamp.analysis.measured.record_quality.noise_floor`, as an
        NRMSE; :data:`FLUID_FLOOR` where lower) times |K*| (a linear loss: the
        quadratic one at :data:`QUADRATIC_SHARE`): a fluid force at the noise
        level is the most the record cannot resolve, and it keeps the device
        model whole (pressures, chambers) for the effects the diagnosis may
        add.  The fluid is held there: only the friction's parameters are
        fitted (the start is a friction damper, not a fluid device in
        disguise).  Where the noise floor is above :data:`FLUID_FLOOR` the
        start is also calibrated with the fluid at :data:`FLUID_FLOOR`
        (negligible) and :func:`choose_start` picks the level on the data
        (:func:`fluid_levels`: one record cannot tell a small fluid force
        from the friction's shape, records at other rates can).  So a fluid
        device with some friction is the fluid start's (the diagnosis adds the
        friction), a friction damper the friction start's.
    ``viscous``
        A viscous damper with a force offset, F = c v + F0: the fluid device
        matched to K = i K'' with a stiff air spring (K' at
        :data:`VISCOUS_FLOOR`, 5 %, of |K*|: a dashpot's loop has no
        stiffness, but its air cannot be rigid) and the quadratic loss at
        :data:`QUADRATIC_SHARE` (5 %) of its describing-function damping (so
        c = K'' / w is the linear loss, read off the first harmonic's loss
        part), and a ``force_offset`` at the records' mean force F0.  Only c
        (the c1 multiplier) and F0 are fitted: the start is the two-parameter
        line F = c v + F0 in the family's terms, not a fluid device in disguise.

    ``valved``
        A valved viscous damper (:mod:`~liquidamp.analysis.measured.start_valved`): the
        dyno's two-slope force-velocity map per direction, read off the records by least
        squares (:func:`~liquidamp.analysis.measured.reference_models.fit_two_slope`), drawn
        by the viscous start's device carrying the map's low-speed slope as its bleed, with
        ``digressive_valve`` from the knees and high-speed slopes, ``asymmetric_loss`` for the
        rebound bleed and ``force_offset`` at the map's F0; its air stiff and its channel
        inertance small at the bleed's reversal rate.  Seven parameters vary (the map's
        count): a power-law building damper, a vehicle damper's bleed and blow-off, and a
        Bingham damper at constant field (a steep bleed, then a viscous slope) are its.

Each start is calibrated with ``max_nfev`` :data:`START_NFEV` (its multipliers
start at 1 on its own device, its effect parameters at the values read off);
the chosen one is continued with the caller's budget (see below: only
continued fits can win).

The choice (:func:`choose_start`)
    On the calibration records: the effective-sample BIC,
    N_eff ln RSS + k ln N_eff, with N_eff from the residuals' correlation
    times (:func:`~liquidamp.analysis.measured.selection.effective_samples`,
    the smallest over the starts) and k the varied parameters (4 for the
    fluid start, 2 for the friction and the viscous starts, 7 for the valved), so that the
    parameters are paid for.  With validation records,
    a start whose fit another start dominates -- predicts the pooled held-out
    records better by more than :data:`HELD_OUT_TOLERANCE` (5 %) without being
    worse by more than 5 % on any record, calibration or held-out, and without a
    BIC higher by :data:`BIC_POSITIVE` or more (its parameters paid for) -- cannot
    win: no start wins that is worse held-out than one at least as good on
    the calibration data.  A start better held-out by more than 5 % also wins
    where the BIC leader's advantage on the calibration records is not
    strong evidence (less than :data:`BIC_STRONG`, 10), and the fluid start
    (the family's own) gives way only to a start that predicts the held-out
    records at least as well and has positive evidence (BIC lower by more than
    :data:`BIC_POSITIVE`, 2, or held-out better by 5 %).  Where the BIC
    advantage is strong (a start better held-out but far worse on the
    calibration record: one record does
    not identify a fluid device's nonlinearity, and a start of another class
    can extrapolate better by chance) the BIC leader stays and the result says
    so (``start["held_out_note"]`` and a warning).  Only continued fits can win:
    the BIC leader of the cheap fits and the fluid start (the family's own,
    so that another class must beat it converged) are continued, then any
    start whose cheap held-out NRMSE beats every continued fit's by more than
    the tolerance.
    The diagnosis can call :func:`choose_start` on any set of fits of the
    same records.

Records with a control input
    Where every record carries a voltage or current channel, the ``field`` start (fitted
    with the caller's budget) is the class without the others being fitted: only its model
    reads the input, and each other start would cost a fit of its own only to say how much
    worse a model that ignores the input does.  That comparison is made on the same device
    instead: :func:`input_held` refits it with a constant yield (the input's share removed,
    the level at the mean input), reported as ``start["without_input"]``.  Where the field
    start cannot be calibrated, the other starts are chosen among as above.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C (friction F_f sign(v), 30 N).
.. [2] C. Canudas de Wit, H. Olsson, K. J. Astrom, P. Lischinsky, "A new model for
   control of systems with friction", IEEE TAC 40(3), 1995 (LuGre).
.. [3] G. Schwarz, "Estimating the dimension of a model", Ann. Stat. 6(2), 1978 (BIC).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from liquidamp.analysis.measured.class_choice import (
    BIC_POSITIVE,
    BIC_STRONG,
    DEFAULT_CLASS,
    HELD_OUT_TOLERANCE,
    StartOutcome,
    choose_start,
)
from liquidamp.analysis.measured.class_start import (  # re-exported
    QUADRATIC_SHARE,
    VISCOUS_FLOOR,
    ClassStart,
    _offset_spec,
    _reference,
    fluid_matched,
)
from liquidamp.analysis.measured.fit_spec import FitSpec
from liquidamp.analysis.measured.loop_reading import LoopReading, _bristle, read_loop
from liquidamp.analysis.measured.plausibility import plausibility_flags
from liquidamp.analysis.measured.record_quality import noise_floor
from liquidamp.analysis.measured.reference_models import fit_two_slope
from liquidamp.analysis.measured.start_valved import valved_start
from liquidamp.device.effects import EFFECTS
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, ParameterError, PressureError

__all__ = ["DEVICE_CLASSES", "FLUID_FLOOR", "VISCOUS_FLOOR", "QUADRATIC_SHARE", "START_NFEV",
           "HELD_OUT_TOLERANCE", "BIC_STRONG", "BIC_POSITIVE", "DEFAULT_CLASS", "LoopReading",
           "read_loop", "ClassStart",
           "fluid_matched", "friction_start", "fluid_levels", "viscous_start", "field_input",
           "field_start",
           "StartOutcome", "choose_start",
           "calibrate_by_class", "input_held"]

#: The structurally different starts, in the order they are tried (``field`` only where
#: every record carries a control input, :func:`field_input`).
DEVICE_CLASSES = ("fluid", "friction", "viscous", "valved", "field")
#: Control inputs a field-controlled (MR/ER) device follows, in the order they are read.
FIELD_CHANNELS = ("voltage", "current")
#: Field lag rates eta tried by the field start [1/s] (MR field time constants of a few to
#: tens of ms, Spencer et al. 1997); its m_eps as a share of the RMS mass flow [-] (fitted).
FIELD_RATES = tuple(float(x) for x in np.geomspace(10.0, 1000.0, 11))
FIELD_SMOOTHING = 0.02
#: Least share of |K*| the fluid keeps in the friction start (each of K', K''), where the
#: record's noise floor (as an NRMSE) is lower [-].
FLUID_FLOOR = 1e-3
#: Evaluation budget of each start's cheap calibration.
START_NFEV = 20
_FRICTION = ("smooth_friction", "coulomb_friction")


# ---------------------------------------------------------------------------
# the starts


def friction_start(base: DeviceParams, effects, records, reading: LoopReading,
                   fluid_share: float | None = None) -> ClassStart:
    """The friction damper start (module docstring): smooth friction at the loop's level,
    a fluid held at the record's noise floor (``fluid_share`` None), or at ``fluid_share``
    of |K*| in each of K', K'' [-] (:data:`FLUID_FLOOR`: a friction damper with negligible
    fluid, :func:`fluid_levels`)."""
    if fluid_share is not None and not (0.0 < fluid_share < 1.0):
        raise ParameterError(f"friction_start: fluid_share must be in (0, 1) [-] (a share of "
                             f"|K*|), got {fluid_share!r}")
    Fc = max(reading.friction, 1e-3)
    dy0 = reading.presliding
    lo, hi = EFFECTS["smooth_friction"].bounds["stiffness_N_per_m"]
    sigma0 = min(max(Fc / dy0, lo), hi)
    present = {e.name: e for e in effects}
    name = next((n for n in _FRICTION if n in present), "smooth_friction")
    fr = present.get(name) or EFFECTS[name]()
    fr = fr.replace(force_N=Fc, **({"stiffness_N_per_m": sigma0}
                                    if name == "smooth_friction" else {}))
    targets = []
    for K, r in zip(reading.stiffnesses, records, strict=True):
        share = (max(noise_floor(r).nrmse, FLUID_FLOOR) if fluid_share is None
                 else fluid_share)
        targets.append(complex(share * abs(K), share * abs(K)))
    p, how = fluid_matched(_reference(base, records), records, targets,
                           quadratic_share=QUADRATIC_SHARE)
    p = p.replace(name=f"{base.name or 'device'} friction start ({how})")
    effs = tuple(fr if e.name == name else e for e in effects) + (
        () if name in present else (fr,))
    # a friction damper's parameters: the friction's; the fluid held
    spec = FitSpec.default(vary=(), effects=effs)
    why = (f"{name} {Fc:.4g} N ({reading.friction_source})"
           + (f", sigma0 {sigma0:.3g} N/m (pre-sliding stroke {dy0 * 1e3:.3g} mm)"
              if name == "smooth_friction" else "")
           + ("; little fluid: K' and K'' at the noise floor" if fluid_share is None else
              f"; negligible fluid: K' and K'' at {fluid_share:.2g} of |K*|")
           + f", held ({how})")
    return ClassStart("friction", p, effs, spec, why)


def fluid_levels(records) -> tuple:
    """The fluid levels of the friction start, as shares of |K*| [-] (None: the noise floor).

    A friction damper may hold some rate-dependent damping (a fluid, a viscous seal) or
    none; one record at one rate cannot tell a small fluid force from the friction's shape
    (both are odd in the velocity), records at other rates can.  So the friction start is
    calibrated with the fluid at the calibration records' noise floor (the most they cannot
    resolve) and, where that floor is above :data:`FLUID_FLOOR`, with the fluid at
    :data:`FLUID_FLOOR` (negligible), and :func:`choose_start` chooses between them as
    between classes (held-out records first, then the effective-sample BIC).

    Examples
    --------
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 8.0, 0.002)
    >>> y = 0.01 * np.sin(2 * np.pi * t)
    >>> F = 500.0 * np.tanh(np.gradient(y, t) / 1e-3)
    >>> F = F + 50.0 * np.random.default_rng(1).standard_normal(t.size)  # floor ~0.1
    >>> fluid_levels([Record.from_arrays(t, y, F)])
    (None, 0.001)
    """
    floor = max(noise_floor(r).nrmse for r in records)
    return (None, FLUID_FLOOR) if floor > FLUID_FLOOR else (None,)


def viscous_start(base: DeviceParams, effects, records, reading: LoopReading) -> ClassStart:
    """The viscous damper with a force offset (module docstring)."""
    targets = []
    for K in reading.stiffnesses:
        floor = VISCOUS_FLOOR * abs(K)
        targets.append(complex(floor, max(K.imag, floor)))  # a dashpot: K' at the floor
    p, how = fluid_matched(_reference(base, records), records, targets,
                           quadratic_share=QUADRATIC_SHARE)
    p = p.replace(name=f"{base.name or 'device'} viscous start ({how})")
    present = {e.name: e for e in effects}
    off = (present.get("force_offset") or EFFECTS["force_offset"]()).replace(
        offset_N=reading.mean_force)
    effs = tuple(off if e.name == "force_offset" else e for e in effects) + (
        () if "force_offset" in present else (off,))
    c = [K.imag / (2 * math.pi * r.frequency) for K, r in zip(reading.stiffnesses, records,
                                                             strict=True)]
    why = (f"linear loss c = K''/w ({', '.join(f'{x:.4g}' for x in c)} N s/m), "
           f"offset {reading.mean_force:.4g} N ({how})")
    # a viscous damper's two parameters, c and F0: the air and the quadratic loss held
    return ClassStart("viscous", p, effs, _offset_spec(effs, records), why)


def field_input(records) -> str | None:
    """The control input every record carries (``voltage``, else ``current``), or None."""
    for c in FIELD_CHANNELS:
        if all(c in r.channels for r in records):
            return c
    return None


def _lagged(u, dt: float, eta: float):
    """u through the first-order lag du_f/dt = eta (u - u_f), exact for u held over each
    sample, settled on u[0] at the start."""
    from scipy.signal import lfilter

    a = math.exp(-eta * dt)
    out, _ = lfilter([1.0 - a], [1.0, -a], u, zi=[a * u[0]])
    return out


def _air_factor(p: DeviceParams, k_target: float) -> float | None:
    """The factor on both air ratios that gives the device the air stiffness k_D =
    ``k_target`` [N/m] (bisection in log; k_D falls as the air grows), or None where the
    bounds of :meth:`FitSpec.default` (0.05 to 20) cannot reach it."""
    def k(f):
        return p.scaled(inv_gamma1=f, inv_gamma2=f).k_D

    lo, hi = 0.05, 20.0
    if not k(hi) <= k_target <= k(lo):
        return lo if k_target > k(lo) else hi
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if k(mid) > k_target:
            lo = mid
        else:
            hi = mid
    return math.sqrt(lo * hi)


def field_start(base: DeviceParams, effects, records, reading: LoopReading) -> ClassStart:
    """A field-controlled (MR/ER) device: the fluid with ``field_yield`` on the channel.

    Read off the records by least squares, F ~ F0 + k y + c v + c_q v|v| + (A + B u_f) z(t):
    z the Dahl bristle state of :func:`read_loop` (a yield that opposes the flow, smoothed
    at reversal) and u_f the control input through the field lag (:func:`_lagged`), the
    pre-sliding stroke dy0 and the lag rate on grids (:data:`FIELD_RATES`), the least
    residual winning.  The device is the starting one stretched to the stroke (its piston
    kept: any piston carries the force at its own pressures), filled at p0 = max(p0,
    max |F - F0| / A_p) so that its low-pressure chamber keeps at least half the filling
    pressure under the records' force (a field-controlled damper is pressurized: the yield
    drop would otherwise pull a chamber to zero), its air giving the pre-yield stiffness
    k_D = (A + B mean u) / dy0 (the yield force builds up over dy0 by compressing the
    fluid), its channel's losses c1 = c / A_p^2, c2 = c_q / A_p^3 read off the line, with
    the yield drops dp_y0 = A / A_p, dp_y1 = B / A_p, the lag rate read and m_eps =
    :data:`FIELD_SMOOTHING` of the records' RMS mass flow.  The air ratios, losses, the
    channel's inertance and the yield's four parameters are fitted.

    Raises
    ------
    ParameterError
        Where a record carries neither a voltage nor a current.
    """
    from liquidamp.device.effects_field import FieldYield

    c = field_input(records)
    if c is None:
        raise ParameterError("the field start needs a voltage or current channel in every "
                             "record")
    Y = max(r.stroke_scale for r in records)
    deltas = np.geomspace(1e-3 * Y, Y, 13)
    zs = [_bristle(r, deltas) for r in records]
    F = np.concatenate([r.force for r in records])
    v = np.concatenate([r.velocity for r in records])
    base_cols = np.column_stack((
        np.ones_like(F), np.concatenate([r.displacement - r.offset for r in records]),
        v, v * np.abs(v)))
    # the line's columns projected out once (Frisch-Waugh-Lovell: the residual sum of squares
    # of the full regression is that of the yield's two columns on the projected force), so
    # that each (eta, dy0) of the grid costs two columns, not a least-squares solve
    Qb, _ = np.linalg.qr(base_cols)
    Fr = F - Qb @ (Qb.T @ F)
    best = None
    for eta in FIELD_RATES:
        uf = np.concatenate([_lagged(r.channels[c], float(np.median(np.diff(r.time))), eta)
                             for r in records])
        for j, _ in enumerate(deltas):
            z = np.concatenate([q[j] for q in zs])
            Z = np.column_stack((z, uf * z))
            Z -= Qb @ (Qb.T @ Z)
            b, *_ = np.linalg.lstsq(Z, Fr, rcond=None)
            rss = float(np.sum((Z @ b - Fr) ** 2))
            if best is None or rss < best[0]:
                best = (rss, eta, j)
    _, eta, j = best
    dy0 = deltas[j]
    uf = np.concatenate([_lagged(r.channels[c], float(np.median(np.diff(r.time))), eta)
                         for r in records])
    z = np.concatenate([q[j] for q in zs])
    coef, *_ = np.linalg.lstsq(np.column_stack((base_cols, z, uf * z)), F, rcond=None)
    F0, k, cv, cq, A, B = coef
    # the device stretched to the stroke (its piston kept: any piston carries the force at
    # its own pressures); its air from the pre-yield stiffness: the yield force builds up
    # over the pre-sliding stroke dy0 by compressing the fluid, k_D = (A + B mean u) / dy0
    p = _reference(base, records)
    f_peak = float(np.max(np.abs(F - F0)))
    p = p.replace(p0=max(p.p0, f_peak / p.A_p))
    how = f"pre-sliding stroke {dy0 * 1e3:.3g} mm"
    u_mean = float(np.mean(np.concatenate([r.channels[c] for r in records])))
    k_target = max(float(A) + float(B) * u_mean, 1e-6) / dy0
    f_air = _air_factor(p, k_target)
    if f_air is not None:
        p = p.scaled(inv_gamma1=f_air, inv_gamma2=f_air)
        how += f", air x{f_air:.3g} (k_D {p.k_D:.3g} N/m)"
    # the channel's losses read off the line: c v + c_q v|v| = A_p (c1 Q + c2 Q|Q|), Q = A_p v
    c1 = max(float(cv), 0.0) / p.A_p ** 2
    c2 = max(float(cq), 0.0) / p.A_p ** 3
    if c1 > 0.0 or c2 > 0.0:
        p = p.replace(c1=max(c1, 1e-3 * p.c1), c2=max(c2, 1e-3 * p.c2))
        how += f", losses read: c1 {p.c1:.3g}, c2 {p.c2:.3g}"
    p0 = p.p0
    p = p.replace(name=f"{base.name or 'device'} field start ({how}, p0 "
                  f"{p0:.3g} Pa)")
    Fa = float(np.sqrt(np.mean((F - F.mean()) ** 2)))
    dp0 = max(float(A), 0.01 * Fa) / p.A_p
    dp1 = max(float(B), 0.0) / p.A_p
    v_rms = float(np.sqrt(np.mean(np.concatenate([r.velocity for r in records]) ** 2)))
    meps = FIELD_SMOOTHING * p.rho0 * p.A_p * max(v_rms, 1e-12)
    fy = FieldYield(dp0, dp1, float(eta), meps, input=c)
    effs = tuple(e for e in effects if e.name != "field_yield") + (fy,)
    # the air ratios, losses and inertance (the channel is the device's own: an MR valve's is
    # not the preset's), the yield's drops, lag rate and smoothing
    spec = FitSpec.default(vary=("inv_gamma1", "inv_gamma2", "c1", "c2", "S_t"),
                           effects=effs).with_effect(fy, keys=("smoothing_flow_kg_per_s",))
    why = (f"field_yield on the {c}: A_p dp_y = {A:.4g} N + {B:.4g} N per unit {c}, lag "
           f"rate {eta:.3g} 1/s (least squares on F0 + k y + c v + c_q v|v| + (A + B u_f) "
           "z), m_eps "
           f"{meps:.3g} kg/s; fluid from k {k:.4g} N/m, c {cv:.4g} N s/m, c_q {cq:.4g} "
           "N s^2/m^2, filled at "
           f"{p0:.3g} Pa (max |F - F0| / A_p) ({how})")
    return ClassStart("field", p, effs, spec, why)


def _map_can_lead(records, fluid) -> None:
    """Refuse (ParameterError) the valved start where the two-slope map it draws fits the
    calibration records worse than the fluid start's cheap fit already does.

    The valved start is the dyno's two-slope force-velocity map drawn by the device, with
    the map's own seven parameters varied and the air held stiff, so its fit lands near
    the map's (on session 13's outside records, held out from 8 % better to 40 % worse than
    the map; `runs/s13_valved/`).  Where the fluid start's cheap fit is already below the
    map's calibration NRMSE, the valved start, landing near the map with more parameters,
    is expected to have the higher BIC, and then cannot dominate it
    (:func:`~.class_choice.choose_start`): its fit (each evaluation a stiff device) is not
    run, and it is reported as a start not built, with both figures (a screen, like the
    published designs' in :mod:`~.class_revisit`: the 200 Hz bench's leakage record 3.7 ->
    2.5 s, no choice changed on the shared or outside records).
    Where the fluid start failed, the valved start is fitted."""
    if fluid is None or isinstance(fluid, BaseException):
        return
    two = fit_two_slope(tuple(records))
    if two.nrmse_calibration > fluid.nrmse_calibration:
        raise ParameterError(
            f"valved start not fitted: the two-slope map it draws fits the calibration "
            f"records at NRMSE {two.nrmse_calibration:.3g}, the fluid start's cheap fit at "
            f"{fluid.nrmse_calibration:.3g} (with more parameters it cannot lead)")


def _friction_fit(fit, params, effects, records, reading, cheap: int, common: dict):
    """The friction start's cheap fit at each fluid level of :func:`fluid_levels`, the level
    chosen by :func:`choose_start` (held-out first, then the effective-sample BIC): the fit
    and its reason (with the level's figures where there was a choice)."""
    levels = fluid_levels(records)
    fits, reasons = {}, {}
    for share in levels:
        label = "noise floor" if share is None else f"{share:.2g} of |K*|"
        try:
            st = friction_start(params, effects, records, reading, fluid_share=share)
            reasons[label] = st.reason
            fits[label] = fit(records, params=st.params, effects=st.effects, spec=st.spec,
                              start="spec", sizing="preset", max_nfev=cheap,
                              device_class="friction", **common)
        except (ConvergenceError, PressureError, ParameterError, ValueError,
                FloatingPointError) as exc:
            if len(levels) == 1:
                raise
            fits[label] = exc
    if len(fits) == 1:
        (label, r), = fits.items()
        return r, reasons[label]
    label, outcomes, _ = choose_start(fits)
    figures = "; ".join(o.describe().replace(" after the cheap fit", "")
                        for o in outcomes)
    return fits[label], (f"{reasons[label]} (fluid level chosen on the data among the noise "
                         f"floor and negligible fluid: {figures})")


def calibrate_by_class(fit, records, validate, *, params: DeviceParams, effects, sizing: str,
                       max_nfev: int, classes=DEVICE_CLASSES, **kwargs):
    """Calibrate each start of ``classes`` cheaply, continue the one chosen (module doc).

    ``fit`` is :func:`~liquidamp.analysis.measured.calibration.calibrate` (passed in, so
    this module does not import it); ``kwargs`` go to every fit (model, options, preroll,
    tol, outliers).  Returns the continued fit with ``device_class`` and ``class_starts``
    set and every start's figures in ``start["classes"]``.
    """
    records, validate, effects = tuple(records), tuple(validate), tuple(effects)
    if len(classes) > 1 and "field" in classes and field_input(records + validate):
        # every record carries a control input: only the field start's model reads it, so it
        # is the class; the starts that do not read it would each cost a fit of their own
        # (every model run marches the whole record) and could only report how much worse a
        # model that ignores the input does, which the input held gives (without_input)
        try:
            return _field_class(fit, records, validate, params=params, effects=effects,
                                sizing=sizing, max_nfev=max_nfev, **kwargs)
        except (ConvergenceError, PressureError, ParameterError, ValueError,
                FloatingPointError):
            classes = tuple(c for c in classes if c != "field")
    cheap = min(START_NFEV, max_nfev) if len(classes) > 1 else max_nfev
    common = dict(validate=validate, warn=False, **kwargs)
    reading = read_loop(records)
    fits, reasons = {}, {}
    for name in classes:
        if name == "field" and field_input(tuple(records) + validate) is None:
            continue  # a field-controlled start only where every record carries its input
        if name == "fluid":  # first: a record the data checks refuse is refused here
            reasons[name] = "the device sized to the records, air and losses from K', K''"
            try:
                fits[name] = fit(records, params=params, effects=effects, spec=None,
                                 start="physics", sizing=sizing, max_nfev=cheap,
                                 device_class="fluid", **common)
            except ConvergenceError as exc:  # no fluid start can be used: try the others
                if len(classes) == 1:
                    raise
                fits[name] = exc
            continue
        try:
            if name == "friction":
                fits[name], reasons[name] = _friction_fit(fit, params, effects, records,
                                                          reading, cheap, common)
                continue
            if name == "valved":
                _map_can_lead(records, fits.get("fluid"))
            make = {"viscous": viscous_start, "valved": valved_start, "field": field_start}[name]
            st = make(params, effects, records, reading)
            reasons[name] = st.reason
            fits[name] = fit(records, params=st.params, effects=st.effects, spec=st.spec,
                             start="spec", sizing="preset", max_nfev=cheap,
                             device_class=name, **common)
        except (ConvergenceError, PressureError, ParameterError, ValueError,
                FloatingPointError) as exc:
            if len(classes) == 1:
                raise
            fits[name] = exc
    if all(isinstance(r, BaseException) for r in fits.values()) and isinstance(
            fits.get("fluid"), ConvergenceError):
        raise ConvergenceError(f"{fits['fluid']}; the friction and viscous starts failed "
                               "too: " + "; ".join(f"{n}: {e}" for n, e in fits.items()
                                                   if n != "fluid"))
    nfev = sum(r.nfev for r in fits.values() if not isinstance(r, BaseException))
    # the BIC leader of the cheap fits is continued; a start whose cheap held-out error
    # beats every continued fit's by more than the tolerance is continued too; the choice is
    # then made among the continued fits (cheap fits are not converged: they cannot win)
    pool, cont = dict(fits), {}

    def extend(name):
        nonlocal nfev
        r = fits[name]
        if not r.converged and len(classes) > 1:
            r = fit(records, params=r.start_params, effects=r.effects, spec=r.spec,
                    start="spec", sizing="preset", max_nfev=max_nfev, device_class=name,
                    **common)
            nfev += r.nfev
        cont[name] = pool[name] = r

    extend(choose_start(fits, math.inf)[0])
    if "fluid" in fits and "fluid" not in cont and not isinstance(fits["fluid"], BaseException):
        extend("fluid")  # the family's own start is judged converged, never cheap
    while validate:
        best = min(r.nrmse_validation for r in cont.values())
        rivals = {n: r for n, r in fits.items() if n not in cont
                  and not isinstance(r, BaseException)
                  and r.nrmse_validation * (1 + HELD_OUT_TOLERANCE) < best}
        if not rivals:
            break
        extend(choose_start(rivals, math.inf)[0])
    chosen, outcomes, note = choose_start(pool, reasons=reasons, eligible=tuple(cont))
    without = None
    if chosen == "field":  # the best fit that does not read the input, converged, beside it
        rest = {n: r for n, r in pool.items() if n != "field"
                and not isinstance(r, BaseException)}
        if rest:
            m = choose_start(rest, reasons=reasons)[0]
            if m not in cont:
                extend(m)
            r = cont[m]
            without = {"class": m, "input": field_input(records),
                       "nrmse_calibration": r.nrmse_calibration,
                       "nrmse_validation": r.nrmse_validation,
                       "validation_records": {e.label: e.nrmse for e in r.record_errors
                                              if e.role == "validation"},
                       "converged": bool(r.converged),
                       "how": "the start chosen among those that do not read the control "
                              "input (the device-class rule), fitted to convergence"}
    outcomes = tuple(dataclasses.replace(
        o, continued=o.name in cont,
        sized=bool(not isinstance(fits[o.name], BaseException)
                   and fits[o.name].start.get("sized", False))) for o in outcomes)
    first, final = fits[chosen], cont[chosen]
    others = "; ".join(o.describe() for o in outcomes if not o.chosen)
    start = {**first.start, "device_class": chosen,
             "device_class_rule": (
                 f"each start calibrated with max_nfev {cheap}; the leader by effective-"
                 "sample BIC on the calibration records continued, and any start better "
                 f"held-out than it by over {HELD_OUT_TOLERANCE:.0%}; of those not "
                 "dominated (better held-out without losing on a record), the lowest BIC, "
                 f"unless one better held-out is within {BIC_STRONG:g} of it"),
             **({"held_out_note": note} if note else {}),
             **({"without_input": without} if without else {}),
             "loop": reading.as_dict(),
             "classes": [o.as_dict() for o in outcomes]}
    warns = [w for w in final.warnings if not w.startswith("implausible: ")]
    if len(classes) > 1:
        warns.append(f"device class: the {chosen} start was chosen ({reasons[chosen]}); "
                     f"others: {others}" + (f"; {note}" if note else ""))
    plaus = plausibility_flags(final.params, final.effects, records,
                               force_scale=float(first.start.get("force_scale", 1.0)),
                               at_bound=final.flags.at_bound)
    warns += [f"implausible: {f.message}" for f in plaus]
    return dataclasses.replace(final, nfev=nfev, start=start, device_class=chosen,
                               plausibility=plaus,
                               class_starts=outcomes, warnings=tuple(warns),
                               start_trials=first.start_trials, starts=first.starts)


def _field_class(fit, records, validate, *, params, effects, sizing, max_nfev, **kwargs):
    """The field start as the class of records that all carry a control input, with the fit
    that does not follow the input beside it (:func:`input_held`)."""
    res = calibrate_by_class(fit, records, validate, params=params, effects=effects,
                             sizing=sizing, max_nfev=max_nfev, classes=("field",), **kwargs)
    without = input_held(fit, res, records, validate, max_nfev=min(START_NFEV, max_nfev),
                         **kwargs)
    rule = ("every record carries a control input: the field start (the only class whose "
            "model reads it) calibrated with max_nfev "
            f"{max_nfev}; the fit that does not follow the input beside it")
    start = {**res.start, "device_class_rule": rule,
             **({"without_input": without} if without else {})}
    warns = res.warnings + (f"device class: the field start was chosen ({rule}; "
                            + (f"without the input: held-out NRMSE "
                               f"{without['nrmse_validation']:.3g} against "
                               f"{res.nrmse_validation:.3g})" if without and
                               without["nrmse_validation"] is not None else "no fit without "
                               "the input)"),)
    return dataclasses.replace(res, start=start, warnings=warns)


def input_held(fit, result, records, validate, *, max_nfev: int, **kwargs) -> dict | None:
    """The fit of ``result``'s model with its field yield not following the control input.

    The yield's dependence on the input removed (dp_y1 = 0, the lag idle) and its level at
    the records' mean input, dp_y0 + dp_y1 mean|u| (a Bingham yield of constant level, the
    same device otherwise), refitted from ``result``'s optimum with everything else free
    (``max_nfev`` evaluations): the comparison a published MR model makes with and without
    its voltage (issue #20).  Returns the ``without_input`` entry (class, input, NRMSE,
    held-out per record, converged, how) or None where ``result`` has no field yield or the
    fit fails.
    """
    fy = next((e for e in result.effects if e.name == "field_yield"), None)
    if fy is None:
        return None
    c = fy.input
    u_mean = float(np.mean(np.concatenate([np.abs(r.channels[c]) for r in records])))
    held = fy.replace(yield_pressure_Pa=fy.yield_pressure_Pa
                      + fy.yield_pressure_per_input * u_mean, yield_pressure_per_input=0.0)
    effs = tuple(held if e.name == "field_yield" else e for e in result.effects)
    drop = {"field_yield.yield_pressure_per_input", "field_yield.lag_rate_per_s",
            "field_yield.yield_pressure_Pa"}
    spec = FitSpec(tuple(p for p in result.spec.parameters if p.name not in drop))
    spec = spec.with_effect(held, keys=("yield_pressure_Pa",))
    try:
        r = fit(records, params=result.start_params, effects=effs, spec=spec, validate=validate,
                start="spec", sizing="preset", max_nfev=max_nfev, warn=False, **kwargs)
    except (ConvergenceError, PressureError, ParameterError, ValueError,
            FloatingPointError):
        return None
    return {"class": "field, input held", "input": c,
            "model": "the same device with a constant yield (its dependence on the input "
                     "removed)",
            "nrmse_calibration": r.nrmse_calibration,
            "nrmse_validation": r.nrmse_validation,
            "validation_records": {e.label: e.nrmse for e in r.record_errors
                                   if e.role == "validation"},
            "converged": bool(r.converged),
            "how": f"the field fit with dp_y1 = 0 and dp_y0 at the mean |{c}| "
                   f"({u_mean:.3g}), refitted with max_nfev {max_nfev}"}

