"""Issue #19 item 1: a periodic record is simulated on the periodic orbit of its cycle,
driven by its Fourier series (exact derivatives), no pre-roll.

Records: :func:`synthetic_record` (LSODA, an integrator neither engine uses) of slowly
settling presets, 2 mm, 8 cycles at 200 Hz, stroke distortion 1 % / 0.5 % (2nd / 3rd
harmonic), force noise 1 N, displacement noise 0.2 um (a 16-bit LVDT over +-6.5 mm).
The noise floor is the NRMSE of the true force against the measured one.  Before:
device_a at 5 Hz gave NRMSE 0.044 against a floor of 0.0017 (x26; with 2 um of
displacement noise), inerter at 7 Hz x192, from the fixed pre-roll.  Now within 1.03x of
the floor at 1-7 Hz (measured, seed 3).

With 2 um of displacement noise (the generator's default) the fitted series' frequency
carries ~1e-4 Hz of error and the ratio reaches 1.9 (device_a 7 Hz) and 2.5 (inerter
7 Hz) against the force-noise floor: that is the stroke's noise, not a bias.

Cost (warm, idle): about 4 s.
"""

import math

import numpy as np
import pytest

from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.record_model import nrmse, record_stroke, simulate_record
from liquidamp.analysis.measured.record_quality import velocity_gain
from liquidamp.analysis.measured.records import Record
from liquidamp.analysis.measured.synthetic import Recipe, synthetic_record
from liquidamp.analysis.response.harmonics import dynamic_stiffness, first_harmonic
from liquidamp.coupled.testrig import simulate
from liquidamp.device import preset
from liquidamp.errors import ParameterError
from liquidamp.options import PRESETS
from liquidamp.structure.testmachine import FourierStroke, HarmonicStroke

FIT = PRESETS["fit"]
NOISE = {"displacement_noise": 2e-7, "force_noise": 1.0}


def _record(name, f, **kw):
    return synthetic_record(preset=name, frequency=f, amplitude=0.002, seed=3,
                            **{**NOISE, **kw})


@pytest.mark.parametrize(("name", "f"), [("device_a", 5.0), ("device_a", 1.0),
                                         ("device_b", 3.0), ("inerter", 1.0),
                                         ("inerter", 7.0)])
def test_true_parameters_reproduce_the_record_to_its_noise_floor(name, f):
    rec = _record(name, f)
    floor = nrmse(rec.meta["true_force"], rec.force)
    sim = simulate_record("full", Recipe(preset=name).params(), rec, options=FIT)
    assert nrmse(sim.force, rec.force) < 1.2 * floor
    assert sim.solver_stats["stroke"] == "fourier" and sim.solver_stats["velocity_gain"] == 1.0
    assert sim.solver_stats["route"] in ("march", "shooting")
    assert "on the periodic orbit of its cycle" in sim.message
    # no start-up transient: the first cycle fits as well as the last
    n = int(rec.sampling_rate / f)
    first, last = (nrmse(sim.force[s], rec.force[s]) for s in (slice(0, n),
                                                                 slice(-n, None)))
    assert first < 1.5 * last + 0.5 * floor


@pytest.mark.parametrize(("name", "f"), [("device_a", 5.0), ("device_b", 3.0)])
def test_averaged_record_to_its_noise_floor(name, f):
    """The cycle average: the floor is the averaged true force against the averaged record
    (a twin record with the same stroke noise and no force noise, conditioned alike)."""
    rec = _record(name, f)
    twin = _record(name, f, force_noise=0.0)
    a, cond = condition(rec, average=True, decimate=1)
    b, _ = condition(twin, average=True, decimate=1)
    assert cond.cycles_averaged == 7 and np.array_equal(a.displacement, b.displacement)
    floor = nrmse(b.force, a.force)
    sim = simulate_record("full", Recipe(preset=name).params(), a, options=FIT)
    assert nrmse(sim.force, a.force) < 1.2 * floor
    assert sim.solver_stats["stroke"] == "fourier"
    assert sim.solver_stats["harmonics"] == cond.fourier_stroke().harmonics == 3


def test_fourier_velocity_is_exact_where_savitzky_golay_is_low():
    """40 samples per cycle: the 21-point SG velocity is 1.3 % low; the record's Fourier
    series gives the analytic velocity (to 1e-7: the refined frequency)."""
    f, fs, Y = 5.0, 200.0, 0.003
    t = np.arange(0, 2.0, 1 / fs)
    w = 2 * math.pi * f
    y = Y * np.sin(w * t) + 0.01 * Y * np.sin(2 * w * t + 0.3) + 0.002
    v = Y * w * np.cos(w * t) + 0.02 * Y * w * np.cos(2 * w * t + 0.3)
    rec = Record.from_arrays(t, y, 0 * t)
    h = rec.window // 2
    gain = velocity_gain(f, fs)
    assert gain == pytest.approx(0.987, abs=1e-3)
    sg = first_harmonic(rec.time[:8 * 40] - rec.time[0], rec.velocity[:8 * 40], f)
    true = first_harmonic(t[h:h + 8 * 40] - t[h], v[h:h + 8 * 40], f)
    assert abs(sg) / abs(true) == pytest.approx(gain, abs=2e-4)  # the SG velocity: low
    s = record_stroke(rec)
    assert s.harmonics == 2 and s.offset == 0.0
    _, vs, _ = s(rec.time)
    assert np.max(np.abs(vs - v[h:t.size - h])) < 1e-7 * Y * w
    sim = simulate_record("full", preset("reference"), rec)
    assert np.max(np.abs(sim.stroke_rate - v[h:t.size - h])) < 1e-7 * Y * w
    assert sim.solver_stats["velocity_gain"] == 1.0


