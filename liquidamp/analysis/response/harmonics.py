"""First harmonic and dynamic stiffness of a periodic response.

Convention (sine convention, used throughout liquidamp): for a stroke
y = Y sin(omega t) the complex first harmonic of a signal
s(t) = a sin(omega t) + b cos(omega t) + ... is S1 = a + i b, and the dynamic
stiffness is K* = F1 / Y1 [N/m].  Its phase is reported in (-180, 180] deg:
0 deg is a spring, +90 deg a damper, 180 deg an inerter (a mass-like force in
phase with the acceleration, -omega^2 b).  This is the phase of
K(i omega) = F(i omega) / Y(i omega) of a linear stroke-to-force transfer
function, so the two agree; python-control's ``bode_plot`` and
``FrequencyResponseData.phase`` instead *unwrap* the phase along frequency
(an inerter-dominated K* may then read +180 deg or -180 deg, or 540 deg after
several turns), while liquidamp always wraps it into (-180, 180].

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV (first-harmonic dynamic
   stiffness of the device on the test machine).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.errors import ParameterError, check_positive

__all__ = ["first_harmonic", "DynamicStiffness", "dynamic_stiffness", "check_samples",
           "check_whole_periods", "WHOLE_PERIOD_TOL"]


def check_samples(name: str, values, unit: str = "-", *, where: str = "") -> np.ndarray:
    """Return ``values`` as a float array or raise if any sample is NaN or infinite.

    Parameters
    ----------
    name : str
        Name of the argument, as the user knows it.
    values : array_like
        Samples.
    unit : str
        Unit shown in the message.
    where : str
        Calling function, shown first in the message.

    Returns
    -------
    ndarray
        ``np.asarray(values, float)``.

    Raises
    ------
    ParameterError
        Naming the argument, the first bad index, its value and how many
        samples are bad (NaN is never passed through).

    Examples
    --------
    >>> check_samples("signal", [1.0, float("nan"), 2.0, float("inf")], "N")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: signal holds 2 non-finite sample(s) of 4, the first at ...
    """
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"{where + ': ' if where else ''}{name} must be an array of real "
                             f"numbers [{unit}], got {type(values).__name__}") from None
    bad = np.flatnonzero(~np.isfinite(arr.ravel()))
    if bad.size:
        i = int(bad[0])
        idx = np.unravel_index(i, arr.shape) if arr.ndim > 1 else i
        raise ParameterError(
            f"{where + ': ' if where else ''}{name} holds {bad.size} non-finite sample(s) of "
            f"{arr.size}, the first at index {idx} ({float(arr.ravel()[i])!r}); every "
            f"sample must be a finite number [{unit}]")
    return arr


#: Largest departure of a span from a whole number of periods (relative to the span) and
#: of a time step from the mean step (relative to that step) [-].
WHOLE_PERIOD_TOL = 1e-6


def check_whole_periods(t, frequency: float, *, where: str = "first_harmonic") -> int:
    """Raise unless ``t`` is uniform and spans a whole number of periods (end point excluded).

    Parameters
    ----------
    t : ndarray
        Sample times [s], at least 2.
    frequency : float
        Fundamental frequency [Hz].
    where : str
        Calling function, first in the message.

    Returns
    -------
    int
        The number of whole periods spanned.

    Raises
    ------
    ParameterError
        Naming the span in periods and what is allowed.

    Examples
    --------
    >>> check_whole_periods(np.arange(64) / 32.0, 1.0)
    2
    >>> check_whole_periods(np.arange(30) / 200.0, 1.0)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: first_harmonic needs uniform samples over a whole ... the 30
    samples span 0.15 period(s) of 1 Hz
    """
    t = np.asarray(t, float)
    n = t.size
    dt = (t[-1] - t[0]) / (n - 1)
    periods = n * dt * frequency
    whole = int(round(periods))
    uniform = dt > 0 and float(np.max(np.abs(np.diff(t) - dt))) <= WHOLE_PERIOD_TOL * dt
    if not uniform or whole < 1 or abs(periods - whole) > WHOLE_PERIOD_TOL * whole:
        what = "are not uniform" if not uniform else f"span {periods:.4g} period(s) of " \
            f"{frequency:g} Hz"
        raise ParameterError(
            f"{where} needs uniform samples over a whole number of periods (end point "
            f"excluded, e.g. one period of a steady state); the {n} samples {what}")
    return whole


def first_harmonic(t, signal, frequency: float) -> complex:
    """Complex first harmonic a + i b of ``signal`` ~ a sin(wt) + b cos(wt).

    Parameters
    ----------
    t : array
        Uniform samples spanning a whole number of periods, end point
        excluded [s].
    signal : array
        Samples of the signal [any unit].
    frequency : float
        Fundamental frequency [Hz].

    Returns
    -------
    complex
        a + i b [unit of the signal].

    Raises
    ------
    ParameterError
        If ``t`` or ``signal`` holds NaN or inf (the argument, the first bad
        index and the count are named), if the shapes differ, if
        ``frequency`` is not finite and > 0, or if ``t`` is not uniform over a
        whole number of periods (:func:`check_whole_periods`): over part of a
        period the sums are not the Fourier coefficients.

    Examples
    --------
    >>> t = np.arange(64) / 64.0
    >>> h = first_harmonic(t, 2 * np.sin(2 * np.pi * t) + 3 * np.cos(2 * np.pi * t), 1.0)
    >>> round(h.real, 12), round(h.imag, 12)
    (2.0, 3.0)
    """
    t = check_samples("t", t, "s", where="first_harmonic")
    s = check_samples("signal", signal, where="first_harmonic")
    if t.shape != s.shape or t.ndim != 1 or t.size < 4:
        raise ParameterError(f"first_harmonic needs matching 1-D arrays of >= 4 samples, got t "
                             f"of shape {t.shape} and signal of shape {s.shape}")
    frequency = check_positive("first_harmonic: frequency", frequency, "Hz")
    check_whole_periods(t, frequency, where="first_harmonic")
    w = 2.0 * math.pi * frequency
    a = 2.0 * float(np.mean(s * np.sin(w * t)))
    b = 2.0 * float(np.mean(s * np.cos(w * t)))
    return complex(a, b)


@dataclass(frozen=True)
class DynamicStiffness:
    """First-harmonic dynamic stiffness K* = F1 / Y1.

    Attributes
    ----------
    frequency : float
        Excitation frequency [Hz].
    amplitude : float
        Stroke amplitude |Y1| [m].
    value : complex
        K* [N/m].
    """

    frequency: float
    amplitude: float
    value: complex

    @property
    def magnitude(self) -> float:
        """|K*| [N/m]."""
        return abs(self.value)

    @property
    def phase_deg(self) -> float:
        """Phase of K* in (-180, 180] [deg]: 0 spring, 90 damper, 180 inerter."""
        return math.degrees(math.atan2(self.value.imag, self.value.real))

    @property
    def storage(self) -> float:
        """Storage stiffness Re K* [N/m]."""
        return self.value.real

    @property
    def loss(self) -> float:
        """Loss stiffness Im K* [N/m]."""
        return self.value.imag

    @property
    def loss_factor(self) -> float:
        """Loss factor Im K* / Re K* [-] (inf for a pure damper)."""
        return self.value.imag / self.value.real if self.value.real != 0 else math.inf

    @property
    def equivalent_damping(self) -> float:
        """Equivalent viscous damping Im K* / omega [N s/m]."""
        return self.value.imag / (2.0 * math.pi * self.frequency)

    def as_dict(self) -> dict:
        """JSON-ready dictionary with unit-named keys."""
        return {
            "frequency [Hz]": self.frequency,
            "amplitude [m]": self.amplitude,
            "magnitude [N/m]": self.magnitude,
            "phase [deg]": self.phase_deg,
            "storage [N/m]": self.storage,
            "loss [N/m]": self.loss,
        }


def dynamic_stiffness(response) -> DynamicStiffness:
    """Dynamic stiffness of a steady-state response on the test machine.

    Parameters
    ----------
    response : DeviceResponse
        Output of :func:`liquidamp.coupled.testrig.steady_state` (one period,
        uniform samples, harmonic stroke).

    Raises
    ------
    ParameterError
        For a response that is not a steady state (``status`` other than
        ``"steady"``), not under a harmonic stroke, or not over whole periods.

    Returns
    -------
    DynamicStiffness
        K* = F1 / Y1 with both first harmonics in the sine convention.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.coupled.testrig import steady_state
    >>> from liquidamp.structure.testmachine import HarmonicStroke
    >>> p = preset("reference")
    >>> K = dynamic_stiffness(steady_state("spring", p, HarmonicStroke(0.001, 3.0)))
    >>> round(K.magnitude / p.k_D, 9), round(K.phase_deg, 6)
    (1.0, 0.0)
    """
    f = response.frequency
    if f is None:
        raise ParameterError("dynamic_stiffness needs a response to a harmonic stroke")
    if response.status != "steady":
        raise ParameterError(
            f"dynamic_stiffness needs a periodic steady state (liquidamp.coupled.testrig."
            f"steady_state), got a response with status {response.status!r} "
            f"({response.message}): a run from rest holds its start-up transient")
    Y1 = first_harmonic(response.time, response.stroke, f)
    F1 = first_harmonic(response.time, response.force, f)
    return DynamicStiffness(frequency=f, amplitude=abs(Y1), value=F1 / Y1)
