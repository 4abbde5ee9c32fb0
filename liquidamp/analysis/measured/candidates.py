"""What each diagnosis candidate proposes: the model it changes to and the parameters it frees.

A candidate of :func:`~liquidamp.analysis.measured.diagnosis.diagnose` is either a catalogue
effect (added at a probe strength, its ``fit_keys`` freed) or a composite (:data:`COMPOSITES`):
a change of how the effects already in the model compose or behave.  Both are described by
one :class:`Change` -- the effects of the candidate model at the probe, the parameters the
refit frees, and the one parameter whose value the score test estimates (its value where the
candidate is absent and at the probe) -- so the score test, the refit and the report treat
them alike.

Most catalogue effects state their probe themselves (``Effect.probe``); a few are placed
from the calibrated model and its residual here (:func:`probe_effect`): ``bypass_groove``'s
band from the apparent damping against stroke position (:func:`groove_band`).

Composites:

=======================  ==========================================================================
``backlash``             friction behind a dead band (location ``"piston"``), as in a friction
                         damper whose band slips only once the play is taken up: the friction
                         at the rod moved behind freeplay in the attachment (frees the gap),
                         or, without friction in the model, smooth friction added behind its
                         own dead band (``freeplay`` with ``drives="friction"``: the fluid
                         stays on the rod) whose half-width is the profile maximum of
                         :func:`backlash_gap` (frees level, bristle stiffness and gap).
``friction_asymmetry``   the friction in the model grips harder one way: its ``reverse_ratio``
                         (reverse-to-forward level, 1 when absent) freed.  Unlike a
                         ``force_offset`` the difference acts only while the friction slides.
``friction_transition``  smooth friction's pre-sliding reshaped: its ``transition_exponent``
                         (1, LuGre's exponential approach, when absent) freed; large values make
                         the elastic-plastic (Jenkins) element of a clamped band.
=======================  ==========================================================================

:data:`DEVICE_REFINEMENTS` are changes of the same form that free a device parameter rather
than add an effect:

=======================  ==========================================================================
``inertance``            the channel inertance S_t freed as a multiplier on the preset's (not
                         among the paper's four fitted parameters): a device whose channel
                         differs from the preset's (Table 3's Device B) is otherwise fitted with
                         the preset's fluid inertia, and effects stand in for it.
``pressure_level``       the filling pressure p0 (the chambers' pressure level) freed with the
                         channel inertance, proposed where the residual keeps a preload
                         consistent with a gas charge (:func:`gas_preload`): a device sized to
                         the records keeps the preset's pressures, so the ratio of the pressure
                         swing to the level (the gas law's nonlinearity) is out of the fit's
                         reach; a gas-charged damper's liquid sits at its charge, several bar.
                         The inertance is held at its least where it ends at the lower bound (a
                         channel the records cannot tell from none); it reduces to
                         ``inertance`` on a tie.  A gas charge added to a pressurised device
                         takes the level as its charge and frees the rod (area, gas volume).
=======================  ==========================================================================

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.C.
.. [2] Y.-K. Wen, "Method for random vibration of hysteretic systems", J. Eng. Mech. Div.
   102(2), 1976 (the transition exponent).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.calibration import FIT_OPTIONS, CalibrationResult, predict
from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.device.effects import EFFECTS, Effect, with_effects
from liquidamp.errors import LiquidampError, ParameterError

__all__ = ["Change", "Composite", "COMPOSITES", "DEVICE_REFINEMENTS", "REDUCTIONS",
           "PRELOAD_SHARE", "gas_preload", "probe_effect",
           "candidate_change", "applicable", "backlash_gap", "GAP_GRID", "free_columns",
           "groove_band", "GROOVE_CENTRES", "GROOVE_WIDTHS"]

#: Candidates that contain another as a limit (candidate -> the simpler one it reduces to).
#: A relief valve whose cracking pressure falls towards zero is a laminar bypass of
#: conductance G: ``leakage``.  When such a candidate is the best held out, its reduction is
#: refitted too, and added instead where it ties on held-out data (the extra parameter then
#: sits at the limit the data cannot tell from the simpler model).  A digressive valve whose
#: two directions crack and open alike is the relief valve.  The pressure level freed with
#: the inertance, its level left where it was, is the inertance alone.  Backlash whose dead
#: band closes (a gap of a micrometre on a friction-and-leak record) is its friction alone.
#: A floating freeplay whose band closes is its contact alone: a spring in series.
REDUCTIONS = {"relief_valve": "leakage", "digressive_valve": "relief_valve",
              "pressure_level": "inertance", "backlash": "smooth_friction",
              "floating_freeplay": "series_compliance"}


@dataclass(frozen=True)
class Change:
    """The model a candidate proposes, at its probe.

    Attributes
    ----------
    effects : tuple of Effect
        Every effect of the candidate model, the lead parameter at its probe value.
    free : tuple of (str, str)
        ``(effect, key)`` parameters the refit adds to the fitted ones.
    lead : (str, str)
        The parameter the score test estimates.
    base, probe : float
        Its value where the candidate is absent (0 for a catalogue effect's strength, 1 for
        a rebound ratio, ``math.inf`` for a stiffness in series, absent when rigid:
        :attr:`~liquidamp.device.effects.Effect.bare`) and in ``effects`` (SI).
    added : str or None
        The catalogue effect the candidate adds (its parameters are reported by bare key).
    report : tuple of str
        Further effects whose fitted parameters the step reports (``effect.key``).
    params : DeviceParams or None
        The device at the probe (None: the calibrated one).
    multipliers : tuple of str
        Device multipliers the refit frees (lead ``("device", name)``, base 1).
    start : DeviceParams or None
        The device the refit's multipliers apply to (None: the calibrated result's start).
    bounds : tuple of (str, float, float)
        Bounds of freed multipliers other than the fit's (name, lower, upper) [-].
    """

    effects: tuple
    free: tuple
    lead: tuple
    base: float
    probe: float
    added: str | None = None
    report: tuple = ()
    params: object = None
    multipliers: tuple = ()
    start: object = None
    bounds: tuple = ()

    def estimate(self, beta: float) -> float:
        """Lead value at the linearized strength ``beta`` of the probe step [SI].

        The score test is linear in the effect's strength, the coordinate that is 0 where the
        effect is absent: the lead less ``base``, or, for a lead absent at infinity (a
        stiffness in series, k = inf: rigid), its inverse (the compliance 1/k, to which the
        force of a spring in series with the device is linear near rigid).  So a finite base
        gives base + beta (probe - base), an infinite one probe / beta (beta > 0; ``inf``
        otherwise).

        Examples
        --------
        >>> Change((), (), ("moving_mass", "mass_kg"), 0.0, 2.0).estimate(0.5)
        1.0
        >>> Change((), (), ("series_compliance", "stiffness_N_per_m"), math.inf,
        ...        2.0e6).estimate(0.5)  # half the probe's compliance: twice its stiffness
        4000000.0
        """
        if math.isinf(self.base):
            return self.probe / beta if beta > 0 else math.inf
        return self.base + beta * (self.probe - self.base)

    @property
    def signed(self) -> bool:
        """Whether the lead may move either way from ``base`` (inside its bounds): not a
        lead absent at infinity (a negative compliance is no spring)."""
        if self.lead[0] == "device":
            return True
        if math.isinf(self.base):
            return False
        lo, _ = EFFECTS[self.lead[0]].bounds[self.lead[1]]
        return lo < self.base

    def effect(self, name: str) -> Effect:
        """The candidate model's effect ``name``."""
        return next(e for e in self.effects if e.name == name)

    def parameters(self, result: CalibrationResult) -> dict:
        """The fitted values of what the change freed, and of the effects it reports (SI):
        the added effect's parameters by bare key, the others as ``effect.key``."""
        out = {}
        for e in result.effects:
            if e.name in self.report:
                out.update({f"{e.name}.{k}": v for k, v in e.parameters.items()})
            elif e.name == self.added:
                out.update(e.parameters)
        for name, key in self.free:
            e = next(e for e in result.effects if e.name == name)
            out[key if name == self.added else f"{name}.{key}"] = getattr(e, key)
        for name in self.multipliers:
            out[f"{name} multiplier"] = result.values.get(name, 1.0)
            out[name] = getattr(result.params, name)
        return out


