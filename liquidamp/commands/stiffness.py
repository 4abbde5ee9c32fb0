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
import math
import sys
from pathlib import Path

from liquidamp.commands._args import parse_length, parse_list, write_json
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands.params import add_device_arguments, device_from_args

LINEAR_MODELS = ("full", "maxwell", "dashpot_inerter", "inertial_2state")


def register(sub) -> None:
    """Add the ``stiffness`` sub-command."""
    p = sub.add_parser(
        "stiffness", help="dynamic stiffness: linear models vs nonlinear first harmonic",
        description="Magnitude and phase of the dynamic stiffness K*(f) of the linear models "
        "(full linearized at rest, Maxwell eq. 16, dashpot+inerter eq. 19, eq. 18) with the "
        "first harmonic of the nonlinear periodic steady state and the equivalent "
        "linearization at each stroke amplitude overlaid. Writes PNG, CSV and JSON.")
    add_device_arguments(p)
    p.add_argument("--frequency", required=True,
                   help="frequencies [Hz]: comma list or START:STOP:COUNT (log-spaced)")
    p.add_argument("--amplitude", required=True,
                   help="stroke amplitudes: comma list (SI metres or with unit, 1mm) or "
                   "START:STOP:COUNT (linear)")
    p.add_argument("--out", required=True, help="output directory (PNG, CSV, JSON)")
    p.add_argument("--json", default=None, help="also write the JSON here")
    p.add_argument("--model", default="full",
                   help="nonlinear model for the first-harmonic points (default %(default)s)")
    add_solver_arguments(p, "default")
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
    >>> amplitude_key(parse_length("1mm"))
    '0.001'
    """
    return repr(float(value))


def run(args) -> int:
    """Compute the sweep, write PNG, CSV and JSON."""
    from liquidamp.analysis.linear import linearize, transfer_function
    from liquidamp.analysis.stiffness import equivalent_sweep, linear_stiffness, nonlinear_stiffness
    from liquidamp.analysis.stiffness_plots import plot_dynamic_stiffness
    from liquidamp.device.models import get_model

    options = solver_options(args, "default")
    params = device_from_args(args)
    model = get_model(args.model).name
    freqs = parse_list(args.frequency, "frequency", log=True)
    amps = parse_list(args.amplitude, "amplitude", item=lambda t: parse_length(t, "amplitude"))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    linear = []
    for name in LINEAR_MODELS + ((model,) if model not in LINEAR_MODELS else ()):
        if name == "full" or name not in ("maxwell", "dashpot_inerter", "inertial_2state"):
            linear.append(linear_stiffness(linearize(name, params), freqs, label=name))
        else:
            linear.append(linear_stiffness(transfer_function(name, params), freqs, label=name))
    nl = nonlinear_stiffness(params, freqs, amps, model=model, on_error="skip", options=options)
    eq = equivalent_sweep(params, freqs, amps, model=model)

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
    for i, Y in enumerate(amps):
        d = _curve_dict(nl.curve(i))
        d["min_pressure [Pa]"] = _clean(nl.min_pressure[i])
        d["cycles"] = nl.cycles[i].tolist()
        data["nonlinear"][amplitude_key(Y)] = d
        e = _curve_dict(eq.curve(i))
        e["valid"] = eq.valid[i].tolist()
        e["min_pressure [Pa]"] = _clean(eq.min_pressure[i])
        data["equivalent"][amplitude_key(Y)] = e

    with open(out / "stiffness.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["curve", "amplitude [m]", "frequency [Hz]", "magnitude [N/m]",
                    "phase [deg]", "storage [N/m]", "loss [N/m]"])
        rows = [(f"linear:{c.label}", "", c) for c in linear]
        rows += [(f"nonlinear:{model}", amplitude_key(Y), nl.curve(i))
                 for i, Y in enumerate(amps)]
        rows += [(f"equivalent:{model}", amplitude_key(Y), eq.curve(i))
                 for i, Y in enumerate(amps)]
        for label, amp, c in rows:
            for k, fk in enumerate(c.frequency):
                vals = [c.magnitude[k], c.phase_deg[k], c.storage[k], c.loss[k]]
                w.writerow([label, amp, f"{fk:.10g}"]
                           + ["" if not math.isfinite(v) else f"{v:.10g}" for v in vals])
    fig = plot_dynamic_stiffness(linear, nl, eq,
                                 title=f"{params.name or 'device'}: dynamic stiffness, "
                                 f"nonlinear model {model}")
    fig.savefig(out / "stiffness.png", dpi=110)
    write_json(out / "stiffness.json", data)
    if args.json:
        write_json(args.json, data)
    for msg in nl.failures:
        print(f"warning: point failed: {msg}", file=sys.stderr)
    print(f"wrote {out / 'stiffness.png'}, {out / 'stiffness.csv'}, {out / 'stiffness.json'}")
    return 0
