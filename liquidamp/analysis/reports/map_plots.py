"""Plot of a two-quantity stability map: filled largest real part, boundary as a contour.

Plotting only: takes a :class:`~liquidamp.analysis.stability.maps.StabilityMap`
and returns a :class:`matplotlib.figure.Figure` (Agg canvas, no ``pyplot``).
Rotor speeds in rpm at this edge; a flutter map (:class:`~liquidamp.analysis.stability.
flutter_maps.FlutterMap`) against reduced speed.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_stability_map"]

_LABELS = {"degradation": "damper kept fraction [-]", "lag_damping": "lag damper [N m s/rad]",
           "arm": "damper arm [m]"}


def plot_stability_map(result, *, title: str | None = None):
    """Filled map of the largest real part [1/s] with its zero level (the stability boundary).

    Parameters
    ----------
    result : StabilityMap or FlutterMap
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        Diverging colours centred on 0 (red unstable); the boundary is the
        black contour ``max Re = neutral_tol``; the unstable side is hatched.

    Examples
    --------
    >>> import numpy as np
    >>> from liquidamp.analysis.stability.maps import StabilityMap
    >>> m = StabilityMap("demo", np.array([10.0, 20.0, 30.0]), "arm", "m",
    ...                  np.array([0.1, 0.2]), np.array([[-1.0, 1.0, -1.0], [-2.0, -1.0, -2.0]]),
    ...                  np.zeros((2, 4)), 64, 0.0, "")
    >>> len(plot_stability_map(m).axes)
    2
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 4.5), constrained_layout=True)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    z = np.asarray(result.max_real_part, float)
    rotor = hasattr(result, "rpm")
    x, y = (result.rpm if rotor else result.speed), np.asarray(result.values, float)
    level = result.neutral_tol if rotor else 1e-9
    lo, hi = float(np.min(z)), float(np.max(z))
    span = max(abs(lo), abs(hi), 1e-12)
    norm = TwoSlopeNorm(vcenter=0.0, vmin=min(lo, -1e-3 * span), vmax=max(hi, 1e-3 * span))
    if y.size > 1 and x.size > 1:
        cs = ax.contourf(x, y, z, levels=21, cmap="RdBu_r", norm=norm)
        if lo < level < hi:
            ax.contour(x, y, z, levels=[level], colors="k", linewidths=1.5)
            ax.contourf(x, y, z, levels=[level, hi], colors="none", hatches=["//"])
    else:
        cs = ax.pcolormesh(x, y, z, cmap="RdBu_r", norm=norm, shading="nearest")
    if rotor:
        fig.colorbar(cs, ax=ax, label="largest real part [1/s]")
        ax.set_xlabel("rotor speed [rpm]")
        ax.set_ylabel(_LABELS.get(result.parameter, f"{result.parameter} [{result.unit}]"))
    else:
        fig.colorbar(cs, ax=ax, label="largest Re p [-] (decay rate / omega_theta)")
        ax.set_xlabel("reduced speed U/(b omega_theta) [-]")
        ax.set_ylabel(f"damper on {result.port} [N s/m]")
    ax.set_title(title or f"{result.host}: stability map (black: boundary, hatched: unstable)",
                 fontsize=10)
    return fig
