"""Profile likelihood of a fitted parameter the records hardly determine; a restart from its
minimum.

A least-squares fit stops where the gradient and the step vanish to its tolerance.  Along a
direction the records hardly determine (two parameters that trade against each other) the
objective is nearly flat, the fit stops wherever it arrives, and its linearized standard
error (``s^2 (J^T J)^-1``) says only that the direction is flat, not where along it the
minimum lies nor how far the data allow it to go.  The *profile* answers both [1]_: the
parameter theta is held at each value of a grid and every other fitted parameter refitted;
the profile cost

    C_p(theta) = min over the others of C(theta, others)

is the fit's own objective (C = RSS / 2 in the calibration's scaling) along the valley.
Its minimum is the least-squares (for Gaussian noise, maximum-likelihood) estimate whatever
the start, and the set where the likelihood ratio statistic

    D(theta) = 2 (C_p(theta) - min C_p) / s^2,    s^2 = 2 C_min / (N - k) x N / N_eff

stays below the chi-square(1) quantile 3.84 is the 95 % profile-likelihood interval, valid
where the linearized interval is not (N / N_eff: the residual's correlation inflation,
:func:`~liquidamp.analysis.measured.selection.correlation_inflation`).

:func:`profile_restart` scans the parameter (fitted in log space) on a grid of factors of
10^(1/4) about the fit's value, each point refitted from its neighbour's optimum (a
continuation along the valley), outward on each side while D stays below 3.84 and within a
decade of the fitted value (the fit's own start came from a linearized estimate; a decade
either way covers what the start could have missed), and beyond the decade while the cost
still falls there (up to four decades: the minimum is bracketed before it is taken); it then
halves the step about the least cost twice (the valley's floor is flat: a free fit started a
grid step away stops where it arrives) and refits every parameter from the least cost where
that is lower than the fit.  It reports the profile and the interval, open on a side where
the scan ended with D still below 3.84: there the records do not bound the parameter, and
the report says so rather than quoting a standard error.

Why it matters (the independent record ``d03_elastomer``: a spring k_e = 20 kN/m in
parallel with a Maxwell branch k_m = 40 kN/m, c_m = 1.82 kN s/m, beside a Device B channel;
one 2 Hz, 3.5 mm calibration record whose stroke carries a 1 % third harmonic): a smaller
k_e with a slower Maxwell branch (larger c_m) gives the same stiffness at 2 Hz, and the
force at the stroke's 6 Hz harmonic (1.8 N of elastomer force) is the only place the branch's
frequency law shows; the fluid's losses and air ratios absorb most of the difference there.
The fit started from the diagnosis's probe (k_e = 1.5 kN/m) stopped at 3.1 kN/m (stderr
28 kN/m, held-out 0.127); the profile's minimum is at 20 kN/m (held-out 0.005), but k_e =
0.3 kN/m lies only D = 1.7 above it: the record does not bound k_e below, and above only
by the elastomer's storage stiffness at 2 Hz (D = 120 at 31 kN/m).  On records made with
this toolkit's own model at the same noise, the profile's minimum scatters from 3 to 25 kN/m
over noise seeds with a 1 % harmonic; with a 10 % harmonic the interval closes to +-15 %
(D grows with the harmonic's amplitude squared).

References
----------
.. [1] D. J. Venzon, S. H. Moolgavkar, "A method for computing profile-likelihood-based
   confidence intervals", J. R. Stat. Soc. C 37(1), 1988.
.. [2] D. M. Bates, D. G. Watts, Nonlinear Regression Analysis and Its Applications, Wiley,
   1988, Ch. 6 (profile t plots).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.fit_spec import FitSpec
from liquidamp.analysis.measured.selection import correlation_inflation
from liquidamp.errors import ConvergenceError, ParameterError, PressureError, check_positive

__all__ = ["Profile", "profile_restart", "undetermined_parameter", "PROFILE_LEVEL",
           "PROFILE_STEP", "PROFILE_SPAN", "PROFILE_REACH"]

#: Chi-square(1) quantile at 95 %: the likelihood-ratio bound of the profile interval [-].
PROFILE_LEVEL = 3.841
#: Grid factor of the profile scan, 10^(1/4) [-].
PROFILE_STEP = 10.0 ** 0.25
#: Factor scanned from the fitted value on each side [-] (further while the cost still falls).
PROFILE_SPAN = 10.0
#: Spans the scan may go on a side while the profile cost still falls there [-].
PROFILE_REACH = 4


@dataclass(frozen=True)
class Profile:
    """The profile of one fitted parameter (module docstring).

    Attributes
    ----------
    name : str
        The parameter (``"effect.key"`` or a device multiplier).
    fitted : float
        Its value in the fit that was profiled [SI or -].
    values : tuple of float
        The grid, ascending (the fitted value included) [SI or -].
    costs : tuple of float
        Profile cost at each grid value (the calibration's cost, RSS / 2 in its scaling;
        inf where the refit could not be run) [-].
    s2 : float
        Residual variance of the profile's minimum in the cost's scaling, inflated by
        N / N_eff [-].
    best : float
        The grid value of least cost [SI or -].
    interval : (float, float)
        Outer bounds of the 95 % profile interval, D = 2 (C_p - min) / s^2 <=
        :data:`PROFILE_LEVEL`: on each side the first grid value where D exceeds the level,
        or the end of the scan where it does not [SI or -].
    open_low, open_high : bool
        True where the scan ended (a decade from the fitted value, or a bound) with D
        still below the level: the records do not bound the parameter on that side.
    restarted : bool
        Whether the fit was restarted from the profile's minimum and that fit kept.
    """

    name: str
    fitted: float
    values: tuple
    costs: tuple
    s2: float
    best: float
    interval: tuple
    open_low: bool
    open_high: bool
    restarted: bool = False

    @property
    def deviance(self) -> tuple:
        """D = 2 (C_p - min C_p) / s^2 at each grid value [-]."""
        c = np.asarray(self.costs, float)
        return tuple(float(x) for x in 2.0 * (c - np.min(c)) / self.s2)

    @property
    def determined(self) -> bool:
        """Whether the records bound the parameter on both sides within the scan."""
        return not (self.open_low or self.open_high)

    def describe(self) -> str:
        """One line: the minimum, the 95 % interval (open sides said) and the scan.

        Examples
        --------
        >>> p = Profile("elastomer.parallel_stiffness_N_per_m", 3e3, (3e3, 1e4, 2e4, 3e4),
        ...             (7.0, 6.9, 6.8, 9.0), 0.1, 2e4, (3e3, 3e4), True, False)
        >>> print(p.describe())
        elastomer.parallel_stiffness_N_per_m: profile minimum 2e+04 (fit was at 3000); 95 % \
