"""Lag damping in forward flight: damping ratio against the 1/rev damper stroke.

Takes the JSON-ready result of
:func:`~liquidamp.analysis.stability.lag_sweep.lag_damping_sweep` and returns a
:class:`matplotlib.figure.Figure` (Agg backend, imported lazily): Floquet
points (markers) and the K_lag prediction (lines, one style per lag
amplitude), one colour per device.  Axes in mm and percent.
"""

from __future__ import annotations

__all__ = ["plot_lag_sweep"]

_STYLES = ("-", "--", ":", "-.")


def plot_lag_sweep(data: dict, *, title: str = ""):
    """Lag damping ratio [%] against the 1/rev stroke [mm]: Floquet points, K_lag lines.

    Parameters
    ----------
    data : dict
        As returned by
        :func:`~liquidamp.analysis.stability.lag_sweep.lag_damping_sweep`.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> d = {"rev_stroke [m]": [0.0, 1e-3], "lag_amplitudes [m]": [1e-4],
    ...      "devices": {"a": {"floquet_damping_ratio [-]": [0.01, 0.02],
    ...                        "klag_damping_ratio [-]": [[0.011, 0.019]]}}}
    >>> fig = plot_lag_sweep(d)
    >>> len(fig.axes[0].lines)
    2
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    A1 = [1e3 * a for a in data["rev_stroke [m]"]]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for i, (label, d) in enumerate(data["devices"].items()):
        color = f"C{i}"
        ax.plot(A1, [100 * z for z in d["floquet_damping_ratio [-]"]], "o", color=color,
                label=f"{label}: Floquet")
        for j, (A2, z) in enumerate(zip(data["lag_amplitudes [m]"], d["klag_damping_ratio [-]"],
                                        strict=True)):
            ax.plot(A1, [100 * v for v in z], _STYLES[j % len(_STYLES)], color=color,
                    label=f"{label}: K_lag, lag {1e3 * A2:g} mm")
    ax.set_xlabel("1/rev damper stroke amplitude [mm]")
    ax.set_ylabel("lag damping ratio [%]")
    ax.set_title(title or "lag damping under 1/rev motion")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig
