"""Standalone simulator of the Titurus (2018) liquid damping device, independent of liquidamp.

Nothing here imports liquidamp: the device equations are written from the paper
(/work/shared/seeds/000_a4bdcc3fc7e6399e.txt) and each effect from its textbook physics, in
this file's own formulation (deliberately not liquidamp/device/effects*.py).

Device (paper eq. 10, written as explicit rates):

- chamber i (i = 1, 2) holds a liquid-air mixture of pressure p_i and density rho_i; its
  volume is V_1 = V01 - A_p y_p, V_2 = V02 + A_p y_p (y_p the piston stroke, positive into
  the damper, i.e. chamber 1 shrinks);
- dp_i/dt = B_i(p_i) / V_i (-dV_i/dt - q_out,i) with q_out the volume flow leaving the
  chamber (channel mass flow plus any bypass's mass flow rho_l q, over the chamber's
  density: mass is conserved between the chambers), and
  drho_i/dt = rho_i (dp_i/dt) / B_i(p_i) (eq. 3/8), rho_i(0) = rho_l;
- B(p) is the Gholizadeh liquid-air mixture modulus (eq. 2) with X0 = (1/gamma)/(1 + 1/gamma);
- the channel carries mass flow m (1 -> 2): S_t dm/dt = p1 - p2 - (c1/rho_l) m -
  (c2/rho_l^2) m |m| (eqs. 6 and 9; c1 [kg m^-4 s^-1] and c2 [kg m^-7] are the volume-flow
  coefficients of the paper's Table 2, hence the division by the channel density rho_l);
- the load-cell force is F = A_p (p1 - p2) (+ the force effects), positive when it resists a
  positive stroke.

Effects (one parameter array, zero = off), in this file's formulation:

- Coulomb friction on the rod: F_c v / sqrt(v^2 + v_eps^2) (algebraic regularisation);
- leakage: laminar bypass q = k_leak (p1 - p2) between the chambers;
- relief valve: a spring-loaded poppet in parallel with the channel whose opening grows
  linearly beyond the cracking pressure difference and whose flow follows the orifice law,
  q = G (|dp| - p_c)+ sqrt(|dp| / p_c) sign(dp) (linear in the overpressure just past
  cracking, steeper at high overpressure);
- digressive valve pair: two such poppets, one per direction, with their own cracking
  pressure and conductance;
- freeplay: the rod drives the piston through a dead band of half-width g; the piston
  (mass m_p) floats inside the band under the fluid force and meets the rod through a stiff
  contact spring-damper at each end of the band;
- series compliance: a massless spring k_s between the actuator and the device (the device
  sees y_d with k_s (y - y_d) = A_p (p1 - p2), solved exactly as a rate equation);
- moving mass: F += m d2y/dt2 (a mass between the load cell and the device);
- force offset: F += F0;
- asymmetric loss: in rebound (m < 0) c1 and c2 are multiplied by their own ratios;
- elastomer: F += k_e y + f_M, dF_M/dt = k_M dy/dt - (k_M / c_M) f_M (Maxwell branch);
- end stops: beyond |y| > y_s a contact k_s delta^e (+ c_s delta_dot) pushes back (contact
  only pushes; e = 1 linear, 1.5 Hertzian);
- cavitation: a chamber's pressure cannot fall below the vapour pressure p_v: a vapour
  cavity of volume V_c opens and takes the volume demand while p = p_v, and must collapse
  before the pressure can rise again.

Input: y(t) = mean + Y [sin(w t) + h3 sin(3 w t + phi3)] from rest (times a stepped
amplitude envelope in :func:`simulate_stepped`); fixed-step RK4 at 1e-5 s.

References
----------
B. Titurus, "Generalized liquid-based damping device for passive vibration control",
AIAA J. 56(10), 4134-4145 (2018).
"""
from __future__ import annotations

import math

import numba
import numpy as np

NSTATE = 11  # p1 rho1 p2 rho2 m fM yd yp vp Vc1 Vc2

