"""What the calibration records' loops show: friction level, pre-sliding stroke, centre line.

:func:`read_loop` reads the numbers the structurally different starts of
:mod:`~liquidamp.analysis.measured.device_class` are built from (split from that module,
which re-exports :class:`LoopReading` and :func:`read_loop`).

References
----------
.. [1] C. Canudas de Wit, H. Olsson, K. J. Astrom, P. Lischinsky, "A new model for
   control of systems with friction", IEEE TAC 40(3), 1995 (LuGre).
.. [2] P. R. Dahl, "A solid friction model", Aerospace Corp. TOR-0158(3107-18)-1, 1968.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.start import first_harmonic_stiffness

__all__ = ["LoopReading", "read_loop"]


@dataclass(frozen=True)
class LoopReading:
    """What the calibration records' loops show (:func:`read_loop`), in SI.

    Attributes
    ----------
    offset : float
        F0, the centre line's force at the mean stroke [N].
    stiffness : float
        k, the centre line's slope [N/m].
    friction : float
        F_c, the friction level (module docstring) [N].
    friction_source : str
        ``"least squares on F0 + k y + F_c z"`` or ``"loss part (pi K'' Y / 4)"``.
    presliding : float
        dy0, the pre-sliding stroke F_c / sigma0 of the best description [m].
    mean_force : float
        Pooled mean force [N].
    stiffnesses : tuple of complex
        Each record's first-harmonic K* [N/m].
    """

    offset: float
    stiffness: float
    friction: float
    friction_source: str
    presliding: float
    mean_force: float
    stiffnesses: tuple

    def as_dict(self) -> dict:
        """JSON-ready (SI)."""
        return {"offset [N]": self.offset, "stiffness [N/m]": self.stiffness,
                "friction [N]": self.friction, "friction_source": self.friction_source,
                "presliding_stroke [m]": None if math.isnan(self.presliding)
                else self.presliding, "mean_force [N]": self.mean_force,
                "K* [N/m]": [[K.real, K.imag] for K in self.stiffnesses]}


def _bristle(record, deltas, passes: int = 2) -> np.ndarray:
    """z(t) of Dahl/LuGre friction (n = 1, no Stribeck) of pre-sliding strokes ``deltas``
    [m] driven by the record's velocity, one row per delta [-]: dz/dy = (sign v - z) / delta,
    exact for a velocity held over each sample; the last of ``passes`` passes (the first
    from z = 0)."""
    v = record.velocity
    dy = np.abs(v) * np.gradient(record.time)
    sv = np.sign(v)
    decay = np.exp(-dy[None, :] / np.asarray(deltas, float)[:, None])
    z = np.zeros(len(deltas))
    out = np.empty((len(deltas), v.size))
    for _ in range(passes):
        for i in range(v.size):
            z = sv[i] + (z - sv[i]) * decay[:, i]
            out[:, i] = z
    return out


def read_loop(records) -> LoopReading:
    """Friction level, pre-sliding stroke, centre line and K* of ``records`` (module doc).

    The loop is described by least squares as F ~ F0 + k (y - mean y) + F_c z(t), z the
    state of Dahl/LuGre friction (n = 1) of pre-sliding stroke dy0 driven by the recorded
    stroke (:func:`_bristle`), for dy0 on a log grid from 1e-3 to 1 times the stroke
    amplitude; the dy0 of the least residual wins (a friction damper's slanted reversal is
    its pre-sliding, a parallel spring is k).  Where F_c is not positive, F_c is the Coulomb
    level pi K'' Y / 4 of the loop's loss part.

    Examples
    --------
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 4.0, 0.002)
    >>> y = 0.01 * np.sin(2 * np.pi * t)
    >>> F = 200.0 + 1e4 * y + 500.0 * np.tanh(np.gradient(y, t) / 1e-3)
    >>> L = read_loop([Record.from_arrays(t, y, F)])
    >>> round(L.friction, -1), round(L.stiffness, -3), round(L.offset)   # tanh, not Dahl
    (500.0, 8000.0, 200)
    """
    records = tuple(records)
    Y = max(r.stroke_scale for r in records)
    deltas = np.geomspace(1e-3 * Y, Y, 31)
    zs = [_bristle(r, deltas) for r in records]
    ys = np.concatenate([r.displacement - r.offset for r in records])
    F = np.concatenate([r.force for r in records])
    best = None
    for j, d in enumerate(deltas):
        X = np.column_stack((np.ones_like(ys), ys, np.concatenate([z[j] for z in zs])))
        coef, *_ = np.linalg.lstsq(X, F, rcond=None)
        rss = float(np.sum((X @ coef - F) ** 2))
        if best is None or rss < best[0]:
            best = (rss, d, coef)
    _, dy0, (F0, k, Fc) = best
    Ks = tuple(first_harmonic_stiffness(r) for r in records)
    source = "least squares on F0 + k y + F_c z"
    if not Fc > 0:
        Fc = float(np.mean([math.pi * K.imag * r.stroke_scale / 4.0
                            for K, r in zip(Ks, records, strict=True)]))
        source = "loss part (pi K'' Y / 4)"
    return LoopReading(float(F0), float(k), float(max(Fc, 0.0)), source, float(dy0),
                       float(np.mean(F)), Ks)
