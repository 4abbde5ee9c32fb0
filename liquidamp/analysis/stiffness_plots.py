"""Bode-style dynamic-stiffness figure: linear models, nonlinear points, equivalent curves.

Compute and plot are separate: :func:`plot_dynamic_stiffness` takes
:class:`~liquidamp.analysis.stiffness.StiffnessCurve` /
:class:`~liquidamp.analysis.stiffness.NonlinearStiffness` /
:class:`~liquidamp.analysis.stiffness.EquivalentSweep` data and returns a
:class:`matplotlib.figure.Figure` (Agg backend, imported lazily).  Axes: Hz,
N/mm for |K*| (log), degrees for the phase.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["plot_dynamic_stiffness"]


def plot_dynamic_stiffness(linear: Sequence = (), nonlinear=None, equivalent=None, *,
                           title: str = ""):
    """Magnitude and phase of K*(f): lines for linear models, markers for the nonlinear.

    Parameters
    ----------
    linear : sequence of StiffnessCurve
        Linear models (one line each).
    nonlinear : NonlinearStiffness, optional
        First-harmonic points, one marker series per amplitude.
    equivalent : EquivalentSweep, optional
        Equivalent-linearization curves, dashed, one per amplitude (invalid
        points left out).
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 6.5), layout="constrained")
    ax_m, ax_p = fig.subplots(2, 1, sharex=True)
    for c in linear:
        # the full model at rest coincides with eq. (18): draw it wide and faint beneath
        style = {"lw": 4.0, "alpha": 0.35} if c.label == "full" else {"lw": 1.4}
        ax_m.loglog(c.frequency, c.magnitude * 1e-3, label=f"{c.label} (linear)", **style)
        ax_p.semilogx(c.frequency, c.phase_deg, **style)
    markers = "osD^v<>"
    if nonlinear is not None:
        for i, Y in enumerate(nonlinear.amplitude):
            ok = np.isfinite(nonlinear.value[i])
            mk = markers[i % len(markers)]
            line, = ax_m.loglog(nonlinear.frequency[ok], nonlinear.magnitude[i][ok] * 1e-3, mk,
                                ms=5, mfc="none", label=f"{nonlinear.model} Y = {Y * 1e3:g} mm")
            ax_p.semilogx(nonlinear.frequency[ok], nonlinear.phase_deg[i][ok], mk, ms=5,
                          mfc="none", color=line.get_color())
            if equivalent is not None and i < len(equivalent.amplitude):
                v = np.where(equivalent.valid[i], equivalent.value[i], np.nan)
                ax_m.loglog(equivalent.frequency, np.abs(v) * 1e-3, "--", lw=1.0,
                            color=line.get_color(),
                            label=f"equivalent, Y = {equivalent.amplitude[i] * 1e3:g} mm")
                ax_p.semilogx(equivalent.frequency, np.degrees(np.angle(v)), "--", lw=1.0,
                              color=line.get_color())
    ax_m.set_ylabel("|K*| [N/mm]")
    ax_p.set_ylabel("phase of K* [deg]")
    ax_p.set_xlabel("frequency [Hz]")
    ax_p.set_yticks([-90, 0, 45, 90, 135, 180])
    for ax in (ax_m, ax_p):
        ax.grid(True, which="both", alpha=0.3)
    ax_m.legend(fontsize=7, loc="best")
    if title:
        fig.suptitle(title)
    return fig