profile interval within [below 3000, 3e+04] (the records do not bound it below)
        """
        lo, hi = self.interval
        low = f"below {lo:.4g}" if self.open_low else f"{lo:.4g}"
        high = f"above {hi:.4g}" if self.open_high else f"{hi:.4g}"
        sides = [s for s, o in (("below", self.open_low), ("above", self.open_high)) if o]
        tail = (f" (the records do not bound it {' or '.join(sides)})" if sides else "")
        return (f"{self.name}: profile minimum {self.best:.4g} (fit was at {self.fitted:.4g}); "
                f"95 % profile interval within [{low}, {high}]{tail}")

    def as_dict(self) -> dict:
        """JSON-ready."""
        return {"parameter": self.name, "fitted": self.fitted, "best": self.best,
                "interval": list(self.interval), "open_low": self.open_low,
                "open_high": self.open_high, "restarted": self.restarted,
                "values": list(self.values), "costs": list(self.costs),
                "deviance": list(self.deviance), "level": PROFILE_LEVEL,
                "description": self.describe()}


def undetermined_parameter(result, names) -> str:
    """The parameter among ``names`` that ``result`` determines least ('' when none is
    undetermined): flagged with a standard error above its value, fitted in log space and
    not at a bound; of several, the largest relative standard error."""
    flags = getattr(result, "flags", None)
    if flags is None:
        return ""
    at = result.at_bounds()
    cand = [(se / abs(v), n) for n, (v, se) in flags.undetermined.items()
            if n in names and n not in at and v != 0 and result.spec[n].log]
    return max(cand)[1] if cand else ""


def _values(result) -> dict:
    return {q.name: q.value for q in result.spec.parameters}


def _s2(result) -> float:
    n, k = result.n_samples, len(result.varying)
    res = [np.asarray(r, float) for r in result.residuals("calibration")]
    return 2.0 * result.cost / max(n - k, 1) * correlation_inflation(res)


def profile_restart(result, name: str, fit, *, step: float = PROFILE_STEP,
                    span: float = PROFILE_SPAN, level: float = PROFILE_LEVEL,
                    refine: int = 2):
    """Profile ``name`` in ``result`` and restart the fit from the profile's minimum.

    Parameters
    ----------
    result : CalibrationResult
        A converged fit in which ``name`` varies (fitted in log space).
    name : str
        The parameter to profile.
    fit : callable
        ``fit(spec) -> CalibrationResult``: the calibration of ``result``'s records, device
        and effects under ``spec``, from the spec's values (e.g. ``calibrate(...,
        start="spec")``).
    step : float
        Grid factor (> 1) [-].
    span : float
        Largest factor from the fitted value on each side (>= step) [-].
    level : float
        Bound on D = 2 (C_p - min C_p) / s^2 of the interval and of the scan [-].
    refine : int
        Halvings of the step about the least cost after the scan (two points each) [-].

    Returns
    -------
    (CalibrationResult, Profile)
        The restart from the profile's minimum where its cost is lower than ``result``'s,
        else ``result``; and the profile (``restarted`` says which).

    Raises
    ------
    ParameterError
        ``name`` not varied in log space by ``result``, or bad ``step``/``span``/``level``.
    """
    check_positive("profile step - 1", step - 1.0, "")
    check_positive("profile level", level, "")
    if not span >= step:
        raise ParameterError(f"profile span must be at least the step {step:g}, got {span!r}")
    if name not in result.varying or not result.spec[name].log:
        raise ParameterError(f"profile: {name!r} is not fitted in log space by this result "
                             f"(varying: {', '.join(result.varying)})")
    p = result.spec[name]
    v0 = float(result.values[name])
    s2 = _s2(result)  # the scan's stopping rule (the interval uses the profile's minimum)
    fixed = FitSpec(tuple(q.replace(vary=False) if q.name == name else q
                          for q in result.spec.parameters))
    points = {v0: (result.cost, result)}
    n_side = int(math.floor(math.log(span) / math.log(step) + 1e-9))
    for direction in (+1.0, -1.0):
        prev, falling = result, False
        for i in range(1, PROFILE_REACH * n_side + 1):
            v = v0 * step ** (direction * i)
            if not p.min <= v <= p.max:
                break
            if i > n_side and not falling:
                break  # past the span, and the cost no longer falls on this side
            spec = fixed.with_values({**_values(prev), name: v})
            try:
                r = fit(spec)
            except (ConvergenceError, ParameterError, PressureError):
                points[v] = (math.inf, None)
                break
            falling = r.cost < min(c for c, _ in points.values())
            points[v] = (r.cost, r)
            prev = r
            if 2.0 * (r.cost - min(c for c, _ in points.values())) / s2 > level:
                break
    # the valley's floor between grid values: halve the step about the least cost twice
    # (the resolution 10^(1/16), 15 %), each point refitted from the least one's optimum
    h = math.log(step)
    for _ in range(refine):
        h *= 0.5
        v_best = min(points, key=lambda v: points[v][0])
        seed = points[v_best][1]
        for direction in (+1.0, -1.0):
            v = v_best * math.exp(direction * h)
            if not p.min <= v <= p.max or v in points:
                continue
            try:
                r = fit(fixed.with_values({**_values(seed), name: v}))
            except (ConvergenceError, ParameterError, PressureError):
                continue
            points[v] = (r.cost, r)
    out, restarted = result, False
    i_best = min(points, key=lambda v: points[v][0])
    if i_best != v0:
        seed = points[i_best][1]
        free = FitSpec(tuple(q.replace(vary=True) if q.name == name else q
                             for q in seed.spec.parameters))
        try:
            r = fit(free.with_values(_values(seed)))
        except (ConvergenceError, ParameterError, PressureError):
            r = None
        if r is not None and name in r.varying and r.cost < result.cost:
            out, restarted = r, True
            points.setdefault(float(r.values[name]), (r.cost, r))
    values = sorted(points)
    costs = [points[v][0] for v in values]
    best_v = min(values, key=lambda v: points[v][0])
    s2 = _s2(points[best_v][1])
    dev = [2.0 * (c - points[best_v][0]) / s2 for c in costs]
    inside = [i for i, d in enumerate(dev) if d <= level]
    lo_i, hi_i = min(inside), max(inside)
    # the interval's outer bounds: the first grid value beyond it on each side, or the end of
    # the scan (a decade out, or a bound) where D stays below the level there: open
    open_low, open_high = lo_i == 0, hi_i == len(values) - 1
    lo = values[lo_i] if open_low else values[lo_i - 1]
    hi = values[hi_i] if open_high else values[hi_i + 1]
    prof = Profile(name, v0, tuple(values), tuple(float(c) for c in costs), s2, best_v,
                   (lo, hi), open_low, open_high, restarted)
    return out, prof
