"""Scale-out of many independent runs: batched map over local processes or any executor.

A sweep (stability map, many steady states, multi-start calibration) is a map
of one function over many items.  With the compiled engine one item can take
a millisecond, far less than the cost of shipping a task to a process, so
:func:`map_batched` times the first item and groups the rest into batches
of at least ``min_task_seconds`` each.  By default it runs on local
processes (:class:`concurrent.futures.ProcessPoolExecutor`, *spawn* start
method: ``fn`` and the items must be picklable, i.e. ``fn`` defined at module
level); any object with a ``submit(fn, *args)`` method returning a future
with ``result()`` works too, e.g. a ``dask.distributed.Client``.  Results
come back in input order.

Examples
--------
>>> import math
>>> map_batched(math.factorial, [3, 4, 5], executor="serial")
[6, 24, 120]
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable, Iterable

from liquidamp.errors import ParameterError

__all__ = ["map_batched", "run_batch"]


def run_batch(fn: Callable, batch: list) -> list:
    """Apply ``fn`` to each item of ``batch`` (the task shipped to a worker)."""
    return [fn(item) for item in batch]


class _Progress:
    """One-line progress text on stderr: ``label: done/total (pct) elapsed``."""

    def __init__(self, total: int, enabled: bool, label: str = "map_batched") -> None:
        self.total, self.enabled, self.label = total, enabled, label
        self.t0 = time.perf_counter()
        self.done = 0

    def update(self, k: int) -> None:
        self.done += k
        if callable(self.enabled):
            self.enabled(k)
        elif self.enabled:
            pct = 100.0 * self.done / max(self.total, 1)
            sys.stderr.write(f"\r{self.label}: {self.done}/{self.total} ({pct:5.1f}%) "
                             f"{time.perf_counter() - self.t0:7.1f} s")
            sys.stderr.flush()

    def close(self) -> None:
        if self.enabled and not callable(self.enabled):
            sys.stderr.write("\n")
            sys.stderr.flush()


def map_batched(fn: Callable, items: Iterable, executor=None, min_task_seconds: float = 0.1,
                progress: bool | None = None, *, max_workers: int | None = None) -> list:
    """Map ``fn`` over ``items`` in batches of at least ``min_task_seconds`` each.

    Parameters
    ----------
    fn : callable
        ``fn(item) -> result``; picklable (module level) for process or
        distributed executors.
    items : iterable
        Inputs.
    executor : None, "serial" or object with ``submit``
        None: a local :class:`~concurrent.futures.ProcessPoolExecutor` (spawn),
        created and shut down here; ``"serial"``: run in this process; else
        an executor such as a ``dask.distributed.Client``, used as given and
        left open.
    min_task_seconds : float
        Smallest work per task, estimated from the timed first item [s].
    progress : bool or callable, optional
        Show a progress line on stderr; default: when stderr is a terminal.
        A callable is called as ``progress(n)`` after every ``n`` items done
        (e.g. a tqdm bar's ``update``).
    max_workers : int, optional
        Processes of the default pool (default: CPU count).

    Returns
    -------
    list
        ``[fn(item) for item in items]``, in input order.

    Notes
    -----
    The first item runs in this process (it also warms up compiled code and
    caches); if the estimated total is below two tasks' worth the remaining
    items run here too, since a pool would cost more than it saves.
    """
    items = list(items)
    if not min_task_seconds >= 0.0:
        raise ParameterError(f"min_task_seconds must be >= 0 [s], got {min_task_seconds!r}")
    if executor is not None and executor != "serial" and not hasattr(executor, "submit"):
        raise ParameterError(
            f"executor must be None, 'serial' or have a submit() method, got "
            f"{type(executor).__name__}"
        )
    if progress is None:
        progress = bool(getattr(sys.stderr, "isatty", lambda: False)())
    bar = _Progress(len(items), progress if callable(progress) else bool(progress))
    if not items:
        return []
    t = time.perf_counter()
    results = [fn(items[0])]
    t_first = max(time.perf_counter() - t, 1e-9)
    bar.update(1)
    rest = items[1:]
    size = max(1, math.ceil(min_task_seconds / t_first))
    batches = [rest[i:i + size] for i in range(0, len(rest), size)]
    local = executor == "serial" or (executor is None and len(batches) < 2)
    if local:
        for batch in batches:
            results.extend(run_batch(fn, batch))
            bar.update(len(batch))
        bar.close()
        return results
    own = executor is None
    if own:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        workers = max_workers or os.cpu_count() or 1
        executor = ProcessPoolExecutor(max_workers=min(workers, len(batches)),
                                       mp_context=multiprocessing.get_context("spawn"))
    try:
        futures = [executor.submit(run_batch, fn, batch) for batch in batches]
        for fut, batch in zip(futures, batches, strict=True):
            results.extend(fut.result())
            bar.update(len(batch))
    finally:
        if own:
            executor.shutdown(wait=True, cancel_futures=True)
        bar.close()
    return results
