"""Dual-frequency figure: lag storage and loss stiffness against the 1/rev amplitude.

Compute and plot are separate: :func:`plot_dual_frequency` takes the
JSON-ready points of ``liquidamp dual-frequency`` (the keys of
:meth:`~liquidamp.analysis.response.dual_frequency.DualFrequencyStiffness.as_dict`)
and returns a :class:`matplotlib.figure.Figure` (Agg backend, imported
lazily).  Axes in mm and N/m.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["plot_dual_frequency"]


def plot_dual_frequency(points: Sequence[dict], *, title: str = ""):
    """K' and K'' at the lag frequency against the 1/rev amplitude, one line per lag amplitude.

    The single-frequency values (the lag motion alone) are drawn as dotted
    horizontal lines in the same colour; failed points (``None`` values) are
    left out.

    Parameters
    ----------
    points : sequence of dict
        Each with ``"rev_amplitude [m]"``, ``"lag_amplitude [m]"``,
        ``"storage [N/m]"``, ``"loss [N/m]"``,
        ``"single_frequency_storage [N/m]"``, ``"single_frequency_loss [N/m]"``.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> pts = [{"rev_amplitude [m]": a, "lag_amplitude [m]": 5e-4, "storage [N/m]": 1e4,
    ...         "loss [N/m]": 2e4 + a * 1e7, "single_frequency_storage [N/m]": 1e4,
    ...         "single_frequency_loss [N/m]": 2e4} for a in (0.0, 1e-3, 2e-3)]
    >>> fig = plot_dual_frequency(pts)
    >>> [len(ax.lines) for ax in fig.axes]
    [2, 2]
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 6.0), layout="constrained")
    ax_s, ax_l = fig.subplots(2, 1, sharex=True)
    lags = sorted({p["lag_amplitude [m]"] for p in points})
    for k, A2 in enumerate(lags):
        rows = sorted((p for p in points if p["lag_amplitude [m]"] == A2),
                      key=lambda p: p["rev_amplitude [m]"])
        color = f"C{k % 10}"
        for ax, key in ((ax_s, "storage [N/m]"), (ax_l, "loss [N/m]")):
            ok = [p for p in rows if p.get(key) is not None]
            ax.plot([p["rev_amplitude [m]"] * 1e3 for p in ok], [p[key] for p in ok], "o-",
                    color=color, label=f"lag amplitude {A2 * 1e3:g} mm")
            single = [p[f"single_frequency_{key}"] for p in rows
                      if p.get(f"single_frequency_{key}") is not None]
            if single:
                ax.axhline(single[0], color=color, ls=":", lw=1.2)
    ax_s.set_ylabel("storage K' at the lag frequency [N/m]")
    ax_l.set_ylabel("loss K'' at the lag frequency [N/m]")
    ax_l.set_xlabel("1/rev amplitude [mm]")
    ax_s.legend(fontsize="small", title="dotted: lag motion alone", title_fontsize="small")
    for ax in (ax_s, ax_l):
        ax.grid(True, alpha=0.3)
    if title:
        fig.suptitle(title)
    return fig
