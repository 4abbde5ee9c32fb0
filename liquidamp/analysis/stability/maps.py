"""Stability maps over two quantities: rotor speed x a damper parameter.

A map is the largest Floquet exponent real part [1/s] of a rotor on its
landing gear (ground resonance, the Hammond 1974 rotor by default) on a
grid of rotor speeds x values of one parameter of the lag dampers:

``degradation``
    blade ``blade``'s damper keeps this fraction of its damping [-]
    (0: failed, 1: healthy); the other dampers are as given.
``lag_damping``
    every working blade's lag damper [N m s/rad] (a damper's coefficient;
    the ``inoperative`` blades stay at zero).
``arm``
    mounting arm [m] of a linear damper of the rotor's coefficient
    ``c = C_lag / a0**2`` [N s/m]: the lag damping is ``c a**2``.

The stability boundary is the zero level of the map (drawn as a contour by
:func:`liquidamp.analysis.reports.map_plots.plot_stability_map`).  Every
point is a Floquet analysis of the periodic rotating-frame model (exact for
dissimilar blades).  The points are integrated by the compiled kernel of
:mod:`liquidamp.analysis.stability._map_kernel` with the step count that the
error control of :func:`~liquidamp.analysis.stability.floquet.batched_monodromy`
picks on the map's extreme rows, on numba's threads locally or in batches of
rows on any executor (:func:`liquidamp.analysis.stability.parallel.map_batched`,
e.g. a ``dask.distributed.Client``); the numbers do not depend on the route.

References
----------
.. [1] C. E. Hammond, "An application of Floquet theory to prediction of
   mechanical instability", J. American Helicopter Society 19(4), 14-23, 1974.
.. [2] A. Gandhi, R. Whitt, "Floquet analysis of ground resonance with a
   degraded lag damper", VFS Forum 78, 2022 (partial degradation).
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.stability.floquet import FloquetOptions
from liquidamp.analysis.stability.ground_resonance import _RotorCoefficients, rad_s_to_rpm
from liquidamp.errors import ConvergenceError, ParameterError, check_choice

__all__ = ["PARAMETERS", "MapOptions", "StabilityMap", "ground_resonance_map",
           "map_dampers", "zero_crossings"]

#: Parameters a ground-resonance map runs over, with their units.
PARAMETERS = {"degradation": "-", "lag_damping": "N m s/rad", "arm": "m"}


@dataclass(frozen=True)
class MapOptions:
    """How a map is computed (not what it computes).

    Attributes
    ----------
    floquet : FloquetOptions, optional
        Tolerances of the step-count control (``rtol``, ``atol``).
    steps : int, optional
        Coarse RK4 steps per revolution (the result combines ``steps`` and
        ``2 steps``); default: chosen by error control on the first, middle
        and last rows.
    executor : None, "serial" or object with ``submit``
        None: this process, numba's threads over the points; ``"serial"``:
        one thread; else rows are sent in batches to the executor (e.g. a
        ``dask.distributed.Client``) by
        :func:`~liquidamp.analysis.stability.parallel.map_batched`.
    min_task_seconds : float
        Smallest batch sent to an executor [s].
    chunk_points : int
        Points per local chunk (one progress update each) [-].
    progress : bool or callable
        ``progress(n)`` after every ``n`` points, or a line on stderr.
    """

    floquet: FloquetOptions | None = None
    steps: int | None = None
    executor: object = None
    min_task_seconds: float = 0.1
    chunk_points: int = 1000
    progress: object = False

    def __post_init__(self) -> None:
        if self.steps is not None and (isinstance(self.steps, bool) or int(self.steps) < 4
                                       or int(self.steps) != self.steps):
            raise ParameterError(f"steps must be an integer >= 4, got {self.steps!r}")
        if not self.chunk_points >= 1:
            raise ParameterError(f"chunk_points must be >= 1, got {self.chunk_points!r}")
        if not self.min_task_seconds >= 0.0:
            raise ParameterError(
                f"min_task_seconds must be >= 0 [s], got {self.min_task_seconds!r}")


def zero_crossings(x, v) -> list[float]:
    """Where ``v`` changes sign along ``x``, by linear interpolation (grid resolution).

    Examples
    --------
    >>> zero_crossings([0.0, 1.0, 2.0, 3.0], [-1.0, 1.0, 1.0, -3.0])
    [0.5, 2.25]
    """
    x, v = np.asarray(x, float), np.asarray(v, float)
    out = []
    for i in range(x.size - 1):
        if (v[i] > 0.0) != (v[i + 1] > 0.0):
            out.append(float(x[i] - v[i] * (x[i + 1] - x[i]) / (v[i + 1] - v[i])))
    return out


@dataclass(frozen=True, eq=False)
class StabilityMap:
    """Largest real part of the Floquet exponents over speed x parameter.

    Attributes
    ----------
    host : str
        Rotor name.
    speed : ndarray, shape (n_speed,)
        Rotor speeds [rad/s].
    parameter : str
        Key of :data:`PARAMETERS`.
    unit : str
        Unit of ``values``.
    values : ndarray, shape (n_values,)
        Parameter values [unit].
    max_real_part : ndarray, shape (n_values, n_speed)
        Largest real part of the Floquet exponents [1/s]; > 0 unstable.
    dampings : ndarray, shape (n_values, n_blades)
        Lag damper of each blade at each value [N m s/rad].
    steps : int
        Coarse RK4 steps per revolution used (and twice as many, extrapolated).
    seconds : float
        Wall time of the computation [s].
    note : str
    neutral_tol : float
        A largest real part up to this counts as neutral [1/s].
    """

    host: str
    speed: np.ndarray
    parameter: str
    unit: str
    values: np.ndarray
    max_real_part: np.ndarray
    dampings: np.ndarray
    steps: int
    seconds: float
    note: str
    neutral_tol: float = 1e-6
    route: str = field(default="threads")

    @property
    def rpm(self) -> np.ndarray:
        """Rotor speeds [rpm]."""
        return rad_s_to_rpm(self.speed)

    def unstable_ranges_rpm(self) -> list[list[list[float]]]:
        """Per parameter value, the unstable rpm intervals at grid resolution [rpm].

        Ends are the zero crossings of ``max_real_part - neutral_tol``
        interpolated linearly between grid speeds.
        """
        rpm = self.rpm
        out = []
        for row in self.max_real_part - self.neutral_tol:
            ends = zero_crossings(rpm, row)
            edges = ([float(rpm[0])] if row[0] > 0.0 else []) + ends + \
                ([float(rpm[-1])] if row[-1] > 0.0 else [])
            out.append([edges[i:i + 2] for i in range(0, len(edges), 2)])
        return out

    def to_dict(self) -> dict:
        """JSON-ready dictionary (rpm at this edge)."""
        return {
            "host": self.host,
            "parameter": self.parameter,
            f"values [{self.unit}]": self.values.tolist(),
            "rpm": self.rpm.tolist(),
            "max_real_part [1/s]": self.max_real_part.tolist(),
            "lag_dampers [N m s/rad]": self.dampings.tolist(),
            "unstable_ranges [rpm]": self.unstable_ranges_rpm(),
            "neutral_tol [1/s]": self.neutral_tol,
            "steps_per_revolution": int(self.steps),
            "route": self.route,
            "seconds": self.seconds,
            "note": self.note,
        }


def map_dampers(rotor, parameter: str, values, *, blade: int = 1, inoperative=()):
    """Lag damper of each blade [N m s/rad] at each parameter value, shape (n_values, N).

    Parameters
    ----------
    rotor : GroundResonanceRotor
    parameter : str
        ``degradation``, ``lag_damping`` or ``arm`` (:data:`PARAMETERS`).
    values : array
        Parameter values: fractions in [0, 1]; dampers >= 0 [N m s/rad]; arms > 0 [m].
    blade : int
        The degraded blade (1-based), for ``degradation``.
    inoperative : tuple of int
        Blades whose damper has failed (zero damping at every value).

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> map_dampers(load_rotor("hammond1974"), "degradation", [0.0, 0.5])[:, :2].tolist()
    [[0.0, 4067.5], [2033.75, 4067.5]]
    """
    check_choice("map parameter", parameter, tuple(PARAMETERS))
    v = np.atleast_1d(np.asarray(values, dtype=float))
    if v.ndim != 1 or v.size == 0 or not np.all(np.isfinite(v)):
        raise ParameterError(f"{parameter} values must be a non-empty list of finite numbers, "
                             f"got {np.asarray(values).tolist()}")
    if v.size > 1 and np.any(np.diff(v) <= 0.0):
        raise ParameterError(f"{parameter} values must be strictly increasing, got {v.tolist()}")
    base = np.asarray(rotor.blade_damping, dtype=float)
    failed = [rotor.check_blade(k) - 1 for k in inoperative]
    base[failed] = 0.0
    if parameter == "degradation":
        if v[0] < 0.0 or v[-1] > 1.0:
            raise ParameterError(f"degradation fraction must lie in [0, 1] (0: failed damper, 1: "
                                 f"healthy), got {v[0]:g} to {v[-1]:g}")
        k = rotor.check_blade(blade) - 1
        D = np.repeat(base[None, :], v.size, axis=0)
        D[:, k] = v * base[k]
        return D
    if parameter == "lag_damping":
        if v[0] < 0.0:
            raise ParameterError(f"lag damping must be >= 0 [N m s/rad], got {v[0]:g}")
        D = np.repeat(np.ones_like(base)[None, :], v.size, axis=0) * v[:, None]
    else:
        a0 = float(rotor.blade.damper_arm)
        if v[0] <= 0.0:
            raise ParameterError(f"damper arm must be > 0 [m], got {v[0]:g}")
        D = base[None, :] * (v[:, None] / a0) ** 2
    D[:, failed] = 0.0
    return D


#: Azimuth nodes at which a rotor's coefficients are evaluated at least (coarser grids are
#: every k-th node of it): 4 x 512, the step count the default tolerances need for Hammond's.
_MIN_NODES = 2048


def _basis(rotor, nodes: int):
    """Coefficient nodes of the undamped rotor and each blade's damper column.

    Returns ``B`` (nodes, 3, r, n) (lower half of ``A0, A1, A2``), ``G``
    (nodes, N, r) and ``cols`` (N,): ``A0 += sum_k c_k G_k`` in column
    ``cols[k]``.  Checked: the dampers enter nowhere else.  Evaluated once on
    a fine grid (at least :data:`_MIN_NODES`); a coarser grid that divides it
    is a slice of it.
    """
    try:
        fine = _basis_fine(rotor, _fine_nodes(nodes))
    except TypeError:  # unhashable rotor
        fine = _basis_eval(rotor, _fine_nodes(nodes))
    B, G, cols = fine
    k = B.shape[0] // nodes
    if k == 1:
        return fine
    return np.ascontiguousarray(B[::k]), np.ascontiguousarray(G[::k]), cols


def _fine_nodes(nodes: int) -> int:
    nodes = int(nodes)
    if nodes < 1:
        raise ParameterError(f"azimuth nodes must be >= 1, got {nodes}")
    fine = max(nodes, _MIN_NODES)
    return fine if fine % nodes == 0 else nodes


@functools.lru_cache(maxsize=4)
def _basis_fine(rotor, nodes: int):
    return _basis_eval(rotor, nodes)


def _first_order_grid(rotor, psi: np.ndarray) -> np.ndarray:
    """``A(Omega, psi) = A0 + Omega A1 + Omega^2 A2`` on the azimuths ``psi``, (m, 3, 2n, 2n).

    The same first-order form as :class:`~liquidamp.analysis.stability.ground_resonance.
    _RotorCoefficients`, evaluated at once on the whole grid from the rotor's
    first-harmonic matrices (:meth:`GroundResonanceRotor.harmonic_second_order`
    at Omega = 0, 1, 2; exact: M does not depend on Omega, C is linear and K
    quadratic in it); checked against it at two azimuths.
    """
    c, s = np.cos(psi)[:, None, None], np.sin(psi)[:, None, None]
    H = [rotor.harmonic_second_order(w) for w in (0.0, 1.0, 2.0)]
    M = H[0][0] + H[0][1] * c + H[0][2] * s
    CK = [[h[3] + h[4] * c + h[5] * s, h[6] + h[7] * c + h[8] * s] for h in H]
    Minv = np.linalg.inv(M)
    n = M.shape[1]
    A = np.zeros((psi.size, 3, 2 * n, 2 * n))
    A[:, 0, :n, n:] = np.eye(n)
    for k in range(2):  # 0: C, 1: K
        X0, X1, X2 = CK[0][k], CK[1][k], CK[2][k]
        c2 = 0.5 * (X2 - 2.0 * X1 + X0)
        for j, X in enumerate((X0, X1 - X0 - c2, c2)):
            if k == 0:
                A[:, j, n:, n:] = -Minv @ X
            else:
                A[:, j, n:, :n] = -Minv @ X
    probe = [0, psi.size // 3] if psi.size > 1 else [0]
    ref = _RotorCoefficients(rotor)._evaluate(psi[probe])
    if not np.allclose(A[probe], ref, rtol=1e-10, atol=1e-10 * np.abs(ref).max()):
        raise ConvergenceError("the rotor's harmonic matrices do not reproduce its periodic "
                               "coefficients; the map kernel does not apply")
    return A


def _basis_eval(rotor, nodes: int):
    N = rotor.n_blades
    psi = np.arange(nodes) * (2.0 * math.pi / nodes)
    A_zero = _first_order_grid(rotor.with_lag_dampers([0.0] * N), psi)
    A_one = _first_order_grid(rotor.with_lag_dampers([1.0] * N), psi)
    n = A_zero.shape[-1]
    r0 = n // 2
    want = np.zeros((n, n))
    want[:r0, r0:] = np.eye(r0)
    if not (np.all(A_zero[:, 0, :r0] == want[:r0]) and np.all(A_zero[:, 1:, :r0] == 0.0)):
        raise ConvergenceError("rotor coefficients are not in second-order form")
    dA = A_one - A_zero
    cols = r0 + np.arange(N)
    G = np.ascontiguousarray(np.transpose(dA[:, 0, r0:, :][:, :, cols], (0, 2, 1)))
    rest = dA.copy()
    rest[:, 0, r0:, cols] = 0.0
    if np.any(np.abs(rest) > 1e-12 * max(np.abs(dA).max(), 1.0)):
        raise ConvergenceError("lag dampers enter the rotor other than as blade lag rate "
                               "damping; the map kernel does not apply")
    B = np.ascontiguousarray(A_zero[:, :, r0:, :])
    return B, G, cols.astype(np.int64)


def _points(rotor, W, D, N, parallel: bool) -> np.ndarray:
    """Largest real part [1/s] of the points (W[i] [rad/s], dampers D[i])."""
    from liquidamp.analysis.stability._map_kernel import monodromies, monodromies_parallel

    B, G, cols = _basis(rotor, 4 * N)
    W = np.ascontiguousarray(W, dtype=float)
    D = np.ascontiguousarray(D, dtype=float)
    run = monodromies_parallel if parallel else monodromies
    Phi = run(B, G, cols, W, D, int(N))
    if not np.all(np.isfinite(Phi)):
        raise ConvergenceError("map monodromy integration produced non-finite values")
    rho = np.max(np.abs(np.linalg.eigvals(Phi)), axis=1)
    if np.any(rho == 0.0):
        raise ConvergenceError("a Floquet multiplier is exactly zero: the monodromy is singular")
    return np.log(rho) * W / (2.0 * math.pi)


def _rows(item) -> np.ndarray:
    """Task of an executor: ``(rotor, W, dampers (k, N), steps)`` -> (k, n_W) [1/s]."""
    rotor, W, D, N = item
    k = D.shape[0]
    return _points(rotor, np.tile(W, k), np.repeat(D, W.size, axis=0), N,
                   parallel=False).reshape(k, W.size)


def _choose_steps(rotor, W, D, opts: FloquetOptions, min_steps: int = 64,
                  max_steps: int = 8192) -> int:
    """Coarse step count by the error control of :func:`batched_monodromy` on rows ``D``."""
    from liquidamp.analysis.stability._map_kernel import monodromies_parallel

    Wp = np.tile(W, D.shape[0])
    Dp = np.repeat(D, W.size, axis=0)

    def R(N):
        B, G, cols = _basis(rotor, 4 * N)
        return monodromies_parallel(B, G, cols, Wp, Dp, N)

    N = int(min_steps)
    R1 = R(N)
    while True:
        R2 = R(2 * N)
        err = np.max(np.abs(R2 - R1), axis=(1, 2)) / 31.0
        scale = np.max(np.abs(R2), axis=(1, 2))
        if np.all(err <= opts.atol + opts.rtol * np.maximum(scale, 1.0)):
            return 2 * N
        if 4 * N > max_steps or not np.all(np.isfinite(err)):
            raise ConvergenceError(
                f"map monodromy: error estimate {float(np.nanmax(err)):.3g} above tolerance with "
                f"{4 * N} steps per revolution")
        N *= 2
        R1 = R2


def ground_resonance_map(rotor, Omega, parameter: str, values, *, blade: int = 1,
                         inoperative=(), options: MapOptions | None = None,
                         neutral_tol: float = 1e-6) -> StabilityMap:
    """Largest Floquet exponent real part over rotor speed x a lag-damper parameter.

    Parameters
    ----------
    rotor : GroundResonanceRotor
        With its viscous lag dampers (``blade_damping``).
    Omega : array
        Rotor speeds > 0 [rad/s], strictly increasing.
    parameter : {"degradation", "lag_damping", "arm"}
        See the module notes; :data:`PARAMETERS` gives the units.
    values : array
        Strictly increasing parameter values [unit of ``parameter``].
    blade : int
        Degraded blade (1-based) for ``degradation``.
    inoperative : tuple of int
        Blades whose damper has failed, at every value.
    options : MapOptions, optional
    neutral_tol : float
        A largest real part up to this is neutral, not unstable [1/s].

    Returns
    -------
    StabilityMap

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    >>> m = ground_resonance_map(load_rotor("hammond1974"), rpm_to_rad_s([150.0, 250.0]),
    ...                          "degradation", [0.0, 1.0], options=MapOptions(steps=64))
    >>> m.max_real_part.shape, bool(m.max_real_part[0, 1] > 0 > m.max_real_part[1, 1])
    ((2, 2), True)
    """
    t0 = time.perf_counter()
    opts = options or MapOptions()
    W = np.atleast_1d(np.asarray(Omega, dtype=float))
    if W.ndim != 1 or W.size == 0 or not np.all(np.isfinite(W)) or np.any(W <= 0.0):
        raise ParameterError(f"rotor speeds must be finite and > 0 [rad/s] (Floquet period "
                             f"2 pi/Omega), got {np.asarray(Omega).tolist()}")
    if W.size > 1 and np.any(np.diff(W) <= 0.0):
        raise ParameterError("rotor speeds must be strictly increasing [rad/s]")
    if not neutral_tol >= 0.0:
        raise ParameterError(f"neutral_tol must be >= 0 [1/s], got {neutral_tol!r}")
    D = map_dampers(rotor, parameter, values, blade=blade, inoperative=inoperative)
    v = np.atleast_1d(np.asarray(values, dtype=float))
    ex = opts.executor
    if ex is not None and ex != "serial" and not hasattr(ex, "submit"):
        raise ParameterError(f"executor must be None, 'serial' or have a submit() method, got "
                             f"{type(ex).__name__}")
    probe = np.unique(np.linspace(0, W.size - 1, min(W.size, 51)).round().astype(int))
    N = opts.steps or _choose_steps(rotor, W[probe], D[sorted({0, D.shape[0] - 1})],
                                    opts.floquet or FloquetOptions())
    N = int(N)
    from liquidamp.analysis.stability.parallel import _Progress

    if ex is None or ex == "serial":
        bar = _Progress(W.size * v.size, opts.progress if callable(opts.progress)
                        else bool(opts.progress), "map")
        Wp, Dp = np.tile(W, v.size), np.repeat(D, W.size, axis=0)
        out = np.empty(Wp.size)
        step = int(opts.chunk_points)
        for i in range(0, Wp.size, step):
            out[i:i + step] = _points(rotor, Wp[i:i + step], Dp[i:i + step], N,
                                      parallel=ex is None)
            bar.update(min(step, Wp.size - i))
        bar.close()
        grid = out.reshape(v.size, W.size)
        route = "threads" if ex is None else "serial"
    else:
        from liquidamp.analysis.stability.parallel import map_batched

        prog = opts.progress
        rows = map_batched(_rows, [(rotor, W, D[i:i + 1], N) for i in range(v.size)],
                           executor=ex, min_task_seconds=opts.min_task_seconds,
                           progress=(lambda n: prog(n * W.size)) if callable(prog) else prog)
        grid = np.concatenate(rows, axis=0)
        route = f"executor {type(ex).__name__}"
    note = (f"largest real part of the Floquet exponents (periodic rotating-frame model, "
            f"classical RK4 with {N} and {2 * N} steps per revolution, Richardson-extrapolated); "
            f"parameter {parameter} [{PARAMETERS[parameter]}]"
            + (f" of blade {blade}'s damper" if parameter == "degradation" else "")
            + (f"; inoperative dampers {list(inoperative)}" if inoperative else ""))
    return StabilityMap(rotor.name, W, parameter, PARAMETERS[parameter], v, grid, D, N,
                        time.perf_counter() - t0, note, float(neutral_tol), route)
