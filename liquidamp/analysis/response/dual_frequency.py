"""Dual-frequency response: the lag damper in forward flight (issue #13).

A lag damper on a rotor in forward flight moves at two frequencies at once:
a large motion at the 1/rev frequency Omega from the blade's periodic loads
and a small one at the lag frequency omega, which the damper is there to
damp,

.. math:: y(t) = y_0 + A_1 \\sin(\\Omega t) + A_2 \\sin(\\omega t + \\varphi).

A nonlinear damper's force at omega then depends on the 1/rev motion.
:func:`dual_frequency_stiffness` returns the equivalent dynamic stiffness at
the lag frequency, K_lag = F(omega) / Y2 (the complex first harmonic of the
force at omega over that of the stroke, Y2 = A2 exp(i phi), sine convention
of :mod:`liquidamp.analysis.response.harmonics`): storage K' = Re K_lag,
loss K'' = Im K_lag, equivalent damping K'' / omega; and at 1/rev K_rev =
F(Omega) / A1; on the quasi-periodic steady state, for any
:class:`~liquidamp.device.models.DeviceModel` with any effects, beside the
single-frequency K at omega for A2 alone.

Routes (``method``):

``"harmonic_balance"`` (default)
    Models with states: a two-frequency harmonic balance, alternating
    frequency-time on a grid over both phases theta1 = Omega t, theta2 =
    omega t (:mod:`liquidamp.analysis.response._torus`: spectral
    collocation, Newton-Krylov with the compiled
    :func:`~liquidamp.device.kernels.model_rhs` and
    :func:`~liquidamp.device.kernels.model_jac` at the grid points, the
    device invariants held by bordering), started from the superposition
    of the two single-frequency periodic states; the grid follows from
    their spectra and is refined until the torus's spectral tail is below
    ``TAIL_TOL``.  Stateless models (dashpot, viscous, inerter, ...) need
    no Newton: the force's torus average is a 2-D quadrature.  The force's
    harmonics come from the converged torus by 2-D FFT; where the force
    has a jump (Coulomb friction: the ``coulomb_friction`` effect or
    ``friction_N``) on a fine grid (``quadrature_grid``), the states
    interpolated spectrally onto it, and the result states the quadrature
    error (the grid against every other point of it).
    Where f_rev / f_lag = a / b is commensurate, the harmonics j (b, -a)
    resonate (k Omega + l omega = 0): for a device with invariants the torus
    is then not unique in them (each closed characteristic keeps its own
    invariant values), so the grid keeps them off (fewer than b harmonics
    along theta1 or fewer than a along theta2; 4.2 Hz / 1.26 Hz = 10/3 leaves
    9 along theta2); at low order (e.g. 2/1) that is impossible and the
    harmonic balance refers to the time route.  The torus answer is the
    quasi-periodic one (independent of the phase phi); at a commensurate
    ratio the periodic response also holds the resonant harmonics, which
    depend on phi: at 10/3 they are of order 12 (K_lag from the time route
    changes by less than 1e-6 with phi at 3 mm for the presets).
``"time"``
    A time-domain run on the engine of ``options`` (compiled by default)
    under a :class:`~liquidamp.structure.testmachine.TwoFrequencyStroke`:
    where omega / Omega is rational (4.2 Hz and 1.26 Hz: 10/3) the
    periodic steady state over the common period and the exact DFT of the
    force; otherwise a march from rest, windows of 20 periods of the slower
    component, the first harmonics at both frequencies by Hann-weighted
    least squares over each window (the combination tones k Omega + l
    omega, 0 <= k <= 4, |l| <= 4, that the window resolves as further
    regressors) until two windows agree to ``tol``: the transient is
    dropped as it decays.

For a small lag velocity amplitude V2 on a large 1/rev velocity amplitude
V1, static laws have closed forms (the tests check them): Coulomb friction
F_c sign(v) gives an equivalent lag damping 2 F_c / (pi V1) (against
4 F_c / (pi V2) alone), a quadratic damper c2 v|v| gives 4 c2 V1 / pi
(against 8 c2 V2 / (3 pi) alone).  A quadratic loss's lag damping therefore
*rises* with the 1/rev amplitude, where a friction (or elastomer) damper's
falls.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018 (the device).
.. [2] T. M. Cameron, J. H. Griffin, "An alternating frequency/time domain
   method for calculating the steady-state response of nonlinear dynamic
   systems", J. Appl. Mech. 56(1), 1989, 149-154.
.. [3] M. Guskov, J.-J. Sinou, F. Thouverez, "Multi-dimensional harmonic
   balance applied to rotor dynamics", Mech. Res. Commun. 35(8), 2008,
   537-545.
.. [4] F. F. Felker, B. H. Lau, S. McLaughlin, W. Johnson, "Nonlinear
   behavior of an elastomeric lag damper undergoing dual-frequency motion
   and its effect on rotor dynamics", J. Am. Helicopter Soc. 32(4), 1987,
   45-53 (the loss of lag damping under 1/rev motion).
.. [5] F. Gandhi, I. Chopra, "A time-domain non-linear viscoelastic damper
   model", Smart Mater. Struct. 5(5), 1996, 517-528.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.response import _torus
from liquidamp.analysis.response._dual_time import time_route
from liquidamp.analysis.response.torus_invariants import (  # noqa: F401 (re-exported)
    TorusInvariants,
    torus_invariants,
)
from liquidamp.coupled.periodic import state_swing
from liquidamp.device import kernels as K
from liquidamp.device.models import ViscousParams, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import (
    LiquidampWarning,
    ParameterError,
    check_choice,
    check_finite,
    check_positive,
)
from liquidamp.options import resolve_options
from liquidamp.structure.testmachine import HarmonicStroke, TwoFrequencyStroke

__all__ = ["DualFrequencyStiffness", "dual_frequency_stiffness", "check_inputs", "METHODS",
           "TAIL_TOL", "QUADRATURE_GRID", "MAX_GRID", "TorusInvariants", "torus_invariants"]

#: Routes of :func:`dual_frequency_stiffness`.
METHODS = ("harmonic_balance", "time")
#: Largest spectral tail of a converged torus (outer third of the harmonics, relative to
#: each state's swing) before the grid is refined [-].
TAIL_TOL = 3e-3
#: Fine grid (points along the larger-velocity phase, along the other) of the force
#: quadrature of stateless models and of forces with a jump [-].
QUADRATURE_GRID = (4096, 64)
#: Largest torus grid along either phase [points].
MAX_GRID = 127
#: Samples per period of the single-frequency runs that start the harmonic balance.
_GUESS_SAMPLES = 256


# ---------------------------------------------------------------------------- result
@dataclass(frozen=True, eq=False)
class DualFrequencyStiffness:
    """Equivalent dynamic stiffness of a device under a two-frequency stroke.

    Stroke y = offset + A1 sin(Omega t) + A2 sin(omega t + phi); sine
    convention (K = F1 / Y1 with F1 = a + i b for a sin + b cos).

    Attributes
    ----------
    model : str
        Model name.
    method : str
        ``"harmonic_balance"`` (torus collocation), ``"quadrature"`` (a
        stateless model: the force's torus average), ``"time_periodic"``
        (steady state over the common period) or ``"time_window"`` (long
        march, least squares).
    rev_frequency, lag_frequency : float
        Omega / 2 pi and omega / 2 pi [Hz].
    rev_amplitude, lag_amplitude : float
        A1 >= 0 and A2 > 0 [m].
    offset : float
        Mean stroke y0 [m].
    lag_phase : float
        phi [rad].
    K_lag : complex
        F(omega) / (A2 e^{i phi}) [N/m].
    K_rev : complex or None
        F(Omega) / A1 [N/m]; None when A1 = 0 (no 1/rev motion).
    K_single : complex
        Dynamic stiffness at omega for A2 alone (A1 = 0, same offset) [N/m],
        from the periodic steady state (quadrature for a stateless model).
    grid : tuple of int or None
        Torus grid (points along theta1, along theta2) of the harmonic
        balance; the quadrature grid of a stateless model; None for the
        time routes.
    harmonics : tuple of int or None
        Harmonics resolved along theta1 and theta2, (N1 - 1) / 2 and
        (N2 - 1) / 2 (None for the time routes).
    residual : float
        Harmonic balance: scaled RMS residual of the collocation equations
        at the end [-]; time routes: the steady-state residual (periodic) or
        the relative change of K_lag between the last two windows [-];
        quadrature: 0.
    converged : bool
        Whether the solve met its tolerance (False only with ``strict=False``).
    iterations : int
        Newton iterations (all grids), cycles or windows marched.
    truncation : float
        Spectral tail of the torus (largest Fourier coefficient in the outer
        third of the harmonics, relative to the state's swing) [-]; 0 for
        the other routes.
    quadrature_error : float
        Relative change of K_lag (and K_rev) between the force quadrature
        grid and every other point of it [-]; 0 where the force is smooth
        on the torus grid (its harmonics are then exact on it).
    samples : int
        Time routes: samples per common period or per window; 0 otherwise.
    min_pressure : float or None
        Lowest chamber pressure on the torus or over the run [Pa] (None
        without chamber pressures).
    message : str
        How the answer was found.
    warnings : tuple of str
        Conditions outside the model's validity or the method's.
    torus : ndarray or None
        Harmonic balance: the converged states on the torus grid, shape
        (n_states, N1, N2), ``torus[:, j, k]`` at theta1 = 2 pi j / N1,
        theta2 = 2 pi k / N2 [state units]; None otherwise.  Read-only.
    """

    model: str
    method: str
    rev_frequency: float
    lag_frequency: float
    rev_amplitude: float
    lag_amplitude: float
    offset: float
    lag_phase: float
    K_lag: complex
    K_rev: complex | None
    K_single: complex
    grid: tuple | None
    harmonics: tuple | None
    residual: float
    converged: bool
    iterations: int
    truncation: float = 0.0
    quadrature_error: float = 0.0
    samples: int = 0
    min_pressure: float | None = None
    message: str = ""
    warnings: tuple = field(default=())
    torus: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.torus is not None:
            self.torus.setflags(write=False)

    @property
    def lag_omega(self) -> float:
        """omega [rad/s]."""
        return 2.0 * math.pi * self.lag_frequency

    @property
    def rev_omega(self) -> float:
        """Omega [rad/s]."""
        return 2.0 * math.pi * self.rev_frequency

    @property
    def storage(self) -> float:
        """Storage stiffness at the lag frequency Re K_lag [N/m]."""
        return self.K_lag.real

    @property
    def loss(self) -> float:
        """Loss stiffness at the lag frequency Im K_lag [N/m]."""
        return self.K_lag.imag

    @property
    def equivalent_damping(self) -> float:
        """Equivalent lag damping Im K_lag / omega [N s/m]."""
        return self.K_lag.imag / self.lag_omega

    @property
    def single_storage(self) -> float:
        """Single-frequency storage stiffness Re K_single [N/m]."""
        return self.K_single.real

    @property
    def single_loss(self) -> float:
        """Single-frequency loss stiffness Im K_single [N/m]."""
        return self.K_single.imag

    @property
    def single_equivalent_damping(self) -> float:
        """Single-frequency equivalent damping Im K_single / omega [N s/m]."""
        return self.K_single.imag / self.lag_omega

    @property
    def damping_ratio(self) -> float:
        """Lag damping under 1/rev motion over the single-frequency one [-]."""
        return self.K_lag.imag / self.K_single.imag

    def as_dict(self) -> dict:
        """JSON-ready point with unit-named keys (SI)."""
        d = {
            "rev_amplitude [m]": self.rev_amplitude,
            "lag_amplitude [m]": self.lag_amplitude,
            "storage [N/m]": self.storage,
            "loss [N/m]": self.loss,
            "equivalent_damping [N s/m]": self.equivalent_damping,
            "magnitude [N/m]": abs(self.K_lag),
            "single_frequency_storage [N/m]": self.single_storage,
            "single_frequency_loss [N/m]": self.single_loss,
            "single_frequency_equivalent_damping [N s/m]": self.single_equivalent_damping,
            "rev_storage [N/m]": None if self.K_rev is None else self.K_rev.real,
            "rev_loss [N/m]": None if self.K_rev is None else self.K_rev.imag,
            "method": self.method,
            "grid": None if self.grid is None else list(self.grid),
            "residual [-]": self.residual,
            "truncation [-]": self.truncation,
            "quadrature_error [-]": self.quadrature_error,
            "converged": self.converged,
            "iterations": self.iterations,
            "min_pressure [Pa]": self.min_pressure,
            "message": self.message,
            "warnings": list(self.warnings),
        }
        return d


# ---------------------------------------------------------------------------- inputs
def check_inputs(model, params, rev_frequency: float, lag_frequency: float,
                 rev_amplitude: float, lag_amplitude: float, *, offset: float = 0.0,
                 lag_phase: float = 0.0, method: str = "harmonic_balance"):
    """Check the inputs of :func:`dual_frequency_stiffness` before any work.

    Parameters
    ----------
    model, params, rev_frequency, lag_frequency, rev_amplitude, lag_amplitude, offset, \
lag_phase, method
        As :func:`dual_frequency_stiffness` (a sweep checks its largest amplitudes).

    Returns
    -------
    model : DeviceModel
    stroke : TwoFrequencyStroke

    Raises
    ------
    ParameterError
        Naming the quantity, its value and what is allowed.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> check_inputs("full", preset("reference"), 4.2, 1.26, 0.02, 0.006)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: two-frequency stroke reaches |y| = |offset| + A1 + A2 = \
0.026 m, past the chamber end at 0.025 m (V0/A_p); allowed: |offset| + A1 + A2 < 0.025 m
    """
    model, stroke = _check_inputs(model, params, rev_frequency, lag_frequency, rev_amplitude,
                                  lag_amplitude, offset, lag_phase)
    check_choice("dual-frequency method", method, METHODS)
    if method == "harmonic_balance" and model.n_states:
        if model.effect("freeplay") is not None:
            raise ParameterError(
                f"model {model.name!r}: the harmonic balance does not take the 'freeplay' "
                "effect: its play operator switches within 0.05 gap + 0.1 um of contact, a "
                "nearly non-smooth law that would need hundreds of harmonics; use "
                "method='time'")
        torus_invariants(model, params)  # volumetric and cavitation raise here
    return model, stroke


def _check_inputs(model, params, f1, f2, A1, A2, y0, phi):
    model = get_model(model)
    f1 = check_positive("rev_frequency", f1, "Hz")
    f2 = check_positive("lag_frequency", f2, "Hz")
    A1 = check_finite("rev_amplitude", A1, "m")
    if A1 < 0.0:
        raise ParameterError(f"rev_amplitude must be >= 0 [m] (0: no 1/rev motion), got {A1:g}")
    A2 = check_positive("lag_amplitude", A2, "m")
    y0 = check_finite("offset", y0, "m")
    phi = check_finite("lag_phase", phi, "rad")
    stroke = TwoFrequencyStroke(A1, f1, A2, f2, offset=y0, phase2=phi)
    if isinstance(params, DeviceParams):
        model.check_params(params)
        limit = params.stroke_limit
        if stroke.max_abs >= limit:
            raise ParameterError(
                f"two-frequency stroke reaches |y| = |offset| + A1 + A2 = {stroke.max_abs:.4g} m, "
                f"past the chamber end at {limit:.4g} m (V0/A_p); allowed: |offset| + A1 + A2 "
                f"< {limit:.4g} m")
    elif isinstance(params, ViscousParams):
        if model.base != "viscous":
            raise ParameterError(f"ViscousParams go with the viscous model, not {model.name!r}")
    else:
        raise ParameterError(f"params must be DeviceParams or ViscousParams, got "
                             f"{type(params).__name__}")
    return model, stroke


def _has_jump(model, params) -> bool:
    """True where the force has a jump on the torus (Coulomb friction)."""
    spec, prm, _ = model.packed(params)
    return bool(spec[K.S_COUL] != 0 or prm[K.P_FRIC] > 0.0)


def _check_quadrature_grid(quadrature_grid):
    try:
        Na, Nb = (int(v) for v in quadrature_grid)
    except (TypeError, ValueError):
        raise ParameterError(f"quadrature_grid must be two even integers, got "
                             f"{quadrature_grid!r}") from None
    for name, v in (("points along the larger-velocity phase", Na),
                    ("points along the other phase", Nb)):
        if v < 16 or v % 2 or v > 1 << 16:
            raise ParameterError(f"quadrature_grid {name} must be an even integer in "
                                 f"[16, 65536], got {v}")
    return Na, Nb


# ---------------------------------------------------------------------------- single frequency
def _single(model, params, stroke: HarmonicStroke, options, samples: int = _GUESS_SAMPLES):
    """(K [N/m], states (n, samples) over one period or None) of a harmonic stroke."""
    from liquidamp.analysis.response.harmonics import dynamic_stiffness
    from liquidamp.coupled.testrig import steady_state

    if model.n_states == 0:
        M = 4096
        t = np.arange(M) * (stroke.period / M)
        y, v, a = stroke(t)
        F = np.asarray(model.force(t, np.zeros((0, M)), (y, v, a), params), float)
        w = 2.0 * math.pi * stroke.frequency
        F1 = 2.0 * np.mean(F * np.sin(w * t)) + 2j * np.mean(F * np.cos(w * t))
        return complex(F1 / (stroke.amplitude * np.exp(1j * stroke.phase))), None
    r = steady_state(model, params, stroke, options=options.replace(samples_per_period=samples))
    return complex(dynamic_stiffness(r).value), np.asarray(r.states)


def _needed(X, floor: int) -> int:
    """Highest harmonic whose amplitude exceeds TAIL_TOL of the state's swing, >= floor."""
    if X is None or X.size == 0:
        return floor
    swing = np.ptp(X, axis=1)
    ok = swing > 1e-12 * (np.max(np.abs(X), axis=1) + 1e-300)
    if not ok.any():
        return floor
    C = 2.0 * np.abs(np.fft.rfft(X[ok], axis=1)) / X.shape[1] / swing[ok, None]
    above = np.nonzero(np.max(C, axis=0)[1:] > TAIL_TOL)[0]
    return max(floor, int(above[-1]) + 1 if above.size else floor)


def _check_grid(grid):
    try:
        N1, N2 = (int(v) for v in grid)
    except (TypeError, ValueError):
        raise ParameterError(f"grid must be two odd integers (points along theta1, theta2), "
                             f"got {grid!r}") from None
    for name, v in (("theta1", N1), ("theta2", N2)):
        if v < 5 or v % 2 == 0 or v > MAX_GRID:
            raise ParameterError(f"grid points along {name} must be an odd integer in "
                                 f"[5, {MAX_GRID}], got {v}")
    return N1, N2


# ---------------------------------------------------------------------------- harmonic balance
def _harmonic_balance(model, params, stroke, options, grid, fine, tol, max_iter, lag_states):
    A1, A2 = stroke.amplitude1, stroke.amplitude2
    W, w = stroke.omega1, stroke.omega2
    what = (f"model {model.name!r}, 1/rev {A1:.4g} m at {stroke.frequency1:g} Hz, lag "
            f"{A2:.4g} m at {stroke.frequency2:g} Hz")
    primary = 1 if A1 * W >= A2 * w else 2
    invariants = torus_invariants(model, params)
    rev_states = None
    if A1 > 0.0:
        _, rev_states = _single(model, params, HarmonicStroke(A1, stroke.frequency1,
                                                                offset=stroke.offset),
                                options)
    if grid is None:
        # the outer third of the harmonics should hold no more than TAIL_TOL of the swing
        # the primary phase carries the nonlinearity: half as many harmonics again; the
        # secondary starts lean (the spectral tail refines it where needed)
        h1 = _needed(rev_states, 3) if A1 > 0.0 else 1
        h2 = _needed(lag_states, 2)
        H1, H2 = ((math.ceil(1.5 * h1), max(3, h2 // 2 + 1)) if primary == 1 else
                  (max(2, h1 // 2 + 1), math.ceil(1.5 * h2)))
        caps, resonance_note = _resonance_caps(stroke, invariants, H1, H2)
        N1, N2 = (min(2 * H1 + 1, caps[0], MAX_GRID), min(2 * H2 + 1, caps[1], MAX_GRID))
    else:
        N1, N2 = grid
        caps, resonance_note = (MAX_GRID, MAX_GRID), ""
    n = model.n_states

    def start(N1, N2):
        lag = _torus.resample(lag_states, N2, axis=1)
        X3 = np.repeat(lag[:, None, :], N1, axis=1)
        if rev_states is not None:
            rev = _torus.resample(rev_states, N1, axis=1)
            X3 = X3 + rev[:, :, None] - lag.mean(axis=1)[:, None, None]
        return X3

    X3 = start(N1, N2)
    iterations = krylov = refinements = 0
    while True:
        Y, V, _ = _torus.grid_strokes(stroke, N1, N2)
        if primary == 1:
            Ya, Va, Xa, wa, wb = Y, V, X3, W, w
        else:
            Ya, Va, Xa, wa, wb = Y.T, V.T, X3.transpose(0, 2, 1), w, W
        Xa = np.ascontiguousarray(Xa).reshape(n, -1)
        swing = state_swing(Xa, np.asarray(model.state_scales(params), float))
        prob = _torus.TorusProblem(model.packed(params), wa, wb, np.ascontiguousarray(Ya),
                                   np.ascontiguousarray(Va), swing, invariants, Xa)
        try:
            Xa, lam, its, residual, kry = prob.solve(Xa, tol=tol, max_iter=max_iter, what=what)
        except _torus.Stalled:
            # an under-resolved grid has no solution near the start: refine, start again
            tails = prob.tail(Xa)
            tail1, tail2 = tails if primary == 1 else tails[::-1]
            grow = _grow(N1, N2, tail1 >= tail2, tail2 > tail1, caps)
            if grid is not None or refinements >= 4 or grow == (N1, N2):
                raise
            N1, N2 = grow
            X3 = start(N1, N2)
            refinements += 1
            continue
        iterations += its
        krylov += kry
        tail_a, tail_b = prob.tail(Xa)
        Xa = Xa.reshape(n, prob.Na, prob.Nb)
        X3 = Xa if primary == 1 else Xa.transpose(0, 2, 1)
        tail1, tail2 = (tail_a, tail_b) if primary == 1 else (tail_b, tail_a)
        if grid is not None or max(tail1, tail2) <= TAIL_TOL or refinements >= 4:
            break
        grow = _grow(N1, N2, tail1 > TAIL_TOL, tail2 > TAIL_TOL, caps)
        if grow == (N1, N2):
            break  # at the largest grid
        X3 = _torus.resample(_torus.resample(X3, grow[0], axis=1), grow[1], axis=2)
        N1, N2 = grow
        refinements += 1
    truncation = max(tail1, tail2)
    Y, V, A = _torus.grid_strokes(stroke, N1, N2)
    X = X3.reshape(n, -1)
    u = (Y.ravel(), V.ravel(), A.ravel())
    warn = []
    quad_err = 0.0
    if _has_jump(model, params):
        K_lag, K_rev, quad_err = _torus.force_quadrature(model, params, stroke, fine, primary, X3)
    else:
        F = np.asarray(model.force(0.0, X, u, params), float).reshape(N1, N2)
        K_lag, K_rev = _torus.harmonics_of(F, stroke)
    pmin = None
    if model.pressures is not None:
        p1, p2 = model.pressures(X, u, params)
        pmin = float(min(np.min(p1), np.min(p2)))
        if pmin < options.vapour_pressure:
            warn.append(f"lowest chamber pressure on the torus {pmin:.4g} Pa is below the "
                        f"vapour pressure {options.vapour_pressure:g} Pa: the liquid would "
                        "cavitate (add the 'cavitation' effect)")
    converged = truncation <= TAIL_TOL
    if resonance_note and not converged:
        warn.append(resonance_note)
    if not converged:
        warn.append(f"torus grid {N1} x {N2} does not resolve the response: spectral tail "
                    f"{truncation:.2e} > {TAIL_TOL:g} of the state swings (give a finer grid)")
    msg = (f"two-frequency harmonic balance on a {N1} x {N2} torus grid ({(N1 - 1) // 2} x "
           f"{(N2 - 1) // 2} harmonics, {refinements} refinement(s)): {iterations} Newton "
           f"iterations, {krylov} GMRES iterations; residual {residual:.2e}, spectral tail "
           f"{truncation:.2e}")
    if quad_err:
        msg += f"; force on a {fine[0]} x {fine[1]} quadrature grid (error {quad_err:.1e})"
    return dict(method="harmonic_balance", K_lag=K_lag, K_rev=K_rev, grid=(N1, N2),
                harmonics=((N1 - 1) // 2, (N2 - 1) // 2), residual=float(residual),
                converged=converged, iterations=iterations, truncation=truncation,
                quadrature_error=quad_err, min_pressure=pmin, message=msg,
                warnings=tuple(warn), torus=np.array(X3))


def _grow(N1: int, N2: int, first: bool, second: bool, caps=(MAX_GRID, MAX_GRID)
          ) -> tuple[int, int]:
    """The grid with about 1.5 times the harmonics along the flagged phases (odd, capped)."""
    out = [N1, N2]
    for k, flag in enumerate((first, second)):
        if flag:
            out[k] = min(2 * math.ceil(0.75 * (out[k] - 1)) + 1, caps[k], MAX_GRID)
    return out[0], out[1]


def _resonance_caps(stroke, invariants, H1: int, H2: int):
    """Largest grid sizes along theta1, theta2 that keep resonant harmonics off the grid.

    Where f1 / f2 = a / b (commensurate), the harmonics (k, l) = j (b, -a) have
    k Omega + l omega = 0: with invariants (neutral modes of the Jacobian) the
    torus is then not unique in them (each closed characteristic keeps its own
    invariant values).  The grid must not hold them: fewer than b harmonics along
    theta1 or fewer than a along theta2, whichever the response needs less.
    Returns ``(caps, note)``; ``note`` is a warning when both were needed.
    """
    ab = stroke.ratio
    if invariants is None or ab is None:
        return (MAX_GRID, MAX_GRID), ""
    a, b = ab
    cap1, cap2 = 2 * (b - 1) + 1, 2 * (a - 1) + 1
    if H2 <= a - 1 and cap2 >= 5:
        return (MAX_GRID, cap2), ""
    if H1 <= b - 1 and cap1 >= 5:
        return (cap1, MAX_GRID), ""
    note = (f"f_rev / f_lag = {a}/{b}: the grid holds fewer harmonics than the response needs "
            f"along one phase, so that the resonant harmonics j ({b}, -{a}) stay off it; "
            "method='time' gives the periodic steady state at this phase")
    if cap2 >= 5 and (cap1 < 5 or H2 - (a - 1) <= H1 - (b - 1)):
        return (MAX_GRID, cap2), note
    if cap1 >= 5:
        return (cap1, MAX_GRID), note
    raise ParameterError(
        f"f_rev / f_lag = {stroke.frequency1:g} / {stroke.frequency2:g} = {a}/{b} is "
        f"commensurate at low order: the harmonics j ({b}, -{a}) resonate (k Omega + l omega "
        "= 0) and the quasi-periodic torus of a device with invariants is not unique there; "
        "use method='time' (the periodic steady state over the common period)")


# ---------------------------------------------------------------------------- public
def dual_frequency_stiffness(model, params, rev_frequency: float, lag_frequency: float,
                             rev_amplitude: float, lag_amplitude: float, *,
                             offset: float = 0.0, lag_phase: float = 0.0,
                             method: str = "harmonic_balance", grid=None,
                             quadrature_grid=QUADRATURE_GRID, options=None,
                             tol: float | None = None,
                             max_iter: int = 40) -> DualFrequencyStiffness:
    """Equivalent dynamic stiffness at the lag frequency under a two-frequency stroke.

    Parameters
    ----------
    model : str or DeviceModel
        Any model of the family, with any effects (``viscous`` with
        :class:`~liquidamp.device.models.ViscousParams`).
    params : DeviceParams or ViscousParams
        Device parameters.
    rev_frequency, lag_frequency : float
        Omega / 2 pi and omega / 2 pi, in (0, 1e4] [Hz].
    rev_amplitude : float
        A1 >= 0 [m] (0: the lag motion alone).
    lag_amplitude : float
        A2 > 0 [m].
    offset : float
        Mean stroke y0 [m]; |y0| + A1 + A2 must stay below the chamber end.
    lag_phase : float
        phi of the lag motion [rad].
    method : {"harmonic_balance", "time"}
        Route (module notes).
    grid : (int, int), optional
        Torus grid of the harmonic balance, odd points along theta1 and
        theta2 in [5, 127]; default: from the spectra of the single-frequency
        states, refined until the spectral tail is below :data:`TAIL_TOL`.
    quadrature_grid : (int, int)
        Even points along the larger-velocity phase and the other of the
        force quadrature (stateless models; forces with a jump).
    options : SolverOptions, optional
        The single-frequency runs and the time route (default: the
        ``"default"`` preset).
    tol : float, optional
        Harmonic balance: largest final Newton step relative to the state
        swings (default 1e-8); time route without a common period: largest
        relative change of K_lag between two windows (default 1e-6).
    max_iter : int
        Newton iterations per grid.

    Returns
    -------
    DualFrequencyStiffness

    Raises
    ------
    ParameterError
        A2 <= 0, A1 < 0, a frequency <= 0 or above 1e4 Hz, a stroke past the
        chamber end, an unknown method, a bad grid, a model without a
        steady state (``volumetric``), or the ``cavitation`` or ``freeplay``
        effect on the harmonic balance (use ``method="time"``).
    ConvergenceError
        The Newton iteration or the time route did not converge (the
        message names the amplitudes and the residual).

    Examples
    --------
    A quadratic damper c2 v|v|: under a large 1/rev motion the lag damping is
    4 c2 V1 / pi (V1 = A1 Omega), against 8 c2 V2 / (3 pi) alone:

    >>> from liquidamp.device.models import VISCOUS, ViscousParams
    >>> r = dual_frequency_stiffness(VISCOUS, ViscousParams(0.0, c2=1e4), 4.2, 1.26,
    ...                              0.003, 1e-5)
    >>> V1 = 0.003 * 2 * math.pi * 4.2
    >>> round(r.equivalent_damping / (4e4 * V1 / math.pi), 3), r.method
    (1.0, 'quadrature')
    >>> V2 = 1e-5 * 2 * math.pi * 1.26
    >>> round(r.single_equivalent_damping / (8e4 * V2 / (3 * math.pi)), 6)
    1.0
    """
    model, stroke = check_inputs(model, params, rev_frequency, lag_frequency, rev_amplitude,
                                 lag_amplitude, offset=offset, lag_phase=lag_phase,
                                 method=method)
    options = resolve_options(options, "default")
    fine = _check_quadrature_grid(quadrature_grid)
    if grid is not None:
        grid = _check_grid(grid)
    if not (isinstance(max_iter, int) and max_iter >= 1):
        raise ParameterError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if tol is not None and not 0.0 < float(tol) < 1.0:
        raise ParameterError(f"tol must lie in (0, 1) [-], got {tol!r}")
    K_single, lag_states = _single(
        model, params, HarmonicStroke(stroke.amplitude2, stroke.frequency2,
                                      offset=stroke.offset, phase=stroke.phase2), options)
    if method == "time":
        out = time_route(model, params, stroke, options, 1e-6 if tol is None else float(tol))
    elif model.n_states == 0:
        primary = 1 if stroke.amplitude1 * stroke.omega1 >= stroke.amplitude2 * stroke.omega2 \
            else 2
        K_lag, K_rev, err = _torus.force_quadrature(model, params, stroke, fine, primary)
        converged = err <= 1e-3
        out = dict(method="quadrature", K_lag=K_lag, K_rev=K_rev,
                   grid=fine if primary == 1 else fine[::-1], harmonics=None,
                   residual=0.0, converged=converged, iterations=0, quadrature_error=err,
                   message=(f"stateless model: force averaged over the torus on a {fine[0]} x "
                            f"{fine[1]} grid (against every other point: {err:.1e})"),
                   warnings=() if converged else (
                       f"force quadrature not converged: {err:.1e} between the grid and "
                       "every other point of it (give a finer quadrature_grid)",))
    else:
        out = _harmonic_balance(model, params, stroke, options, grid, fine,
                                1e-8 if tol is None else float(tol), max_iter, lag_states)
    result = DualFrequencyStiffness(
        model=model.name, rev_frequency=stroke.frequency1, lag_frequency=stroke.frequency2,
        rev_amplitude=stroke.amplitude1, lag_amplitude=stroke.amplitude2, offset=stroke.offset,
        lag_phase=stroke.phase2, K_single=K_single, **out)
    for w in result.warnings:
        warnings.warn(w, LiquidampWarning, stacklevel=2)
    return result
