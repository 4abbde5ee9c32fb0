"""``liquidamp simulate``: one device model on the test machine, periodic steady state."""

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
    save_figure,
    working,
)
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands._units import MODEL_NAMES, name_type, quantity_type
from liquidamp.commands.params import add_device_arguments, device_and_effects, device_inputs


def add_model_argument(p, what: str = "device model") -> None:
    """Add ``--model NAME`` (checked at parse time)."""
    p.add_argument("--model", default="full", type=name_type("--model", MODEL_NAMES, "model"),
                   help=f"{what} (default %(default)s): {{models}}")


def register(sub) -> None:
    """Add the ``simulate`` sub-command."""
    p = sub.add_parser(
        "simulate", help="periodic steady state under a harmonic stroke",
        description="Run a device model under y = Y sin(2 pi f t) to its periodic steady "
        "state; write the first-harmonic dynamic stiffness, peak forces, lowest chamber "
        "pressure, mass-conservation error and steady-state residual as JSON.")
    add_device_arguments(p)
    add_model_argument(p)
    add_effect_argument(p)
    p.add_argument("--frequency", required=True, metavar="HZ",
                   type=quantity_type("--frequency", "frequency", "frequency"),
                   help="excitation frequency, Hz or with a unit (3Hz, 180rpm), at most 10 kHz")
    p.add_argument("--amplitude", required=True, metavar="LEN",
                   type=quantity_type("--amplitude", "length", "amplitude"),
                   help="stroke amplitude, SI metres or with a unit (3mm)")
    add_solver_arguments(p, "default")
    add_json_argument(p, "summary")
    add_plot_argument(p, "three-panel loop figure")
    add_quiet_argument(p)
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
    options = solver_options(args, "default")  # every argument before any numerical import
    check_outputs([Output("--json", json_path(args), "json"),
                   Output("--plot", args.plot, "plot")], device_inputs(args))
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.device.effects import with_effects
    from liquidamp.device.models import get_model
    from liquidamp.structure.testmachine import HarmonicStroke

    params, effects = device_and_effects(args)
    model = get_model(args.model)
    if effects:
        model = with_effects(model, *effects)
    stroke = HarmonicStroke(args.amplitude, args.frequency)
    with working("simulate: periodic steady state", args.quiet):
        response = steady_state(model, params, stroke, options=options)
    data = summary(response)
    if effects:
        data["effects"] = {e.name: e.as_dict() for e in effects}
    emit(args, "simulate", data, None, "plot")
    if args.plot:
        from liquidamp.analysis.reports.plots import plot_loops

        ideal = {"spring": ("spring",), "damper": ("damper",), "inerter": ("inerter",)}.get(
            params.name, ("spring", "damper", "inerter"))
        fig = plot_loops([response], ideal=ideal,
                         title=f"{params.name or 'device'}: model {model.name}")
        save_figure(fig, args.plot, dpi=110)
    return 0
