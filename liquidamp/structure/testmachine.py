"""The test machine: a host that prescribes the device stroke.

A stroke is a callable ``stroke(t) -> (y, v, a)`` returning the piston
displacement [m], velocity [m/s] and acceleration [m/s^2].  The harmonic
stroke is the paper's ``y = Y sin(2 pi f t)`` (Sec. IV.B); a recorded stroke
interpolates a measured LVDT signal whose rate and acceleration come from a
Savitzky-Golay filter, as in the paper (21 points, 4th order).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B.
.. [2] A. Savitzky, M. J. E. Golay, Anal. Chem. 36(8), 1964.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.errors import ParameterError, check_finite, check_positive

__all__ = ["HarmonicStroke", "RecordedStroke", "savgol_derivatives"]


@dataclass(frozen=True)
class HarmonicStroke:
    """Harmonic stroke y(t) = offset + Y sin(2 pi f t + phase).

    Parameters
    ----------
    amplitude : float
        Y > 0 [m].
    frequency : float
        f > 0 [Hz] (the only Hz quantity inside: it is the test machine's dial).
    offset : float
        Mean stroke [m].
    phase : float
        Phase [rad].

    Examples
    --------
    >>> s = HarmonicStroke(0.003, 3.0)
    >>> y, v, a = s(0.0)
    >>> y, round(v, 6)
    (0.0, 0.056549)
    """

    amplitude: float
    frequency: float
    offset: float = 0.0
    phase: float = 0.0

    def __post_init__(self) -> None:
        check_positive("stroke amplitude", self.amplitude, "m")
        f = check_positive("stroke frequency", self.frequency, "Hz")
        if f > 1.0e4:
            raise ParameterError(
                f"stroke frequency must lie in (0, 1e4] [Hz] for a lumped device model, got {f:g}"
            )
        check_finite("stroke offset", self.offset, "m")
        check_finite("stroke phase", self.phase, "rad")

    @property
    def omega(self) -> float:
        """Circular frequency [rad/s]."""
        return 2.0 * math.pi * self.frequency

    @property
    def period(self) -> float:
        """Period 1/f [s]."""
        return 1.0 / self.frequency

    @property
    def max_abs(self) -> float:
        """Largest |y| reached [m]."""
        return abs(self.offset) + self.amplitude

    def __call__(self, t):
        """Stroke, rate and acceleration at time ``t`` [s] (scalar or array)."""
        w = self.omega
        if np.ndim(t):
            s, c = np.sin(w * t + self.phase), np.cos(w * t + self.phase)
        else:
            s, c = math.sin(w * t + self.phase), math.cos(w * t + self.phase)
        Y = self.amplitude
        return self.offset + Y * s, Y * w * c, -Y * w * w * s


def savgol_derivatives(t, y, window: int = 21, order: int = 4):
    """Smoothed displacement, velocity and acceleration of a uniformly sampled record.

    Parameters
    ----------
    t : array
        Sample times, uniform spacing [s].
    y : array
        Displacement [m].
    window : int
        Savitzky-Golay window length (odd) [samples]; the paper uses 21.
    order : int
        Polynomial order; the paper uses 4.

    Returns
    -------
    y, v, a : ndarray
        Smoothed displacement [m], velocity [m/s], acceleration [m/s^2].

    Raises
    ------
    ParameterError
        If ``t`` or ``y`` holds NaN or inf (named with the first bad index
        and the count), if their shapes differ, or if the window is invalid.

    Examples
    --------
    >>> t = np.arange(400) / 200.0
    >>> y, v, a = savgol_derivatives(t, 0.002 * np.sin(2 * np.pi * 3 * t))
    >>> exact = 0.002 * 2 * np.pi * 3 * np.cos(2 * np.pi * 3 * t[200])
    >>> bool(abs(v[200] / exact - 1) < 3e-3)  # 21-point window: 0.2 % attenuation at 3 Hz
    True
    """
    from scipy.signal import savgol_filter

    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    for name, arr, unit in (("t", t, "s"), ("y", y, "m")):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise ParameterError(
                f"savgol_derivatives: {name} holds {bad.size} non-finite sample(s) of "
                f"{arr.size}, the first at index {int(bad[0])} "
                f"({float(arr.flat[bad[0]])!r}); every sample must be a finite number [{unit}]")
    if t.shape != y.shape or t.ndim != 1:
        raise ParameterError(f"savgol_derivatives: t and y must be 1-D arrays of one length, "
                             f"got shapes {t.shape} and {y.shape}")
    if window % 2 == 0 or window <= order:
        raise ParameterError(
            f"Savitzky-Golay window must be odd and > order={order}, got window={window}"
        )
    if y.size < window:
        raise ParameterError(f"record has {y.size} samples, fewer than the filter window {window}")
    dt = float(np.mean(np.diff(t)))
    ys = savgol_filter(y, window, order, deriv=0)
    v = savgol_filter(y, window, order, deriv=1, delta=dt)
    a = savgol_filter(y, window, order, deriv=2, delta=dt)
    return ys, v, a


@dataclass(frozen=True, eq=False)
class RecordedStroke:
    """A measured stroke, linearly interpolated between samples.

    Parameters
    ----------
    time : array
        Strictly increasing sample times [s].
    displacement, velocity, acceleration : array
        Samples [m], [m/s], [m/s^2] (see :func:`savgol_derivatives`).

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 201)
    >>> s = RecordedStroke.from_displacement(t, 0.001 * np.sin(2 * np.pi * 2 * t))
    >>> round(float(s(0.125)[0]), 6)
    0.001
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray

    def __post_init__(self) -> None:
        arrays = {}
        for name in ("time", "displacement", "velocity", "acceleration"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.setflags(write=False)
            if arr.ndim != 1 or arr.size < 2:
                raise ParameterError(f"recorded stroke {name} must be a 1-D array of >= 2 samples")
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise ParameterError(f"recorded stroke {name} is not finite at sample {bad[0]}")
            arrays[name] = arr
            object.__setattr__(self, name, arr)
        n = arrays["time"].size
        for name, arr in arrays.items():
            if arr.size != n:
                raise ParameterError(
                    f"recorded stroke {name} has {arr.size} samples, time has {n}"
                )
        dt = np.diff(arrays["time"])
        if np.any(dt <= 0):
            i = int(np.flatnonzero(dt <= 0)[0])
            raise ParameterError(f"recorded stroke time is not increasing at sample {i + 1}")

    @classmethod
    def from_displacement(cls, time, displacement, window: int = 21, order: int = 4):
        """Build from displacement alone, differentiating with Savitzky-Golay."""
        y, v, a = savgol_derivatives(time, displacement, window, order)
        return cls(np.asarray(time, float), y, v, a)

    @property
    def max_abs(self) -> float:
        """Largest |y| in the record [m]."""
        return float(np.max(np.abs(self.displacement)))

    def __call__(self, t):
        """Interpolated stroke, rate and acceleration at ``t`` [s]."""
        tt = self.time
        return (
            np.interp(t, tt, self.displacement),
            np.interp(t, tt, self.velocity),
            np.interp(t, tt, self.acceleration),
        )
