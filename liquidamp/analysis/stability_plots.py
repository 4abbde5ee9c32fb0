"""Plots of stability results: Coleman diagram, V-g and V-f diagrams.

Plotting only: each function takes a result object and returns a
:class:`matplotlib.figure.Figure` (built without ``pyplot`` on the Agg
canvas, so nothing global changes).  matplotlib is imported lazily, here
only.  Units are converted at this edge (rpm, Hz).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["plot_ground_resonance", "plot_flutter"]


def _figure(nrows: int):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 3.0 * nrows), constrained_layout=True)
    FigureCanvasAgg(fig)
    axes = [fig.add_subplot(nrows, 1, i + 1) for i in range(nrows)]
    return fig, axes


def plot_ground_resonance(sweep):
    """Coleman diagram: fixed-frame frequencies [Hz] and real parts [1/s] against rpm.

    Parameters
    ----------
    sweep : GroundResonanceSweep
        From :func:`liquidamp.analysis.ground_resonance.ground_resonance_sweep`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.analysis.ground_resonance import ground_resonance_sweep, rpm_to_rad_s
    >>> sweep = ground_resonance_sweep(load_rotor("hammond1974"),
    ...                                rpm_to_rad_s(np.linspace(100, 400, 7)))
    >>> len(plot_ground_resonance(sweep).axes)
    2
    """
    fig, (ax_f, ax_r) = _figure(2)
    rpm = sweep.rpm
    lam = sweep.eigenvalues
    for j in range(lam.shape[1]):
        if np.all(lam[:, j].imag < -1e-9):
            continue  # the conjugate partner is drawn
        ax_f.plot(rpm, np.abs(lam[:, j].imag) / (2.0 * math.pi), ".-", ms=3, lw=0.8)
        ax_r.plot(rpm, lam[:, j].real, ".-", ms=3, lw=0.8)
    for ax in (ax_f, ax_r):
        for a, b in sweep.unstable_ranges_rpm:
            ax.axvspan(a, b, color="red", alpha=0.12)
    ax_f.plot(rpm, rpm / 60.0, "k--", lw=0.6, label="1/rev")
    ax_f.legend(loc="upper left", fontsize=8)
    ax_f.set_ylabel("frequency [Hz]")
    ax_r.axhline(0.0, color="k", lw=0.6)
    ax_r.set_ylabel("real part [1/s]")
    ax_r.set_xlabel("rotor speed [rpm]")
    ax_f.set_title(f"{sweep.rotor_name}: {sweep.method}")
    return fig


def plot_flutter(result):
    """V-g and V-f diagrams of a flutter analysis.

    Parameters
    ----------
    result : FlutterResult
        From :func:`liquidamp.analysis.flutter.flutter_analysis`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> from liquidamp.analysis.flutter import flutter_analysis
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
    ax_g.legend(fontsize=8)
    ax_g.set_title(f"{result.section_name}: {result.aero}, {result.method} method")
    return fig
