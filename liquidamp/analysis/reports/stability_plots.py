"""Plots of stability results: Coleman diagram, V-g and V-f diagrams, limit cycles.

Plotting only: each function takes a result object and returns a
:class:`matplotlib.figure.Figure` (built without ``pyplot`` on the Agg
canvas, so nothing global changes).  matplotlib is imported lazily, here
only.  Units are converted at this edge (rpm, Hz).
"""

from __future__ import annotations

import math
import re

import numpy as np

__all__ = ["plot_ground_resonance", "plot_flutter", "plot_limit_cycle", "plot_margin",
           "plot_degradation"]


def _figure(nrows: int):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 3.0 * nrows), constrained_layout=True)
    FigureCanvasAgg(fig)
    axes = [fig.add_subplot(nrows, 1, i + 1) for i in range(nrows)]
    return fig, axes


def _failed_blades(sweep) -> tuple[int, ...]:
    """Blades (1-based) whose lag damper is zero, from the sweep (``inoperative`` if it has
    one, else the damper list its note states when the blades differ)."""
    if getattr(sweep, "inoperative", None) is not None:
        return tuple(int(k) for k in sweep.inoperative)
    m = re.search(r"blade lag dampers differ \(([^)]*)\)", sweep.note or "")
    if not m:
        return ()
    try:
        values = [float(v) for v in m.group(1).split(",")]
    except ValueError:
        return ()
    return tuple(k + 1 for k, v in enumerate(values) if v == 0.0)


def plot_ground_resonance(sweep, *, inoperative=None, title: str | None = None):
    """Coleman diagram: fixed-frame frequencies [Hz] and real parts [1/s] against rpm.

    Each tracked mode keeps one colour in both panels and is named in the
    legend by its frequency at the lowest speed; the mode that reaches the
    largest real part is drawn thicker; unstable speed ranges are shaded red.
    The title names the method and any blade whose lag damper is inoperative.

    Parameters
    ----------
    sweep : GroundResonanceSweep
        From :func:`liquidamp.analysis.stability.ground_resonance.ground_resonance_sweep`.
    inoperative : sequence of int, optional
        Blades (1-based) whose damper failed, for the title; default: read
        from the sweep (the blades whose lag damper is zero).
    title : str, optional
        Replaces the default title.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.analysis.stability.ground_resonance import (
    ...     ground_resonance_sweep, rpm_to_rad_s)
    >>> sweep = ground_resonance_sweep(load_rotor("hammond1974"),
    ...                                rpm_to_rad_s(np.linspace(100, 400, 7)))
    >>> fig = plot_ground_resonance(sweep)
    >>> len(fig.axes), fig.axes[1].get_legend() is not None
    (2, True)
    """
    fig, (ax_f, ax_r) = _figure(2)
    fig.set_size_inches(9.0, 6.5)
    rpm = sweep.rpm
    lam = sweep.eigenvalues
    cols = [j for j in range(lam.shape[1]) if not np.all(lam[:, j].imag < -1e-9)]
    worst = max(cols, key=lambda j: float(np.max(lam[:, j].real))) if cols else None
    palette = ("#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#D55E00", "#000000",
               "#999999", "#F0E442", "#882255")
    for k, j in enumerate(cols):
        f0 = abs(lam[0, j].imag) / (2.0 * math.pi)
        style = {"color": palette[k % len(palette)], "ms": 3,
                 "lw": 2.2 if j == worst else 0.9}
        label = f"mode {k + 1} ({f0:.2f} Hz at {rpm[0]:.0f} rpm)"
        if j == worst and np.max(lam[:, j].real) > 0:
            label += ", unstable"
        ax_f.plot(rpm, np.abs(lam[:, j].imag) / (2.0 * math.pi), ".-", **style)
        ax_r.plot(rpm, lam[:, j].real, ".-", label=label, **style)
    for ax in (ax_f, ax_r):
        for i, (a, b) in enumerate(sweep.unstable_ranges_rpm):
            ax.axvspan(a, b, color="red", alpha=0.12,
                       label="unstable" if (i == 0 and ax is ax_f) else None)
    ax_f.plot(rpm, rpm / 60.0, "k--", lw=0.6, label="1/rev")
    ax_f.legend(loc="upper left", fontsize=8)
    ax_f.set_ylabel("frequency [Hz]")
    ax_r.axhline(0.0, color="k", lw=0.6)
    ax_r.set_ylabel("real part [1/s]")
    ax_r.set_xlabel("rotor speed [rpm]")
    ax_r.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5), title="modes",
                title_fontsize=8)
    if title is None:
        failed = _failed_blades(sweep) if inoperative is None else tuple(inoperative)
        what = ("all lag dampers working" if not failed else
                "lag damper of blade " + ", ".join(str(b) for b in failed) + " inoperative")
        method = ("Floquet exponents (periodic coefficients)" if sweep.method == "floquet"
                  else "multiblade (Coleman) eigenvalues")
        title = f"{sweep.rotor_name}: {what}; {method}"
    ax_f.set_title(title, fontsize=10)
    return fig