def free_columns(result, r, tol: float = 1e-3):
    """Jacobian columns of the fitted parameters that can still move to mimic an effect.

    ``result`` is a :class:`CalibrationResult`, ``r`` its residual [N] (model minus record,
    or its negative: only the sign of the gradient matters); returns the columns of
    ``result.jacobian`` not pinned at a bound.

    A parameter held at a bound by the residual (within ``tol`` of it in the fit
    coordinate, with the descent direction -J^T r pointing out of the bounds) is
    effectively fixed at the constrained optimum (Kuhn-Tucker): the fit cannot move it
    to absorb an effect's signature, so its column must not be projected out of the
    signature.  Otherwise a parameter stuck at its bound in the direction the missing
    effect pulls it (c1 at its lower bound for a bypass leak) hides the effect from the
    score test.
    """
    J = result.jacobian
    if not J.size:
        return J
    g = J.T @ r
    keep = []
    for i, name in enumerate(result.varying):
        p = result.spec[name]
        lo, hi = p.x_bounds()
        x = p.to_x(result.values[name])
        pinned = (x - lo < tol and g[i] > 0) or (hi - x < tol and g[i] < 0)
        if not pinned:
            keep.append(i)
    return J[:, keep]


def probe_effect(name: str, result: CalibrationResult) -> Effect:
    """The effect at a probe strength scaled to the records and the calibrated model."""
    recs = result.calibration
    F = np.concatenate([r.force for r in recs])
    Fa = math.sqrt(2.0) * float(np.sqrt(np.mean((F - F.mean()) ** 2)))
    Y = float(np.mean([r.amplitude for r in recs]))
    w = 2 * math.pi * float(np.mean([r.frequency for r in recs]))
    p = result.params
    cls = EFFECTS[name]
    if name == "coulomb_friction":
        return cls(force_N=0.05 * Fa)
    if name == "smooth_friction":
        return cls(force_N=0.05 * Fa, stiffness_N_per_m=0.05 * Fa / (0.05 * Y))
    if name == "force_offset":
        return cls(offset_N=0.02 * Fa)
    if name == "moving_mass":
        return cls(mass_kg=0.05 * Fa / (w * w * Y))
    if name == "series_compliance":
        return cls(stiffness_N_per_m=10.0 * Fa / Y)
    if name == "freeplay":
        return cls(gap_m=0.03 * Y)
    if name == "floating_freeplay":
        # the contact a hundred times stiffer than the loop's secant Fa / Y: the probe is the
        # dead band, not a series spring
        return cls(gap_m=0.03 * Y, contact_stiffness_N_per_m=100.0 * Fa / Y)
    if name == "slip_weakening":
        # the weakening shows only beyond the friction's pre-sliding stroke F_c / sigma0 (a
        # shorter one is hidden in the bristles' rise, a much longer one is a level): probed
        # at three of them
        sf = next((e for e in result.effects if e.name == "smooth_friction"), None)
        if sf is not None and sf.force_N > 0:
            return cls(ratio=0.1, distance_m=min(3.0 * sf.force_N / sf.stiffness_N_per_m,
                                                 cls.bounds["distance_m"][1]))
    if name == "leakage":
        Q = p.A_p * w * Y
        return cls(coefficient_m3_per_s_Pa=0.3 / (p.c1 + 8.0 / (3.0 * math.pi) * p.c2 * Q))
    if name == "bypass_groove":
        centre, width, _ = groove_band(result)
        return cls(depth=0.2, centre_m=centre, half_width_m=width)
    if name == "gas_charge" and hasattr(p, "A_p"):
        return _gas_probe(result)
    if name == "cavitation":
        resp = simulate_record(result.device_model, p, recs[0], options=FIT_OPTIONS)
        pmin = float(min(resp.p1.min(), resp.p2.min()))
        return cls(vapour_pressure_Pa=max(pmin + 0.3 * (p.p0 - pmin), 1.0))
    # the other catalogue effects state their own probe (on the channel the records carry)
    return _on_records(cls.probe(Fa, Y, w, p), result)


