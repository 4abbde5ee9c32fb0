"""The fluid family's other starts diagnosed beside the class choice (issue 19, items 2-4).

The class choice judges its starts before any effect.  Two things the fluid start holds fixed
can put an undeclared effect out of reach: its size (sized for a force that end-stop spikes
inflate, it carries a times the fluid inertance) and its channel (the fit never moves S_t by a
decade, and Table 3's Device B channel is a decade below the reference's).
:func:`~liquidamp.analysis.measured.class_revisit.fluid_alternatives` lists those starts and
the diagnosis judges each by its selection rule.

Cost: the unit checks well under a second; the two records made by the toolkit's own model
(a reference device with end stops, a Device B device with an elastomer) about 15 s each on
an idle machine (``slow``).  Both chose the friction start and missed the effect under the
old rule (end stops: nothing added, held-out 0.51; elastomer: the friction class).  The shared
d03 record (an independent simulator's) runs only with ``LIQUIDAMP_INDEPENDENT=all``.
"""

import dataclasses
import json
import os
from types import SimpleNamespace

import numpy as np
import pytest

from liquidamp.analysis.measured.class_revisit import (
    design_channels,
    fluid_alternatives,
    revisit,
)
from liquidamp.analysis.measured.device_class import StartOutcome
from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.diagnosis_options import SelectionRule
from liquidamp.analysis.measured.records import Record, read_record
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.device import preset


def test_design_channels_are_the_families_with_air():
    # Table 3: Device B, spring and damper at S_t x0.1 of the reference; Device A x1.8; the
    # inerter (x7) has air ratios of 1e-5, the family's air-free limit, and is left out
    ch = design_channels()
    assert ch == (0.1, 1.0, 1.8)
    ref = preset("reference").S_t
    assert preset("device_b").S_t / ref == pytest.approx(ch[0])
    assert preset("device_a").S_t / ref == pytest.approx(ch[2])


def _baseline(sized: bool, amplitude: float = 0.003):
    t = np.arange(0, 2.0, 0.005)
    rec = Record.from_arrays(t, amplitude * np.sin(2 * np.pi * 2 * t),
                             1e3 * np.sin(2 * np.pi * 2 * t))
    starts = (StartOutcome("fluid", "", 0.5, 0.7, {}, 4, 10.0, True, False, 20,
                           continued=True, sized=sized),
              StartOutcome("friction", "", 0.4, 0.5, {}, 2, 0.0, True, True, 20,
                           continued=True))
    return SimpleNamespace(calibration=(rec,), class_starts=starts)


