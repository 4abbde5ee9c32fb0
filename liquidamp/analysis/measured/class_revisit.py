"""The device class revisited by the diagnosis: the runner-up start diagnosed too.

The start's class (fluid, friction, viscous;
:mod:`~liquidamp.analysis.measured.device_class`) is chosen on the baselines alone,
before any effect.  An averaged cycle holds few independent values, so where the
calibration BIC does not hold strong evidence the held-out records decide, and a
start of the wrong class can win because the right class misses an effect it has not
been given yet: a fluid device with an elastomer (or with friction and leakage)
predicts the held-out record worse without its effect than a friction damper does,
and from the friction start the elastomer is never found (the loop is stuck in the
wrong family).  The class is a model choice like any other, so it is judged like one
on the models the diagnosis ends with:

* when the class choice continued another start beside the chosen one (its fit was
  good enough to be judged converged; :func:`runner_up`), the calibration records do not
  hold strong evidence for the chosen start against it (its effective-sample BIC is not
  lower by :data:`~liquidamp.analysis.measured.device_class.BIC_STRONG`, 10, or more:
  the class choice's own measure of strong evidence) and the diagnosis from the chosen
  start ends with its calibration residual above the noise level (a residual at the
  noise floor leaves nothing another class could explain), the runner-up start is
  diagnosed too;
* its final model replaces the chosen start's only where it passes the diagnosis's
  own selection rule against it, as a step would
  (:func:`~liquidamp.analysis.measured.selection.judge`: no held-out record worse by
  more than the tolerance, better together by more than it, and the calibration BIC
  over the honest sample count lower by more than the threshold, the parameters of
  both models counted; non-nested models compare on BIC as nested ones do [1]_).

The fluid family's other starts (:func:`fluid_alternatives`)
    The class choice judges starts on their baselines, before any effect, and the fluid
    start holds two things fixed that an undeclared effect can put out of the fit's reach:

    * its *size*: the device is sized to the records when the RMS force of the device as
      given is more than :data:`~liquidamp.analysis.measured.start.NEAR_FORCE_RATIO` (4)
      off, and an effect inflates that RMS (the contact spikes of end stops: a reference
      design with stops at 3.2 mm of a 3.5 mm stroke reads 5.9x the RMS of
      ``paper_initial``).  A similar device scaled by the force factor a carries a times
      the fluid inertance b_L = rho S_t A_p^2, which none of the four fitted multipliers
      moves, so the sized start can never draw the unsized device plus the effect.  Where the
      fluid start was sized for its force alone (the stroke fits the device as given, the
      stroke factor is 1), the device as given is a start too (``sizing='preset'``).
      Where the stroke does not fit the device as given, no other start is tried: the
      device had to be sized, and the published designs say nothing of a sized device's
      channel.
    * its *channel*: the fit varies the air ratios and losses, not the channel inertance
      S_t; the inertance refinement probes it near its value, and whether a local fit then
      reaches another design's channel depends on the effect in the residual, not on a
      ratio: one calibration frequency hardly identifies S_t, which trades off against the
      air ratios and c1 (session 10: Device A's channel, x1.8 of the reference, was reached
      from the reference's on the records without an effect and not on those with a relief
      valve, friction or a digressive valve, where the refit stopped at x1.0-1.1 and the
      effect then scored 0.003).  So each published design's channel other than the
      device's own (Table 3: Device B, the spring and the damper designs at S_t x0.1 of the
      reference, the reference, Device A at x1.8) is a start too, on the device given
      otherwise, not sized (an elastomer beside a Device B channel is otherwise fitted from
      the reference channel into a basin where the elastomer's branch stands in for the
      fluid: held-out 0.37 against 0.13 from the Device B channel).
    * its *air*: the fitted air multipliers span [0.05, 20] of the start's, so no fit from
      a device with air reaches the family's air-free limit (eqs. 19-20, the inerter design,
      air ratio 1e-5): there a rod mass stands in for the missing fluid inertia (a rigid
      device's force is b_L a + losses; session 10: a 636 kg ``moving_mass`` added first on
      every record of an inerter-like device, the null record too).  So the air-free
      designs are starts too, with their channel and air ratios (:func:`airfree_designs`).
    * its *stroke datum*: the record's mean stroke is taken as the mid-position where the
      chambers hold V01 and V02; a record about a mean m off the mid-position its LVDT was
      zeroed at has chambers of V01 - A_p m and V02 + A_p m, the force moved by up to
      |m| / L (28 % at -10 mm of 25 mm on the reference design), and the effect the records
      hold is invisible until the chambers are right (session 11: a leakage record about
      -10 mm diagnosed as a groove and a digressive valve).  So the device with its
      chambers about the record's zero is a start too, where |m| / L exceeds the loop's
      calibration residual and the chambers can hold the stroke there
      (:func:`~liquidamp.analysis.measured.stroke_datum.datum_start`).

    Each is diagnosed one step first (its best first effect); a published design's start
    runs that step's refits and device refinement first, without restarts: where neither its
    baseline nor any of them predicts any held-out record within the rule's tolerance of the
    model held, the rest of the round is not run (:func:`screened`; the fits one at a time,
    none after the first within the tolerance, and the score tests that rank them without
    the Newton shooting: a probe the march does not bring to its orbit is not scored).
    Only where the one-step model passes the selection rule against the model held
    (:func:`passes`) is its loop continued, and its final model replaces the model held
    only where it passes the rule against it, in turn (so every alternative must beat the
    best model so far). An alternative whose baseline the records cannot support
    (:func:`unsupported`: a fluid device sized far from the one given with its fluid at a
    bound, as on a friction damper's records) is reported, not diagnosed.

The friction start's fluid level (:func:`friction_alternatives`)
    The friction start holds its fluid at one of two levels, the calibration records' noise
    floor or negligible (:func:`~liquidamp.analysis.measured.device_class.fluid_levels`),
    chosen on the bare baselines (held-out records first, then the effective-sample BIC);
    its fit varies the friction only, so no fit moves the fluid it holds.  An effect
    found later changes which level the records support: a friction damper with a dead
    band read from the bare start with a fluid at the noise floor of the 0.5 Hz record (a
    viscous force that doubles with the rate) predicts the 1 Hz record with 0.147, from
    the negligible fluid with 0.132 (the real friction-damper records), while after the
    first effect (the friction's asymmetry) the two levels are alike (0.175, 0.174).  So
    the level not chosen is a start too, its whole loop run (not gated on its first step
    as the fluid family's other starts are) and its final model judged against the held
    one's by the selection rule.

The price is a second loop where the class was in doubt or the first loop ends above the
noise level; nothing changes where the first loop reached the noise floor.

References
----------
.. [1] R. E. Kass, A. E. Raftery, "Bayes factors", JASA 90(430), 1995, Sec. 4
   (BIC for non-nested models).
"""

