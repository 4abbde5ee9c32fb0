"""Dynamic-stiffness sweeps K*(f; Y): nonlinear first harmonic, linear and equivalent.

* :func:`nonlinear_stiffness` -- the judge: the first harmonic of the
  periodic steady state of a nonlinear model on the test machine
  (:func:`liquidamp.coupled.testrig.steady_state`) at each frequency and
  amplitude.
* :func:`linear_stiffness` -- K(i 2 pi f) of any transfer function, LTI
  system or :class:`~liquidamp.analysis.response.linear.Linearization` (stroke to force).
* :func:`equivalent_sweep` -- the amplitude-dependent equivalent
  linearization of :mod:`liquidamp.analysis.response.equivalent` over the same grid.

All share the sine convention of :mod:`liquidamp.analysis.response.harmonics`
(y = Y sin(w t), K* = F1/Y1 [N/m]; phase wrapped into (-180, 180] deg: 0 deg
spring, 90 deg damper, 180 deg inerter).  Storage stiffness Re K*, loss
stiffness Im K*, loss factor Im K*/Re K*.  ``to_frd`` gives any curve as a
:class:`control.FrequencyResponseData` (stroke [m] -> force [N], omega in
rad/s); python-control unwraps the phase along frequency where liquidamp
wraps it, so an inerter's 180 deg may read -180 deg there.

Nothing is faked: a nonlinear point that failed holds K* = NaN + i NaN
(never a zero loss stiffness) and a status ``"failed: <reason>"``; an
equivalent point outside the validity of the linearization keeps its value
and a status ``"invalid: <reason>"``.  :meth:`NonlinearStiffness.as_dict` and
:func:`write_stiffness_csv` write ``null`` / an empty cell and the status of
every point; results that carry warnings or failures also issue a
:class:`~liquidamp.errors.LiquidampWarning`.

Engine
------
:func:`nonlinear_stiffness` runs on :data:`STIFFNESS_OPTIONS` unless given
options: the compiled engine (numba) where it is installed, which agrees
with the plain-Python reference to about 1e-7 in |K*| and is about 200x
faster (30 frequencies x 2 amplitudes of the reference design: 54 s with
the Python engine, 0.3 s compiled once the kernels are cached).

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

import csv
import functools
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from liquidamp._compat import renamed
from liquidamp.analysis.response.harmonics import DynamicStiffness, dynamic_stiffness
from liquidamp.analysis.response.linear import Linearization, linearize, tf_frequency_response
from liquidamp.device.fluid import density_constant_bulk, density_gholizadeh
from liquidamp.device.models import check_input_channels, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import (
    LiquidampError,
    LiquidampWarning,
    ParameterError,
    check_choice,
    check_positive,
)
from liquidamp.options import SolverOptions

__all__ = [
    "StiffnessCurve",
    "NonlinearStiffness",
    "EquivalentSweep",
    "linear_stiffness",
    "nonlinear_stiffness",
    "equivalent_sweep",
    "warm_start_state",
    "write_stiffness_csv",
    "STIFFNESS_OPTIONS",
    "PHASE_CONVENTION",
]

PHASE_CONVENTION = ("phase of K* = F1/Y1 in (-180, 180] deg (sine convention y = Y sin(wt)): "
                    "0 deg spring, +90 deg damper, 180 deg inerter; python-control's "
                    "FrequencyResponseData/bode_plot unwrap it along frequency instead")
"""One-line statement of the phase convention, written beside K* in reports."""


def _default_engine() -> str:
    try:
        import numba  # noqa: F401
    except ImportError:  # pragma: no cover - numba is a dependency
        return "python"
    return "compiled"


STIFFNESS_OPTIONS = SolverOptions(engine=_default_engine())
"""Default solver options of :func:`nonlinear_stiffness`: the package defaults with the
compiled engine where numba is installed (module notes, "Engine")."""


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
        """Loss factor Im K* / Re K* [-] (inf where Re K* = 0, NaN at failed points)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.value.real != 0, self.value.imag / self.value.real, np.inf)