def test_a_tapered_record_keeps_savitzky_golay_and_states_its_gain():
    f, fs = 5.0, 200.0
    t = np.arange(0, 3.0, 1 / fs)
    y = 0.003 * np.sin(2 * math.pi * f * t) * np.exp(-t / 0.8)
    rec = Record.from_arrays(t, y, 0 * t)
    assert not rec.periodic
    sim = simulate_record("full", preset("reference"), rec)
    g = velocity_gain(rec.frequency, fs)
    assert sim.solver_stats["stroke"] == "savitzky-golay"
    assert sim.solver_stats["velocity_gain"] == pytest.approx(g)
    assert f"gain {g:.4f}" in sim.message
    with pytest.raises(ParameterError, match="not periodic has no Fourier series"):
        record_stroke(rec)


def test_warm_start_and_preroll_keyword():
    """The previous orbit as first guess (as a calibration would pass it) gives the same
    force; ``preroll`` is still accepted (ignored)."""
    rec = _record("device_a", 5.0)
    p = Recipe(preset="device_a").params()
    cold = simulate_record("full", p, rec, options=FIT, preroll=2)
    near = simulate_record("full", p.replace(c1=p.c1 * 1.01), rec, options=FIT)
    warm = simulate_record("full", p, rec, options=FIT, x0=near.states[:, 0])
    assert np.max(np.abs(warm.force - cold.force)) < 1e-5 * np.max(np.abs(cold.force))
    assert warm.solver_stats["march_cycles"] <= cold.solver_stats["march_cycles"]


def test_fourier_stroke_checks_and_fit():
    with pytest.raises(ParameterError, match="sine and 1 cosine"):
        FourierStroke(3.0, [1e-3, 0.0], [0.0])
    with pytest.raises(ParameterError, match="every coefficient is 0"):
        FourierStroke(3.0, [0.0], [0.0])
    with pytest.raises(ParameterError, match="harmonic 2 is not finite"):
        FourierStroke(3.0, [1e-3, float("nan")], [0.0, 0.0])
    # a harmonic stroke as a Fourier series: the same periodic steady state
    s = FourierStroke(3.0, [0.003], [0.0])
    from liquidamp.coupled.testrig import steady_state

    a = steady_state("full", preset("device_b"), s)
    b = steady_state("full", preset("device_b"), HarmonicStroke(0.003, 3.0))
    assert np.max(np.abs(a.force - b.force)) < 1e-6 * np.max(np.abs(b.force))
    # the fundamental refined: a record whose frequency estimate is off
    t = np.arange(0, 1.6, 1 / 200.0)
    fit = FourierStroke.fit(t, 0.002 * np.sin(2 * math.pi * 7.0 * t), 7.0003,
                            refine_frequency=True)
    assert abs(fit.frequency - 7.0) < 1e-7


def test_dynamic_stiffness_refuses_a_partial_period_or_a_run_from_rest():
    """Issue #21: a 0.15-cycle run returned a number."""
    s = HarmonicStroke(0.001, 3.0)
    run = simulate("maxwell", preset("reference"), s, 0.05, t_eval=np.arange(30) / 600.0)
    with pytest.raises(ParameterError, match="needs a periodic steady state .* status "
                       "'completed'"):
        dynamic_stiffness(run)
    with pytest.raises(ParameterError, match="span 0.15 period"):
        first_harmonic(run.time, run.force, 3.0)
    with pytest.raises(ParameterError, match="are not uniform"):
        first_harmonic(np.r_[0.0, 0.1, 0.15, 0.3], np.ones(4), 1 / 0.4)
    # two whole periods are fine and give the one-period answer
    tt = np.arange(128) / 64.0
    assert first_harmonic(tt, np.sin(2 * np.pi * tt), 1.0) == pytest.approx(1.0 + 0j)


def test_a_warm_start_that_fails_is_retried_from_rest(monkeypatch):
    """A warm start (another parameter point's orbit) that finds no orbit is not the end:
    the record is simulated from the rest state, as without a warm start, and gives the same
    force to the orbit's tolerance."""
    import liquidamp.analysis.measured.record_model as RM
    from liquidamp.errors import ConvergenceError

    rec = _record("reference", 3.0)
    real = RM.periodic_state
    firsts = []

    def spy(rig, engine, first, *a, **k):
        firsts.append(np.array(first))
        if fail and len(firsts) == 1:
            raise ConvergenceError("no periodic steady state (simulated failure)")
        return real(rig, engine, first, *a, **k)

    monkeypatch.setattr(RM, "periodic_state", spy)
    fail = False
    ref = simulate_record("full", preset("reference"), rec, options=FIT)
    rest = firsts.pop()
    fail = True
    got = simulate_record("full", preset("reference"), rec, options=FIT,
                          x0=np.array(ref.states[:, 0]) * 1.01)
    assert len(firsts) == 2 and not np.allclose(firsts[0], rest)
    np.testing.assert_array_equal(firsts[1], rest)
    assert nrmse(got.force, ref.force) < 1e-5


