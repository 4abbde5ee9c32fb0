"""Figures a damper engineer reads, in one journal-column style (vector beside PNG).

Plotting only: the numbers come from
:mod:`liquidamp.analysis.reports.damper_characteristics`.  Every figure is drawn inside
:func:`journal_style` (the style sheet ``data/journal.mplstyle``: 3.5 in wide, 8 pt fonts,
applied as a context, never globally) and :func:`write_damper_figures` writes each as PNG
and SVG through :func:`liquidamp.atomic.save_figure`.

- :func:`plot_force_velocity`: the loop split into compression (v > 0) and rebound
  (v < 0), with the cycle-averaged curve; a broadband record as a force-velocity density
  (2-D histogram) instead of overplotted loops;
- :func:`plot_peak_curve`: peak force against peak velocity per stroke, the two-slope map
  and its knees, measured and model;
- :func:`plot_temperature`: force amplitude and temperature [C] cycle by cycle;
- :func:`plot_windows`: short windows of a broadband record's stroke and force.

References
----------
.. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5 and 7.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np

from liquidamp.analysis.reports.damper_characteristics import (
    KELVIN,
    cycle_average,
    cycle_table,
    damper_characteristics,
    peak_points,
    two_slope_curve,
)
from liquidamp.atomic import save_figure
from liquidamp.errors import ParameterError

__all__ = ["STYLE", "journal_style", "plot_force_velocity", "plot_peak_curve",
           "plot_temperature", "plot_windows", "write_damper_figures", "attribution_of"]

#: The style sheet of every figure here.
STYLE = Path(__file__).with_name("data") / "journal.mplstyle"

COMPRESSION, REBOUND, MODEL = "#0072B2", "#D55E00", "0.15"

#: Attributions of the public records the project ships or reads, by a folder name.
ATTRIBUTIONS = {"friction-damper-backlash": "Data: Coble, Huggins, Cao, Ricles, Downey "
                "(2022), CC BY-SA 4.0"}


@contextlib.contextmanager
def journal_style():
    """Context in which figures take the journal-column style (``STYLE``), then revert.

    Examples
    --------
    >>> import matplotlib
    >>> before = matplotlib.rcParams["font.size"]
    >>> with journal_style():
    ...     matplotlib.rcParams["font.size"]
    8.0
    >>> matplotlib.rcParams["font.size"] == before
    True
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.style

    with matplotlib.style.context(str(STYLE)):
        yield


def _figure(nrows=1, ncols=1, height=2.6, width=3.5):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height))
    return fig, fig.subplots(nrows, ncols, squeeze=False)


def attribution_of(record) -> str:
    """The attribution a figure from ``record`` must carry ('' if none is known)."""
    src = str(getattr(record, "source", ""))
    return next((a for k, a in ATTRIBUTIONS.items() if k in src), "")


def _force_unit(*forces):
    big = max(float(np.max(np.abs(f))) for f in forces)
    return (1e-3, "kN") if big >= 1e4 else (1.0, "N")


def _finish(fig, record, title):
    if title:
        fig.suptitle(title)
    att = attribution_of(record)
    if att:
        fig.supxlabel(att, x=0.99, ha="right", fontsize=5, color="0.35")
    return fig


def plot_force_velocity(record, model_force=None, *, title: str = "", bins: int = 60):
    """Force against stroke rate, compression (v > 0) and rebound (v < 0) apart.

    Parameters
    ----------
    record : Record
    model_force : array_like, optional
        A model's force on the record's samples [N] (drawn dashed; cycle-averaged for a
        periodic record).
    title : str
    bins : int
        Bins per axis of the density of a broadband record.

    Returns
    -------
    matplotlib.figure.Figure
        A periodic record: the measured samples per direction (thin, light) and their
        cycle-averaged curve per direction (thick; the model's dashed); any other: the
        2-D histogram of (v, F), log colour.
    """
    v = np.asarray(record.velocity, float) * 1e3
    F = np.asarray(record.force, float)
    s, unit = _force_unit(F)
    fig, ax = _figure()
    ax = ax[0, 0]
    if record.periodic:
        for mask, col in ((v > 0, COMPRESSION), (v < 0, REBOUND)):
            ax.plot(np.where(mask, v, np.nan), np.where(mask, F * s, np.nan), "-", lw=0.4,
                    color=col, alpha=0.35)
        for force, ls, who in ((None, "-", "measured"), (model_force, "--", "model")):
            if who == "model" and model_force is None:
                continue
            avg = cycle_average(record, force)
            va = np.append(avg["velocity"], avg["velocity"][:1]) * 1e3
            fa = np.append(avg["force"], avg["force"][:1]) * s
            for sign, col, d in ((1, COMPRESSION, "compression"), (-1, REBOUND, "rebound")):
                keep = sign * va >= 0  # each direction's half of the averaged loop
                ax.plot(np.where(keep, va, np.nan), np.where(keep, fa, np.nan), ls,
                        color=col if who == "measured" else MODEL,
                        lw=1.2 if who == "measured" else 0.8,
                        label=f"{d}, cycle average" if who == "measured"
                        else ("model, cycle average" if sign > 0 else None))
    else:
        from matplotlib.colors import LogNorm

        h = ax.hist2d(v, F * s, bins=bins, norm=LogNorm(), cmap="viridis", rasterized=True)
        fig.colorbar(h[3], ax=ax, label="samples per bin", pad=0.01)
        if model_force is not None:
            m = np.asarray(model_force, float)
            order = np.argsort(v)
            edges = np.linspace(v.min(), v.max(), bins + 1)
            k = np.clip(np.digitize(v[order], edges) - 1, 0, bins - 1)
            n = np.bincount(k, minlength=bins)
            ok = n > 0
            mean = np.bincount(k, weights=m[order], minlength=bins)[ok] / n[ok]
            ax.plot(0.5 * (edges[:-1] + edges[1:])[ok], mean * s, "--", color="w", lw=1.0,
                    label="model, bin mean")
    ax.axvline(0, color="0.5", lw=0.5)
    ax.set_xlabel("stroke rate [mm/s]  (> 0 compression)")
    ax.set_ylabel(f"force [{unit}]")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best")
    return _finish(fig, record, title or record.label)


