"""External inputs of a coupled system: known forcing on a host input.

A host's inputs (:class:`~liquidamp.coupled.assembly.HostMatrices`) are of
two kinds: those that take a device force at a port, and the others -- a
blade's lag moment ``moment`` [N m], a rotor's ``moment_k`` and
``hub_force_x`` [N], a section's aerodynamic inputs.  A
:class:`HarmonicInput` drives one of the others with a known harmonic
signal; :func:`~liquidamp.coupled.assembly.couple` (``inputs=``) adds

.. math:: x_h' = A(t) x_h + B_F(t) F + B_u(t) u(t)

to the coupled equations, for both engines (the compiled second-order
kernel takes each input as a generalized force ``G u(t)`` on the host's
coordinates).  The inputs do not enter the linearization about a state:
the variational equations, Floquet multipliers and closed-loop matrices
are those of the unforced system along the forced motion.

References
----------
.. [1] W. Johnson, *Rotorcraft Aeromechanics*, Cambridge University Press,
   2013, Sec. 16.3 (lag dynamics, periodic in-plane loads in forward flight).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.errors import ParameterError, check_nonnegative

__all__ = ["HarmonicInput", "input_values"]


def _finite(name: str, value, unit: str) -> float:
    v = float(value)
    if not math.isfinite(v):
        raise ParameterError(f"{name} must be finite [{unit}], got {value!r}")
    return v


@dataclass(frozen=True)
class HarmonicInput:
    """A host input driven harmonically (module notes).

    ``u(t) = mean + cos_amplitude cos(omega t) + sin_amplitude sin(omega t)``.

    Parameters
    ----------
    input : str
        Name of the host input (not one that takes a device force).
    omega : float
        Circular frequency >= 0 [rad/s] (the rotor speed Omega for 1/rev).
    cos_amplitude, sin_amplitude : float
        Amplitudes of the cosine and sine parts [unit of the input: N, N m].
    mean : float
        Constant part [unit of the input].

    Examples
    --------
    >>> u = HarmonicInput.polar("moment", 200.0, 26.0, phase=math.pi / 2)
    >>> round(u.amplitude, 12), round(float(u(0.0)), 9)     # 200 sin(26 t + pi/2) at t = 0
    (200.0, 200.0)
    >>> u.scaled(0.5).amplitude
    100.0
    """

    input: str
    omega: float
    cos_amplitude: float = 0.0
    sin_amplitude: float = 0.0
    mean: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.input, str) or not self.input:
            raise ParameterError(f"input must be a host input name, got {self.input!r}")
        object.__setattr__(self, "omega", check_nonnegative("input frequency omega",
                                                            self.omega, "rad/s"))
        for name in ("cos_amplitude", "sin_amplitude", "mean"):
            object.__setattr__(self, name, _finite(f"input {name}", getattr(self, name),
                                                   "input unit"))

    @classmethod
    def polar(cls, input: str, amplitude: float, omega: float, phase: float = 0.0,
              mean: float = 0.0) -> HarmonicInput:
        """``u(t) = mean + amplitude sin(omega t + phase)`` (phase [rad])."""
        A = _finite("input amplitude", amplitude, "input unit")
        ph = _finite("input phase", phase, "rad")
        return cls(input, omega, A * math.sin(ph), A * math.cos(ph), mean)

    @property
    def amplitude(self) -> float:
        """Amplitude of the harmonic part, ``hypot(cos_amplitude, sin_amplitude)``."""
        return math.hypot(self.cos_amplitude, self.sin_amplitude)

    def scaled(self, factor: float) -> HarmonicInput:
        """The same input with the harmonic part (not the mean) times ``factor`` [-]."""
        f = _finite("input scale factor", factor, "-")
        return HarmonicInput(self.input, self.omega, f * self.cos_amplitude,
                             f * self.sin_amplitude, self.mean)

    def __call__(self, t):
        """u(t) [unit of the input] (t [s], scalar or array)."""
        wt = self.omega * np.asarray(t, float)
        return self.mean + self.cos_amplitude * np.cos(wt) + self.sin_amplitude * np.sin(wt)


def input_values(inputs, t) -> np.ndarray:
    """Values of ``inputs`` (a sequence of :class:`HarmonicInput`) at time ``t`` [s], shape (k,)."""
    return np.array([float(u(t)) for u in inputs])
