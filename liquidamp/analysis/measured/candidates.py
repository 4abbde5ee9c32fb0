"""What each diagnosis candidate proposes: the model it changes to and the parameters it frees.

A candidate of :func:`~liquidamp.analysis.measured.diagnosis.diagnose` is either a catalogue
effect (added at a probe strength, its ``fit_keys`` freed) or a composite (:data:`COMPOSITES`):
a change of how the effects already in the model compose or behave.  Both are described by
one :class:`Change` -- the effects of the candidate model at the probe, the parameters the
refit frees, and the one parameter whose value the score test estimates (its value where the
candidate is absent and at the probe) -- so the score test, the refit and the report treat
them alike.

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

from liquidamp.analysis.measured.calibration import FIT_OPTIONS, CalibrationResult
from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.device.effects import EFFECTS, Effect, with_effects
from liquidamp.errors import ParameterError

__all__ = ["Change", "Composite", "COMPOSITES", "DEVICE_REFINEMENTS", "REDUCTIONS",
           "probe_effect",
           "candidate_change", "applicable", "backlash_gap", "GAP_GRID", "free_columns"]

#: Candidates that contain another as a limit (candidate -> the simpler one it reduces to).
#: A relief valve whose cracking pressure falls towards zero is a laminar bypass of
#: conductance G: ``leakage``.  When such a candidate is the best held out, its reduction is
#: refitted too, and added instead where it ties on held-out data (the extra parameter then
#: sits at the limit the data cannot tell from the simpler model).  A digressive valve whose
#: two directions crack and open alike is the relief valve.
REDUCTIONS = {"relief_valve": "leakage", "digressive_valve": "relief_valve"}


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
        Its value where the candidate is absent (0 for a catalogue effect's strength) and
        in ``effects`` (SI).
    added : str or None
        The catalogue effect the candidate adds (its parameters are reported by bare key).
    report : tuple of str
        Further effects whose fitted parameters the step reports (``effect.key``).
    params : DeviceParams or None
        The device at the probe (None: the calibrated one).
    multipliers : tuple of str
        Device multipliers the refit frees (lead ``("device", name)``, base 1).
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

    def estimate(self, beta: float) -> float:
        """Lead value at the linearized strength ``beta`` of the probe step [SI]."""
        return self.base + beta * (self.probe - self.base)

    @property
    def signed(self) -> bool:
        """Whether the lead may move either way from ``base`` (inside its bounds)."""
        if self.lead[0] == "device":
            return True
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
    if name == "cavitation":
        resp = simulate_record(result.device_model, p, recs[0], options=FIT_OPTIONS)
        pmin = float(min(resp.p1.min(), resp.p2.min()))
        return cls(vapour_pressure_Pa=max(pmin + 0.3 * (p.p0 - pmin), 1.0))
    # the other catalogue effects state their own probe (on the channel the records carry)
    return _on_records(cls.probe(Fa, Y, w, p), result)


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
        s = np.nan_to_num(s)
        if P is not None:
            s = s - J @ (P @ s)
        ss = float(s @ s)
        se = float(s @ e)
        if ss <= 0 or se <= 0 or ee <= 0:
            continue
        drop = se * se / ss / ee
        if drop > best[1]:
            best = (g, drop)
    return best


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

DEVICE_REFINEMENTS = {c.name: c for c in (
    Composite("inertance", "the channel's inertance S_t = l_t / A_t freed (a multiplier on "
              "the preset's; the paper's four fitted parameters hold it at the preset's, and "
              "a device with another channel, e.g. Table 3's Device B, needs it)",
              *_multiplier("S_t", "channel inertance")),
)}
"""Device parameters the preset holds fixed that the diagnosis frees before it screens effects
(where the held-out records ask for it): not effects, the device's own parameters."""


def candidate_change(name: str, result: CalibrationResult) -> Change:
    """The model candidate ``name`` proposes for the calibrated ``result``, at its probe.

    A catalogue effect is added at :func:`probe_effect`'s strength (its fit keys freed, the
    first estimated from 0); a composite (:data:`COMPOSITES`) states its own change.
    """
    if name in COMPOSITES:
        return COMPOSITES[name].change(result)
    e = probe_effect(name, result)
    if getattr(e, "proposed_by", ()):
        return _drifting_change(e, result)
    key = e.fit_keys[0]
    return Change(tuple(result.effects) + (e,), free=tuple((name, k) for k in e.fit_keys),
                  lead=(name, key), base=0.0, probe=float(getattr(e, key)), added=name)


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