#: Groove centres of the band profile, as fractions of the stroke amplitude about the
#: records' mean absolute stroke [-] (:func:`groove_band`): across the stroke, its ends
#: included.
GROOVE_CENTRES = tuple(float(c) for c in np.linspace(-1.0, 1.0, 21))
#: Groove half-widths of the band profile, as fractions of the stroke amplitude [-]: from a
#: twentieth of the stroke (about two samples of a 200 Hz record at the centre) to the whole
#: stroke (wider, the scale is near uniform: the fitted losses' own signature).
GROOVE_WIDTHS = tuple(float(w) for w in np.geomspace(0.05, 1.0, 14))


def groove_band(result: CalibrationResult) -> tuple[float, float, float]:
    """Where a bypass groove best explains the calibration residual: (centre [m],
    half-width [m], share of the residual sum of squares it removes [-]).

    The apparent damping against stroke position: lowering the channel's losses by a
    small uniform factor changes the model's force by U(t) (one run of the calibrated model
    with a groove wider than the stroke); a groove of centre y_c and half-width w lowers
    them only where the piston is, so to first order, and where the fluid follows the
    loss faster than the stroke moves, its signature is phi((y(t) - y_c) / w) U(t), y the
    absolute stroke (the groove is cut at a fixed place in the tube).  As in
    :func:`backlash_gap` the fitted parameters' span is projected out (a uniform change is
    c1's and c2's), and for each (y_c, w) on :data:`GROOVE_CENTRES` x
    :data:`GROOVE_WIDTHS` times the stroke amplitude the least-squares drop
    (s . e)^2 / (s . s) / (e . e) of a softer band (s . e > 0) is a closed form; the
    profile maximum places the probe (the score test then runs the exact model).
    Returns the mid stroke, half the amplitude and 0 where no band softens.
    """
    recs = result.calibration
    Y = float(np.mean([r.amplitude for r in recs]))
    mid = float(np.mean([r.offset for r in recs]))
    fallback = (mid, 0.5 * Y, 0.0)
    meas = np.concatenate([r.force for r in recs])
    model = np.concatenate(result.predictions_calibration)
    e = meas - model
    ee = float(e @ e)
    wide = EFFECTS["bypass_groove"](depth=0.05, centre_m=mid, half_width_m=1e3 * Y)
    try:
        Fu = predict(result.model, result.params, tuple(result.effects) + (wide,), recs,
                     options=FIT_OPTIONS)
    except LiquidampError:  # the probe run itself reports the failure
        return fallback
    U = np.concatenate(Fu) - model
    y = np.concatenate([r.smoothed for r in recs])  # absolute: the groove sits in the tube
    J = free_columns(result, -e)
    P = np.linalg.pinv(J) if J.size else None
    best = fallback
    for fw in GROOVE_WIDTHS:
        w = fw * Y
        for fc in GROOVE_CENTRES:
            c = mid + fc * Y
            drop = _projected_drop(np.exp(-((y - c) / w) ** 2) * U, e, ee, J, P)
            if drop > best[2]:
                best = (c, w, drop)
    return best


