"""`liquidamp bench --quick`: the JSON holds every case with the documented keys (no timings
are asserted)."""

import json

from liquidamp.analysis.bench import CASES, baseline_steady_state
from liquidamp.cli import main
from liquidamp.device import preset
from liquidamp.structure.testmachine import HarmonicStroke


def test_quick_bench_writes_the_documented_keys(tmp_path):
    out = tmp_path / "bench.json"
    code = main(["bench", "--quick", "--repeats", "2", "--cases",
                 "steady_state_loop,coupled_rotor,diagnosis", "--json", str(out)])
    assert code == 0
    data = json.loads(out.read_text())
    assert set(data["cases"]) == {"steady_state_loop", "coupled_rotor", "diagnosis"}
    s = data["cases"]["steady_state_loop"]
    for key in ("seconds", "baseline_seconds", "speedup", "first_call_seconds", "accuracy"):
        assert key in s
    assert s["seconds"] > 0 and s["baseline_seconds"] > 0
    assert abs(s["speedup"] - s["baseline_seconds"] / s["seconds"]) < 1e-9 * s["speedup"]
    # both routes agree with the tight reference far inside the steady-state tolerance
    assert s["accuracy"]["fast_K_rel_error"] < 1e-6
    assert s["accuracy"]["baseline_K_rel_error"] < 1e-5
    assert "cached_seconds" in data["first_call"]
    cold = data["cold_start"]  # fresh processes: import, --help, an argument error
    assert cold["import_seconds"] > 0 and cold["help_seconds"] > 0
    assert cold["argument_error_exit_code"] == 2 and "demo_first_run_seconds" not in cold
    assert "cold_start.import_seconds < 0.5" in data["goals"]
    for name in ("coupled_rotor", "diagnosis"):
        case = data["cases"][name]
        assert "skipped" in case or "seconds" in case
    rotor = data["cases"]["coupled_rotor"]
    if "skipped" not in rotor:  # compiled kernel = the Python coupled route (same DOP853)
        assert rotor["status"] == "completed"
        assert rotor["host_state_max_rel_difference_vs_python"] < 1e-9
        assert rotor["real_time_factor"] > 0 and rotor["baseline_real_time_factor"] > 0
    assert set(CASES) >= set(data["cases"])
    assert any(k.startswith("steady_state_loop.seconds") for k in data["goals"])


def test_unknown_case_is_an_error(capsys):
    assert main(["bench", "--quick", "--cases", "nope"]) == 2
    assert "unknown bench case 'nope'" in capsys.readouterr().err


def test_user_style_baseline_gives_the_paper_stiffness():
    """The baseline is a correct (if slow) steady state: same K* as the library's."""
    from liquidamp.analysis.response.harmonics import dynamic_stiffness
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.options import SolverOptions

    p, s = preset("device_b"), HarmonicStroke(0.003, 3.0)
    K_b, cycles = baseline_steady_state("full", p, s, 1e-8)
    K = dynamic_stiffness(steady_state("full", p, s, options=SolverOptions(engine="compiled")))
    assert abs(K_b - K.value) / abs(K.value) < 1e-6
    assert cycles >= 3


def test_stiffness_sweep_bench_case_is_within_its_goal():
    from liquidamp.analysis.bench import run_bench

    data = run_bench(quick=True, repeats=1, cases=["stiffness_sweep"])
    case = data["cases"]["stiffness_sweep"]
    assert case["points"] == 60 and case["failed_points"] == 0
    assert case["seconds"] < 5.0
    assert data["goals"]["stiffness_sweep.seconds < 5"]["reached"] is True