def plot_flutter(result):
    """V-g and V-f diagrams of a flutter analysis.

    Parameters
    ----------
    result : FlutterResult
        From :func:`liquidamp.analysis.stability.flutter.flutter_analysis`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> from liquidamp.analysis.stability.flutter import flutter_analysis
    >>> res = flutter_analysis(load_section("hodges-pierce"), "steady", "p")
    >>> len(plot_flutter(res).axes)
    2
    """
    fig, (ax_g, ax_f) = _figure(2)
    for j in range(result.speed.shape[0]):
        ax_g.plot(result.speed[j], result.damping[j], lw=1.0, label=f"mode {j + 1}")
        ax_f.plot(result.speed[j], result.frequency[j], lw=1.0)
    ax_g.axhline(0.0, color="k", lw=0.6)
    for ax in (ax_g, ax_f):
        if result.flutter_speed is not None:
            ax.axvline(result.flutter_speed, color="red", ls="--", lw=0.8)
        if math.isfinite(result.divergence_speed):
            ax.axvline(result.divergence_speed, color="grey", ls=":", lw=0.8)
    ax_g.set_ylabel(result.damping_kind)
    ax_f.set_ylabel("frequency omega/omega_theta [-]")
    ax_f.set_xlabel("speed U/(b omega_theta) [-]")
    if result.flutter_speed is not None:
        ax_g.plot([], [], color="red", ls="--", lw=0.8, label="flutter speed")
    if math.isfinite(result.divergence_speed):
        ax_g.plot([], [], color="grey", ls=":", lw=0.8, label="divergence speed")
    ax_g.legend(fontsize=8)
    ax_g.set_title(f"{result.section_name}: {result.aero}, {result.method} method")
    return fig


def _dominant_period(t, x) -> float:
    """Period of the strongest spectral line of x(t) [s] (NaN if none)."""
    if t.size < 8:
        return math.nan
    dt = float(np.median(np.diff(t)))
    spec = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size)))
    freqs = np.fft.rfftfreq(x.size, dt)
    spec[0] = 0.0
    k = int(np.argmax(spec))
    return 1.0 / freqs[k] if freqs[k] > 0 else math.nan


def _envelope(t, x, period: float):
    """Amplitude envelope: the peaks of |x| (at least half a period apart) [t], [x]."""
    from scipy.signal import find_peaks

    dt = float(np.median(np.diff(t)))
    dist = max(int(0.4 * period / dt), 1) if math.isfinite(period) else 1
    k, _ = find_peaks(np.abs(x), distance=dist)
    if k.size < 2:
        return t, np.abs(x)
    return t[k], np.abs(x)[k]


