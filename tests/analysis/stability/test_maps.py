"""Stability maps (rotor speed x damper parameter) against the one-parameter sweep.

Independent routes: the map's compiled lane-blocked kernel against the batched
numpy Floquet sweep (:func:`ground_resonance_sweep`) at the same parameter value,
against the constant-coefficient multiblade (Coleman) eigenvalues when the blades
are alike, its boundary against the root-found unstable-range edges, and the
same map computed in one thread, in threads and on a Dask cluster.
"""

import json

import numpy as np
import pytest

from liquidamp.analysis.stability.ground_resonance import (
    ground_resonance_sweep,
    rpm_to_rad_s,
)
from liquidamp.analysis.stability.maps import (
    MapOptions,
    ground_resonance_map,
    map_dampers,
    zero_crossings,
)
from liquidamp.errors import ParameterError
from liquidamp.structure.hostio import load_rotor

RPM = np.linspace(150.0, 350.0, 41)  # 5 rpm spacing
FRACTIONS = [0.0, 0.3, 1.0]


@pytest.fixture(scope="module")
def rotor():
    return load_rotor("hammond1974")


@pytest.fixture(scope="module")
def degradation_map(rotor):
    return ground_resonance_map(rotor, rpm_to_rad_s(RPM), "degradation", FRACTIONS)


@pytest.fixture(scope="module")
def sweeps(rotor, degradation_map):
    return [ground_resonance_sweep(rotor.with_lag_dampers(d), rpm_to_rad_s(RPM), "floquet")
            for d in degradation_map.dampings]


def test_map_equals_the_sweep_point_for_point(degradation_map, sweeps):
    m = degradation_map
    assert m.dampings[:, 0].tolist() == [0.0, 0.3 * 4067.5, 4067.5]
    assert np.all(m.dampings[:, 1:] == 4067.5)
    for row, sweep in zip(m.max_real_part, sweeps, strict=True):
        np.testing.assert_allclose(row, sweep.max_real_part, rtol=0.0, atol=1e-9)
    # the failed damper is unstable in Hammond's band, the healthy rotor is not
    assert m.max_real_part[0].max() > 0.1 and m.max_real_part[-1].max() < -0.1


def test_healthy_row_equals_the_multiblade_eigenvalues(degradation_map, rotor):
    """All dampers alike: constant coefficients after the Coleman transform (another route)."""
    coleman = ground_resonance_sweep(rotor, rpm_to_rad_s(RPM), "coleman")
    np.testing.assert_allclose(degradation_map.max_real_part[-1], coleman.max_real_part,
                               rtol=0.0, atol=1e-8)


def test_boundary_agrees_with_root_found_edges_within_the_grid_spacing(degradation_map,
                                                                       sweeps):
    from contourpy import contour_generator

    m = degradation_map
    spacing = RPM[1] - RPM[0]
    ranges = m.unstable_ranges_rpm()
    assert [len(r) for r in ranges] == [1, 1, 0]  # the band closes as the damper recovers
    for got, sweep in zip(ranges, sweeps, strict=True):
        want = sweep.unstable_ranges_rpm
        assert len(got) == len(want)
        for (a, b), (c, d) in zip(got, want, strict=True):
            assert abs(a - c) < spacing and abs(b - d) < spacing
    # the drawn contour (the plot's zero level) crosses each row at those edges
    lines = contour_generator(m.rpm, m.values, m.max_real_part - m.neutral_tol).lines(0.0)
    pts = np.concatenate(lines)
    for v, rr in zip(m.values, ranges, strict=True):
        on_row = np.sort(pts[np.isclose(pts[:, 1], v, atol=1e-12), 0])
        want = np.unique(np.round([e for r in rr for e in r], 9))
        np.testing.assert_allclose(np.unique(np.round(on_row, 9)), want, atol=1e-9)


def test_the_critical_fraction_is_bracketed_along_the_parameter(rotor):
    """At 250 rpm the damper must keep a fraction between the map's rows to be stable; the
    sweep at the interpolated fraction is within one row spacing of neutral."""
    fr = np.linspace(0.0, 1.0, 11)
    m = ground_resonance_map(rotor, rpm_to_rad_s([250.0]), "degradation", fr)
    col = m.max_real_part[:, 0]
    (f_crit,) = zero_crossings(fr, col)
    assert 0.0 < f_crit < 1.0
    for f, sign in ((f_crit - 0.1, 1.0), (f_crit + 0.1, -1.0)):
        r = rotor.with_lag_dampers(map_dampers(rotor, "degradation", [f])[0])
        s = ground_resonance_sweep(r, rpm_to_rad_s([250.0]), "floquet")
        assert sign * s.max_real_part[0] > 0.0


