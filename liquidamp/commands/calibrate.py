"""``liquidamp calibrate``: fit a device model to measured records, validate on others."""

from __future__ import annotations

import sys

from liquidamp.commands._args import write_json
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands.params import add_device_arguments


def add_fit_arguments(p) -> None:
    """Arguments shared by calibrate and diagnose."""
    p.add_argument("records", nargs="+", help="calibration record CSV files")
    p.add_argument("--validate", nargs="*", default=[], help="held-out record CSV files")
    add_device_arguments(p)
    p.add_argument("--model", default="full", help="device model (default %(default)s)")
    p.add_argument("--vary", default="inv_gamma1,inv_gamma2,c1,c2",
                   help="comma list of multipliers to fit (default %(default)s)")
    p.add_argument("--window", type=int, default=21, help="Savitzky-Golay window [samples]")
    p.add_argument("--order", type=int, default=4, help="Savitzky-Golay order")
    p.add_argument("--max-nfev", type=int, default=80, help="model evaluations per fit")
    p.add_argument("--json", required=True, help="output JSON file")
    p.add_argument("--report", default=None, help="directory for an HTML report")
    add_solver_arguments(p, "fit")


def load(args):
    """Records, validation records, start parameters and fit spec from the arguments."""
    from liquidamp.analysis.calibration import FitSpec
    from liquidamp.analysis.records import read_record
    from liquidamp.commands.params import device_from_args

    cal = [read_record(f, args.window, args.order) for f in args.records]
    val = [read_record(f, args.window, args.order) for f in args.validate]
    params = device_from_args(args, default="paper_initial")
    vary = tuple(v.strip() for v in args.vary.split(",") if v.strip())
    return cal, val, params, FitSpec.default(vary=vary)


def register(sub) -> None:
    """Add the ``calibrate`` sub-command."""
    p = sub.add_parser(
        "calibrate", help="fit device multipliers to measured records",
        description="Least-squares fit of the device model, driven by each record's stroke, "
        "to the recorded force; JSON holds the calibrated parameters, standard errors, "
        "correlations, fit status and the NRMSE on calibration and validation records.")
    add_fit_arguments(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """Calibrate; exit 1 if the fit did not converge (the JSON says so)."""
    from liquidamp.analysis.calibration import calibrate

    options = solver_options(args, "fit")
    cal, val, params, spec = load(args)
    res = calibrate(cal, model=args.model, params=params, spec=spec, validate=val,
                    max_nfev=args.max_nfev, options=options)
    write_json(args.json, res.as_dict())
    if args.report:
        from liquidamp.analysis.report_calibration import write_report

        write_report(args.report, result=res, title="liquidamp calibrate")
    if not res.converged:
        print(f"warning: calibration did not converge: {res.message}", file=sys.stderr)
        return 1
    d = res.as_dict()
    val_txt = d["nrmse"]["validation"]
    val_txt = "n/a" if val_txt is None else f"{val_txt:.4g}"
    print(f"calibrated ({res.nfev} evaluations): NRMSE calibration "
          f"{d['nrmse']['calibration']:.4g}, validation {val_txt}; wrote {args.json}")
    return 0
