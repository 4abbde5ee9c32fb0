"""Stability margins with confidence: a fitted device's covariance carried to the answers.

A device calibrated against test records (``liquidamp calibrate --save-device``) carries
the fit's covariance of its varied parameters (:class:`FitUncertainty`).  This module
gives, for a rotor on its landing gear (ground resonance) or a typical section (flutter)
with that device as measured, each answer with an interval at a stated confidence:

* the edges of every unstable speed band (roots of the largest real part g(s) = 0);
* the minimum damping ratio zeta = -Re(lambda)/|lambda| over all modes and the speed range
  (Floquet exponents with the frequency resolved against the revolution-averaged
  multiblade system, as :func:`~liquidamp.analysis.stability.damped_stability.rotor_device_floquet`
  gives them; where that resolution changes branch the ratio jumps, so a perturbed
  answer keeps the nominal branch);
* the flutter speed (the first band's lower edge, section only).

Method (``linearized``, the only one here): the delta method with secant sensitivities.
The fit reports standard errors in the space it fitted (log space for positive
quantities: every multiplier, and an effect parameter with a positive lower bound;
:mod:`liquidamp.analysis.measured.calibration`), so the covariance of the device file
(linear, C_ij = s_i s_j r_ij with s_i = v_i sd_i) is taken back to that space,
C_log,ij = C_ij / (v_i v_j), and parameters are perturbed there (a multiplier by
exp(delta)).  Each answer is re-evaluated at +-1 standard deviation along the
principal axes of that covariance (2 p evaluations for p parameters), at the answer's
own point only: an edge moves by -dg/(dg/ds) (implicit-function theorem), the minimum
damping ratio and a band's peak by their value at the fixed optimum (envelope theorem).
The half-width is z sqrt(sum_k delta_k^2), z the normal quantile of the confidence.
Cheap (a few evaluations per answer, so Floquet analyses stay affordable) and exact to
first order; the secant over one standard deviation absorbs mild curvature.  A band
whose peak interval reaches below zero ``may_vanish`` (its edges' intervals are then
not reliable), and a stable hump whose peak interval reaches above zero is reported in
``possible_bands``: a band appearing or disappearing inside the interval is told, not
hidden.  All dampers are taken as copies of the measured one (fully correlated).
Parameter sampling (whole analyses per draw, percentile intervals) is the robust check:
:mod:`liquidamp.analysis.stability.margin_sampling`.

Partial degradation (:func:`degradation_comparison`): one damper keeps a fraction
(1 - f) of its force (f = 0 intact, f = 1 failed; for a viscous damper exactly a
fraction of its damping): periodic coefficients, Floquet theory; beside it the smeared
answer, the loss averaged over all N dampers (each at 1 - f/N: constant coefficients
after the multiblade transformation), and the ratio of their losses of minimum damping
ratio (Gandhi & Whitt [2]: smearing captures 46 % to 55 % of the Floquet loss).

References
----------
.. [1] C. E. Hammond, J. American Helicopter Society 19(4), 14-23, 1974.
.. [2] F. Gandhi, R. Whitt, "Ground resonance with a degraded lag damper",
   VFS Forum 78, 2022.
.. [3] D. H. Hodges, G. A. Pierce, Introduction to Structural Dynamics and
   Aeroelasticity, 2nd ed., 2011, Ch. 5.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize_scalar
from scipy.stats import norm

from liquidamp.analysis.stability.damped_stability import (
    DeviceLTI,
    device_lti,
    rotor_device_eigenvalues,
    rotor_device_floquet,
    section_device_eigenvalues,
)
from liquidamp.coupled.assembly import Device, viscous
from liquidamp.device.effects import with_effects
from liquidamp.device.models import BASES
from liquidamp.errors import ParameterError, check_in_range

__all__ = ["FitUncertainty", "Interval", "Band", "StabilityMargin", "MarginOptions",
           "confidence_z", "ground_resonance_margin", "flutter_margin",
           "degradation_comparison", "DegradationComparison", "host_viscous_device",
           "scaled_lti", "changed_device", "METHOD"]

#: What the intervals are, stated in every JSON.
METHOD = ("linearized (delta method): secant sensitivities at +-1 standard deviation along "
          "the principal axes of the fit's covariance in the fit's own (log) space; band "
          "edges and the flutter speed by the implicit-function theorem, the minimum damping "
          "ratio and band peaks by the envelope theorem; normal quantile")


def confidence_z(confidence: float) -> float:
    """Two-sided normal quantile z of ``confidence`` in (0, 1).

    Examples
    --------
    >>> round(confidence_z(0.95), 4)
    1.96
    """
    check_in_range("confidence", confidence, 1e-6, 1.0 - 1e-9)
    return float(norm.ppf(0.5 + 0.5 * confidence))


@dataclass(frozen=True)
class FitUncertainty:
    """Varied parameters of a fit and their covariance in the fit's own space.

    Attributes
    ----------
    names : tuple of str
        Multipliers [-] (``c1``) or effect parameters ``effect.key`` [SI].
    values : ndarray
        Fitted values (the device file's parameters already hold them).
    log : tuple of bool
        Fitted in log space (every multiplier; an effect parameter with a positive bound).
    covariance : ndarray
        Covariance in the fit space: of log(value) where ``log``, else of the value.
    source : str

    Examples
    --------
    >>> u = FitUncertainty.from_fit({"varied": ["c1"], "values": [2.0], "stderr": [0.2],
    ...                              "covariance": [[0.04]]})
    >>> u.log, float(u.covariance[0, 0])      # sd of log(c1) = 0.2 / 2
    ((True,), 0.01)
    """

    names: tuple
    values: np.ndarray
    log: tuple
    covariance: np.ndarray
    source: str = ""

    @classmethod
    def from_fit(cls, fit: dict, source: str = "") -> FitUncertainty:
        """From a device file's ``[fit]`` table (:class:`liquidamp.device.presets.DeviceFile`).

        The table's covariance is linear (C_ij = s_i s_j r_ij, the fit's stderr being
        v sd_log for a log parameter); it is taken back to the fit space.  ``log`` (a list
        of booleans) says which were log; without it a multiplier (a name without a dot)
        is log and an effect parameter linear.
        """
        names = tuple(fit.get("varied", ()))
        if not names:
            raise ParameterError("the device's [fit] table varies no parameter: no "
                                 "covariance to carry (write it with calibrate --save-device)")
        v = np.asarray(fit["values"], float)
        cov = np.asarray(fit["covariance"], float)
        log = tuple(bool(x) for x in fit.get("log", ["." not in n for n in names]))
        if not np.all(np.isfinite(cov)):
            raise ParameterError(f"the fit's covariance of {', '.join(names)} is not finite "
                                 "(an undetermined parameter): no interval can be stated")
        s = np.where(log, v, 1.0)
        if np.any(s <= 0):
            raise ParameterError("a log-fitted parameter must be > 0, got "
                                 f"{dict(zip(names, v.tolist(), strict=True))}")
        return cls(names, v, log, cov / np.outer(s, s), source or str(fit.get("source", "")))

    def axes(self) -> np.ndarray:
        """Principal axes scaled by their standard deviation (columns) in the fit space."""
        w, U = np.linalg.eigh(0.5 * (self.covariance + self.covariance.T))
        w = np.clip(w, 0.0, None)
        keep = w > 1e-30 * max(float(w.max()), 1e-300)
        return U[:, keep] * np.sqrt(w[keep])

    def apply(self, device: Device, delta) -> Device:
        """``device`` (the fitted one) moved by ``delta`` in the fit space."""
        delta = np.asarray(delta, float)
        if not np.any(delta):
            return device
        mult, eff = {}, {}
        for n, lg, v, d in zip(self.names, self.log, self.values, delta, strict=True):
            new = v * math.exp(d) if lg else v + d
            if "." in n:
                e, k = n.split(".", 1)
                eff.setdefault(e, {})[k] = new
            else:
                mult[n] = new / v
        params = device.params.scaled(**mult) if mult else device.params
        model = device.model
        if eff:
            missing = set(eff) - {e.name for e in model.effects}
            if missing:
                raise ParameterError(f"fit parameter(s) of effect(s) {sorted(missing)} not in "
                                     f"the device model {model.name!r}")
            effects = [e.replace(**eff[e.name]) if e.name in eff else e for e in model.effects]
            model = with_effects(BASES[model.base], *effects)
        return Device(model, params, device.label)


@dataclass(frozen=True)
class Interval:
    """A value and its interval ``[low, high]`` at ``confidence`` (same unit as the value)."""

    value: float
    low: float
    high: float
    std: float = 0.0

    @property
    def half_width(self) -> float:
        """(high - low) / 2."""
        return 0.5 * (self.high - self.low)

    def contains(self, x: float) -> bool:
        """Whether ``x`` lies in [low, high]."""
        return self.low <= x <= self.high

    def scaled(self, factor: float) -> Interval:
        """The interval in another unit (``factor`` > 0)."""
        return Interval(self.value * factor, self.low * factor, self.high * factor,
                        self.std * factor)

    def as_dict(self) -> dict:
        """``value``, ``interval`` [low, high], ``half_width``."""
        return {"value": self.value, "interval": [self.low, self.high],
                "half_width": self.half_width}


@dataclass(frozen=True)
class Band:
    """One unstable band: edges with intervals, its peak real part and whether it may vanish.

    ``start``/``end`` are in the host's speed unit (rad/s or reduced speed); an edge open
    at the range end has a zero-width interval (``open_start``/``open_end``).
    """

    start: Interval
    end: Interval
    open_start: bool
    open_end: bool
    peak: Interval
    peak_at: float
    may_vanish: bool


@dataclass(frozen=True)
class MarginOptions:
    """Knobs of the margin analyses.

    Attributes
    ----------
    confidence : float
        Two-sided confidence of the intervals (default 0.95).
    speed_step : float
        Step of dg/ds relative to the speed range [-] (default 1e-4).
    xtol : float
        Brent tolerance of edges relative to the range [-] (default 1e-9).
    """

    confidence: float = 0.95
    speed_step: float = 1e-4
    xtol: float = 1e-9

    def __post_init__(self):
        confidence_z(self.confidence)
        check_in_range("speed_step", self.speed_step, 1e-9, 1e-2)
        check_in_range("xtol", self.xtol, 1e-14, 1e-3)


@dataclass(frozen=True)
class StabilityMargin:
    """Stability answers of one configuration, each with its interval.

    Attributes
    ----------
    host : str
    speed_name, speed_unit : str
        ``rotor speed``/``rpm`` or ``reduced speed``/``U/(b omega_theta)``.
    to_unit : float
        Factor from the internal speed (rad/s or reduced) to ``speed_unit``.
    speeds, max_real_part, damping_ratio : ndarray
        The nominal grid (internal unit), largest real part [1/s or -] and minimum
        damping ratio [-] at each speed.
    bands : tuple of Band
    min_damping_ratio : Interval
    min_damping_at : float
    flutter_speed : Interval or None
    possible_bands : tuple of (speed, Interval)
        Stable humps whose peak interval reaches above zero.
    confidence : float
    method, note : str
    uncertainty : FitUncertainty or None
    """

    host: str
    speed_name: str
    speed_unit: str
    to_unit: float
    speeds: np.ndarray
    max_real_part: np.ndarray
    damping_ratio: np.ndarray
    bands: tuple
    min_damping_ratio: Interval
    min_damping_at: float
    flutter_speed: Interval | None
    possible_bands: tuple
    confidence: float
    method: str
    note: str
    uncertainty: FitUncertainty | None = field(default=None, repr=False)

    def band_edges(self) -> list[tuple[Interval, Interval]]:
        """Edges of each band in ``speed_unit``."""
        return [(b.start.scaled(self.to_unit), b.end.scaled(self.to_unit)) for b in self.bands]

    def to_dict(self) -> dict:
        """JSON-ready answers (speeds in ``speed_unit``)."""
        u, k = self.speed_unit, self.to_unit
        bands = []
        for b in self.bands:
            s, e = b.start.scaled(k), b.end.scaled(k)
            bands.append({"start": s.value, "end": e.value, "start_interval": [s.low, s.high],
                          "end_interval": [e.low, e.high], "open_start": b.open_start,
                          "open_end": b.open_end, "peak_real_part": b.peak.as_dict(),
                          f"peak_at [{u}]": b.peak_at * k, "may_vanish": b.may_vanish})
        out = {
            "host": self.host, "confidence": self.confidence, "method": self.method,
            f"unstable_ranges [{u}]": bands,
            "min_damping_ratio": {**self.min_damping_ratio.as_dict(),
                                  f"at [{u}]": self.min_damping_at * k},
            "flutter_speed": (None if self.flutter_speed is None else
                              self.flutter_speed.scaled(k).as_dict()),
            "possible_bands": [{f"at [{u}]": s * k, "peak_real_part": p.as_dict()}
                               for s, p in self.possible_bands],
            "note": self.note,
        }
        if self.uncertainty is not None:
            un = self.uncertainty
            out["uncertainty"] = {"source": un.source, "varied": list(un.names),
                                  "values": un.values.tolist(), "log": list(un.log),
                                  "stderr_fit_space": np.sqrt(np.diag(un.covariance)).tolist()}
        return out


# ---------------------------------------------------------------------------
# problems: eigenvalues at (speed, delta)


def scaled_lti(lti: DeviceLTI, factor: float) -> DeviceLTI:
    """``lti`` with its force scaled by ``factor`` in [0, 1] (0: the null placeholder).

    Examples
    --------
    >>> from liquidamp.coupled.assembly import viscous
    >>> float(scaled_lti(device_lti(viscous(100.0)), 0.25).D[0, 1])
    25.0
    """
    check_in_range("damper fraction", factor, 0.0, 1.0)
    if factor == 0.0:
        return lti.null()
    if factor == 1.0:
        return lti
    return DeviceLTI(lti.A, lti.B, lti.C * factor, lti.D * factor, lti.label,
                     f"{lti.kind}, force x{factor:g}")


def host_viscous_device(rotor) -> Device:
    """The rotor's own lag damper as a viscous device on its arm (blades alike) [N s/m].

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> round(host_viscous_device(load_rotor("hammond1974")).params.c, 1)   # 4067.5/0.25^2
    65080.0
    """
    c = set(rotor.blade_damping)
    if len(c) != 1:
        raise ParameterError(f"the rotor's lag dampers differ ({rotor.blade_damping}); give a "
                             "device")
    arm = rotor.blade.damper_arm
    return viscous(c.pop() / arm ** 2, label="viscous")


def changed_device(device: Device, name: str, value: float) -> Device:
    """``device`` with one parameter changed: a multiplier or an effect parameter [SI].

    ``name`` is a device parameter that :meth:`DeviceParams.scaled` takes (``c1``,
    ``inv_gamma1``, ...; ``value`` multiplies it) or ``effect.key`` (``value`` replaces it).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> d = Device("full", preset("reference"))
    >>> round(changed_device(d, "c1", 0.5).params.c1 / d.params.c1, 12)
    0.5
    """
    if not math.isfinite(value) or ("." not in name and value <= 0):
        raise ParameterError(f"changed parameter {name} = {value!r}: a multiplier must be a "
                             "finite number > 0")
    u = FitUncertainty((name,), np.array([1.0 if "." not in name else 0.0]),
                       ("." not in name,), np.zeros((1, 1)))
    if "." in name:
        e, k = name.split(".", 1)
        effects = {x.name: x for x in device.model.effects}
        if e not in effects:
            raise ParameterError(f"changed parameter {name!r}: the device has no effect {e!r} "
                                 f"(it has: {', '.join(effects) or 'none'})")
        model = with_effects(BASES[device.model.base],
                             *[x.replace(**{k: value}) if x.name == e else x
                               for x in device.model.effects])
        return Device(model, device.params, f"{device.label} ({name}={value:g})")
    out = u.apply(device, [math.log(value)])
    return Device(out.model, out.params, f"{device.label} ({name} x{value:g})")


class _Problem:
    """Eigenvalues at (speed, delta), with a cache of linear devices by delta."""

    threshold = 0.0

    def __init__(self, device, uncertainty):
        self.device, self.unc = device, uncertainty
        self._ltis = {}

    def lti(self, delta) -> DeviceLTI:
        key = None if delta is None else tuple(np.round(np.asarray(delta, float), 15))
        if key not in self._ltis:
            dev = self.device if delta is None else self.unc.apply(self.device, delta)
            self._ltis[key] = device_lti(dev)
        return self._ltis[key]

    def g(self, s, delta=None) -> float:
        return float(np.max(self.eig(s, delta).real)) - self.threshold

    def zeta(self, s, delta=None) -> float:
        lam = self.eig(s, delta)
        W = self.branch(s)
        if W and delta is not None and np.any(delta):
            lam = _same_branch(lam, self.eig(s, None), W)
        return _damping_ratio(lam)

    def branch(self, s) -> float:
        """Spacing of a Floquet exponent's frequency branches [1/s] (0: no ambiguity)."""
        return 0.0


