"""``liquidamp simulate``: one device model on the test machine, periodic steady state."""

from __future__ import annotations

import sys

from liquidamp.commands._args import (
    Output,
    add_effect_argument,
    check_outputs,
    effects_from_args,
    parse_length,
    print_warnings,
    write_json,
)
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands.params import add_device_arguments, device_from_args, device_inputs


def register(sub) -> None:
    """Add the ``simulate`` sub-command."""
    p = sub.add_parser(
        "simulate", help="periodic steady state under a harmonic stroke",
        description="Run a device model under y = Y sin(2 pi f t) to its periodic steady "
        "state; write the first-harmonic dynamic stiffness, peak forces, lowest chamber "
        "pressure, mass-conservation error and steady-state residual as JSON.")
    add_device_arguments(p)
    p.add_argument("--model", default="full",
                   help="device model (default %(default)s): {models}")
    add_effect_argument(p)
    p.add_argument("--frequency", required=True, type=float, help="excitation frequency [Hz]")
    p.add_argument("--amplitude", required=True,
                   help="stroke amplitude, SI metres or with unit (3mm)")
    add_solver_arguments(p, "default")
    p.add_argument("--json", default=None, help="output JSON (default stdout)")
    p.add_argument("--plot", default=None,
                   help="three-panel loop figure (.png, .pdf, .svg, ...; written after the JSON)")
    p.set_defaults(func=run)


def summary(response) -> dict:
    """JSON-ready summary of a steady-state response (SI, keys 'name [unit]')."""
    from liquidamp.analysis.response.harmonics import dynamic_stiffness

    K = dynamic_stiffness(response)
    return {
        "model": response.model,
        "preset": response.params.name,
        "frequency [Hz]": response.frequency,
        "amplitude [m]": response.amplitude,
        "dynamic_stiffness": {"magnitude [N/m]": K.magnitude, "phase [deg]": K.phase_deg,
                              "storage [N/m]": K.storage, "loss [N/m]": K.loss},
        "peak_force [N]": {"max": float(response.force.max()),
                           "min": float(response.force.min())},
        "min_pressure [Pa]": response.min_pressure,
        "mass_conservation_error [-]": response.mass_error,
        "steady_state_residual [-]": response.residual,
        "cycles": response.cycles,
        "status": response.status,
        "message": response.message,
        "warnings": list(response.warnings),
        "solver": dict(response.solver_stats),
    }


def run(args) -> int:
    """Run the simulation and write its summary (JSON first, then the figure)."""
    import json

    check_outputs([Output("--json", args.json, "json"), Output("--plot", args.plot, "plot")],
                  device_inputs(args))
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.device.effects import with_effects
    from liquidamp.device.models import get_model
    from liquidamp.structure.testmachine import HarmonicStroke

    options = solver_options(args, "default")
    params = device_from_args(args)
    model = get_model(args.model)
    effects = effects_from_args(args)
    if effects:
        model = with_effects(model, *effects)
    stroke = HarmonicStroke(parse_length(args.amplitude, "amplitude"), args.frequency)
    response = steady_state(model, params, stroke, options=options)
    data = summary(response)
    if effects:
        data["effects"] = {e.name: e.as_dict() for e in effects}
    if args.json:
        write_json(args.json, data)
    else:
        json.dump(data, sys.stdout, indent=2)
        print()
    print_warnings("simulate", data)
    if args.plot:
        from liquidamp.analysis.reports.plots import plot_loops

        ideal = {"spring": ("spring",), "damper": ("damper",), "inerter": ("inerter",)}.get(
            params.name, ("spring", "damper", "inerter"))
        fig = plot_loops([response], ideal=ideal,
                         title=f"{params.name or 'device'}: model {model.name}")
        fig.savefig(args.plot, dpi=110)
    return 0
