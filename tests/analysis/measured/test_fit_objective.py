"""The fit objective: Jacobian columns on threads give the numbers of one thread, bit for bit."""

import threading

import numpy as np
import pytest

from liquidamp.analysis.measured import fit_objective
from liquidamp.analysis.measured.calibration import FitSpec, calibrate
from liquidamp.analysis.measured.fit_objective import FitObjective, fit_threads
from liquidamp.analysis.measured.synthetic import synthetic_record
from liquidamp.device import preset
from liquidamp.errors import ParameterError
from liquidamp.options import PRESETS


@pytest.fixture(scope="module")
def record():
    return synthetic_record(frequency=3.0, amplitude=0.003, cycles=3, seed=21)


def _fit(record, monkeypatch, threads):
    monkeypatch.setenv("LIQUIDAMP_THREADS", str(threads))
    return calibrate([record], params=preset("paper_initial"), sizing="preset",
                     spec=FitSpec.default(), max_nfev=12, warn=False)


def test_threads_give_the_same_fit_as_one_thread(record, monkeypatch):
    """Each column starts from the base point's orbits, never another column's: the fit
    (values, Jacobian-based standard errors, run count) does not depend on the threads."""
    one = _fit(record, monkeypatch, 1)
    two = _fit(record, monkeypatch, 2)
    assert one.nfev == two.nfev > 4
    for k, v in one.values.items():
        assert two.values[k] == v, k
        assert two.stderr[k] == one.stderr[k], k
    assert two.nrmse_calibration == one.nrmse_calibration


def test_columns_run_on_threads_and_keep_order(record, monkeypatch):
    """The map runs its calls on worker threads (two at a time here), returns them in the
    order given, and leaves the objective's own orbits at the base point's."""
    monkeypatch.setenv("LIQUIDAMP_THREADS", "2")
    spec = FitSpec.default()
    obj = FitObjective("full", preset("paper_initial"), (), spec, [record], PRESETS["fit"], 1)
    x0 = np.zeros(len(obj.var))
    obj(x0)
    base = {k: v.copy() for k, v in obj.warm.items()}
    assert base  # a periodic record: its orbit is kept as the next first guess
    names = []

    def fun(x):
        names.append(threading.current_thread().name)
        return obj(x)

    pts = [x0 + 1e-3 * np.eye(len(x0))[j] for j in range(len(x0))]
    cols = obj.columns(fun, pts)
    assert all(n.startswith("liquidamp-jac") for n in names)
    for j, c in enumerate(cols):  # same as a sequential call from the same base orbits
        obj.warm = {k: v.copy() for k, v in base.items()}
        np.testing.assert_array_equal(c, obj(pts[j]))
    obj.warm = {k: v.copy() for k, v in base.items()}
    obj.columns(obj, pts)
    for k in base:
        np.testing.assert_array_equal(obj.warm[k], base[k])
    assert obj.nfev == 1 + 3 * len(pts)  # the base, two maps and the sequential checks


@pytest.mark.parametrize("bad", ["0", "two", "65", "-1"])
def test_thread_count_is_checked(monkeypatch, bad):
    monkeypatch.setenv("LIQUIDAMP_THREADS", bad)
    with pytest.raises(ParameterError, match="LIQUIDAMP_THREADS"):
        fit_threads()


def test_thread_count_defaults_to_the_usable_cores(monkeypatch):
    monkeypatch.delenv("LIQUIDAMP_THREADS", raising=False)
    monkeypatch.setattr(fit_objective.os, "sched_getaffinity", lambda pid: set(range(40)),
                        raising=False)
    assert fit_threads() == fit_objective.MAX_THREADS
    monkeypatch.setattr(fit_objective.os, "sched_getaffinity", lambda pid: {0},
                        raising=False)
    assert fit_threads() == 1


def test_a_columns_record_memory_stays_with_the_column(record, monkeypatch):
    """What a record simulation keeps in ``record.meta`` between runs (a drifting record's
    last start temperature, the next estimate's first guess) is the base point's in every
    column, and a column's writes never reach the objective's records: otherwise the order
    in which the threads finish would move the Jacobian (d07 on two threads: held-out
    0.02535, 0.02566, 0.02595 in three runs of the same code)."""
    monkeypatch.setenv("LIQUIDAMP_THREADS", "2")
    obj = FitObjective("full", preset("paper_initial"), (), FitSpec.default(), [record],
                       PRESETS["fit"], 1)
    x0 = np.zeros(len(obj.var))
    obj(x0)
    record.meta["_probe"] = "base"
    seen = []

    def fun(x):
        rec = obj._local.records[0]
        seen.append(rec.meta["_probe"])
        rec.meta["_probe"] = float(x[0])  # a column's own memory
        np.testing.assert_array_equal(rec.force, record.force)
        return obj(x)

    pts = [x0 + 1e-3 * np.eye(len(x0))[j] for j in range(len(x0))]
    obj.columns(fun, pts)
    assert seen == ["base"] * len(pts)
    assert record.meta["_probe"] == "base"
    del record.meta["_probe"]