class _RotorProblem(_Problem):
    threshold = 1e-6

    def __init__(self, rotor, device, uncertainty, factors, changed=None):
        super().__init__(device, uncertainty)
        self.rotor, self.factors, self.changed = rotor, tuple(factors), changed
        self.symmetric = len(set(self.factors)) == 1 and changed is None

    def eig(self, W, delta=None):
        lti = self.lti(delta)
        if self.symmetric:
            return rotor_device_eigenvalues(self.rotor, float(W), self.device, method="coleman",
                                            lti=scaled_lti(lti, self.factors[0]))
        ltis = [scaled_lti(lti, f) for f in self.factors]
        if self.changed is not None:
            k, dev = self.changed
            dev = dev if delta is None else self.unc.apply(dev, delta)
            ltis[k - 1] = device_lti(dev)
        return rotor_device_floquet(self.rotor, float(W), self.device, blade_ltis=ltis)[0]

    def branch(self, W) -> float:
        return 0.0 if self.symmetric else float(W)


class _SectionProblem(_Problem):
    threshold = 1e-9

    def __init__(self, section, port, device, uncertainty, aero):
        super().__init__(device, uncertainty)
        self.section, self.port, self.aero = section, port, aero

    def eig(self, V, delta=None):
        lam = section_device_eigenvalues(self.section, self.section.speed(float(V)),
                                         {self.port: self.device}, aero=self.aero,
                                         ltis=[self.lti(delta)])
        return lam / self.section.omega_theta


