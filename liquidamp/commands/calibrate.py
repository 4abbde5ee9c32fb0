"""``liquidamp calibrate``: fit a device model to measured records, validate on others."""

from __future__ import annotations

import sys

from liquidamp.commands._args import (
    Output,
    add_effect_argument,
    add_force_argument,
    check_outputs,
    count_type,
    effects_from_args,
    file_inputs,
    print_warnings,
    write_json,
)
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands.params import add_device_arguments, device_inputs

#: Files the HTML report writes into ``--report DIR``.
REPORT_FILES = ("index.html", "records.png", "loops_calibration.png",
                "residuals_calibration.png", "loops_validation.png", "residuals_validation.png")


def add_fit_arguments(p) -> None:
    """Arguments shared by calibrate and diagnose."""
    p.add_argument("records", nargs="+", metavar="RECORD",
                   help="calibration record CSV files (time [s], displacement [mm] or [m], "
                   "force [N] or [kN])")
    p.add_argument("--validate", action="append", default=[], metavar="FILE",
                   help="held-out record CSV file; repeat the option for several")
    add_device_arguments(p, default="paper_initial")
    p.add_argument("--model", default="full",
                   help="device model (default %(default)s): {models}")
    add_effect_argument(p, " Their default fit keys are fitted, starting from the values "
                        "given.")
    p.add_argument("--vary", default="inv_gamma1,inv_gamma2,c1,c2",
                   help="comma list of multipliers to fit (default %(default)s)")
    p.add_argument("--window", type=count_type("--window", 3, 10_001,
                                               "Savitzky-Golay window [samples]"),
                   default=21, help="Savitzky-Golay window [samples] (default %(default)s)")
    p.add_argument("--order", type=count_type("--order", 1, 10, "Savitzky-Golay order"),
                   default=4, help="Savitzky-Golay polynomial order (default %(default)s)")
    p.add_argument("--max-nfev", type=count_type("--max-nfev", 1, 100_000,
                                                 "model evaluations per fit"),
                   default=80,
                   help="model evaluations per fit, 1-100000 (default %(default)s)")
    p.add_argument("--json", required=True, help="output JSON file (.json)")
    p.add_argument("--report", default=None,
                   help="folder for an HTML report (index.html and PNGs, written after the "
                   "JSON); an existing report is replaced only with --force")
    add_force_argument(p)
    add_solver_arguments(p, "fit")


def check_fit_outputs(args, command: str) -> None:
    """Check --json and --report against the inputs; warn if a record validates itself.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed calibrate/diagnose arguments.
    command : str
        Command name for the stderr warning.

    Raises
    ------
    ParameterError
        An output that would overwrite an input or an existing report, or a
        bad output path (see :func:`liquidamp.commands._args.check_outputs`).
    """
    from pathlib import Path

    inputs = file_inputs(("RECORD", args.records), ("--validate", args.validate))
    inputs += device_inputs(args)
    check_outputs([Output("--json", args.json, "json"),
                   Output("--report", args.report, "dir", REPORT_FILES)],
                  inputs, force=args.force)
    cal = {Path(f).resolve() for f in args.records}
    for f in args.validate:
        if Path(f).resolve() in cal:
            print(f"liquidamp {command}: warning: validation record {f!r} is also a "
                  "calibration record: its validation error is not held-out",
                  file=sys.stderr)


def _read(path, window: int, order: int):
    """read_record, with an error that names the file for a file that is not text."""
    from liquidamp.analysis.measured.records import read_record
    from liquidamp.errors import DataFileError

    try:
        return read_record(path, window, order)
    except UnicodeDecodeError as exc:
        raise DataFileError(f"record {str(path)!r} is not a text CSV file ({exc.reason} at "
                            f"byte {exc.start})") from None


def load(args):
    """Records, validation records, start parameters, effects and fit spec from the arguments."""
    from liquidamp.analysis.measured.calibration import FitSpec
    from liquidamp.commands.params import device_from_args

    effects = effects_from_args(args)
    cal = [_read(f, args.window, args.order) for f in args.records]
    val = [_read(f, args.window, args.order) for f in args.validate]
    params = device_from_args(args, default="paper_initial")
    vary = tuple(v.strip() for v in args.vary.split(",") if v.strip())
    return cal, val, params, effects, FitSpec.default(vary=vary, effects=effects)


def register(sub) -> None:
    """Add the ``calibrate`` sub-command."""
    p = sub.add_parser(
        "calibrate", help="fit device multipliers to measured records",
        description="Least-squares fit of the device model, driven by each record's stroke, "
        "to the recorded force; JSON holds the calibrated parameters, standard errors, "
        "correlations, fit status and the NRMSE on calibration and validation records. "
        "Exit code 1 if the fit did not converge (the JSON says so).")
    add_fit_arguments(p)
    p.add_argument("--sizing", choices=("auto", "preset", "data"), default="auto",
                   help="device the fit starts from: auto (default) the --preset/--device when "
                   "the records are near it (RMS force within 4x, stroke within half the "
                   "chamber), else a similar device sized to the records; preset: always the "
                   "given device; data: always the sized device")
    p.set_defaults(func=run)


def run(args) -> int:
    """Calibrate; exit 1 if the fit did not converge (the JSON says so)."""
    options = solver_options(args, "fit")  # the arguments first, then the outputs
    check_fit_outputs(args, "calibrate")
    from liquidamp.analysis.measured.calibration import calibrate

    cal, val, params, effects, spec = load(args)
    res = calibrate(cal, model=args.model, params=params, effects=effects, spec=spec,
                    validate=val, max_nfev=args.max_nfev, options=options, sizing=args.sizing)
    d = res.as_dict()
    write_json(args.json, d)
    print_warnings("calibrate", d)
    if args.report:
        from liquidamp.analysis.reports.report_calibration import write_report

        write_report(args.report, result=res, title="liquidamp calibrate")
    if not res.converged:
        print(f"liquidamp calibrate: warning: calibration did not converge: {res.message}",
              file=sys.stderr)
        return 1
    print(f"calibrated: {res.summary()}; wrote {args.json}")
    return 0
