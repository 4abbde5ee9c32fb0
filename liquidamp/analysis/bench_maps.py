"""Bench cases of the stability maps (``liquidamp bench``, issue #22 item 4).

``stability_map``: a ground-resonance map of the Hammond (1974) rotor over 201 rotor
speeds x 50 degradation fractions of one lag damper (10 050 Floquet points), goal at most
30 s on two cores; with the time split (coefficient grid, step-count control, kernel,
eigenvalues) and numba's thread efficiency on a sample of the points.

``stability_map_dask``: the same kind of map on a ``dask.distributed.LocalCluster`` of two
single-thread worker processes against the same points in one thread of this process;
parallel efficiency ``t_serial / (2 t_cluster)``, goal at least 0.8 for batches of 0.1 s or
more; the numbers must equal the local ones bit for bit.
"""

from __future__ import annotations

import os
import time

import numpy as np

__all__ = ["case_map", "case_map_dask"]


def _setup(quick: bool, rows: int | None = None):
    from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    from liquidamp.structure.hostio import load_rotor

    rotor = load_rotor("hammond1974")
    W = rpm_to_rad_s(np.linspace(100.0, 400.0, 11 if quick else 201))
    fr = np.linspace(0.0, 1.0, 3 if quick else (rows or 50))
    return rotor, W, fr


def _load() -> list | None:
    return [round(x, 2) for x in os.getloadavg()] if hasattr(os, "getloadavg") else None


def case_map(quick: bool, repeats: int) -> dict:
    """Time the 201 x 50 map (median of up to three runs, each from cold coefficient caches)."""
    from liquidamp.analysis.stability import maps
    from liquidamp.analysis.stability._map_kernel import monodromies, monodromies_parallel

    rotor, W, fr = _setup(quick)
    load_before = _load()
    maps.ground_resonance_map(rotor, W[:2], "degradation", fr[:1],
                              options=maps.MapOptions(steps=64))  # compiled code loaded
    times, result = [], None
    for _ in range(1 if quick else min(max(repeats, 1), 3)):
        maps._basis_fine.cache_clear()
        t = time.perf_counter()
        result = maps.ground_resonance_map(rotor, W, "degradation", fr)
        times.append(time.perf_counter() - t)
    N = result.steps
    # where the time goes: each part timed on its own
    maps._basis_fine.cache_clear()
    t = time.perf_counter()
    B, G, cols = maps._basis(rotor, 4 * N)
    t_basis = time.perf_counter() - t
    D = maps.map_dampers(rotor, "degradation", fr)
    probe = np.unique(np.linspace(0, W.size - 1, min(W.size, 51)).round().astype(int))
    t = time.perf_counter()
    maps._choose_steps(rotor, W[probe], D[[0, -1]], maps.FloquetOptions())
    t_steps = time.perf_counter() - t
    Wp, Dp = np.tile(W, fr.size), np.repeat(D, W.size, axis=0)
    t = time.perf_counter()
    Phi = monodromies_parallel(B, G, cols, Wp, Dp, N)
    t_kernel = time.perf_counter() - t
    t = time.perf_counter()
    np.linalg.eigvals(Phi)
    t_eig = time.perf_counter() - t
    # numba threads against one thread on a sample of the points
    k = min(Wp.size, 8 * 64)
    t = time.perf_counter()
    c0 = time.process_time()
    monodromies(B, G, cols, Wp[:k], Dp[:k], N)
    t_one, cpu_one = time.perf_counter() - t, time.process_time() - c0
    t = time.perf_counter()
    monodromies_parallel(B, G, cols, Wp[:k], Dp[:k], N)
    t_two = time.perf_counter() - t
    from numba import get_num_threads

    threads = get_num_threads()
    seconds = float(np.median(times))
    return {
        "description": f"Hammond (1974) rotor, ground-resonance map: {W.size} rotor speeds "
                       f"100-400 rpm x {fr.size} fractions 0-1 of blade 1's lag damper "
                       f"({W.size * fr.size} Floquet points; liquidamp.analysis.stability.maps, "
                       "default options: step count by error control on the extreme rows, "
                       "compiled lane-blocked RK4 + Richardson on numba's threads; coefficient "
                       "grid evaluated in every repeat)",
        "seconds": seconds,
        "runs_seconds": times,
        "points": int(W.size * fr.size),
        "ms_per_point": 1e3 * seconds / (W.size * fr.size),
        "steps_per_revolution": int(N),
        "split_seconds": {"coefficient_grid": t_basis, "step_control": t_steps,
                          "kernel": t_kernel, "eigenvalues": t_eig},
        "threads": threads,
        "thread_sample_points": int(k),
        "one_thread_seconds": t_one,
        "one_thread_cpu_ms_per_point": 1e3 * cpu_one / k,
        "threads_seconds": t_two,
        "thread_efficiency": t_one / (threads * t_two),
        "unstable_fraction_of_points": float(np.mean(result.max_real_part > 1e-6)),
        "load_average_before": load_before,
        "load_average_after": _load(),
    }


