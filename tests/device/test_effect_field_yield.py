"""Measured input channels and the field-dependent yield (issue #20 items 2 and 6).

* The mechanism: a record's channel reaches the compiled law at every stage, interpolated
  as the stroke is (compiled channel_eval against numpy), on both engines; a model that
  reads a channel its drive lacks is refused before any work, naming the effect, the
  channel and the channels there (record, analytic stroke, coupled host, linearization).
* Zero yield gives the passive device exactly (right-hand side, and a run on both engines).
* The field lag's response to a step of the input (a ramp over one sample interval): the
  closed form, on both engines.
* Rigid-fluid steady flow: F = A_p (dp_y(u) tanh(m/m_eps) + g1 m + g2 m |m|).
* Jacobian entries of the yield and the lag against their closed forms; the channel rate
  reaches d rhs/dt as eta du/dt.
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.analysis.measured.records import Record
from liquidamp.coupled._stroke_kernels import channel_eval
from liquidamp.coupled.testrig import simulate
from liquidamp.device import kernels as K
from liquidamp.device import preset
from liquidamp.device.effects import FieldYield, make_effect, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke, RecordedStroke

P = preset("reference").replace(p0=2e6)  # filled at 2 MPa, like an MR damper
FY = FieldYield(6e4, 2.2e5, 120.0, 5e-4)
MODEL = with_effects(get_model("full"), FY)
OPTS = {e: SolverOptions(engine=e, rtol=1e-9) for e in ("compiled", "scipy")}


def _record(duration=0.2, fs=2000.0, voltage=None):
    t = np.arange(0.0, duration, 1.0 / fs)
    y = 6e-4 * np.sin(2 * np.pi * 7.0 * t) + 5e-4 * np.sin(2 * np.pi * 16.3 * t + 1.0)
    u = np.where(t < 0.5 * duration, 0.4, 1.6) if voltage is None else voltage(t)
    return Record.from_arrays(t, y, 0.0 * t, channels={"voltage": u})


def test_channel_eval_interpolates_as_numpy_does():
    t = np.linspace(0.0, 1.0, 11)
    s = RecordedStroke(t, 0 * t, 0 * t, 0 * t, channels={"current": t ** 2})
    sa = np.concatenate([s.acceleration] + [s.channels.get(c, 0 * t) for c in K.CHANNELS])
    prm = np.zeros(K.N_PRM_ALL)
    k = K.channel_index("current")
    for tq in (-0.5, 0.0, 0.37, 0.55, 1.0, 2.0):
        channel_eval(1, tq, t, sa, prm)
        assert prm[K.P_CH + k] == pytest.approx(float(np.interp(tq, t, t ** 2)), abs=1e-15)
        assert prm[K.P_CHD + k] == pytest.approx(s.channel_rates(tq)["current"], abs=1e-12)
    assert prm[K.P_CH + K.channel_index("voltage")] == 0.0  # a channel not carried


def test_zero_yield_is_the_passive_device_exactly():
    x = MODEL.initial_state(P, 0.0).astype(float)
    x[0], x[2], x[4] = 2.1e6, 1.95e6, 3e-3
    bare = get_model("full")
    u = (1e-4, 0.02, 0.0, np.array([0.0, 1.3, 0.0, 0.0]))
    zero = with_effects(bare, FieldYield(0.0, 0.0, 120.0, 5e-4))
    np.testing.assert_array_equal(zero.rhs(0.0, x, u, P)[:5], bare.rhs(0.0, x[:5], u, P))
    with_yield = MODEL.rhs(0.0, x, u, P)
    dp_y = 6e4 + 2.2e5 * x[5]
    assert with_yield[4] == pytest.approx(bare.rhs(0.0, x[:5], u, P)[4]
                                          - dp_y * math.tanh(x[4] / 5e-4) / P.S_t, rel=1e-12)
    rec = _record()
    assert not rec.periodic  # both run from rest at the first sample
    passive = simulate_record(bare, P, rec, options=OPTS["compiled"]).force
    for engine in ("compiled", "scipy"):
        f = simulate_record(zero, P, rec, options=OPTS[engine]).force
        assert np.max(np.abs(f - passive)) < 1e-6 * np.max(np.abs(passive))


@pytest.mark.parametrize("engine", ["compiled", "scipy"])
def test_the_field_lag_follows_a_step_by_the_closed_form(engine):
    fs, eta = 2000.0, 120.0
    dt = 1.0 / fs
    ts = 0.05  # the input steps 0 -> 1 V over the sample interval [ts, ts + dt]
    rec = _record(duration=0.2, voltage=lambda t: np.where(t <= ts + 1e-9, 0.0, 1.0))
    r = simulate_record(MODEL, P, rec, options=OPTS[engine])
    uf = r.state("u_field")
    ramp_end = 1.0 - (1.0 - math.exp(-eta * dt)) / (eta * dt)  # u_f at ts + dt
    after = r.time > ts + dt + 1e-9
    expect = 1.0 - (1.0 - ramp_end) * np.exp(-eta * (r.time[after] - ts - dt))
    np.testing.assert_allclose(uf[after], expect, atol=2e-7)
    assert np.all(uf[r.time <= ts + 1e-9] == pytest.approx(0.0, abs=1e-6))  # settled at 0


def test_rigid_fluid_steady_flow_force_is_the_closed_form():
    # a slow ramp: the chambers' compliance settles, the flow is rho A_p v, the channel's
    # pressure balance is steady: F = A_p (dp_y tanh(m/m_eps) + g1 m + g2 m |m|)
    v = 0.02
    t = np.arange(0.0, 0.25, 5e-4)
    ramp = RecordedStroke(t, v * (t - t[-1] / 2), np.full(t.size, v), 0.0 * t,
                          channels={"voltage": np.full(t.size, 1.5)})
    x0 = MODEL.initial_state(P, float(ramp.displacement[0]))
    r = simulate(MODEL, P, ramp, float(t[-1]), x0=x0, options=OPTS["compiled"], t_eval=t)
    i = r.time.size - 40
    m = r.state("m12")[i]
    rho1 = r.state("rho1")[i]
    # steady flow: the piston's displacement less what the air takes up as p1 creeps up
    assert m == pytest.approx(rho1 * P.A_p * v, rel=1e-2)
    dp_y = 6e4 + 2.2e5 * 1.5
    closed = P.A_p * (dp_y * math.tanh(m / 5e-4) + P.g1 * m + P.g2 * m * abs(m))
    assert r.force[i] == pytest.approx(closed, rel=1e-4)
    assert dp_y * P.A_p / r.force[i] > 0.5  # the yield is most of it


def test_jacobian_and_time_derivative_closed_forms():
    x = MODEL.initial_state(P, 0.0).astype(float)
    x[0], x[2], x[4], x[5] = 2.1e6, 1.95e6, 2e-4, 0.8
    u = (1e-4, 0.02, 0.0, np.array([0.0, 1.3, 0.0, 0.0]))
    J = MODEL.jacobian(0.0, x, u, P)
    th = math.tanh(x[4] / 5e-4)
    dp_y = 6e4 + 2.2e5 * x[5]
    bare = get_model("full").jacobian(0.0, x[:5], u, P)
    assert J[4, 5] == pytest.approx(-2.2e5 * th / P.S_t, rel=1e-6)
    assert J[4, 4] == pytest.approx(bare[4, 4] - dp_y * (1 - th * th) / 5e-4 / P.S_t, rel=1e-6)
    assert J[5, 5] == pytest.approx(-120.0, rel=1e-9)
    np.testing.assert_allclose(J[:4, :5], bare[:4, :5], rtol=1e-6, atol=1e-9 * np.abs(bare).max())
    # the channel's rate reaches d rhs / dt: eta du/dt in the lag's row
    rt = MODEL.rhs_t(0.0, x, u, (0.0, 0.0, np.array([0.0, 50.0, 0.0, 0.0])), P)
    assert rt[5] == pytest.approx(120.0 * 50.0, rel=1e-6)
    # the analytic Jacobian against central differences of the right-hand side, on every
    # base the effect composes with (the compiled engine's RODAS4 uses it; scipy's Radau too)
    for base in ("full", "inertial", "inertial_2state"):
        m = with_effects(get_model(base), FY)
        assert m.analytic_jacobian
        xb = m.initial_state(P, 0.0).astype(float)
        xb[:-1] *= 1.0 + 0.01 * np.arange(1, xb.size)
        xb[m.state_names.index("m12") if "m12" in m.state_names else 1] = 2e-4 \
            if "m12" in m.state_names else 2e-7
        xb[-1] = 0.8
        Jb = m.jacobian(0.0, xb, u, P)
        sc = m.state_scales(P)
        for j in range(m.n_states):
            h = 1e-7 * max(abs(xb[j]), sc[j])
            xp, xm = xb.copy(), xb.copy()
            xp[j] += h
            xm[j] -= h
            fd = (m.rhs(0.0, xp, u, P) - m.rhs(0.0, xm, u, P)) / (2 * h)
            np.testing.assert_allclose(Jb[:, j], fd, rtol=1e-5,
                                       atol=1e-7 * np.max(np.abs(fd)) + 1e-300)


def test_both_engines_agree_under_a_switching_input():
    rec = _record(duration=0.2)
    a = simulate_record(MODEL, P, rec, options=OPTS["compiled"]).force
    b = simulate_record(MODEL, P, rec, options=OPTS["scipy"]).force
    assert np.max(np.abs(a - b)) < 1e-5 * np.max(np.abs(a))
    # the input matters: the same record at a constant 0.4 V gives another force
    c = simulate_record(MODEL, P, _record(duration=0.2, voltage=lambda t: 0.4 + 0 * t),
                        options=OPTS["compiled"]).force
    assert np.max(np.abs(a - c)) > 0.1 * np.max(np.abs(a))


def test_a_model_that_reads_a_channel_is_refused_where_none_is_carried():
    t = np.arange(0.0, 0.2, 5e-4)
    rec = Record.from_arrays(t, 8e-4 * np.sin(2 * np.pi * 7 * t), 0 * t,
                             channels={"temperature": 300 + 0 * t})
    with pytest.raises(ParameterError, match=r"'field_yield' reads the measured 'voltage' "
                                             r"channel.*channels there: temperature"):
        simulate_record(MODEL, P, rec)
    with pytest.raises(ParameterError, match="'field_yield'.*HarmonicStroke"):
        simulate(MODEL, P, HarmonicStroke(1e-3, 3.0), 0.1)
    with pytest.raises(ParameterError, match="'field_yield'.*without channel values"):
        MODEL.rhs(0.0, MODEL.initial_state(P, 0.0), (0.0, 0.0, 0.0), P)
    with pytest.raises(ParameterError, match="no equivalent linearization"):
        FY.describing_function(1e-3, 10.0, P, MODEL)
    with pytest.raises(ParameterError, match="no small-signal model"):
        FY.check_small_signal(P)
    # current instead of voltage: the record must carry a current
    cur = with_effects(get_model("full"), make_effect("field_yield", yield_pressure_Pa=1e4,
                                                      input="current"))
    assert cur.input_channels == ("current",)
    with pytest.raises(ParameterError, match="'current' channel"):
        simulate_record(cur, P, _record())
    with pytest.raises(ParameterError, match="lag_rate_per_s"):
        FieldYield(1e4, 0.0, 0.0)
    with pytest.raises(ParameterError, match="input must be one of"):
        FieldYield(1e4, input="temperature")


def test_a_coupled_host_refuses_a_model_that_reads_a_channel():
    from liquidamp.coupled.assembly import Device, rotor_system
    from liquidamp.coupled.compiled_route import compiled_support
    from liquidamp.structure.hostio import load_rotor

    system = rotor_system(load_rotor("hammond1974"), 27.2, Device(MODEL, P))
    assert "'field_yield' reads the measured 'voltage' channel" in compiled_support(system)


def test_a_record_that_is_not_periodic_starts_in_motion():
    """The lead-in (steady flow at the first sample's velocity) against starting from rest:
    the record cut from a longer run, whose earlier part is the true history."""
    import liquidamp.analysis.measured.record_model as RM

    long = _record(duration=0.4, voltage=lambda t: 1.0 + 0 * t)
    truth = simulate_record(MODEL, P, long, options=OPTS["compiled"])
    k = truth.time.size // 2
    cut = Record.from_arrays(long.time[k - 10:], long.displacement[k - 10:],
                             0 * long.time[k - 10:],
                             channels={"voltage": long.channels["voltage"][k - 10:]})
    assert not cut.periodic
    ref = np.interp(cut.time, truth.time, truth.force)
    lead = simulate_record(MODEL, P, cut, options=OPTS["compiled"])
    assert lead.solver_stats["lead_in"] > 0
    share = RM.LEAD_IN_SHARE
    try:
        RM.LEAD_IN_SHARE = 0.0
        rest = simulate_record(MODEL, P, cut, options=OPTS["compiled"])
    finally:
        RM.LEAD_IN_SHARE = share
    first = slice(0, 20)
    e_lead = np.sqrt(np.mean((lead.force[first] - ref[first]) ** 2))
    e_rest = np.sqrt(np.mean((rest.force[first] - ref[first]) ** 2))
    assert e_lead < 0.3 * e_rest, (e_lead, e_rest)