#: parameter array layout (index -> name); zero switches an effect off
PNAMES = ("inv_gamma1", "inv_gamma2", "c1", "c2", "S_t", "V01", "V02", "A_p", "p0", "B_l",
          "n", "rho_l",
          "Y", "f", "h3", "phi3", "mean",
          "Fc", "v_eps", "k_leak", "pc_relief", "G_relief", "pc_comp", "G_comp",
          "pc_reb", "G_reb", "gap", "m_p", "k_gap", "c_gap", "k_series", "mass", "offset",
          "asym_lin", "asym_quad", "k_e", "k_m", "c_m", "y_stop", "k_stop", "c_stop",
          "e_stop", "p_vap", "valve_linear", "valve_on_loss", "gap_held",
          "n_steps", "step_ratio", "step_cycles")
IX = {k: i for i, k in enumerate(PNAMES)}


@numba.njit(cache=True)
def _bulk(p, B_l, X0, p0, n):
    """Gholizadeh liquid-air mixture tangent modulus B(p) [Pa] (paper eq. 2)."""
    p = max(p, 1.0)
    r = (p0 / p) ** (1.0 / n)
    return B_l * (1.0 - X0 + X0 * r) / (1.0 - X0 + B_l * X0 * r / (n * p))


@numba.njit(cache=True)
def _valve(dp, pc, G, linear):
    """Poppet relief flow [m^3/s] from 1 to 2 for pressure difference dp [Pa]
    (``linear`` > 0: the plain law G (|dp| - pc)+ sign(dp), for checks)."""
    a = abs(dp)
    if G <= 0.0 or a <= pc:
        return 0.0
    q = G * (a - pc) if linear > 0.0 else G * (a - pc) * math.sqrt(a / pc)
    return q if dp > 0.0 else -q


@numba.njit(cache=True)
def _loss_split(m, g1, g2, pc, G, linear, rho):
    """Resistive drop dp_R [Pa] when a valve (pc, G) sits in parallel with the channel's
    loss only (the channel's inertance carries the whole mass flow m): solves
    m_R(dp_R) + rho q_valve(dp_R) = m by bisection on dp_R."""
    target = abs(m)
    lo = 0.0
    hi = g1 * target + g2 * target * target
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        mr = 2.0 * mid / (g1 + math.sqrt(g1 * g1 + 4.0 * g2 * mid))
        if mr + rho * _valve(mid, pc, G, linear) > target:
            hi = mid
        else:
            lo = mid
        if hi - lo < 1e-9 * (hi + 1.0):
            break
    d = 0.5 * (lo + hi)
    return d if m >= 0.0 else -d


@numba.njit(cache=True)
def _envelope(t, P):
    """Amplitude factor of a stepped test and its two time derivatives: n_steps levels
    ratio^k, each step_cycles long, each reached by a half-cycle cosine ramp from the level
    before (the first from 0); no steps: 1."""
    ns = int(P[46])
    if ns <= 0:
        return 1.0, 0.0, 0.0
    f = P[13]
    Ts = P[48] / f
    k = min(int(math.floor(t / Ts)), ns - 1)
    a_k = P[47] ** k
    a_prev = P[47] ** (k - 1) if k > 0 else 0.0
    s = (t - k * Ts) * 2.0 * f
    if s >= 1.0:
        return a_k, 0.0, 0.0
    d = a_k - a_prev
    return (a_prev + d * 0.5 * (1.0 - math.cos(math.pi * s)),
            d * 0.5 * math.pi * math.sin(math.pi * s) * 2.0 * f,
            d * 0.5 * math.pi ** 2 * math.cos(math.pi * s) * 4.0 * f * f)