from __future__ import annotations

import dataclasses
import math

from liquidamp.analysis.measured.device_class import (
    BIC_STRONG,
    StartOutcome,
    fluid_levels,
    friction_start,
    read_loop,
)
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record, judge_fits
from liquidamp.analysis.measured.start import stroke_factor
from liquidamp.analysis.measured.stroke_datum import datum_start
from liquidamp.errors import LiquidampError

__all__ = ["runner_up", "design_channels", "airfree_designs", "fluid_alternatives",
           "friction_alternatives",
           "alternative_outcome", "unsupported", "UNSUPPORTED", "passes", "revisit",
           "revisit_starts", "screened"]

#: Least air ratio of a design "with air": the inerter design (1e-5) is the family's
#: air-free limit (eqs. 19-20), the damper design (0.015) the least air of the others [-].
_AIR = 1e-3


def runner_up(baseline, run: dict, noise_level: float) -> str:
    """The continued start to diagnose as well ('' when none; module docstring).

    Parameters
    ----------
    baseline : CalibrationResult
        The chosen start's calibration (its ``class_starts``).
    run : dict
        The loop's state from the chosen start (``current``: the final fit).
    noise_level : float
        Calibration NRMSE at or below which the residual is noise [-].

    Returns
    -------
    str
        The runner-up class: among the continued starts not chosen whose BIC is within
        ``BIC_STRONG`` of the chosen one's, the best held out.
    """
    if run["current"].nrmse_calibration <= noise_level:
        return ""
    starts = getattr(baseline, "class_starts", ())
    chosen = next((o for o in starts if o.chosen), None)
    others = [o for o in starts if o.continued and not o.chosen
              and o.nrmse_validation is not None
              and (chosen is None or chosen.bic is None or o.bic is None
                   or o.bic - chosen.bic < BIC_STRONG)]
    if not others:
        return ""
    return min(others, key=lambda o: o.nrmse_validation).name


