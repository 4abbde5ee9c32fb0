"""Equivalent (describing-function) linearization of the device at finite amplitude.

At rest the quadratic loss dp = c2 q|q| has zero slope and Coulomb friction
has none, so the small-signal transfer functions of
:mod:`liquidamp.analysis.response.linear` drop both.  For a harmonic stroke
y = Y sin(omega t) of finite amplitude each nonlinearity is replaced by the
linear element that dissipates the same energy per cycle under the
first-harmonic motion:

* quadratic loss, q = q_hat sin(.):  c_eq = c1 + 8 c2 q_hat / (3 pi)
  [kg m^-4 s^-1], where the flow amplitude q_hat = |Q(i w)/Y(i w)| Y
  depends on c_eq itself through the transfer function; c_eq is the unique
  root of c - c1 - 8 c2 q_hat(c) / (3 pi) (q_hat falls as c rises), found by
  bracketing (Brent), not by a fixed-point iteration that can oscillate;
* Coulomb friction |F_f| sign(v):  a viscous damper in parallel,
  c_f = 4 |F_f| / (pi omega Y) [N s/m], i.e. i 4 |F_f| / pi added to K*;
* pressure-dependent bulk modulus (eq. 2), optional (``bulk="averaged"``):
  in a sealed chamber of the full model the density is a function of the
  pressure, ln(rho/rho0) = int_{p0}^{p} dp'/B(p'), so each chamber is a
  nonlinear spring p_i(rho_i).  Driven by the stroke its density swings
  nearly harmonically, rho_i/rho0 = 1 + e_i sin(theta), and the spring is
  replaced by its describing function
  B_i,eq = (1/(pi e_i)) int_0^{2 pi} (p_i(rho0 (1 + e_i sin theta)) - p0) sin theta dtheta,
  with e_i = P_i / B_i,eq and the chamber pressure amplitude
  P_i = (B_i,eq/V0i) / (B1,eq/V01 + B2,eq/V02) |dp|, iterated together with
  c_eq.  Air stiffens on compression far more than it softens on expansion,
  so B_eq > B(p0) and the device stiffens with amplitude.  The mean-pressure
  shift (rectification) is not represented.  ``bulk="rest"`` keeps B_i(p0),
  the assumption of eqs. (12)-(18).

The result is the linear eq. (18) (or the Maxwell unit for the models
without inertance) with c1 -> c_eq, B -> B_eq, plus c_f s.

Where it fails (reported in ``valid``/``warnings`` rather than hidden):

* the lowest chamber pressure estimate p0 - max_i P_i approaches zero or the
  vapour pressure: the device cavitates (the inerter preset, with almost no
  air, does so at a few mm and a few Hz); eq. (2) is singular at p = 0;
* large pressure swings: B(p) then changes over the cycle by the reported
  ratio and the force waveform is far from sinusoidal;
* strokes that are a large fraction of the chamber length (V = V0 -/+ A_p y
  changes the compliance over the cycle).

Measured agreement with the first harmonic of the full nonlinear model
(eq. 10), relative error |K_eq - K_NL| / |K_NL| with ``bulk="auto"``
(= averaged for ``full``), frequencies 0.5, 2, 5, 10, 20 Hz (issue #3
report; spot checks in tests/analysis/response/test_equivalent.py; ``--`` not
re-measured after the amplitude continuation was added, ``inv.`` flagged
invalid):

================  ========================  ========================  ========================
preset            Y = 1 mm                  Y = 2 mm                  Y = 3 mm
================  ========================  ========================  ========================
reference         .001 .011 .071 .124 .085  .004 .034 .160 .218 .266  .006 .069 .162 .199 .241
paper_initial     .000 .013 .065 .186 .045  .001 .023 .127  --   --   .002 .033 .145 .156 .156
paper_calibrated  .001 .006 .027 .093 .059  .005 .012 .079 .243 .295  .008 .033 .012 .038 .160
spring            .009 .020 .021 .021 .021  .040 .096 .105 .106 .107  .088 .296 .389 .412 .419
damper            .000 .008 .008 .051 .087  .001 .006 .033 .063 .069  .002 .010 .040 .058 .056
device_a          .001 .018 .089 .028 .023  .003 .045 .256 .274 .132  .005 .075 .215 inv. .977
device_b          .001 .016 .017 .033 .031  .002 .020 .056 .117 .140  .004 .007 .139 .307 .490
inerter (0.5-5)   .000 .000 inv.            .000 .000 inv.            .000 inv. inv.
================  ========================  ========================  ========================

In words: at 0.5-2 Hz within 2 % at 1 mm and within 10 % at 2-3 mm (the
air-rich spring preset 30 % at 3 mm); near and above the channel resonance
(5-20 Hz) the air springs stiffen strongly and the error grows to 10-20 %
at 1 mm and 25-50 % at 2-3 mm.  With B at p0 (``bulk="rest"``) the errors
there are 35-99 %.  Near the stiffening resonance at 3 mm the describing
function can have several solutions (a jump): device_a at 20 Hz 3 mm
returns a valid-looking branch 98 % away from the time-domain steady state
started from rest, and at 10 Hz no solution (``valid`` False).  ``valid``
flags cavitation and a missing solution, not accuracy.  The
lowest-pressure estimate agrees with the nonlinear runs to 1-3 % of p0
at 1 mm.  The inerter preset (almost no air) agrees to 0.3 % even where it
is flagged invalid (inv.): its chambers fall below the vapour pressure
there, which neither model represents, so the agreement is between two
models, not with the device.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (2), (5), (16), (18).
.. [2] A. Gelb and W. E. Vander Velde, Multiple-Input Describing Functions
   and Nonlinear System Design, McGraw-Hill, 1968 (describing functions of
   the quadratic damper, 8/(3 pi), and of Coulomb friction, 4/pi).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import control
import numpy as np
from scipy.optimize import brentq, root

from liquidamp._compat import renamed
from liquidamp.analysis.response.harmonics import DynamicStiffness
from liquidamp.device.fluid import bulk_modulus_gholizadeh
from liquidamp.device.models import get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, check_choice, check_positive
from liquidamp.options import SolverOptions, resolve_options

__all__ = [
    "EquivalentLinearization",
    "equivalent_linearization",
    "equivalent_stiffness",
    "equivalent_transfer_function",
    "quadratic_loss_df",
    "friction_df",
    "BULK_CHOICES",
    "linear_range_amplitude",
]

#: Bulk-modulus treatments: at rest (p0), cycle-averaged compliance, or auto.
BULK_CHOICES = ("auto", "rest", "averaged")

_INERTIAL = ("full", "inertial", "inertial_2state")
_NO_INERTIA = ("no_inertia", "constant_bulk", "volumetric", "single_state")
_LINEAR = ("maxwell", "dashpot", "spring", "dashpot_inerter", "inerter")


def quadratic_loss_df(c1: float, c2: float, flow_amplitude: float) -> float:
    """Equivalent linear loss c1 + 8 c2 q_hat / (3 pi) [kg m^-4 s^-1].

    Same energy per cycle as dp = c1 q + c2 q|q| under q = q_hat sin(wt).

    Examples
    --------
    >>> quadratic_loss_df(0.0, 3 * math.pi / 8, 2.0)
    2.0
    """
    return c1 + 8.0 * c2 * abs(flow_amplitude) / (3.0 * math.pi)


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def friction_df(friction_N: float, frequency: float, amplitude: float) -> float:
    """Equivalent viscous damping of Coulomb friction 4 |F_f| / (pi w Y) [N s/m].

    Examples
    --------
    >>> round(friction_df(30.0, 1.0, 1e-3) * 2 * math.pi * 1e-3 * math.pi / 4, 12)
    30.0
    """
    return 4.0 * friction_N / (math.pi * 2.0 * math.pi * frequency * amplitude)


@dataclass(frozen=True)
class EquivalentLinearization:
    """Amplitude-dependent linear model of a device under y = Y sin(w t).

    Attributes
    ----------
    model : str
        Registered model that was linearized.
    frequency : float
        Excitation frequency [Hz].
    amplitude : float
        Stroke amplitude Y [m].
    stiffness : DynamicStiffness
        K*_eq = K_eq(i w) [N/m] (fluid force plus friction).
    transfer_function : control.TransferFunction
        K_eq(s) from ``'stroke'`` [m] to ``'force'`` [N] with the
        coefficients frozen at this amplitude and frequency (improper if
        friction or a dashpot/inerter element is present).
    c_eq : float
        Equivalent linear loss [kg m^-4 s^-1] (c1 for models without c2).
    c_friction : float
        Equivalent viscous damping of friction [N s/m].
    B : float
        Stiffness factor used, B1/V01 + B2/V02 (rest or averaged) [Pa/m^3].
    B_rest : float
        The same at p0 [Pa/m^3].
    flow_amplitude : float
        Channel flow amplitude q_hat [m^3/s] (0 for the ideal elements).
    dp_amplitude : float
        Differential pressure amplitude |dp| [Pa].
    min_pressure : float
        Estimated lowest chamber pressure p0 - max_i P_i [Pa].
    bulk : str
        ``"rest"`` or ``"averaged"``.
    iterations : int
        Residual evaluations of the bulk-modulus solve (1 for ``"rest"``).
    valid : bool
        False where the estimate is outside its validity (cavitation,
        pressure through zero, no convergence).
    warnings : tuple of str
        Why, in words, and softer cautions (large pressure swings).
    """

    model: str
    frequency: float
    amplitude: float
    stiffness: DynamicStiffness
    transfer_function: control.TransferFunction
    c_eq: float
    c_friction: float
    B: float
    B_rest: float
    flow_amplitude: float
    dp_amplitude: float
    min_pressure: float
    bulk: str
    iterations: int
    valid: bool
    warnings: tuple[str, ...]

    def as_dict(self) -> dict:
        """JSON-ready dictionary with unit-named keys."""
        d = self.stiffness.as_dict()
        d.update({
            "model": self.model,
            "c_eq [kg m^-4 s^-1]": self.c_eq,
            "c_friction [N s/m]": self.c_friction,
            "B [Pa/m^3]": self.B,
            "flow_amplitude [m^3/s]": self.flow_amplitude,
            "dp_amplitude [Pa]": self.dp_amplitude,
            "min_pressure [Pa]": self.min_pressure,
            "bulk": self.bulk,
            "valid": self.valid,
            "warnings": list(self.warnings),
        })
        return d


def _k_and_q(A_p, B, L_t, c, s):
    """Fluid K(s) [N/m] and flow per stroke Q/Y [m^2/s] of linear eq. (18)."""
    den = L_t * s * s + c * s + B
    return A_p * A_p * B * s * (L_t * s + c) / den, A_p * B * s / den


def _pressure_of_density(B_l: float, X0: float, p0: float, n: float):
    """p(lambda), lambda = ln(rho/rho0) = int_{p0}^{p} dp'/B(p') (fixed-mass chamber) [Pa].

    Tabulated on a logarithmic pressure grid (the integrand p/B(p) is smooth
    in ln p) and interpolated monotonically.
    """
    from scipy.integrate import cumulative_simpson
    from scipy.interpolate import PchipInterpolator

    lnp = np.linspace(math.log(p0) - 14.0, math.log(p0) + 12.0, 6001)
    pp = np.exp(lnp)
    integrand = pp / bulk_modulus_gholizadeh(pp, B_l, X0, p0, n)
    lam = cumulative_simpson(integrand, x=lnp, initial=0.0)
    lam -= np.interp(math.log(p0), lnp, lam)
    return PchipInterpolator(lam, lnp, extrapolate=False)


def _bulk_df(strain: float, table, B0: float, p0: float, points: int = 128) -> float:
    """Describing function of p(rho) under rho/rho0 = 1 + strain sin(theta) [Pa].

    B_eq = (1/(pi e)) int (p(1 + e sin) - p0) sin dtheta; NaN if the density
    ratio leaves the table (pressure through ~0).
    """
    if strain <= 0.0:
        return B0
    if strain >= 1.0:
        return math.nan
    th = 2.0 * math.pi * (np.arange(points) + 0.5) / points
    lnp = table(np.log1p(strain * np.sin(th)))
    if not np.all(np.isfinite(lnp)):
        return math.nan
    return float(2.0 * np.mean((np.exp(lnp) - p0) * np.sin(th)) / strain)


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def equivalent_linearization(params: DeviceParams, frequency: float, amplitude: float,
                             model: str = "inertial_2state", *, bulk: str = "auto",
                             options: SolverOptions | None = None
                             ) -> EquivalentLinearization:
    """Equivalent linearization of ``model`` at stroke amplitude Y and frequency f.

    Parameters
    ----------
    params : DeviceParams
        Device (friction enters through its describing function).
    frequency : float
        Excitation frequency f > 0 [Hz].
    amplitude : float
        Stroke amplitude 0 < Y < V0/A_p [m].
    model : str
        Registered model whose equivalent linearization is wanted: the
        inertial models (``full``, ``inertial``, ``inertial_2state``) give
        eq. (18) with c_eq; the models without inertance (``no_inertia``,
        ``constant_bulk``, ``volumetric``, ``single_state``) the Maxwell unit
        with c_eq; the linear ones (``maxwell``, ``dashpot``, ``spring``,
        ``dashpot_inerter``, ``inerter``) their own transfer function (they
        have no c2); every one adds friction.
    bulk : {"auto", "rest", "averaged"}
        Bulk modulus: at p0 (``rest``) or cycle-averaged compliance
        (``averaged``, module notes).  ``auto`` averages for the models that
        follow ``params.bulk_law`` (``full``, ``no_inertia``) and uses p0
        for the constant-bulk reductions (what those models assume).
    options : SolverOptions, optional
        Only ``vapour_pressure`` [Pa] is used (cavitation check); default the
        ``"default"`` preset of :data:`liquidamp.options.PRESETS`.

    Returns
    -------
    EquivalentLinearization

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> e = equivalent_linearization(p, 3.0, 0.001, "inertial_2state")
    >>> e.valid, e.c_eq > p.c1          # the quadratic loss adds resistance
    (True, True)
    >>> small = equivalent_linearization(p, 3.0, 1e-9, "inertial_2state")
    >>> round(small.c_eq / p.c1, 4)     # vanishing amplitude: the linear loss
    1.0
    """
    p = params
    if not isinstance(p, DeviceParams):
        raise ParameterError(f"params must be DeviceParams, got {type(p).__name__}")
    m = get_model(model)
    m.check_params(p)
    f = check_positive("frequency", frequency, "Hz")
    Y = check_positive("amplitude", amplitude, "m")
    if Y >= p.stroke_limit:
        raise ParameterError(f"amplitude {Y:g} m reaches the chamber end; allowed: "
                             f"0 < amplitude < {p.stroke_limit:g} m (V0/A_p)")
    check_choice("bulk", bulk, BULK_CHOICES)
    opts = resolve_options(options, "default")
    if bulk == "auto":
        bulk = "averaged" if (m.uses_bulk_law and p.bulk_law == "gholizadeh") else "rest"
    w = 2.0 * math.pi * f
    s = 1j * w
    c_f = friction_df(p.friction_N, f, Y) if p.friction_N > 0 else 0.0
    warns: list[str] = []
    valid = True
    B_rest = p.B_eff
    A_p = p.A_p

    if m.name in _LINEAR:
        lin = {"maxwell": ([p.k_D * p.T_D, 0.0], [p.T_D, 1.0]),
               "dashpot": ([p.c_L, 0.0], [1.0]),
               "spring": ([p.k_D], [1.0]),
               "dashpot_inerter": ([p.b_L, p.c_L, 0.0], [1.0]),
               "inerter": ([p.b_L, 0.0, 0.0], [1.0])}[m.name]
        num, den = np.asarray(lin[0], float), np.asarray(lin[1], float)
        K_fluid = complex(np.polyval(num, s) / np.polyval(den, s))
        c_eq, B, q_hat, iters = p.c1, B_rest, 0.0, 1
        if m.name == "maxwell":
            q_hat = abs(K_fluid) * Y / (A_p * p.c1)  # q = dp / c1
    else:
        L_t = p.L_t if m.name in _INERTIAL else 0.0
        B1, B2 = p.B01, p.B02
        B1, B2 = p.B01, p.B02

        def solve_c(B, Y=Y):
            """Unique root of c = c1 + 8 c2 q_hat(c) / (3 pi) (q_hat falls as c rises)."""
            if p.c2 == 0.0:
                return p.c1

            def resid(c):
                return c - quadratic_loss_df(p.c1, p.c2, abs(_k_and_q(A_p, B, L_t, c, s)[1]) * Y)

            lo = max(p.c1, 1e-300)
            hi = quadratic_loss_df(p.c1, p.c2, abs(_k_and_q(A_p, B, L_t, lo, s)[1]) * Y)
            if resid(hi) == 0.0 or hi == lo:
                return hi
            return brentq(resid, lo, hi, xtol=1e-14 * hi, rtol=1e-13, maxiter=200)

        ln_rest = np.log([B1, B2])

        def bulk_map(lnB, Y=Y):
            """ln B_i,eq(e_i) - ln B_i for the trial ln B_i (both chambers).

            Trial points far from the rest value (a factor e^20) or where the
            loss solve fails are pushed back by a finite penalty so the root
            finder never sees NaN or overflow.
            """
            lnB = np.asarray(lnB, float)
            if not np.all(np.isfinite(lnB)) or np.max(np.abs(lnB - ln_rest)) > 20.0:
                return 10.0 * np.nan_to_num(lnB - ln_rest, nan=100.0)
            b1, b2 = np.exp(lnB)
            B = b1 / p.V01 + b2 / p.V02
            try:
                K_f, _ = _k_and_q(A_p, B, L_t, solve_c(B, Y), s)
            except ValueError:
                return 10.0 * (lnB - ln_rest) + 100.0
            dp = abs(K_f) * Y / A_p
            n1 = _bulk_df((b1 / p.V01) / B * dp / b1, tables[0], p.B01, p.p0)
            n2 = _bulk_df((b2 / p.V02) / B * dp / b2, tables[1], p.B02, p.p0)
            if not (math.isfinite(n1) and math.isfinite(n2)):
                return 10.0 * (lnB - ln_rest) + 100.0
            return np.log([n1, n2]) - lnB

        iters = 1
        if bulk == "averaged":
            tables = [_pressure_of_density(p.B_l, X0, p.p0, p.n) for X0 in (p.X01, p.X02)]
            sol = root(bulk_map, np.log([B1, B2]), method="hybr", options={"xtol": 1e-12})
            r = bulk_map(sol.x)
            iters = int(sol.nfev)
            if not (sol.success and np.max(np.abs(r)) < 1e-9):
                # continuation in the amplitude from the small-signal solution
                z = np.log([B1, B2])
                for frac in np.linspace(0.125, 1.0, 8):
                    sol = root(bulk_map, z, args=(Y * frac,), method="hybr",
                               options={"xtol": 1e-12})
                    iters += int(sol.nfev)
                    if not sol.success:
                        break
                    z = sol.x
                r = bulk_map(sol.x)
            if sol.success and np.max(np.abs(r)) < 1e-9:
                B1, B2 = np.exp(sol.x)
            else:
                valid = False
                warns.append(
                    "no amplitude-dependent bulk modulus found (the chamber pressure swing "
                    "takes the pressure near 0 over part of the cycle, where eq. (2) is "
                    "singular, or the stiffening chambers fold the response near the "
                    "resonance -- a jump, several solutions -- and the continuation in the "
                    f"amplitude stalled: {' '.join(sol.message.split())}); B at p0 used")
        c_eq = solve_c(B1 / p.V01 + B2 / p.V02)
        B = B1 / p.V01 + B2 / p.V02
        K_fluid, q_per_y = _k_and_q(A_p, B, L_t, c_eq, s)
        q_hat = abs(q_per_y) * Y
        num = [A_p**2 * B * L_t, A_p**2 * B * c_eq, 0.0]
        den = [L_t, c_eq, B]
        if L_t == 0.0:
            num, den = num[1:], den[1:]
        num, den = np.asarray(num, float), np.asarray(den, float)

    # friction in parallel: + c_f s
    if c_f > 0.0:
        num = np.polyadd(num, np.polymul([c_f, 0.0], den))
    K = complex(np.polyval(num, s) / np.polyval(den, s))
    tf = control.tf(num.tolist(), den.tolist(), inputs="stroke", outputs="force",
                    name=f"{m.name}_eq")
    dp_hat = abs(K_fluid) * Y / A_p
    Bw1 = p.B01 / p.V01 if bulk == "rest" or m.name in _LINEAR else B1 / p.V01
    Bw2 = p.B02 / p.V02 if bulk == "rest" or m.name in _LINEAR else B2 / p.V02
    P_max = max(Bw1, Bw2) / (Bw1 + Bw2) * dp_hat
    p_min = p.p0 - P_max
    if bulk == "averaged" and m.name not in _LINEAR:
        # the nonlinear chamber spring: lowest pressure at the largest expansion
        lows = []
        for Bw, Bi, table in ((Bw1, B1, tables[0]), (Bw2, B2, tables[1])):
            e = Bw / (Bw1 + Bw2) * dp_hat / Bi
            lnp = table(math.log1p(-e)) if e < 1.0 else math.nan
            lows.append(math.exp(lnp) if math.isfinite(lnp) else 0.0)
        p_min = min(lows)
    if m.name in ("dashpot", "spring", "dashpot_inerter", "inerter"):
        p_min = p.p0 - 0.5 * dp_hat  # ideal elements: symmetric split of the force
    if p_min <= 0.0:
        valid = False
        warns.append(f"estimated lowest chamber pressure {p_min:.4g} Pa is not positive: the "
                     "linearization is meaningless here (the device cavitates)")
    elif p_min < opts.vapour_pressure:
        valid = False
        warns.append(f"estimated lowest chamber pressure {p_min:.4g} Pa is below the vapour "
                     f"pressure {opts.vapour_pressure:g} Pa: the liquid cavitates, which no "
                     "linear model represents")
    elif p_min < 0.5 * p.p0 and p.bulk_law == "gholizadeh":
        ratio = (bulk_modulus_gholizadeh(p.p0 + P_max, p.B_l, max(p.X01, p.X02), p.p0, p.n)
                 / bulk_modulus_gholizadeh(p_min, p.B_l, max(p.X01, p.X02), p.p0, p.n))
        warns.append(f"pressure swing +-{P_max:.3g} Pa: the bulk modulus (eq. 2) varies by a "
                     f"factor {ratio:.3g} over the cycle; the linearization is approximate")
    if Y > 0.2 * p.stroke_limit:
        warns.append(f"stroke {Y:g} m is {Y / p.stroke_limit:.0%} of the chamber length: the "
                     "chamber volumes change markedly over the cycle")
    return EquivalentLinearization(
        model=m.name, frequency=f, amplitude=Y,
        stiffness=DynamicStiffness(frequency=f, amplitude=Y, value=K), transfer_function=tf,
        c_eq=float(c_eq), c_friction=float(c_f), B=float(B), B_rest=float(B_rest),
        flow_amplitude=float(q_hat), dp_amplitude=float(dp_hat), min_pressure=float(p_min),
        bulk=bulk, iterations=int(iters), valid=valid, warnings=tuple(warns))


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def equivalent_stiffness(params: DeviceParams, frequency: float, amplitude: float,
                         model: str = "inertial_2state", *, bulk: str = "auto"
                         ) -> DynamicStiffness:
    """Dynamic stiffness K*_eq(f; Y) of the equivalent linearization [N/m].

    Shorthand for ``equivalent_linearization(...).stiffness``; check
    ``equivalent_linearization(...).valid`` where cavitation is possible.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> K = equivalent_stiffness(preset("damper"), 2.0, 0.001)
    >>> 80 < K.phase_deg < 90          # the damper preset: nearly a pure damper
    True
    """
    return equivalent_linearization(params, frequency, amplitude, model,
                                    bulk=bulk).stiffness


@renamed(amplitude_m="amplitude", frequency_hz="frequency")
def equivalent_transfer_function(params: DeviceParams, *, amplitude: float,
                                 frequency: float, model: str = "inertial_2state",
                                 bulk: str = "auto") -> control.TransferFunction:
    """K_eq(s) frozen at (Y, f): input ``'stroke'`` [m], output ``'force'`` [N].

    Amplitude and frequency are keyword-only (they are easy to swap).  The
    coefficients hold at this amplitude and frequency only; the TF is
    improper when friction is present (+ c_f s).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> tf = equivalent_transfer_function(preset("reference"), amplitude=0.002,
    ...                                   frequency=3.0)
    >>> tf.input_labels, tf.output_labels
    (['stroke'], ['force'])
    """
    return equivalent_linearization(params, frequency, amplitude, model,
                                    bulk=bulk).transfer_function


@renamed(frequency_hz="frequency")
def linear_range_amplitude(params: DeviceParams, frequency: float, fraction: float = 0.1
                           ) -> float:
    """Stroke amplitude at which the quadratic loss adds ``fraction`` to c1 [m].

    Solves 8 c2 q_hat / (3 pi c1) = fraction with the flow of the linear
    eq. (18) at rest, q_hat = |Q(i w)/Y| Y.  Below it the small-signal
    transfer function is accurate to about ``fraction`` (the describing
    function of the quadratic loss is O(Y)); inf when c2 = 0.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> Y = linear_range_amplitude(p, 5.0, 0.1)
    >>> e = equivalent_linearization(p, 5.0, Y, "inertial_2state")
    >>> bool(1.0 < e.c_eq / p.c1 < 1.1)
    True
    """
    check_positive("frequency", frequency, "Hz")
    check_positive("fraction", fraction, "-")
    if params.c2 == 0.0:
        return math.inf
    if params.c1 == 0.0:
        raise ParameterError("c1 = 0: the small-signal loss vanishes; no linear range")
    L_t = params.L_t
    _, qy = _k_and_q(params.A_p, params.B_eff, L_t, params.c1, 2j * math.pi * frequency)
    return fraction * 3.0 * math.pi * params.c1 / (8.0 * params.c2 * abs(qy))