def test_fluid_alternatives_follow_the_size_and_the_channel():
    p = preset("paper_initial")
    above = {"current": SimpleNamespace(nrmse_calibration=0.4)}
    labels = [(a, kw["sizing"], kw["params"].S_t / preset("reference").S_t)
              for a, kw in fluid_alternatives(_baseline(True), above, 0.01, p)]
    # sized for its force (the 3 mm stroke fits paper_initial's 25 mm chamber): as given,
    # unsized; every other published channel (Device B's x0.1, Device A's x1.8; x1 is
    # paper_initial's own, the reference's); the air-free inerter design with its air
    ref = preset("reference").S_t
    assert labels[0][1:] == ("preset", 1.0) and "as given" in labels[0][0]
    assert [lab[1:] for lab in labels[1:3]] == [("preset", pytest.approx(0.1)),
                                                ("preset", pytest.approx(1.8))]
    assert labels[3][1:] == ("preset", pytest.approx(7.0)) and len(labels) == 4
    air = fluid_alternatives(_baseline(True), above, 0.01, p)[3][1]["params"]
    assert "air-free" in fluid_alternatives(_baseline(True), above, 0.01, p)[3][0]
    assert air.inv_gamma1 == preset("inerter").inv_gamma1 and air.A_p == p.A_p
    # not sized: the device as given is the fluid start already; the design starts stay
    alts = fluid_alternatives(_baseline(False), above, 0.01, p)
    assert [kw["params"].S_t / p.S_t for _, kw in alts] == [pytest.approx(0.1),
                                                            pytest.approx(1.8),
                                                            pytest.approx(7.0)]
    # sized for the stroke (15 mm past half of the 25 mm chamber): the device as given
    # cannot take it, no other start (a friction damper's 12.7 mm on paper_initial)
    assert fluid_alternatives(_baseline(True, 0.015), above, 0.01, p) == []
    assert fluid_alternatives(_baseline(False), above, 0.01, p, sizing="data") == []
    # a device on Device B's channel: the reference's and Device A's channels
    b = preset("device_b")
    alts = fluid_alternatives(_baseline(False), above, 0.01, b)
    got = sorted(round(kw["params"].S_t / ref, 6) for _, kw in alts)
    assert got == [1.0, 1.8, 7.0]
    # a channel between the designs' (x0.198): every published channel is a start (a
    # local fit's reach depends on the effect in the residual, not on a ratio)
    near = p.replace(S_t=p.S_t * 0.198)
    alts = fluid_alternatives(_baseline(False), above, 0.01, near)
    assert [round(kw["params"].S_t / ref, 6) for _, kw in alts] == [0.1, 1.0, 1.8, 7.0]
    # an air-free device given: no air-free start again
    alts = fluid_alternatives(_baseline(False), above, 0.01, preset("inerter"))
    assert [round(kw["params"].S_t / ref, 6) for _, kw in alts] == [0.1, 1.0, 1.8]
    # at the noise, or without a class choice (a fixed structure): nothing
    at_noise = {"current": SimpleNamespace(nrmse_calibration=0.005)}
    assert fluid_alternatives(_baseline(True), at_noise, 0.01, p) == []
    fixed = SimpleNamespace(calibration=_baseline(True).calibration, class_starts=())
    assert fluid_alternatives(fixed, above, 0.01, p) == []


@dataclasses.dataclass(frozen=True)
class _Fit:
    res: tuple
    heldout: dict
    varying: tuple
    nrmse_calibration: float = 0.1
    nrmse_validation: float = 0.1
    class_starts: tuple = ()
    device_class: str = ""
    nfev: int = 7
    start: dict = dataclasses.field(default_factory=dict)

    @property
    def calibration(self):
        return tuple(SimpleNamespace(time=np.arange(r.size) * 0.01, meta={}) for r in self.res)

    def residuals(self, role):
        return self.res

    @property
    def record_errors(self):
        return tuple(SimpleNamespace(role="validation", label=k, nrmse=v)
                     for k, v in self.heldout.items())


def test_an_alternative_start_that_passes_the_rule_is_reported_as_fluid():
    e = np.random.default_rng(3).normal(size=200)
    starts = (StartOutcome("friction", "", 0.2, 0.21, {"v": 0.21}, 2, 0.0, True, True, 9),)
    a = _Fit((2.0 * e,), {"v": 0.21}, ("x", "y"), class_starts=starts,
             device_class="friction")
    b = _Fit((0.02 * e,), {"v": 0.01}, tuple("abcdefg"), nrmse_validation=0.01)
    run = {"baseline": a, "current": a, "steps": [], "warnings": []}
    alt = {"baseline": b, "current": b, "steps": [SimpleNamespace(effect="end_stops")],
           "warnings": []}
    label = "fluid (paper_initial as given, not sized)"
    out = revisit(run, alt, "friction", label, SelectionRule(), "fluid")
    assert out["current"] is b
    assert out["baseline"].device_class == "fluid"
    chosen = [o for o in out["baseline"].class_starts if o.chosen]
    assert [o.name for o in chosen] == [label] and chosen[0].nrmse_validation == 0.01
    assert "replaces the friction start" in out["warnings"][0]
    # worse held out: the friction start stays, its class unchanged
    worse = {"baseline": b, "current": dataclasses.replace(b, heldout={"v": 0.3}),
             "steps": [], "warnings": []}
    out = revisit(run, worse, "friction", label, SelectionRule(), "fluid")
    assert out["current"] is a and out["baseline"].device_class == "friction"


