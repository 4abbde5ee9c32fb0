"""``liquidamp dual-frequency``: lag stiffness and damping under a two-frequency stroke.

For every (1/rev amplitude, lag amplitude) pair, the equivalent dynamic
stiffness at the lag frequency of the quasi-periodic steady state under
y = offset + A1 sin(2 pi f_rev t) + A2 sin(2 pi f_lag t)
(:func:`liquidamp.analysis.response.dual_frequency.dual_frequency_stiffness`).
JSON layout::

    {"preset": ..., "model": M, "method": ..., "rev_frequency [Hz]": ...,
     "lag_frequency [Hz]": ..., "offset [m]": ..., "rev_amplitude [m]": [...],
     "lag_amplitude [m]": [...],
     "points": [{"rev_amplitude [m]": ..., "lag_amplitude [m]": ..., "storage [N/m]": ...,
                 "loss [N/m]": ..., "equivalent_damping [N s/m]": ...,
                 "single_frequency_storage [N/m]": ..., "single_frequency_loss [N/m]": ...,
                 "single_frequency_equivalent_damping [N s/m]": ..., "rev_storage [N/m]": ...,
                 "rev_loss [N/m]": ..., "method": ..., "grid": [N1, N2], ...}, ...],
     "warnings": [...], "failures": [...]}

A failed point keeps its amplitudes, holds null values and its reason in
``"failure"`` and in ``"failures"``.
"""

from __future__ import annotations

from liquidamp.commands._args import (
    Output,
    add_effect_argument,
    add_json_argument,
    add_plot_argument,
    add_quiet_argument,
    check_outputs,
    emit,
    json_path,
    progress_bar,
    save_figure,
    warn_once,
)
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands._units import Bound, grid_type, quantity_type
from liquidamp.commands.params import add_device_arguments, device_and_effects, device_inputs
from liquidamp.commands.simulate import add_model_argument
from liquidamp.errors import ParameterError

#: Largest number of points (1/rev amplitudes x lag amplitudes).
MAX_POINTS = 2_000
_NULL_KEYS = ("storage [N/m]", "loss [N/m]", "equivalent_damping [N s/m]",
              "single_frequency_storage [N/m]", "single_frequency_loss [N/m]",
              "single_frequency_equivalent_damping [N s/m]", "rev_storage [N/m]",
              "rev_loss [N/m]")


def register(sub) -> None:
    """Add the ``dual-frequency`` sub-command."""
    p = sub.add_parser(
        "dual-frequency", help="lag stiffness and damping under 1/rev + lag motion",
        description="Equivalent dynamic stiffness at the lag frequency (storage K', loss K'', "
        "equivalent damping K''/omega) of a device moving at the rotor's 1/rev frequency and "
        "at the lag frequency at once, y = offset + A1 sin(2 pi f_rev t) + A2 sin(2 pi f_lag "
        "t), beside the single-frequency values for the lag motion alone. Two-frequency "
        "harmonic balance (default) or a time-domain run. Writes JSON and a plot of K' and "
        "K'' against the 1/rev amplitude, one line per lag amplitude.")
    add_device_arguments(p)
    add_model_argument(p)
    add_effect_argument(p)
    p.add_argument("--rev-frequency", required=True, metavar="HZ",
                   type=quantity_type("--rev-frequency", "frequency", "frequency"),
                   help="1/rev frequency f_rev = Omega / 2 pi [Hz], or with a unit (4.2Hz, "
                   "252rpm)")
    p.add_argument("--lag-frequency", required=True, metavar="HZ",
                   type=quantity_type("--lag-frequency", "frequency", "frequency"),
                   help="lag frequency f_lag = omega / 2 pi [Hz], or with a unit")
    p.add_argument("--rev-amplitude", required=True, metavar="LIST",
                   type=grid_type("--rev-amplitude", "length",
                                  Bound(0.0, 1.0, low_open=False,
                                        why=" (longer than any device's stroke)")),
                   help="1/rev stroke amplitudes A1 >= 0: comma list in SI metres or with a "
                   "unit (0,1mm,2mm) or START:STOP:COUNT (COUNT points linearly spaced)")
    p.add_argument("--lag-amplitude", required=True, metavar="LIST",
                   type=grid_type("--lag-amplitude", "length", "amplitude"),
                   help="lag stroke amplitudes A2 > 0: comma list in SI metres or with a unit "
                   "(0.5mm) or START:STOP:COUNT (COUNT points linearly spaced)")
    p.add_argument("--offset", default=0.0, metavar="LEN",
                   type=quantity_type("--offset", "length", "offset"),
                   help="mean stroke, SI metres or with a unit (default 0)")
    p.add_argument("--method", default="harmonic_balance",
                   choices=("harmonic_balance", "time"),
                   help="two-frequency harmonic balance (default) or a time-domain run "
                   "(periodic steady state over the common period where f_rev/f_lag is "
                   "rational)")
    add_solver_arguments(p, "default")
    add_json_argument(p, "points")
    add_plot_argument(p, "figure of K' and K'' against the 1/rev amplitude")
    add_quiet_argument(p)
    p.set_defaults(func=run, command_name="dual-frequency")


