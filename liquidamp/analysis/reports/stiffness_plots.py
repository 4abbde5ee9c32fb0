"""Bode-style dynamic-stiffness figure: linear models, nonlinear points, equivalent curves.

Compute and plot are separate: :func:`plot_dynamic_stiffness` takes
:class:`~liquidamp.analysis.response.stiffness.StiffnessCurve` /
:class:`~liquidamp.analysis.response.stiffness.NonlinearStiffness` /
:class:`~liquidamp.analysis.response.stiffness.EquivalentSweep` data and returns a
:class:`matplotlib.figure.Figure` (Agg backend, imported lazily).  Axes: Hz,
N/m for |K*| (log; the unit of the JSON and CSV outputs), degrees for the
phase, wrapped into (-180, 180] (0 deg spring, 90 deg damper, 180 deg
inerter; python-control's Bode plots unwrap it instead).
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
        ax_m.loglog(c.frequency, c.magnitude, label=f"{c.label} (linear)", **style)
        ax_p.semilogx(c.frequency, c.phase_deg, **style)
    markers = "osD^v<>"
    failed = False
    if nonlinear is not None:
        for i, Y in enumerate(nonlinear.amplitude):
            ok = np.isfinite(nonlinear.value[i])
            mk = markers[i % len(markers)]
            line, = ax_m.loglog(nonlinear.frequency[ok], nonlinear.magnitude[i][ok], mk,
                                ms=5, mfc="none", label=f"{nonlinear.model} Y = {Y * 1e3:g} mm")
            ax_p.semilogx(nonlinear.frequency[ok], nonlinear.phase_deg[i][ok], mk, ms=5,
                          mfc="none", color=line.get_color())
            if not ok.all():
                # failed points: a cross on the frequency axis, never a made-up value
                ax_p.plot(nonlinear.frequency[~ok], np.full((~ok).sum(), 0.04), "x",
                          color=line.get_color(), ms=7, mew=1.5,
                          transform=ax_p.get_xaxis_transform(),
                          label=f"failed, Y = {Y * 1e3:g} mm (see status)")
                failed = True
            if equivalent is not None and i < len(equivalent.amplitude):
                v = np.where(equivalent.valid[i], equivalent.value[i], np.nan)
                ax_m.loglog(equivalent.frequency, np.abs(v), "--", lw=1.0,
                            color=line.get_color(),
                            label=f"equivalent, Y = {equivalent.amplitude[i] * 1e3:g} mm")
                ax_p.semilogx(equivalent.frequency, np.degrees(np.angle(v)), "--", lw=1.0,
                              color=line.get_color())
    ax_m.set_ylabel("|K*| [N/m]")
    ax_p.set_ylabel("phase of K* [deg]\n(0 spring, 90 damper, 180 inerter)")
    ax_p.set_xlabel("frequency [Hz]")
    ax_p.set_yticks([-90, 0, 45, 90, 135, 180])
    if failed:
        ax_p.legend(fontsize=7, loc="lower left")
    for ax in (ax_m, ax_p):
        ax.grid(True, which="both", alpha=0.3)
    ax_m.legend(fontsize=7, loc="best")
    if title:
        fig.suptitle(title)
    return fig