def _same_branch(lam, ref, W: float):
    """Floquet exponents ``lam`` with each frequency moved by a multiple of ``W`` onto the
    branch of the nearest nominal exponent in ``ref`` (a perturbed answer keeps the
    nominal frequency resolution: a damping ratio must not jump by a change of branch)."""
    lam = np.array(lam, complex)
    for i, x in enumerate(lam):
        dim = ref.imag - x.imag
        wrap = dim - W * np.round(dim / W)
        j = int(np.argmin(np.abs(ref.real - x.real) + np.abs(wrap)))
        k = np.round((ref[j].imag - x.imag) / W)
        lam[i] = complex(x.real, x.imag + k * W)
    return lam


def _damping_ratio(lam) -> float:
    lam = np.asarray(lam)
    mag = np.abs(lam)
    keep = mag > 1e-9 * max(float(mag.max()), 1e-300)
    return float(np.min(-lam.real[keep] / mag[keep]))


# ---------------------------------------------------------------------------
# the analysis


def _refine_extremum(f, x, i, sign):
    """Refine an extremum of f (sign +1: max, -1: min) near grid index i; (x*, f*)."""
    lo, hi = x[max(i - 1, 0)], x[min(i + 1, x.size - 1)]
    if hi <= lo:
        return float(x[i]), float(f(x[i]))
    r = minimize_scalar(lambda s: -sign * f(s), bounds=(lo, hi), method="bounded",
                        options={"xatol": 1e-7 * (x[-1] - x[0])})
    best = max([(float(x[i]), sign * float(f(x[i]))), (float(r.x), -float(r.fun))],
               key=lambda t: t[1])
    return best[0], sign * best[1]


