"""Limit cycles of a rotor with liquid lag dampers: describing function against time domain.

Where the small-signal closed loop is unstable the motion grows until the
device's nonlinearity stops it -- or does not.  The quadratic channel loss
dp = c1 q + c2 q|q| (and Coulomb friction) dissipates more per cycle at
larger amplitude; its describing function c_eq = c1 + 8 c2 q_hat/(3 pi)
(friction: 4 F_f/(pi omega Y)) turns the device into an amplitude-dependent
linear system (:func:`~liquidamp.analysis.stability.damped_stability.device_lti`).

Prediction (:func:`predict_lco`)
    Every operative blade's device is linearized at the same stroke
    amplitude Y, at the frequency the blade sees in the rotating frame for
    the critical mode; the largest real part g(Y) of the closed loop
    (Coleman or Floquet) is computed on a logarithmic grid of Y and its
    zero crossing refined by Brent's method: g(Y*) = 0 is the limit cycle,
    stable where g falls through zero (dg/dY < 0).  The frequency is
    iterated with Y (the mode's frequency moves with the device's
    stiffness).  The blade frequency: with the Coleman eigenvector, blade
    k's lag contains omega_f (collective, differential) and omega_f +- Omega
    (the cyclic pair, amplitudes |v_1c -+ i v_1s|/2); the largest component
    is taken.  With a failed damper (Floquet) the regressing value
    |Omega - omega_f| is used.  Assumptions: one harmonic, every operative
    device at the same amplitude (exact for the symmetric rotor's whirl
    mode; with a failed damper the blades' amplitudes differ and the
    estimate uses the largest).

Time domain (:func:`simulate_lco`, :func:`growth_rate`)
    The coupled nonlinear system (:mod:`liquidamp.coupled.assembly`) is
    started on the host part of the critical eigenvector (devices at rest).
    The growth or decay rate is the slope of the logarithm of the peak
    envelope of the most-moving blade's lag angle over a window; the limit
    cycle amplitude is half the peak-to-peak lag of that blade over the last
    revolutions.

Typical section (:func:`predict_section_lco`, :func:`simulate_section_lco`)
    The same two views for a wing section with a device on its plunge or
    pitch port (:func:`~liquidamp.coupled.assembly.section_system`, state-space
    aerodynamics): g(Y) is the largest real part of the section with the
    device's equivalent linearization at stroke amplitude Y and the critical
    mode's frequency (iterated); the time domain starts on the real part of
    the small-signal critical mode (devices at rest) and measures the port
    stroke.  By default the cycle-averaged bulk modulus enters the
    describing function: the small sized devices swing their chamber
    pressures by bars at limit-cycle amplitude, and on the plunge port this
    softening, not the quadratic loss, is what stops the growth
    (tests/coupled/test_section_lco.py gives the numbers).

Measured agreement (tests/coupled/test_lco.py and the issue report): small
amplitude growth rate within 5 % of the linear real part; limit-cycle
amplitude predicted within the tolerance stated in the tests.

References
----------
.. [1] A. Gelb, W. E. Vander Velde, Multiple-Input Describing Functions and
   Nonlinear System Design, McGraw-Hill, 1968.
.. [2] B. Titurus, AIAA J. 56(10), 2018, eqs. (5), (10), (18).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.signal import find_peaks

from liquidamp.analysis.stability.damped_stability import (
    closed_loop_mbc_transform,
    device_lti,
    rotor_closed_loop,
    rotor_device_eigenvalues,
)
from liquidamp.coupled.assembly import (
    CoupledResponse,
    Device,
    compiled_support,
    rotor_system,
    section_system,
    simulate_coupled,
)
from liquidamp.errors import ParameterError, check_positive
from liquidamp.options import SolverOptions, resolve_options

__all__ = [
    "GrowthFit",
    "growth_rate",
    "CriticalMode",
    "critical_mode",
    "LCOPrediction",
    "predict_lco",
    "LCOSimulation",
    "simulate_lco",
    "SectionMode",
    "section_critical_mode",
    "SectionLCOPrediction",
    "predict_section_lco",
    "SectionLCOSimulation",
    "simulate_section_lco",
]


@dataclass(frozen=True)
class GrowthFit:
    """Exponential fit of a peak envelope, |s| ~ exp(rate t + intercept).

    Attributes
    ----------
    rate : float
        Growth (> 0) or decay (< 0) rate [1/s].
    intercept : float
        ln of the envelope at t = 0 [ln(signal unit)].
    n_peaks : int
        Peaks used.
    t_start, t_end : float
        Window [s].
    """

    rate: float
    intercept: float
    n_peaks: int
    t_start: float
    t_end: float


def growth_rate(t, signal, t_start: float | None = None, t_end: float | None = None
                ) -> GrowthFit:
    """Least-squares slope of ln(peaks of |signal|) over [t_start, t_end] [1/s].

    Examples
    --------
    >>> t = np.linspace(0.0, 10.0, 4001)
    >>> round(growth_rate(t, np.exp(-0.3 * t) * np.sin(5.0 * t)).rate, 4)
    -0.3
    """
    t = np.asarray(t, float)
    s = np.abs(np.asarray(signal, float))
    lo = t[0] if t_start is None else t_start
    hi = t[-1] if t_end is None else t_end
    sel = (t >= lo) & (t <= hi)
    tt, ss = t[sel], s[sel]
    pk, _ = find_peaks(ss)
    if pk.size < 3:
        raise ParameterError(f"fewer than 3 peaks in the window [{lo:g}, {hi:g}] s; "
                             "lengthen the run")
    # refine each peak by a parabola through its neighbours (log scale)
    tp, lp = [], []
    for i in pk:
        y0, y1, y2 = np.log(ss[i - 1:i + 2])
        den = y0 - 2 * y1 + y2
        dx = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        h = tt[i + 1] - tt[i]
        tp.append(tt[i] + dx * h)
        lp.append(y1 - 0.25 * (y0 - y2) * dx)
    rate, icpt = np.polyfit(tp, lp, 1)
    return GrowthFit(float(rate), float(icpt), int(pk.size), float(lo), float(hi))


def _iterate_frequency(mode_at, f0, iters, rtol):
    """Fixed-point iteration of the describing function's frequency [Hz].

    ``mode_at(f)`` returns (largest real part [1/s], critical mode frequency
    [Hz]) with the device(s) linearized at ``f``; stops after ``iters``
    passes or when the frequency moves by less than ``rtol * f``.  Returns
    (real part [1/s], frequency [Hz]) of the last pass.
    """
    f = f0
    for _ in range(iters):
        g, f_new = mode_at(f)
        done = abs(f_new - f) < rtol * f
        f = f_new
        if done:
            break
    return g, f


def _amplitude_scan(g_at, device, amplitudes, smallest, f0):
    """g(Y) [1/s] and the iterated frequency [Hz] over the stroke amplitude grid [m].

    The default grid is 24 log-spaced amplitudes from ``smallest`` [m] to 0.8
    x the device's stroke limit (at most 0.8 m); ``g_at(Y, f)`` returns
    (g, f) at amplitude Y started from frequency f, each point starting from
    the previous one's frequency.  Returns (amplitudes, g, frequencies).
    """
    Ys = (np.geomspace(smallest, 0.8 * min(device.stroke_limit, 1.0), 24) if amplitudes is None
          else np.asarray(amplitudes, float))
    f = f0
    g, fs = [], []
    for Y in Ys:
        gi, f = g_at(float(Y), f)
        g.append(gi)
        fs.append(f)
    return Ys, np.array(g), np.array(fs)


def _try_growth_rate(t, signal, window, default_start):
    """:func:`growth_rate` over ``window`` [s] (default ``default_start`` to the end), or None.

    None when the window holds fewer than 3 peaks.
    """
    lo, hi = window or (default_start, t[-1])
    try:
        return growth_rate(t, signal, lo, hi)
    except ParameterError:
        return None


def _tail_amplitude(t, signal, tail):
    """Half peak-to-peak of ``signal`` over the last ``tail`` seconds, and its change.

    Returns (amplitude [signal unit], relative change [-] from the tail window
    before; NaN if there is none or the amplitude is 0).
    """
    last = t >= t[-1] - tail
    prev = (t >= t[-1] - 2 * tail) & ~last
    a_last = 0.5 * (signal[last].max() - signal[last].min())
    a_prev = 0.5 * (signal[prev].max() - signal[prev].min()) if prev.any() else math.nan
    change = abs(a_last - a_prev) / a_last if a_last > 0 else math.nan
    return a_last, change


@dataclass(frozen=True, eq=False)
class CriticalMode:
    """The least stable mode of the linear closed loop.

    Attributes
    ----------
    eigenvalue : complex
        Fixed-frame eigenvalue or resolved Floquet exponent [1/s].
    blade_frequency : float
        Frequency of the blades' lag motion in the rotating frame [rad/s].
    host_state : ndarray
        Real host state (rotating frame) of the mode, lag of the most-moving
        blade scaled to 1 rad [host units].
    method : str
    """

    eigenvalue: complex
    blade_frequency: float
    host_state: np.ndarray
    method: str


def critical_mode(rotor, Omega: float, device: Device, *, inoperative=(), lti=None
                  ) -> CriticalMode:
    """Least stable mode of rotor + linear devices and the blade frequency it drives."""
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    N = rotor.n_blades
    if not inoperative:
        lam, vec = rotor_device_eigenvalues(rotor, W, device, lti=lti, method="coleman",
                                            vectors=True)
        up = np.flatnonzero(lam.imag > 0)
        i = up[np.argmax(lam.real[up])]
        loop = rotor_closed_loop(rotor, W, device, lti=lti)
        P, _ = closed_loop_mbc_transform(N, loop.ltis[0].n_states, W, 0.0)
        v = vec[:, i]
        wf = lam[i].imag
        c = [abs(v[0]), 0.0, 0.0]
        if N >= 3:
            c[1] = 0.5 * abs(v[1] - 1j * v[2])  # omega_f + Omega
            c[2] = 0.5 * abs(v[1] + 1j * v[2])  # omega_f - Omega
        freqs = [wf, wf + W, abs(wf - W)]
        wb = freqs[int(np.argmax(c))]
        x = (P @ v)[: 2 * (N + 2)]
        method = "coleman"
        eig = complex(lam[i])
    else:
        from liquidamp.analysis.stability.damped_stability import rotor_device_floquet

        resolved, res = rotor_device_floquet(rotor, W, device, inoperative=inoperative,
                                             lti=lti)
        i = int(np.argmax(resolved.real + 1e-12 * (resolved.imag > 0)))
        mu, V = np.linalg.eig(res.monodromy)
        j = int(np.argmin(np.abs(mu - res.multipliers[i])))
        x = V[: 2 * (N + 2), j]
        eig = complex(resolved[i].real + 1j * abs(resolved[i].imag))
        wb = abs(W - abs(eig.imag))
        method = "floquet"
    k = int(np.argmax(np.abs(x[:N])))
    x = x / x[k]
    return CriticalMode(eig, float(wb), np.real(x), method)


@dataclass(frozen=True, eq=False)
class LCOPrediction:
    """Describing-function prediction of a limit cycle.

    Attributes
    ----------
    linear_eigenvalue : complex
        Small-signal critical eigenvalue [1/s].
    amplitudes : ndarray
        Stroke amplitudes of the grid [m].
    real_parts : ndarray
        Largest real part g(Y) at each [1/s].
    frequencies_hz : ndarray
        Blade (device) frequency used at each [Hz].
    stroke_amplitude : float or None
        Y* [m] where g falls through zero (stable limit cycle); None if none.
    lag_amplitude : float or None
        Y*/arm [rad].
    frequency_hz : float or None
        Device frequency at Y* [Hz].
    stable : bool or None
        True for a stable limit cycle (g falls through zero).
    note : str
    """

    linear_eigenvalue: complex
    amplitudes: np.ndarray
    real_parts: np.ndarray
    frequencies_hz: np.ndarray
    stroke_amplitude: float | None
    lag_amplitude: float | None
    frequency_hz: float | None
    stable: bool | None
    note: str


def _g(rotor, W, device, inop, Y, f0, iters=3):
    """Largest real part with the devices linearized at (Y, f), f iterated [1/s, Hz]."""

    def mode_at(f):
        lti = device_lti(device, amplitude=Y, frequency=f)
        cm = critical_mode(rotor, W, device, inoperative=inop, lti=lti)
        return cm.eigenvalue.real, cm.blade_frequency / (2 * math.pi)

    return _iterate_frequency(mode_at, f0, iters, 1e-6)


def predict_lco(rotor, Omega: float, device: Device, *, inoperative=(),
                amplitudes=None) -> LCOPrediction:
    """Limit-cycle stroke amplitude from the describing function (module notes).

    Parameters
    ----------
    rotor : GroundResonanceRotor
    Omega : float
        Rotor speed [rad/s].
    device : Device
        On every operative blade.
    inoperative : sequence of int
    amplitudes : array, optional
        Stroke amplitude grid [m] (default 24 log-spaced from 1e-5 m to
        0.8 x stroke limit).

    Returns
    -------
    LCOPrediction
    """
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    inop = tuple(inoperative)
    cm0 = critical_mode(rotor, W, device, inoperative=inop)
    Ys, g, fs = _amplitude_scan(lambda Y, f: _g(rotor, W, device, inop, Y, f), device,
                                amplitudes, 1e-5, cm0.blade_frequency / (2 * math.pi))
    Ystar = fstar = stable = None
    note = "no zero crossing of the largest real part over the amplitude grid"
    for i in range(Ys.size - 1):
        if g[i] > 0.0 >= g[i + 1]:
            fi = fs[i]
            Ystar = brentq(lambda y, fi=fi: _g(rotor, W, device, inop, y, fi)[0], Ys[i], Ys[i + 1],
                           xtol=1e-9, rtol=1e-6)
            fstar = _g(rotor, W, device, inop, Ystar, fi)[1]
            stable = True
            note = "stable limit cycle: the largest real part falls through zero"
            break
        if g[i] <= 0.0 < g[i + 1]:
            note = (f"unstable limit cycle between {Ys[i]:.3g} and {Ys[i + 1]:.3g} m: motion "
                    "above it grows")
    arm = rotor.blade.damper_arm
    if cm0.eigenvalue.real <= 0 and Ystar is None:
        note = "linearly stable and no limit cycle found: small motions decay"
    return LCOPrediction(cm0.eigenvalue, Ys, g, fs, Ystar,
                         None if Ystar is None else Ystar / arm, fstar, stable, note)


@dataclass(frozen=True, eq=False)
class LCOSimulation:
    """A time-domain run of rotor + nonlinear devices from the critical mode.

    Attributes
    ----------
    response : CoupledResponse
    blade : int
        The most-moving blade (1-based).
    growth : GrowthFit or None
        Envelope fit over the growth window.
    lag_amplitude : float
        Half peak-to-peak lag of that blade over the last ``tail`` seconds [rad].
    amplitude_change : float
        Relative change of that amplitude between the last two tail windows [-]
        (small when the motion has settled on a limit cycle).
    """

    response: CoupledResponse
    blade: int
    growth: GrowthFit | None
    lag_amplitude: float
    amplitude_change: float


def simulate_lco(rotor, Omega: float, device: Device, *, inoperative=(),
                 initial_lag: float = 1e-3, t_end: float = 10.0,
                 growth_window: tuple[float, float] | None = None, tail: float | None = None,
                 options: SolverOptions | None = None, mode: CriticalMode | None = None
                 ) -> LCOSimulation:
    """Time-domain run started on the critical mode (host part, lag ``initial_lag`` [rad]).

    Parameters
    ----------
    rotor, Omega, device, inoperative
        As in :func:`predict_lco`.
    initial_lag : float
        Initial lag of the most-moving blade [rad].
    t_end : float
        Simulated time [s].
    growth_window : (float, float), optional
        Window of the envelope fit [s] (default the whole run minus the first
        revolution).
    tail : float, optional
        Window of the final amplitude [s] (default 3 blade periods).
    options : SolverOptions, optional
        Default: the ``"rotor"`` preset of :data:`liquidamp.options.PRESETS`
        (DOP853, rtol 1e-7: the coupled Hammond system is not stiff for
        these devices; pass Radau for stiff ones) on the compiled engine, or
        on the scipy engine (the same DOP853; agreement about 1e-13) where
        :func:`~liquidamp.coupled.assembly.compiled_support` says the
        compiled kernel cannot run the system.  Options given are used as
        given.
    mode : CriticalMode, optional
        Precomputed small-signal critical mode.
    """
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    inop = tuple(inoperative)
    cm = mode or critical_mode(rotor, W, device, inoperative=inop)
    sys_ = rotor_system(rotor, W, device, inoperative=inop)
    opts = resolve_options(options, "rotor")
    if options is None and opts.engine == "compiled" and compiled_support(sys_) is not None:
        opts = opts.replace(engine="scipy")
    x0 = cm.host_state * initial_lag
    res = simulate_coupled(sys_, t_end, x0, options=opts, strict=False, energy=False,
                           samples_per_second=max(200.0, 40 * W / (2 * math.pi)))
    N = rotor.n_blades
    lag = res.host_states[:N]
    t = res.time
    k = int(np.argmax(np.max(np.abs(lag), axis=1)))
    Tb = 2 * math.pi / max(cm.blade_frequency, 1e-9)
    tail = 3 * Tb if tail is None else tail
    growth = _try_growth_rate(t, lag[k], growth_window, min(2 * math.pi / W, 0.25 * t[-1]))
    a_last, change = _tail_amplitude(t, lag[k], tail)
    return LCOSimulation(res, k + 1, growth, float(a_last), float(change))



# ---------------------------------------------------------------------------
# typical section (Hodges & Pierce) with a device on the plunge or pitch port


@dataclass(frozen=True, eq=False)
class SectionMode:
    """The least stable mode of the section with linear devices.

    Attributes
    ----------
    eigenvalue : complex
        Critical eigenvalue (Im > 0) [1/s].
    host_state : ndarray
        Real host state of the mode (h [m], theta [rad], rates, aerodynamic
        lag states), scaled to a unit stroke at the device's port [host units/m].
    frequency_hz : float
        Im(eigenvalue)/(2 pi) [Hz].
    """

    eigenvalue: complex
    host_state: np.ndarray
    frequency_hz: float


def _check_port(port: str) -> str:
    if port not in ("plunge", "pitch"):
        raise ParameterError(f"unknown port {port!r}; valid: plunge, pitch")
    return port


def section_critical_mode(section, U: float, device: Device, *, port: str = "plunge",
                          aero: str = "jones", lti=None) -> SectionMode:
    """Least stable mode of the section at ``U`` [m/s] with ``device`` (linear) on ``port``."""
    from liquidamp.analysis.stability.damped_stability import closed_loop_matrix

    U = check_positive("airspeed U", U, "m/s")
    port = _check_port(port)
    sys_ = section_system(section, U, {port: device}, aero)
    lt = [lti] if lti is not None else None
    lam, vec = np.linalg.eig(closed_loop_matrix(sys_, lt))
    up = np.flatnonzero(lam.imag > 1e-9)
    i = up[np.argmax(lam.real[up])]
    nh = sys_.host.nstates
    x = vec[:nh, i]
    y = complex(sys_.stroke_matrix[0] @ x)
    x = x / y
    return SectionMode(complex(lam[i]), np.real(x), float(lam[i].imag / (2 * math.pi)))


def _g_section(section, U, device, port, aero, Y, f0, bulk="averaged", iters=4):
    """Largest real part with the device linearized at (Y, f), f iterated [1/s, Hz]."""

    def mode_at(f):
        lti = device_lti(device, amplitude=Y, frequency=f, bulk=bulk)
        cm = section_critical_mode(section, U, device, port=port, aero=aero, lti=lti)
        return cm.eigenvalue.real, cm.frequency_hz

    return _iterate_frequency(mode_at, f0, iters, 1e-7)


@dataclass(frozen=True, eq=False)
class SectionLCOPrediction:
    """Describing-function prediction of a limit cycle of the section.

    Attributes
    ----------
    port : str
        ``plunge`` or ``pitch``.
    linear_eigenvalue : complex
        Small-signal critical eigenvalue [1/s].
    amplitudes : ndarray
        Stroke amplitudes of the grid [m].
    real_parts : ndarray
        Largest real part g(Y) at each [1/s].
    frequencies_hz : ndarray
        Mode (device) frequency at each [Hz].
    stroke_amplitude : float or None
        Y* [m] where g falls through zero (stable limit cycle); None if none.
    host_amplitude : float or None
        The port's host coordinate at Y*: plunge h [m] or pitch theta [rad].
    frequency_hz : float or None
        Frequency at Y* [Hz].
    stable : bool or None
        True for a stable limit cycle.
    unstable_amplitude : float or None
        Stroke amplitude [m] of an unstable limit cycle (g rises through
        zero: motion above it grows), if any on the grid.
    note : str
    """

    port: str
    linear_eigenvalue: complex
    amplitudes: np.ndarray
    real_parts: np.ndarray
    frequencies_hz: np.ndarray
    stroke_amplitude: float | None
    host_amplitude: float | None
    frequency_hz: float | None
    stable: bool | None
    unstable_amplitude: float | None
    note: str


def _port_arm(section, port: str) -> float:
    return 1.0 if port == "plunge" else float(section.pitch_arm)


def predict_section_lco(section, U: float, device: Device, *, port: str = "plunge",
                        aero: str = "jones", amplitudes=None, bulk: str = "averaged"
                        ) -> SectionLCOPrediction:
    """Limit-cycle stroke amplitude of the section from the describing function.

    The device is replaced by its equivalent linearization at stroke
    amplitude Y and the critical mode's frequency (iterated with Y); g(Y) is
    the largest real part of the closed loop with the host's state-space
    aerodynamics.  A zero where g falls is a stable limit cycle (refined by
    Brent's method); one where g rises is unstable.

    Parameters
    ----------
    section : TypicalSection
    U : float
        Airspeed [m/s].
    device : Device
    port : {"plunge", "pitch"}
    aero : {"jones", "quasi-steady", "steady"}
    amplitudes : array, optional
        Stroke amplitude grid [m] (default 24 log-spaced from 1e-6 m to
        0.8 x stroke limit).
    bulk : {"averaged", "rest", "auto"}
        Bulk modulus of the equivalent linearization (see
        :func:`~liquidamp.analysis.stability.damped_stability.device_lti`).  Default
        ``averaged``: on the section the sized devices are small (A_p ~ 7e-6
        m^2) and at limit-cycle amplitude the quadratic loss swings the
        chamber pressures by several bar, so the pressure-dependent bulk
        modulus (Titurus eq. 2) softens the device; ``rest`` keeps B at p0
        (the losses' amplitude dependence alone).  Measured
        (tests/coupled/test_section_lco.py): pitch port, 1.03 V_F, averaged
        0.8 % and rest 3 % from the simulated amplitude; plunge port: rest
        predicts no limit cycle (g rises with Y), averaged predicts one 17 %
        above the simulated one.

    Returns
    -------
    SectionLCOPrediction
    """
    U = check_positive("airspeed U", U, "m/s")
    port = _check_port(port)
    cm0 = section_critical_mode(section, U, device, port=port, aero=aero)
    Ys, g, fs = _amplitude_scan(
        lambda Y, f: _g_section(section, U, device, port, aero, Y, f, bulk), device,
        amplitudes, 1e-6, cm0.frequency_hz)
    Ystar = fstar = stable = Yun = None
    note = "no zero crossing of the largest real part over the amplitude grid"
    for i in range(Ys.size - 1):
        if g[i] > 0.0 >= g[i + 1] and Ystar is None:
            fi = fs[i]

            def gfun(y, fi=fi):
                return _g_section(section, U, device, port, aero, y, fi, bulk)[0]

            Ystar = float(brentq(gfun, Ys[i], Ys[i + 1], xtol=1e-10, rtol=1e-7))
            fstar = _g_section(section, U, device, port, aero, Ystar, fi, bulk)[1]
            stable = True
            note = "stable limit cycle: the largest real part falls through zero"
        elif g[i] <= 0.0 < g[i + 1] and Yun is None:
            fi = fs[i]
            Yun = float(brentq(lambda y, fi=fi: _g_section(section, U, device, port, aero, y,
                                                           fi, bulk)[0],
                               Ys[i], Ys[i + 1], xtol=1e-10, rtol=1e-7))
    if Ystar is None:
        if cm0.eigenvalue.real <= 0:
            note = "linearly stable and no limit cycle found: small motions decay"
        elif np.all(g > 0):
            note = ("no limit cycle: the equivalent linear system is unstable at every "
                    f"amplitude up to {Ys[-1]:.3g} m (g from {g[0]:.3g} to {g[-1]:.3g} 1/s)")
    if Yun is not None:
        note += f"; unstable limit cycle at {Yun:.3g} m stroke: motion above it grows"
    host = None if Ystar is None else Ystar / _port_arm(section, port)
    return SectionLCOPrediction(port, cm0.eigenvalue, Ys, g, fs, Ystar, host, fstar, stable,
                                Yun, note)


@dataclass(frozen=True, eq=False)
class SectionLCOSimulation:
    """A time-domain run of the section with the nonlinear device from its critical mode.

    Attributes
    ----------
    response : CoupledResponse
    port : str
    linear_eigenvalue : complex
        Small-signal critical eigenvalue [1/s].
    growth : GrowthFit or None
        Envelope fit of the port stroke over the growth window.
    stroke_amplitude : float
        Half peak-to-peak stroke over the last ``tail`` seconds [m].
    host_amplitude : float
        Same for the port's host coordinate (h [m] or theta [rad]).
    amplitude_change : float
        Relative change of the stroke amplitude between the last two tail
        windows [-] (small when settled on a limit cycle).
    """

    response: CoupledResponse
    port: str
    linear_eigenvalue: complex
    growth: GrowthFit | None
    stroke_amplitude: float
    host_amplitude: float
    amplitude_change: float


def simulate_section_lco(section, U: float, device: Device, *, port: str = "plunge",
                         aero: str = "jones", initial_stroke: float = 1e-5,
                         t_end: float = 10.0, growth_window: tuple[float, float] | None = None,
                         tail: float | None = None, options: SolverOptions | None = None,
                         mode: SectionMode | None = None) -> SectionLCOSimulation:
    """Time-domain run of section + nonlinear device started on the critical mode.

    The host starts on the real part of the small-signal critical mode
    scaled to the stroke ``initial_stroke`` [m], the device at rest.

    Parameters
    ----------
    section, U, device, port, aero
        As in :func:`predict_section_lco`.
    initial_stroke : float
        Initial port stroke [m].
    t_end : float
        Simulated time [s].
    growth_window : (float, float), optional
        Window of the envelope fit [s] (default: after two mode periods to the end).
    tail : float, optional
        Window of the final amplitude [s] (default 3 mode periods).
    options : SolverOptions, optional
        Default: the ``"section"`` preset of :data:`liquidamp.options.PRESETS`
        (Radau, rtol 1e-6, scipy engine).
    mode : SectionMode, optional
        Precomputed small-signal critical mode.
    """
    U = check_positive("airspeed U", U, "m/s")
    port = _check_port(port)
    cm = mode or section_critical_mode(section, U, device, port=port, aero=aero)
    opts = resolve_options(options, "section")
    sys_ = section_system(section, U, {port: device}, aero)
    x0 = cm.host_state * check_positive("initial stroke", initial_stroke, "m")
    Tm = 1.0 / max(cm.frequency_hz, 1e-9)
    res = simulate_coupled(sys_, t_end, x0, options=opts, strict=False, energy=False,
                           samples_per_second=64.0 / Tm, max_step=Tm / 20.0)
    t = res.time
    y = res.strokes[0]
    growth = _try_growth_rate(t, y, growth_window, min(2 * Tm, 0.25 * t[-1]))
    tail = 3 * Tm if tail is None else tail
    a_last, change = _tail_amplitude(t, y, tail)
    return SectionLCOSimulation(res, port, cm.eigenvalue, growth, float(a_last),
                                float(a_last / _port_arm(section, port)), float(change))
