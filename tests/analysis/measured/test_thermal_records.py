"""Records of a warming device (issue #20 items 5 and 7): marched over the whole record.

* A record made by LSODA (a third algorithm) from rest with self-heating is reproduced by
  ``simulate_record`` (start on the orbit held at the start temperature, then the march)
  to its noise, on both engines; a stationary model of the same device cannot.
* ``start="record"``: the start temperature estimated from the first cycles.
* A measured ``temperature`` channel drives the law: the record is reproduced from its
  channel; a channel 10 K off is not; a record without the channel is refused.
* Diagnosis: only a drifting record or one with a measured temperature proposes it.
"""

from types import SimpleNamespace

import numpy as np
import pytest

from liquidamp.analysis.measured.candidates import applicable, candidate_change
from liquidamp.analysis.measured.record_model import integrate, nrmse, simulate_record
from liquidamp.analysis.measured.records import Record
from liquidamp.device import preset
from liquidamp.device.effects import SelfHeating, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import LiquidampError
from liquidamp.options import resolve_options

P = preset("reference")
HEAT = SelfHeating(heat_capacity_J_per_K=1.5, conductance_W_per_K=0.5, beta_per_K=0.03,
                   c2_exponent=0.25)
F_HZ, Y = 3.0, 0.003
NOISE = 1.5


@pytest.fixture(scope="module")
def warming():
    """6 s of a 3 Hz stroke from rest, kept from 1 s: the force fades as the fluid warms."""
    m = with_effects(get_model("full"), HEAT)
    w = 2 * np.pi * F_HZ
    t = np.arange(0.0, 6.0, 1 / 200.0)

    def stroke(tt):
        return Y * np.sin(w * tt), Y * w * np.cos(w * tt), -Y * w * w * np.sin(w * tt)

    X = integrate(m, P, stroke, t, m.initial_state(P, 0.0), rtol=1e-9, atol_scale=1e-10)
    F = np.asarray(m.force(t, X, stroke(t), P))
    keep = t >= 1.0
    rng = np.random.default_rng(5)
    T = X[-1]
    rec = Record.from_arrays(t[keep], stroke(t[keep])[0], F[keep] + rng.normal(0, NOISE,
                                                                             keep.sum()),
                             channels={"temperature": T[keep]}, source="warming.csv")
    # the record's own span (its first and last Savitzky-Golay half-windows trimmed)
    return rec, float(np.interp(rec.time[0], t, T)), float(np.interp(rec.time[-1], t, T))


def _fit_options(engine="compiled"):
    return resolve_options(None, "fit").replace(engine=engine)


@pytest.mark.parametrize("engine", ["compiled", "scipy"])
def test_a_warming_record_is_reproduced_by_the_march(warming, engine):
    rec, T0, T1 = warming
    assert T1 - T0 > 5.0  # it warms
    floor = NOISE / np.std(rec.force)
    m = with_effects(get_model("full"), HEAT.replace(initial_temperature_K=T0))
    r = simulate_record(m, P, rec, options=_fit_options(engine))
    assert "marched over the whole record" in r.message
    assert nrmse(r.force, rec.force) < 1.1 * floor
    assert r.states[-1, -1] == pytest.approx(T1, abs=0.05)
    # the device held at its start temperature (a stationary model) misses the fade
    held = simulate_record("full", P.scaled(c1=HEAT.viscosity_ratio(T0)), rec)
    assert nrmse(held.force, rec.force) > 5 * floor


def test_an_averaged_record_is_refused(warming):
    from liquidamp.analysis.measured.conditioning import condition

    rec = warming[0]
    avg = condition(rec, average=True)[0]
    m = with_effects(get_model("full"), HEAT)
    with pytest.raises(LiquidampError, match="average=False"):
        simulate_record(m, P, avg, options=_fit_options())