#: Least mean force a calibrated model leaves in the residual, as a share of the records'
#: force swing, read as a preload consistent with a gas charge (:func:`gas_preload`) [-].
PRELOAD_SHARE = 0.01


def gas_preload(result: CalibrationResult) -> float | None:
    """The preload consistent with a gas charge the calibrated ``result`` leaves unexplained
    [N], or None.

    The mean of the calibration residual, measured minus model force, where it is positive
    (a gas charge pushes the rod out: a force that resists the stroke into the damper) and
    above :data:`PRELOAD_SHARE` of the records' largest force swing max |F - mean F| (a
    sealed device's own nonlinearity leaves less; a load-cell zero of the other sign is not
    a gas).  On the shared records only the gas-charged one leaves more than 0.5 %: d09
    2.0 %, the others -6.6 % (asymmetric loss) to +0.45 %.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0.0, 2.0, 0.01)
    >>> F = 20.0 + 500 * np.cos(2 * np.pi * t)
    >>> rec = Record.from_arrays(t, 0.01 * np.sin(2 * np.pi * t), F)
    >>> fit = SimpleNamespace(calibration=(rec,), predictions_calibration=(rec.force - 20.0,))
    >>> round(gas_preload(fit), 6)
    20.0
    >>> gas_preload(SimpleNamespace(calibration=(rec,), predictions_calibration=(rec.force,)))
    """
    recs = tuple(result.calibration)
    swing = max(float(np.max(np.abs(r.force - r.force.mean()))) for r in recs)
    meas = np.concatenate([r.force for r in recs])
    resid = float(meas.mean() - np.concatenate(result.predictions_calibration).mean())
    return resid if resid > PRELOAD_SHARE * swing else None


def _gas_probe(result: CalibrationResult) -> Effect:
    """``gas_charge`` read off the records (issue #20): the charge, the preload, the travel.

    A gas-charged damper's liquid sits at the charge's pressure
    (:func:`~liquidamp.device.effects_damper.on_absolute_stroke`): where the calibrated
    device is pressurised (its filling pressure p0 above the ambient p_a, e.g. freed by the
    ``pressure_level`` refinement) the charge is the level it holds, p_c = p0 - p_a, so that
    the probe adds the rod's force and nothing else; otherwise the charge keeps the rebound
    chamber off cavitation: the largest pressure difference the records' force asks of the
    piston, max |F - mean F| / A_p.  The rod area gives the mean force the
    model leaves in the residual (the preload at the records' mean stroke): A_r = F_0 / p_c,
    F_0 the residual's mean where positive (a gas pushes the rod out) and above 1 % of the
    force swing, else 5 % of the swing; at most half the piston area.  The gas volume
    V_g = 2 A_r max |y_abs| lets the gas halve its volume over the largest absolute stroke
    (a spring rate of about the preload over twice that stroke); isothermal (n = 1).
    """
    recs, p = result.calibration, result.params
    swing = max(float(np.max(np.abs(r.force - r.force.mean()))) for r in recs)
    p_a = EFFECTS["gas_charge"]().ambient_pressure_Pa
    p_c = p.p0 - p_a if p.p0 > p_a * (1.0 + 1e-6) else max(swing / p.A_p, 1e4)
    F0 = gas_preload(result) or 0.05 * swing
    A_r = min(F0 / p_c, 0.5 * p.A_p)
    y_max = max(float(np.max(np.abs(r.displacement))) for r in recs)
    return EFFECTS["gas_charge"](A_r, p_c, 2.0 * A_r * max(y_max, 1e-6), 1.0)


