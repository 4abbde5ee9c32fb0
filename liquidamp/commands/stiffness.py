"""``liquidamp stiffness``: Bode / dynamic-stiffness report, linear against nonlinear.

Writes into ``--out DIR``: ``stiffness.png`` (magnitude and phase of K*),
``stiffness.csv`` (one row per curve and frequency) and ``stiffness.json``
(also to ``--json FILE`` if given).  JSON layout::

    {"preset": ..., "model": M, "frequency [Hz]": [...],
     "amplitude_keys": "stroke amplitude in metres, repr of the float",
     "linear": {MODEL: {"magnitude [N/m]": [...], "phase [deg]": [...], ...}},
     "nonlinear": {AMPLITUDE: {"magnitude [N/m]": [...], "phase [deg]": [...], ...}},
     "equivalent": {AMPLITUDE: {"magnitude [N/m]": [...], "phase [deg]": [...],
                                "valid": [...]}},
     "warnings": [...], "failures": [...]}

``linear`` holds ``full`` (eq. 10 linearized at rest, = eq. 18 with B at p0
and the linear loss), ``maxwell`` (eq. 16), ``dashpot_inerter`` (eq. 19),
``inertial_2state`` (eq. 18) and the linearized ``--model`` if it is another
one.  ``nonlinear`` holds the first harmonic of ``--model``'s periodic steady
state at each amplitude (null where a point failed, listed in
``failures``); ``equivalent`` the amplitude-dependent equivalent
linearization of ``--model``.  AMPLITUDE keys are amplitudes in metres as
strings, e.g. ``"0.001"``.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

from liquidamp.commands._args import (
    Output,
    add_effect_argument,
    add_json_argument,
    add_overwrite_argument,
    add_quiet_argument,
    check_outputs,
    emit,
    json_path,
    progress_bar,
    save_figure,
    warn_once,
)
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands._units import grid_type
from liquidamp.commands.params import add_device_arguments, device_and_effects, device_inputs
from liquidamp.commands.simulate import add_model_argument
from liquidamp.errors import ParameterError

#: Default ``--frequency``: 13 log-spaced points from 0.5 to 20 Hz.
DEFAULT_FREQUENCY = "log:0.5:20:13"
LINEAR_MODELS = ("full", "maxwell", "dashpot_inerter", "inertial_2state")
#: Largest number of nonlinear points (frequencies x amplitudes); each is a
#: periodic steady state of 0.01-1 s.
MAX_GRID = 10_000
#: Files written into ``--out``.
FILES = ("stiffness.json", "stiffness.csv", "stiffness.png")


def register(sub) -> None:
    """Add the ``stiffness`` sub-command."""
    p = sub.add_parser(
        "stiffness", help="dynamic stiffness: linear models vs nonlinear first harmonic",
        description="Magnitude and phase of the dynamic stiffness K*(f) of the linear models "
        "(full linearized at rest, Maxwell eq. 16, dashpot+inerter eq. 19, eq. 18) with the "
        "first harmonic of the nonlinear periodic steady state and the equivalent "
        "linearization at each stroke amplitude overlaid. Writes PNG, CSV and JSON.")
    add_device_arguments(p)
    p.add_argument("--frequency", default=DEFAULT_FREQUENCY, metavar="LIST",
                   type=grid_type("--frequency", "frequency", "frequency"),
                   help="frequencies, Hz or with a unit: comma list, START:STOP:COUNT (COUNT "
                   "points linearly spaced) or log:START:STOP:COUNT (log-spaced) (default "
                   f"{DEFAULT_FREQUENCY})")
    p.add_argument("--amplitude", required=True, metavar="LIST",
                   type=grid_type("--amplitude", "length", "amplitude"),
                   help="stroke amplitudes: comma list (SI metres or with unit, 1mm) or "
                   "START:STOP:COUNT (COUNT points linearly spaced from START to STOP)")
    p.add_argument("--out", required=True,
                   help="output folder: stiffness.json, stiffness.csv, stiffness.png, built "
                   "beside it and swapped in whole; an existing one is replaced only with "
                   "--overwrite")
    add_json_argument(p, "JSON (also written into --out)")
    add_model_argument(p, "nonlinear model for the first-harmonic points")
    add_effect_argument(p, " The effects apply to the nonlinear first-harmonic points only; "
                        "the linear and equivalent curves are of the model without them.")
    add_solver_arguments(p, "default")
    add_overwrite_argument(p)
    add_quiet_argument(p)
    p.set_defaults(func=run)


def _clean(values) -> list:
    return [None if not math.isfinite(v) else float(v) for v in values]


def _curve_dict(c) -> dict:
    return {"magnitude [N/m]": _clean(c.magnitude), "phase [deg]": _clean(c.phase_deg),
            "storage [N/m]": _clean(c.storage), "loss [N/m]": _clean(c.loss)}


def amplitude_key(value: float) -> str:
    """JSON key of an amplitude [m]: ``repr`` of the float, e.g. ``'0.001'``.

    Examples
    --------
    >>> amplitude_key(1e-3)
    '0.001'
    """
    return repr(float(value))


def _nonlinear(params, model, freqs, amps, quiet: bool, options=None):
    """``nonlinear_stiffness`` point by point under a progress bar (same numbers)."""
    import numpy as np

    from liquidamp.analysis.response.stiffness import NonlinearStiffness, nonlinear_stiffness

    shape = (amps.size, freqs.size)
    value = np.full(shape, np.nan, complex)
    pmin, res = np.full(shape, np.nan), np.full(shape, np.nan)
    cyc = np.zeros(shape, int)
    warns, fails = [], []
    name = None
    with progress_bar(amps.size * freqs.size, "stiffness points", quiet) as bar:
        for i, Y in enumerate(amps):
            for j, fj in enumerate(freqs):
                r = nonlinear_stiffness(params, [fj], [Y], model=model, on_error="skip",
                                        options=options)
                name = r.model
                value[i, j], pmin[i, j] = r.value[0, 0], r.min_pressure[0, 0]
                res[i, j], cyc[i, j] = r.residual[0, 0], r.cycles[0, 0]
                warns += r.warnings
                fails += r.failures
                bar.update()
    return NonlinearStiffness(model=name, params=params, frequency=freqs, amplitude=amps,
                              value=value, min_pressure=pmin, residual=res, cycles=cyc,
                              warnings=tuple(warns), failures=tuple(fails))


def run(args) -> int:
    """Compute the sweep; write JSON, CSV, then PNG (data before the figure) into a folder
    built beside ``--out`` and swapped in whole."""
    from liquidamp.atomic import atomic_folder

    options = solver_options(args, "default")  # every argument before the numerics
    out = Path(args.out)
    check_outputs([Output("--out", args.out, "dir", FILES),
                   Output("--json", json_path(args), "json")],
                  device_inputs(args), force=args.overwrite)
    n_f, n_a = len(args.frequency), len(args.amplitude)
    if n_f * n_a > MAX_GRID:
        raise ParameterError(
            f"frequency x amplitude grid has {n_f} x {n_a} = {n_f * n_a} nonlinear points; at "
            f"most {MAX_GRID} (each is a periodic steady state of 0.01-1 s, about "
            f"{n_f * n_a * 0.05:.0f} s in all)")
    import numpy as np

    freqs = np.asarray(args.frequency, float)
    amps = np.asarray(args.amplitude, float)
    from liquidamp.analysis.response.linear import linearize, transfer_function
    from liquidamp.analysis.response.stiffness import equivalent_sweep, linear_stiffness
    from liquidamp.device.effects import with_effects
    from liquidamp.device.models import check_input_channels, get_model

    params, effects = device_and_effects(args)
    model = get_model(args.model).name
    nl_model = with_effects(get_model(model), *effects) if effects else model
    # an effect that reads a measured channel is refused here, before any sweep
    check_input_channels(get_model(nl_model), (), "a harmonic stroke (the dynamic stiffness)")

    # the equivalent sweep is cheap and checks every frequency and amplitude first
    eq = equivalent_sweep(params, freqs, amps, model=model)
    linear = []
    for name in LINEAR_MODELS + ((model,) if model not in LINEAR_MODELS else ()):
        if name == "full" or name not in ("maxwell", "dashpot_inerter", "inertial_2state"):
            linear.append(linear_stiffness(linearize(name, params), freqs, label=name))
        else:
            linear.append(linear_stiffness(transfer_function(name, params), freqs, label=name))
    nl = _nonlinear(params, nl_model, freqs, amps, args.quiet, options)

    data = {
        "preset": params.name,
        "model": model,
        "frequency [Hz]": freqs.tolist(),
        "amplitude_keys": "stroke amplitude in metres, repr of the float (e.g. '0.001')",
        "linear": {c.label: _curve_dict(c) for c in linear},
        "nonlinear": {},
        "equivalent": {},
        "warnings": list(nl.warnings) + [f"equivalent: {w}" for w in eq.warnings],
        "failures": list(nl.failures),
    }
    if effects:
        data["effects"] = {e.name: e.as_dict() for e in effects}
        data["effects_note"] = (f"nonlinear points: model {nl.model}; the linear and "
                                f"equivalent curves are of {model} without the effects")
    for i, Y in enumerate(amps):
        d = _curve_dict(nl.curve(i))
        d["min_pressure [Pa]"] = _clean(nl.min_pressure[i])
        d["cycles"] = nl.cycles[i].tolist()
        data["nonlinear"][amplitude_key(Y)] = d
        e = _curve_dict(eq.curve(i))
        e["valid"] = eq.valid[i].tolist()
        e["min_pressure [Pa]"] = _clean(eq.min_pressure[i])
        data["equivalent"][amplitude_key(Y)] = e

    from liquidamp.analysis.reports.stiffness_plots import plot_dynamic_stiffness

    fig = plot_dynamic_stiffness(linear, nl, eq,
                                 title=f"{params.name or 'device'}: dynamic stiffness, "
                                 f"nonlinear model {nl.model}")
    with atomic_folder(out) as stage:
        _write_csv(stage / "stiffness.csv", linear, nl, eq, amps, model)
        (stage / "stiffness.json").write_text(json.dumps(data, indent=2, allow_nan=False)
                                              + "\n")
        save_figure(fig, stage / "stiffness.png", dpi=110)
    emit(args, "stiffness", data,
         f"wrote {out / 'stiffness.json'}, {out / 'stiffness.csv'}, {out / 'stiffness.png'}",
         "out")
    for msg in nl.failures:
        warn_once("stiffness", f"point failed: {msg}")
    return 0


def _write_csv(path, linear, nl, eq, amps, model) -> None:
    """One row per curve and frequency (SI)."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["curve", "amplitude [m]", "frequency [Hz]", "magnitude [N/m]",
                    "phase [deg]", "storage [N/m]", "loss [N/m]"])
        rows = [(f"linear:{c.label}", "", c) for c in linear]
        rows += [(f"nonlinear:{nl.model}", amplitude_key(Y), nl.curve(i))
                 for i, Y in enumerate(amps)]
        rows += [(f"equivalent:{model}", amplitude_key(Y), eq.curve(i))
                 for i, Y in enumerate(amps)]
        for label, amp, c in rows:
            for k, fk in enumerate(c.frequency):
                vals = [c.magnitude[k], c.phase_deg[k], c.storage[k], c.loss[k]]
                w.writerow([label, amp, f"{fk:.10g}"]
                           + ["" if not math.isfinite(v) else f"{v:.10g}" for v in vals])