def design_channels() -> tuple[float, ...]:
    """Channel inertances of the family's published designs with air (air ratios of at least
    1e-3), as factors on the reference design's S_t [-], distinct and sorted (Table 3;
    module docstring).

    Examples
    --------
    >>> design_channels()
    (0.1, 1.0, 1.8)
    """
    from liquidamp.device import preset, preset_names

    ref = preset("reference").S_t
    out = set()
    for name in preset_names():
        p = preset(name)
        if min(p.inv_gamma1, p.inv_gamma2) >= _AIR and p.S_t > 0:
            out.add(round(p.S_t / ref, 6))
    return tuple(sorted(out))


def airfree_designs() -> tuple:
    """The family's published air-free designs (air ratio below 1e-3: the inerter, eqs.
    19-20), the starts of :func:`fluid_alternatives` that carry their air ratios (module
    docstring).

    Returns
    -------
    tuple of (str, float, float, float)
        ``(preset name, S_t [kg/m^4], inv_gamma1 [-], inv_gamma2 [-])`` of each.

    Examples
    --------
    >>> [(n, round(g1, 8)) for n, _, g1, _ in airfree_designs()]
    [('inerter', 9.75e-06)]
    """
    from liquidamp.device import preset, preset_names

    out = []
    for name in preset_names():
        p = preset(name)
        if min(p.inv_gamma1, p.inv_gamma2) < _AIR and p.S_t > 0:
            out.append((name, p.S_t, p.inv_gamma1, p.inv_gamma2))
    return tuple(out)


def fluid_alternatives(baseline, run: dict, noise_level: float, params,
                       sizing: str = "auto") -> list:
    """The fluid family's other starts to diagnose as well (module docstring).

    Parameters
    ----------
    baseline : CalibrationResult
        The chosen start's calibration (its ``class_starts``).
    run : dict
        The loop's state from the chosen start (``current``: the final fit).
    noise_level : float
        Calibration NRMSE at or below which the residual is noise [-] (nothing is tried
        then).
    params : DeviceParams
        The device the calibration was given.
    sizing : str
        The diagnosis's sizing choice ('preset': the device as given is the fluid start
        already, no other size is tried).

    Returns
    -------
    list of (str, dict)
        A label and the keywords of :func:`~liquidamp.analysis.measured.calibration.
        calibrate` (``params``, ``sizing``) for each start, in the order to try them.
    """
    starts = getattr(baseline, "class_starts", ())
    if run["current"].nrmse_calibration <= noise_level or params is None or not starts:
        return []  # at the noise, or the caller fixed the structure (no class choice)
    if getattr(baseline, "device_class", "") == "field":
        return []  # records with a control input: a fluid start does not read it
    fluid = next((o for o in starts if o.name == "fluid"), None)
    if sizing == "data" or stroke_factor(baseline.calibration, params) > 1.0:
        return []  # the device as given cannot take the stroke: sized for it, no other start
    out = []
    if fluid is not None and fluid.sized and sizing != "preset":
        out.append((f"fluid ({params.name or 'device'} as given, not sized)",
                    {"params": params, "sizing": "preset", "device_class": "fluid"}))
    if params.S_t > 0:
        from liquidamp.device import preset

        own = params.S_t / preset("reference").S_t
        for f in design_channels():
            if abs(math.log(f / own)) > 1e-6:  # every published channel but its own
                out.append((f"fluid (channel S_t x{f:g} of the reference design)",
                            {"params": params.replace(S_t=f * preset("reference").S_t,
                                                      name=f"{params.name or 'device'} "
                                                      f"with S_t x{f:g} of the reference"),
                             "sizing": "preset", "device_class": "fluid"}))
    # the record's zero as the chambers' mid-position (a record not centred on it:
    # liquidamp.analysis.measured.stroke_datum)
    moved = datum_start(params, baseline.calibration, run["current"].nrmse_calibration)
    if moved is not None:
        out.append((f"fluid ({moved.name})",
                    {"params": moved, "sizing": "preset", "device_class": "fluid"}))
    airy = min(params.inv_gamma1, params.inv_gamma2) >= _AIR
    for name, S_t, g1, g2 in airfree_designs() if airy else ():
        out.append((f"fluid ({name} design: air-free, channel S_t {S_t:.3g})",
                    {"params": params.replace(S_t=S_t, inv_gamma1=g1, inv_gamma2=g2,
                                              name=f"{params.name or 'device'} as the "
                                              f"{name} design"),
                     "sizing": "preset", "device_class": "fluid"}))
    return out


