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
    float_type,
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
    add_conditioning_arguments(p)
    p.add_argument("--json", required=True, help="output JSON file (.json)")
    p.add_argument("--report", default=None,
                   help="folder for an HTML report (index.html and PNGs, written after the "
                   "JSON); an existing report is replaced only with --force")
    add_force_argument(p)
    add_solver_arguments(p, "fit")


def _decimate(text: str):
    """argparse type of --decimate: 'auto' or an integer factor 1-10000."""
    import argparse

    if text.strip().lower() == "auto":
        return "auto"
    try:
        q = int(text)
    except ValueError:
        q = 0
    if not 1 <= q <= 10_000:
        raise argparse.ArgumentTypeError(f"--decimate must be 'auto' or an integer factor "
                                         f"1-10000 (1: none), got {text!r}")
    return q


def add_conditioning_arguments(p) -> None:
    """Record conditioning before the fit (liquidamp.analysis.measured.conditioning)."""
    p.add_argument("--force-filter", type=float_type("--force-filter", "Hz"), default=None,
                   metavar="HZ", help="zero-phase Butterworth low-pass of the force at HZ "
                   "(order 4, forward and backward) before fitting; the model's force is "
                   "filtered the same way; the JSON states what it removed (default: none)")
    p.add_argument("--decimate", type=_decimate, default="auto",
                   help="decimation factor of each record after a zero-phase anti-alias "
                   "low-pass at 0.8 x the new Nyquist frequency: auto (default) keeps "
                   "--harmonics harmonics of the stroke frequency; 1: none")
    p.add_argument("--harmonics", type=float_type("--harmonics", "-", low=2.0, high=1e4,
                                                  low_open=False),
                   default=30.0, help="harmonics of the stroke frequency kept by --decimate "
                   "auto (default %(default)s)")
    p.add_argument("--average", choices=("auto", "yes", "no"), default="auto",
                   help="average the whole cycles of a periodic record into one before "
                   "fitting (auto, default: at least 4 whole cycles; least squares on the "
                   "average is least squares on every cycle at a steady state)")


def conditioning_options(args) -> dict:
    """Keyword arguments of :func:`~liquidamp.analysis.measured.conditioning.condition` from
    the conditioning arguments."""
    return {"force_cutoff": args.force_filter, "decimate": args.decimate,
            "harmonics": args.harmonics,
            "average": {"auto": "auto", "yes": True, "no": False}[args.average]}


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
    from liquidamp.analysis.measured.calibration import PAPER_FOUR, FitSpec
    from liquidamp.commands.params import device_from_args

    effects = effects_from_args(args)
    cal = [_read(f, args.window, args.order) for f in args.records]
    val = [_read(f, args.window, args.order) for f in args.validate]
    params = device_from_args(args, default="paper_initial")
    vary = tuple(v.strip() for v in args.vary.split(",") if v.strip())
    # the default --vary leaves the model's structure to the start (spec None: calibrate
    # compares the fluid, friction and viscous starts, analysis.measured.device_class)
    spec = None if vary == PAPER_FOUR else FitSpec.default(vary=vary, effects=effects)
    return cal, val, params, effects, spec


def register(sub) -> None:
    """Add the ``calibrate`` sub-command."""
    p = sub.add_parser(
        "calibrate", help="fit device multipliers to measured records",
        description="Least-squares fit of the device model, driven by each record's stroke, "
        "to the recorded force (records conditioned first: --force-filter, --decimate, "
        "--average); JSON holds the calibrated parameters, standard errors, "
        "correlations, fit status, the NRMSE on calibration and validation records "
        "(conditioned) and what the conditioning did and removed. "
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
    from liquidamp.analysis.measured.calibration import calibrate, check_records
    from liquidamp.analysis.measured.conditioning import condition

    cal, val, params, effects, spec = load(args)
    # spikes, noise-only records and strokes past the chamber end are found in the records
    # as given (the conditioned ones are checked again by calibrate)
    check_records(tuple(cal) + tuple(val), params)
    kw = conditioning_options(args)
    cal, cc = zip(*(condition(r, **kw) for r in cal), strict=True)
    val, vc = zip(*(condition(r, **kw) for r in val), strict=True) if val else ((), ())
    res = calibrate(cal, model=args.model, params=params, effects=effects, spec=spec,
                    validate=val, max_nfev=args.max_nfev, options=options, sizing=args.sizing)
    d = res.as_dict()
    d["conditioning"] = [c.as_dict() for c in cc + vc]
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
