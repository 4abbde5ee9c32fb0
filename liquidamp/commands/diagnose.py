"""``liquidamp diagnose``: calibrate, trace the residual to missing effects, add them."""

from __future__ import annotations

import sys

from liquidamp.commands._args import count_type, emit, json_path, json_to_stdout, warn_once
from liquidamp.commands._solver import solver_options
from liquidamp.commands._units import COMPOSITE_NAMES, EFFECT_UNITS, name_type
from liquidamp.commands.calibrate import (
    add_fit_arguments,
    check_fit_outputs,
    checked,
    conditioning_options,
    fit_progress,
    load,
    save_device,
    write_report_folder,
)

#: Model evaluations per fit of ``liquidamp diagnose`` without ``--max-nfev``: the
#: library's :attr:`Budget.max_nfev <liquidamp.analysis.measured.diagnosis_options.Budget>`
#: (a literal here, so the parser is built without importing the fitting code; the test of
#: the command's defaults holds the two equal).
DIAGNOSE_MAX_NFEV = 60


def register(sub) -> None:
    """Add the ``diagnose`` sub-command."""
    p = sub.add_parser(
        "diagnose", help="calibrate and add the catalogue effects the residual asks for",
        description="Condition the records (--force-filter, --decimate, --average), "
        "calibrate, score every catalogue effect and composite on the residual, refit the "
        "best, keep one only if it predicts every held-out record no worse than 2% and "
        "together better by more than 2%, the calibration BIC counted over the samples the "
        "kept band can hold falls by more than 10, and no parameter it frees ends at a "
        "bound; the best held-out one wins. Repeat until the residual is at the noise floor. "
        "Where the start's class (fluid, friction, viscous) was in doubt and the residual "
        "stays above the noise, the runner-up start is diagnosed too and replaces the first "
        "only where its final model passes the same rule against it. "
        "The line F = c v + k y + F0 and the two-slope force-velocity map are fitted on the "
        "same split. JSON: summary (verdict first), held-out NRMSE per record, reference "
        "models, drift, conditioning, noise floors, baseline, steps, final. Without "
        "--validate the last record, or the second half of one record of 6+ cycles, is held "
        "out.")
    add_fit_arguments(p)
    # the diagnosis's budget per fit (Budget.max_nfev; calibrate's is its own): the command
    # without flags runs the library's defaults (tests/test_options.py)
    p.set_defaults(max_nfev=DIAGNOSE_MAX_NFEV)
    p.add_argument("--max-steps", type=count_type("--max-steps", 0, 8, "effects added at most"),
                   default=5, help="effects added at most, 0-8 (default %(default)s; the "
                   "loop stops earlier at the noise floor or where no candidate passes)")
    p.add_argument("--sizing", choices=("auto", "preset", "data"), default="auto",
                   help="device the baseline calibration starts from, as for calibrate: auto "
                   "(default) the --preset/--device when the records are near it, else a "
                   "similar device sized to the records; preset: always the given device; "
                   "data: always the sized device")
    p.add_argument("--top", type=count_type("--top", 1, 8, "candidates refitted per step"),
                   default=2, help="candidates refitted per step, 1-8 (default %(default)s)")
    p.add_argument("--candidate", action="append", default=None, metavar="NAME",
                   type=name_type("--candidate", tuple(EFFECT_UNITS) + COMPOSITE_NAMES,
                                  "candidate effect"),
                   help="consider only the named candidates (repeat the flag): catalogue "
                   "effects, the composites backlash, friction_asymmetry, "
                   "friction_transition, and inertance (the channel inertance S_t freed) "
                   "(default: every catalogue effect with fitted parameters, every "
                   "composite and inertance)")
    p.set_defaults(func=run)


def diagnose_config(args):
    """The :class:`~liquidamp.analysis.measured.diagnosis_options.DiagnoseOptions` of the
    parsed ``diagnose`` arguments ``args`` (without any flag: ``DiagnoseOptions()``)."""
    from liquidamp.analysis.measured.diagnosis_options import DiagnoseOptions

    return DiagnoseOptions.from_keywords(
        candidates=args.candidate, sizing=args.sizing, max_steps=args.max_steps,
        top=args.top, max_nfev=args.max_nfev, outliers=args.outliers,
        **conditioning_options(args))


def run(args) -> int:
    """Diagnose and write the JSON (then the report)."""
    options = solver_options(args, "fit")  # flags added by add_fit_arguments
    check_fit_outputs(args, "diagnose")
    from liquidamp.analysis.measured.candidates import DEVICE_REFINEMENTS
    from liquidamp.analysis.measured.diagnosis import COMPOSITES, diagnose
    from liquidamp.device.effects import EFFECTS
    from liquidamp.errors import check_choice

    for name in args.candidate or ():  # before the records are read
        check_choice("candidate effect", name, {**EFFECTS, **COMPOSITES, **DEVICE_REFINEMENTS})

    cal, val, params, effects, spec = load(args)
    # the data checks first, as read, naming the command-line options (diagnose repeats
    # them on the same records)
    cal, val = checked(cal, val, args, params, "diagnose")
    config = diagnose_config(args)
    with fit_progress(args, "diagnose: model evaluations") as bar:
        d = diagnose(cal, val, model=args.model, params=params, effects=effects, spec=spec,
                     options=options, config=config, progress=bar.update)
    nr = d.as_dict()
    from liquidamp.analysis.reports.damper_characteristics import (
        gas_line,
        result_characteristics,
    )

    nr["damper_characteristics"] = result_characteristics(d.final)
    if args.save_device:
        save_device(args.save_device, d.final, "liquidamp diagnose")
    emit(args, "diagnose", nr, None, "report", "save_device")
    if d.unexplained:
        print(f"liquidamp diagnose: note: {d.unexplained}", file=sys.stderr)
    if args.report:
        write_report_folder(args.report, diagnosis=d, title="liquidamp diagnose")
    if d.final.flags:
        warn_once("diagnose", f"final fit: {d.final.flags.short()}")
    print(f"liquidamp diagnose: {d.summary().splitlines()[0]}", file=sys.stderr)
    gas = nr["damper_characteristics"].get("gas_charge")
    if gas:  # the identifiable numbers of a gas charge (issue #20)
        print("liquidamp diagnose: " + gas_line(gas), file=sys.stderr)
    added = ", ".join(d.added) or "nothing"
    raw = (f", {d.nrmse_raw['validation']:.4g} on the records as given"
           if d.nrmse_raw else "")
    wrote = ", ".join(str(f) for f in (json_path(args), args.save_device) if f)
    print(f"added: {added}; validation NRMSE {nr['baseline']['nrmse']['validation']:.4g} -> "
          f"{nr['final']['nrmse']['validation']:.4g}{raw} ({d.stop_reason}); noise floor "
          f"{d.noise_nrmse:.3g}; final fit {d.final.summary()}"
          + (f"; wrote {wrote}" if wrote else ""),
          file=sys.stderr if json_to_stdout(args, "report", "save_device") else sys.stdout)
    return 0
