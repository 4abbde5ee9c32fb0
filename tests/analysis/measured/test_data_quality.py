"""Issue #14: data quality is checked before any fit; results say what they are."""

import json
import time
import warnings

import numpy as np
import pytest

from liquidamp.analysis.measured.calibration import FitSpec, calibrate
from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.record_quality import check_record
from liquidamp.analysis.measured.records import Record
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.device import preset
from liquidamp.errors import DataFileError, LiquidampWarning


@pytest.fixture(scope="module")
def clean():
    cal = synthetic_record(frequency=3.0, amplitude=0.003, cycles=3, seed=21)
    val = synthetic_record(frequency=4.0, amplitude=0.002, cycles=3, seed=22)
    return cal, val


def _with(rec, force=None, displacement=None):
    """The record rebuilt from its arrays (10 more samples trimmed at each end), as if read
    from spiky.csv whose first data line holds rec.time[0]."""
    return Record.from_arrays(rec.time, rec.displacement if displacement is None else displacement,
                              rec.force if force is None else force, source="spiky.csv",
                              first_line=2)


def test_clean_and_friction_records_pass(clean):
    p = preset("paper_initial")
    recs = list(clean) + [synthetic_record(frequency=3.0, amplitude=0.003, cycles=3, seed=5,
                                           effects={"coulomb_friction": {"force_N": 30.0}})]
    for r in recs:
        q = check_record(r, p)
        assert q.ok, (q.problems, q.outliers)
        assert q.force_snr > 100 and q.periodic_fraction > 0.99
        assert r.amplitude <= q.max_stroke < 1.25 * r.amplitude and q.stroke_limit == p.stroke_limit


def test_pure_noise_record_is_refused_not_calibrated(clean):
    cal, _ = clean
    rng = np.random.default_rng(4)
    noise = Record.from_arrays(cal.time, cal.displacement, rng.normal(0, 200.0, cal.time.size),
                               source="noise.csv")
    q = check_record(noise)
    assert q.force_snr < 5 and q.periodic_fraction < 0.3
    t0 = time.perf_counter()
    with pytest.raises(DataFileError, match=r"noise.csv: the force's first harmonic at the "
                       r"stroke frequency 3.* Hz .* is not distinguishable from the noise"):
        calibrate([noise])
    assert time.perf_counter() - t0 < 1.0  # refused before any model run


def test_force_spikes_are_refused_with_their_lines_or_dropped(clean):
    cal, val = clean
    F = cal.force.copy()
    F[[40, 105, 160]] = 5e4  # three 50 kN spikes: samples 30, 95, 150 after the SG trim
    spiky = _with(cal, force=F)
    cal = _with(cal)  # the same samples without the spikes
    q = check_record(spiky)
    assert [o.index for o in q.outliers] == [30, 95, 150]
    assert [o.column for o in q.outliers] == ["force"] * 3
    lines = [spiky.line(i) for i in (30, 95, 150)]
    assert lines == [o.line for o in q.outliers] == [42, 107, 162]  # header is line 1
    with pytest.raises(DataFileError, match=rf"3 force outlier\(s\) .*spiky.csv, line {lines[0]} "
                       r"\(t = .* s\): force 50000 N.*outliers='drop'"):
        calibrate([spiky], validate=[val])
    spec = FitSpec.default(vary=("c1", "c2"))
    with pytest.warns(LiquidampWarning, match=r"3 force outlier\(s\) dropped"):
        res = calibrate([spiky], validate=[val], spec=spec, outliers="drop", max_nfev=20)
    assert [o.index for _, o in res.dropped] == [30, 95, 150]
    ref = calibrate([cal], validate=[val], spec=spec, max_nfev=20, warn=False)
    # the fit without the spikes equals the fit of the clean record, nothing else was lost
    assert res.n_samples == ref.n_samples - 3
    for k in ("c1", "c2"):
        assert res.values[k] == pytest.approx(ref.values[k], rel=1e-2)
    assert res.nrmse_calibration == pytest.approx(ref.nrmse_calibration, rel=0.05)
    d = json.loads(json.dumps(res.as_dict(), default=float))
    assert [x["line"] for x in d["dropped"]] == lines and d["dropped"][0]["value"] == 5e4
    assert any("dropped" in w for w in d["warnings"])
    assert np.all(res.residuals()[0][[30, 95, 150]] == 0.0)


