"""Lag damping under 1/rev motion: the lag mode on top of the forced periodic response.

In forward flight a lag damper carries a large 1/rev stroke from the
blade's periodic in-plane loads while it is meant to damp the lag mode at
nu Omega.  A nonlinear damper damps the lag mode differently on top of that
motion: elastomeric dampers lose about half their lag damping (Felker et
al. 1987; Gandhi & Chopra 1996), while a quadratic (orifice) loss gains, its
local slope 2 c2 |q| growing with the 1/rev flow.  This module measures it:

1. Forcing.  The blade (:func:`~liquidamp.coupled.assembly.blade_system`)
   takes a lag moment ``M(t) = M1 sin(Omega t)`` [N m] on its input
   ``moment`` (:class:`~liquidamp.coupled.inputs.HarmonicInput`); the rotor
   (:func:`~liquidamp.coupled.assembly.rotor_system`) the same load on every
   blade at its azimuth, ``M_k = M1 sin(Omega t + 2 pi (k - 1)/N)``.  Given
   a target 1/rev damper stroke or lag angle amplitude instead,
   :func:`forced_lag_damping` solves for M1 (the first harmonic of the
   orbit's stroke scaled by target/achieved until they agree).
2. The forced periodic response (period T = 2 pi/Omega) by shooting with
   the invariants of the sealed device held, and the monodromy of the
   variational equations along it (:func:`~liquidamp.analysis.stability.forced_orbit.forced_orbit`).
3. The lag mode's Floquet exponent, branch resolved against the eigenvalue
   of the orbit-averaged Jacobian that lives in the lag coordinates
   (:func:`~liquidamp.analysis.stability.forced_orbit.floquet_mode`):
   damping ratio ``-Re(eta)/|eta|`` and damped frequency ``Im(eta)``.
4. An independent check in the time domain (:func:`lag_decay_check`): the
   orbit is kicked along the lag mode, the nonlinear system integrated, the
   unkicked orbit (a second run) subtracted, and the decay of the lag
   deviation measured by the matrix pencil (Prony) and the moving-block
   analysis (:mod:`liquidamp.analysis.stability.decay`).

Prediction hook (:func:`lag_damping_from_stiffness`): the blade's lag
damping with the device replaced by an equivalent linear element of complex
stiffness ``K_lag = k' + i k''`` [N/m] at the lag frequency (the element
``k' y + (k''/omega) y'``), e.g. the dual-frequency dynamic stiffness under
the 1/rev stroke: the roots of ``I s^2 + (C + a^2 k''/omega) s + K + a^2 k' = 0``.

References
----------
.. [1] K. Felker, B. Lau, S. McLaughlin, W. Johnson, "Nonlinear behavior of
   an elastomeric lag damper undergoing dual-frequency motion and its effect
   on rotor dynamics", J. American Helicopter Society 32(4), 45-53, 1987.
.. [2] F. Gandhi, I. Chopra, "An analytical model for a nonlinear elastomeric
   lag damper and its effect on aeromechanical stability in hover",
   J. American Helicopter Society 41(3), 1996.
.. [3] W. G. Bousman, D. J. Winkler, AIAA Paper 81-0653, 1981 (moving block).
.. [4] W. Johnson, *Rotorcraft Aeromechanics*, Cambridge University Press,
   2013, Sec. 16.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.stability.damped_stability import DeviceLTI, closed_loop_matrix
from liquidamp.analysis.stability.decay import DecayEstimate, moving_block, pencil_damping
from liquidamp.analysis.stability.forced_orbit import (
    FloquetMode,
    ForcedOrbit,
    floquet_mode,
    forced_orbit,
)
from liquidamp.coupled.assembly import (
    Device,
    blade_system,
    rotor_system,
    simulate_coupled,
    viscous,
)
from liquidamp.coupled.inputs import HarmonicInput
from liquidamp.errors import ConvergenceError, ParameterError, check_positive
from liquidamp.options import SolverOptions, resolve_options

__all__ = ["ForcedLagResult", "forced_lag_damping", "LagDecayCheck", "lag_decay_check",
           "lag_damping_from_stiffness"]

#: Relative tolerance on the 1/rev amplitude when solving for the moment [-].
AMPLITUDE_RTOL = 1e-6


@dataclass(frozen=True, eq=False)
class ForcedLagResult:
    """Damping of the lag mode on top of the forced 1/rev response.

    Attributes
    ----------
    host : str
        ``blade`` or ``rotor``.
    rotor_speed : float
        Omega [rad/s].
    moment_amplitude : float
        M1, amplitude of the 1/rev lag moment [N m] (per blade).
    stroke_amplitude : float
        First-harmonic (1/rev) amplitude of the damper stroke on the orbit
        [m] (blade 1 on the rotor).
    lag_amplitude : float
        First-harmonic amplitude of the lag angle [rad] (blade 1).
    damping_ratio : float
        Lag mode damping ratio -Re(eta)/|eta| [-].
    frequency : float
        Damped lag frequency Im(eta) [rad/s] (rotating frame).
    exponent : complex
        Lag Floquet exponent eta, resolved branch [1/s].
    multipliers : ndarray of complex
        All Floquet multipliers of the orbit [-].
    lag_multiplier : complex
        The lag mode's multiplier exp(eta T) [-].
    orbit : ForcedOrbit
    mode : FloquetMode
    notes : str
        How the result was obtained.
    """

    host: str
    rotor_speed: float
    moment_amplitude: float
    stroke_amplitude: float
    lag_amplitude: float
    damping_ratio: float
    frequency: float
    exponent: complex
    multipliers: np.ndarray
    lag_multiplier: complex
    orbit: ForcedOrbit
    mode: FloquetMode
    notes: str

    @property
    def frequency_hz(self) -> float:
        """Damped lag frequency [Hz]."""
        return self.frequency / (2.0 * math.pi)

    @property
    def frequency_per_rev(self) -> float:
        """Damped lag frequency in per rev [-]."""
        return self.frequency / self.rotor_speed

    def as_dict(self) -> dict:
        """JSON-ready dictionary with unit-named keys."""
        return {"host": self.host, "rotor_speed [rad/s]": self.rotor_speed,
                "moment_amplitude [N m]": self.moment_amplitude,
                "stroke_amplitude [m]": self.stroke_amplitude,
                "lag_amplitude [rad]": self.lag_amplitude,
                "damping_ratio [-]": self.damping_ratio, "frequency [rad/s]": self.frequency,
                "exponent [1/s]": [self.exponent.real, self.exponent.imag],
                "lag_multiplier [-]": [self.lag_multiplier.real, self.lag_multiplier.imag],
                "multipliers [-]": [[float(m.real), float(m.imag)] for m in self.multipliers],
                "notes": self.notes}


def _inputs(host: str, structure, Omega: float, M1: float) -> list[HarmonicInput]:
    if host == "blade":
        return [HarmonicInput.polar("moment", M1, Omega)]
    N = structure.n_blades
    return [HarmonicInput.polar(f"moment_{k}", M1, Omega, 2.0 * math.pi * (k - 1) / N)
            for k in range(1, N + 1)]


def _lag_states(system, host: str) -> list[str]:
    names = system.host.state_names
    if host == "blade":
        return ["zeta", "zeta_dot"]
    return [s for s in names if s.startswith("zeta_")]


def _solve(system, host, structure, Omega, M1, x0, options, tol, max_iter):
    sys_ = system.with_inputs(_inputs(host, structure, Omega, M1))
    return forced_orbit(sys_, x0=x0, options=options, tol=tol, max_iter=max_iter)


def _amplitudes(orbit: ForcedOrbit, lag_state: str):
    y = abs(orbit.first_harmonic(orbit.strokes()[0]))
    z = abs(orbit.first_harmonic(orbit.host_state(lag_state)))
    return y, z


def forced_lag_damping(structure, Omega: float, device: Device, *, moment: float | None = None,
                       stroke: float | None = None, lag_angle: float | None = None,
                       options: SolverOptions | None = None, tol: float = 1e-8,
                       max_iter: int = 20) -> ForcedLagResult:
    """Lag damping of a blade or rotor with ``device`` under a 1/rev lag forcing.

    Parameters
    ----------
    structure : ArticulatedBlade or GroundResonanceRotor
        The host: a blade (its own lag damper kept; set ``lag_damping=0``
        for the device alone) or a rotor (the device on every blade, their
        own dampers removed).
    Omega : float
        Rotor speed > 0 [rad/s].
    device : Device
        Any model driven by stroke and rate with smooth effects (module
        notes of :mod:`~liquidamp.analysis.stability.forced_orbit`).
    moment : float, optional
        1/rev lag moment amplitude M1 >= 0 [N m] (0: the orbit is the rest
        state and the result is the small-signal lag damping).
    stroke : float, optional
        Target 1/rev damper stroke amplitude > 0 [m] (blade 1 on a rotor).
    lag_angle : float, optional
        Target 1/rev lag angle amplitude > 0 [rad]; give exactly one of
        ``moment``, ``stroke``, ``lag_angle``.
    options : SolverOptions, optional
        As :func:`~liquidamp.analysis.stability.forced_orbit.forced_orbit`
        (default the ``"decay"`` preset, compiled kernel).
    tol : float
        Periodicity tolerance of the orbit [-].
    max_iter : int
        Newton iterations per orbit; also the iterations on the moment.

    Returns
    -------
    ForcedLagResult

    Raises
    ------
    ConvergenceError
        The orbit does not converge (the message names the amplitude and the
        residual); the moment for the target amplitude is not found; the lag
        mode is not identified (the message says why).
    ParameterError
        Bad input.

    Examples
    --------
    A linear viscous damper: the lag damping does not depend on the 1/rev
    amplitude and is the blade's closed form c a^2 / (2 sqrt(I K)).

    >>> from liquidamp.coupled.assembly import viscous
    >>> from liquidamp.structure.hostio import load_blade
    >>> b = load_blade("hammond1974").replace(lag_damping=0.0)
    >>> W = 2 * math.pi * 4.2
    >>> r = forced_lag_damping(b, W, viscous(5e3), lag_angle=0.02)
    >>> exact = 5e3 * 0.25**2 / (2 * math.sqrt(b.inertia * b.lag_stiffness(W)))
    >>> round(r.damping_ratio / exact, 8), round(r.lag_amplitude, 6)
    (1.0, 0.02)
    """
    from liquidamp.structure.blade import ArticulatedBlade
    from liquidamp.structure.rotor import GroundResonanceRotor

    W = check_positive("rotor speed Omega", Omega, "rad/s")
    if not isinstance(device, Device):
        raise ParameterError(f"device must be a Device, got {type(device).__name__}")
    given = {k: v for k, v in (("moment", moment), ("stroke", stroke),
                               ("lag_angle", lag_angle)) if v is not None}
    if len(given) != 1:
        raise ParameterError("give exactly one of moment [N m], stroke [m] or lag_angle [rad], "
                             f"got {', '.join(given) or 'none'}")
    if isinstance(structure, ArticulatedBlade):
        host, system = "blade", blade_system(structure, W, device)
        inertia, stiffness = structure.inertia, structure.lag_stiffness(W)
    elif isinstance(structure, GroundResonanceRotor):
        host, system = "rotor", rotor_system(structure, W, device)
        inertia, stiffness = structure.blade.inertia, structure.blade.lag_stiffness(W)
    else:
        raise ParameterError(f"structure must be an ArticulatedBlade or GroundResonanceRotor, "
                             f"got {type(structure).__name__}")
    lag_states = _lag_states(system, host)
    arm = system.stroke_matrix[0, system.host.state_names.index(lag_states[0])]
    notes = []
    if moment is not None:
        M1 = float(moment)
        if not (math.isfinite(M1) and M1 >= 0.0):
            raise ParameterError(f"moment amplitude must be finite and >= 0 [N m], got {moment!r}")
        orbit = _solve(system, host, structure, W, M1, None, options, tol, max_iter)
        notes.append(f"1/rev lag moment {M1:.6g} N m given")
    else:
        name, target = next(iter(given.items()))
        unit = "m" if name == "stroke" else "rad"
        target = check_positive(f"target 1/rev {name} amplitude", target, unit)
        # start from the blade alone (inertia and centrifugal stiffness; the device adds
        # little at 1/rev), then scale the moment by target/achieved
        z_goal = target / abs(arm) if name == "stroke" else target
        M1 = z_goal * abs(stiffness - inertia * W * W)
        x0 = None
        history = []
        for _ in range(max_iter):
            orbit = _solve(system, host, structure, W, M1, x0, options, tol, max_iter)
            y, z = _amplitudes(orbit, lag_states[0])
            got = y if name == "stroke" else z
            history.append(got)
            if abs(got / target - 1.0) < AMPLITUDE_RTOL:
                break
            ratio = target / got
            M1 *= ratio
            nh = system.host.nstates
            x0 = orbit.x0.copy()
            x0[:nh] *= ratio
        else:
            raise ConvergenceError(
                f"no 1/rev lag moment gives the {name} amplitude {target:g} {unit} in "
                f"{max_iter} iterations: last amplitudes "
                f"{', '.join(f'{h:.6g}' for h in history[-4:])} {unit}, moment {M1:.6g} N m")
        notes.append(f"1/rev lag moment {M1:.6g} N m solved for the {name} amplitude "
                     f"{target:g} {unit} ({len(history)} orbits)")
    mode = floquet_mode(orbit, lag_states, what="lag mode")
    y, z = _amplitudes(orbit, lag_states[0])
    notes.append(orbit.message)
    notes.append(f"lag mode: exponent branch resolved against the orbit-averaged Jacobian's "
                 f"{mode.reference:.6g} 1/s; share in {', '.join(lag_states)} "
                 f"{mode.participation:.3g} (scaled coordinates)")
    return ForcedLagResult(host, W, M1, y, z, mode.damping_ratio, mode.frequency, mode.exponent,
                           orbit.floquet.multipliers.copy(), mode.multiplier, orbit, mode,
                           "; ".join(notes))


@dataclass(frozen=True, eq=False)
class LagDecayCheck:
    """The lag damping from a free decay on top of the orbit, against Floquet.

    Attributes
    ----------
    floquet : float
        Floquet lag damping ratio [-].
    pencil : DecayEstimate
        Matrix pencil (Prony) estimate.
    moving_block : DecayEstimate
        Moving-block estimate.
    time : ndarray
        Sample times of the decay [s].
    signal : ndarray
        Deviation from the orbit (the kicked run minus the orbit) of the lag
        angle the mode moves most [rad].
    state : str
        That lag angle's name.
    kick : float
        Lag angle of the perturbation along the lag mode [rad].
    revolutions : int
        Length of the record [rev].
    """

    floquet: float
    pencil: DecayEstimate
    moving_block: DecayEstimate
    time: np.ndarray
    signal: np.ndarray
    kick: float
    revolutions: int
    state: str = ""

    @property
    def pencil_error(self) -> float:
        """Relative difference pencil/Floquet - 1 of the damping ratio [-]."""
        return self.pencil.damping_ratio / self.floquet - 1.0

    @property
    def moving_block_error(self) -> float:
        """Relative difference moving-block/Floquet - 1 of the damping ratio [-]."""
        return self.moving_block.damping_ratio / self.floquet - 1.0


def lag_decay_check(result: ForcedLagResult, *, kick: float | None = None,
                    revolutions: int | None = None, samples_per_rev: int = 16,
                    block_cycles: int = 4, options: SolverOptions | None = None
                    ) -> LagDecayCheck:
    """Lag damping from the time domain on top of the orbit of ``result`` (module notes).

    The orbit state is perturbed by ``kick`` times the real part of the lag
    Floquet eigenvector (normalized to 1 in the lag angle it moves most), the
    nonlinear system integrated from the kicked and the unkicked state over
    the same output times (``simulate_coupled``, compiled kernel by default)
    and the difference of that lag angle analysed by
    :func:`~liquidamp.analysis.stability.decay.pencil_damping` (the dominant
    pole) and :func:`~liquidamp.analysis.stability.decay.moving_block` (at the
    record's spectral peak) -- neither uses the Floquet frequency.

    Parameters
    ----------
    result : ForcedLagResult
    kick : float, optional
        Size of the perturbation [rad]: ``kick`` times the lag Floquet
        eigenvector normalized to 1 in the lag angle it moves most (default
        1e-3 of the orbit's 1/rev lag amplitude, 1e-6 rad at rest): small
        enough for the linearization, far above the integration error.
    revolutions : int, optional
        Record length [rev] (default: until the Floquet decay reaches 5 %,
        within 20 to 400).
    samples_per_rev : int
        Samples per revolution (>= 8).
    block_cycles : int
        Moving-block length in lag cycles.
    options : SolverOptions, optional
        Integration (default the ``"decay"`` preset, rtol 1e-10, compiled).

    Returns
    -------
    LagDecayCheck
    """
    orbit, mode = result.orbit, result.mode
    system = orbit.system
    T = orbit.period
    opts = resolve_options(options, "decay")
    if not (isinstance(samples_per_rev, int) and samples_per_rev >= 8):
        raise ParameterError(f"samples_per_rev must be an integer >= 8, got {samples_per_rev!r}")
    sigma = -result.exponent.real
    if revolutions is None:
        R = 40 if sigma <= 0.0 else int(min(400, max(20, math.ceil(math.log(20.0) /
                                                                     (sigma * T)))))
    else:
        R = int(revolutions)
        if R < 4:
            raise ParameterError(f"revolutions must be >= 4, got {revolutions!r}")
    eps = (1e-3 * result.lag_amplitude if result.lag_amplitude > 0.0 else 1e-6) \
        if kick is None else check_positive("kick", kick, "rad")
    # the lag angle the mode moves most (a lag state read by a port's stroke), where the
    # kick vector is 1
    nh = system.host.nstates
    angle = np.isin(system.host.state_names, _lag_states(system, result.host)) \
        & np.any(system.stroke_matrix != 0.0, axis=0)
    i_lag = int(np.argmax(np.abs(mode.vector[:nh]) * angle))
    v = mode.vector / mode.vector[i_lag]
    x_star = orbit.x0
    x_kick = x_star + eps * np.real(v)
    t = np.arange(R * samples_per_rev + 1) * (T / samples_per_rev)
    runs = [simulate_coupled(system, float(t[-1]), x, t_eval=t, options=opts, energy=False,
                             max_step=T / 20.0) for x in (x_kick, x_star)]
    d = runs[0].host_states[i_lag] - runs[1].host_states[i_lag]
    dt = T / samples_per_rev
    pen = pencil_damping(d, dt)
    mb = moving_block(d, dt, block_cycles=block_cycles)
    return LagDecayCheck(result.damping_ratio, pen, mb, t, d, eps, R,
                         system.host.state_names[i_lag])


def lag_damping_from_stiffness(blade, Omega: float, K_lag, *, frequency: float | None = None,
                               max_iter: int = 50) -> tuple[float, float]:
    """The blade's lag damping with the device replaced by a complex stiffness ``K_lag``.

    The device becomes the linear element ``F = k' y + (k''/omega) y'``
    with ``K_lag = k' + i k''`` [N/m] evaluated at ``omega`` [rad/s] (a
    :class:`~liquidamp.analysis.stability.damped_stability.DeviceLTI` on the
    blade's port, :func:`~liquidamp.analysis.stability.damped_stability.closed_loop_matrix`):
    the roots of ``I s^2 + (C + a^2 k''/omega) s + K + a^2 k' = 0`` (the
    blade's own damper C stays).

    Parameters
    ----------
    blade : ArticulatedBlade
    Omega : float
        Rotor speed > 0 [rad/s].
    K_lag : complex or callable
        The device's equivalent dynamic stiffness at the lag frequency [N/m]
        (e.g. the dual-frequency K_lag under the 1/rev stroke), or a function
        ``omega [rad/s] -> K_lag``: then ``omega`` is iterated to the damped
        frequency of the result (fixed point, relative change 1e-10).
    frequency : float, optional
        omega at which a complex ``K_lag`` was evaluated [rad/s] (default the
        blade's undamped lag frequency; the start of the iteration for a
        callable).

    Returns
    -------
    damping_ratio : float
        [-].
    frequency : float
        Damped lag frequency [rad/s].

    Examples
    --------
    A viscous damper c is K_lag = i c omega at any omega: the closed form.

    >>> from liquidamp.structure.hostio import load_blade
    >>> b = load_blade("hammond1974").replace(lag_damping=0.0)
    >>> W, c = 26.0, 5e3
    >>> zeta, w = lag_damping_from_stiffness(b, W, lambda w: 1j * c * w)
    >>> round(zeta / (c * 0.25**2 / (2 * math.sqrt(b.inertia * b.lag_stiffness(W)))), 10)
    1.0
    """
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    w = blade.lag_frequency(W) if frequency is None else check_positive(
        "frequency of K_lag", frequency, "rad/s")
    system = blade_system(blade, W, viscous(0.0))

    def solve(K, w):
        K = complex(K)
        if not (math.isfinite(K.real) and math.isfinite(K.imag)):
            raise ParameterError(f"K_lag must be finite [N/m], got {K}")
        lti = DeviceLTI(np.zeros((0, 0)), np.zeros((0, 3)), np.zeros((1, 0)),
                        np.array([[K.real, K.imag / w, 0.0]]), "K_lag", "equivalent")
        lam = np.linalg.eigvals(closed_loop_matrix(system, [lti]))
        up = lam[lam.imag > 0.0]
        if up.size == 0:
            raise ParameterError(f"with K_lag = {K:.6g} N/m at {w:.6g} rad/s the lag mode is "
                                 f"overdamped or statically unstable (eigenvalues {lam})")
        s = complex(up[0])
        return -s.real / abs(s), s.imag

    if not callable(K_lag):
        return solve(K_lag, w)
    for _ in range(max_iter):
        zeta, wd = solve(K_lag(w), w)
        if abs(wd / w - 1.0) < 1e-10:
            return zeta, wd
        w = wd
    raise ConvergenceError(f"lag frequency iteration with a frequency-dependent K_lag did not "
                           f"settle in {max_iter} steps (last {w:.8g} rad/s)")
