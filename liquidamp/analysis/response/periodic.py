"""Periodic steady state by shooting: a thin, documented front to :mod:`liquidamp.coupled.periodic`.

The numerics (Newton shooting on the one-period map with the sealed device's
invariants held, and the route that marches first and shoots where the march
stalls) live in :mod:`liquidamp.coupled.periodic`, where
:func:`liquidamp.coupled.testrig.steady_state` uses them.  This module keeps the
shooting-only entry point :func:`periodic_orbit` and re-exports the invariants
and level-set helpers for the analyses that use them
(:mod:`liquidamp.analysis.stability.forced_orbit`, the dual-frequency harmonic
balance).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (3), (10).
.. [2] R. Seydel, Practical Bifurcation and Stability Analysis, 3rd ed.,
   Springer 2010, Ch. 7 (shooting for periodic solutions).
"""

from __future__ import annotations

from liquidamp.coupled.invariants import invariants, project_level_set
from liquidamp.coupled.periodic import ShootingOptions, state_swing
from liquidamp.coupled.testrig import DeviceResponse, steady_state
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, check_choice
from liquidamp.structure.testmachine import HarmonicStroke

__all__ = ["periodic_orbit", "invariants", "project_level_set", "state_swing", "METHODS"]

#: Solution methods of :func:`periodic_orbit`.
METHODS = ("shooting",)


def periodic_orbit(model, params: DeviceParams, stroke: HarmonicStroke, options=None,
                   method: str = "shooting", *, x0=None, tol: float | None = None,
                   max_iter: int = 25) -> DeviceResponse:
    """Periodic steady state under a harmonic stroke by shooting alone (no transient march).

    ``steady_state(model, params, stroke, options=options, x0=x0, route="shooting",
    shooting=ShootingOptions(tol, max_iter))``: one marched period, then Newton on the
    one-period map with the invariants of ``x0`` held
    (:mod:`liquidamp.coupled.periodic`).  :func:`liquidamp.coupled.testrig.steady_state`
    with its default ``route="auto"`` marches first and shoots only where needed.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model.
    params : DeviceParams
        Device parameters.
    stroke : HarmonicStroke
        Excitation.
    options : SolverOptions, optional
        Tolerances and engine of every one-period run.
    method : {"shooting"}
        Solution method.
    x0 : array, optional
        Starting state; its invariants select the orbit (default: rest at ``p0``).
    tol : float, optional
        Periodicity residual and invariant gap accepted [-] (default
        ``options.steady_tol``).
    max_iter : int
        Largest number of iterations (Newton steps and marched periods).

    Returns
    -------
    DeviceResponse
        One period, ``status = "steady"``, ``residual`` the periodicity residual
        max_i |x_i(T) - x_i(0)| / scale_i, ``cycles`` the one-period runs spent.

    Raises
    ------
    ConvergenceError
        If the iteration does not reach ``tol`` within ``max_iter`` steps (the
        iterations, the last residual and ``tol``).
    ParameterError, PressureError
        As :func:`~liquidamp.coupled.testrig.steady_state`.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.options import SolverOptions
    >>> r = periodic_orbit("full", preset("inerter"), HarmonicStroke(0.001, 3.0),
    ...                    SolverOptions(engine="compiled"))
    >>> r.residual < 1e-6, r.cycles < 40  # one-period runs (a march needs 12 cycles)
    (True, True)
    """
    check_choice("periodic-orbit method", method, METHODS)
    if not isinstance(stroke, HarmonicStroke):
        raise ParameterError("periodic_orbit needs a HarmonicStroke")
    return steady_state(model, params, stroke, options=options, x0=x0, route="shooting",
                        shooting=ShootingOptions(tol=tol, max_iter=max_iter))
