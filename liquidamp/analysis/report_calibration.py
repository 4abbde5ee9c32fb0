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

__all__ = ["plot_records", "plot_loops_fit", "plot_residuals", "write_report"]


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
        ax.set_title(f"{r.label}: {r.frequency:.3g} Hz, {r.amplitude * 1e3:.3g} mm, "
                     f"{r.cycles:.1f} cycles", fontsize=9)
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


def _table(rows, header):
    out = ["<table border=1 cellpadding=3><tr>" + "".join(f"<th>{html.escape(h)}</th>"
                                                         for h in header) + "</tr>"]
    for row in rows:
        out.append("<tr>" + "".join(f"<td>{html.escape(_fmt(c))}</td>" for c in row) + "</tr>")
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
        with force and residual in [N]) are PNGs beside it.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plt = _plt()
    if diagnosis is not None:
        results = [diagnosis.baseline] + [s.result for s in diagnosis.steps]
        labels = ["baseline"] + [f"+ {s.effect}" for s in diagnosis.steps]
    else:
        results, labels = [result], ["calibrated"]
    first = results[0]
    parts = [f"<html><head><meta charset='utf-8'><title>{html.escape(title)}</title></head>"
             f"<body><h1>{html.escape(title)}</h1>"]
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
        prow = [[k, v, d["stderr"].get(k)] for k, v in d["multipliers"].items()]
        for e, kv in d["effects"].items():
            prow += [[f"{e}.{k}", v, d["stderr"].get(f"{e}.{k}")] for k, v in kv.items()]
        parts.append(_table(prow, ["parameter", "value (multiplier or SI)", "std. error"]))
    if diagnosis is not None:
        parts.append("<h2>Diagnosis</h2>")
        parts.append(f"<p>Noise floor (NRMSE): {diagnosis.noise_nrmse:.4g}. Stop: "
                     f"{html.escape(diagnosis.stop_reason)}</p>")
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
        fig.savefig(out / fname, dpi=90)
        plt.close(fig)
        parts.append(f"<h2>{html.escape(caption)}</h2><img src='{fname}' width='100%'>")
    parts.append("</body></html>")
    path = out / "index.html"
    path.write_text("\n".join(parts))
    return path