def plot_peak_curve(records, model_forces=None, *, title: str = ""):
    """Peak force against peak velocity per stroke, with the two-slope map and its knees.

    Parameters
    ----------
    records : sequence of Record
        One map is fitted on them together (more amplitudes give more of the curve).
    model_forces : sequence of array_like, optional
        A model's force on each record's samples [N]: its peaks and map drawn dashed.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
        Compression in the first quadrant, rebound in the third; the knees marked.
    """
    records = list(records)
    if not records:
        raise ParameterError("plot_peak_curve: no record given")
    s, unit = _force_unit(*[r.force for r in records])
    fig, ax = _figure()
    ax = ax[0, 0]
    sets = [("measured", None, "o", "-")]
    if model_forces is not None:
        sets.append(("model", list(model_forces), "x", "--"))
    for name, forces, marker, ls in sets:
        ch = damper_characteristics(records, forces)
        fs = forces or [None] * len(records)
        for d, col in (("compression", COMPRESSION), ("rebound", REBOUND)):
            pts = [peak_points(r, f)[d] for r, f in zip(records, fs, strict=True)]
            pv = np.concatenate([p[0] for p in pts])
            pf = np.concatenate([p[1] for p in pts])
            ax.plot(pv * 1e3, pf * s, marker, ms=2.5, mfc="none" if marker == "o" else col,
                    color=col, lw=0, label=f"{name}, {d} peaks")
            vk = ch[d]["knee_velocity [m/s]"]
            vp = ch[d]["peak_velocity [m/s]"]
            vv = np.linspace(0.0, vp, 50)
            ax.plot(vv * 1e3, two_slope_curve(ch["two_slope"], vv) * s, ls, color=col,
                    lw=0.9 if ls == "-" else 0.8)
            ax.plot([vk * 1e3], [ch[d]["knee_force [N]"] * s], "D" if ls == "-" else "s",
                    ms=4, color=col, mfc="w", zorder=5,
                    label=f"{name} knee {abs(vk) * 1e3:.3g} mm/s" if d == "compression"
                    else None)
    ax.axvline(0, color="0.5", lw=0.5)
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_xlabel("peak stroke rate [mm/s]  (> 0 compression)")
    ax.set_ylabel(f"force at peak rate [{unit}]")
    ax.legend(loc="upper left", fontsize=5.5)
    return _finish(fig, records[0], title or "peak force against peak velocity")


def plot_temperature(record, *, title: str = ""):
    """Force amplitude and temperature [C] cycle by cycle (record with a temperature channel).

    Returns
    -------
    matplotlib.figure.Figure
        Force amplitude (half peak-to-peak) [N] on the left axis, the cycle's mean
        temperature [C] on the right, against the cycle's time [s].
    """
    tab = cycle_table(record)
    if tab["temperature"] is None:
        raise ParameterError(f"record {record.label!r} has no temperature channel; "
                             f"channels: {', '.join(record.channels) or 'none'}")
    s, unit = _force_unit(tab["force_amplitude"])
    fig, ax = _figure()
    ax = ax[0, 0]
    ax.plot(tab["time"], tab["force_amplitude"] * s, "o-", ms=2, color=COMPRESSION)
    ax.set_xlabel("time [s] (one point per cycle)")
    ax.set_ylabel(f"force amplitude [{unit}]", color=COMPRESSION)
    ax2 = ax.twinx()
    ax2.grid(False)
    ax2.plot(tab["time"], tab["temperature"] - KELVIN, "s-", ms=2, color=REBOUND)
    ax2.set_ylabel("temperature [C]", color=REBOUND)
    return _finish(fig, record, title or record.label)