def _secants(func, axes):
    """Half-differences (f(+a_k) - f(-a_k)) / 2 along each axis column a_k."""
    return np.array([0.5 * (func(a) - func(-a)) for a in axes.T])


def _interval(value, deltas, z) -> Interval:
    sd = float(math.sqrt(float(np.sum(np.square(deltas))))) if len(deltas) else 0.0
    return Interval(float(value), float(value - z * sd), float(value + z * sd), sd)


def _analyse(problem: _Problem, x, options: MarginOptions, flutter: bool):
    x = np.asarray(x, float)
    if x.size < 2 or np.any(~np.isfinite(x)) or np.any(np.diff(x) <= 0):
        raise ParameterError(f"speeds must hold at least two finite, increasing values, got "
                             f"{x.tolist()}")
    z = confidence_z(options.confidence)
    unc = problem.unc
    axes = unc.axes() if unc is not None else np.zeros((0, 0))
    lams = [problem.eig(s) for s in x]
    g = np.array([float(np.max(lam.real)) for lam in lams]) - problem.threshold
    zeta = np.array([_damping_ratio(lam) for lam in lams])
    span = float(x[-1] - x[0])
    h = options.speed_step * span

    def edge(i):
        return brentq(problem.g, x[i], x[i + 1], xtol=options.xtol * span)

    def edge_interval(e):
        dgds = (problem.g(e + h) - problem.g(e - h)) / (2 * h)
        d = _secants(lambda a: problem.g(e, a), axes) if axes.size else []
        if dgds == 0.0:
            return Interval(e, -math.inf, math.inf, math.inf)
        return _interval(e, -np.asarray(d) / dgds, z)

    bands, possible = [], []
    up = g > 0
    i = 0
    while i < x.size:
        if not up[i]:
            i += 1
            continue
        j = i
        while j + 1 < x.size and up[j + 1]:
            j += 1
        open_s, open_e = i == 0, j == x.size - 1
        a = float(x[0]) if open_s else edge(i - 1)
        b = float(x[-1]) if open_e else edge(j)
        ia = Interval(a, a, a) if open_s else edge_interval(a)
        ib = Interval(b, b, b) if open_e else edge_interval(b)
        k = i + int(np.argmax(g[i:j + 1]))
        sp, gp = _refine_extremum(problem.g, x, k, +1)
        dp = _secants(lambda a_, s=sp: problem.g(s, a_), axes) if axes.size else []
        peak = _interval(gp + problem.threshold, dp, z)
        bands.append(Band(ia, ib, open_s, open_e, peak, sp,
                          bool(peak.low <= problem.threshold)))
        i = j + 1
    # stable humps that could cross zero inside the interval
    if axes.size:
        for k in range(1, x.size - 1):
            if not up[k] and g[k] >= g[k - 1] and g[k] >= g[k + 1]:
                sp, gp = _refine_extremum(problem.g, x, k, +1)
                dp = _secants(lambda a_, s=sp: problem.g(s, a_), axes)
                peak = _interval(gp + problem.threshold, dp, z)
                if peak.high > problem.threshold:
                    possible.append((sp, peak))
    k = int(np.argmin(zeta))
    sz, zv = _refine_extremum(problem.zeta, x, k, -1)
    dz = _secants(lambda a_: problem.zeta(sz, a_), axes) if axes.size else []
    zmin = _interval(zv, dz, z)
    vf = None
    if flutter:
        first = next((b for b in bands if not b.open_start), None)
        if first is not None and (not bands or bands[0] is first):
            vf = first.start
    return x, g + problem.threshold, zeta, tuple(bands), zmin, sz, vf, tuple(possible)