def test_routes_give_identical_numbers_and_arm_is_damping_times_arm_squared(rotor):
    W = rpm_to_rad_s(np.linspace(180.0, 320.0, 13))
    opts = dict(steps=64)
    thr = ground_resonance_map(rotor, W, "arm", [0.15, 0.25], options=MapOptions(**opts))
    ser = ground_resonance_map(rotor, W, "arm", [0.15, 0.25],
                               options=MapOptions(executor="serial", chunk_points=5, **opts))
    assert np.array_equal(thr.max_real_part, ser.max_real_part)
    lag = ground_resonance_map(rotor, W, "lag_damping", [4067.5 * 0.36, 4067.5],
                               options=MapOptions(**opts))
    np.testing.assert_allclose(thr.dampings, [[4067.5 * 0.36] * 4, [4067.5] * 4], rtol=1e-12)
    np.testing.assert_allclose(lag.max_real_part, thr.max_real_part, rtol=0, atol=1e-12)


def test_dask_cluster_equals_local(rotor):
    distributed = pytest.importorskip("dask.distributed")
    W = rpm_to_rad_s(np.linspace(200.0, 300.0, 9))
    local = ground_resonance_map(rotor, W, "degradation", [0.0, 0.5, 1.0],
                                 options=MapOptions(steps=64))
    seen = []
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = ground_resonance_map(
                rotor, W, "degradation", [0.0, 0.5, 1.0],
                options=MapOptions(steps=64, executor=client, min_task_seconds=0.0,
                                   progress=seen.append))
    assert remote.route == "executor Client"
    assert np.array_equal(remote.max_real_part, local.max_real_part)
    assert sum(seen) == W.size * 3


def test_bad_input_is_refused_before_work(rotor):
    W = rpm_to_rad_s([200.0, 250.0])
    with pytest.raises(ParameterError, match=r"degradation fraction must lie in \[0, 1\].*1.5"):
        ground_resonance_map(rotor, W, "degradation", [0.5, 1.5])
    with pytest.raises(ParameterError, match="strictly increasing"):
        ground_resonance_map(rotor, W, "arm", [0.3, 0.2])
    with pytest.raises(ParameterError, match="rotor speeds must be finite and > 0"):
        ground_resonance_map(rotor, [0.0, 1.0], "arm", [0.2])
    with pytest.raises(ParameterError, match="map parameter"):
        ground_resonance_map(rotor, W, "stiffness", [0.2])


def test_map_command_writes_json_and_plot_and_refuses_a_long_silent_grid(tmp_path, capsys):
    from liquidamp.cli import main

    out, fig = tmp_path / "m.json", tmp_path / "m.png"
    assert main(["map", "ground-resonance", "--rpm", "200:300:5", "--degradation",
                 "0%,50%,100%", "--json", str(out), "--plot", str(fig), "--quiet"]) == 0
    data = json.loads(out.read_text())
    assert data["parameter"] == "degradation" and data["values [-]"] == [0.0, 0.5, 1.0]
    assert np.asarray(data["max_real_part [1/s]"]).shape == (3, 5)
    assert data["unstable_ranges [rpm]"][0] and not data["unstable_ranges [rpm]"][2]
    assert fig.stat().st_size > 1000
    assert main(["map", "ground-resonance", "--rpm", "100:400:2001", "--arm", "0.1:0.3:20",
                 "--quiet"]) == 2
    assert "would take about 60 s" in capsys.readouterr().err


def test_flutter_map_boundary_matches_the_p_method_flutter_speed_and_divergence():
    from liquidamp.analysis.stability.damped_stability import damped_flutter_analysis
    from liquidamp.analysis.stability.flutter_maps import flutter_map
    from liquidamp.coupled.assembly import viscous
    from liquidamp.structure.hostio import load_section

    s = load_section("hodges-pierce")
    V = np.linspace(1.5, 3.2, 18)  # 0.1 spacing
    m = flutter_map(s, V, [1e-9, 300.0, 5000.0])
    for c, vf in zip(m.values, m.flutter_speeds(), strict=True):
        ref = damped_flutter_analysis(s, {"plunge": viscous(c)}, speeds=V).flutter_speed
        assert abs(vf - ref) < V[1] - V[0]
    # heavy plunge damping leaves divergence, sqrt(mu r^2 / (1 + 2 a)) = sqrt(8), as the edge
    assert abs(m.flutter_speeds()[-1] - np.sqrt(8.0)) < V[1] - V[0]
    assert np.all((m.min_damping_ratio < 0.0) == (m.max_real_part > 0.0))


def test_map_command_on_a_dask_scheduler_equals_local(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    from liquidamp.cli import main

    argv = ["map", "ground-resonance", "--rpm", "200:300:3", "--arm", "0.1,0.25", "--quiet"]
    assert main(argv + ["--json", str(tmp_path / "local.json")]) == 0
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        assert main(argv + ["--json", str(tmp_path / "dask.json"), "--dask",
                            cluster.scheduler_address]) == 0
    local, remote = (json.loads((tmp_path / f).read_text()) for f in ("local.json", "dask.json"))
    assert remote["route"] == "executor Client" and local["route"] == "threads"
    assert remote["max_real_part [1/s]"] == local["max_real_part [1/s]"]
