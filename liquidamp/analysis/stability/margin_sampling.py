"""Stability intervals by parameter sampling: the robust (and costly) route.

:func:`sampled_margin` draws the device's varied parameters from the fit's normal
distribution in the fit's own (log) space
(:class:`~liquidamp.analysis.stability.margins.FitUncertainty`), re-runs the whole
analysis for each draw (grid, Brent edges, refined minima) and states
percentile intervals: no linearization, so curvature and a band that appears or vanishes
inside the interval are carried as they are (the share of draws that hold each nominal band
is reported).  It costs one analysis per draw, so it suits constant-coefficient cases
(Coleman, flutter); for Floquet cases the linearized route of
:mod:`liquidamp.analysis.stability.margins` (a few evaluations per answer) is the default,
and this one is its check (tested: the two agree where the answers are nearly linear).

References
----------
.. [1] B. Efron, R. Tibshirani, An Introduction to the Bootstrap, 1993, Ch. 13
   (percentile intervals).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.stability.margins import FitUncertainty, Interval, confidence_z
from liquidamp.errors import check_in_range

__all__ = ["SampledMargin", "sampled_margin"]


@dataclass(frozen=True)
class SampledMargin:
    """Percentile intervals of each answer over parameter draws.

    Attributes
    ----------
    edges : tuple of (Interval, Interval, float)
        Per nominal band: start and end intervals (internal speed unit) over the draws that
        hold an overlapping band, and that share of the draws [-].
    min_damping_ratio : Interval
    flutter_speed : Interval or None
        Over the draws with a flutter speed.
    flutter_share : float
        Share of draws with a flutter speed [-].
    samples : int
    confidence : float
    """

    edges: tuple
    min_damping_ratio: Interval
    flutter_speed: Interval | None
    flutter_share: float
    samples: int
    confidence: float

    def as_dict(self, to_unit: float = 1.0) -> dict:
        """JSON-ready; speeds multiplied by ``to_unit``."""
        return {"method": f"parameter sampling ({self.samples} draws in the fit's log space, "
                          "percentile intervals)", "confidence": self.confidence,
                "bands": [{"start": s.scaled(to_unit).as_dict(), "end": e.scaled(to_unit)
                           .as_dict(), "share_of_draws": p} for s, e, p in self.edges],
                "min_damping_ratio": self.min_damping_ratio.as_dict(),
                "flutter_speed": (None if self.flutter_speed is None else
                                  self.flutter_speed.scaled(to_unit).as_dict()),
                "flutter_share_of_draws": self.flutter_share}


def _percentiles(values, nominal: float, confidence: float) -> Interval:
    v = np.asarray(values, float)
    if v.size == 0:
        return Interval(nominal, -np.inf, np.inf, np.inf)
    q = 50.0 * (1.0 - confidence)
    lo, hi = np.percentile(v, [q, 100.0 - q])
    return Interval(float(nominal), float(min(lo, nominal)), float(max(hi, nominal)),
                    float(np.std(v)))


def sampled_margin(analysis, device, uncertainty: FitUncertainty, *, samples: int = 200,
                   seed: int = 0, confidence: float = 0.95) -> SampledMargin:
    """Percentile intervals of ``analysis(device)`` over draws of the device's parameters.

    Parameters
    ----------
    analysis : callable
        ``analysis(device) -> StabilityMargin`` without uncertainty, e.g.
        ``lambda d: ground_resonance_margin(rotor, Omega, d)``.
    device : Device
        The fitted device.
    uncertainty : FitUncertainty
    samples : int
        Draws (>= 20).
    seed : int
        Seed of :func:`numpy.random.default_rng`.
    confidence : float
        Two-sided confidence in (0, 1).

    Returns
    -------
    SampledMargin

    Examples
    --------
    >>> import dataclasses
    >>> import numpy as np
    >>> from liquidamp.coupled.assembly import Device
    >>> from liquidamp.device import preset
    >>> from liquidamp.structure.hostio import load_section
    >>> from liquidamp.analysis.stability.margins import flutter_margin
    >>> wing = dataclasses.replace(load_section("hodges-pierce"), span=10.0, semichord=1.0)
    >>> u = FitUncertainty(("c1",), np.array([1.0]), (True,), np.array([[0.05 ** 2]]))
    >>> s = sampled_margin(lambda d: flutter_margin(wing, np.linspace(2.0, 2.6, 7), d),
    ...                    Device("full", preset("paper_calibrated")), u, samples=20)
    >>> s.flutter_share, s.flutter_speed.low < 2.3274 < s.flutter_speed.high
    (1.0, True)
    """
    confidence_z(confidence)
    check_in_range("samples", samples, 20, 100000)
    nominal = analysis(device)
    A = uncertainty.axes()
    rng = np.random.default_rng(seed)
    starts = [[] for _ in nominal.bands]
    ends = [[] for _ in nominal.bands]
    zetas, flutter = [], []
    for _ in range(int(samples)):
        delta = A @ rng.standard_normal(A.shape[1]) if A.size else np.zeros(len(
            uncertainty.names))
        m = analysis(uncertainty.apply(device, delta))
        zetas.append(m.min_damping_ratio.value)
        if m.flutter_speed is not None:
            flutter.append(m.flutter_speed.value)
        for i, b in enumerate(nominal.bands):
            best = max(m.bands, default=None, key=lambda c, b=b: min(c.end.value, b.end.value)
                       - max(c.start.value, b.start.value))
            if best is not None and min(best.end.value, b.end.value) > max(
                    best.start.value, b.start.value):
                starts[i].append(best.start.value)
                ends[i].append(best.end.value)
    edges = tuple((_percentiles(s, b.start.value, confidence),
                   _percentiles(e, b.end.value, confidence), len(s) / samples)
                  for s, e, b in zip(starts, ends, nominal.bands, strict=True))
    vf = None
    if nominal.flutter_speed is not None:
        vf = _percentiles(flutter, nominal.flutter_speed.value, confidence)
    return SampledMargin(edges, _percentiles(zetas, nominal.min_damping_ratio.value, confidence),
                         vf, len(flutter) / samples, int(samples), float(confidence))