def _margin(host, problem, x, options, flutter, note) -> StabilityMargin:
    options = options or MarginOptions()
    xs, g, zeta, bands, zmin, sz, vf, possible = _analyse(problem, x, options, flutter)
    if flutter:
        name, unit, k = "reduced speed", "U/(b omega_theta)", 1.0
    else:
        name, unit, k = "rotor speed", "rpm", 30.0 / math.pi
    unc = problem.unc
    method = METHOD if unc is not None else "none (no covariance given: zero-width intervals)"
    if flutter and bands and bands[0].open_start:
        note += "; unstable at the lowest speed: flutter speed below the range"
    return StabilityMargin(host, name, unit, k, xs, g, zeta, bands, zmin, sz, vf, possible,
                           options.confidence, method, note, unc)


def ground_resonance_margin(rotor, Omega, device: Device | None = None,
                            uncertainty: FitUncertainty | None = None, *, inoperative=(),
                            degraded: tuple | None = None, changed: tuple | None = None,
                            options: MarginOptions | None = None) -> StabilityMargin:
    """Ground-resonance answers with intervals for a rotor whose lag dampers are ``device``.

    Parameters
    ----------
    rotor : GroundResonanceRotor
        Its ``blade.damper_arm`` [m] mounts the device.
    Omega : array
        Increasing rotor speeds > 0 [rad/s].
    device : Device, optional
        The measured device (default the rotor's own viscous damper).
    uncertainty : FitUncertainty, optional
        The fit's covariance (default none: zero-width intervals).
    inoperative : sequence of int
        Failed blades (1-based).
    degraded : (int, float), optional
        ``(blade, f)``: that damper keeps (1 - f) of its force, f in [0, 1].
    changed : (int, Device), optional
        ``(blade, device)``: that blade carries another device (e.g. a named
        parameter changed), same model.
    options : MarginOptions, optional

    Returns
    -------
    StabilityMargin
        Speeds in rpm at its edges (``to_dict``).

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.analysis.stability.ground_resonance import rpm_to_rad_s
    >>> r = load_rotor("hammond1974")
    >>> m = ground_resonance_margin(r, rpm_to_rad_s([150, 200, 250]))
    >>> m.bands, round(m.min_damping_ratio.value, 4)
    ((), 0.0178)
    """
    device = device or host_viscous_device(rotor)
    N = rotor.n_blades
    factors = [1.0] * N
    for k in inoperative:
        factors[rotor.check_blade(k) - 1] = 0.0
    if degraded is not None:
        k, f = degraded
        check_in_range("degradation fraction", f, 0.0, 1.0)
        factors[rotor.check_blade(k) - 1] *= 1.0 - f
    ch = None
    if changed is not None:
        ch = (rotor.check_blade(changed[0]), changed[1])
    problem = _RotorProblem(rotor, device, uncertainty, factors, ch)
    how = ("multiblade (Coleman) closed loop" if problem.symmetric else
           "Floquet exponents of the periodic closed loop")
    note = (f"{device.label} on every blade through the arm {rotor.blade.damper_arm:g} m, "
            f"force factors {[round(f, 6) for f in factors]}"
            + (f", blade {ch[0]} with {ch[1].label}" if ch else "") + f"; {how}")
    return _margin(rotor.name, problem, Omega, options, False, note)


