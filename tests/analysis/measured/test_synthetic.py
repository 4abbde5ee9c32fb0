"""Synthetic records: reproducible, realistic, and read back like measured data."""

import numpy as np
import pytest

from liquidamp.analysis.measured.record_quality import noise_floor
from liquidamp.analysis.measured.records import read_record
from liquidamp.analysis.measured.synthetic import (
    Recipe,
    recipe_from_dict,
    synthetic_record,
    write_synthetic,
)


def test_reproducible_and_realistic():
    kw = dict(frequency=4.0, amplitude=0.002, cycles=3, seed=5, force_noise=2.0,
              displacement_noise=3e-6, displacement_offset=5e-4)
    a, b = synthetic_record(**kw), synthetic_record(**kw)
    assert np.array_equal(a.force, b.force)
    assert not np.array_equal(a.force, synthetic_record(**{**kw, "seed": 6}).force)
    assert a.frequency == pytest.approx(4.0, rel=1e-3)
    assert a.amplitude == pytest.approx(0.002, rel=1e-2)
    assert a.offset == pytest.approx(5e-4, abs=2e-5)
    assert abs(a.displacement[0] - a.offset) < 0.95 * a.amplitude or a.phase != 0.0
    nf = noise_floor(a)
    assert nf.force_std == pytest.approx(2.0, rel=0.2)
    assert a.sampling_rate == pytest.approx(200.0)
    # stroke distortion: the 2nd harmonic is present at about 1 %
    t = a.time - a.time[0]
    w = 2 * np.pi * a.frequency
    c2 = np.linalg.lstsq(np.column_stack((np.sin(2 * w * t), np.cos(2 * w * t), np.sin(w * t),
                                          np.cos(w * t), np.ones_like(t))), a.displacement,
                         rcond=None)[0]
    assert 0.005 < np.hypot(c2[0], c2[1]) / a.amplitude < 0.02


def test_write_with_sidecar(tmp_path):
    p = write_synthetic(tmp_path / "x.csv", cycles=2, seed=1,
                        effects={"force_offset": {"offset_N": 12.0}})
    r = read_record(p)
    import json

    rec = recipe_from_dict(json.loads(p.with_suffix(".json").read_text()))
    assert isinstance(rec, Recipe)
    assert rec.effect_objects()[0].offset_N == 12.0
    assert r.cycles > 1.2  # each read drops the 2 x 10 filter-edge samples


def test_bundled_records_are_documented():
    from liquidamp.analysis.measured.diagnosis import bundled_records

    files = bundled_records()
    assert {"demo_3Hz_3mm", "demo_4Hz_2mm"} <= set(files)
    readme = (next(iter(files.values())).parent / "README.md").read_text()
    for stem, path in files.items():
        assert stem in readme
        assert path.with_suffix(".json").exists()
        assert read_record(path).cycles > 8