_STOPS = {"end_stops": {"stiffness_N_per_m": 2e6, "clearance_m": 0.0032,
                        "damping_N_s_per_m": 300.0}}
_ELASTOMER = {"elastomer": {"parallel_stiffness_N_per_m": 2e4, "branch_stiffness_N_per_m": 4e4,
                            "branch_damping_N_s_per_m": 1800.0}}


@pytest.mark.slow
@pytest.mark.parametrize("case", ["end_stops", "elastomer"])
def test_default_diagnosis_finds_the_fluid_class_and_the_effect(case):
    # records made by the toolkit's own model: a reference design with end stops at 3.2 mm
    # under 3.5 and 3.35 mm strokes (the old rule: friction start, nothing added, held-out
    # 0.51), and a Device B design with an elastomer (the old rule: the friction start)
    if case == "end_stops":
        common = dict(preset="reference", effects=_STOPS, cycles=5, force_noise=1.5,
                      multipliers=(("inv_gamma1", 1.06), ("inv_gamma2", 0.9), ("c1", 0.95),
                                   ("c2", 1.1), ("S_t", 0.9)))
        cal = synthetic_record(frequency=1.5, amplitude=0.0035, seed=41, **common)
        val = synthetic_record(frequency=2.5, amplitude=0.00335, seed=42, **common)
        key, truth = "clearance_m", 0.0032
    else:
        common = dict(preset="device_b", effects=_ELASTOMER, cycles=5, force_noise=1.5,
                      multipliers=(("inv_gamma1", 0.95), ("inv_gamma2", 1.08), ("c1", 1.1),
                                   ("c2", 0.95), ("S_t", 1.2)))
        cal = synthetic_record(frequency=2.0, amplitude=0.0035, seed=43, **common)
        val = synthetic_record(frequency=5.0, amplitude=0.0018, seed=44, **common)
        key, truth = "parallel_stiffness_N_per_m", 2e4
    d = diagnose([cal], [val], max_steps=1)
    assert d.baseline.device_class == "fluid", d.summary()
    assert d.added == (case,), d.summary()
    assert d.steps[0].parameters[key] == pytest.approx(truth, rel=0.3)
    assert d.final.nrmse_validation <= 0.5 * d.baseline.nrmse_validation
    # the friction start the old rule chose is still reported beside it
    assert any(o.name == "friction" and not o.chosen for o in d.baseline.class_starts)


@pytest.mark.parametrize("case", ["d03_elastomer", "d04_end_stops_2kHz"])
def test_shared_records_are_read_as_a_fluid_device(independent_records, case):
    if os.environ.get("LIQUIDAMP_INDEPENDENT") != "all":
        pytest.skip("long held-out check: set LIQUIDAMP_INDEPENDENT=all to run it")
    d = diagnose([read_record(independent_records / f"{case}_cal.csv")],
                 [read_record(independent_records / f"{case}_val.csv")])
    truth = json.loads((independent_records / "truth.json").read_text())[case]
    # old rule: the friction start, nothing added (held-out 0.21 on d03, 0.537 on d04,
    # where the line F = c v + k y + F0 reaches 0.383)
    assert d.baseline.device_class == "fluid", d.summary()
    assert d.added[:1] == (case.split("_", 1)[1].replace("_2kHz", ""),), d.summary()
    assert d.final.nrmse_validation <= 0.5 * d.baseline.nrmse_validation
    assert d.final.nrmse_validation < 0.5 * {"d03_elastomer": 0.2096,
                                             "d04_end_stops_2kHz": 0.5367}[case]
    if case == "d04_end_stops_2kHz":
        clearance = truth["parameters"]["clearance (stroke where contact starts)"]["value"]
        assert d.steps[0].parameters["clearance_m"] == pytest.approx(clearance, rel=0.3)
    # d03's parallel stiffness: one 2 Hz record hardly determines it (the fit stopped at
    # 3.1 kN/m, standard error 28 kN/m); the profile over it (liquidamp.analysis.measured.
    # profile) restarts the fit from its minimum and reports its 95 % interval, which holds
    # the truth and is open below (the record does not bound k_e below: D < 2 at 0.3 kN/m)
    if case == "d03_elastomer":
        k_e = truth["parameters"]["parallel stiffness k_e"]["value"]
        prof = d.steps[0].profile
        assert prof and prof["open_low"], d.summary()
        assert prof["interval"][0] <= k_e <= prof["interval"][1]
        assert d.steps[0].parameters["parallel_stiffness_N_per_m"] == pytest.approx(k_e, rel=0.3)