def _gas_device(result: CalibrationResult, p):
    """Device ``p`` with its chambers moved to the stroke datum for the absolute stroke
    (:func:`~liquidamp.device.effects_damper.on_absolute_stroke`).

    The first calibration record (mean y_m) holds them where the calibrated model did: V01 +
    A_p y_m, V02 - A_p y_m at the datum; each is enlarged where a record (calibration or
    held out, mean y_r, amplitude Y_r) would use more than
    :data:`~liquidamp.analysis.measured.start.NEAR_STROKE_SHARE` of its chamber about its
    mean (V01 >= A_p (y_r + Y_r / share), V02 >= A_p (Y_r / share - y_r)), so that the
    refit runs near this device instead of sizing another.  The score test's probe (on the
    calibrated device) then differs from the calibrated model by the charge and little
    else, and the refit (on its start device) starts where the calibrated model is."""
    from liquidamp.analysis.measured.start import NEAR_STROKE_SHARE

    recs = tuple(result.calibration) + tuple(result.validation)
    A, off = p.A_p, float(result.calibration[0].offset)
    need = [(float(r.offset), float(np.max(np.abs(r.displacement - r.offset)))
             / NEAR_STROKE_SHARE * 1.001) for r in recs]
    V1 = max([p.V01 + A * off] + [A * (y + Y) for y, Y in need])
    V2 = max([p.V02 - A * off] + [A * (Y - y) for y, Y in need])
    return p.replace(V01=V1, V02=V2)


@dataclass(frozen=True)
class Composite:
    """A candidate that changes how the model's effects compose or behave.

    Attributes
    ----------
    name, description : str
    applicable : callable
        ``applicable(result) -> str``: why it cannot apply to the calibrated model
        (``''`` when it can).
    change : callable
        ``change(result) -> Change`` at its probe.
    """

    name: str
    description: str
    applicable: Callable[[CalibrationResult], str]
    change: Callable[[CalibrationResult], Change]

    def __str__(self) -> str:
        return self.description


_FRICTION = ("coulomb_friction", "smooth_friction")


def _friction(effects, location: str | None = None) -> list:
    """The friction effects with a level (at ``location`` if given), strongest first."""
    out = [e for e in effects if e.name in _FRICTION and e.force_N > 0
           and (location is None or e.location == location)]
    return sorted(out, key=lambda e: -e.force_N)


def _varied(result: CalibrationResult, effect: str, key: str) -> bool:
    return f"{effect}.{key}" in result.varying


def _backlash_applicable(result) -> str:
    if "drives" not in EFFECTS["freeplay"].__dataclass_fields__:
        return "this catalogue cannot place friction behind a dead band"
    if any(e.name == "freeplay" for e in result.effects):
        return "the model holds freeplay already"
    if _friction(result.effects, "piston"):
        return "the friction sits behind a dead band already"
    if any(e.name in _FRICTION for e in result.effects) and not _friction(result.effects,
                                                                          "rod"):
        return "no friction level at the rod to move behind a dead band"
    if any(e.name == "series_compliance" for e in result.effects):
        return "friction behind a dead band cannot sit behind series_compliance"
    return ""


#: Dead-band half-widths of the gap profile, as fractions of the stroke amplitude [-]
#: (:func:`backlash_gap`): from a tenth of a percent (the friction on the rod, within the
#: resolution of a sampled stroke) to 80 % (the element slides over a fifth of the stroke).
GAP_GRID = tuple(float(g) for g in np.geomspace(1e-3, 0.8, 30))


def _play(y: np.ndarray, gap: float) -> np.ndarray:
    """The driven side of a dead band of half-width ``gap`` [m] under the stroke ``y`` [m]
    (the play operator, discrete), on the periodic orbit: the record is run twice and the
    second pass kept (its start then holds the state its end leaves)."""
    yy = np.concatenate((y, y))
    out = np.empty_like(yy)
    w = yy[0]
    for k, yk in enumerate(yy):
        w = min(max(w, yk - gap), yk + gap)
        out[k] = w
    return out[y.size:]


def backlash_gap(result: CalibrationResult) -> tuple[float, float]:
    """The dead band that best explains the calibration residual as friction behind it [m].

    A friction element behind a dead band of half-width g adds F_c s_g(t) to the force of a
    model with the fluid on the rod, s_g = sign of the driven side's motion while it moves
    and 0 while the rod crosses the gap (2 g of travel after each reversal): linear in F_c,
    so that for each g the least-squares level and its drop of the residual sum of squares
    are closed forms, (s_g . e)^2 / (s_g . s_g) with e the measured minus the model force
    and s_g with the span of the fitted parameters' Jacobian projected out (as the score
    test does: what the calibrated parameters can mimic is no evidence).
    The gap is the maximum of that profile (a profile likelihood over g, the one nonlinear
    parameter) over :data:`GAP_GRID` times the stroke amplitude of each record.  The
    signature of each record is built on its smoothed stroke (the play operator is
    translation invariant, so its offset does not matter).

    Returns
    -------
    (gap, drop) : tuple of float
        The best half-width [m] and its share of the residual sum of squares it removes
        [-] (0 where no gap gives a positive friction level).

    References
    ----------
    .. [1] M. A. Krasnosel'skii, A. V. Pokrovskii, Systems with Hysteresis, Springer, 1989
       (the play operator).
    """

    recs = result.calibration
    e = -np.concatenate(result.residuals("calibration"))
    ee = float(e @ e)
    Y = float(np.mean([r.amplitude for r in recs]))
    # as the score test: the part of each signature the fitted parameters cannot mimic (a
    # fluid fit without the friction has bent its losses towards it)
    J = free_columns(result, -e)
    P = np.linalg.pinv(J) if J.size else None
    best = (0.0, 0.0)
    for f in GAP_GRID:
        g = f * Y
        s = np.concatenate([np.sign(np.diff(_play(r.smoothed, g), prepend=np.nan))
                            for r in recs])
        drop = _projected_drop(np.nan_to_num(s), e, ee, J, P)
        if drop > best[1]:
            best = (g, drop)
    return best


