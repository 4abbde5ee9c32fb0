"""Dynamic-stiffness sweeps K*(f; Y): nonlinear first harmonic, linear and equivalent.

* :func:`nonlinear_stiffness` -- the judge: the first harmonic of the
  periodic steady state of a nonlinear model on the test machine
  (:func:`liquidamp.coupled.testrig.steady_state`) at each frequency and
  amplitude.
* :func:`linear_stiffness` -- K(i 2 pi f) of any transfer function, LTI
  system or :class:`~liquidamp.analysis.linear.Linearization` (stroke to force).
* :func:`equivalent_sweep` -- the amplitude-dependent equivalent
  linearization of :mod:`liquidamp.analysis.equivalent` over the same grid.

All share the sine convention of :mod:`liquidamp.analysis.harmonics`
(y = Y sin(w t), K* = F1/Y1; phase 0 deg spring, 90 deg damper, 180 deg
inerter).  Storage stiffness Re K*, loss stiffness Im K*, loss factor
Im K*/Re K*.

Warm start
----------
By default each nonlinear steady state starts from the periodic solution of
the model linearized at rest with the quadratic loss replaced by its
equivalent c_eq at that amplitude (x(0) = x0 + Im X, X the state phasor), projected
onto the invariants of the sealed device (each chamber's density on its
pressure curve, total mass equal to the filling mass), so the march starts
on the same family of periodic orbits as a start from rest and needs fewer
cycles.  ``warm_start=False`` starts from rest.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV and Figs. 7-11.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from liquidamp.analysis.harmonics import DynamicStiffness, dynamic_stiffness
from liquidamp.analysis.linear import Linearization, linearize, tf_frequency_response
from liquidamp.device.fluid import density_constant_bulk, density_gholizadeh
from liquidamp.device.models import get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import LiquidampError, ParameterError, check_choice, check_positive

__all__ = [
    "StiffnessCurve",
    "NonlinearStiffness",
    "EquivalentSweep",
    "linear_stiffness",
    "nonlinear_stiffness",
    "equivalent_sweep",
    "warm_start_state",
]


def _freeze(*arrays):
    for a in arrays:
        a.setflags(write=False)


class _KMixin:
    value: np.ndarray

    @property
    def magnitude(self) -> np.ndarray:
        """|K*| [N/m]."""
        return np.abs(self.value)

    @property
    def phase_deg(self) -> np.ndarray:
        """Phase of K* [deg] in (-180, 180]."""
        return np.degrees(np.angle(self.value))

    @property
    def storage(self) -> np.ndarray:
        """Storage stiffness Re K* [N/m]."""
        return self.value.real

    @property
    def loss(self) -> np.ndarray:
        """Loss stiffness Im K* [N/m]."""
        return self.value.imag

    @property
    def loss_factor(self) -> np.ndarray:
        """Loss factor Im K* / Re K* [-] (inf where Re K* = 0)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.value.real != 0, self.value.imag / self.value.real, np.inf)


@dataclass(frozen=True, eq=False)
class StiffnessCurve(_KMixin):
    """K*(f) along a frequency axis for one model (and amplitude, where it matters).

    Attributes
    ----------
    label : str
        Model or curve name.
    frequency : ndarray
        Frequencies [Hz].
    value : ndarray of complex
        K* [N/m].
    amplitude : float or None
        Stroke amplitude [m] for amplitude-dependent curves, None for linear.
    """

    label: str
    frequency: np.ndarray
    value: np.ndarray
    amplitude: float | None = None

    def __post_init__(self) -> None:
        _freeze(self.frequency, self.value)

    def point(self, i: int) -> DynamicStiffness:
        """The i-th point as a :class:`DynamicStiffness`."""
        return DynamicStiffness(float(self.frequency[i]), float(self.amplitude or 0.0),
                                complex(self.value[i]))

    def as_dict(self) -> dict:
        """JSON-ready: magnitude [N/m] and phase [deg] lists."""
        return {"magnitude [N/m]": self.magnitude.tolist(), "phase [deg]": self.phase_deg.tolist(),
                "storage [N/m]": self.storage.tolist(), "loss [N/m]": self.loss.tolist()}


