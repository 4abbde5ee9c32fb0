"""``liquidamp lco``: limit cycle of a rotor with liquid lag dampers.

``liquidamp lco --rotor hammond1974 --damper device_a --rpm 230
[--inoperative K] [--arm M] [--model full] [--t-end S] --json FILE
[--plot FILE]`` sizes the damper (:func:`liquidamp.analysis.stability.sizing.size_lag_damper`),
puts it on every operative blade, and reports the small-signal growth rate
of the critical mode, the growth rate of the full nonlinear time domain at
small amplitude, the describing-function prediction of the limit-cycle lag
amplitude and the simulated one (the blade that moves most; null where no
limit cycle exists: linearly stable, or growth to the chamber end).
"""

from __future__ import annotations

import math

from liquidamp.commands._args import (
    Output,
    add_json_argument,
    add_plot_argument,
    add_quiet_argument,
    check_outputs,
    emit,
    file_inputs,
    json_path,
    progress_bar,
    save_figure,
)
from liquidamp.commands._solver import add_solver_arguments, solver_options
from liquidamp.commands._units import MODEL_NAMES, name_type, preset_names, quantity_type
from liquidamp.commands.params import (
    add_measured_device_argument,
    measured_device,
    measured_entries,
)
from liquidamp.commands.sweep import _blade, _damper_names

#: Longest limit-cycle run [s]: the run keeps every sample (at least 200 per
#: second) and a limit cycle settles in 10-60 s.
MAX_T_END = 600.0

__all__ = ["register", "run"]


def register(subparsers) -> None:
    """Add the ``lco`` command."""
    p = subparsers.add_parser(
        "lco", help="limit cycle of a rotor with liquid lag dampers (linear, DF, time domain)",
        description=__doc__.split("\n\n", 1)[1])
    p.add_argument("--rotor", default="hammond1974",
                   type=name_type("--rotor", lambda: preset_names("rotor"), "rotor preset",
                                  files=True),
                   help="rotor preset ({rotors}) or .toml/.json file (default hammond1974)")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--damper",
                   type=name_type("--damper", _damper_names, "damper", files=True),
                   help="viscous, maxwell, a device preset ({presets}) or a device file, sized "
                   "to the rotor's lag damper")
    add_measured_device_argument(g)
    p.add_argument("--rpm", required=True, metavar="RPM",
                   type=quantity_type("--rpm", "rotor_speed", "rpm"),
                   help="rotor speed, rpm or with a unit (4Hz), > 0 and at most 10000 rpm")
    p.add_argument("--inoperative", action="append", default=[], metavar="K", type=_blade,
                   help="blade whose damper has failed (1-based; repeatable)")
    p.add_argument("--arm", default=None, metavar="LEN",
                   type=quantity_type("--arm", "length", "arm"),
                   help="damper arm, metres or with unit (250mm), at most 10 m")
    p.add_argument("--model", default="full", type=name_type("--model", MODEL_NAMES, "model"),
                   help="device model (default full): {models}")
    p.add_argument("--t-end", dest="t_end", default=None, metavar="S",
                   type=quantity_type("--t-end", "time", "t_end"),
                   help="simulated time of the limit-cycle run, s or with a unit (2min), at "
                   "most 600 s: the run keeps every sample, at least 200 per second (default "
                   "from the growth rate, 10-60 s)")
    add_json_argument(p, "results")
    add_plot_argument(p, "time-history figure")
    add_quiet_argument(p)
    add_solver_arguments(p, "rotor")
    p.set_defaults(func=run)


