"""``liquidamp demo --out DIR``: the paper's case study, end to end."""

from __future__ import annotations

import json
import time
from pathlib import Path

from liquidamp.commands._args import (
    Output,
    add_overwrite_argument,
    add_quiet_argument,
    check_outputs,
    progress_lines,
    save_figure,
)
from liquidamp.commands._solver import add_solver_arguments, solver_options


def register(sub) -> None:
    """Add the ``demo`` sub-command."""
    p = sub.add_parser(
        "demo",
        help="reproduce the paper's case study (Figs. 7-11) into DIR/index.html",
        description="Reproduce Titurus (2018) Figs. 7-11 with the full model: PNGs and an "
        "index.html with the first-harmonic dynamic stiffness of every case.",
    )
    p.add_argument("--out", default="liquidamp-demo",
                   help="output folder (default %(default)s), built beside it and swapped in "
                   "whole; an existing index.html there is replaced only with --overwrite")
    add_quiet_argument(p)
    p.add_argument("--skip-diagnosis", action="store_true",
                   help="only the case study, not the calibrate-and-diagnose loop")
    p.add_argument("--skip-lag-damping", action="store_true",
                   help="leave out the lag damping in forward flight section")
    p.add_argument("--no-background-compile", dest="background_compile",
                   action="store_false",
                   help="on a first run (empty compile cache) with an idle core, the later "
                        "sections' kernels compile in a second process meanwhile; this "
                        "compiles them in this process only")
    add_solver_arguments(p, "casestudy")  # the case study; the diagnosis loop uses "fit"
    add_overwrite_argument(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """Run the demo; return the exit code."""
    options = solver_options(args, "casestudy")  # the arguments before the numerics
    check_outputs([Output("--out", args.out, "dir", ("index.html",))], force=args.overwrite)
    from liquidamp.analysis.reports.casestudy import run_case_study, write_case_study
    from liquidamp.atomic import atomic_folder

    start = time.perf_counter()
    bar = progress_lines(args.quiet, "demo")

    def progress(msg: str) -> None:
        bar(f"[{time.perf_counter() - start:.0f} s] {msg}")

    out = Path(args.out)
    # the later sections' kernels compile in a second process meanwhile (first run only)
    from liquidamp._warm import FAMILIES, Warmer

    later = [f for f, skip in (("effects", args.skip_diagnosis),
                               ("lag", args.skip_lag_damping)) if not skip]
    warmer = Warmer(later if args.background_compile else [])
    for family in warmer.todo:
        progress(f"compiling {FAMILIES[family][0]} in a second process (once; cached) ...")
    try:
        _prefer_full_kernel(options)
        study = run_case_study(options=options, progress=progress)
        with atomic_folder(out) as stage:
            extra = ""
            if not args.skip_diagnosis:
                warmer.wait("effects", progress)
                extra = _diagnosis_section(stage, progress)
            if not args.skip_lag_damping:
                warmer.wait("lag", progress)
                extra += _lag_section(stage, progress)
            write_case_study(study, stage, extra_html=extra)
    finally:
        warmer.stop()
        bar.close()
    index = out / "index.html"
    progress(f"wrote {index}")
    print(index)
    return 0


def _prefer_full_kernel(options) -> None:
    """Load the base models' integrator with RODAS4 before the case study.

    The case study meets stiff points, which need that kernel anyway; with
    it loaded and the explicit-only kernel not, ``"auto"`` runs it at once
    (:func:`liquidamp.coupled.fast._run`: the same steps), so a first run
    does not compile the explicit-only kernel as well.  A no-op from the
    cache, or on another engine or method.
    """
    from liquidamp.options import resolve_options

    opts = resolve_options(options, "casestudy")
    if opts.engine != "compiled" or opts.compiled_method != "auto":
        return
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.device.presets import preset
    from liquidamp.structure.testmachine import HarmonicStroke

    steady_state("maxwell", preset("reference"), HarmonicStroke(0.001, 3.0),
                 options=opts.replace(compiled_method="rodas4"))


def _diagnosis_section(out: Path, progress) -> str:
    """Run the measured-data loop on the bundled records; return its HTML summary."""
    import html

    from liquidamp.analysis.measured.diagnosis_demo import demo_loop

    progress("calibrate and diagnose the bundled synthetic records (undeclared effect) ...")
    summary = demo_loop(out / "diagnosis")
    nr = summary["nrmse"]
    added = ", ".join(summary["added"]) or "nothing"
    truth = ", ".join(e["name"] if isinstance(e, dict) and "name" in e else str(e)
                      for e in summary["truth_effects"]) or "none"
    progress(f"diagnosis added {added} (the records were made with {truth}); validation NRMSE "
             f"{nr['baseline']['validation']:.4f} -> {nr['final']['validation']:.4f}")
    report = Path(summary["report"]).relative_to(out)
    rows = "".join(
        f"<tr><td>{k}</td><td>{nr[k]['calibration']:.4f}</td><td>{nr[k]['validation']:.4f}</td>"
        "</tr>" for k in ("baseline", "final"))
    warnings = "".join(f"<li>{html.escape(str(w))}</li>" for w in summary["warnings"])
    return f"""
<h2>Closing the loop with measured data</h2>
<p>Two bundled synthetic test-machine records (3 Hz 3 mm for calibration, 4 Hz 2 mm for
validation; recipe in <code>liquidamp/analysis/measured/data/README.md</code>) hold an effect the
model does not declare ({html.escape(truth)}). The paper's four multipliers are calibrated, the
residual is traced to the catalogue of missing effects, and the best is added:
<b>{html.escape(added)}</b>. Stop reason: {html.escape(str(summary['stop_reason']))}.</p>
<table border=1 cellpadding=4 style='border-collapse:collapse'>
<tr><th>model</th><th>NRMSE calibration</th><th>NRMSE validation</th></tr>{rows}</table>
<ul>{warnings}</ul>
<p><a href="{report.as_posix()}">Full calibration and diagnosis report</a></p>
"""


def _lag_section(out: Path, progress) -> str:
    """Lag damping against the 1/rev stroke (paper_calibrated x2 and a friction damper)."""
    from liquidamp.analysis.reports.lag_plots import plot_lag_sweep
    from liquidamp.analysis.stability.lag_sweep import lag_damping_sweep
    from liquidamp.examples.forward_flight_lag_damping import MATCH_AMPLITUDE, OMEGA, devices

    progress("lag damping in forward flight (Floquet about the forced 1/rev orbit) ...")
    blade, devs, Fc = devices(names=("paper_calibrated",))
    strokes = (0.0, 1e-3, 2e-3)
    data = lag_damping_sweep(blade, OMEGA, devs, strokes, lag_amplitudes=(MATCH_AMPLITUDE,),
                             progress=progress)
    out.mkdir(parents=True, exist_ok=True)
    fig = plot_lag_sweep(data, title="Hammond blade, 4.2 Hz: lag damping under 1/rev motion")
    save_figure(fig, out / "lag_damping.png", dpi=110)
    (out / "lag_damping.json").write_text(json.dumps(data, indent=1))
    (p, f) = (data["devices"][k] for k in devs)
    zp, zf = p["floquet_damping_ratio [-]"], f["floquet_damping_ratio [-]"]
    single = f["klag_damping_ratio [-]"][0][0]
    return f"""
<h2>Lag damping in forward flight</h2>
<p>The Hammond (1974) blade at 4.2 Hz with two parallel <code>paper_calibrated</code> devices as
its lag damper, and a smooth-friction damper (F<sub>c</sub> = {Fc:.3g} N) of the same
single-frequency lag damping at the lag frequency and {1e3 * MATCH_AMPLITUDE:g} mm. Points: the lag
mode's damping by Floquet about the forced 1/rev orbit; lines: the prediction from the
dual-frequency stiffness K_lag at a {1e3 * MATCH_AMPLITUDE:g} mm lag motion.
The quadratic loss gains lag damping under 1/rev motion ({100 * zp[0]:.2f} % at rest,
{100 * zp[1]:.2f} % at 1 mm, {100 * zp[2]:.2f} % at 2 mm of 1/rev stroke); the friction damper
loses it ({100 * single:.2f} % for the lag motion alone by K_lag, none by Floquet at rest
where an infinitesimal lag motion sticks; {100 * zf[1]:.2f} % and
{100 * zf[2]:.2f} % at 1 and 2 mm: 2 F<sub>c</sub> / (&pi; &Omega; A<sub>1</sub>)).
Script: <code>python -m liquidamp.examples.forward_flight_lag_damping</code>.</p>
<img src="lag_damping.png" alt="lag damping against the 1/rev stroke">
"""
