"""Batched map over local processes and a Dask cluster: same results, input order."""

import io
import math
import sys

import numpy as np
import pytest

from liquidamp.analysis.stability.parallel import map_batched
from liquidamp.errors import ParameterError


def _k_star(frequency):
    """Dynamic stiffness of the reference design at 1 mm (compiled engine)."""
    from liquidamp.analysis.response.harmonics import dynamic_stiffness
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.device import preset
    from liquidamp.options import SolverOptions
    from liquidamp.structure.testmachine import HarmonicStroke

    r = steady_state("full", preset("reference"), HarmonicStroke(0.001, frequency),
                     options=SolverOptions(engine="compiled", samples_per_period=64))
    return dynamic_stiffness(r).value


class _CountingExecutor:
    """A minimal executor with submit(): records the batch sizes it was given."""

    def __init__(self):
        self.sizes = []

    def submit(self, fn, *args):
        from concurrent.futures import Future

        self.sizes.append(len(args[1]))
        f = Future()
        f.set_result(fn(*args))
        return f


def test_batches_follow_the_timed_first_item_and_keep_order():
    ex = _CountingExecutor()
    items = list(range(50))
    out = map_batched(math.factorial, items, executor=ex, min_task_seconds=0.0)
    assert out == [math.factorial(i) for i in items]
    assert ex.sizes == [1] * 49  # zero minimum: one item per task
    ex = _CountingExecutor()
    out = map_batched(math.factorial, items, executor=ex, min_task_seconds=1e3)
    assert ex.sizes == [49] and out[-1] == math.factorial(49)


def test_local_processes_give_the_serial_results():
    items = [200, 300, 400, 500]
    serial = map_batched(math.factorial, items, executor="serial")
    pooled = map_batched(math.factorial, items, min_task_seconds=0.0, max_workers=2)
    assert pooled == serial


def test_progress_text_and_errors(monkeypatch):
    buf = io.StringIO()
    monkeypatch.setattr(sys, "stderr", buf)
    map_batched(abs, [-1, -2, -3], executor="serial", progress=True)
    assert "3/3 (100.0%)" in buf.getvalue()
    assert map_batched(abs, [], executor="serial") == []
    with pytest.raises(ParameterError, match="submit"):
        map_batched(abs, [1], executor=object())


def test_dask_local_cluster_gives_identical_results():
    distributed = pytest.importorskip("dask.distributed")
    freqs = [1.0, 2.0, 3.0, 5.0]
    serial = map_batched(_k_star, freqs, executor="serial")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = map_batched(_k_star, freqs, executor=client, min_task_seconds=0.0)
    assert np.array_equal(np.array(remote), np.array(serial))


def _k_star_batch(frequency):
    """A module-level task for process workers: K* of the reference design (compiled)."""
    return complex(_k_star(frequency))


def test_dask_sweep_matches_the_local_result():
    """The sweep on a Dask LocalCluster (one in-process worker) equals the local result, in
    input order, with batches shipped through a real distributed Client."""
    distributed = pytest.importorskip("dask.distributed")
    freqs = [0.7, 1.5, 2.5, 4.0, 6.0, 9.0]
    local = map_batched(_k_star_batch, freqs, executor="serial")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = map_batched(_k_star_batch, freqs, executor=client, min_task_seconds=0.0)
            # the client ran the tasks: its scheduler saw the batches
            assert len(client.run_on_scheduler(
                lambda dask_scheduler: list(dask_scheduler.task_prefixes))) >= 1
    assert remote == local
    assert all(abs(k) > 0 and np.isfinite(abs(k)) for k in remote)