def friction_alternatives(baseline, run: dict, noise_level: float, params) -> list:
    """The friction start at the fluid level the class choice did not choose (module
    docstring).

    Parameters
    ----------
    baseline : CalibrationResult
        The chosen start's calibration (its ``device_class``, ``class_starts``,
        ``start_params`` and ``calibration`` records).
    run : dict
        The loop's state from the chosen start (``current``: the final fit).
    noise_level : float
        Calibration NRMSE at or below which the residual is noise [-] (nothing is tried
        then).
    params : DeviceParams
        The device the calibration was given (the friction start's reference).

    Returns
    -------
    list of (str, dict)
        A label and the keywords of :func:`~liquidamp.analysis.measured.calibration.
        calibrate` (``params``, ``effects``, ``spec``, ``start``, ``sizing``,
        ``device_class``) of the friction start at each fluid level other than the
        chosen one; empty where the friction start was not chosen, the caller fixed the
        structure, the records offer one level only, or the model held is at the noise.
    """
    starts = getattr(baseline, "class_starts", ())
    if (run["current"].nrmse_calibration <= noise_level or params is None or not starts
            or getattr(baseline, "device_class", "") != "friction"):
        return []
    records = tuple(baseline.calibration)
    levels = fluid_levels(records)
    if len(levels) < 2:
        return []
    reading = read_loop(records)
    chosen = getattr(baseline.start_params, "name", "") or ""
    out = []
    for share in levels:
        st = friction_start(params, baseline.effects, records, reading, fluid_share=share)
        if chosen.startswith(st.params.name):
            continue  # the level the class choice continued
        label = "the noise floor" if share is None else f"{share:.2g} of |K*|"
        out.append((f"friction (fluid at {label})",
                    {"params": st.params, "effects": st.effects, "spec": st.spec,
                     "start": "spec", "sizing": "preset", "device_class": "friction"}))
    return out if len(out) < len(levels) else []  # the chosen level not recognised: none


#: Plausibility findings that make a fluid start's baseline a device the records cannot
#: support (:mod:`~liquidamp.analysis.measured.plausibility`): its loop is not run.
UNSUPPORTED = ("fluid_unsupported", "piston_too_large")


def unsupported(result) -> str:
    """Why an alternative fluid start's baseline ``result`` is not diagnosed ('' when it is):
    its fitted geometry is one the records cannot support (a piston sized far from the
    device with the fluid at a bound, or too large for the force; :data:`UNSUPPORTED`)."""
    return "; ".join(f.message for f in getattr(result, "plausibility", ())
                     if f.kind in UNSUPPORTED)


def alternative_outcome(label: str, result, cls: str = "fluid") -> StartOutcome:
    """The :class:`StartOutcome` of an alternative start's baseline ``result``."""
    val = {e.label: e.nrmse for e in result.record_errors if e.role == "validation"}
    return StartOutcome(label, f"a start of the {cls} class beside the class choice's",
                        result.nrmse_calibration, result.nrmse_validation, val,
                        len(result.varying), None, True, False, result.nfev,
                        continued=True,
                        sized=bool(result.start.get("sized", False)))


def _verdict(run: dict, alt_run: dict, sel):
    a, b = run["current"], alt_run["current"]
    now, new = heldout_per_record(a), heldout_per_record(b)
    v = judge_fits(a, b, sel)
    return v, now, new


def passes(run: dict, alt_run: dict, sel) -> bool:
    """Whether ``alt_run``'s final model passes the selection rule ``sel`` against
    ``run``'s (as :func:`revisit` judges)."""
    return _verdict(run, alt_run, sel)[0].accepted


