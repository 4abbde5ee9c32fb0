"""``liquidamp bench``: speed of the compiled core against a plain-scipy baseline."""

from __future__ import annotations

from liquidamp.commands._args import (
    Output,
    add_json_argument,
    add_quiet_argument,
    check_outputs,
    count_type,
    emit,
    json_path,
    progress_lines,
)


def register(sub) -> None:
    """Add the ``bench`` sub-command."""
    p = sub.add_parser(
        "bench", help="benchmark the fast simulation routes",
        description="Median wall times of the fast routes (compiled engine), of a user-style "
                    "scipy LSODA baseline at the same accuracy, their ratio and the first "
                    "call's time (compilation included) in fresh processes; JSON output.")
    add_json_argument(p, "timings")
    p.add_argument("--quick", action="store_true",
                   help="tiny configuration (seconds, for tests); numbers not representative")
    p.add_argument("--repeats", type=count_type("--repeats", 1, 1000, "repeats of the fast "
                                                "routes"), default=None,
                   help="repeats of the fast routes, 1-1000")
    p.add_argument("--cases", default=None,
                   help="comma list of cases (default all: steady_state_loop, calibration, "
                        "floquet_sweep, coupled_rotor, diagnosis, stiffness_sweep, "
                        "diagnosis_hidden_effects, diagnosis_3khz_20s, "
                        "diagnosis_200hz_10_cycles, dual_frequency)")
    add_quiet_argument(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """Run the benchmark and write the JSON."""
    check_outputs([Output("--json", json_path(args), "json")])
    from liquidamp.analysis.bench import run_bench

    cases = None
    if args.cases:
        cases = [c.strip() for c in args.cases.split(",") if c.strip()]
    bar = progress_lines(args.quiet, "bench")
    try:
        data = run_bench(quick=args.quick, repeats=args.repeats, cases=cases,
                         progress=lambda name: bar(str(name)))
    finally:
        bar.close()
    emit(args, "bench", data)
    return 0
