"""Record conditioning: zero-phase force filter, anti-alias decimation, cycle average, and the
model force conditioned like the record's (liquidamp.analysis.measured.conditioning)."""

import dataclasses

import numpy as np
import pytest

from liquidamp.analysis.measured.calibration import FIT_OPTIONS, calibrate
from liquidamp.analysis.measured.conditioning import (
    condition,
    decimation_factor,
    lowpass,
)
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.analysis.measured.records import Record
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError

COULOMB = {"coulomb_friction": {"force_N": 30.0}}


@pytest.fixture(scope="module")
def dense_coulomb():
    """A 3 kHz record of the paper's device with 30 N of Coulomb friction, 1 Hz, 8 cycles."""
    return synthetic_record(preset="paper_calibrated", frequency=1.0, amplitude=0.003,
                            cycles=8, sampling_rate=3000.0, seed=11, effects=COULOMB)


def _true_model():
    return with_effects(get_model("full"), make_effect("coulomb_friction", force_N=30.0))


def test_lowpass_is_zero_phase_and_keeps_a_line():
    t = np.arange(2000) / 1000.0
    slow = np.sin(2 * np.pi * 2 * t)
    y = lowpass(slow + 0.5 * np.sin(2 * np.pi * 200 * t), 1000.0, 20.0)
    # a 2 Hz sine passes with neither delay nor loss (|H|^2 = 1 - 1e-21 there), 200 Hz goes
    assert np.max(np.abs(y - slow)[100:-100]) < 1e-3
    # the ends are padded about a fitted line: a straight line comes out unchanged, even on
    # a record shorter than the pad (the pad then spans the whole record)
    for n in (50, 500):
        line = 1.0 + 3.0 * np.linspace(0.0, 1.0, n)
        assert np.max(np.abs(lowpass(line, 100.0, 5.0) - line)) < 1e-3
    with pytest.raises(ParameterError, match="cut-off must lie between 0 and the Nyquist"):
        lowpass(slow, 1000.0, 600.0)


def test_force_filter_reports_what_it_removed():
    """Rig ringing at 40 Hz on a 0.5 Hz loop: a 10 Hz filter removes it, and says how much."""
    t = np.arange(0, 8.0, 1 / 1000)
    loop = 1e4 * np.tanh(5 * np.cos(np.pi * t))
    ringing = 800.0 * np.sin(2 * np.pi * 40 * t)
    r = Record.from_arrays(t, 0.0127 * np.sin(np.pi * t), loop + ringing)
    rc, c = condition(r, force_cutoff=10.0, decimate=1)
    assert c.factor == 1 and c.force_cutoff == 10.0
    # 3 periods of the cut-off at each end are not fitted: 300 samples at 1 kHz
    assert c.trimmed == 300 and rc.time.size == r.time.size - 600
    assert rc.time[0] == r.time[300]
    rms, share = c.removed_by_stage["force filter"]
    assert rms == pytest.approx(800.0 / np.sqrt(2), rel=0.02)
    assert share == pytest.approx(0.5 * 800.0 ** 2 / np.var(r.force), rel=0.05)
    assert c.removed_rms == pytest.approx(rms) and "force low-pass 10 Hz" in c.describe()
    assert c.as_dict()["force_cutoff [Hz]"] == 10.0
    with pytest.raises(ParameterError, match="above the stroke frequency"):
        condition(r, force_cutoff=0.3)


def test_tapered_stroke_keeps_its_carriers_harmonics_not_its_band_edges():
    # 1 Hz at 1024 Hz, 7 cycles ramping over 2 at each end (the friction-damper's tapered
    # records): its force holds k f spread by the envelope's bandwidth B, so the cut-off
    # reaches 30 f + B (q = 13, as the constant-amplitude record), not 30 (f + B) (q = 11)
    t = np.arange(0, 7.0, 1 / 1024)
    env = np.clip(np.minimum(t, 7.0 - t) / 2.0, 0.0, 1.0)
    y = 0.0127 * np.sin(2 * np.pi * t)
    tap = Record.from_arrays(t, env * y, 1e4 * np.cos(2 * np.pi * t))
    edge = tap.shape.band[1]
    assert tap.shape.kind == "tapered" and 1.05 < edge < 1.3
    assert decimation_factor(tap) == int(1.001 * 1024 / (2.5 * (30 * tap.frequency + edge
                                                                 - tap.frequency))) == 13
    assert int(1.001 * 1024 / (2.5 * 30 * edge)) <= 11  # the band edge's harmonics
    assert decimation_factor(Record.from_arrays(t, y, 1e4 * np.cos(2 * np.pi * t))) == 13


