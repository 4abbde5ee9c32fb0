"""Plots of device responses in the paper's three-panel style (Figs. 5-11).

Compute and plot are separate: these functions take results and return a
:class:`matplotlib.figure.Figure`; they are the only place here that imports
matplotlib (lazily, on the non-interactive Agg backend).  Units are converted
at this edge: displacement in mm, velocity in mm/s, acceleration in m/s^2,
force in N.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from liquidamp.device.ideal import ideal_damper_force, ideal_inerter_force, ideal_spring_force

__all__ = ["plot_loops", "IDEAL_EFFECTS", "PALETTE"]

#: Ideal characteristics that :func:`plot_loops` can overlay, by panel.
IDEAL_EFFECTS = ("spring", "damper", "inerter")

#: Distinct line colours (Okabe-Ito, colour-blind safe; vermillion left out: the ideal
#: characteristics are red dashes).
PALETTE = ("#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#000000", "#F0E442")


def _figure(ncols: int, width: float = 4.2, height: float = 3.6):
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width * ncols, height), layout="constrained")
    return fig, fig.subplots(1, ncols)


def _closed(a: np.ndarray) -> np.ndarray:
    return np.append(a, a[:1])


def _cavitating(r, vapour_pressure: float) -> np.ndarray:
    """Samples of a response where a chamber pressure is below the vapour pressure."""
    p1, p2 = getattr(r, "p1", None), getattr(r, "p2", None)
    if p1 is None or p2 is None:
        return np.zeros(np.shape(r.force), bool)
    return np.minimum(np.asarray(p1, float), np.asarray(p2, float)) < vapour_pressure


def plot_loops(responses: Sequence, labels: Sequence[str] | None = None, *,
               reference: Sequence = (), ideal: Sequence[str] = (), ideal_params=None,
               title: str = "", colors: Sequence | None = None,
               vapour_pressure: float | None = None):
    """Force against displacement, velocity and acceleration (paper's Figs. 7-11).

    Parameters
    ----------
    responses : sequence of DeviceResponse
        Steady-state (one period) or longer responses, drawn in blue shades.
    labels : sequence of str, optional
        Legend labels; default "Y mm, f Hz".
    reference : sequence of DeviceResponse
        Responses drawn in grey (the paper's reference design).
    ideal : sequence of {"spring", "damper", "inerter"}
        Ideal characteristics to overlay in red dashes on the displacement,
        velocity and acceleration panels respectively.
    ideal_params : DeviceParams, optional
        Parameters of the ideal overlays; default those of the first response.
    title : str
        Figure title.
    colors : sequence, optional
        Colours of ``responses`` (default :data:`PALETTE`: one distinct colour
        per response).
    vapour_pressure : float, optional
        Stretches where a chamber pressure lies below it [Pa] are marked by a
        wide translucent purple band under the loop on every panel
        ("cavitation": the liquid would boil there, which a model without the
        cavitation effect does not represent); default ``SolverOptions().vapour_pressure`` (water at
        20 C, about 2.3 kPa).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.coupled.testrig import steady_state
    >>> from liquidamp.structure.testmachine import HarmonicStroke
    >>> r = steady_state("maxwell", preset("damper"), HarmonicStroke(0.001, 3.0))
    >>> fig = plot_loops([r], ideal=["damper"])
    >>> len(fig.axes)
    3
    """
    responses = list(responses)
    if labels is None:
        labels = [
            f"{r.amplitude * 1e3:g} mm, {r.frequency:g} Hz" if r.frequency else r.model
            for r in responses
        ]
    if colors is None:
        colors = [PALETTE[i % len(PALETTE)] for i in range(len(responses))]
    if vapour_pressure is None:
        from liquidamp.options import DEFAULT_OPTIONS

        vapour_pressure = DEFAULT_OPTIONS.vapour_pressure
    fig, axes = _figure(3)
    keys = (("stroke", 1e3, "displacement [mm]"),
            ("stroke_rate", 1e3, "velocity [mm/s]"),
            ("stroke_acceleration", 1.0, "acceleration [m/s$^2$]"))
    for j, (attr, scale, xlabel) in enumerate(keys):
        ax = axes[j]
        for k, r in enumerate(reference):
            ax.plot(_closed(getattr(r, attr)) * scale, _closed(r.force), color="0.6", lw=1.2,
                    label="reference design" if k == 0 else None)
        marked = False
        for r, lab, col in zip(responses, labels, colors, strict=True):
            ax.plot(_closed(getattr(r, attr)) * scale, _closed(r.force), color=col, lw=1.6,
                    label=lab)
            low = _closed(_cavitating(r, vapour_pressure))
            if low.any():
                x = _closed(np.asarray(getattr(r, attr), float)) * scale
                ax.plot(np.where(low, x, np.nan), np.where(low, _closed(r.force), np.nan),
                        "-", color="#7a0177", lw=7, alpha=0.25, solid_capstyle="butt",
                        zorder=1, label=None if marked else
                        f"p < {vapour_pressure / 1e3:.2g} kPa (cavitation)")
                marked = True
        ax.set_xlabel(xlabel)
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("force [N]")
    params = ideal_params if ideal_params is not None else (
        responses[0].params if responses else None)
    for effect in ideal:
        if effect not in IDEAL_EFFECTS:
            from liquidamp.errors import ParameterError

            raise ParameterError(
                f"unknown ideal effect {effect!r}; valid: {', '.join(IDEAL_EFFECTS)}"
            )
        j = IDEAL_EFFECTS.index(effect)
        attr, scale, _ = keys[j]
        span = max(float(np.max(np.abs(getattr(r, attr)))) for r in responses)
        xs = np.linspace(-span, span, 81)
        fn = (ideal_spring_force, ideal_damper_force, ideal_inerter_force)[j]
        axes[j].plot(xs * scale, fn(xs, params), "r--", lw=1.2, label=f"ideal {effect}")
    for ax in axes:
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7, loc="best")
    if title:
        fig.suptitle(title)
    return fig