@numba.njit(cache=True)
def _stroke(t, P):
    w = 2.0 * math.pi * P[13]
    Y = P[12]
    h3 = P[14]
    ph = P[15]
    g = math.sin(w * t) + h3 * math.sin(3.0 * w * t + ph)
    g1 = w * (math.cos(w * t) + 3.0 * h3 * math.cos(3.0 * w * t + ph))
    g2 = -w * w * (math.sin(w * t) + 9.0 * h3 * math.sin(3.0 * w * t + ph))
    e, e1, e2 = _envelope(t, P)
    return (P[16] + Y * e * g, Y * (e1 * g + e * g1), Y * (e2 * g + 2.0 * e1 * g1 + e * g2))


@numba.njit(cache=True)
def _rhs(t, x, P, dx):
    X01 = P[0] / (1.0 + P[0])
    X02 = P[1] / (1.0 + P[1])
    c1 = P[2]
    c2 = P[3]
    St = P[4]
    Ap = P[7]
    p0 = P[8]
    Bl = P[9]
    n = P[10]
    rl = P[11]
    y, v, _ = _stroke(t, P)
    p1, r1, p2, r2, m = x[0], x[1], x[2], x[3], x[4]
    dp = p1 - p2
    # bypass volume flow 1 -> 2
    on_loss = P[44] > 0.0
    qb = P[19] * dp
    if not on_loss:
        qb += _valve(dp, P[20], P[21], P[43])
    if P[23] > 0.0 and dp > 0.0:
        qb += _valve(dp, P[22], P[23], P[43])
    if P[25] > 0.0 and dp < 0.0:
        qb += _valve(dp, P[24], P[25], P[43])
    B1 = _bulk(p1, Bl, X01, p0, n)
    B2 = _bulk(p2, Bl, X02, p0, n)
    # piston kinematics
    ks = P[30]
    gap = P[26]
    for i in range(NSTATE):
        dx[i] = 0.0
    if gap > 0.0:
        yp = x[7]
        vp = x[8]
        rel = y - yp
        fc = 0.0
        if rel > gap:
            fc = P[28] * (rel - gap) + P[29] * (v - vp)
            fc = max(fc, 0.0)
        elif rel < -gap:
            fc = P[28] * (rel + gap) + P[29] * (v - vp)
            fc = min(fc, 0.0)
        if P[45] > 0.0:
            # seal-held piston (play operator): it stays put in the band, follows in contact
            dx[7] = v if (rel >= gap and v > 0.0) or (rel <= -gap and v < 0.0) else 0.0
            vp = dx[7]
        else:
            dx[7] = vp
            dx[8] = (fc - Ap * dp) / P[27]
        vdev = vp
        ydev = yp
    elif ks > 0.0:
        ydev = x[6]
        V1 = P[5] - Ap * ydev
        V2 = P[6] + Ap * ydev
        a1 = B1 / V1
        a2 = B2 / V2
        u1 = (m + rl * qb) / r1
        u2 = (m + rl * qb) / r2
        drift = (y - ydev) - Ap * dp / ks
        vdev = (ks * (v + 200.0 * drift) + Ap * (a1 * u1 + a2 * u2)) / (ks + Ap * Ap * (a1 + a2))
        dx[6] = vdev
    else:
        ydev = y
        vdev = v
    V1 = P[5] - Ap * ydev
    V2 = P[6] + Ap * ydev
    # free-volume rates (volume demand of the fluid in each chamber)
    # the bypass passes the mass rho_l q_b (mass conserved between the chambers)
    r1v = Ap * vdev - (m + rl * qb) / r1     # > 0 compresses chamber 1
    r2v = -Ap * vdev + (m + rl * qb) / r2
    pv = P[42]
    if pv > 0.0:
        # chamber 1
        if x[9] > 0.0 or (p1 <= pv and r1v < 0.0):
            dx[9] = -r1v
            if x[9] <= 0.0 and dx[9] < 0.0:
                dx[9] = 0.0
            r1v = 0.0
        if x[10] > 0.0 or (p2 <= pv and r2v < 0.0):
            dx[10] = -r2v
            if x[10] <= 0.0 and dx[10] < 0.0:
                dx[10] = 0.0
            r2v = 0.0
    dx[0] = B1 / (V1 - x[9]) * r1v
    dx[2] = B2 / (V2 - x[10]) * r2v
    dx[1] = r1 * dx[0] / B1
    dx[3] = r2 * dx[2] / B2
    k1 = c1 / rl
    k2 = c2 / (rl * rl)
    if m < 0.0:
        if P[33] > 0.0:
            k1 *= P[33]
        if P[34] > 0.0:
            k2 *= P[34]
    if on_loss:
        dx[4] = (dp - _loss_split(m, k1, k2, P[20], P[21], P[43], rl)) / St
    else:
        dx[4] = (dp - k1 * m - k2 * m * abs(m)) / St
    if P[37] > 0.0:
        dx[5] = P[36] * v - P[36] / P[37] * x[5]


