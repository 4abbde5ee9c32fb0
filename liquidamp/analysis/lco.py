"""Limit cycles of a rotor with liquid lag dampers: describing function against time domain.

Where the small-signal closed loop is unstable the motion grows until the
device's nonlinearity stops it -- or does not.  The quadratic channel loss
dp = c1 q + c2 q|q| (and Coulomb friction) dissipates more per cycle at
larger amplitude; its describing function c_eq = c1 + 8 c2 q_hat/(3 pi)
(friction: 4 F_f/(pi omega Y)) turns the device into an amplitude-dependent
linear system (:func:`~liquidamp.analysis.damped_stability.device_lti`).

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

from liquidamp.analysis.damped_stability import (
    _mbc_transform,
    device_lti,
    rotor_closed_loop,
    rotor_device_eigenvalues,
)
from liquidamp.coupled.assembly import (
    CoupledResponse,
    Device,
    rotor_system,
    simulate_coupled,
)
from liquidamp.errors import ParameterError, check_positive
from liquidamp.options import SolverOptions

__all__ = [
    "GrowthFit",
    "growth_rate",
    "CriticalMode",
    "critical_mode",
    "LCOPrediction",
    "predict_lco",
    "LCOSimulation",
    "simulate_lco",
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
        P, _ = _mbc_transform(N, loop.ltis[0].n_states, W, 0.0)
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
        from liquidamp.analysis.damped_stability import rotor_device_floquet

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
    f = f0
    for _ in range(iters):
        lti = device_lti(device, amplitude_m=Y, frequency_hz=f)
        cm = critical_mode(rotor, W, device, inoperative=inop, lti=lti)
        f_new = cm.blade_frequency / (2 * math.pi)
        if abs(f_new - f) < 1e-6 * f:
            f = f_new
            break
        f = f_new
    return cm.eigenvalue.real, f


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
    lim = device.stroke_limit
    Ys = np.geomspace(1e-5, 0.8 * min(lim, 1.0), 24) if amplitudes is None else np.asarray(
        amplitudes, float)
    f = cm0.blade_frequency / (2 * math.pi)
    g, fs = [], []
    for Y in Ys:
        gi, f = _g(rotor, W, device, inop, float(Y), f)
        g.append(gi)
        fs.append(f)
    g, fs = np.array(g), np.array(fs)
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
        Default: DOP853, rtol 1e-7 (the coupled Hammond system is not stiff
        for these devices; pass Radau for stiff ones).
    mode : CriticalMode, optional
        Precomputed small-signal critical mode.
    """
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    inop = tuple(inoperative)
    cm = mode or critical_mode(rotor, W, device, inoperative=inop)
    opts = options or SolverOptions(method="DOP853", rtol=1e-7)
    sys_ = rotor_system(rotor, W, device, inoperative=inop)
    x0 = cm.host_state * initial_lag
    res = simulate_coupled(sys_, t_end, x0, options=opts, strict=False, energy=False,
                           samples_per_second=max(200.0, 40 * W / (2 * math.pi)))
    N = rotor.n_blades
    lag = res.host_states[:N]
    t = res.time
    k = int(np.argmax(np.max(np.abs(lag), axis=1)))
    Tb = 2 * math.pi / max(cm.blade_frequency, 1e-9)
    tail = 3 * Tb if tail is None else tail
    growth = None
    lo, hi = growth_window or (min(2 * math.pi / W, 0.25 * t[-1]), t[-1])
    try:
        growth = growth_rate(t, lag[k], lo, hi)
    except ParameterError:
        growth = None
    last = t >= t[-1] - tail
    prev = (t >= t[-1] - 2 * tail) & ~last
    a_last = 0.5 * (lag[k][last].max() - lag[k][last].min())
    a_prev = 0.5 * (lag[k][prev].max() - lag[k][prev].min()) if prev.any() else math.nan
    change = abs(a_last - a_prev) / a_last if a_last > 0 else math.nan
    return LCOSimulation(res, k + 1, growth, float(a_last), float(change))

