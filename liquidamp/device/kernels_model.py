"""The compiled composed models: a base model with its add-on effects (the ``spec``
slots of :mod:`liquidamp.device.kernels_layout`): right-hand side, Jacobian, time
derivative and load-cell force.  Part of :mod:`liquidamp.device.kernels` (the public
face, which re-exports every name; references there).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.device.kernels_base import (
    base_force,
    base_jac,
    base_rhs,
    base_rhs_inline,
    base_rhs_t,
    state_force,
)
from liquidamp.device.kernels_laws import (
    _fd_step,
    _lugre_dz_dv,
    _sign,
    bulk,
    cavity_rates,
    compliance_rate,
    elastomer_rate,
    float_contact,
    friction_level,
    gas_force,
    gas_pressure,
    gas_slope,
    lugre_rate,
    piston_contact,
    play_contact,
    relief_force,
    rotating_heads,
    rotating_offset_slopes,
    rotating_slope,
    slip_memory_rate,
    stop_force,
    valve_flow,
    weakening,
    yield_drop,
)
from liquidamp.device.kernels_layout import (
    _FM,
    E_AR,
    E_C1E,
    E_CF,
    E_CLR,
    E_CRQ,
    E_CS,
    E_CTR,
    E_DPY0,
    E_DPY1,
    E_ETA,
    E_FEX,
    E_FRQ,
    E_FYCH,
    E_GAP,
    E_GR,
    E_GR2,
    E_K0,
    E_K1,
    E_KC,
    E_KCG,
    E_KS,
    E_LEAK,
    E_MASS,
    E_MEPS,
    E_NG,
    E_OFF,
    E_PAT,
    E_PCH,
    E_PR,
    E_PR2,
    E_PV,
    E_RR,
    E_SFC,
    E_SIG,
    E_SR,
    E_TAMB,
    E_TC,
    E_THA,
    E_TREF,
    E_VG,
    E_VS,
    E_WB,
    E_WD,
    E_Y0G,
    M_CONSTANT_BULK,
    M_DASHPOT,
    M_DASHPOT_INERTER,
    M_FULL,
    M_INERTIAL,
    M_INERTIAL_2STATE,
    M_MAXWELL,
    M_NO_INERTIA,
    M_SINGLE_STATE,
    M_VISCOUS,
    M_VOLUMETRIC,
    N_CH,
    N_EP,
    P_AP,
    P_B01,
    P_B02,
    P_BLM,
    P_C1,
    P_C2,
    P_CH,
    P_CHD,
    P_CL,
    P_CV,
    P_CV2,
    P_FRIC,
    P_G1,
    P_G2,
    P_KD,
    P_LT,
    P_RHO0,
    P_ST,
    P_TD,
    P_V01,
    P_V02,
    P_X01,
    P_X02,
    S_ANALYTIC,
    S_ASYM,
    S_COUL,
    S_CPIST,
    S_FPFRIC,
    S_FY,
    S_GAS,
    S_GROOVE,
    S_I1,
    S_I2,
    S_IC,
    S_ICAV,
    S_IEL,
    S_IFP,
    S_IW,
    S_IZ,
    S_LEAK,
    S_MASS,
    S_MID,
    S_N,
    S_NB,
    S_OFF,
    S_RELIEF,
    S_ROT,
    S_STOP,
    S_TH,
    S_ZPIST,
)
from liquidamp.device.kernels_position import groove_ep_scale, groove_rate_terms
from liquidamp.device.kernels_thermal import (
    channel_power,
    heat_rate,
    law_temperature,
    thermal_params,
)

drop_stale(__file__)  # before any kernel of this module loads from the cache


# -------------------------------------------------------- composed models
@njit(cache=True, error_model="numpy")
def flow_direction(mid, spec, x, v, dpc=0.0):
    """Sign of the channel flow (compression > 0, rebound < 0) of base ``mid`` [-].

    The channel mass flow where it is a state (``full``, ``inertial``), the
    volumetric flow (``inertial_2state``), the pressure difference it follows
    (``no_inertia``, ``constant_bulk``, ``volumetric``, ``single_state``),
    the Maxwell force, or the piston velocity ``v`` (stateless bases).
    """
    if mid == M_FULL:
        d = x[4]
    elif mid == M_INERTIAL or mid == M_INERTIAL_2STATE:
        d = x[2] if mid == M_INERTIAL else x[1]
    elif mid == M_NO_INERTIA or mid == M_CONSTANT_BULK or mid == M_VOLUMETRIC:
        d = x[spec[S_I1]] - x[spec[S_I2]] + dpc
    elif mid == M_SINGLE_STATE:
        d = x[0] + dpc
    elif mid == M_MAXWELL:
        d = x[0]
    else:
        d = v
    return 1.0 if d > 0.0 else (-1.0 if d < 0.0 else 0.0)


@njit(cache=True, error_model="numpy")
def loss_params(spec, x, v, prm, ep, dpc=0.0):
    """Copy of ``prm`` with the channel's loss coefficients of the flow's direction.

    In rebound (:func:`flow_direction` < 0) c1, c2, g1, g2, c_L, the viscous
    c and T_D (= c1 / B) are multiplied by the rebound ratio ``ep[E_RR]``;
    piecewise constant, so the analytic Jacobian stays exact off zero flow.
    """
    q = prm.copy()
    if flow_direction(spec[S_MID], spec, x, v, dpc) < 0.0:
        r = ep[E_RR]
        for k in (P_G1, P_G2, P_C1, P_C2, P_CL, P_CV, P_TD):
            q[k] = q[k] * r
    return q


@njit(cache=True, error_model="numpy")
def channel_params(spec, x, y, v, prm, ep, dpc=0.0):
    """Copy of ``prm`` with the channel's loss coefficients at piston stroke y [m] and the
    flow's direction: :func:`loss_params`' rebound ratio (``S_ASYM``) times the bypass
    groove's scale s(y) (``S_GROOVE``, :func:`~.kernels_position.groove_scale`) on c1, c2,
    g1, g2, c_L, the viscous c and c2, and T_D."""
    s = 1.0
    if spec[S_ASYM] != 0 and flow_direction(spec[S_MID], spec, x, v, dpc) < 0.0:
        s = ep[E_RR]
    if spec[S_GROOVE] > 0:
        s *= groove_ep_scale(y, ep)[0]
    q = prm.copy()
    if s != 1.0:
        for k in (P_G1, P_G2, P_C1, P_C2, P_CL, P_CV, P_CV2, P_TD):
            q[k] = q[k] * s
    return q


@njit(cache=True, error_model="numpy")
def _scaled_losses(spec):
    """Whether the channel's loss coefficients change along the cycle (rebound ratio,
    bypass groove): :func:`channel_params` is then needed."""
    return spec[S_ASYM] != 0 or spec[S_GROOVE] > 0


@njit(cache=True, error_model="numpy")
def _valve(dp, ep):
    """Flow of the valve in the ``S_RELIEF`` slot at pressure difference dp [m^3/s]: its
    compression pair (E_PR, E_GR) for dp >= 0, its rebound pair (E_PR2, E_GR2) below
    (:func:`valve_flow`; equal pairs for ``relief_valve``)."""
    return valve_flow(dp, ep[E_PR], ep[E_GR], ep[E_PR2], ep[E_GR2])


@njit(cache=True, error_model="numpy")
def _relief_differential(mid, x, y, prm, ep, dpc, out):
    """The relief flow in the differential and linear models (eqs. 15, 16, 18)."""
    Ap = prm[P_AP]
    if mid == M_MAXWELL:  # dF/dt = A_p B (A_p v - q - q_r), k_D = A_p^2 B
        out[0] -= prm[P_KD] / Ap * _valve(x[0] / Ap, ep)
    elif mid == M_SINGLE_STATE or mid == M_INERTIAL_2STATE:
        B = prm[P_B01] / (prm[P_V01] - Ap * y) + prm[P_B02] / (prm[P_V02] + Ap * y)
        out[0] -= B * _valve(x[0] + dpc, ep)


@njit(cache=True, error_model="numpy")
def _damper_force(spec, y, v, prm, ep):
    """Force of a stateless dashpot-type base (dashpot, dashpot_inerter's dashpot, viscous)
    at piston stroke (y, v) with the rebound ratio, the bypass groove's scale and the
    relief valve as an exact force saturation [N] (the viscous damper is read as a dashpot
    of unit piston area; its quadratic c2 v|v| scales with the groove too)."""
    c2 = 0.0
    if spec[S_MID] == M_VISCOUS:
        c, area = prm[P_CV], 1.0
        c2 = prm[P_CV2]
    else:
        c, area = prm[P_CL], prm[P_AP]
    if spec[S_ASYM] != 0 and v < 0.0:
        c *= ep[E_RR]
    if spec[S_GROOVE] > 0:
        g = groove_ep_scale(y, ep)[0]
        c *= g
        c2 *= g
    if spec[S_RELIEF] != 0 and c > 0.0:
        if v >= 0.0:
            return relief_force(v, c, ep[E_PR] * area, ep[E_GR] / (area * area))
        return relief_force(v, c, ep[E_PR2] * area, ep[E_GR2] / (area * area))
    return c * v + c2 * v * abs(v)


@njit(cache=True, error_model="numpy")
def _field_yield(mid, x, ify, prm, ep, out):
    """Field-dependent yield (``field_yield``): the channel's momentum balance loses the
    yield drop :func:`yield_drop` at the lagged field u_f = x[ify], whose rate
    eta (u - u_f) follows the measured input u (``prm[P_CH + k]``, k = ``ep[E_FYCH]``)."""
    uf = x[ify]
    u = prm[P_CH + int(ep[E_FYCH])]
    out[ify] = ep[E_ETA] * (u - uf)
    if mid == M_FULL:
        out[4] -= yield_drop(x[4], uf, ep[E_DPY0], ep[E_DPY1], ep[E_MEPS]) / prm[P_ST]
    elif mid == M_INERTIAL:
        out[2] -= yield_drop(x[2], uf, ep[E_DPY0], ep[E_DPY1], ep[E_MEPS]) / prm[P_ST]
    elif mid == M_INERTIAL_2STATE:  # volumetric flow q: mass flow rho0 q, inertance L_t
        out[1] -= yield_drop(prm[P_RHO0] * x[1], uf, ep[E_DPY0], ep[E_DPY1],
                             ep[E_MEPS]) / prm[P_LT]


@njit(cache=True, error_model="numpy")
def _field_yield_jac(mid, x, ify, prm, ep, J):
    """The field yield's entries of the analytic Jacobian (:func:`_field_yield`)."""
    uf = x[ify]
    meps = ep[E_MEPS]
    dpy = ep[E_DPY0] + ep[E_DPY1] * abs(uf)
    su = 1.0 if uf > 0.0 else (-1.0 if uf < 0.0 else 0.0)
    J[ify, ify] = -ep[E_ETA]
    if mid == M_FULL or mid == M_INERTIAL:
        i = 4 if mid == M_FULL else 2
        th = math.tanh(x[i] / meps)
        J[i, i] -= dpy * (1.0 - th * th) / meps / prm[P_ST]
        J[i, ify] -= ep[E_DPY1] * su * th / prm[P_ST]
    elif mid == M_INERTIAL_2STATE:
        r = prm[P_RHO0]
        th = math.tanh(r * x[1] / meps)
        J[1, 1] -= dpy * (1.0 - th * th) * r / meps / prm[P_LT]
        J[1, ify] -= ep[E_DPY1] * su * th / prm[P_LT]


@njit(cache=True, error_model="numpy")
def _fluid_rhs(spec, x, y, v, prm, ep, out):
    """Base model with the fluid effects (leakage, rotating frame, cavitation) at piston
    stroke (y, v)."""
    mid = spec[S_MID]
    kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
    dpc = 0.0
    o1 = 0.0
    o2 = 0.0
    if spec[S_ROT] > 0:
        dpc, o1, o2 = rotating_heads(y, prm, ep)
    i1 = spec[S_I1]
    if spec[S_RELIEF] != 0 and i1 >= 0:  # a second path beside the channel, driven like
        dp = x[i1] - x[spec[S_I2]] + dpc  # it: its secant conductance joins the leakage's
        if dp != 0.0:
            kL += _valve(dp, ep) / dp
    if _scaled_losses(spec):
        base_rhs(mid, x, y, v, channel_params(spec, x, y, v, prm, ep, dpc), kL, dpc, out)
    else:
        base_rhs(mid, x, y, v, prm, kL, dpc, out)
    if spec[S_RELIEF] != 0 and i1 < 0:
        _relief_differential(mid, x, y, prm, ep, dpc, out)
    ify = spec[S_FY]
    if ify >= 0:
        _field_yield(mid, x, ify, prm, ep, out)
    ic = spec[S_ICAV]
    if ic >= 0:
        i2 = spec[S_I2]
        Ap = prm[P_AP]
        V1 = prm[P_V01] - Ap * y
        V2 = prm[P_V02] + Ap * y
        if mid == M_FULL or mid == M_NO_INERTIA:
            B1 = bulk(x[i1], prm[P_X01], prm)
            B2 = bulk(x[i2], prm[P_X02], prm)
        else:
            B1, B2 = prm[P_B01], prm[P_B02]
        pv = ep[E_PV]
        # the cavity opens where the pressure is least: in a rotating frame the inboard end,
        # whose pressure p_i + o_i(y) changes at dp_i/dt + (do_i/dy) v; the switch acts on it
        s1 = 0.0
        s2 = 0.0
        if spec[S_ROT] > 0:
            s1, s2 = rotating_offset_slopes(y, prm, ep)
            s1 *= v
            s2 *= v
        if spec[S_GAS] != 0:  # the charge raises both chambers' level: the states are
            # about the filling pressure p0, the chambers sit p_g(y) above them, so the
            # cavity switch sees p_i + p_g(y) (the piston stroke stands for the rod's here)
            yg = y + ep[E_Y0G]
            pch = _charge(spec, x, prm, ep)
            pg = gas_pressure(yg, ep[E_AR], pch, ep[E_VG], ep[E_NG], ep[E_PAT])
            sg = gas_slope(yg, ep[E_AR], pch, ep[E_VG], ep[E_NG], ep[E_PAT]) * v
            o1 += pg
            o2 += pg
            s1 += sg
            s2 += sg
        # the liquid fills V_i - Vc_i: its mass m_i at its pressure-curve density r_i(p_i)
        # (m_i = rho_i V_i on the bases with density states, r_i(p_i) (V_i - Vc_i) on the
        # others), so the compression rate the switch splits between the pressure and the
        # cavity is that of the liquid volume, u_i = d ln m_i/dt - (dV_i/dt) / (V_i - Vc_i),
        # times B_i; then dp_i/B_i - dVc_i/(V_i - Vc_i) = u_i for any share, and
        # rho_i V_i = r_i(p_i) (V_i - Vc_i) holds exactly (with the base's rate over V_i
        # the chambers' liquid drifted off its pressure curve while a cavity was open, a
        # slow mode that kept the orbit from settling for hundreds of cycles)
        Vl1 = V1 - x[ic]
        Vl2 = V2 - x[ic + 1]
        if mid == M_FULL or mid == M_NO_INERTIA:
            a1 = out[i1] + B1 * Ap * v * x[ic] / (V1 * Vl1)
            a2 = out[i2] - B2 * Ap * v * x[ic + 1] / (V2 * Vl2)
        else:
            a1 = out[i1] * V1 / Vl1
            a2 = out[i2] * V2 / Vl2
        dp1, dc1 = cavity_rates(x[i1] + o1, a1 + s1, x[ic], Vl1, B1, pv)
        dp2, dc2 = cavity_rates(x[i2] + o2, a2 + s2, x[ic + 1], Vl2, B2, pv)
        out[i1] = dp1 - s1
        out[i2] = dp2 - s2
        out[ic] = dc1
        out[ic + 1] = dc2


@njit(cache=True, error_model="numpy")
def _charge(spec, x, prm, ep):
    """Gauge charge pressure of the gas at its reference volume [Pa]: ``ep[E_PCH]``, or, with
    self-heating, the gas at the fluid's temperature T (isochoric, ideal gas):
    (p_c + p_a) T / T_ref - p_a."""
    ith = spec[S_TH]
    if ith < 0:
        return ep[E_PCH]
    T = law_temperature(x[ith], prm, ep)
    return (ep[E_PCH] + ep[E_PAT]) * T / ep[E_TREF] - ep[E_PAT]


@njit(cache=True, error_model="numpy")
def _fp_contact(spec, x, y, v, ep):
    """Contact factor of the freeplay (needs ``spec[S_IFP] >= 0``) [-].

    :func:`play_contact`, or :func:`piston_contact` where smooth friction
    sits behind the dead band (its loaded bristles hold the contact).
    """
    e = y - x[spec[S_IFP]]
    if spec[S_ZPIST] != 0 and spec[S_IZ] >= 0:
        return piston_contact(e, x[spec[S_IZ]], ep[E_SFC] / ep[E_SIG], ep[E_GAP])
    return play_contact(e, v, ep[E_GAP])


@njit(cache=True, error_model="numpy")
def dissipated_power(spec, x, y, v, prm, ep):
    """Power the flow paths dissipate [W] at the piston stroke (y [m], v [m/s]).

    The channel's linear and quadratic losses (:func:`~.kernels_thermal.channel_power`, at
    the coefficients of the flow's direction), the leakage's kL dp^2 and the valve's q_v dp
    beside it; on the stateless dashpot-type bases with a valve or a rebound ratio, their
    exact force law times v.  ``prm`` as the right-hand side sees it (at the fluid's
    temperature where self-heating is composed).  Friction's heat (at the seals, not in the
    fluid) is not counted.
    """
    mid = spec[S_MID]
    if mid == M_DASHPOT or mid == M_DASHPOT_INERTER or mid == M_VISCOUS:
        if spec[S_RELIEF] != 0 or _scaled_losses(spec):
            return _damper_force(spec, y, v, prm, ep) * v
        return channel_power(mid, x, v, 0.0, prm)
    dpc = 0.0
    if spec[S_ROT] > 0:
        dpc = rotating_heads(y, prm, ep)[0]
    i1 = spec[S_I1]
    if i1 >= 0:
        dp = x[i1] - x[spec[S_I2]] + dpc
    elif mid == M_MAXWELL:
        dp = x[0] / prm[P_AP]
    else:
        dp = x[0] + dpc
    q = channel_params(spec, x, y, v, prm, ep, dpc) if _scaled_losses(spec) else prm
    P = channel_power(mid, x, v, dp, q)
    if spec[S_LEAK] != 0 and i1 >= 0:
        P += ep[E_LEAK] * dp * dp
    if spec[S_RELIEF] != 0:
        P += _valve(dp, ep) * dp
    return P


@njit(cache=True, error_model="numpy", fastmath=_FM)
def model_rhs(spec, x, y, v, prm, ep, out):
    """dx/dt of a composed model at the measured rod stroke (y [m], v [m/s]), into ``out``.

    Freeplay (``y_fp``) and series compliance (``y_piston``) map the rod
    stroke to the piston stroke; the fluid sees the piston (the rod where the
    freeplay drives only the friction, ``spec[S_FPFRIC]``); smooth
    friction's bristle state follows the rod velocity, or the piston's
    behind a dead band (``spec[S_ZPIST]``: friction at the piston).
    """
    if (spec[S_N] == spec[S_NB] and spec[S_LEAK] == 0 and spec[S_RELIEF] == 0
            and spec[S_ASYM] == 0 and spec[S_ROT] <= 0 and spec[S_GROOVE] <= 0):
        base_rhs_inline(spec[S_MID], x, y, v, prm, 0.0, 0.0, out)
        return
    ith = spec[S_TH]
    if ith >= 0:  # self-heating: the loss coefficients at the fluid's temperature
        prm = thermal_params(law_temperature(x[ith], prm, ep), prm, ep)
    yi = y
    vi = v
    vpist = v  # the velocity of the friction at the piston (behind the dead band)
    ifp = spec[S_IFP]
    iz = spec[S_IZ]
    if ifp >= 0:
        r = v * _fp_contact(spec, x, y, v, ep)
        out[ifp] = r
        vpist = r
        if spec[S_FPFRIC] != 1:  # the fluid behind the dead band too (else on the rod)
            yi = x[ifp]
            vi = r
    icp = spec[S_IC]
    yq = yi  # the piston stroke the fluid sees (self-heating's dissipation)
    vq = vi
    if icp >= 0:
        yp = x[icp]
        yq = yp
        k = ep[E_KC]
        if math.isinf(k):
            _fluid_rhs(spec, x, yp, vi, prm, ep, out)
            out[icp] = vi
        else:
            n_in = icp  # the fluid block (base and cavities) precedes y_piston
            d1 = np.empty(n_in)
            _fluid_rhs(spec, x, yp, 1.0, prm, ep, d1)
            _fluid_rhs(spec, x, yp, 0.0, prm, ep, out)
            mid = spec[S_MID]
            g0 = state_force(mid, out, prm)
            g1 = state_force(mid, d1, prm) - g0
            if spec[S_ROT] > 0:  # the force's centrifugal term A_p dp_c(y_piston)
                g1 += prm[P_AP] * rotating_slope(prm, ep)
            # behind a dead band (floating_freeplay) the contact engages its stiffness
            # only past the band: inside it k -> 0 and the piston floats, the fluid force
            # held where it is (0, the contact's)
            vp = compliance_rate(vi, k * float_contact(yi - yp, ep[E_KCG]), g0, g1)
            for i in range(n_in):
                out[i] = out[i] + vp * (d1[i] - out[i])
            out[icp] = vp
            vq = vp
    else:
        _fluid_rhs(spec, x, yi, vi, prm, ep, out)
    if ith >= 0:  # the fluid warms by what the flow paths dissipate, cools to ambient
        out[ith] = heat_rate(x[ith], dissipated_power(spec, x, yq, vq, prm, ep), ep[E_TC],
                             ep[E_THA], ep[E_TAMB])
    if iz >= 0:  # the bristles move with the rod, or with the piston behind the dead band
        vz = vpist if spec[S_ZPIST] != 0 else v
        out[iz] = lugre_rate(vz, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                             ep[E_FEX])
        iw = spec[S_IW]
        if iw >= 0:  # the slip memory of slip-weakening friction, driven as the bristles
            out[iw] = slip_memory_rate(vz, x[iw], ep[E_WD])
    iel = spec[S_IEL]
    if iel >= 0:
        out[iel] = elastomer_rate(v, x[iel], ep[E_K1], ep[E_C1E])


@njit(cache=True, error_model="numpy")
def model_jac(spec, x, y, v, prm, ep, J):
    """Jacobian d rhs / dx of a composed model into ``J[:n, :n]`` (zeroed here).

    Analytic where ``spec[S_ANALYTIC]``; otherwise central differences of
    :func:`model_rhs` with increments 2e-6 max(|x_j|, scale_j).
    """
    n = spec[S_N]
    for i in range(n):
        for j in range(n):
            J[i, j] = 0.0
    if spec[S_ANALYTIC] != 0:
        kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
        if _scaled_losses(spec):  # the scale does not depend on the states
            base_jac(spec[S_MID], x, y, v, channel_params(spec, x, y, v, prm, ep, 0.0), kL, J)
        else:
            base_jac(spec[S_MID], x, y, v, prm, kL, J)
        iz = spec[S_IZ]
        if iz >= 0:
            J[iz, iz] = _lugre_dz_dv(v, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                                     ep[E_FEX])[0]
        iel = spec[S_IEL]
        if iel >= 0:
            J[iel, iel] = -ep[E_K1] / ep[E_C1E]
        if spec[S_FY] >= 0:
            _field_yield_jac(spec[S_MID], x, spec[S_FY], prm, ep, J)
        return
    xp = x.copy()
    fp = np.empty(n)
    fm = np.empty(n)
    for j in range(n):
        h = _fd_step(x[j], ep[N_EP + j])
        xp[j] = x[j] + h
        model_rhs(spec, xp, y, v, prm, ep, fp)
        xp[j] = x[j] - h
        model_rhs(spec, xp, y, v, prm, ep, fm)
        xp[j] = x[j]
        for i in range(n):
            J[i, j] = (fp[i] - fm[i]) / (2.0 * h)


@njit(cache=True, error_model="numpy")
def model_rhs_t(spec, x, y, v, yd, vd, prm, ep, out):
    """d rhs / dt at fixed x through the stroke (dy/dt = yd [m/s], dv/dt = vd [m/s^2]).

    Analytic where ``spec[S_ANALYTIC]``; otherwise a central difference along
    the stroke over +/- 1e-7 s.
    """
    n = spec[S_N]
    if spec[S_ANALYTIC] != 0:
        kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
        if _scaled_losses(spec):
            q = channel_params(spec, x, y, v, prm, ep, 0.0)
            base_rhs_t(spec[S_MID], x, y, v, yd, vd, q, kL, out)
            if spec[S_GROOVE] > 0:  # the scale changes along the stroke: d ln s / dt
                s, ds = groove_ep_scale(y, ep)
                groove_rate_terms(spec[S_MID], x, y, v, q, kL, ds / s * yd, out)
        else:
            base_rhs_t(spec[S_MID], x, y, v, yd, vd, prm, kL, out)
        iz = spec[S_IZ]
        if iz >= 0:
            out[iz] = _lugre_dz_dv(v, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                                   ep[E_FEX])[1] * vd
        iel = spec[S_IEL]
        if iel >= 0:
            out[iel] = ep[E_K1] * vd
        ify = spec[S_FY]
        if ify >= 0:  # the field lag through the measured input's rate
            out[ify] = ep[E_ETA] * prm[P_CHD + int(ep[E_FYCH])]
        return
    dt = 1.0e-7
    fm = np.empty(n)
    moving = False  # measured input channels that change along the step (their rates)
    for k in range(N_CH):
        if prm[P_CHD + k] != 0.0:
            moving = True
    if moving:
        qp = prm.copy()
        qm = prm.copy()
        for k in range(N_CH):
            qp[P_CH + k] = prm[P_CH + k] + dt * prm[P_CHD + k]
            qm[P_CH + k] = prm[P_CH + k] - dt * prm[P_CHD + k]
        model_rhs(spec, x, y + dt * yd, v + dt * vd, qp, ep, out)
        model_rhs(spec, x, y - dt * yd, v - dt * vd, qm, ep, fm)
    else:
        model_rhs(spec, x, y + dt * yd, v + dt * vd, prm, ep, out)
        model_rhs(spec, x, y - dt * yd, v - dt * vd, prm, ep, fm)
    for i in range(n):
        out[i] = (out[i] - fm[i]) / (2.0 * dt)


@njit(cache=True, error_model="numpy")
def model_force(spec, x, y, v, a, prm, ep, with_friction):
    """Load-cell force of a composed model [N] at the rod stroke (y, v, a).

    The fluid force at the piston stroke plus the effect forces (Coulomb
    friction behind a dead band, ``spec[S_CPIST]``: F_c sign(v) C, C the
    dead band's contact factor, 0 in the gap); with
    ``with_friction`` also the parameter set's Coulomb friction
    ``friction_N sign(v)`` (:attr:`DeviceParams.friction_N`).
    """
    mid = spec[S_MID]
    if spec[S_TH] >= 0:  # self-heating: the loss coefficients at the fluid's temperature
        prm = thermal_params(law_temperature(x[spec[S_TH]], prm, ep), prm, ep)
    yi = y
    vi = v
    ifp = spec[S_IFP]
    cfp = 1.0  # contact factor of the dead band (1: no freeplay)
    if ifp >= 0:
        cfp = _fp_contact(spec, x, y, v, ep)
        if spec[S_FPFRIC] != 1:  # the fluid behind the dead band too (else on the rod)
            vi = v * cfp
            yi = x[ifp]
    if spec[S_IC] >= 0:
        yi = x[spec[S_IC]]
    if (spec[S_RELIEF] != 0 or _scaled_losses(spec)) and (
            mid == M_DASHPOT or mid == M_DASHPOT_INERTER or mid == M_VISCOUS):
        f = _damper_force(spec, yi, vi, prm, ep)
        if mid == M_DASHPOT_INERTER:
            f += prm[P_BLM] * a
    else:
        f = base_force(mid, x, yi, vi, a, prm)
        if spec[S_ROT] > 0:  # piston faces: A_p (p1 - p2 + dp_c) (rotating_heads)
            f += prm[P_AP] * rotating_heads(yi, prm, ep)[0]
    iz = spec[S_IZ]
    if iz >= 0:
        ff = ep[E_SFC] * friction_level(x[iz], ep[E_FRQ])
        if spec[S_IW] >= 0:  # slip weakening: the breakaway level decays over a slip
            ff *= weakening(x[iz], x[spec[S_IW]], ep[E_WB])
        f += ff
    if spec[S_COUL] != 0:
        # at the piston the dead band passes the friction force only in contact
        f += ep[E_CF] * friction_level(_sign(v), ep[E_CRQ]) * (
            cfp if spec[S_CPIST] != 0 else 1.0)
    iel = spec[S_IEL]
    if iel >= 0:  # the elastomer on the rod: k0 y plus its Maxwell branch
        f += ep[E_K0] * y + x[iel]
    if spec[S_STOP] != 0:
        f += stop_force(y, v, ep[E_KS], ep[E_CS], ep[E_CLR], ep[E_CTR])
    if spec[S_GAS] != 0:  # the gas charge on the absolute rod stroke
        f += gas_force(y + ep[E_Y0G], ep[E_AR], _charge(spec, x, prm, ep), ep[E_VG], ep[E_NG],
                       ep[E_PAT])
    if spec[S_MASS] != 0:
        f += ep[E_MASS] * a
    if spec[S_OFF] != 0:
        f += ep[E_OFF]
    if with_friction and prm[P_FRIC] > 0.0:
        f += prm[P_FRIC] * _sign(v)
    return f


@njit(cache=True, error_model="numpy", nogil=True)
def force_series(spec, X, Y, V, A, prm, ep, with_friction, out):
    """:func:`model_force` over samples: X (n, N) states, Y, V, A (N,) strokes; into ``out``.

    Each state goes through a contiguous copy and the friction flag as a
    constant, as the integrators pass them, so that :func:`model_force` is
    compiled once for both.
    """
    xk = np.empty(X.shape[0])
    for k in range(out.size):
        for i in range(X.shape[0]):
            xk[i] = X[i, k]
        if with_friction:
            out[k] = model_force(spec, xk, Y[k], V[k], A[k], prm, ep, True)
        else:
            out[k] = model_force(spec, xk, Y[k], V[k], A[k], prm, ep, False)


@njit(cache=True, error_model="numpy", nogil=True)
def force_series_inputs(spec, X, Y, V, A, C, prm, ep, with_friction, out):
    """:func:`force_series` with the measured input channels of every sample: ``C`` (N_CH, N)
    the channel values in slot order (``prm[P_CH + k]``, see ``kernels_layout.CHANNELS``)."""
    q = prm.copy()
    xk = np.empty(X.shape[0])
    for k in range(out.size):
        for j in range(N_CH):
            q[P_CH + j] = C[j, k]
        for i in range(X.shape[0]):
            xk[i] = X[i, k]
        if with_friction:
            out[k] = model_force(spec, xk, Y[k], V[k], A[k], q, ep, True)
        else:
            out[k] = model_force(spec, xk, Y[k], V[k], A[k], q, ep, False)