@dataclass(frozen=True, eq=False)
class NonlinearStiffness(_KMixin):
    """First-harmonic dynamic stiffness of a nonlinear model over (amplitude, frequency).

    Attributes
    ----------
    model : str
        Registered model.
    params : DeviceParams
        Parameters.
    frequency : ndarray
        Frequencies [Hz], shape (nf,).
    amplitude : ndarray
        Stroke amplitudes [m], shape (na,).
    value : ndarray of complex
        K* [N/m], shape (na, nf); NaN only at points listed in ``failures``.
    min_pressure : ndarray
        Lowest chamber pressure over the steady cycle [Pa] (NaN where the
        model has none or the point failed).
    residual : ndarray
        Steady-state residual of each point [-].
    cycles : ndarray of int
        Cycles marched at each point.
    warnings : tuple of str
        Warnings of the steady states, prefixed with the point.
    failures : tuple of str
        Points that raised (only with ``on_error="skip"``), with the reason.
    """

    model: str
    params: DeviceParams
    frequency: np.ndarray
    amplitude: np.ndarray
    value: np.ndarray
    min_pressure: np.ndarray
    residual: np.ndarray
    cycles: np.ndarray
    warnings: tuple[str, ...] = field(default=())
    failures: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        _freeze(self.frequency, self.amplitude, self.value, self.min_pressure, self.residual,
                self.cycles)

    def curve(self, i: int) -> StiffnessCurve:
        """K*(f) at the i-th amplitude."""
        return StiffnessCurve(f"{self.model} Y={self.amplitude[i]:g} m", self.frequency.copy(),
                              self.value[i].copy(), float(self.amplitude[i]))


@dataclass(frozen=True, eq=False)
class EquivalentSweep(_KMixin):
    """Equivalent-linearization K*_eq over (amplitude, frequency).

    Attributes
    ----------
    model : str
        Model linearized.
    frequency, amplitude : ndarray
        Grid [Hz], [m].
    value : ndarray of complex
        K*_eq [N/m], shape (na, nf).
    valid : ndarray of bool
        Validity of each point (see ``EquivalentLinearization.valid``).
    min_pressure : ndarray
        Estimated lowest chamber pressure [Pa].
    warnings : tuple of str
        Warnings, prefixed with the point.
    """

    model: str
    frequency: np.ndarray
    amplitude: np.ndarray
    value: np.ndarray
    valid: np.ndarray
    min_pressure: np.ndarray
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        _freeze(self.frequency, self.amplitude, self.value, self.valid, self.min_pressure)

    def curve(self, i: int) -> StiffnessCurve:
        """K*_eq(f) at the i-th amplitude."""
        return StiffnessCurve(f"{self.model} eq. Y={self.amplitude[i]:g} m",
                              self.frequency.copy(), self.value[i].copy(),
                              float(self.amplitude[i]))


def _frequencies(frequencies_hz) -> np.ndarray:
    f = np.atleast_1d(np.asarray(frequencies_hz, float))
    if f.ndim != 1 or f.size == 0:
        raise ParameterError("frequencies must be a non-empty 1-D list [Hz]")
    for v in f:
        check_positive("frequency", v, "Hz")
    return f


def _amplitudes(amplitudes_m, params: DeviceParams) -> np.ndarray:
    a = np.atleast_1d(np.asarray(amplitudes_m, float))
    if a.ndim != 1 or a.size == 0:
        raise ParameterError("amplitudes must be a non-empty 1-D list [m]")
    for v in a:
        check_positive("amplitude", v, "m")
        if v >= params.stroke_limit:
            raise ParameterError(f"amplitude {v:g} m reaches the chamber end; allowed: "
                                 f"0 < amplitude < {params.stroke_limit:g} m (V0/A_p)")
    return a


