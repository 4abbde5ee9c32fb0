"""The stability-map bench case runs, reports its split and finds Hammond's unstable band."""

from liquidamp.analysis.bench import CASES, GOALS
from liquidamp.analysis.bench_maps import case_map


def test_map_case_quick_reports_the_split_and_the_band():
    assert {"stability_map", "stability_map_dask"} <= set(CASES) & set(GOALS)
    data = case_map(quick=True, repeats=1)
    assert data["points"] == 33 and data["steps_per_revolution"] == 512
    assert set(data["split_seconds"]) == {"coefficient_grid", "step_control", "kernel",
                                          "eigenvalues"}
    # the failed damper's row is unstable at 220, 250 and 280 rpm (band 210-307 rpm),
    # every other point is stable
    assert data["unstable_fraction_of_points"] == 3 / 33
