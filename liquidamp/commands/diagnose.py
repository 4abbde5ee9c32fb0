"""``liquidamp diagnose``: calibrate, trace the residual to missing effects, add them."""

from __future__ import annotations

import sys

from liquidamp.commands._args import write_json
from liquidamp.commands._solver import solver_options
from liquidamp.commands.calibrate import add_fit_arguments, load


def register(sub) -> None:
    """Add the ``diagnose`` sub-command."""
    p = sub.add_parser(
        "diagnose", help="calibrate and add the catalogue effects the residual asks for",
        description="Calibrate on the records, rank the catalogue effects by the evidence in "
        "the residual, refit the best, keep one only if the held-out NRMSE falls by more than "
        "10%% and the BIC by more than 10; repeat. JSON: baseline, steps, final.")
    add_fit_arguments(p)
    p.add_argument("--max-steps", type=int, default=3, help="effects added at most")
    p.add_argument("--top", type=int, default=2, help="candidates refitted per step")
    p.set_defaults(func=run)


def run(args) -> int:
    """Diagnose and write the JSON (and report)."""
    from liquidamp.analysis.diagnosis import diagnose
    from liquidamp.errors import ParameterError

    options = solver_options(args, "fit")  # flags added by add_fit_arguments
    cal, val, params, spec = load(args)
    if not val:
        raise ParameterError("diagnose needs held-out records: --validate FILE [...]")
    d = diagnose(cal, val, model=args.model, params=params, spec=spec,
                 max_steps=args.max_steps, top=args.top, max_nfev=args.max_nfev,
                 options=options)
    write_json(args.json, d.as_dict())
    if args.report:
        from liquidamp.analysis.report_calibration import write_report

        write_report(args.report, diagnosis=d, title="liquidamp diagnose")
    for w in d.warnings:
        print(f"warning: {w}", file=sys.stderr)
    if d.unexplained:
        print(f"note: {d.unexplained}", file=sys.stderr)
    nr = d.as_dict()
    added = ", ".join(d.added) or "nothing"
    print(f"added: {added}; validation NRMSE {nr['baseline']['nrmse']['validation']:.4g} -> "
          f"{nr['final']['nrmse']['validation']:.4g} ({d.stop_reason}); wrote {args.json}")
    return 0
