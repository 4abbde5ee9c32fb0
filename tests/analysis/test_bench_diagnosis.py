"""`liquidamp bench` cases of the diagnosis at real sampling rates (quick configuration: the
keys and what was found, no timing asserted)."""

from liquidamp.analysis.bench import GOALS, run_bench


def test_real_rate_cases_report_time_result_and_conditioning():
    cases = ("diagnosis_3khz_20s", "diagnosis_200hz_10_cycles")
    data = run_bench(quick=True, cases=cases, cold=False)
    three_khz = data["cases"]["diagnosis_3khz_20s"]
    assert three_khz["seconds_coulomb_friction"] > 0
    assert three_khz["added_coulomb_friction"] == ["coulomb_friction"]
    assert three_khz["parameter_error_coulomb_friction"] < 0.3
    assert "decimated 20x to 150 Hz" in three_khz["conditioning_coulomb_friction"]
    two_hundred = data["cases"]["diagnosis_200hz_10_cycles"]
    assert two_hundred["added_smooth_friction"] == ["smooth_friction"]
    for case in cases:
        for key, op, target in GOALS[case]:
            if key in data["cases"][case]:
                assert f"{case}.{key} {op} {target:g}" in data["goals"]