def _nan_complex(value) -> np.ndarray:
    """Copy of ``value`` with every non-finite entry NaN + i NaN (a NaN never reads as a zero
    loss or storage stiffness)."""
    v = np.array(value, complex)
    v[~np.isfinite(v)] = complex(math.nan, math.nan)
    return v


def _frd(frequency, value, name: str, what: str):
    """control.FrequencyResponseData of K*(f) from stroke [m] to force [N]; NaN points dropped
    with a warning naming them."""

    f = np.asarray(frequency, float)
    v = np.asarray(value, complex)
    ok = np.isfinite(v)
    if not ok.any():
        raise ParameterError(f"{what}: no finite K* point to build a frequency response from")
    if not ok.all():
        warnings.warn(f"{what}: {int((~ok).sum())} failed point(s) left out of the frequency "
                      f"response (at {', '.join(f'{x:g}' for x in f[~ok])} Hz)",
                      LiquidampWarning, stacklevel=3)
    return _frd_class()(v[ok], 2.0 * math.pi * f[ok], name=name, inputs="stroke",
                        outputs="force")


@functools.cache
def _frd_class():
    """:class:`control.FrequencyResponseData` whose Bode plot wraps the phase by default."""
    import control

    class StiffnessFRD(control.FrequencyResponseData):
        """K*(f) [N/m] from stroke to force; ``plot()`` draws the phase in (-180, 180] deg.

        python-control's own default unwraps the phase and starts it in
        [-360, 0) deg, which draws a damper (+90 deg) at -270 deg; this
        response passes ``wrap_phase=True`` unless told otherwise, so its Bode
        plot shows liquidamp's convention (0 spring, +90 damper, 180 inerter).
        ``control.bode_plot(frd)`` called directly keeps python-control's
        default: give it ``wrap_phase=True``.
        """

        def plot(self, plot_type=None, *args, **kwargs):
            if (plot_type or self.plot_type) in ("bode", None):
                kwargs.setdefault("wrap_phase", True)
            return super().plot(plot_type, *args, **kwargs)

    return StiffnessFRD


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
    status: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "frequency", np.array(self.frequency, float))
        object.__setattr__(self, "value", _nan_complex(self.value))
        if self.status is None:
            st = tuple("ok" if math.isfinite(abs(v)) else "failed" for v in self.value)
            object.__setattr__(self, "status", st)
        else:
            object.__setattr__(self, "status", tuple(str(x) for x in self.status))
        if len(self.status) != self.frequency.size:
            raise ParameterError(f"StiffnessCurve: {len(self.status)} status entries for "
                                 f"{self.frequency.size} frequencies")
        _freeze(self.frequency, self.value)

    def point(self, i: int) -> DynamicStiffness:
        """The i-th point as a :class:`DynamicStiffness`."""
        return DynamicStiffness(float(self.frequency[i]), float(self.amplitude or 0.0),
                                complex(self.value[i]))

    def as_dict(self) -> dict:
        """JSON-ready lists: magnitude [N/m], phase [deg], storage and loss [N/m], status.

        A failed point is ``null`` in every list (never 0) and its ``status``
        says why; the phase convention is :data:`PHASE_CONVENTION`.
        """
        return {"magnitude [N/m]": _clean(self.magnitude), "phase [deg]": _clean(self.phase_deg),
                "storage [N/m]": _clean(self.storage), "loss [N/m]": _clean(self.loss),
                "status": list(self.status)}

    def to_frd(self):
        """K*(f) as a :class:`control.FrequencyResponseData` (stroke [m] -> force [N]).

        Frequencies are given to python-control in rad/s (omega = 2 pi f) and
        the response is K* [N/m].  ``frd.plot()`` draws the Bode phase in
        liquidamp's convention, wrapped into (-180, 180] deg
        (:data:`PHASE_CONVENTION`: a damper at +90 deg); python-control's
        ``bode_plot(frd)`` unwraps it and starts it in [-360, 0) deg unless
        given ``wrap_phase=True`` (the complex values agree either way).
        Failed points (NaN) are left out with a :class:`LiquidampWarning`.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> from liquidamp.analysis.response.linear import maxwell_tf
        >>> c = linear_stiffness(maxwell_tf(preset("reference")), [0.5, 5.0, 50.0])
        >>> frd = c.to_frd()
        >>> bool(np.allclose(frd.frequency_response(2 * np.pi * c.frequency).complex.ravel(),
        ...                  c.value))
        True
        >>> import matplotlib; matplotlib.use("Agg")
        >>> import matplotlib.pyplot as plt
        >>> _ = frd.plot()
        >>> phase = plt.gcf().axes[1].get_lines()[0].get_ydata()
        >>> bool(np.allclose(phase, c.phase_deg))
        True
        >>> plt.close("all")
        """
        return _frd(self.frequency, self.value, self.label, f"curve {self.label!r}")


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
    status : ndarray of str
        ``"ok"`` or ``"failed: <reason>"`` at each point, shape (na, nf).
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
    status: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _nan_complex(self.value))
        if self.status is None:
            st = np.where(np.isfinite(self.value), "ok", "failed").astype(object)
            object.__setattr__(self, "status", st)
        else:
            object.__setattr__(self, "status", np.array(self.status, dtype=object))
        _freeze(self.frequency, self.amplitude, self.value, self.min_pressure, self.residual,
                self.cycles, self.status)

    def curve(self, i: int) -> StiffnessCurve:
        """K*(f) at the i-th amplitude (with each point's status)."""
        return StiffnessCurve(f"{self.model} Y={self.amplitude[i]:g} m", self.frequency.copy(),
                              self.value[i].copy(), float(self.amplitude[i]),
                              tuple(self.status[i]))

    def to_frd(self, i: int = 0):
        """K*(f) at the i-th amplitude as :class:`control.FrequencyResponseData`
        (see :meth:`StiffnessCurve.to_frd`: omega [rad/s], K* [N/m], failed points left out)."""
        return self.curve(i).to_frd()

    def as_dict(self) -> dict:
        """JSON-ready sweep: per amplitude (key ``repr`` of Y [m]) the lists of
        :meth:`StiffnessCurve.as_dict` plus ``min_pressure [Pa]``, ``cycles`` and
        ``residual``; failed points are ``null`` with ``status`` ``"failed: <reason>"``.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> r = nonlinear_stiffness(preset("reference"), [3.0], [1e-3], model="spring")
        >>> d = r.as_dict()["0.001"]
        >>> d["status"], d["phase [deg]"]
        (['ok'], [0.0])
        """
        out = {}
        for i, Y in enumerate(self.amplitude):
            d = self.curve(i).as_dict()
            d["min_pressure [Pa]"] = _clean(self.min_pressure[i])
            d["cycles"] = [int(c) if s == "ok" else None
                           for c, s in zip(self.cycles[i], self.status[i], strict=True)]
            d["residual"] = _clean(self.residual[i])
            out[repr(float(Y))] = d
        return out


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
    status : ndarray of str
        ``"ok"``, or ``"invalid: <reason>"`` where ``valid`` is False (the
        value is kept: it is what the linearization gives, not a result to
        trust), shape (na, nf).
    """

    model: str
    frequency: np.ndarray
    amplitude: np.ndarray
    value: np.ndarray
    valid: np.ndarray
    min_pressure: np.ndarray
    warnings: tuple[str, ...] = field(default=())
    status: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.status is None:
            st = np.where(self.valid, "ok", "invalid").astype(object)
            object.__setattr__(self, "status", st)
        else:
            object.__setattr__(self, "status", np.array(self.status, dtype=object))
        _freeze(self.frequency, self.amplitude, self.value, self.valid, self.min_pressure,
                self.status)

    def curve(self, i: int) -> StiffnessCurve:
        """K*_eq(f) at the i-th amplitude (with each point's status)."""
        return StiffnessCurve(f"{self.model} eq. Y={self.amplitude[i]:g} m",
                              self.frequency.copy(), self.value[i].copy(),
                              float(self.amplitude[i]), tuple(self.status[i]))

    def to_frd(self, i: int = 0):
        """K*_eq(f) at the i-th amplitude as :class:`control.FrequencyResponseData`
        (omega [rad/s], K* [N/m]; invalid points included: check ``status``)."""
        return self.curve(i).to_frd()

    def as_dict(self) -> dict:
        """JSON-ready sweep: per amplitude the lists of :meth:`StiffnessCurve.as_dict` plus
        ``valid`` and ``min_pressure [Pa]``."""
        out = {}
        for i, Y in enumerate(self.amplitude):
            d = self.curve(i).as_dict()
            d["valid"] = [bool(v) for v in self.valid[i]]
            d["min_pressure [Pa]"] = _clean(self.min_pressure[i])
            out[repr(float(Y))] = d
        return out


def _summary(messages, n: int = 2) -> str:
    """The first ``n`` messages and how many more (the result holds them all)."""
    head = "; ".join(messages[:n])
    more = len(messages) - n
    return head + (f"; ... and {more} more (all in the result's warnings/failures)"
                   if more > 0 else "")


def _clean(values) -> list:
    """Floats with NaN/inf as None (JSON null)."""
    return [float(v) if math.isfinite(v) else None for v in np.asarray(values, float).ravel()]


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
    >>> from liquidamp.analysis.response.linear import maxwell_tf
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


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def warm_start_state(model, params: DeviceParams, frequency: float, amplitude: float,
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
    x = lin.x0 + np.imag(lin.state_phasor(frequency, amplitude))
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
    from liquidamp.analysis.response.equivalent import equivalent_linearization

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
        Passed to :func:`~liquidamp.coupled.testrig.steady_state` (default
        :data:`STIFFNESS_OPTIONS`: the compiled engine where numba is installed).
    warm_start : bool
        Start from the linear periodic orbit (module notes) instead of rest;
        changes the cycle count, not the answer.
    on_error : {"raise", "skip"}
        ``skip`` records a point that raises (e.g. PressureError near
        cavitation) in ``failures`` and in ``status`` (``"failed: <reason>"``)
        and leaves K* = NaN + i NaN there.

    Returns
    -------
    NonlinearStiffness

    Warns
    -----
    LiquidampWarning
        When points failed or the steady states carry warnings (the same text
        as ``failures`` and ``warnings``).

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
    check_input_channels(m, (), "a harmonic stroke (the dynamic stiffness)")
    check_choice("on_error", on_error, ("raise", "skip"))
    f = _frequencies(frequencies_hz)
    a = _amplitudes(amplitudes_m, params)
    options = STIFFNESS_OPTIONS if options is None else options
    value = np.full((a.size, f.size), complex(math.nan, math.nan))  # never a fake 0 loss
    pmin = np.full(value.shape, np.nan)
    res = np.full(value.shape, np.nan)
    cyc = np.zeros(value.shape, int)
    status = np.full(value.shape, "ok", dtype=object)
    warns, fails = [], []
    # a warm start from the linearization at rest needs one: an effect without a small-
    # signal model at rest (a drifting one) starts from the march instead
    use_warm = (warm_start and m.n_states > 0 and (m.pressures is None or m.conserves_mass)
                and all(e.small_signal_reason is None for e in getattr(m, "effects", ())))
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
                status[i, j] = f"failed: {type(exc).__name__}: {exc}"
                continue
            K = dynamic_stiffness(r)
            value[i, j] = K.value
            pmin[i, j] = r.min_pressure if r.min_pressure is not None else math.nan
            res[i, j] = r.residual
            cyc[i, j] = r.cycles
            warns += [f"{fj:g} Hz, {Y:g} m: {w}" for w in r.warnings]
    if fails:
        warnings.warn(f"nonlinear_stiffness: {len(fails)} of {value.size} point(s) failed "
                      f"(NaN, status 'failed'): " + _summary(fails), LiquidampWarning,
                      stacklevel=2)
    if warns:
        warnings.warn(f"nonlinear_stiffness: {len(warns)} warning(s): " + _summary(warns),
                      LiquidampWarning, stacklevel=2)
    return NonlinearStiffness(model=m.name, params=params, frequency=f, amplitude=a,
                              value=value, min_pressure=pmin, residual=res, cycles=cyc,
                              warnings=tuple(warns), failures=tuple(fails), status=status)


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
    from liquidamp.analysis.response.equivalent import equivalent_linearization

    f = _frequencies(frequencies_hz)
    a = _amplitudes(amplitudes_m, params)
    value = np.empty((a.size, f.size), complex)
    valid = np.empty(value.shape, bool)
    pmin = np.empty(value.shape)
    status = np.full(value.shape, "ok", dtype=object)
    warns = []
    name = get_model(model).name
    for i, Y in enumerate(a):
        for j, fj in enumerate(f):
            e = equivalent_linearization(params, float(fj), float(Y), name, bulk=bulk)
            value[i, j] = e.stiffness.value
            valid[i, j] = e.valid
            pmin[i, j] = e.min_pressure
            if not e.valid:
                status[i, j] = "invalid: " + ("; ".join(e.warnings) or "outside validity")
            warns += [f"{fj:g} Hz, {Y:g} m: {w}" for w in e.warnings]
    if warns:
        warnings.warn(f"equivalent_sweep: {len(warns)} warning(s): " + _summary(warns),
                      LiquidampWarning, stacklevel=2)
    return EquivalentSweep(model=name, frequency=f, amplitude=a, value=value, valid=valid,
                           min_pressure=pmin, warnings=tuple(warns), status=status)


def write_stiffness_csv(path, linear=(), nonlinear=None, equivalent=None) -> Path:
    """Write K* sweeps as CSV: one row per curve and frequency, with a status column.

    Columns: ``curve``, ``amplitude [m]``, ``frequency [Hz]``, ``magnitude
    [N/m]``, ``phase [deg]`` (:data:`PHASE_CONVENTION`), ``storage [N/m]``,
    ``loss [N/m]``, ``status``.  A failed point has empty value cells and
    ``status`` ``failed: <reason>`` (never a 0); an invalid equivalent point
    keeps its values with ``status`` ``invalid: <reason>``.

    Parameters
    ----------
    path : str or Path
        File to write.
    linear : sequence of StiffnessCurve
        Linear curves (rows ``linear:<label>``).
    nonlinear : NonlinearStiffness, optional
        Rows ``nonlinear:<model>``, one block per amplitude.
    equivalent : EquivalentSweep, optional
        Rows ``equivalent:<model>``.

    Returns
    -------
    Path
        ``path``.

    Examples
    --------
    >>> import tempfile, os
    >>> c = StiffnessCurve("demo", np.array([1.0, 2.0]), np.array([1e5 + 0j, np.nan]),
    ...                    status=("ok", "failed: PressureError: p = 0"))
    >>> path = write_stiffness_csv(os.path.join(tempfile.mkdtemp(), "k.csv"), [c])
    >>> print(path.read_text().splitlines()[2])
    linear:demo,,2,,,,,failed: PressureError: p = 0
    """
    rows = [(f"linear:{c.label}", "", c) for c in linear]
    if nonlinear is not None:
        rows += [(f"nonlinear:{nonlinear.model}", repr(float(Y)), nonlinear.curve(i))
                 for i, Y in enumerate(nonlinear.amplitude)]
    if equivalent is not None:
        rows += [(f"equivalent:{equivalent.model}", repr(float(Y)), equivalent.curve(i))
                 for i, Y in enumerate(equivalent.amplitude)]
    from liquidamp.atomic import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp, tmp.open("w", newline="") as fh:  # whole file or none
        w = csv.writer(fh)
        w.writerow(["curve", "amplitude [m]", "frequency [Hz]", "magnitude [N/m]",
                    "phase [deg]", "storage [N/m]", "loss [N/m]", "status"])
        for label, amp, c in rows:
            for k, fk in enumerate(c.frequency):
                vals = [c.magnitude[k], c.phase_deg[k], c.storage[k], c.loss[k]]
                w.writerow([label, amp, f"{fk:.10g}"]
                           + ["" if not math.isfinite(v) else f"{v:.10g}" for v in vals]
                           + [c.status[k]])
    return path