def linear_stiffness(system, frequencies_hz, label: str | None = None) -> StiffnessCurve:
    """K*(f) = K(i 2 pi f) of a stroke-to-force linear model.

    Parameters
    ----------
    system : control.TransferFunction, control.StateSpace or Linearization
        SISO from stroke [m] to force [N] (a Linearization uses its force
        output and folds the rate and acceleration inputs into the stroke).
    frequencies_hz : array
        Frequencies [Hz].
    label : str, optional
        Curve label (default the system name).

    Returns
    -------
    StiffnessCurve

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.analysis.linear import maxwell_tf
    >>> p = preset("reference")
    >>> c = linear_stiffness(maxwell_tf(p), [1e-3, 1e4])
    >>> [round(float(x)) for x in c.phase_deg]   # damper at low, spring at high frequency
    [90, 0]
    """
    f = _frequencies(frequencies_hz)
    if isinstance(system, Linearization):
        value = system.frequency_response(f)
        name = system.model
    else:
        if getattr(system, "ninputs", 1) != 1 or getattr(system, "noutputs", 1) != 1:
            raise ParameterError("linear_stiffness needs a SISO system (stroke -> force)")
        value = tf_frequency_response(system, f)
        name = getattr(system, "name", "linear")
    return StiffnessCurve(label or name, f, np.asarray(value, complex))


def warm_start_state(model, params: DeviceParams, frequency_hz: float, amplitude_m: float,
                     lin: Linearization | None = None) -> np.ndarray:
    """Initial state on the linear periodic orbit, projected onto the invariants.

    x(0) = x_rest + Im X for y = Y sin(w t) (X from the linearization at
    rest); for models with densities as states each density is put back on
    its pressure curve (eq. 3 with eq. 2, or exp((p - p0)/B0) for a constant
    bulk modulus), and for mass-conserving models a common pressure shift
    restores the filling mass.  Friction is ignored (it only sets the start).
    Where the linear orbit would take a chamber pressure below 0.2 p0 the
    rest state is returned instead.

    Returns
    -------
    ndarray
        Initial state [state units].

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> p = preset("reference")
    >>> x = warm_start_state("full", p, 5.0, 1e-4)
    >>> m = get_model("full")
    >>> u = (0.0, 0.0, 0.0)
    >>> bool(abs(m.mass(x, u, p) / m.mass(m.initial_state(p, 0.0), u, p) - 1) < 1e-12)
    True
    """
    m = get_model(model)
    p = params
    if m.n_states == 0:
        return np.zeros(0)
    lin = linearize(m, p) if lin is None else lin
    x = lin.x0 + np.imag(lin.state_phasor(frequency_hz, amplitude_m))
    if m.pressures is None:
        return x
    names = m.state_names
    i1, i2 = (names.index("p1"), names.index("p2"))
    if min(x[i1], x[i2]) <= 0.2 * p.p0:
        # the linear orbit would take a chamber near or through zero pressure: start at rest
        return m.initial_state(p, 0.0)
    r1 = names.index("rho1") if "rho1" in names else None
    r2 = names.index("rho2") if "rho2" in names else None

    def density(pr, chamber):
        X0, B0 = (p.X01, p.B01) if chamber == 1 else (p.X02, p.B02)
        if p.bulk_law == "constant":
            return density_constant_bulk(pr, p.rho0, B0, p.p0)
        return density_gholizadeh(pr, p.rho0, p.B_l, X0, p.p0, p.n)

    def shifted(d):
        z = x.copy()
        z[i1] += d
        z[i2] += d
        if r1 is not None:
            z[r1] = density(z[i1], 1)
            z[r2] = density(z[i2], 2)
        return z

    if not m.conserves_mass or m.mass is None:
        return shifted(0.0)
    u0 = (0.0, 0.0, 0.0)
    target = float(m.mass(m.initial_state(p, 0.0), u0, p))
    lo = -0.5 * min(x[i1], x[i2])
    hi = 0.5 * p.p0

    def g(d):
        return float(m.mass(shifted(d), u0, p)) / target - 1.0

    if g(lo) > 0 or g(hi) < 0:
        return m.initial_state(p, 0.0)
    d = brentq(g, lo, hi, xtol=1e-9, rtol=1e-15)
    return shifted(d)


def _warm(m, params: DeviceParams, f: float, Y: float) -> np.ndarray:
    """Warm start from the model linearized with the equivalent loss c_eq (rest bulk)."""
    from liquidamp.analysis.equivalent import equivalent_linearization

    peq = params
    if params.c2 > 0.0 and params.c1 > 0.0:
        kind = "inertial_2state" if params.S_t > 0 else "single_state"
        c_eq = equivalent_linearization(params.replace(friction_N=0.0), f, Y, kind,
                                        bulk="rest").c_eq
        peq = params.replace(c1=c_eq, c2=0.0)
    return warm_start_state(m, params, f, Y, linearize(m, peq))