def test_displacement_spike_refused_before_any_integration(clean):
    cal, val = clean
    y = cal.displacement.copy()
    y[70] += 0.030  # one 30 mm spike (sample 60 after the trim): past the chamber end (25 mm)
    spiky = _with(cal, displacement=y)
    assert spiky.line(60) == 72
    t0 = time.perf_counter()
    # the device keeps its chambers (sizing 'preset'): past the chamber end
    with pytest.raises(DataFileError, match=r"diagnose: spiky.csv, line 72 \(t = .* s\):"
                       r" displacement \+3.* mm from the mid-position, past the chamber end at 25 "
                       r"mm \(V0/A_p; allowed \|y\| < 25 mm\)"):
        diagnose([spiky], [val], sizing="preset")
    assert time.perf_counter() - t0 < 1.0  # was > 120 s
    # by default the chambers are sized to the records: the same sample is refused as a spike
    t0 = time.perf_counter()
    with pytest.raises(DataFileError, match=r"diagnose: spiky.csv: 1 displacement spike\(s\) on "
                       r"line 72 .*displacement \+?3.* mm where its neighbours give"):
        diagnose([spiky], [val])
    assert time.perf_counter() - t0 < 1.0
    # a smaller spike inside the chamber is still a spike
    y = cal.displacement.copy()
    y[70] += 0.005
    with pytest.raises(DataFileError, match=r"1 displacement spike\(s\).*line 72 .*"
                       r"cannot be dropped"):
        calibrate([_with(cal, displacement=y)], outliers="drop")


def test_result_repr_report_and_plot(clean):
    cal, val = clean
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LiquidampWarning)
        res = calibrate([cal], validate=[val], spec=FitSpec.default(vary=("c1", "c2")),
                        max_nfev=3, start="spec")
    assert len(repr(res)) < 300 and len(str(res)) < 2000
    assert "max_nfev" in repr(res) and "c1=" in repr(res)
    rep = res.fit_report()
    assert "[[Variables]]" in rep and "[[Correlations]]" in rep
    assert "c1:" in rep and "+/-" in rep and "[-] multiplier" in rep
    assert "C(c1, c2)" in rep or "none" in rep
    low = res.fit_report(min_correl=0.0)
    assert f"C(c1, c2) = {res.correlation[0, 1]:+.4f}" in low
    assert "NOT CONVERGED" in rep  # the warnings are in the report too
    fig = res.plot()
    assert len(fig.axes) == 2
    assert fig.axes[0].get_ylabel() == "force [N]" and fig.axes[1].get_xlabel() == \
        "displacement [mm]"
    assert len(res.plot("validation").axes) == 2


def test_parameter_at_bound_is_flagged(clean):
    cal, _ = clean
    from liquidamp.analysis.measured.calibration import Parameter
    spec = FitSpec((Parameter("c1", 1.0, 0.9, 1.1), Parameter("c2", 1.0, 0.05, 20.0)))
    with pytest.warns(LiquidampWarning, match="at a bound"):
        res = calibrate([cal], spec=spec, max_nfev=15, start="spec")
    assert res.at_bounds() == {"c1": "lower"}
    assert "AT LOWER BOUND" in res.fit_report()


def test_rig_ringing_on_real_records_is_not_taken_for_spikes(friction_damper_records):
    """Rig ringing (10-50 Hz, 2-7 % of the loop) is texture, not spikes: before the
    texture floor 732 samples of the 0.5 Hz record were refused as outliers."""
    from liquidamp.analysis.measured.records import read_record

    for f in sorted(friction_damper_records.glob("brfd30_*_steady.csv")):
        q = check_record(read_record(f))
        assert q.outliers == () and q.problems == (), f.name
    # a real spike on the same record is still found
    rec = read_record(friction_damper_records / "brfd30_0.5Hz_0.5in_steady.csv")
    F = rec.force.copy()
    F[1000] += 10 * float(np.ptp(F))
    q = check_record(_with(rec, force=F))
    assert [o.index for o in q.outliers] == [990]  # _with trims 10 samples at the start
