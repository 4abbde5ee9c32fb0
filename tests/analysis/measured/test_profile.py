"""The profile likelihood of a fitted parameter and the restart from its minimum
(:mod:`liquidamp.analysis.measured.profile`): a closed-form profile, and an elastomer's
parallel spring recovered from a synthetic record made with this toolkit's own model."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pytest

from liquidamp.analysis.measured.fit_spec import FitSpec, Parameter
from liquidamp.analysis.measured.profile import (
    PROFILE_LEVEL,
    profile_restart,
    undetermined_parameter,
)
from liquidamp.errors import ParameterError

NAME = "elastomer.parallel_stiffness_N_per_m"


@dataclass
class _Fit:
    """What profile_restart reads of a CalibrationResult."""

    spec: FitSpec
    cost: float
    n_samples: int = 100
    flags: object = None
    resid: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def varying(self):
        return self.spec.varying

    @property
    def values(self):
        return {p.name: p.value for p in self.spec.parameters if p.vary}

    def residuals(self, role="calibration"):
        return [self.resid]

    def at_bounds(self):
        return {}


def _closed_form(deviance, v_star, v0):
    """A fit whose profile deviance is ``deviance(v)`` exactly: C = 1 + D / 98 (N = 100,
    k = 2, white residuals, so s^2 = 2 C_min / 98); the free fit lands on ``v_star``."""
    rng = np.random.default_rng(0)
    resid = rng.normal(size=4000)  # white: no correlation inflation

    def cost(v):
        return 1.0 + deviance(v) / 98.0

    def at(spec, v):
        return _Fit(spec.with_values({NAME: v, "c1": 1.0 + 0.1 * math.log(v)}), cost(v),
                    resid=resid)

    def fit(spec):  # held: the profile's point; free: where the optimizer lands
        v = spec[NAME].value
        return at(spec, v_star(v) if spec[NAME].vary else v)

    spec = FitSpec((Parameter("c1", 1.0, 0.05, 20.0),
                    Parameter(NAME, v0, 1e-3, 1e3)))
    return at(spec, v0), fit


def test_profile_finds_the_valley_minimum_and_its_likelihood_interval():
    # D(v) = 4 ln(v / 2)^2: the 95 % interval |ln(v/2)| <= sqrt(3.841 / 4), [0.75, 5.33];
    # the fit stopped at 1 (D = 1.9), where a least-squares fit on a flat valley can stop
    def dev(v):
        return 4.0 * math.log(v / 2.0) ** 2

    result, fit = _closed_form(dev, lambda v: 2.0, 1.0)
    out, prof = profile_restart(result, NAME, fit)
    assert prof.restarted and out.values[NAME] == 2.0 and out.cost == 1.0
    assert prof.best == 2.0
    lo_exact = 2.0 * math.exp(-math.sqrt(PROFILE_LEVEL / 4.0))
    hi_exact = 2.0 * math.exp(math.sqrt(PROFILE_LEVEL / 4.0))
    lo, hi = prof.interval
    # outer bounds: the first grid value beyond the interval, one grid step (10^0.25) out
    assert lo_exact / 10 ** 0.25 <= lo < lo_exact and hi_exact < hi <= hi_exact * 10 ** 0.25
    assert prof.determined
    d = dict(zip(prof.values, prof.deviance, strict=True))
    assert d[2.0] == 0.0
    # D measured from the true minimum, s^2 = 2 C_min / (N - k) (white residuals: N_eff ~ N)
    assert prof.s2 == pytest.approx(2.0 / 98.0, rel=0.05)
    assert d[1.0] == pytest.approx(dev(1.0), rel=0.05)
    # the step was halved twice about the grid's least cost: a point within 10^(1/16) of 2
    assert min(abs(math.log(v / 2.0)) for v in prof.values if v != 2.0) < math.log(10) / 16


def test_a_flat_side_is_reported_open_and_the_fit_is_kept():
    # flat below 2 (the records cannot tell these values apart), rising above; the free fit
    # stays where it starts (a stalled optimizer): no restart, the low side open
    def dev(v):
        return 0.0 if v <= 2.0 else 40.0 * math.log(v / 2.0) ** 2

    result, fit = _closed_form(dev, lambda v: v, 0.5)
    out, prof = profile_restart(result, NAME, fit)
    assert out is result and not prof.restarted
    assert prof.open_low and not prof.open_high and not prof.determined
    assert prof.interval[0] == pytest.approx(0.05)  # a decade below the fit: the scan's end
    assert 2.0 * math.exp(math.sqrt(PROFILE_LEVEL / 40.0)) < prof.interval[1] < 5.01
    assert max(prof.values) < 5.01  # the scan stopped at the first D > 3.84 above
    assert "do not bound it below" in prof.describe()


def test_undetermined_parameter_and_bad_input():
    result, fit = _closed_form(lambda v: 0.0, lambda v: v, 0.5)

    class Flags:
        undetermined = {NAME: (0.5, 2.0), "c1": (1.0, 1.5)}

    result.flags = Flags()
    assert undetermined_parameter(result, [NAME]) == NAME
    assert undetermined_parameter(result, [NAME, "c1"]) == NAME  # se/value 4 beats 1.5
    assert undetermined_parameter(result, ["c1"]) == "c1"
    Flags.undetermined = {}
    assert undetermined_parameter(result, [NAME]) == ""
    with pytest.raises(ParameterError, match="not fitted in log space"):
        profile_restart(result, "c2", fit)
    with pytest.raises(ParameterError, match="span"):
        profile_restart(result, NAME, fit, span=1.1)


def test_elastomer_parallel_spring_from_a_stroke_with_a_strong_third_harmonic():
    """A synthetic 2 Hz, 3.5 mm record of the independent d03 device (Table 3 Device B,
    perturbed) with an elastomer k_e 20 kN/m parallel to a Maxwell branch 40 kN/m, 1.82 kN
    s/m (relaxation 45 ms), made with this toolkit's model; its stroke carries a 10 % third
    harmonic.  The parallel spring and a slower Maxwell branch give the same stiffness at
    2 Hz; only the branch's frequency law at 6 Hz tells them apart.  With a 10 % harmonic
    the fit from a start a decade low (k_e 1.5 kN/m, as the diagnosis's probe) finds k_e
    within 5 % and its 95 % profile interval is closed and within 15 %; with the 1 % of
    the shared records the same profile stays below D = 3.84 down to a tenth of the value
    on most noise seeds (the record does not bound it below: Profile.open_low).

    The least-squares minimum of this noise seed is itself 5.5 % high: with k_e held at the
    truth and the rest refitted the cost is 4.191e-5, at the fit's 21.2 kN/m 4.145e-5, and a
    free fit started at the truth goes to 21.1 kN/m (4.144e-5); session 9's Jacobian (its
    columns from the base point's orbits) stops at 21.2 kN/m, session 8's chained one
    stopped nearer the truth by chance.  Hence 7 % on the point, the truth inside the closed
    95 % interval, the interval within 15 %."""
    from liquidamp.analysis.measured.calibration import calibrate
    from liquidamp.analysis.measured.conditioning import condition
    from liquidamp.analysis.measured.synthetic import synthetic_record
    from liquidamp.device import preset
    from liquidamp.device.effects import EFFECTS

    mult = {"inv_gamma1": 1.9, "inv_gamma2": 2.16, "c1": 0.33, "c2": 0.285, "S_t": 0.12}
    truth = {"parallel_stiffness_N_per_m": 2e4, "branch_stiffness_N_per_m": 4e4,
             "branch_damping_N_s_per_m": 1819.0}
    rec = synthetic_record(preset="reference", multipliers=mult, effects={"elastomer": truth},
                           frequency=2.0, amplitude=0.0035, cycles=4, distortion=(0.0, 0.1),
                           force_noise=1.5, seed=3)
    cal, _ = condition(rec)
    base = preset("reference").scaled(**mult)
    start = EFFECTS["elastomer"](1500.0, 15000.0, 240.0)
    kw = {"params": base, "start": "spec", "sizing": "preset", "max_nfev": 300, "tol": 1e-5,
          "warn": False}
    res = calibrate([cal], effects=(start,), spec=FitSpec.default(effects=(start,)), **kw)
    out, prof = profile_restart(res, NAME, lambda s: calibrate([cal], effects=res.effects,
                                                               spec=s, **kw))
    k_e = out.values[NAME]
    assert k_e == pytest.approx(2e4, rel=0.07)
    assert prof.determined
    lo, hi = prof.interval
    assert 0.85 * 2e4 < lo < 2e4 < hi < 1.15 * 2e4 * 10 ** 0.25
    assert min(prof.deviance[0], prof.deviance[-1]) > PROFILE_LEVEL


def test_a_failed_profile_keeps_the_accepted_fit_and_says_so(monkeypatch):
    """The profile refines a fit the selection rule accepted: a library error in one of its
    refits leaves that fit standing, with a warning naming the effect and the error, instead
    of stopping the diagnosis (a gas charge's profile refit once ended a diagnosis with exit
    code 2).  Any other error is a bug and still propagates."""
    from liquidamp.analysis.measured import diagnosis_fits
    from liquidamp.analysis.measured.diagnosis_evidence import Candidate
    from liquidamp.analysis.measured.diagnosis_options import Budget, SelectionRule
    from liquidamp.errors import DataFileError

    def failing(*args, **kwargs):
        raise DataFileError("calibrate: rec.csv, line 230: displacement past the chamber end")

    monkeypatch.setattr(diagnosis_fits, "_profiled", failing)
    fit, cand, warnings = object(), Candidate("gas_charge", 0.7, 0.5, {}), []
    res, chosen, prof = diagnosis_fits._profile_step(
        fit, cand, {"gas_charge": None}, None, (), None, Budget(), SelectionRule(), warnings)
    assert res is fit and chosen is cand and prof is None
    assert len(warnings) == 1 and warnings[0].startswith("not profiled: gas_charge's fit kept")
    assert "line 230: displacement past the chamber end" in warnings[0]

    def buggy(*args, **kwargs):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(diagnosis_fits, "_profiled", buggy)
    with pytest.raises(ZeroDivisionError):
        diagnosis_fits._profile_step(fit, cand, {"gas_charge": None}, None, (), None,
                                     Budget(), SelectionRule(), [])