def flutter_margin(section, speeds, device: Device, uncertainty: FitUncertainty | None = None,
                   *, port: str = "plunge", aero: str = "jones",
                   options: MarginOptions | None = None) -> StabilityMargin:
    """Flutter answers with intervals for a section with ``device`` on ``port`` (p method).

    Parameters
    ----------
    section : TypicalSection
    speeds : array
        Increasing reduced speeds U/(b omega_theta) > 0 [-].
    device : Device
    uncertainty : FitUncertainty, optional
    port : {"plunge", "pitch"}
    aero : str
        State-space aerodynamics (default R. T. Jones').
    options : MarginOptions, optional

    Returns
    -------
    StabilityMargin
        ``flutter_speed`` the lower edge of the first band (None if no band starts in
        the range); damping ratios from p = lambda/omega_theta.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_section
    >>> from liquidamp.coupled.assembly import viscous
    >>> m = flutter_margin(load_section("hodges-pierce"), np.linspace(1.5, 2.5, 11),
    ...                    viscous(1e-9))
    >>> round(m.flutter_speed.value, 4)       # Jones, no device: 2.17036
    2.1704
    """
    problem = _SectionProblem(section, port, device, uncertainty, aero)
    note = f"p method, {aero} aerodynamics, {device.label} on {port}"
    return _margin(section.name, problem, speeds, options, True, note)