@numba.njit(cache=True)
def _force(t, x, P):
    y, v, a = _stroke(t, P)
    F = P[7] * (x[0] - x[2])
    if P[17] > 0.0:
        F += P[17] * v / math.sqrt(v * v + P[18] * P[18])
    F += P[31] * a + P[32]
    F += P[35] * y + x[5]
    ys = P[38]
    if ys > 0.0:
        d = abs(y) - ys
        if d > 0.0:
            s = 1.0 if y > 0.0 else -1.0
            fs = P[39] * d ** P[41] + P[40] * v * s
            if fs > 0.0:
                F += s * fs
    return F


@numba.njit(cache=True)
def _run(P, t_start, n_out, dt_out, h):
    x = np.zeros(NSTATE)
    x[0] = P[8]
    x[2] = P[8]
    x[1] = P[11]
    x[3] = P[11]
    if P[26] > 0.0:
        x[7] = P[16]
    if P[30] > 0.0:
        x[6] = P[16]
    k1 = np.empty(NSTATE)
    k2 = np.empty(NSTATE)
    k3 = np.empty(NSTATE)
    k4 = np.empty(NSTATE)
    xt = np.empty(NSTATE)
    out = np.empty((n_out, 3 + NSTATE))
    t = 0.0
    for j in range(n_out):
        t_target = t_start + j * dt_out
        nst = int(math.ceil((t_target - t) / h - 1e-9))
        if nst > 0:
            hh = (t_target - t) / nst
            for _ in range(nst):
                _rhs(t, x, P, k1)
                for i in range(NSTATE):
                    xt[i] = x[i] + 0.5 * hh * k1[i]
                _rhs(t + 0.5 * hh, xt, P, k2)
                for i in range(NSTATE):
                    xt[i] = x[i] + 0.5 * hh * k2[i]
                _rhs(t + 0.5 * hh, xt, P, k3)
                for i in range(NSTATE):
                    xt[i] = x[i] + hh * k3[i]
                _rhs(t + hh, xt, P, k4)
                for i in range(NSTATE):
                    x[i] += hh / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
                    if i >= 9 and x[i] < 0.0:
                        x[i] = 0.0
                t += hh
        y, _, _ = _stroke(t, P)
        out[j, 0] = t
        out[j, 1] = y
        out[j, 2] = _force(t, x, P)
        for i in range(NSTATE):
            out[j, 3 + i] = x[i]
    return out


#: Table 3 reference design and Device B (paper Tables 2-3: initial x calibration x specialisation)
BASE = {
    "reference": {"inv_gamma1": 0.1 * 0.75, "inv_gamma2": 0.1 * 0.75, "c1": 1.0485e9 * 3.56,
                  "c2": 1.3539e14 * 4.04, "S_t": 0.75 / 4e-6},
    "device_b": {"inv_gamma1": 0.1 * 0.75 * 2.0, "inv_gamma2": 0.1 * 0.75 * 2.0,
                 "c1": 1.0485e9 * 3.56 * 0.3,
                 "c2": 1.3539e14 * 4.04 * 0.3, "S_t": 0.75 / 4e-6 * 0.1},
}
COMMON = {"V01": 1.7279e-05, "V02": 1.7279e-05, "A_p": 0.00069115, "p0": 101325.0,
          "B_l": 1551300000.0, "n": 1.35, "rho_l": 998.2}