def analyse(rotor, Omega, device, inoperative=(), t_end=None, bar=None, options=None) -> dict:
    """Linear rate, time-domain rate, DF prediction and simulated amplitude (SI dict).

    ``bar`` (optional) has ``update()`` and is advanced after each of the four
    stages: critical mode, small-amplitude run, describing function, limit-cycle run.
    ``options`` (SolverOptions or None: the ``"rotor"`` preset) for the time-domain runs.
    """
    from liquidamp.analysis.stability.lco import critical_mode, predict_lco, simulate_lco

    def step():
        if bar is not None:
            bar.update()

    inop = tuple(inoperative)
    cm = critical_mode(rotor, Omega, device, inoperative=inop)
    step()
    sigma = cm.eigenvalue.real
    arm = rotor.blade.damper_arm
    # small-amplitude run: stroke 1e-6 x the stroke limit (quadratic loss negligible)
    lim = device.stroke_limit
    lag0 = (1e-4 * lim if math.isfinite(lim) else 1e-6) / arm
    Tb = 2 * math.pi / max(cm.blade_frequency, 1e-6)
    t_small = min(max(6 * Tb, 2.0 / max(abs(sigma), 1e-3)), 12.0)
    small = simulate_lco(rotor, Omega, device, inoperative=inop, initial_lag=lag0,
                         t_end=t_small, mode=cm, options=options)
    step()
    pred = predict_lco(rotor, Omega, device, inoperative=inop)
    step()
    out = {
        "rotor": rotor.name, "damper": device.label, "model": device.model.name,
        "rotor_speed [rpm]": Omega * 60 / (2 * math.pi), "inoperative_blades": list(inop),
        "damper_arm [m]": arm,
        "critical_eigenvalue [1/s]": [cm.eigenvalue.real, cm.eigenvalue.imag],
        "stability_method": cm.method,
        "blade_frequency [Hz]": cm.blade_frequency / (2 * math.pi),
        "linear_growth_rate [1/s]": sigma,
        "time_domain_growth_rate [1/s]": None if small.growth is None else small.growth.rate,
        "predicted_amplitude [rad]": pred.lag_amplitude,
        "predicted_stroke_amplitude [m]": pred.stroke_amplitude,
        "prediction_note": pred.note,
        "time_domain_amplitude [rad]": None,
    }
    run_ = small
    if sigma > 0:
        start = 0.8 * pred.lag_amplitude if pred.lag_amplitude else 10 * lag0
        T = t_end or min(max(12.0 / sigma, 10.0), 60.0)
        big = simulate_lco(rotor, Omega, device, inoperative=inop, initial_lag=start,
                           t_end=T, mode=cm, options=options)
        run_ = big
        settled = big.response.status == "completed" and big.amplitude_change < 0.05
        out["time_domain_status"] = big.response.status
        out["time_domain_message"] = big.response.message
        out["time_domain_amplitude_change [-]"] = big.amplitude_change
        out["time_domain_blade"] = big.blade
        if settled:
            out["time_domain_amplitude [rad]"] = big.lag_amplitude
        out["simulated_time [s]"] = float(big.response.time[-1])
    else:
        out["time_domain_status"] = "decays (linearly stable)"
        out["simulated_time [s]"] = float(small.response.time[-1])
    step()
    out["warnings"] = list(run_.response.warnings)
    return out, run_


def run(args) -> int:
    """Run the analysis and write the JSON (then the figure)."""
    options = solver_options(args, "rotor")
    check_outputs([Output("--json", json_path(args), "json"),
                   Output("--plot", args.plot, "plot")],
                  file_inputs(("--rotor", args.rotor), ("--damper", args.damper),
                              ("--device", args.device)))
    from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    from liquidamp.analysis.stability.sizing import lag_damper_device
    from liquidamp.structure.hostio import load_rotor

    rotor = load_rotor(args.rotor)
    inop = [rotor.check_blade(k) for k in args.inoperative]
    dev = None
    if args.device:
        device, dev = measured_device(args)
        if args.arm is not None:
            rotor = rotor.replace(blade=rotor.blade.replace(damper_arm=args.arm))
        sizing = None
    else:
        device, rotor, sizing = lag_damper_device(args.damper, rotor, arm=args.arm,
                                                  model=args.model)
    with progress_bar(4, "lco stages", args.quiet) as bar:
        data, sim = analyse(rotor, rpm_to_rad_s(args.rpm), device, inop, args.t_end, bar,
                            options)
    if sizing is not None:
        data["sizing"] = sizing.as_dict()
    if dev is not None:
        data.update(measured_entries(dev))
    amp = data["time_domain_amplitude [rad]"]
    emit(args, "lco", data,
         f"{rotor.name} + {device.label} at {args.rpm:g} rpm: linear rate "
         f"{data['linear_growth_rate [1/s]']:+.4f} 1/s; predicted LCO "
         f"{data['predicted_amplitude [rad]']} rad; simulated {amp} rad", "plot")
    if args.plot:
        save_figure(plot_lco(sim, data), args.plot, dpi=120)
    return 0


def plot_lco(sim, data: dict):
    """Lag angles and device strokes against time (returns the Figure)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = sim.response
    N = sum(1 for n in res.host_state_names if n.startswith("zeta_") and "dot" not in n)
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    for k in range(N):
        ax1.plot(res.time, res.host_states[k] * 180 / math.pi, lw=0.8, label=f"blade {k + 1}")
    pa = data.get("predicted_amplitude [rad]")
    if pa:
        for s in (1, -1):
            ax1.axhline(s * pa * 180 / math.pi, color="k", ls="--", lw=0.8)
    ax1.set_ylabel("lag [deg]")
    ax1.legend(fontsize=8, ncol=4)
    ax1.set_title(f"{data['rotor']} + {data['damper']} at {data['rotor_speed [rpm]']:.0f} rpm"
                  " (dashed: describing-function LCO)")
    for j, p in enumerate(res.port_names):
        ax2.plot(res.time, res.strokes[j] * 1e3, lw=0.8, label=p)
    ax2.set_ylabel("stroke [mm]")
    ax2.set_xlabel("time [s]")
    ax2.legend(fontsize=8, ncol=4)
    fig.tight_layout()
    return fig