def run(args) -> int:
    """Compute every point; write the JSON, then the figure."""
    options = solver_options(args, "default")  # every argument before the numerics
    check_outputs([Output("--json", json_path(args), "json"),
                   Output("--plot", args.plot, "plot")], device_inputs(args))
    import numpy as np

    rev, lag = np.asarray(args.rev_amplitude, float), np.asarray(args.lag_amplitude, float)
    offset = args.offset
    if rev.size * lag.size > MAX_POINTS:
        raise ParameterError(f"--rev-amplitude x --lag-amplitude gives {rev.size} x {lag.size}"
                             f" = {rev.size * lag.size} points; at most {MAX_POINTS}")
    import warnings

    from liquidamp.analysis.response.dual_frequency import check_inputs, dual_frequency_stiffness
    from liquidamp.device.effects import with_effects
    from liquidamp.device.models import get_model
    from liquidamp.errors import ConvergenceError, LiquidampWarning, PressureError

    params, effects = device_and_effects(args)
    model = get_model(args.model)
    if effects:
        model = with_effects(model, *effects)
    # every input is checked before the first point: the largest stroke, the model
    check_inputs(model, params, args.rev_frequency, args.lag_frequency, float(rev.max()),
                 float(lag.max()), offset=offset, method=args.method)
    points, failures, warns = [], [], []

    with progress_bar(rev.size * lag.size, "dual-frequency points", args.quiet) as bar:
        for A2 in sorted(lag):
            for A1 in sorted(rev):
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", LiquidampWarning)
                        r = dual_frequency_stiffness(
                            model, params, args.rev_frequency, args.lag_frequency, float(A1),
                            float(A2), offset=offset, method=args.method, options=options)
                    points.append(r.as_dict())
                    warns += [f"1/rev {A1:g} m, lag {A2:g} m: {w}" for w in r.warnings]
                except (ConvergenceError, PressureError) as exc:
                    msg = f"1/rev {A1:g} m, lag {A2:g} m: {exc}"
                    failures.append(msg)
                    point = {"rev_amplitude [m]": float(A1), "lag_amplitude [m]": float(A2)}
                    point.update(dict.fromkeys(_NULL_KEYS))
                    point["failure"] = str(exc)
                    points.append(point)
                bar.update()
    data = {
        "preset": params.name,
        "model": model.name,
        "method": args.method,
        "rev_frequency [Hz]": args.rev_frequency,
        "lag_frequency [Hz]": args.lag_frequency,
        "offset [m]": offset,
        "rev_amplitude [m]": sorted(rev.tolist()),
        "lag_amplitude [m]": sorted(lag.tolist()),
        "points": points,
        "warnings": list(dict.fromkeys(warns)),
        "failures": failures,
    }
    if effects:
        data["effects"] = {e.name: e.parameters for e in effects}
    wrote = ", ".join(str(f) for f in (json_path(args), args.plot) if f)
    emit(args, "dual-frequency", data, f"wrote {wrote}" if wrote else None, "plot")
    for msg in failures:
        warn_once("dual-frequency", f"point failed: {msg}")
    if args.plot:
        from liquidamp.analysis.reports.dual_frequency_plots import plot_dual_frequency

        fig = plot_dual_frequency(points, title=(
            f"{params.name or 'device'}, model {model.name}: lag {args.lag_frequency:g} Hz "
            f"under 1/rev {args.rev_frequency:g} Hz"))
        save_figure(fig, args.plot, dpi=110)
    return 0
