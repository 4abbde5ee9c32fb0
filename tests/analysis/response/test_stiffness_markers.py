"""Issue #14: failed K* points are explicit (null + status, empty CSV cell), never a fake 0;
K* as control.FrequencyResponseData; the compiled engine keeps the sweep fast."""

import csv
import json
import math
import time

import control
import numpy as np
import pytest

from liquidamp.analysis.response.linear import linearize, maxwell_tf
from liquidamp.analysis.response.stiffness import (
    STIFFNESS_OPTIONS,
    StiffnessCurve,
    equivalent_sweep,
    linear_stiffness,
    nonlinear_stiffness,
    write_stiffness_csv,
)
from liquidamp.device import preset
from liquidamp.errors import LiquidampWarning


@pytest.fixture(scope="module")
def failing_sweep():
    # inerter, 5 mm: 3 Hz runs (below vapour pressure: a warning), 20 Hz reaches p = 0
    with pytest.warns(LiquidampWarning, match=r"1 of 2 point\(s\) failed"):
        return nonlinear_stiffness(preset("inerter"), [3.0, 20.0], [5e-3], on_error="skip",
                                   options=STIFFNESS_OPTIONS.replace(max_cycles=20))


def test_failed_point_is_nan_with_a_reason_not_a_zero_loss(failing_sweep):
    r = failing_sweep
    assert r.status[0, 0] == "ok" and r.status[0, 1].startswith("failed: PressureError")
    assert math.isnan(r.storage[0, 1]) and math.isnan(r.loss[0, 1])  # was loss = 0
    assert math.isnan(r.magnitude[0, 1]) and math.isfinite(r.loss[0, 0])
    d = json.loads(json.dumps(r.as_dict()))["0.005"]
    assert d["loss [N/m]"][1] is None and d["storage [N/m]"][1] is None
    assert d["magnitude [N/m]"][1] is None and d["cycles"][1] is None
    assert d["status"][1].startswith("failed: PressureError") and d["status"][0] == "ok"
    assert d["loss [N/m]"][0] == pytest.approx(r.loss[0, 0])


def test_csv_has_empty_cells_and_a_status_column(failing_sweep, tmp_path):
    lin = [linear_stiffness(maxwell_tf(preset("inerter")), [3.0, 20.0], label="maxwell")]
    with pytest.warns(LiquidampWarning, match="equivalent_sweep"):
        eq = equivalent_sweep(preset("inerter"), [3.0, 20.0], [5e-3])
    path = write_stiffness_csv(tmp_path / "k.csv", lin, failing_sweep, eq)
    rows = list(csv.DictReader(path.open()))
    assert len(rows) == 6 and "status" in rows[0]
    failed = [r for r in rows if r["status"].startswith("failed")]
    assert len(failed) == 1 and failed[0]["frequency [Hz]"] == "20"
    assert failed[0]["curve"] == "nonlinear:full" and failed[0]["amplitude [m]"] == "0.005"
    for k in ("magnitude [N/m]", "phase [deg]", "storage [N/m]", "loss [N/m]"):
        assert failed[0][k] == ""  # never "0"
    invalid = [r for r in rows if r["curve"].startswith("equivalent")
               and r["status"].startswith("invalid")]
    assert invalid, "the inerter at 5 mm cavitates: the equivalent points must say so"
    assert all(float(r["magnitude [N/m]"]) > 0 for r in invalid)  # value kept, marked
    assert all(r["status"] == "ok" for r in rows if r["curve"].startswith("linear"))


def test_curve_from_user_nan_is_nan_both_parts():
    c = StiffnessCurve("user", np.array([1.0, 2.0]), np.array([1e5 + 2e4j, np.nan]))
    assert c.status == ("ok", "failed") and math.isnan(c.loss[1]) and math.isnan(c.storage[1])


def test_k_star_as_frequency_response_data():
    p = preset("reference")
    f = np.geomspace(0.5, 20.0, 7)
    c = linear_stiffness(linearize("full", p), f, label="full")
    frd = c.to_frd()
    assert isinstance(frd, control.FrequencyResponseData)
    assert np.allclose(frd.omega, 2 * np.pi * f)
    assert np.allclose(frd.frequency_response(2 * np.pi * f).complex.ravel(), c.value)
    assert frd.input_labels == ["stroke"] and frd.output_labels == ["force"]
    # failed nonlinear points are left out, with a warning naming them
    nl = StiffnessCurve("nl", f[:3], np.array([1e5 + 1e4j, np.nan, 2e5 + 3e4j]))
    with pytest.warns(LiquidampWarning,
                      match=r"1 failed point\(s\) left out of the frequency response \(at 0.92"):
        frd2 = nl.to_frd()
    assert frd2.omega.size == 2


def test_phase_convention_wrapped_where_python_control_unwraps():
    """An inerter's K* = -w^2 b: liquidamp reads 180 deg, python-control's unwrapped phase may
    read +-180 deg (same complex value)."""
    b = 50.0
    f = np.array([1.0, 2.0, 4.0])
    w = 2 * np.pi * f
    c = StiffnessCurve("inerter", f, -b * w**2 + 1e-9j * w)
    assert np.allclose(c.phase_deg, 180.0, atol=1e-6)
    ph = np.degrees(np.angle(c.to_frd().frequency_response(w).complex.ravel()))
    assert np.allclose(np.abs(ph), 180.0, atol=1e-6)


def test_stiffness_sweep_uses_the_compiled_engine_and_is_fast():
    """30 frequencies x 2 amplitudes: 54 s on the Python engine before, <= 5 s now."""
    p = preset("reference")
    nonlinear_stiffness(p, [3.0], [1e-3])  # compile / load the cache
    t0 = time.perf_counter()
    r = nonlinear_stiffness(p, np.geomspace(0.5, 20.0, 30), [1e-3, 3e-3])
    dt = time.perf_counter() - t0
    assert STIFFNESS_OPTIONS.engine == "compiled"
    assert np.isfinite(r.value).all() and (r.status == "ok").all()
    assert dt < 5.0, f"stiffness sweep took {dt:.1f} s"