def _friction_baseline(level, noise: float = 50.0, device_class: str = "friction",
                       v0: float = 1e-3):
    from liquidamp.analysis.measured.device_class import friction_start, read_loop

    t = np.arange(0, 8.0, 0.002)
    y = 0.01 * np.sin(2 * np.pi * t)
    F = 500.0 * np.tanh(np.gradient(y, t) / v0)
    F = F + noise * np.random.default_rng(1).standard_normal(t.size)
    rec = Record.from_arrays(t, y, F)
    params = preset("paper_initial")
    st = friction_start(params, (), [rec], read_loop([rec]), fluid_share=level)
    starts = (StartOutcome("friction", "", 0.2, 0.2, {}, 2, 0.0, True, True, 20,
                           continued=True),)
    base = SimpleNamespace(calibration=(rec,), class_starts=starts, device_class=device_class,
                           start_params=st.params, effects=st.effects)
    return base, params, rec


def test_friction_alternatives_offer_the_fluid_level_not_chosen():
    from liquidamp.analysis.measured.class_revisit import friction_alternatives
    from liquidamp.analysis.measured.device_class import FLUID_FLOOR
    from liquidamp.analysis.measured.record_quality import noise_floor
    from liquidamp.analysis.measured.start import linear_stiffness

    run = {"current": SimpleNamespace(nrmse_calibration=0.3)}
    base, params, rec = _friction_baseline(None)  # the noise floor chosen
    (label, kw), = friction_alternatives(base, run, 0.01, params)
    assert "0.001 of |K*|" in label
    assert kw["device_class"] == "friction" and kw["sizing"] == "preset"
    assert kw["start"] == "spec" and kw["spec"].varying == ("smooth_friction.force_N",
                                                            "smooth_friction.stiffness_N_per_m")
    # the alternative's fluid carries FLUID_FLOOR of |K*| where the chosen one carries the
    # record's noise floor: |K_fluid| in their ratio (both matched to their targets)
    Y = rec.stroke_scale
    k_alt = abs(linear_stiffness(kw["params"], rec.frequency, Y))
    k_held = abs(linear_stiffness(base.start_params, rec.frequency, Y))
    ratio = FLUID_FLOOR / noise_floor(rec).nrmse
    assert k_alt / k_held == pytest.approx(ratio, rel=0.05)
    # the other way round: the negligible fluid chosen, the noise floor offered
    base2, params, _ = _friction_baseline(FLUID_FLOOR)
    (label2, kw2), = friction_alternatives(base2, run, 0.01, params)
    assert "noise floor" in label2
    assert kw2["params"].name == base.start_params.name
    # nothing where the model held is at the noise, the class is not friction, or the
    # records offer one level (noise floor below FLUID_FLOOR)
    assert friction_alternatives(base, {"current": SimpleNamespace(nrmse_calibration=0.01)},
                                 0.01, params) == []
    fluid, params, _ = _friction_baseline(None, device_class="fluid")
    assert friction_alternatives(fluid, run, 0.01, params) == []
    clean, params, rec = _friction_baseline(None, noise=0.0, v0=0.02)
    assert noise_floor(rec).nrmse < FLUID_FLOOR
    assert friction_alternatives(clean, run, 0.01, params) == []