def device(base: str = "reference", multipliers: dict | None = None, **overrides) -> dict:
    """Device values [SI] (the toolkit's device-file keys) of ``base`` times ``multipliers``."""
    d = {**BASE[base], **COMMON}
    for k, m in (multipliers or {}).items():
        d[k] *= m
    d.update(overrides)
    return d


def simulate(dev: dict, frequency: float, amplitude: float, *, fs: float = 200.0,
             run_cycles: float = 16.0, keep_cycles: float = 10.0, h3: float = 0.01,
             phi3: float = 0.0, mean: float = 0.0, effects: dict | None = None,
             h: float = 1e-5) -> dict:
    """Noise-free record of one sine test: time [s] from 0 at the kept start, stroke [m],
    force [N] and the states (columns of :data:`NSTATE` after the first three)."""
    P = np.zeros(len(PNAMES))
    for k, v in dev.items():
        P[IX[k]] = v
    P[IX["Y"]] = amplitude
    P[IX["f"]] = frequency
    P[IX["h3"]] = h3
    P[IX["phi3"]] = phi3
    P[IX["mean"]] = mean
    P[IX["v_eps"]] = 5e-4
    P[IX["m_p"]] = 0.05
    P[IX["k_gap"]] = 2e7
    P[IX["c_gap"]] = 600.0
    P[IX["e_stop"]] = 1.0
    for k, v in (effects or {}).items():
        P[IX[k]] = v
    T = 1.0 / frequency
    # samples lie on the global grid k / fs from the start; the kept ones from the first
    # sample at or after (run - keep) cycles (as the shared records do)
    t0 = math.ceil((run_cycles - keep_cycles) * T * fs - 1e-6) / fs
    n = int(math.floor((run_cycles * T - t0) * fs + 1e-6)) + 1
    out = _run(P, t0, n, 1.0 / fs, h)
    return {"t": out[:, 0] - t0, "y": out[:, 1], "F": out[:, 2], "states": out[:, 3:]}


def simulate_stepped(dev: dict, frequency: float, amplitude: float, *, steps: int = 3,
                     ratio: float = 2.0, cycles_per_step: float = 4.0, fs: float = 500.0,
                     h3: float = 0.01, phi3: float = 0.0, effects: dict | None = None,
                     h: float = 1e-5) -> dict:
    """Noise-free record of a stepped test from rest, kept whole: the amplitude ``amplitude``
    x ratio^k over ``steps`` steps of ``cycles_per_step`` cycles, each reached by a
    half-cycle cosine ramp (a stroke that does not repeat; a dyno's amplitude series in one
    run).  Effect settings as :func:`simulate`."""
    P = np.zeros(len(PNAMES))
    for k, v in dev.items():
        P[IX[k]] = v
    for k, v in (("Y", amplitude), ("f", frequency), ("h3", h3), ("phi3", phi3),
                 ("v_eps", 5e-4), ("m_p", 0.05), ("k_gap", 2e7), ("c_gap", 600.0),
                 ("e_stop", 1.0), ("n_steps", steps), ("step_ratio", ratio),
                 ("step_cycles", cycles_per_step)):
        P[IX[k]] = v
    for k, v in (effects or {}).items():
        P[IX[k]] = v
    n = int(math.floor(steps * cycles_per_step / frequency * fs + 1e-6)) + 1
    out = _run(P, 0.0, n, 1.0 / fs, h)
    return {"t": out[:, 0], "y": out[:, 1], "F": out[:, 2], "states": out[:, 3:]}


def write_csv(path, t, y, F) -> None:
    """The toolkit's CSV: ``time [s],displacement [mm],force [N]``."""
    with open(path, "w") as f:
        f.write("time [s],displacement [mm],force [N]\n")
        for a, b, c in zip(t, y, F, strict=True):
            f.write(f"{a:.5f},{b * 1e3:.6f},{c:.4f}\n")