@pytest.mark.parametrize(("effect", "kw", "near"), [
    ("freeplay", {"gap_m": 1e-4}, {"gap_m": 1.2e-4}),
    ("series_compliance", {"stiffness_N_per_m": 5e5}, {"stiffness_N_per_m": 4e5})])
def test_warm_start_behind_a_dead_band_or_compliance_keeps_the_fluid_mass(effect, kw, near):
    """Behind a dead band (or a series spring) the chambers follow the piston's state, not
    the rod: a warm start from a nearby point's orbit, moved onto the invariants of rest,
    must count the fluid mass at the piston's stroke (coupled.invariants.invariants), and behind a
    spring hold the massless piston's balance k (y - y_p) - F_fluid at rest's too
    (invariants.onto_invariants).  Otherwise it lands on another sealed device's orbit
    (session 10: freeplay's bench record gave NRMSE 0.00072 cold against 0.0022 warm).
    Before the fix the warm force here was 6.6 N (freeplay) and 9.9 N (compliance; 2.0 N
    with the mass alone counted at the piston) off the cold one, of 830 and 450 N."""
    from liquidamp.device.effects import make_effect, with_effects
    from liquidamp.device.models import get_model

    rec = condition(synthetic_record(preset="paper_calibrated", frequency=3.0,
                                     amplitude=0.003, cycles=4, sampling_rate=200.0, seed=5,
                                     effects={effect: kw}))[0]
    p = preset("paper_calibrated")
    m = with_effects(get_model("full"), make_effect(effect, **kw))
    cold = simulate_record(m, p, rec, options=FIT)
    other = simulate_record(with_effects(get_model("full"), make_effect(effect, **near)),
                            p.replace(c1=p.c1 * 1.05), rec, options=FIT)
    warm = simulate_record(m, p, rec, options=FIT, x0=other.states[:, 0])
    assert np.max(np.abs(warm.force - cold.force)) < 1e-5 * np.max(np.abs(cold.force))


def test_warm_start_outside_the_dead_band_is_brought_back_into_it():
    """A warm start from a wider gap's orbit can hold the driven side of a dead band further
    from the rod than the present gap allows: behind friction (backlash) the contact then
    never opens and the piston stays locked to the rod past the band's edge, an orbit no
    motion from inside the band reaches (session 10: a backlash refit of the 200 Hz
    Coulomb-friction bench record reached NRMSE 0.00084 on it, 0.0527 on the orbit from
    rest).  invariants.onto_invariants clips y_fp into |y - y_fp| <= gap; here 1 mm
    outside a 0.2 mm band, the force was 6.8 % of its peak off the cold one before, now
    within 0.1 %."""
    from liquidamp.device.effects import make_effect, with_effects
    from liquidamp.device.models import get_model

    rec = condition(synthetic_record(preset="paper_calibrated", frequency=3.0,
                                     amplitude=0.003, cycles=4, sampling_rate=200.0, seed=5,
                                     effects={"coulomb_friction": {"force_N": 60.0}}))[0]
    p = preset("paper_calibrated")
    m = with_effects(get_model("full"),
                     make_effect("smooth_friction", force_N=60.0, stiffness_N_per_m=3e6,
                                 location="piston"),
                     make_effect("freeplay", gap_m=2e-4, drives="friction"))
    cold = simulate_record(m, p, rec, options=FIT)
    x0 = np.array(cold.states[:, 0])
    x0[m.state_names.index("y_fp")] = float(rec.displacement[0]) - 1e-3
    warm = simulate_record(m, p, rec, options=FIT, x0=x0)
    assert np.max(np.abs(warm.force - cold.force)) < 1e-3 * np.max(np.abs(cold.force))


def test_a_warm_start_on_the_orbit_is_accepted_after_three_periods():
    """``record_model.WARM_MIN_CYCLES``: a fit's next evaluation starts from the last orbit;
    on that orbit the march accepts after three periods (four before), to the force of the
    march from rest within the steady tolerance; from rest the rule is unchanged."""
    rec = synthetic_record(preset="paper_calibrated", frequency=3.0, amplitude=0.003,
                           cycles=4, seed=5)
    p = preset("paper_calibrated")
    cold = simulate_record("full", p, rec, options=FIT)
    warm = simulate_record("full", p, rec, options=FIT, x0=cold.states[:, 0])
    assert cold.solver_stats["march_cycles"] >= 4
    assert warm.solver_stats["march_cycles"] == 3
    # measured 6.7e-8 of the peak force
    assert np.max(np.abs(warm.force - cold.force)) < 1e-6 * np.max(np.abs(cold.force))
