"""The force's sign convention: a damper's loop recorded backwards is read negated by default.

Laboratories record the load-cell force tension- or compression-positive; liquidamp reads it
positive where it resists a positive stroke (a passive device absorbs energy).  A record in
the other convention draws its loop backwards.  ``orient_force`` (``--force-sign auto``, the
default) negates such a loop where it delivers at least FLIP_SHARE of RMS(F) x RMS(v); a
loop that delivers a little (a stiff device whose channels are skewed) stays as read and is
refused by the data checks, never turned into a negative stiffness.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from liquidamp.analysis.measured.checks import FLIP_SHARE, check_records, orient_force
from liquidamp.analysis.measured.diagnosis import _holdout
from liquidamp.analysis.measured.record_quality import check_record
from liquidamp.analysis.measured.records import Record, read_record, write_record
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.cli import main
from liquidamp.errors import DataFileError, ParameterError


def _negated(record: Record, path):
    """``record`` written to ``path`` with its force negated (the other convention)."""
    return write_record(path, time=record.time, displacement=record.displacement,
                        force=-np.asarray(record.force))


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    """A model-made record pair (reference device, 3 and 4 Hz) as recorded and negated."""
    d = tmp_path_factory.mktemp("sign")
    cal = synthetic_record(frequency=3.0, amplitude=0.003, cycles=8, seed=31)
    val = synthetic_record(frequency=4.0, amplitude=0.002, cycles=4, seed=32)
    files = {"cal": write_record(d / "cal.csv", cal), "val": write_record(d / "val.csv", val),
             "ncal": _negated(cal, d / "ncal.csv"), "nval": _negated(val, d / "nval.csv")}
    return d, files


def test_a_backwards_loop_is_negated_and_a_skewed_spring_is_not():
    t = np.arange(0.0, 2.0, 0.002)
    w = 2 * math.pi * 3.0
    y = 0.003 * np.sin(w * t)
    rng = np.random.default_rng(3)
    noise = rng.normal(0.0, 2.0, t.size)
    damper = Record.from_arrays(t, y, 800.0 * np.cos(w * t) + noise, source="damper.csv")
    assert orient_force(damper) is damper  # absorbs energy: as read
    back = Record.from_arrays(t, y, -800.0 * np.cos(w * t) + noise, source="back.csv")
    r = orient_force(back)
    np.testing.assert_array_equal(r.force, -back.force)
    q = check_record(r)
    assert q.loss_share == pytest.approx(1.0, abs=0.01) and not q.problems
    assert q.force_negated.startswith("the loop as recorded delivers")
    assert any("force read negated" in n for n in q.notes)
    assert orient_force(r) is r  # once only
    assert orient_force(back, "as-read") is back
    np.testing.assert_array_equal(orient_force(damper, "flip").force, -damper.force)
    # a stiff spring whose force lags the stroke by 2 samples' worth of phase the other way
    # (channels skewed): loss share about -0.075, refused by the checks, never negated
    lead = 3 * 2 * math.pi * 3.0 * 0.002
    spring = Record.from_arrays(t, y, 1e5 * 0.003 * np.sin(w * t - lead) + noise,
                                source="spring.csv")
    qs = check_record(spring)
    assert -FLIP_SHARE < qs.loss_share < -0.05
    assert orient_force(spring) is spring
    with pytest.raises(DataFileError, match="runs against the stroke rate"):
        check_records([spring])
    with pytest.raises(ParameterError, match="force_sign"):
        orient_force(damper, "negative")


def test_calibrate_reads_a_negated_pair_as_the_recorded_one_and_says_so(pair):
    d, f = pair
    out = {}
    for tag, (c, v) in {"as": ("cal", "val"), "neg": ("ncal", "nval")}.items():
        code = main(["calibrate", str(f[c]), "--validate", str(f[v]), "--json",
                     str(d / f"c_{tag}.json")])
        assert code == 0
        out[tag] = json.loads((d / f"c_{tag}.json").read_text())
    # the same fit to the last digit the JSON holds: the negated records are the records
    assert out["neg"]["nrmse"] == out["as"]["nrmse"]
    assert out["neg"]["summary"].startswith("FORCE NEGATED: ncal.csv, nval.csv")
    assert "FORCE NEGATED" not in out["as"]["summary"]
    assert [q["force_negated"] != "" for q in out["neg"]["data_quality"]] == [True, True]
    # --force-sign as-read refuses, naming the sign
    code = main(["calibrate", str(f["ncal"]), "--force-sign", "as-read", "--json",
                 str(d / "refused.json")])
    assert code == 2 and not (d / "refused.json").exists()


def test_a_single_record_split_keeps_its_lines_channels_and_sign(pair):
    """The second half a diagnosis holds out keeps the file's own lines, the measured
    channels and the negated sign's record (it was lost in the split before)."""
    d, f = pair
    rec = orient_force(read_record(f["ncal"]))
    n = rec.time.size
    assert n > 400
    volts = Record.from_arrays(rec.time, rec.displacement, rec.force, source=rec.source,
                               channels={"voltage": np.linspace(0.0, 1.0, n)},
                               lines=[rec.line(k) for k in range(n)],
                               meta=dict(rec.meta))
    (first,), (second,), how = _holdout((volts,))
    for half in (first, second):
        # each sample's line is the file's line of the sample at its time (header = 1)
        j = np.searchsorted(volts.time, half.time)
        np.testing.assert_array_equal(volts.time[j], half.time)
        assert [half.line(k) for k in (0, half.time.size - 1)] == [volts.line(j[0]),
                                                                   volts.line(j[-1])]
        np.testing.assert_array_equal(half.channels["voltage"], volts.channels["voltage"][j])
    assert second.line(0) > first.line(first.time.size - 1)
    assert second.meta["force_sign"] == rec.meta["force_sign"] and "second half" in how
