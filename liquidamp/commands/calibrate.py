"""``liquidamp calibrate``: fit a device model to measured records, validate on others."""

from __future__ import annotations

import sys

from liquidamp.commands._args import (
    Output,
    add_effect_argument,
    add_json_argument,
    add_overwrite_argument,
    add_quiet_argument,
    check_outputs,
    count_type,
    emit,
    file_inputs,
    json_path,
    json_to_stdout,
    warn_once,
)
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands._units import quantity_type
from liquidamp.commands.params import add_device_arguments, device_and_effects, device_inputs
from liquidamp.commands.simulate import add_model_argument

#: Files the HTML report writes into ``--report DIR``.
REPORT_FILES = ("index.html", "records.png", "loops_calibration.png",
                "residuals_calibration.png", "loops_validation.png", "residuals_validation.png",
                "damper_fv_0.png", "damper_fv_0.svg", "damper_peaks.png", "damper_peaks.svg")


def add_fit_arguments(p) -> None:
    """Arguments shared by calibrate and diagnose."""
    p.add_argument("records", nargs="+", metavar="RECORD",
                   help="calibration record CSV files (time [s], displacement [mm], [m] or [in], "
                   "force [N], [kN], [lbf] or [kip])")
    p.add_argument("--validate", action="append", default=[], metavar="FILE",
                   help="held-out record CSV file; repeat the option for several")
    add_device_arguments(p, default="paper_initial")
    add_model_argument(p)
    add_effect_argument(p, " Their default fit keys are fitted, starting from the values "
                        "given (so are those of the --device file's effects).")
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
    p.add_argument("--outliers", choices=("refuse", "drop", "keep"), default="refuse",
                   help="spikes found in the records as read (a sample that leaves its "
                   "neighbours and comes back by more than the record's own local rates): "
                   "refuse (default) the records, listing every spike with its file line; "
                   "drop the force spikes (a displacement spike is still refused: the stroke "
                   "drives the model); keep every spike, fitted as recorded")
    p.add_argument("--force-sign", choices=("auto", "as-read", "flip"), default="auto",
                   help="the force's sign convention: auto (default) reads a record whose "
                   "loop delivers energy (a damper's loop drawn backwards: at least 25%% of "
                   "RMS(F) x RMS(v), beyond 5 standard errors) with its force negated and "
                   "says so first in the summary; as-read keeps every sign (such a record "
                   "is refused); flip negates every force")
    add_json_argument(p, "fit")
    p.add_argument("--report", default=None, metavar="DIR",
                   help="folder for an HTML report (index.html and PNGs, written after the "
                   "JSON, built beside DIR and swapped in whole); an existing report is "
                   "replaced only with --overwrite")
    p.add_argument("--save-device", default=None, metavar="FILE",
                   help="write the fitted device as a device file (.toml or .json): "
                   "parameters with p0 and n, effects, and a [fit] table with the varied "
                   "parameters' names, values, standard errors and covariance; every "
                   "command's --device reads it back")
    add_overwrite_argument(p)
    add_quiet_argument(p)
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
    p.add_argument("--force-filter", default=None, metavar="HZ",
                   type=quantity_type("--force-filter", "frequency", "filter"),
                   help="zero-phase Butterworth low-pass of the force at HZ (Hz or with a unit) "
                   "(order 4, forward and backward) before fitting; the model's force is "
                   "filtered the same way; the JSON states what it removed (default: none)")
    p.add_argument("--decimate", type=_decimate, default="auto",
                   help="decimation factor of each record after a zero-phase anti-alias "
                   "low-pass at 0.8 x the new Nyquist frequency: auto (default) keeps "
                   "--harmonics harmonics of the stroke frequency; 1: none")
    p.add_argument("--harmonics", type=quantity_type("--harmonics", "reduced", "harmonics"),
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
    check_outputs([Output("--json", json_path(args), "json"),
                   Output("--report", args.report, "dir", REPORT_FILES),
                   Output("--save-device", args.save_device, "device")],
                  inputs, force=args.overwrite)
    cal = {Path(f).resolve() for f in args.records}
    for f in args.validate:
        if Path(f).resolve() in cal:
            warn_once(command, f"validation record {f!r} is also a calibration record: its "
                      "validation error is not held-out")


def _read(path, window: int, order: int):
    """read_record, with an error that names the file for a file that is not text."""
    from liquidamp.analysis.measured.records import read_record
    from liquidamp.errors import DataFileError

    try:
        return read_record(path, window, order)
    except UnicodeDecodeError as exc:
        raise DataFileError(f"record {str(path)!r} is not a text CSV file ({exc.reason} at "
                            f"byte {exc.start})") from None


def checked(cal, val, args, params, command: str):
    """The records after the data checks, as read, with ``--outliers``
    (:func:`~liquidamp.analysis.measured.checks.check_records`): refused with every problem
    and file line, or with their force spikes dropped, or their spikes kept, before any
    conditioning."""
    from liquidamp.analysis.measured.checks import check_records, drop_outliers, keep_outliers

    recs = tuple(cal) + tuple(val)
    # the chamber end bounds the stroke only where the device keeps its size (--sizing
    # preset); otherwise the start stretches the chambers to the records (start.stroke_factor)
    held = params if getattr(args, "sizing", "preset") == "preset" else None
    quality, _ = check_records(recs, held, outliers=args.outliers, what=command, cli=True)
    if args.outliers != "refuse":
        how = drop_outliers if args.outliers == "drop" else keep_outliers
        recs = tuple(how(r, q) for r, q in zip(recs, quality, strict=True))
    return list(recs[:len(cal)]), list(recs[len(cal):])


def load(args):
    """Records, validation records, start parameters, effects and fit spec from the arguments."""
    from liquidamp.analysis.measured.calibration import PAPER_FOUR, FitSpec

    params, effects = device_and_effects(args, default="paper_initial")
    from liquidamp.analysis.measured.checks import orient_force

    cal = [orient_force(_read(f, args.window, args.order), args.force_sign)
           for f in args.records]
    val = [orient_force(_read(f, args.window, args.order), args.force_sign)
           for f in args.validate]
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


def fit_table(res, source: str) -> dict:
    """The ``[fit]`` table of a device file for a CalibrationResult ``res``.

    Covariance of the varied parameters (multipliers [-], effect parameters
    [SI]) from their standard errors and correlation: C_ij = s_i s_j r_ij;
    ``log`` says which were fitted in log space (their correlation is that of
    the logarithms, and s_i = v_i sd(log v_i)), so that a reader can carry the
    covariance back to the fit's space
    (:class:`liquidamp.analysis.stability.margins.FitUncertainty`).
    """
    import math

    names = list(res.varying)
    se = [float(res.stderr.get(n, math.nan)) for n in names]
    corr = res.correlation
    cov = [[se[i] * se[j] * float(corr[i][j]) for j in range(len(names))]
           for i in range(len(names))]
    return {"source": source, "model": res.model, "status": res.status,
            "nrmse_calibration": float(res.nrmse_calibration),
            "nrmse_validation": (float(res.nrmse_validation)
                                 if res.nrmse_validation is not None else math.nan),
            "varied": names, "values": [float(res.values[n]) for n in names],
            "stderr": se, "covariance": cov,
            "log": [bool(res.spec[n].log) for n in names]}


def save_device(path, res, source: str) -> None:
    """Write the fitted device of ``res`` (parameters, effects, fit table) to ``path``."""
    from liquidamp.device import write_device_file

    write_device_file(path, res.params, res.effects, fit=fit_table(res, source))


def write_report_folder(folder, **kwargs) -> None:
    """The HTML report, built beside ``folder`` and swapped in whole."""
    from liquidamp.analysis.reports.report_calibration import write_report
    from liquidamp.atomic import atomic_folder

    with atomic_folder(folder) as stage:
        write_report(stage, **kwargs)


def fit_progress(args, desc: str):
    """A tqdm bar of model evaluations (nothing with --quiet or without a terminal)."""
    from liquidamp.commands._args import progress_bar

    return progress_bar(None, desc, args.quiet)


def run(args) -> int:
    """Calibrate; exit 1 if the fit did not converge (the JSON says so)."""
    options = solver_options(args, "fit")  # the arguments first, then the outputs
    check_fit_outputs(args, "calibrate")
    from liquidamp.analysis.measured.calibration import calibrate
    from liquidamp.analysis.measured.conditioning import condition

    cal, val, params, effects, spec = load(args)
    # spikes, noise-only records and strokes past the chamber end are found in the records
    # as read, before any conditioning (calibrate checks the same records as read again)
    cal, val = checked(cal, val, args, params, "calibrate")
    kw = conditioning_options(args)
    cal, cc = zip(*(condition(r, **kw) for r in cal), strict=True)
    val, vc = zip(*(condition(r, **kw) for r in val), strict=True) if val else ((), ())
    with fit_progress(args, "calibrate: model evaluations") as bar:
        res = calibrate(cal, model=args.model, params=params, effects=effects, spec=spec,
                        validate=val, max_nfev=args.max_nfev, options=options,
                        sizing=args.sizing, progress=bar.update,
                        outliers=args.outliers)
    d = res.as_dict()
    d["conditioning"] = [c.as_dict() for c in cc + vc]
    from liquidamp.analysis.reports.damper_characteristics import result_characteristics

    d["damper_characteristics"] = result_characteristics(res)
    if args.save_device:
        save_device(args.save_device, res, "liquidamp calibrate")
    wrote = ", ".join(str(f) for f in (json_path(args), args.save_device) if f)
    emit(args, "calibrate", d, None, "report", "save_device")
    if args.report:
        write_report_folder(args.report, result=res, title="liquidamp calibrate")
    if not res.converged:
        warn_once("calibrate", f"calibration did not converge: {res.message}")
        return 1
    line = f"calibrated: {res.summary()}" + (f"; wrote {wrote}" if wrote else "")
    print(line, file=sys.stderr if json_to_stdout(args, "report", "save_device") else sys.stdout)
    return 0
