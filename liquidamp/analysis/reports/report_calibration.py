"""HTML report of a calibration or a diagnosis, with PNG figures.

Compute and plot are separate: the plot functions take results and return
a matplotlib Figure (Agg backend, imported lazily); :func:`write_report`
saves them and an ``index.html`` beside them.

Contents: every record (stroke and force against time); the loops (force
against displacement and against velocity) measured, before and after each
step; the residual against time, displacement and velocity before and after;
the ranking of candidates with their evidence; the error table before and
after.
"""

from __future__ import annotations

import html
from pathlib import Path

import numpy as np

from liquidamp.atomic import save_figure, write_text

__all__ = ["plot_records", "plot_loops_fit", "plot_residuals", "plot_fit", "write_report",
           "CSS"]

CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif;
       max-width: 1100px; margin: 2em auto; padding: 0 1em; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; border-bottom: 2px solid #3b6ea5; padding-bottom: .2em; }
h2 { font-size: 1.25em; margin-top: 1.6em; color: #1d3f66; }
h3 { font-size: 1.05em; margin-top: 1.2em; }
table { border-collapse: collapse; margin: .6em 0; font-size: .9em; }
th, td { border: 1px solid #c8d0da; padding: .3em .6em; text-align: left; vertical-align: top; }
th { background: #eef3f8; }
tr:nth-child(even) td { background: #fafbfc; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
img { max-width: 100%; height: auto; border: 1px solid #e3e7ec; margin: .4em 0; }
pre { background: #f6f8fa; padding: .8em; overflow-x: auto; font-size: .85em; }
.warn { background: #fff6e0; border-left: 4px solid #e0a800; padding: .4em .8em; }
.bad { background: #fdecea; border-left: 4px solid #c62828; padding: .4em .8em; }
.ok { background: #e8f5e9; border-left: 4px solid #2e7d32; padding: .4em .8em; }
figcaption { font-size: .85em; color: #555; }
"""
"""Style sheet of the HTML reports (calibration, diagnosis, the demo page)."""

#: Resolution of the report figures [dots per inch].
DPI = 150


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_records(records):
    """Stroke [mm] and force [N] against time [s] of each record.

    Parameters
    ----------
    records : sequence of Record
        Measured records (time [s], displacement [m], force [N]).

    Returns
    -------
    matplotlib.figure.Figure
        One row per record, force on a twin axis.
    """
    plt = _plt()
    fig, axes = plt.subplots(len(records), 1, figsize=(8, 2.6 * len(records)), squeeze=False)
    for ax, r in zip(axes[:, 0], records, strict=True):
        ax.plot(r.time, r.displacement * 1e3, "C0", lw=0.8)
        ax.set_ylabel("stroke [mm]", color="C0")
        ax2 = ax.twinx()
        ax2.plot(r.time, r.force, "C3", lw=0.8)
        ax2.set_ylabel("force [N]", color="C3")
        what = (f"{r.describe()}, {r.cycles:.1f} cycles" if r.periodic
                else f"{r.describe()}, {r.time[-1] - r.time[0]:.3g} s")
        ax.set_title(f"{r.label}: {what}" if r.label != r.describe() else what, fontsize=9)
    axes[-1, 0].set_xlabel("time [s]")
    fig.tight_layout()
    return fig


def _role_grid(results, role, ncols, width, row_height):
    """The first result's ``role`` records and a Figure with one row of axes per record.

    ``width`` and ``row_height`` are the figure's width and height per row [in].
    """
    first = results[0]
    recs = first.calibration if role == "calibration" else first.validation
    fig, axes = _plt().subplots(len(recs), ncols, figsize=(width, row_height * len(recs)),
                                squeeze=False)
    return recs, fig, axes


def plot_loops_fit(results, labels, role="calibration"):
    """Force against displacement and velocity: measured and each result's model.

    Parameters
    ----------
    results : sequence of CalibrationResult
        Results sharing the same records; the first one's records are plotted.
    labels : sequence of str
        Legend label of each result.
    role : {"calibration", "validation"}
        Which records (and predictions) to plot.

    Returns
    -------
    matplotlib.figure.Figure
        One row per record: force [N] against displacement [mm] (offset
        removed) and against velocity [mm/s].
    """
    recs, fig, axes = _role_grid(results, role, 2, 10, 3.4)
    for i, r in enumerate(recs):
        y = (r.smoothed - r.offset) * 1e3
        for j, x in enumerate((y, r.velocity * 1e3)):
            ax = axes[i, j]
            ax.plot(x, r.force, ".", ms=2, color="0.5", label="measured")
            for k, (res, lab) in enumerate(zip(results, labels, strict=True)):
                preds = (res.predictions_calibration if role == "calibration"
                         else res.predictions_validation)
                ax.plot(x, preds[i], "-", lw=0.9, color=f"C{k}", label=lab)
            ax.set_xlabel("displacement [mm]" if j == 0 else "velocity [mm/s]")
            ax.set_ylabel("force [N]")
            ax.set_title(f"{role}: {r.label}", fontsize=9)
        axes[i, 0].legend(fontsize=7)
    fig.tight_layout()
    return fig


def plot_residuals(results, labels, role="calibration"):
    """Residual (model - measured) [N] against time, displacement and velocity.

    Parameters
    ----------
    results, labels, role
        As in :func:`plot_loops_fit` (``role`` selects the residuals too).

    Returns
    -------
    matplotlib.figure.Figure
        One row per record: residual [N] against time [s], displacement [mm]
        (offset removed) and velocity [mm/s].
    """
    recs, fig, axes = _role_grid(results, role, 3, 12, 3.0)
    for i, r in enumerate(recs):
        xs = (r.time, (r.smoothed - r.offset) * 1e3, r.velocity * 1e3)
        names = ("time [s]", "displacement [mm]", "velocity [mm/s]")
        for k, (res, lab) in enumerate(zip(results, labels, strict=True)):
            e = res.residuals(role)[i]
            for j in range(3):
                axes[i, j].plot(xs[j], e, "." if j else "-", ms=2, lw=0.7, color=f"C{k}",
                                label=lab)
        for j in range(3):
            axes[i, j].set_xlabel(names[j])
            axes[i, j].set_ylabel("residual [N]")
        axes[i, 0].set_title(f"{role}: {r.label}", fontsize=9)
        axes[i, 0].legend(fontsize=7)
    fig.tight_layout()
    return fig


def plot_fit(result, role: str = "calibration"):
    """Measured and fitted force over time, and the force-displacement loops.

    Parameters
    ----------
    result : CalibrationResult
        A calibration (:func:`liquidamp.analysis.measured.calibration.calibrate`).
    role : {"calibration", "validation"}
        Which records (and predictions).

    Returns
    -------
    matplotlib.figure.Figure
        One row per record: force [N] against time [s] (measured dots,
        model line, dropped outliers as red crosses) and force [N] against
        displacement [mm] (offset removed); NRMSE in each title.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    from liquidamp.errors import ParameterError

    if role not in ("calibration", "validation"):
        raise ParameterError(f"role must be 'calibration' or 'validation', got {role!r}")
    recs = result.calibration if role == "calibration" else result.validation
    if not recs:
        raise ParameterError(f"the result has no {role} records to plot")
    preds = (result.predictions_calibration if role == "calibration"
             else result.predictions_validation)
    errs = {e.label: e.nrmse for e in result.record_errors if e.role == role}
    fig = Figure(figsize=(11, 3.4 * len(recs)), layout="constrained")
    axes = fig.subplots(len(recs), 2, squeeze=False, width_ratios=(1.7, 1))
    for i, (r, f) in enumerate(zip(recs, preds, strict=True)):
        ax, ax2 = axes[i]
        ax.plot(r.time, r.force, ".", ms=2.5, color="0.45", label="measured")
        ax.plot(r.time, f, "-", lw=1.2, color="C0", label=f"model ({result.model})")
        drop = [o for lab, o in result.dropped if lab == r.label]
        if drop:
            ax.plot([o.time for o in drop], [o.value for o in drop], "x", color="C3", ms=7,
                    label=f"dropped outliers ({len(drop)})")
            lo, hi = np.percentile(r.force, [0.5, 99.5])
            pad = 0.15 * (hi - lo)
            ax.set_ylim(lo - pad, hi + pad)  # the spikes would flatten the record
        ax.set_xlabel("time [s]")
        ax.set_ylabel("force [N]")
        what = r.describe() if r.periodic else f"{r.shape.kind} stroke"
        ax.set_title(f"{role}: {r.label} ({what}), NRMSE "
                     f"{errs.get(r.label, float('nan')):.3g}", fontsize=9)
        ax.legend(fontsize=7, loc="upper right")
        y = (r.smoothed - r.offset) * 1e3
        ax2.plot(y, r.force, ".", ms=2.5, color="0.45", label="measured")
        ax2.plot(y, f, "-", lw=1.0, color="C0", label="model")
        if drop:
            ax2.set_ylim(ax.get_ylim())
        ax2.set_xlabel("displacement [mm]")
        ax2.set_ylabel("force [N]")
        ax2.set_title("force-displacement loop", fontsize=9)
    fig.suptitle(f"{result.model}: {result.status}, NRMSE calibration "
                 f"{result.nrmse_calibration:.3g}", fontsize=10)
    return fig


def _table(rows, header):
    out = ["<table><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>"]
    for row in rows:
        out.append("<tr>" + "".join(
            f"<td class='num'>{html.escape(_fmt(c))}</td>" if isinstance(c, (int, float))
            else f"<td>{html.escape(_fmt(c))}</td>" for c in row) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def _fmt(c):
    if c is None:
        return "-"
    if isinstance(c, float):
        return f"{c:.4g}"
    if isinstance(c, dict):
        return ", ".join(f"{k}={_fmt(v)}" for k, v in c.items())
    return str(c)


def _flag(res, name: str) -> str:
    """'at upper bound', 'stderr > value', 'unused' or '' for a parameter of a result."""
    f = res.flags
    if name in f.at_bound:
        return f"AT {f.at_bound[name][2].upper()} BOUND"
    if name in f.undetermined:
        return "NOT DETERMINED (stderr > value)"
    if name in f.unused:
        return "UNUSED"
    return ""


def _start_section(res) -> list[str]:
    """The device the fit started from and every start tried (HTML parts)."""
    if not res.start:
        return []
    st = res.start
    head = (f"sized to the records: {st.get('device')} ({st.get('reason')})" if st.get("sized")
            else f"{st.get('device')} as given ({st.get('reason')})")
    out = ["<h2>Start</h2>", f"<p>Start device: {html.escape(head)}. Start chosen: "
           f"{html.escape(str(st.get('chosen')))}. Near rule: "
           f"{html.escape(str(st.get('near_rule')))}.</p>"]
    rows = [[t.label, t.nrmse, t.peak_model, t.peak_measured, t.rms_ratio,
             t.loss_share_model, t.loss_share_measured, t.cause, t.error]
            for t in res.start_trials]
    out.append(_table(rows, ["start", "NRMSE", "peak force model [N]",
                             "peak force measured [N]", "RMS ratio", "loss share model",
                             "loss share measured", "what was off", "error"]))
    if res.class_starts:
        out.append(f"<h3>Device class: {html.escape(res.device_class)}</h3><p>"
                   f"{html.escape(str(st.get('device_class_rule', '')))}.</p>")
        out.append(_table([[o.name, o.nrmse_calibration, o.nrmse_validation,
                            _fmt(o.validation_records), o.k, o.bic,
                            "yes" if o.admissible else "no", "chosen" if o.chosen else "",
                            o.reason or o.error] for o in res.class_starts],
                          ["start", "NRMSE calibration", "NRMSE validation",
                           "validation per record", "parameters", "BIC (N_eff)",
                           "held-out admissible", "", "read off the records"]))
    return out


def _drift_cell(q) -> str:
    """The data-quality table's drift verdict of one record (DataQuality.drift)."""
    d = getattr(q, "drift", None)
    if d is None or not d.tested:
        return "not tested"
    unit = "cycle" if d.method == "cycles" else "window"
    text = (f"{d.amplitude_trend:+.3g} %/{unit} ({100 * d.amplitude_change:+.3g} % over "
            f"{d.segments}), p = {d.amplitude_p:.2g}")
    return ("NON-STATIONARY: " if d.nonstationary else "stationary: ") + text


def _verdict_section(final, diagnosis) -> list[str]:
    """The verdict first (the summary's first line), then the held-out NRMSE per record of
    the physics model beside the reference models fitted on the same split."""
    out = []
    if diagnosis is not None:
        lines = diagnosis.summary().splitlines()
        bad = bool(diagnosis.non_stationary or diagnosis.unexplained
                   or diagnosis.loses_to_line)
        out.append(f"<div class='{'bad' if bad else 'ok'}'><b>{html.escape(lines[0])}</b>"
                   + "".join(f"<br>{html.escape(x)}" for x in lines[1:]) + "</div>")
    else:
        lose = final.versus_line()
        out.append(f"<div class='{'bad' if lose else 'ok'}'><b>"
                   f"{html.escape(final.summary())}</b></div>")
    refs = final.references if final.validation else {}
    if refs:
        out.append("<h2>Held-out NRMSE per record: physics model and reference models</h2>")
        out.append("<p>Reference models fitted on the same calibration records: the line "
                   "F = c v + k y + F0 and the two-slope force-velocity map per direction "
                   "with its knee (what a damper dynamometer reports).  The pooled figure is "
                   "given beside the records.</p>")
        per = final.heldout_records()
        rows = [[lab, per[lab]] + [r.validation_of(lab) for r in refs.values()]
                for lab in per]
        rows.append(["pooled", final.nrmse_validation]
                    + [r.nrmse_validation for r in refs.values()])
        out.append(_table(rows, ["held-out record", "physics model"]
                          + [f"{k}: {html.escape(r.formula)}" for k, r in refs.items()]))
        out.append(_table([[k, r.parameters] for k, r in refs.items()],
                          ["reference model", "parameters (SI)"]))
    return out


def _plausibility_section(results, labels) -> list[str]:
    """Fitted geometry the records cannot support, per fit (HTML parts; none: [])."""
    rows = [[lab, f.kind, f.message] for res, lab in zip(results, labels, strict=True)
            for f in res.plausibility]
    if not rows:
        return []
    return ["<h2>Plausibility</h2><div class='warn'>", _table(rows, ["fit", "flag", "finding"]),
            "</div>"]


def _damper_section(out: Path, final, label: str) -> list[str]:
    """The dynamometer's numbers and figures (measured and ``final``'s model) as HTML.

    Figures are written as PNG (shown) and SVG (linked) in the journal style of
    :mod:`liquidamp.analysis.reports.damper_plots`.
    """
    from liquidamp.analysis.reports.damper_characteristics import damper_characteristics
    from liquidamp.analysis.reports.damper_plots import attribution_of, write_damper_figures
    from liquidamp.errors import ParameterError

    recs = list(final.calibration)
    preds = list(final.predictions_calibration)
    parts = ["<h2>Damper characteristics (calibration records; compression: stroke rate "
             "&gt; 0)</h2>",
             "<p>Two-slope force-velocity map per direction (the reference model "
             "<code>two_slope</code>); gas force: the force at zero velocity at mid stroke "
             "(the loop's offset at mid stroke with the map's damping force removed).</p>"]
    try:
        rows = []
        for who, forces in (("measured", None), (f"model: {label}", preds)):
            d = damper_characteristics(recs, forces)
            rows.append([who, d["gas_force [N]"]] + [
                d[k][q] for k in ("compression", "rebound")
                for q in ("c_low [N s/m]", "c_high [N s/m]", "knee_velocity [m/s]")])
        parts.append(_table(rows, ["", "gas force [N]", "compression c low [N s/m]",
                                   "compression c high [N s/m]", "compression knee [m/s]",
                                   "rebound c low [N s/m]", "rebound c high [N s/m]",
                                   "rebound knee [m/s]"]))
        written = write_damper_figures(out, recs, preds, prefix="damper")
    except ParameterError as exc:
        return parts + [f"<p class='warn'>No damper characteristics: {html.escape(str(exc))}"
                        "</p>"]
    if any("temperature" in r.channels and int(r.cycles) < 2 for r in recs):
        parts.append("<p>The temperature channel is not drawn cycle by cycle: the records "
                     "were conditioned into fewer than two cycles (cycle averaging); "
                     "<code>--average no</code> keeps them.</p>")
    att = next((a for a in map(attribution_of, recs) if a), "")
    if att:
        parts.append(f"<p>{html.escape(att)}</p>")
    for caption, paths in written:
        png = next(p.name for p in paths if p.suffix == ".png")
        vec = " ".join(f"<a href='{p.name}'>{p.suffix[1:].upper()}</a>" for p in paths
                       if p.suffix != ".png")
        parts.append(f"<figure><img src='{png}' alt='{png}' style='max-width:520px'>"
                     f"<figcaption>{html.escape(caption)} ({vec})</figcaption></figure>")
    return parts


def write_report(out_dir, result=None, diagnosis=None, title="liquidamp calibration") -> Path:
    """Write ``index.html`` and PNGs for a CalibrationResult or a Diagnosis.

    Parameters
    ----------
    out_dir : str or Path
        Folder of the report (created if missing).
    result : CalibrationResult, optional
        The calibration to report (used when ``diagnosis`` is None).
    diagnosis : Diagnosis, optional
        A diagnosis: its baseline and every step are reported.
    title : str
        Page title.

    Returns
    -------
    Path
        The path of ``index.html``; the figures (records, loops and residuals
        with force and residual in [N]) are PNGs beside it, and the damper figures
        (``damper_*``: force-velocity per direction, peak curve with knees, temperature
        and short windows where they apply) PNG and SVG in the journal-column style.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plt = _plt()
    if diagnosis is not None:
        dev = list(getattr(diagnosis, "device_steps", ()))
        results = ([diagnosis.baseline] + [s.result for s in dev]
                   + [s.result for s in diagnosis.steps])
        labels = (["baseline"] + [f"device: {s.effect}" for s in dev]
                  + [f"+ {s.effect}" for s in diagnosis.steps])
    else:
        results, labels = [result], ["calibrated"]
    first = results[0]
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}"
             f"</title><style>{CSS}</style></head><body><h1>{html.escape(title)}</h1>"]
    parts += _verdict_section(results[-1], diagnosis)
    warns = list(dict.fromkeys(w for res in results for w in res.warnings))
    if diagnosis is not None:
        warns += [w for w in diagnosis.warnings if w not in warns]
    if warns:
        parts.append("<div class='warn'><b>Warnings</b><ul>" + "".join(
            f"<li>{html.escape(w)}</li>" for w in warns) + "</ul></div>")
    if first.data_quality:
        parts.append("<h2>Data quality (checked before the fit)</h2>")
        parts.append("<p>Harmonic summaries (frequency, amplitude, |F1|) are given only for a "
                     "periodic stroke; a tapered or broadband stroke is summarized by its RMS "
                     "and band and fitted on the recorded stroke as it is.  Loss share: power "
                     "absorbed over RMS(F) RMS(v), positive for a passive device.</p>")
        parts.append(_table(
            [[q.source, q.stroke.get("description", ""), q.force_first_harmonic,
              q.force_noise_std, q.force_snr, q.periodic_fraction,
              q.energy_per_cycle, q.loss_share, q.samples_per_cycle, q.max_stroke * 1e3,
              len(q.outliers), _drift_cell(q),
              "; ".join(f"{k} {c['min']:.4g}-{c['max']:.4g} {c['unit']}"
                        for k, c in getattr(q, "channels", {}).items()) or "-"]
             for q in first.data_quality],
            ["record", "stroke", "|F1| [N]", "noise std [N]", "signal / std. error",
             "periodic share", "energy per cycle [J]", "loss share", "samples per cycle",
             "max |stroke| [mm]", "outliers", "drift", "measured channels"]))
    parts += _start_section(first)
    parts += _plausibility_section(results, labels)
    figs = [("records.png", plot_records(list(first.calibration) + list(first.validation)),
             "Records")]
    for role in ("calibration", "validation"):
        if role == "validation" and not first.validation:
            continue
        figs.append((f"loops_{role}.png", plot_loops_fit(results, labels, role),
                     f"Loops, {role} records"))
        figs.append((f"residuals_{role}.png", plot_residuals(results, labels, role),
                     f"Residuals, {role} records"))
    rows = []
    for res, lab in zip(results, labels, strict=True):
        rows.append([lab, res.nrmse_calibration, res.nrmse_validation, res.status, res.nfev,
                     res.bic])
    parts.append("<h2>Error table (NRMSE = RMS(model - measured) / RMS(measured - mean))</h2>")
    parts.append(_table(rows, ["model", "NRMSE calibration", "NRMSE validation", "fit status",
                               "evaluations", "BIC"]))
    for res, lab in zip(results, labels, strict=True):
        parts.append(f"<h3>Parameters: {html.escape(lab)}</h3>")
        d = res.parameters_dict()
        prow = [[k, v, d["stderr"].get(k), _flag(res, k)] for k, v in d["multipliers"].items()]
        for e, kv in d["effects"].items():
            prow += [[f"{e}.{k}", v, d["stderr"].get(f"{e}.{k}"), _flag(res, f"{e}.{k}")]
                     for k, v in kv.items()]
        parts.append(f"<p>{html.escape(res.summary())}</p>")
        parts.append(_table(prow, ["parameter", "value (multiplier or SI)", "std. error",
                                   "flag"]))
        parts.append(f"<details><summary>fit report</summary><pre>"
                     f"{html.escape(res.fit_report())}</pre></details>")
    if diagnosis is not None:
        parts.append("<h2>Diagnosis</h2>")
        parts.append(f"<p>Noise floor (NRMSE): {diagnosis.noise_nrmse:.4g}. Stop: "
                     f"{html.escape(diagnosis.stop_reason)}</p>")
        if diagnosis.conditioning:
            parts.append("<p>Records as fitted (conditioning; every NRMSE above is on these; "
                         "the final model on the records as given: "
                         + (", ".join(f"{k} {v:.4g}" for k, v in diagnosis.nrmse_raw.items())
                            or "same records") + "):</p><ul>"
                         + "".join(f"<li>{html.escape(c.describe())}</li>"
                                   for c in diagnosis.conditioning) + "</ul>")
        nc = diagnosis.as_dict()["not_converged"]
        if nc:
            parts.append("<p><b>Fits that did NOT converge (their parameters are where the "
                         "optimizer stopped, not an optimum): " + html.escape("; ".join(
                             f"{x['fit']} ({x['status']}, {x['nfev']} evaluations)"
                             for x in nc)) + "</b></p>")
        else:
            parts.append("<p>Every fit converged.</p>")
        if diagnosis.unexplained:
            parts.append(f"<p><b>{html.escape(diagnosis.unexplained)}</b></p>")
        for w in diagnosis.warnings:
            parts.append(f"<p><i>{html.escape(w)}</i></p>")
        parts.append("<h3>Baseline residual signatures (correlations)</h3>")
        parts.append(_table(list(diagnosis.signatures.items()), ["signature", "value"]))
        rounds = [(f"step {i + 1}: added {s.effect}", s.candidates)
                  for i, s in enumerate(diagnosis.steps)]
        if diagnosis.last_candidates:
            rounds.append(("final round (nothing added)", diagnosis.last_candidates))
        for name, cands in rounds:
            parts.append(f"<h3>Candidates, {html.escape(name)}</h3>")
            parts.append(_table(
                [[c.effect, c.score, c.signature_correlation, c.estimate, c.nrmse_validation,
                  c.relative_reduction, c.delta_bic, c.parameters, c.accepted, c.note]
                 for c in cands],
                ["effect", "score", "signature corr.", "linear estimate", "NRMSE val.",
                 "rel. reduction", "dBIC", "fitted", "accepted", "note"]))
    for fname, fig, caption in figs:
        save_figure(fig, out / fname, dpi=DPI)
        plt.close(fig)
        parts.append(f"<h2>{html.escape(caption)}</h2><img src='{fname}' alt='{fname}'>")
    parts += _damper_section(out, results[-1], labels[-1])
    parts.append("</body></html>")
    path = out / "index.html"
    write_text(path, "\n".join(parts))
    return path