def test_start_temperature_estimated_from_the_first_cycles(warming):
    rec, T0, _ = warming
    m = with_effects(get_model("full"), HEAT.replace(start="record"))
    r = simulate_record(m, P, rec, options=_fit_options())
    assert r.solver_stats["start_temperature [K]"] == pytest.approx(T0, abs=0.3)
    assert nrmse(r.force, rec.force) < 1.1 * NOISE / np.std(rec.force)
    # the next call (a fit's next parameters) refines from the record's last estimate by
    # Newton steps: the same minimum; a device 5 % stiffer in losses starts warmer
    again = simulate_record(m, P, rec, options=_fit_options())
    assert again.solver_stats["start_temperature [K]"] == pytest.approx(
        r.solver_stats["start_temperature [K]"], abs=0.05)
    lossy = simulate_record(m, P.scaled(c1=1.05, c2=1.05), rec, options=_fit_options())
    assert lossy.solver_stats["start_temperature [K]"] > T0 + 1.0


def test_a_measured_temperature_drives_the_law(warming):
    rec, T0, _ = warming
    floor = NOISE / np.std(rec.force)
    # the heat balance's own parameters do not matter: the channel drives the law
    m = with_effects(get_model("full"), HEAT.replace(temperature="measured",
                                                     heat_capacity_J_per_K=100.0))
    assert m.input_channels == ("temperature",)
    r = simulate_record(m, P, rec, options=_fit_options())
    assert nrmse(r.force, rec.force) < 1.1 * floor
    off = Record.from_arrays(rec.time, rec.displacement, rec.force,
                             channels={"temperature": rec.channels["temperature"] + 10.0})
    assert nrmse(simulate_record(m, P, off, options=_fit_options()).force, off.force) > 5 * floor
    bare = Record.from_arrays(rec.time, rec.displacement, rec.force)
    with pytest.raises(LiquidampError, match="temperature"):
        simulate_record(m, P, bare, options=_fit_options())


def test_only_a_drift_or_a_temperature_proposes_self_heating(warming):
    rec, _, _ = warming
    t = rec.time
    steady = Record.from_arrays(t, rec.displacement, 500 * np.cos(2 * np.pi * F_HZ * t)
                                + np.random.default_rng(1).normal(0, NOISE, t.size))
    model = get_model("full")

    def result(*recs):
        return SimpleNamespace(calibration=recs, validation=(), device_model=model,
                               effects=(), params=P)

    assert "proposed only by" in applicable("self_heating", result(steady))
    no_channel = Record.from_arrays(t, rec.displacement, rec.force)
    assert applicable("self_heating", result(no_channel)) == ""  # it drifts
    assert applicable("self_heating", result(rec)) == ""
    # with the temperature measured beta is freed, without it the heat capacity and
    # conductance (and each record's start temperature is its own)
    c = candidate_change("self_heating", result(rec))
    assert c.free == (("self_heating", "beta_per_K"),) and c.lead[1] == "beta_per_K"
    assert c.effect("self_heating").temperature == "measured"
    c = candidate_change("self_heating", result(no_channel))
    assert {k for _, k in c.free} == {"heat_capacity_J_per_K", "conductance_W_per_K"}
    assert c.effect("self_heating").start == "record"


def test_a_step_reports_only_the_parameters_its_refit_varied():
    """With a measured temperature only beta is fitted: the summary's step must not
    present the thermal state's default heat capacity and conductance as findings."""
    from liquidamp.analysis.measured.diagnosis_result import Step

    params = {"heat_capacity_J_per_K": 4.83, "conductance_W_per_K": 0.483,
              "beta_per_K": 0.0303}
    measured = Step("self_heating", params, 0.007, 0.02, (),
                    result=SimpleNamespace(varying=("self_heating.beta_per_K",)))
    assert measured.fitted_parameters() == {"beta_per_K": 0.0303}
    state = Step("self_heating", params, 0.007, 0.02, (),
                 result=SimpleNamespace(varying=("self_heating.heat_capacity_J_per_K",
                                                 "self_heating.conductance_W_per_K")))
    assert list(state.fitted_parameters()) == ["heat_capacity_J_per_K",
                                               "conductance_W_per_K"]
    # a step with no refit kept reports everything it holds
    assert Step("self_heating", params, 0.007, 0.02, ()).fitted_parameters() == params