@dataclass(frozen=True)
class DegradationComparison:
    """One damper degraded: Floquet (periodic) beside smeared (averaged) answers.

    Attributes
    ----------
    blade : int
    fraction : float
        Fraction f of the damper's force lost [-] (0 intact, 1 failed).
    intact, floquet, smeared : StabilityMargin
    loss_ratio : float
        (zeta_intact - zeta_smeared) / (zeta_intact - zeta_floquet) of the minimum
        damping ratios over the range [-] (NaN-free: None when the Floquet loss is 0).
    """

    blade: int
    fraction: float
    intact: StabilityMargin
    floquet: StabilityMargin
    smeared: StabilityMargin
    loss_ratio: float | None

    def to_dict(self) -> dict:
        """JSON-ready comparison."""
        zi = self.intact.min_damping_ratio.value
        return {"blade": self.blade, "fraction_lost": self.fraction,
                "floquet": self.floquet.to_dict(), "smeared": self.smeared.to_dict(),
                "intact": self.intact.to_dict(),
                "damping_loss": {"floquet": zi - self.floquet.min_damping_ratio.value,
                                 "smeared": zi - self.smeared.min_damping_ratio.value},
                "loss_ratio_smeared_to_floquet": self.loss_ratio,
                "published_loss_ratio": "0.46 (articulated) to 0.55 (hingeless), Gandhi & "
                                        "Whitt, VFS Forum 78, 2022"}