def _warm(steps: int) -> int:
    """Worker warm-up: load the compiled kernel and evaluate the rotor's coefficient grid."""
    from liquidamp.analysis.stability import maps

    rotor, W, fr = _setup(True)
    maps.ground_resonance_map(rotor, W[:2], "degradation", fr[:1],
                              options=maps.MapOptions(steps=steps, executor="serial"))
    return os.getpid()


def case_map_dask(quick: bool, repeats: int) -> dict:
    """Parallel efficiency of the map on a two-worker ``LocalCluster`` (processes)."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:  # pragma: no cover - optional dependency
        return {"skipped": f"dask.distributed not installed: {exc}"}
    from liquidamp.analysis.stability import maps

    rotor, W, fr = _setup(quick, rows=20)
    steps = 64 if quick else 512
    _warm(steps)
    opts = dict(steps=steps)
    load_before = _load()
    workers = 2
    serial_times, serial_cpu, times, cluster_cpu, done = [], [], [], [], []
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        pids = client.run(_warm, steps)
        for _ in range(1 if quick else min(max(repeats, 1), 3)):
            # serial and cluster runs interleaved, so that both see the same machine load
            c0, t = time.process_time(), time.perf_counter()
            serial = maps.ground_resonance_map(rotor, W, "degradation", fr,
                                               options=maps.MapOptions(executor="serial",
                                                                       **opts))
            serial_times.append(time.perf_counter() - t)
            serial_cpu.append(time.process_time() - c0)
            done.clear()
            w0 = sum(client.run(time.process_time).values())
            c0, t = time.process_time(), time.perf_counter()
            remote = maps.ground_resonance_map(
                rotor, W, "degradation", fr,
                options=maps.MapOptions(executor=client, progress=done.append, **opts))
            times.append(time.perf_counter() - t)
            cluster_cpu.append(time.process_time() - c0
                               + sum(client.run(time.process_time).values()) - w0)
    t_serial = float(np.median(serial_times))
    t_cluster = float(np.median(times))
    row = t_serial / fr.size
    return {
        "description": f"the map on a dask.distributed LocalCluster of {workers} single-thread "
                       f"worker processes: {W.size} rotor speeds x {fr.size} fractions, one row "
                       f"({W.size} points, about {row:.2f} s) per task, fixed {steps} steps; "
                       "against the same map in one thread of this process (warm workers)",
        "seconds": t_cluster,
        "runs_seconds": times,
        "serial_seconds": t_serial,
        "serial_runs_seconds": serial_times,
        "cpu_efficiency": float(np.median(serial_cpu) / np.median(cluster_cpu)),
        "cpu_efficiency_note": "CPU seconds of the serial map / CPU seconds of the cluster run "
                               "(client + workers): the work the distribution adds, whatever "
                               "the machine load; parallel_efficiency (wall) also counts the "
                               "waits for cores that other jobs hold",
        "workers": len(pids),
        "task_seconds": row,
        "parallel_efficiency": t_serial / (workers * t_cluster),
        "run_efficiencies": [a / (workers * b) for a, b in zip(serial_times, times,
                                                               strict=True)],
        "equal_to_local": bool(np.array_equal(remote.max_real_part, serial.max_real_part)),
        "progress_points_reported": int(sum(done)),
        "load_average_before": load_before,
        "load_average_after": _load(),
    }
