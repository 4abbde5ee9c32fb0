"""The public face: lazy top-level verbs, scalar in / scalar out, Bode phase, renames."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import liquidamp

ROOT = Path(__file__).resolve().parents[1]


def test_import_loads_no_numerical_library():
    code = ("import sys, liquidamp; heavy = [m for m in ('numpy', 'scipy', 'numba', 'control',"
            " 'matplotlib') if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout
    assert out.strip() == "[]"


def test_every_exported_name_resolves_to_its_defining_object():
    from liquidamp.analysis.measured.calibration import calibrate
    from liquidamp.device.presets import preset

    for name in liquidamp.__all__:
        assert getattr(liquidamp, name) is not None, name
    assert liquidamp.preset is preset and liquidamp.calibrate is calibrate
    assert set(liquidamp.__all__) <= set(dir(liquidamp))
    with pytest.raises(AttributeError, match="no attribute 'simulatte'"):
        liquidamp.simulatte  # noqa: B018


def test_lti_stiffness_scalar_in_scalar_out():
    lti = liquidamp.device_lti(liquidamp.viscous(1e3))
    k = lti.stiffness(3.0)
    assert isinstance(k, complex) and k == pytest.approx(2j * math.pi * 3.0 * 1e3)
    K = lti.stiffness(np.array([[1.0, 2.0]]))
    assert K.shape == (1, 2) and K[0, 1] == pytest.approx(2j * math.pi * 2.0 * 1e3)


def test_bode_plot_of_a_damper_draws_plus_90_deg():
    """python-control's default would draw this damper at -270 deg."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from liquidamp.analysis.response.stiffness import StiffnessCurve

    f = np.array([0.5, 2.0, 10.0])
    curve = StiffnessCurve("damper", f, liquidamp.device_lti(liquidamp.viscous(1e3)).stiffness(f))
    frd = curve.to_frd()
    plt.close("all")  # a figure left open by another test in this process would be drawn on
    frd.plot()
    phase = plt.gcf().axes[1].get_lines()[0].get_ydata()
    plt.close("all")
    assert np.allclose(phase, 90.0)


def test_former_keyword_names_work_with_a_deprecation_warning():
    d = liquidamp.viscous(1e3, c2=50.0)
    new = liquidamp.device_lti(d, amplitude=2e-3, frequency=3.0).stiffness(3.0)
    with pytest.warns(DeprecationWarning) as record:
        old = liquidamp.device_lti(d, amplitude_m=2e-3, frequency_hz=3.0).stiffness(3.0)
    assert sorted(str(w.message) for w in record) == [
        "device_lti(): keyword 'amplitude_m' is now 'amplitude'",
        "device_lti(): keyword 'frequency_hz' is now 'frequency'"]
    assert old == new and new.imag > 2 * math.pi * 3.0 * 1e3  # the quadratic term counts