def revisit(run: dict, alt_run: dict, chosen: str, alt: str, sel, cls: str = "") -> dict:
    """The loop's state to report: ``alt_run`` where its final model passes the selection
    rule ``sel`` against ``run``'s (module docstring), else ``run``; a warning says which
    and why.  ``cls``: the device class of an alternative start that is not one of the
    class choice's (its outcome is added to ``class_starts``)."""
    v, now, new = _verdict(run, alt_run, sel)
    added = ", ".join(s.effect for s in alt_run["steps"]) or "nothing added"
    what = (f"the {alt} start diagnosed too ({added}; held-out "
            + ", ".join(f"{k} {new[k]:.3g}" for k in now) + f" against {chosen}'s "
            + ", ".join(f"{k} {now[k]:.3g}" for k in now)
            + f"; delta BIC {v.delta_bic:.4g} over N {v.n_effective:.4g})")
    if not v.accepted:
        run["warnings"].append(f"device class revisited: {what}; the {chosen} start is kept ("
                               + "; ".join(v.reasons) + ")")
        return run
    base = alt_run["baseline"]
    starts = tuple(dataclasses.replace(o, chosen=o.name == alt)
                   for o in run["baseline"].class_starts)
    if cls:
        starts += (dataclasses.replace(alternative_outcome(alt, base, cls), chosen=True),)
    alt_run = dict(alt_run, baseline=dataclasses.replace(base, class_starts=starts,
                                                         device_class=cls or alt))
    # the starts revisited before this one stay named (every start tried is reported)
    tried = [w for w in run["warnings"] if w.startswith("device class revisited: ")]
    alt_run["warnings"] = tried + [f"device class revisited: {what}: it passes the selection "
                                   f"rule, the {alt} start replaces the {chosen} start"
                                   ] + alt_run["warnings"]
    return alt_run


def screened(run: dict, base2, first, sel) -> str:
    """Why a published design's start does not run the rest of its first round ('' when it
    does): that round's refits first, without their restarts (module docstring, the fluid
    family's other starts).

    The step of a gated start (:func:`_alternative_loop`) is a whole round: the score test
    of every candidate, the refits of the best two or three, each restarted from the physics
    start where none reaches the noise, the device refinement and the profile (on d04's
    2 kHz records 22-42 s a start, half of it the restarts).  Its refits and the device
    refinement (the channel inertance freed, which can carry a start to another design's
    channel: session 10's A_elastomer, from S_t x0.1 to x1.8), each fitted once (``first``),
    show whether the start can win: the selection rule (:func:`passes`) needs every
    held-out record within its ``validation_tolerance`` of the model held, and session 10's
    held-out sweep had each start that replaced the model held do so with one effect or
    none, far better held out (d04's losing channel and air-free starts reached 0.077-0.57
    against 0.0035).  So where neither the alternative's baseline nor any of those refits
    predicts any held-out record within the tolerance of the model held, the restarts and
    the profile, and the rounds after the device refinement, are not run.  Anywhere else
    (one record within, no candidate to refit, every refit failed) the start is diagnosed
    as before.

    Parameters
    ----------
    run : dict
        The loop's state held (``current``: the model held).
    base2 : CalibrationResult
        The alternative start's baseline.
    first : callable
        ``first(baseline) -> iterable of (name, CalibrationResult)``: the candidates a round
        from ``baseline`` refits first, each refitted once (no restart), and its device
        refinement; taken one at a time, and no further once one does not miss (the
        start is diagnosed whatever the fits after it give).
    sel : SelectionRule
        Its ``validation_tolerance`` [-].

    Returns
    -------
    str
        The reason, with the held-out NRMSE per record of each model; '' to diagnose.
    """
    now = heldout_per_record(run["current"])
    tol = sel.validation_tolerance

    def misses(res) -> bool:
        new = heldout_per_record(res)
        return bool(now) and all(k in new and new[k] > (1.0 + tol) * now[k] for k in now)

    def shown(res) -> str:
        new = heldout_per_record(res)
        return ", ".join(f"{k} {new[k]:.3g}" for k in now)

    if not misses(base2):
        return ""
    got = []
    try:
        # one fit after the other (``first`` may yield them): the first that does not miss
        # decides, and the fits after it are not made (the start is diagnosed either way)
        for name, res in first(base2):
            if not misses(res):
                return ""
            got.append((name, res))
    except LiquidampError:
        return ""  # the screen could not be run: the start is diagnosed
    if not got:
        return ""
    held = ", ".join(f"{k} {v:.3g}" for k, v in now.items())
    refits = "; ".join(f"{name} {shown(res)}" for name, res in got)
    return (f"neither its baseline (held-out {shown(base2)}) nor its first round's fits "
            f"without restart (held-out {refits}) predict any held-out record within "
            f"{tol:.0%} of the model held ({held}): the rest of that round is not run")