def plot_limit_cycle(response, *, predicted_amplitude: float | None = None, title: str = "",
                     zoom_cycles: float = 4.0):
    """Lag angles and device strokes of a rotor run: envelopes over the run, a zoom at its end.

    A run of tens of seconds holds hundreds of lag cycles: drawn whole, four
    blades fill the axes with colour.  The left column shows each blade's
    amplitude envelope (the peaks of |signal|, at least 0.4 period of the
    dominant oscillation apart) over the whole run, with the describing-function
    prediction dashed; the right column the last ``zoom_cycles`` cycles, where
    the blades' phases can be read.

    Parameters
    ----------
    response : AssemblyResponse
        A rotor run (``time`` [s], ``host_states`` with the lag angles
        ``zeta_k`` [rad] named in ``host_state_names``, ``strokes`` [m] per
        ``port_names``), e.g. ``simulate_lco(...).response``.
    predicted_amplitude : float, optional
        Describing-function lag amplitude [rad] (dashed).
    title : str
        Figure title.
    zoom_cycles : float
        Cycles shown in the zoom [-].

    Returns
    -------
    matplotlib.figure.Figure
        2 x 2 axes: lag [deg] and stroke [mm] against time [s].
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    t = np.asarray(response.time, float)
    names = list(response.host_state_names)
    lag_idx = [i for i, n in enumerate(names) if n.startswith("zeta_") and "dot" not in n]
    lags = [np.degrees(np.asarray(response.host_states[i], float)) for i in lag_idx]
    strokes = [np.asarray(s, float) * 1e3 for s in response.strokes]
    period = _dominant_period(t, lags[0]) if lags else _dominant_period(t, strokes[0])
    fig = Figure(figsize=(11.0, 6.5), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, 2, width_ratios=(1.6, 1))
    t0 = t[-1] - zoom_cycles * period if math.isfinite(period) else t[0]
    zoom = t >= max(t0, t[0])
    palette = ("#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#D55E00", "#000000")
    rows = ((lags, [f"blade {names[i].split('_', 1)[1]}" for i in lag_idx], "lag [deg]"),
            (strokes, list(response.port_names), "stroke [mm]"))
    for r, (signals, labels, ylabel) in enumerate(rows):
        ax_env, ax_zoom = axes[r]
        for k, (x, lab) in enumerate(zip(signals, labels, strict=True)):
            col = palette[k % len(palette)]
            ax_env.plot(*_envelope(t, x, period), color=col, lw=1.4, label=lab)
            ax_zoom.plot(t[zoom], x[zoom], color=col, lw=1.3, label=lab)
        ax_env.set_ylabel(f"amplitude envelope,\n{ylabel}")
        ax_zoom.set_ylabel(ylabel)
        ax_env.set_ylim(bottom=0.0)
        for ax in (ax_env, ax_zoom):
            ax.grid(True, alpha=0.3)
        ax_env.axvspan(t[zoom][0], t[-1], color="0.85", zorder=0,
                       label="zoomed (right)" if r == 0 else None)
    if predicted_amplitude:
        pa = math.degrees(predicted_amplitude)
        axes[0, 0].axhline(pa, color="k", ls="--", lw=0.9, label="describing-function LCO")
        for sgn in (1, -1):
            axes[0, 1].axhline(sgn * pa, color="k", ls="--", lw=0.9)
    axes[0, 0].legend(fontsize=7, ncol=2, loc="lower right")
    axes[1, 0].legend(fontsize=7, ncol=2, loc="lower right")
    for ax in axes[1]:
        ax.set_xlabel("time [s]")
    axes[0, 0].set_title("whole run: amplitude envelope (peaks of |signal|)",
                         fontsize=9)
    axes[0, 1].set_title(f"last {zoom_cycles:g} cycles"
                         + (f" (period {period:.3g} s)" if math.isfinite(period) else ""),
                         fontsize=9)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def _bands_with_intervals(ax, margin, k):
    """Shade each band (red) and its edges' intervals (hatched) on ``ax`` (x scaled by k)."""
    for b in margin.bands:
        ax.axvspan(b.start.value * k, b.end.value * k, color="tab:red", alpha=0.15, lw=0)
        for e, open_ in ((b.start, b.open_start), (b.end, b.open_end)):
            if not open_ and e.high > e.low:
                ax.axvspan(e.low * k, e.high * k, facecolor="none", edgecolor="tab:red",
                           hatch="///", lw=0.0, alpha=0.6)
            ax.axvline(e.value * k, color="tab:red", lw=0.8)