def _projected_drop(sig, e, ee: float, J, P) -> float:
    """Share of the residual ``e`` (``ee`` = e . e) a signature ``sig`` removes once the
    span ``J`` of the fitted parameters (pseudo-inverse ``P``, None when empty) is projected
    out of it: (s . e)^2 / (s . s) / ee, or 0 where it does not point along ``e``."""
    if P is not None:
        sig = sig - J @ (P @ sig)
    ss, se = float(sig @ sig), float(sig @ e)
    return se * se / ss / ee if ss > 0 and se > 0 and ee > 0 else 0.0


def _backlash(result) -> Change:
    """Friction behind its own dead band (the fluid stays on the rod: ``freeplay`` with
    ``drives="friction"``).

    Without friction in the model, smooth friction at the piston is added behind a dead band
    whose half-width is the profile maximum of :func:`backlash_gap`; its level is the lead
    (0 where absent, probed at 5 % of the force amplitude as the catalogue's friction), its
    bristle stiffness puts the pre-sliding stroke at a tenth of the gap (a dead band takes
    up the slack a soft bristle would stand in for), and the refit frees level, stiffness
    and gap (the signature is then additive, linear in the level, whence the profile).
    With friction at the rod, that friction is moved behind a dead band in the attachment
    that the fluid sits behind too (``drives="piston"``: the rod -> dead band -> piston and
    band of a friction damper with backlash), and the gap is the lead: 3 % of the stroke
    amplitude behind Coulomb friction; behind smooth friction half its pre-sliding stroke
    F_c / sigma0, whose bristle stiffness is doubled (the dead band takes over half the
    compliance a soft bristle stood in for, so that the score compares a dead band with a
    soft bristle)."""
    Y = float(np.mean([r.amplitude for r in result.calibration]))
    movable = _friction(result.effects, "rod")
    if not movable:
        recs = result.calibration
        F = np.concatenate([r.force for r in recs])
        Fa = math.sqrt(2.0) * float(np.sqrt(np.mean((F - F.mean()) ** 2)))
        gap, _ = backlash_gap(result)
        lo, hi = EFFECTS["freeplay"].bounds["gap_m"]
        gap = min(max(gap, 10.0 * lo), hi / 10.0)
        level = 0.05 * Fa
        friction = EFFECTS["smooth_friction"](force_N=level,
                                              stiffness_N_per_m=level / (0.1 * gap),
                                              location="piston")
        effects = tuple(result.effects) + (
            friction, EFFECTS["freeplay"](gap_m=gap, drives="friction"))
        return Change(effects, free=(("smooth_friction", "force_N"),
                                     ("smooth_friction", "stiffness_N_per_m"),
                                     ("freeplay", "gap_m")),
                      lead=("smooth_friction", "force_N"), base=0.0, probe=level,
                      added="freeplay", report=("smooth_friction",))
    smooth = [e for e in movable if e.name == "smooth_friction"]
    gap = 0.5 * smooth[0].force_N / smooth[0].stiffness_N_per_m if smooth else 0.03 * Y
    moved = tuple((e.replace(location="piston", stiffness_N_per_m=2 * e.stiffness_N_per_m)
                   if e in smooth else e.replace(location="piston")) if e in movable
                  else e for e in result.effects)
    return Change(moved + (EFFECTS["freeplay"](gap_m=gap),),
                  free=(("freeplay", "gap_m"),),
                  lead=("freeplay", "gap_m"), base=0.0, probe=gap, added="freeplay",
                  report=tuple(e.name for e in movable))