def plot_windows(record, model_force=None, *, windows: int = 3, length: float | None = None,
                 title: str = ""):
    """Short windows of a (broadband) record: stroke and force against time.

    Parameters
    ----------
    record : Record
    model_force : array_like, optional
        A model's force [N] drawn dashed.
    windows : int
        Windows taken evenly from the start to the end (>= 1).
    length : float, optional
        Window length [s]; default 3 periods of the periodogram peak, at most a tenth of
        the record.

    Returns
    -------
    matplotlib.figure.Figure
        One column per window: stroke [mm] above, force below, then a measured
        ``voltage`` [V] or ``current`` [A] channel where the record has one.
    """
    if windows < 1:
        raise ParameterError(f"plot_windows: windows = {windows}; at least 1 allowed")
    t = np.asarray(record.time, float)
    dur = t[-1] - t[0]
    if length is None:
        length = min(3.0 / record.frequency, dur / 10)
    if not 0 < length <= dur:
        raise ParameterError(f"plot_windows: length = {length} s; allowed (0, {dur:.4g}] s")
    F = np.asarray(record.force, float)
    s, unit = _force_unit(F)
    starts = np.linspace(t[0], t[-1] - length, windows)
    extra = [(k, u) for k, u in (("voltage", "V"), ("current", "A")) if k in record.channels]
    fig, axes = _figure(2 + len(extra), windows, height=2.4 + 0.9 * len(extra))
    for j, a in enumerate(starts):
        m = (t >= a) & (t <= a + length)
        axes[0, j].plot(t[m], record.displacement[m] * 1e3, color="k", lw=0.7)
        axes[1, j].plot(t[m], F[m] * s, color=COMPRESSION, lw=0.7, label="measured")
        if model_force is not None:
            axes[1, j].plot(t[m], np.asarray(model_force, float)[m] * s, "--", color=REBOUND,
                            lw=0.7, label="model")
        for row, (k, u) in enumerate(extra, start=2):
            axes[row, j].plot(t[m], record.channels[k][m], color="0.3", lw=0.7)
            if j == 0:
                axes[row, 0].set_ylabel(f"{k} [{u}]")
        axes[-1, j].set_xlabel("time [s]")
        for ax in axes[:, j]:
            ax.tick_params(labelsize=6)
    axes[0, 0].set_ylabel("stroke [mm]")
    axes[1, 0].set_ylabel(f"force [{unit}]")
    if model_force is not None:
        axes[1, 0].legend(loc="best", fontsize=5.5)
    return _finish(fig, record, title or record.label)


def write_damper_figures(out_dir, records, model_forces=None, *, prefix: str = "damper",
                         formats=("png", "svg"), dpi: int = 300) -> list:
    """Draw every figure that applies to ``records`` and write each in ``formats``.

    Parameters
    ----------
    out_dir : str or Path
        Folder (created if missing).
    records : sequence of Record
    model_forces : sequence of array_like, optional
        A model's force on each record's samples [N].
    prefix : str
        File names start with it.
    formats : sequence of str
        File suffixes; a vector one (``svg`` or ``pdf``) must be among them.
    dpi : int
        Resolution of the raster files.

    Returns
    -------
    list of (str, list of Path)
        Caption and the files written, per figure: the force-velocity figure of each
        record, its short windows if it is not periodic, its temperature beside the force
        amplitude if it has a ``temperature`` channel and two whole cycles or more (not
        after averaging its cycles into one), and the peak curve of all of them.
    """
    formats = tuple(formats)
    if not {"svg", "pdf"} & set(formats):
        raise ParameterError(f"formats = {formats}; a vector format (svg or pdf) is needed")
    records = list(records)
    forces = list(model_forces) if model_forces is not None else [None] * len(records)
    if len(forces) != len(records):
        raise ParameterError(f"{len(forces)} model forces for {len(records)} records")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    with journal_style():
        jobs = []
        for i, (r, f) in enumerate(zip(records, forces, strict=True)):
            jobs.append((f"{prefix}_fv_{i}", f"force-velocity, {r.label}",
                         lambda r=r, f=f: plot_force_velocity(r, f)))
            if not r.periodic:
                jobs.append((f"{prefix}_windows_{i}", f"short windows, {r.label}",
                             lambda r=r, f=f: plot_windows(r, f)))
            if "temperature" in r.channels and int(r.cycles) >= 2:  # cycle by cycle
                jobs.append((f"{prefix}_temperature_{i}", f"force amplitude and temperature "
                             f"cycle by cycle, {r.label}", lambda r=r: plot_temperature(r)))
        jobs.append((f"{prefix}_peaks", "peak force against peak velocity, knees",
                     lambda: plot_peak_curve(records, model_forces)))
        for stem, caption, make in jobs:
            fig = make()
            paths = [save_figure(fig, out / f"{stem}.{ext}", dpi=dpi) for ext in formats]
            written.append((caption, paths))
    return written