def _alternative_loop(base2, run, gated: bool, loop, config) -> dict:
    """The loop from an alternative start.  ``gated`` (the fluid family's other starts): one
    step first, the rest only where that one-step model already passes the selection rule
    against the model held (``run``): a start is compared after its best first effect, and
    one that does not beat the model held then costs one round, not a whole loop."""
    if not gated:
        return loop(base2, config)
    bud = config.budget
    run1 = loop(base2, dataclasses.replace(config, budget=bud.replace(max_steps=1)))
    if (not run1["steps"] or bud.max_steps <= 1 or not run1["stop"].startswith("max_steps")
            or not passes(run, run1, config.selection)):
        return run1
    rest = dataclasses.replace(config, budget=bud.replace(max_steps=bud.max_steps - 1))
    run2 = loop(run1["current"], rest)
    return dict(run2, baseline=run1["baseline"], steps=run1["steps"] + run2["steps"],
                device_steps=run1["device_steps"] + run2["device_steps"],
                warnings=run1["warnings"] + run2["warnings"])


def revisit_starts(run: dict, baseline, level: float, params, config, fit, loop,
                   first=None) -> dict:
    """The loop's state after the other starts are diagnosed too (module docstring).

    Parameters
    ----------
    run : dict
        The loop's state from the chosen start.
    baseline : CalibrationResult
        The chosen start's calibration (its ``class_starts``).
    level : float
        Calibration NRMSE at or below which the residual is noise [-]: once the model held
        reaches it, no further start is tried.
    params : DeviceParams
        The device the calibration was given.
    config : DiagnoseOptions
        The diagnosis's options (``selection``, ``budget``, ``sizing``).
    fit : callable
        ``fit(keywords) -> CalibrationResult``: the baseline of a start (``keywords`` for
        :func:`~liquidamp.analysis.measured.calibration.calibrate`).
    loop : callable
        ``loop(baseline, config) -> dict``: the diagnosis loop from a baseline.
    first : callable, optional
        ``first(baseline) -> list of (effect name, CalibrationResult)``: the first refits
        of a round from a baseline, without restart, the screen of the published designs'
        starts (:func:`screened`); None: every such start runs its first round.

    Returns
    -------
    dict
        The loop's state to report; every start tried is named in its ``warnings``.
    """
    sel = config.selection
    alts = [(a, {"device_class": a, "sizing": config.sizing}, "")
            for a in (runner_up(baseline, run, level),) if a]
    alts += [(label, kw, "fluid") for label, kw in fluid_alternatives(
        baseline, run, level, params, config.sizing)]
    alts += [(label, kw, "friction") for label, kw in friction_alternatives(
        baseline, run, level, params)]
    for alt, kw, cls in alts:
        if run["current"].nrmse_calibration <= level:
            break  # the model held has reached the noise: nothing is left to explain
        try:
            base2 = fit(kw)
            why = unsupported(base2) if cls else ""
            if why:
                run["warnings"].append(f"device class revisited: the {alt} start is not "
                                       f"diagnosed: the records cannot support it ({why})")
                continue
            # a published design's start (another channel or the air-free design; not the
            # device as given, not sized, whose start is about the size) is screened first
            design = cls == "fluid" and kw.get("params") is not params
            why = screened(run, base2, first, sel) if design and first else ""
            if why:
                run["warnings"].append(f"device class revisited: the {alt} start is not "
                                       f"diagnosed: {why}")
                continue
            # the fluid family's other starts gated; the friction start at its other
            # fluid level differs from the start held by that level alone, which the
            # first effect hardly tells apart (module docstring): its whole loop
            run2 = _alternative_loop(base2, run, cls == "fluid", loop, config)
        except LiquidampError as exc:  # an alternative that cannot be run is reported
            run["warnings"].append(f"device class revisited: the {alt} start could not be "
                                   f"diagnosed ({exc})")
        else:
            run = revisit(run, run2, run["baseline"].device_class, alt, sel, cls)
    return run
