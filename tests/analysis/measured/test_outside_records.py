"""Records of dampers outside the device family (session 12, issue #19 items 4-6): the
default commands read, check and judge them honestly."""

import argparse

import numpy as np
import pytest

from liquidamp.analysis.measured.records import Record
from liquidamp.commands.calibrate import checked
from liquidamp.device import preset
from liquidamp.errors import DataFileError


def _power_law_damper(stroke=0.050, freq=0.5, alpha=0.3, fs=200.0):
    """A building fluid-viscous damper F = C |v|^alpha sign v + k y (Symans et al. 2008):
    400 kN at 0.25 m/s, a 160 kN/m accumulator spring, 50 mm stroke."""
    t = np.arange(int(4 / freq * fs)) / fs
    y = stroke * np.sin(2 * np.pi * freq * t)
    v = stroke * 2 * np.pi * freq * np.cos(2 * np.pi * freq * t)
    F = 400e3 / 0.25 ** alpha * np.abs(v) ** alpha * np.sign(v) + 1.6e5 * y
    F = F + np.random.default_rng(3).normal(0.0, 1e3, t.size)
    return Record.from_arrays(t, y, F, source="fvd.csv", first_line=2)


def test_long_stroke_passes_the_checks_unless_the_chambers_are_held():
    """A 50 mm stroke is twice the paper device's chamber end (V0/A_p = 25 mm): by default
    (--sizing auto) the start stretches the chambers to the records, so the stroke is no
    problem of the record; with --sizing preset the device keeps its chambers and the
    stroke is refused with its line, as before."""
    rec = _power_law_damper()
    assert np.max(np.abs(rec.displacement)) > 1.9 * preset("paper_initial").stroke_limit
    args = argparse.Namespace(outliers="refuse", sizing="auto")
    cal, val = checked([rec], [], args, preset("paper_initial"), "calibrate")
    assert cal[0] is rec and val == []
    args.sizing = "preset"
    with pytest.raises(DataFileError, match=r"fvd.csv, line \d+ \(t = .* s\): displacement "
                       r"[+-]50 mm from the mid-position, past the chamber end at 25 mm"):
        checked([rec], [], args, preset("paper_initial"), "calibrate")