def test_automatic_decimation_keeps_the_harmonics_asked_for():
    t = np.arange(0, 6.0, 1 / 1024)
    r = Record.from_arrays(t, 0.0127 * np.sin(np.pi * t), 1e4 * np.cos(np.pi * t))
    # fs / q >= 2.5 x 30 x f: 1024 / (75 x 0.5) = 27.3
    assert decimation_factor(r) == 27
    rc, c = condition(r, average=False)
    # 227 kept samples, 8 at each end not fitted (3 periods of the 15.2 Hz cut-off)
    assert (c.factor, c.trimmed, rc.time.size) == (27, 8, 211)
    assert c.anti_alias_cutoff == pytest.approx(0.4 * 1024 / 27, rel=1e-4)
    assert c.harmonics_kept >= 30.0
    # a 200 Hz record of a 3 Hz stroke is left as it is
    t2 = np.arange(0, 3.0, 1 / 200)
    r2 = Record.from_arrays(t2, 0.003 * np.sin(6 * np.pi * t2), np.cos(6 * np.pi * t2))
    assert condition(r2, average=False)[0] is r2
    with pytest.raises(ParameterError, match="fewer than 5 harmonics"):
        condition(r, decimate=200)
    with pytest.raises(ParameterError, match="'auto' or an integer factor"):
        condition(r, decimate=0)


def test_model_force_is_conditioned_like_the_record(dense_coulomb):
    """The true model against the decimated record reaches the noise floor; the same model
    force taken at the kept samples without the record's filter does not (its Coulomb jump
    is sharp, the record's rounded by the anti-alias filter)."""
    rc, c = condition(dense_coulomb, average=False)
    assert c.factor == 40
    m, p = _true_model(), preset("paper_calibrated")
    like = simulate_record(m, p, rc, options=FIT_OPTIONS).force
    plain = simulate_record(m, p, dataclasses.replace(rc, meta={}), options=FIT_OPTIONS).force
    floor = c.noise.nrmse
    assert nrmse(like, rc.force) < 1.5 * floor
    assert nrmse(plain, rc.force) > 5.0 * floor


def test_cycle_average_fits_as_every_cycle_does(dense_coulomb):
    """Averaged over its 7 whole cycles the record holds one cycle; the true model meets it
    at the averaged record's own noise floor (about sqrt(7) below the record's), and a fit of
    the four multipliers and the friction on the average finds what the fit on the
    decimated record finds."""
    ra, ca = condition(dense_coulomb)
    rd, cd = condition(dense_coulomb, average=False)
    assert ca.cycles_averaged == 7 and ra.time.size == 75
    assert ca.noise.force_std == pytest.approx(cd.noise.force_std / np.sqrt(7), rel=0.25)
    m, p = _true_model(), preset("paper_calibrated")
    assert nrmse(simulate_record(m, p, ra, options=FIT_OPTIONS).force, ra.force) \
        < 2.0 * ca.noise.nrmse  # 1.36 x: the floor of an average of 7 cycles is tiny
    effect = (make_effect("coulomb_friction", force_N=20.0),)
    fits = [calibrate([r], params=p, effects=effect, warn=False) for r in (ra, rd)]
    for key in ("coulomb_friction.force_N", "inv_gamma1", "c1"):
        assert fits[0].values[key] == pytest.approx(fits[1].values[key], rel=0.02), key
    assert fits[0].values["coulomb_friction.force_N"] == pytest.approx(30.0, rel=0.02)
    assert "7 whole cycles averaged" in ca.describe()
    assert ca.as_dict()["cycles_averaged"] == 7


def test_average_refuses_a_stroke_that_does_not_repeat():
    t = np.arange(0, 8.0, 1 / 200)
    ramp = np.minimum(1.0, t / 6.0)
    r = Record.from_arrays(t, ramp * 0.003 * np.sin(6 * np.pi * t), np.cos(6 * np.pi * t))
    with pytest.raises(ParameterError, match="does not repeat"):
        condition(r, average=True)
    assert condition(r)[1].cycles_averaged == 1  # 'auto' leaves it as it is


def test_a_conditioned_record_cannot_be_cut(dense_coulomb):
    rc, c = condition(dense_coulomb, average=False)
    assert c.samples == rc.time.size
    cut = dataclasses.replace(rc, **{k: getattr(rc, k)[:-5] for k in (
        "time", "displacement", "force", "velocity", "acceleration", "smoothed")})
    with pytest.raises(ParameterError, match="a conditioned record cannot be cut"):
        simulate_record("full", preset("paper_calibrated"), cut, options=FIT_OPTIONS)