def nonlinear_stiffness(params: DeviceParams, frequencies_hz, amplitudes_m,
                        model: str = "full", options=None, *, warm_start: bool = True,
                        on_error: str = "raise") -> NonlinearStiffness:
    """First-harmonic K*(f; Y) of ``model`` from its periodic steady state.

    Parameters
    ----------
    params : DeviceParams
        Device (friction included in the force).
    frequencies_hz : array
        Frequencies [Hz].
    amplitudes_m : array
        Stroke amplitudes [m].
    model : str
        Registered model (default the full eq. 10).
    options : SolverOptions, optional
        Passed to :func:`~liquidamp.coupled.testrig.steady_state`.
    warm_start : bool
        Start from the linear periodic orbit (module notes) instead of rest;
        changes the cycle count, not the answer.
    on_error : {"raise", "skip"}
        ``skip`` records a point that raises (e.g. PressureError near
        cavitation) in ``failures`` and leaves NaN there.

    Returns
    -------
    NonlinearStiffness

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> r = nonlinear_stiffness(preset("reference"), [3.0], [1e-3], model="inertial_2state")
    >>> r.value.shape, bool(45 < r.phase_deg[0, 0] < 90)
    ((1, 1), True)
    """
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.structure.testmachine import HarmonicStroke

    if not isinstance(params, DeviceParams):
        raise ParameterError(f"params must be DeviceParams, got {type(params).__name__}")
    m = get_model(model)
    m.check_params(params)
    check_choice("on_error", on_error, ("raise", "skip"))
    f = _frequencies(frequencies_hz)
    a = _amplitudes(amplitudes_m, params)
    value = np.full((a.size, f.size), np.nan, complex)
    pmin = np.full(value.shape, np.nan)
    res = np.full(value.shape, np.nan)
    cyc = np.zeros(value.shape, int)
    warns, fails = [], []
    use_warm = warm_start and m.n_states > 0 and (m.pressures is None or m.conserves_mass)
    for i, Y in enumerate(a):
        for j, fj in enumerate(f):
            x0 = _warm(m, params, float(fj), float(Y)) if use_warm else None
            try:
                r = steady_state(m, params, HarmonicStroke(float(Y), float(fj)),
                                 options=options, x0=x0)
            except LiquidampError as exc:
                if on_error == "raise":
                    raise
                fails.append(f"{fj:g} Hz, {Y:g} m: {exc}")
                continue
            K = dynamic_stiffness(r)
            value[i, j] = K.value
            pmin[i, j] = r.min_pressure if r.min_pressure is not None else math.nan
            res[i, j] = r.residual
            cyc[i, j] = r.cycles
            warns += [f"{fj:g} Hz, {Y:g} m: {w}" for w in r.warnings]
    return NonlinearStiffness(model=m.name, params=params, frequency=f, amplitude=a,
                              value=value, min_pressure=pmin, residual=res, cycles=cyc,
                              warnings=tuple(warns), failures=tuple(fails))


def equivalent_sweep(params: DeviceParams, frequencies_hz, amplitudes_m,
                     model: str = "full", *, bulk: str = "auto") -> EquivalentSweep:
    """Equivalent-linearization K*_eq(f; Y) over a grid (see :mod:`.equivalent`).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> e = equivalent_sweep(preset("reference"), [1.0, 10.0], [1e-3])
    >>> e.value.shape, bool(e.valid.all())
    ((1, 2), True)
    """
    from liquidamp.analysis.equivalent import equivalent_linearization

    f = _frequencies(frequencies_hz)
    a = _amplitudes(amplitudes_m, params)
    value = np.empty((a.size, f.size), complex)
    valid = np.empty(value.shape, bool)
    pmin = np.empty(value.shape)
    warns = []
    name = get_model(model).name
    for i, Y in enumerate(a):
        for j, fj in enumerate(f):
            e = equivalent_linearization(params, float(fj), float(Y), name, bulk=bulk)
            value[i, j] = e.stiffness.value
            valid[i, j] = e.valid
            pmin[i, j] = e.min_pressure
            warns += [f"{fj:g} Hz, {Y:g} m: {w}" for w in e.warnings]
    return EquivalentSweep(model=name, frequency=f, amplitude=a, value=value, valid=valid,
                           min_pressure=pmin, warnings=tuple(warns))
