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

The price is a second loop where the class was in doubt; nothing changes where it was
not (one continued start) or where the first loop reached the noise floor.

References
----------
.. [1] R. E. Kass, A. E. Raftery, "Bayes factors", JASA 90(430), 1995, Sec. 4
   (BIC for non-nested models).
"""

from __future__ import annotations

import dataclasses

from liquidamp.analysis.measured.device_class import BIC_STRONG
from liquidamp.analysis.measured.diagnosis_result import heldout_per_record
from liquidamp.analysis.measured.selection import judge, sample_count

__all__ = ["runner_up", "revisit"]


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


def revisit(run: dict, alt_run: dict, chosen: str, alt: str, sel) -> dict:
    """The loop's state to report: ``alt_run`` where its final model passes the selection
    rule ``sel`` against ``run``'s (module docstring), else ``run``; a warning says which
    and why."""
    a, b = run["current"], alt_run["current"]
    now, new = heldout_per_record(a), heldout_per_record(b)
    v = judge(a.residuals("calibration"), b.residuals("calibration"),
              len(b.varying) - len(a.varying), [now[k] for k in now], [new[k] for k in now],
              bic_threshold=sel.bic_threshold, validation_tolerance=sel.validation_tolerance,
              n_eff=sample_count(b.calibration, b.residuals("calibration"),
                                 sel.sample_count))
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
    alt_run = dict(alt_run, baseline=dataclasses.replace(base, class_starts=starts,
                                                         device_class=alt))
    alt_run["warnings"] = [f"device class revisited: {what}: it passes the selection rule, "
                           f"the {alt} start replaces the {chosen} start"] + alt_run["warnings"]
    return alt_run
