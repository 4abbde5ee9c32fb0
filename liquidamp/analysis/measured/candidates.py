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
``backlash``             freeplay added and the friction at the rod moved behind it (location
                         ``"piston"``): a dead band in series with the friction, as in a friction
                         damper whose band slips only once the play is taken up; frees the gap.
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
           "candidate_change", "applicable"]

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
    start : DeviceParams or None
        The device the refit's multipliers apply to (None: the calibrated result's start).
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
    if name == "leakage":
        Q = p.A_p * w * Y
        return cls(coefficient_m3_per_s_Pa=0.3 / (p.c1 + 8.0 / (3.0 * math.pi) * p.c2 * Q))
    if name == "gas_charge" and hasattr(p, "A_p"):
        return _gas_probe(result)
    if name == "cavitation":
        resp = simulate_record(result.device_model, p, recs[0], options=FIT_OPTIONS)
        pmin = float(min(resp.p1.min(), resp.p2.min()))
        return cls(vapour_pressure_Pa=max(pmin + 0.3 * (p.p0 - pmin), 1.0))
    return cls.probe(Fa, Y, w, p)  # the other catalogue effects state their own probe


def _gas_probe(result: CalibrationResult) -> Effect:
    """``gas_charge`` read off the records (issue #20): the charge, the preload, the travel.

    A gas-charged damper's liquid sits at the charge's pressure
    (:func:`~liquidamp.device.effects_damper.on_absolute_stroke`), which keeps its rebound
    chamber off cavitation: the charge p_c is the largest pressure difference the records'
    force asks of the piston, max |F - mean F| / A_p.  The rod area gives the mean force the
    model leaves in the residual (the preload at the records' mean stroke): A_r = F_0 / p_c,
    F_0 the residual's mean where positive (a gas pushes the rod out) and above 1 % of the
    force swing, else 5 % of the swing; at most half the piston area.  The gas volume
    V_g = 2 A_r max |y_abs| lets the gas halve its volume over the largest absolute stroke
    (a spring rate of about the preload over twice that stroke); isothermal (n = 1).
    """
    recs, p = result.calibration, result.params
    swing = max(float(np.max(np.abs(r.force - r.force.mean()))) for r in recs)
    p_c = max(swing / p.A_p, 1e4)
    meas = np.concatenate([r.force for r in recs])
    resid = float(meas.mean() - np.concatenate(result.predictions_calibration).mean())
    F0 = resid if resid > 0.01 * swing else 0.05 * swing
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
    if "location" not in EFFECTS["coulomb_friction"].__dataclass_fields__:
        return "this catalogue cannot place friction behind a dead band"
    if any(e.name == "freeplay" for e in result.effects):
        return "the model holds freeplay already"
    if not _friction(result.effects, "rod"):
        return "no friction at the rod to move behind a dead band (add friction first)"
    try:
        with_effects(result.device_model, EFFECTS["freeplay"]())
    except ParameterError as exc:
        return str(exc)
    return ""


def _backlash(result) -> Change:
    """Freeplay added, the friction at the rod moved behind it: the gap 3 % of the stroke
    amplitude behind Coulomb friction; behind smooth friction half its pre-sliding stroke
    F_c / sigma0, whose bristle stiffness is doubled (the dead band takes over half the
    compliance a soft bristle stood in for, so that the score compares a dead band with a
    soft bristle)."""
    Y = float(np.mean([r.amplitude for r in result.calibration]))
    movable = _friction(result.effects, "rod")
    smooth = [e for e in movable if e.name == "smooth_friction"]
    gap = 0.5 * smooth[0].force_N / smooth[0].stiffness_N_per_m if smooth else 0.03 * Y
    moved = tuple((e.replace(location="piston", stiffness_N_per_m=2 * e.stiffness_N_per_m)
                   if e in smooth else e.replace(location="piston")) if e in movable
                  else e for e in result.effects)
    return Change(moved + (EFFECTS["freeplay"](gap_m=gap),), free=(("freeplay", "gap_m"),),
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
    Composite("backlash", "a dead band in series with the friction: freeplay added and the "
              "friction already in the model moved behind it (location 'piston'), as in a "
              "friction damper whose band slips only once the play is taken up",
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
    key = e.fit_keys[0]
    gas = name == "gas_charge" and hasattr(result.params, "A_p")
    return Change(tuple(result.effects) + (e,), free=tuple((name, k) for k in e.fit_keys),
                  lead=(name, key), base=0.0, probe=float(getattr(e, key)), added=name,
                  params=_gas_device(result, result.params) if gas else None,
                  start=_gas_device(result, result.start_params) if gas else None)


def applicable(name: str, result: CalibrationResult) -> str:
    """Why candidate ``name`` cannot apply to the calibrated model ('' when it can)."""
    if name in COMPOSITES:
        return COMPOSITES[name].applicable(result)
    try:
        with_effects(result.device_model, EFFECTS[name]())
    except ParameterError as exc:
        return str(exc)
    return ""
