"""Analytic Jacobian and time derivative of a base fluid behind a stroke map (series
compliance or freeplay): the stiff RODAS4 route's d rhs/dx and d rhs/dt, which
:func:`liquidamp.device.kernels_model.model_jac` and ``model_rhs_t`` now form by central
differences there (2n + 2 right-hand sides per step).

NOT wired into ``model_jac``/``model_rhs_t`` (session 8, issue 19 bench): with them wired
in, the default diagnosis's answers on the shared records moved (the 200 Hz
series-compliance bench record added force_offset, d05's held-out NRMSE 0.0022 -> 0.0059),
but so did they with nothing but a compiled-out hook or a changed list of cached sources:
``record_model._phases`` keyed its cache on ``id()`` of the conditioning, which a new
object can reuse (fixed on the same branch).  Whether the answers move with these forms
once that is fixed was then measured (branch s8-wire, the id fix in place, default
``diagnose``): d01, d02, d04, d11 and d12 unchanged, but d05's backlash refit stops on its
budget (613 model runs) with held-out NRMSE 0.0059 instead of 0.0022: the fits' finite
differences of the objective see the integrator's path, which the exact Jacobian changes;
until the fits are made insensitive to it (an objective smooth to well below diff_step),
the forms stay out.  To wire them in, call them first in ``model_jac`` and
``model_rhs_t`` (they return False where they do not apply) and re-run the shared cases
(runs/s8_speed/README.md).

The old central differences are off by up to 2 % in the density columns behind the
compliance (step 2e-6 x scale: round-off); these forms are checked against
Richardson-extrapolated differences in ``tests/device/test_kernels_stroke_map.py``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.device.kernels_base import base_jac, base_rhs, base_rhs_t, state_force
from liquidamp.device.kernels_laws import (
    Z_HOLD,
    _lugre_dz_dv,
    compliance_rate,
    piston_contact,
    play_contact,
)
from liquidamp.device.kernels_layout import (
    E_C1E,
    E_FEX,
    E_GAP,
    E_K1,
    E_KC,
    E_KCG,
    E_LEAK,
    E_SFC,
    E_SIG,
    E_SR,
    E_VS,
    M_FULL,
    M_NO_INERTIA,
    N_CH,
    P_CHD,
    S_ASYM,
    S_FPFRIC,
    S_FY,
    S_GROOVE,
    S_IC,
    S_ICAV,
    S_IEL,
    S_IFP,
    S_IW,
    S_IZ,
    S_LEAK,
    S_MID,
    S_N,
    S_NB,
    S_RELIEF,
    S_ROT,
    S_TH,
    S_ZPIST,
)

drop_stale(__file__)  # before any kernel of this module loads from the cache

__all__ = ["stroke_map_jac", "stroke_map_rhs_t"]


@njit(cache=True, error_model="numpy")
def _applies(spec, ep):
    """Whether the stroke-map forms hold the composition: one map (series compliance of
    finite stiffness without a dead band, its piston stroke right after the fluid's states,
    or freeplay; not a floating freeplay, whose contact stiffness depends on the stroke),
    leakage only on the ``full`` and ``no_inertia`` bases, and none of the effects they do not
    cover (cavities, relief valves, rebound asymmetry, a bypass groove, slip weakening, the
    rotating frame, self-heating, the field yield)."""
    icp = spec[S_IC]
    if (icp >= 0) == (spec[S_IFP] >= 0):
        return False
    if (spec[S_ICAV] >= 0 or spec[S_RELIEF] != 0 or spec[S_ROT] > 0 or spec[S_TH] >= 0
            or spec[S_FY] >= 0 or spec[S_ASYM] != 0 or spec[S_GROOVE] > 0
            or spec[S_IW] >= 0):
        return False
    mid = spec[S_MID]
    if spec[S_LEAK] != 0 and not (mid == M_FULL or mid == M_NO_INERTIA):
        return False
    return not (icp >= 0 and (math.isinf(ep[E_KC]) or icp != spec[S_NB] or ep[E_KCG] > 0.0))


@njit(cache=True, error_model="numpy")
def stroke_map_jac(spec, x, y, v, prm, ep, J):
    """Analytic Jacobian of a base fluid behind a stroke map (series compliance or
    freeplay, one of them), into ``J`` (already zeroed); False where it does not apply.

    Applies to the plain fluid (leakage on ``full``/``no_inertia`` allowed) with smooth
    friction (bristles on the rod) and elastomer states; not to cavities, relief valves,
    rebound asymmetry, a bypass groove, slip weakening, the rotating frame, self-heating, the
    field yield, an infinite
    series stiffness, or both maps at once (those keep :func:`model_jac`'s central
    differences).

    With f(x, y_p, u) the fluid's rates at piston stroke y_p and velocity u (affine in
    u: f = a + u b, b = df/du) and S the linear force functional
    (:func:`state_force`):

    * series compliance, k (v - v_p) = S a + v_p S b, so
      v_p = (k v - S a) / (k + S b) and, for z each fluid state and y_p,
      d v_p / dz = -S(df/dz |_{u=v_p}) / (k + S b);
      d rates / dz = df/dz |_{u=v_p} + b d v_p / dz, d y_p' / dz = d v_p / dz;
    * freeplay, r = v C(y - y_fp, v) (:func:`play_contact`), the fluid at (y_fp, r):
      d r / d y_fp = -v C'(e); d rates / d y_fp = df/dy + (df/du) dr/dy_fp; with the
      bristles behind the dead band (:func:`piston_contact`, C of e + lam z) also
      d r / d z = v C' lam, d rates / d z = (df/du) dr/dz, and the bristle rate
      g(r, z) gives d z' / d z = g_z + g_v dr/dz, d z' / d y_fp = g_v dr/dy_fp.

    df/dx is :func:`base_jac`, df/dy and df/du :func:`base_rhs_t` with unit rates.
    Checked against central differences of :func:`model_rhs` in
    ``tests/device/test_kernels_stroke_map.py``.
    """
    if not _applies(spec, ep):
        return False
    icp = spec[S_IC]
    ifp = spec[S_IFP]
    mid = spec[S_MID]
    nb = spec[S_NB]
    kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
    if icp >= 0:
        k = ep[E_KC]
        yp = x[icp]
        a = np.empty(nb)
        b = np.empty(nb)
        base_rhs(mid, x, yp, 0.0, prm, kL, 0.0, a)
        base_rhs(mid, x, yp, 1.0, prm, kL, 0.0, b)
        g0 = state_force(mid, a, prm)
        g1 = state_force(mid, b, prm) - g0
        for i in range(nb):
            b[i] = b[i] - a[i]
        den = k + g1
        vp = compliance_rate(v, k, g0, g1)
        base_jac(mid, x, yp, vp, prm, kL, J)
        col = np.empty(nb)
        for j in range(nb + 1):
            if j < nb:
                for i in range(nb):
                    col[i] = J[i, j]
            else:  # the piston stroke's column: df/dy at u = v_p
                base_rhs_t(mid, x, yp, vp, 1.0, 0.0, prm, kL, col)
            dvp = -state_force(mid, col, prm) / den
            for i in range(nb):
                J[i, j] = col[i] + b[i] * dvp
            J[icp, j] = dvp
    else:
        gap = ep[E_GAP]
        e = y - x[ifp]
        iz = spec[S_IZ]
        behind = spec[S_ZPIST] != 0 and iz >= 0  # bristles behind the dead band
        lam = 0.0
        if behind:  # piston_contact: C = S((|e + lam z| - gap) / delta + 1)
            lam = ep[E_SFC] / ep[E_SIG]
            delta = min(0.05 * gap + 1.0e-7, Z_HOLD * lam)
            q = e + lam * x[iz]
            s = (abs(q) - gap) / delta + 1.0
            dsde = (1.0 if q > 0.0 else (-1.0 if q < 0.0 else 0.0)) / delta
            r = v * piston_contact(e, x[iz], lam, gap)
        else:  # play_contact: C = S((e sign(v) - gap) / delta + 1)
            delta = 0.05 * gap + 1.0e-7
            if v > 0.0:
                s = (e - gap) / delta + 1.0
                dsde = 1.0 / delta
            elif v < 0.0:
                s = (-e - gap) / delta + 1.0
                dsde = -1.0 / delta
            else:
                s = 0.0
                dsde = 0.0
            r = v * play_contact(e, v, gap)
        dcde = 6.0 * s * (1.0 - s) * dsde if 0.0 < s < 1.0 else 0.0
        dr = -v * dcde  # d r / d y_fp
        drz = v * dcde * lam  # d r / d z (bristles behind the dead band)
        J[ifp, ifp] = dr
        if spec[S_FPFRIC] == 1:  # the fluid on the rod: the dead band drives the friction
            base_jac(mid, x, y, v, prm, kL, J)
        else:
            base_jac(mid, x, x[ifp], r, prm, kL, J)
            col = np.empty(nb)
            base_rhs_t(mid, x, x[ifp], r, 1.0, dr, prm, kL, col)
            for i in range(nb):
                J[i, ifp] = col[i]
            if behind:
                base_rhs_t(mid, x, x[ifp], r, 0.0, drz, prm, kL, col)
                for i in range(nb):
                    J[i, iz] = col[i]
        if behind:  # the bristles driven by the piston: dz/dt = g(r, z)
            J[ifp, iz] = drz
            gz, gv = _lugre_dz_dv(r, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                                  ep[E_FEX])
            J[iz, iz] = gz + gv * drz
            J[iz, ifp] = gv * dr
    iz = spec[S_IZ]
    if iz >= 0 and not (ifp >= 0 and spec[S_ZPIST] != 0):  # the bristles follow the rod
        J[iz, iz] = _lugre_dz_dv(v, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                                 ep[E_FEX])[0]
    iel = spec[S_IEL]
    if iel >= 0:
        J[iel, iel] = -ep[E_K1] / ep[E_C1E]
    return True


@njit(cache=True, error_model="numpy")
def stroke_map_rhs_t(spec, x, y, v, yd, vd, prm, ep, out):
    """d rhs / dt at fixed x of the compositions :func:`stroke_map_jac` covers, into
    ``out``; False elsewhere (or with measured input channels changing along the step).

    Series compliance: the stroke enters through the rod velocity alone,
    d v_p / dt = k / (k + S b) dv/dt and d rates / dt = b d v_p / dt.  Freeplay:
    r = v C(e), e = y - y_fp (+ lam z behind it), d r / dt = C dv/dt + v C'(e) dy/dt and
    the fluid at (y_fp, r) changes at (df/du) dr/dt.  Bristles on the rod change at
    g_v dv/dt, behind the dead band at g_v dr/dt; the elastomer at k_1 dv/dt.
    """
    icp = spec[S_IC]
    ifp = spec[S_IFP]
    if not _applies(spec, ep):
        return False
    for k in range(N_CH):
        if prm[P_CHD + k] != 0.0:
            return False
    mid = spec[S_MID]
    nb = spec[S_NB]
    kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
    n = spec[S_N]
    for i in range(n):
        out[i] = 0.0
    iz = spec[S_IZ]
    vz = v  # the velocity that drives the bristles
    dvz = vd
    if icp >= 0:
        k = ep[E_KC]
        yp = x[icp]
        a = np.empty(nb)
        b = np.empty(nb)
        base_rhs(mid, x, yp, 0.0, prm, kL, 0.0, a)
        base_rhs(mid, x, yp, 1.0, prm, kL, 0.0, b)
        g0 = state_force(mid, a, prm)
        g1 = state_force(mid, b, prm) - g0
        dvp = k / (k + g1) * vd
        for i in range(nb):
            out[i] = (b[i] - a[i]) * dvp
        out[icp] = dvp
    else:
        gap = ep[E_GAP]
        e = y - x[ifp]
        behind = spec[S_ZPIST] != 0 and iz >= 0
        if behind:
            lam = ep[E_SFC] / ep[E_SIG]
            delta = min(0.05 * gap + 1.0e-7, Z_HOLD * lam)
            q = e + lam * x[iz]
            s = (abs(q) - gap) / delta + 1.0
            dsde = (1.0 if q > 0.0 else (-1.0 if q < 0.0 else 0.0)) / delta
            c = piston_contact(e, x[iz], lam, gap)
        else:
            delta = 0.05 * gap + 1.0e-7
            if v > 0.0:
                s = (e - gap) / delta + 1.0
                dsde = 1.0 / delta
            elif v < 0.0:
                s = (-e - gap) / delta + 1.0
                dsde = -1.0 / delta
            else:
                s = 0.0
                dsde = 0.0
            c = play_contact(e, v, gap)
        dcde = 6.0 * s * (1.0 - s) * dsde if 0.0 < s < 1.0 else 0.0
        r = v * c
        drt = c * vd + v * dcde * yd
        out[ifp] = drt
        col = np.empty(nb)
        if spec[S_FPFRIC] == 1:  # the fluid on the rod
            base_rhs_t(mid, x, y, v, yd, vd, prm, kL, col)
        else:
            base_rhs_t(mid, x, x[ifp], r, 0.0, drt, prm, kL, col)
        for i in range(nb):
            out[i] = col[i]
        if behind:
            vz = r
            dvz = drt
    if iz >= 0:
        out[iz] = _lugre_dz_dv(vz, x[iz], ep[E_SFC], ep[E_SIG], ep[E_VS], ep[E_SR],
                               ep[E_FEX])[1] * dvz
    iel = spec[S_IEL]
    if iel >= 0:
        out[iel] = ep[E_K1] * vd
    return True