def _refinement(key: str, kinds: tuple, probe: Callable[[float], float]):
    """Composite that frees ``key`` of the strongest friction of ``kinds`` in the model,
    probed at ``probe(current value)``."""

    def target(result):
        return next(iter(_friction([e for e in result.effects if e.name in kinds])), None)

    def why(result) -> str:
        e = target(result)
        if e is None:
            return f"no {' or '.join(kinds)} in the model (add friction first)"
        if _varied(result, e.name, key):
            return f"{e.name} {key} is fitted already"
        return ""

    def change(result) -> Change:
        e = target(result)
        base = float(getattr(e, key))
        p = probe(base)
        effects = tuple(x.replace(**{key: p}) if x is e else x for x in result.effects)
        return Change(effects, free=((e.name, key),), lead=(e.name, key), base=base, probe=p)

    return why, change


def _multiplier(name: str, what: str):
    """Composite that frees the device multiplier ``name`` (held at the preset's value by the
    fit so far), probed at 0.9."""

    def why(result) -> str:
        if name in result.varying:
            return f"{name} is fitted already"
        if name not in {p.name for p in result.spec.parameters if p.kind == "multiplier"} \
                and getattr(result.params, name, None) in (None, 0.0):
            return f"the device has no {what}"
        return ""

    def change(result) -> Change:
        return Change(tuple(result.effects), free=(), lead=("device", name), base=1.0,
                      probe=0.9, params=result.params.scaled(**{name: 0.9}),
                      multipliers=(name,))

    return why, change


COMPOSITES = {c.name: c for c in (
    Composite("backlash", "friction behind a dead band: the friction in the model moved "
              "behind freeplay, or smooth friction added behind its own dead band (the "
              "fluid on the rod), as in a friction damper whose band slips only once the "
              "play is taken up",
              _backlash_applicable, _backlash),
    Composite("friction_asymmetry", "the friction grips harder one way: its reverse-to-"
              "forward level ratio freed (a band or seal unlike in compression and "
              "rebound; acts only while sliding, unlike a force offset)",
              *_refinement("reverse_ratio", _FRICTION, lambda q: 0.9 * q)),
    Composite("friction_transition", "smooth friction's pre-sliding reshaped: its "
              "transition exponent freed (stiff until near the sliding level, then a sharp "
              "slip: the elastic-plastic element of a clamped band)",
              *_refinement("transition_exponent", ("smooth_friction",), lambda n: n + 1.0)),
)}
"""Candidates that change how effects compose rather than add one (module docstring)."""

def _level_applicable(result) -> str:
    """Why the pressure level cannot be freed ('' when it can)."""
    if "p0" in result.varying:
        return "p0 is fitted already"
    if getattr(result.device_model, "pressures", None) is None:
        return "the model has no chamber pressures"
    if any(e.name in ("gas_charge", "field_yield") for e in result.effects):
        return "the chambers' level is set by the model's gas charge or field start"
    if gas_preload(result) is None:
        return ("no preload consistent with a gas charge in the residual (a pressurised "
                f"device's sign; mean force above {PRELOAD_SHARE:.0%} of the swing)")
    return ""


def _level_change(result) -> Change:
    """The filling pressure p0 freed with the channel's inertance S_t (where not fitted yet),
    both from the current fit (``pressure_level``)."""
    mult = ("p0",) + (() if "S_t" in result.varying or not result.params.S_t else ("S_t",))
    lo, hi = next(((p.min, p.max) for p in result.spec.parameters if p.kind == "multiplier"),
                  (0.05, 20.0))
    # at a given force the channel's inertance follows the level as 1/k: its reach widens by
    # the level's own
    bounds = (("S_t", lo * lo, hi * hi),) if "S_t" in mult else ()
    return Change(tuple(result.effects), free=(), lead=("device", "p0"), base=1.0,
                  probe=1.0, params=result.params, multipliers=mult, bounds=bounds)


DEVICE_REFINEMENTS = {c.name: c for c in (
    Composite("inertance", "the channel's inertance S_t = l_t / A_t freed (a multiplier on "
              "the preset's; the paper's four fitted parameters hold it at the preset's, and "
              "a device with another channel, e.g. Table 3's Device B, needs it)",
              *_multiplier("S_t", "channel inertance")),
    Composite("pressure_level", "the chambers' pressure level p0 freed, with the channel's "
              "inertance: a device sized to the records keeps the preset's pressures (its "
              "piston set by the force at the preset's filling pressure), so the one shape "
              "the sizing fixes is the ratio of the chamber pressure swing to the level (the "
              "gas law's nonlinearity; a gas-charged damper's liquid swings several bar about "
              "its charge); the inertance the 1-atm fit needed to draw that shape is freed "
              "with it (proposed where the residual keeps a preload consistent with a gas "
              "charge)",
              _level_applicable, _level_change),
)}
"""Device parameters the preset holds fixed that the diagnosis frees before it screens effects
(where the held-out records ask for it): not effects, the device's own parameters."""


