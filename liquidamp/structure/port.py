"""Device ports and the common interface of every host structure.

A host is a linear structure written in first-order state-space form

.. math:: \\dot x = A x + B u, \\qquad y = C x + D u

whose signals carry names.  A *device port* names three of those signals:
the output that is the device stroke [m], the output that is the stroke rate
[m/s] and the input that takes the device force [N].  The coupling joins a
device to a host by these names (``control.interconnect``), never by
hand-indexed state vectors.

Sign convention of every port
    The stroke ``y`` is positive when the host moves in the positive
    direction of the coordinate the device is attached to (``arm * zeta`` for
    a blade, ``h`` for a plunging section, ``arm * theta`` for a pitching
    one).  The port force ``F`` is the device force in the device's own
    convention, i.e. positive when it resists a positive stroke (a linear
    damper gives ``F = c * dy/dt``; the liquid device gives
    ``F = A_p (p1 - p2)``).  The host applies ``-F`` along the stroke, i.e.
    a generalized force ``-arm * F`` on the attached coordinate.  Connecting
    ``F = c * dy/dt`` therefore adds the damping ``c * arm**2`` to the host.

Hosts whose coefficients depend on the azimuth (a rotor with dissimilar
blades) are :class:`PeriodicStateSpace` objects: matrices as functions of
time over one period, with the same signal names.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import control
import numpy as np

from liquidamp.errors import ParameterError, check_positive

__all__ = ["DevicePort", "Host", "PeriodicStateSpace", "find_port"]


@dataclass(frozen=True)
class DevicePort:
    """Names of the signals by which a device is attached to a host.

    Parameters
    ----------
    name : str
        Port name, unique within a host (e.g. ``"blade_2"``, ``"plunge"``).
    stroke_output : str
        Name of the host output that is the device stroke [m].
    rate_output : str
        Name of the host output that is the stroke rate [m/s].
    force_input : str
        Name of the host input that takes the device force [N] (positive
        when the device resists a positive stroke; see the module notes).
    arm : float
        Lever arm between the host coordinate and the stroke [m] for an
        angular coordinate, or 1 [-] for a translational one.
    coordinate : str
        Name of the host state the device acts on (``"zeta_2"``, ``"h"``).

    Examples
    --------
    >>> p = DevicePort("lag", "stroke", "stroke_rate", "force", 0.25, "zeta")
    >>> p.signals
    ('stroke', 'stroke_rate', 'force')
    """

    name: str
    stroke_output: str
    rate_output: str
    force_input: str
    arm: float = 1.0
    coordinate: str = ""

    def __post_init__(self) -> None:
        names = (self.stroke_output, self.rate_output, self.force_input)
        if not self.name or not all(isinstance(s, str) and s for s in names):
            raise ParameterError(f"a device port needs non-empty signal names, got {self!r}")
        if len(set(names)) != 3:
            raise ParameterError(f"port {self.name!r} signal names must differ, got {names}")
        check_positive(f"arm of port {self.name!r}", self.arm, "m")

    @property
    def signals(self) -> tuple[str, str, str]:
        """``(stroke_output, rate_output, force_input)``."""
        return (self.stroke_output, self.rate_output, self.force_input)


@runtime_checkable
class Host(Protocol):
    """What every host structure offers the coupling.

    Attributes
    ----------
    ports : tuple of DevicePort
        The device ports, in a fixed order.
    state_names : tuple of str
        Names of the first-order states (with their units in the host's
        docstring).

    Notes
    -----
    ``statespace(**conditions)`` returns a :class:`control.StateSpace` with
    named states, inputs and outputs in SI (e.g. ``Omega`` [rad/s] for a
    blade, ``U`` [m/s] for a wing section).  A periodic host also has
    ``periodic_statespace(...)`` returning a :class:`PeriodicStateSpace`.
    """

    @property
    def ports(self) -> tuple[DevicePort, ...]: ...

    @property
    def state_names(self) -> tuple[str, ...]: ...

    def statespace(self, *args, **kwargs) -> control.StateSpace: ...


def find_port(ports, name: str) -> DevicePort:
    """Return the port called ``name`` or raise listing the valid ones.

    Examples
    --------
    >>> ports = (DevicePort("plunge", "stroke_plunge", "stroke_rate_plunge", "force_plunge"),)
    >>> find_port(ports, "plunge").force_input
    'force_plunge'
    >>> find_port(ports, "pitch")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown port 'pitch'; valid: plunge
    """
    for p in ports:
        if p.name == name:
            return p
    raise ParameterError(f"unknown port {name!r}; valid: {', '.join(p.name for p in ports)}")


@dataclass(frozen=True, eq=False)
class PeriodicStateSpace:
    """A linear system with periodic coefficients, with named signals.

    ``A(t)`` and ``B(t)`` are periodic with period ``period``; ``C`` and
    ``D`` are constant.  ``statespace(t)`` freezes the coefficients at time
    ``t`` into a :class:`control.StateSpace` with the same names, which the
    coupling can interconnect at each time (e.g. to build the closed-loop
    ``A(t)`` for a Floquet analysis).

    Parameters
    ----------
    period : float
        Period of the coefficients [s].
    A, B : callable
        ``A(t) -> (n, n)`` and ``B(t) -> (n, m)`` arrays, ``t`` in [s].
    C, D : ndarray
        Output matrices ``(p, n)`` and ``(p, m)``.
    state_names, input_names, output_names : tuple of str
        Signal names.
    ports : tuple of DevicePort
        Device ports of the host.
    name : str
        System name.

    Examples
    --------
    >>> import numpy as np
    >>> sys = PeriodicStateSpace(
    ...     2 * np.pi, lambda t: np.array([[0.0, 1.0], [-1.0 - 0.1 * np.cos(t), 0.0]]),
    ...     lambda t: np.array([[0.0], [1.0]]), np.eye(2), np.zeros((2, 1)),
    ...     ("q", "q_dot"), ("f",), ("q_out", "q_dot_out"))
    >>> float(sys.statespace(0.0).A[1, 0])
    -1.1
    """

    period: float
    A: Callable[[float], np.ndarray]
    B: Callable[[float], np.ndarray]
    C: np.ndarray
    D: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    ports: tuple[DevicePort, ...] = ()
    name: str = "periodic_host"

    def __post_init__(self) -> None:
        check_positive("period", self.period, "s")

    @property
    def nstates(self) -> int:
        """Number of states [-]."""
        return len(self.state_names)

    def statespace(self, t: float) -> control.StateSpace:
        """Coefficients frozen at time ``t`` [s] as a named :class:`control.StateSpace`."""
        return control.ss(
            self.A(t),
            self.B(t),
            self.C,
            self.D,
            states=list(self.state_names),
            inputs=list(self.input_names),
            outputs=list(self.output_names),
            name=self.name,
        )