def degradation_comparison(rotor, Omega, device: Device | None = None,
                           uncertainty: FitUncertainty | None = None, *, blade: int = 1,
                           fraction: float = 0.5, options: MarginOptions | None = None
                           ) -> DegradationComparison:
    """One damper at (1 - ``fraction``) of its force: Floquet, smeared and intact answers.

    The smeared rotor has every damper at (1 - fraction/N) (constant coefficients); see
    the module notes.  Arguments as :func:`ground_resonance_margin`.
    """
    check_in_range("degradation fraction", fraction, 0.0, 1.0)
    N = rotor.n_blades
    device = device or host_viscous_device(rotor)
    intact = ground_resonance_margin(rotor, Omega, device, uncertainty, options=options)
    floq = ground_resonance_margin(rotor, Omega, device, uncertainty,
                                   degraded=(blade, fraction), options=options)
    problem = _RotorProblem(rotor, device, uncertainty, [1.0 - fraction / N] * N)
    smeared = _margin(rotor.name, problem, Omega, options, False,
                      f"smeared: every damper at {1 - fraction / N:g} of its force; "
                      "multiblade (Coleman) closed loop")
    zi = intact.min_damping_ratio.value
    lf = zi - floq.min_damping_ratio.value
    ls = zi - smeared.min_damping_ratio.value
    ratio = ls / lf if lf != 0.0 else None
    return DegradationComparison(rotor.check_blade(blade), float(fraction), intact, floq,
                                 smeared, ratio)