def candidate_change(name: str, result: CalibrationResult) -> Change:
    """The model candidate ``name`` proposes for the calibrated ``result``, at its probe.

    A catalogue effect is added at :func:`probe_effect`'s strength (its fit keys freed, the
    first estimated from where the effect is absent, :attr:`Effect.bare`: 0, a symmetric
    rebound ratio 1, or rigid for a spring in series, whose compliance is the strength,
    :meth:`Change.estimate`); a composite
    (:data:`COMPOSITES`) states its own change.
    """
    if name in COMPOSITES:
        return COMPOSITES[name].change(result)
    e = probe_effect(name, result)
    if getattr(e, "proposed_by", ()):
        return _drifting_change(e, result)
    key = e.fit_keys[0]
    gas = name == "gas_charge" and hasattr(result.params, "A_p")
    keys = e.fit_keys
    if gas and e.charge_pressure_Pa == result.params.p0 - e.ambient_pressure_Pa:
        # on a pressurised device the charge is the level the fit holds (fitted without the
        # gas, held): the probe adds the rod, whose area is the preload's strength (the lead)
        # and whose gas volume sets the gas spring
        key, keys = "rod_area_m2", ("rod_area_m2", "gas_volume_m3")
    # the lead where the effect is absent (Effect.bare): 0 for a strength, 1 for a rebound
    # ratio, infinity for a stiffness in series (k = inf is the bare model)
    base = float(type(e).bare.get(key, 0.0))
    return Change(tuple(result.effects) + (e,), free=tuple((name, k) for k in keys),
                  lead=(name, key), base=base, probe=float(getattr(e, key)), added=name,
                  params=_gas_device(result, result.params) if gas else None,
                  start=_gas_device(result, result.start_params) if gas else None)


def _measured(result: CalibrationResult, channel: str) -> bool:
    """Whether every calibration and held-out record carries the measured ``channel``."""
    recs = tuple(result.calibration) + tuple(getattr(result, "validation", ()) or ())
    return bool(recs) and all(channel in getattr(r, "channels", {}) for r in recs)


def _drifting_change(e: Effect, result: CalibrationResult) -> Change:
    """Self-heating proposed by a drift or a measured temperature (``Effect.proposed_by``).

    With the temperature measured on every record it drives the viscosity law: the
    coefficient beta (``fit_keys_measured``) is the one freed, the lead from beta = 0
    (the device without the effect).  Without it each record's start temperature is its
    own (``start="record"``), the law's beta stays at its probe (only beta / h_A and
    C_th / h_A show in a force), and the heat capacity and conductance (``fit_keys``) are
    freed, the lead again beta from 0.
    """
    if _measured(result, "temperature"):
        e = e.replace(start="given", temperature="measured")
        free = e.fit_keys_measured
    else:
        e = e.replace(start="record")
        free = e.fit_keys
    return Change(tuple(result.effects) + (e,), free=tuple((e.name, k) for k in free),
                  lead=(e.name, "beta_per_K"), base=0.0, probe=float(e.beta_per_K),
                  added=e.name)


def applicable(name: str, result: CalibrationResult) -> str:
    """Why candidate ``name`` cannot apply to the calibrated model ('' when it can)."""
    if name in COMPOSITES:
        return COMPOSITES[name].applicable(result)
    try:
        e = _on_records(EFFECTS[name](), result)
        with_effects(result.device_model, e)
    except ParameterError as exc:
        return str(exc)
    return _proposed(EFFECTS[name], result)


def _proposed(cls, result: CalibrationResult) -> str:
    """Why an effect proposed only by what a record shows (``Effect.proposed_by``: a drift of
    its force, a measured temperature) is not proposed by these records ('' when it is): a
    stationary record without the channel has nothing such an effect could follow."""
    why = getattr(cls, "proposed_by", ())
    if not why:
        return ""
    recs = tuple(result.calibration)
    if "temperature" in why and _measured(result, "temperature"):
        return ""
    if "drift" in why:
        from liquidamp.analysis.measured.drift import record_drift

        if any(r.periodic and record_drift(r).nonstationary for r in recs):
            return ""
    return ("proposed only by a record whose force drifts from cycle to cycle or that "
            "carries a measured temperature; these records do neither")


def _on_records(effect: Effect, result: CalibrationResult) -> Effect:
    """``effect`` reading the measured channel the records carry (an effect with an ``input``
    composition field, e.g. ``field_yield``: voltage or current); ParameterError naming why
    where a record carries none it can read (so that such an effect is screened only on
    records with its input, issue #20)."""
    if not effect.input_channels:
        return effect
    records = tuple(result.calibration) + tuple(getattr(result, "validation", ()) or ())
    choices = effect.composition_keys().get("input", effect.input_channels)
    for c in choices:
        if all(c in r.channels for r in records):
            return effect.replace(input=c) if "input" in effect.composition_keys() else effect
    have = sorted({k for r in records for k in r.channels})
    raise ParameterError(
        f"effect {effect.name!r} follows a measured {' or '.join(choices)} channel, which "
        f"not every record carries (channels there: {', '.join(have) or 'none'})")