def plot_margin(margin, *, title: str | None = None):
    """Largest real part and minimum damping ratio against speed, bands with their intervals.

    Parameters
    ----------
    margin : StabilityMargin
        From :func:`liquidamp.analysis.stability.margins.ground_resonance_margin` or
        :func:`~liquidamp.analysis.stability.margins.flutter_margin`.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        Two panels: max Re(lambda) with the unstable bands shaded and each edge's interval
        hatched; the minimum damping ratio with its interval at its minimum (error bar).

    Examples
    --------
    >>> import numpy as np
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    >>> from liquidamp.analysis.stability.margins import ground_resonance_margin
    >>> r = load_rotor("hammond1974")
    >>> m = ground_resonance_margin(r, rpm_to_rad_s(np.linspace(150, 350, 9)), inoperative=[1])
    >>> len(plot_margin(m).axes)
    2
    """
    fig, (ax_g, ax_z) = _figure(2)
    k = margin.to_unit
    x = margin.speeds * k
    ax_g.plot(x, margin.max_real_part, "k.-", lw=1.0)
    ax_g.axhline(0.0, color="0.5", lw=0.6)
    _bands_with_intervals(ax_g, margin, k)
    ax_g.set_ylabel("largest Re(λ)" + (" [1/s]" if margin.speed_unit == "rpm" else " [-]"))
    ax_z.plot(x, margin.damping_ratio, "b.-", lw=1.0)
    z = margin.min_damping_ratio
    ax_z.errorbar([margin.min_damping_at * k], [z.value],
                  yerr=[[z.value - z.low], [z.high - z.value]], fmt="o", color="tab:red",
                  capsize=4, label=f"min {z.value:.4g} [{z.low:.4g}, {z.high:.4g}]")
    if margin.flutter_speed is not None:
        f = margin.flutter_speed
        ax_g.errorbar([f.value * k], [0.0], xerr=[[f.value - f.low], [f.high - f.value]],
                      fmt="s", color="tab:red", capsize=4,
                      label=f"flutter {f.value:.4f} [{f.low:.4f}, {f.high:.4f}]")
        ax_g.legend(loc="best", fontsize=8)
    _bands_with_intervals(ax_z, margin, k)
    ax_z.axhline(0.0, color="0.5", lw=0.6)
    ax_z.set_ylabel("min damping ratio [-]")
    ax_z.set_xlabel(f"{margin.speed_name} [{margin.speed_unit}]")
    ax_z.legend(loc="best", fontsize=8)
    ax_g.set_title(title or f"{margin.host}: bands and margins at "
                   f"{100 * margin.confidence:g} % confidence", fontsize=10)
    return fig


def plot_degradation(comparison, *, title: str | None = None):
    """Minimum damping ratio against rpm: intact, one damper degraded (Floquet), smeared.

    Parameters
    ----------
    comparison : DegradationComparison
        From :func:`liquidamp.analysis.stability.margins.degradation_comparison`.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        One panel; each curve's minimum with its interval; the title states the
        smeared/Floquet ratio of the damping losses.

    Examples
    --------
    >>> import numpy as np
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    >>> from liquidamp.analysis.stability.margins import degradation_comparison
    >>> c = degradation_comparison(load_rotor("hammond1974"),
    ...                            rpm_to_rad_s(np.linspace(200, 300, 5)), fraction=0.5)
    >>> len(plot_degradation(c).axes[0].lines) >= 3
    True
    """
    fig, (ax,) = _figure(1)
    fig.set_size_inches(8.0, 4.0)
    c = comparison
    for m, lab, col in ((c.intact, "all dampers", "k"),
                        (c.floquet, f"blade {c.blade} at {1 - c.fraction:g} (Floquet)",
                         "tab:red"),
                        (c.smeared, "smeared (the loss averaged over the blades)",
                         "tab:blue")):
        k = m.to_unit
        ax.plot(m.speeds * k, m.damping_ratio, ".-", color=col, lw=1.0, label=lab)
        z = m.min_damping_ratio
        ax.errorbar([m.min_damping_at * k], [z.value], yerr=[[z.value - z.low],
                                                             [z.high - z.value]],
                    fmt="o", color=col, capsize=4)
    _bands_with_intervals(ax, c.floquet, c.floquet.to_unit)
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xlabel("rotor speed [rpm]")
    ax.set_ylabel("min damping ratio [-]")
    ax.legend(loc="best", fontsize=8)
    ratio = "n/a" if c.loss_ratio is None else f"{c.loss_ratio:.3f}"
    ax.set_title(title or f"{c.intact.host}: one damper losing {c.fraction:g} of its force; "
                 f"smeared/Floquet damping loss {ratio} (published 0.46-0.55)", fontsize=9)
    return fig
