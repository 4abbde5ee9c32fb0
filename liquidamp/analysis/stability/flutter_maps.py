"""Flutter stability map: reduced flight speed x a damper's coefficient on a section port.

The typical section (Hodges & Pierce by default) with a linear viscous damper
``F = c v`` on its ``plunge`` or ``pitch`` port, state-space aerodynamics
(R. T. Jones' approximation of Theodorsen's C(k) by default): at every
(speed, coefficient) point the largest real part of the closed-loop
eigenvalues p [-] (in units of omega_theta, the p method of
:func:`liquidamp.analysis.stability.damped_stability.damped_flutter_analysis`)
and the least damping ratio ``-Re p/|p|`` [-] of the eigenvalues (1 for a
real decaying one, -1 for divergence).
The flutter boundary is the zero level.  Points are independent: they run
here or, in batches of rows, on any executor
(:func:`liquidamp.analysis.stability.parallel.map_batched`).

References
----------
.. [1] D. H. Hodges, G. A. Pierce, *Introduction to Structural Dynamics and
   Aeroelasticity*, 2nd ed., Cambridge University Press, 2011, Ch. 5.
.. [2] R. T. Jones, "The unsteady lift of a wing of finite aspect ratio",
   NACA Report 681, 1940.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.stability.maps import zero_crossings
from liquidamp.errors import ParameterError, check_choice

__all__ = ["FlutterMap", "flutter_map"]


@dataclass(frozen=True, eq=False)
class FlutterMap:
    """Largest real part and least damping ratio over reduced speed x damper coefficient.

    Attributes
    ----------
    host : str
        Section name.
    speed : ndarray, shape (n_speed,)
        Reduced speeds U/(b omega_theta) [-].
    port : str
        ``plunge`` or ``pitch``.
    values : ndarray, shape (n_values,)
        Damper coefficients [N s/m].
    max_real_part : ndarray, shape (n_values, n_speed)
        Largest Re p of the closed loop [-] (decay rate / omega_theta); > 0 unstable.
    min_damping_ratio : ndarray, shape (n_values, n_speed)
        Least ``-Re p/|p|`` over the non-zero eigenvalues [-]; < 0 unstable.
    aero : str
    seconds : float
        Wall time [s].
    note : str
    """

    host: str
    speed: np.ndarray
    port: str
    values: np.ndarray
    max_real_part: np.ndarray
    min_damping_ratio: np.ndarray
    aero: str
    seconds: float
    note: str

    def flutter_speeds(self) -> list[float | None]:
        """Per coefficient, the first speed where ``max_real_part`` crosses zero upwards [-]
        (linear interpolation on the grid), or None."""
        out = []
        V = self.speed
        for row in self.max_real_part - 1e-9:
            if row[0] > 0.0:
                out.append(float(V[0]))
                continue
            up = np.flatnonzero((row[:-1] <= 0.0) & (row[1:] > 0.0))
            out.append(None if up.size == 0 else zero_crossings(V[up[0]:up[0] + 2],
                                                                row[up[0]:up[0] + 2])[0])
        return out

    def to_dict(self) -> dict:
        """JSON-ready dictionary."""
        return {
            "host": self.host, "aero": self.aero, "port": self.port,
            "parameter": "damping", "values [N s/m]": self.values.tolist(),
            "speeds [U/(b omega_theta)]": self.speed.tolist(),
            "max_real_part [-]": self.max_real_part.tolist(),
            "min_damping_ratio [-]": self.min_damping_ratio.tolist(),
            "flutter_speed [U/(b omega_theta)]": self.flutter_speeds(),
            "seconds": self.seconds, "note": self.note,
        }


def _row(item) -> tuple[np.ndarray, np.ndarray]:
    """Task: ``(section, speeds, port, c, aero)`` -> (max Re p, least damping ratio) per speed."""
    from liquidamp.analysis.stability.damped_stability import (
        closed_loop_matrix,
        device_lti,
        section_system,
    )
    from liquidamp.coupled.assembly import viscous

    section, V, port, c, aero = item
    dev = viscous(float(c))
    lti = [device_lti(dev)]
    mx, zeta = np.empty(V.size), np.empty(V.size)
    for i, v in enumerate(V):
        lam = np.linalg.eigvals(closed_loop_matrix(
            section_system(section, section.speed(float(v)), {port: dev}, aero), lti))
        p = lam / section.omega_theta
        mx[i] = p.real.max()
        p = p[np.abs(p) > 0.0]
        zeta[i] = float(np.min(-p.real / np.abs(p)))
    return mx, zeta


def flutter_map(section, speeds, values, *, port: str = "plunge", aero: str = "jones",
                executor="serial", progress=False) -> FlutterMap:
    """Flutter map of a section with a viscous damper of coefficient ``values`` on ``port``.

    Parameters
    ----------
    section : TypicalSection
    speeds : array
        Strictly increasing reduced speeds U/(b omega_theta) > 0 [-].
    values : array
        Strictly increasing damper coefficients >= 0 [N s/m].
    port : {"plunge", "pitch"}
    aero : {"jones", "quasi-steady", "steady"}
        State-space aerodynamics.
    executor : "serial", None or executor
        :func:`~liquidamp.analysis.stability.parallel.map_batched` (rows are tasks).
    progress : bool or callable
        ``progress(n)`` after every ``n`` points.

    Returns
    -------
    FlutterMap

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> m = flutter_map(load_section("hodges-pierce"), [1.5, 2.5], [1e-9])
    >>> bool(m.max_real_part[0, 0] < 0 < m.max_real_part[0, 1])   # Jones: 2.17036
    True
    """
    from liquidamp.analysis.stability.parallel import map_batched

    t0 = time.perf_counter()
    check_choice("port", port, ("plunge", "pitch"))
    check_choice("aerodynamics", aero, ("jones", "quasi-steady", "steady"))
    V = np.atleast_1d(np.asarray(speeds, float))
    c = np.atleast_1d(np.asarray(values, float))
    if V.size == 0 or not np.all(np.isfinite(V)) or np.any(V <= 0.0) or np.any(np.diff(V) <= 0):
        raise ParameterError(f"reduced speeds must be finite, > 0 and strictly increasing "
                             f"[U/(b omega_theta)], got {V.tolist()}")
    if c.size == 0 or not np.all(np.isfinite(c)) or np.any(c < 0.0) or np.any(np.diff(c) <= 0):
        raise ParameterError(f"damper coefficients must be finite, >= 0 and strictly increasing "
                             f"[N s/m], got {c.tolist()}")
    rows = map_batched(_row, [(section, V, port, float(x), aero) for x in c], executor=executor,
                       progress=(lambda n: progress(n * V.size)) if callable(progress)
                       else progress)
    mx = np.array([r[0] for r in rows])
    zeta = np.array([r[1] for r in rows])
    note = (f"p method, {aero} aerodynamics, viscous damper on {port}; Re p in units of "
            "omega_theta; damping ratio -Re p/|p| over the eigenvalues")
    return FlutterMap(section.name, V, port, c, mx, zeta, aero, time.perf_counter() - t0,
                      note)
