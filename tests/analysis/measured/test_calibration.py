"""Calibration: recovers known multipliers, reports errors and convergence honestly."""

import numpy as np
import pytest

from liquidamp.analysis.measured.calibration import FitSpec, Parameter, calibrate, physics_start
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.device import preset
from liquidamp.errors import ConvergenceError, ParameterError

TRUTH = {"inv_gamma1": 0.75, "inv_gamma2": 1.22, "c1": 3.56, "c2": 4.04}  # Table 2


@pytest.fixture(scope="module")
def records():
    cal = synthetic_record(frequency=3.0, amplitude=0.003, cycles=3, seed=21)
    val = synthetic_record(frequency=4.0, amplitude=0.002, cycles=3, seed=22)
    return cal, val


@pytest.fixture(scope="module")
def fitted(records):
    cal, val = records
    return calibrate([cal], validate=[val], max_nfev=80)


def test_recovers_table2_multipliers_from_paper_initial(fitted):
    """The paper's calibration of Table 2, done automatically from the initial values."""
    res = fitted
    assert res.converged and res.status == "converged"
    for k, v in TRUTH.items():
        assert res.values[k] == pytest.approx(v, rel=0.05), k
        assert 0 < res.stderr[k] < 0.2 * v
    assert res.nrmse_calibration < 0.01
    assert res.nrmse_validation < 0.03
    assert res.correlation.shape == (4, 4)
    assert np.allclose(np.diag(res.correlation), 1.0)
    assert [e.role for e in res.record_errors] == ["calibration", "validation"]
    assert res.params.c1 == pytest.approx(preset("paper_initial").c1 * res.values["c1"])
    d = res.as_dict()
    assert set(d["nrmse"]) == {"calibration", "validation"}
    assert d["fit"]["status"] == "converged"


def test_fluid_record_keeps_the_fluid_start(fitted):
    """Issue #19 item 4: the friction and viscous starts are tried and lose on a record of
    the fluid device (Table 2 recovered above from the same fit)."""
    assert fitted.device_class == "fluid"
    by = {o.name: o for o in fitted.class_starts}
    assert set(by) == {"fluid", "friction", "viscous", "valved"} and by["fluid"].chosen
    # a start the records cannot build (the valved start where a slope of the map is not
    # positive) has no fit and no BIC: it is reported failed with its reason
    built = [o for n, o in by.items() if n != "fluid" and o.bic is not None]
    assert len(built) >= 2 and all(by["fluid"].bic < o.bic for o in built)
    assert all(o.error and not o.chosen for o in by.values() if o.bic is None), \
        [(n, o.error) for n, o in by.items()]
    assert fitted.plausibility == ()


def test_physics_start_is_in_the_right_decade(records):
    s = physics_start([records[0]], preset("paper_initial"), FitSpec.default())
    assert 1.0 < s["c1"] < 10.0 and s["c1"] == s["c2"]
    assert 0.05 < s["inv_gamma1"] < 2.0


def test_non_convergence_is_reported_never_hidden(records):
    cal, _ = records
    res = calibrate([cal], max_nfev=3, start="spec")
    assert not res.converged
    assert res.status == "max_nfev"
    assert "not converged" in res.message
    with pytest.raises(ConvergenceError, match="did not converge"):
        calibrate([cal], max_nfev=3, start="spec", strict=True)


def test_inputs_not_mutated(records):
    cal, _ = records
    spec = FitSpec.default(vary=("c1",))
    p = preset("paper_initial")
    f0 = cal.force.copy()
    res = calibrate([cal], params=p, spec=spec, max_nfev=6, start="spec")
    assert spec["c1"].value == 1.0 and p == preset("paper_initial")
    assert np.array_equal(cal.force, f0) and not cal.force.flags.writeable
    assert res.spec["c1"].value != 1.0


def test_fitspec_validation():
    with pytest.raises(ParameterError, match="outside its bounds"):
        Parameter("c1", 50.0, 0.05, 20.0)
    with pytest.raises(ParameterError, match="unknown fitted device parameter"):
        Parameter("c3", 1.0, 0.05, 20.0)
    with pytest.raises(ParameterError, match="given twice"):
        FitSpec((Parameter("c1", 1, 0.1, 2), Parameter("c1", 1, 0.1, 2)))
    spec = FitSpec.default(effects=["force_offset"])
    assert not spec["force_offset.offset_N"].log
