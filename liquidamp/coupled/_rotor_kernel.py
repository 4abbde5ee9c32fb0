"""Compiled integrator of a periodic second-order host with devices on its ports (rotor).

Private module: use it through :func:`liquidamp.coupled.fast_rotor.simulate_rotor`.  The host's
equations come from :mod:`liquidamp.structure` (the harmonic matrices of
:meth:`~liquidamp.structure.rotor.GroundResonanceRotor.harmonic_second_order` and the
port maps of its force and output matrices), the devices' from
:mod:`liquidamp.device.kernels`; the integrator is DOP853 with the coefficients of
:mod:`liquidamp.coupled._dop853` (scipy's to the last bit), error norm, step control and
dense output.

References
----------
.. [1] E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I,
   2nd ed., Springer 1993, Sec. II.10 (DOP853).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.coupled._kernels import ST_OK, ST_PRESSURE, ST_STEP_TOO_SMALL, ST_TOO_MANY_STEPS
from liquidamp.coupled._linalg import lu_factor, lu_solve
from liquidamp.device.kernels import (
    N_EP,
    P_FRIC,
    S_EFFECTS,
    S_MID,
    S_N,
    S_NB,
    base_force,
    base_rhs_inline,
    model_force,
    model_jac,
    model_rhs,
)

drop_stale(__file__)  # before any kernel of this module loads from the cache

__all__ = ["ST_STROKE_LIMIT", "FD_REL", "rotor_rhs", "device_derivatives", "rotor_variation",
           "rotor_integrate"]

#: Status: a device stroke reached its chamber end.
ST_STROKE_LIMIT = 5

#: Relative increment of the central differences of a device's force and right-hand side in
#: its states, stroke and stroke rate (the variational equations) [-].
FD_REL = 1e-6

@njit(cache=True, error_model="numpy")
def rotor_rhs(t, X, W, HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP, M, b, piv, Fk, out):
    """Periodic second-order host + devices on its ports: dX/dt into ``out``.

    The host is ``M(psi) q'' + C(psi) q' + K(psi) q = Pin F`` with
    ``psi = W t`` and each matrix a first harmonic of psi, ``X0 + Xc cos(psi)
    + Xs sin(psi)``: the non-zero entries of the nine matrices ``M0, Mc, Ms,
    C0, Cc, Cs, K0, Kc, Ks`` of
    :meth:`liquidamp.structure.rotor.GroundResonanceRotor.harmonic_second_order`
    (the rotor's own equations; none are written here) as triplets
    ``HI[e] = (matrix 0-8, row, column)``, ``HV[e]`` = value.  Host state
    ``[q, q']`` (n = M.shape[0] coordinates); the port maps as triplets
    ``PI[e] = (kind, device, index)``, ``PV[e]`` = value, kind 0: stroke of
    device j = sum PV X[index], kind 1: its rate, kind 2: generalized force
    on coordinate ``index`` = PV F_j.  External inputs as generalized
    forces: coordinate ``UI[e]`` gets ``UV[e, 0] + UV[e, 1] cos(UV[e, 3] t) +
    UV[e, 2] sin(UV[e, 3] t)`` (:class:`~liquidamp.coupled.inputs.HarmonicInput`
    times its column of the host's force matrix).
    """
    n = M.shape[0]
    nh = 2 * n
    psi = W * t
    cp = math.cos(psi)
    sp = math.sin(psi)
    nd = DSPEC.shape[0]
    for j in range(2 * nd):
        Fk[j] = 0.0  # stroke and rate of each device
    npi = PI.shape[0]
    for e in range(npi):
        kind = PI[e, 0]
        if kind < 2:
            Fk[2 * PI[e, 1] + kind] += PV[e] * X[PI[e, 2]]
    for j in range(nd):
        y = Fk[2 * j]
        v = Fk[2 * j + 1]
        a0 = nh + doff[j]
        a1 = nh + doff[j + 1]
        z = X[a0:a1]
        spec = DSPEC[j]
        prm = PRM[j]
        if spec[S_N] == spec[S_NB] and spec[S_EFFECTS] == 0:  # the base equation alone
            mid = spec[S_MID]
            if a1 > a0:
                base_rhs_inline(mid, z, y, v, prm, 0.0, 0.0, out[a0:a1])
            F = base_force(mid, z, y, v, 0.0, prm)
            if prm[P_FRIC] > 0.0:
                F += prm[P_FRIC] * (1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0))
            Fk[2 * j] = F
        else:
            if a1 > a0:
                model_rhs(spec, z, y, v, prm, DEP[j], out[a0:a1])
            Fk[2 * j] = model_force(spec, z, y, v, 0.0, prm, DEP[j], True)
    for i in range(n):
        b[i] = 0.0
        for k in range(n):
            M[i, k] = 0.0
    for e in range(npi):
        if PI[e, 0] == 2:
            b[PI[e, 2]] += PV[e] * Fk[2 * PI[e, 1]]
    for e in range(UI.shape[0]):
        wt = UV[e, 3] * t
        b[UI[e]] += UV[e, 0] + UV[e, 1] * math.cos(wt) + UV[e, 2] * math.sin(wt)
    for e in range(HI.shape[0]):
        m = HI[e, 0]
        i = HI[e, 1]
        k = HI[e, 2]
        h = m % 3
        w = HV[e] if h == 0 else (HV[e] * cp if h == 1 else HV[e] * sp)
        if m < 3:
            M[i, k] += w
        elif m < 6:
            b[i] -= w * X[n + k]
        else:
            b[i] -= w * X[k]
    lu_factor(M, piv)
    lu_solve(M, piv, b)
    for i in range(n):
        out[i] = X[n + i]
        out[n + i] = b[i]


@njit(cache=True, error_model="numpy")
def device_derivatives(spec, z, y, v, prm, ep, lim, dFdz, dfdz, dfdy, dfdv, zp, f1, f2):
    """Derivatives of one device's force and right-hand side at (z, y [m], v [m/s]).

    Writes dF/dz [N per state unit] into ``dFdz``, d rhs/dz (:func:`model_jac`) into
    ``dfdz``, d rhs/dy and d rhs/dv into ``dfdy``, ``dfdv``; returns (dF/dy [N/m],
    dF/dv [N s/m]).  Central differences with increments ``FD_REL`` times
    max(|z_k|, scale_k), max(|y|, min(lim, 0.01 m)), max(|v|, 0.01 m/s).
    """
    nz = z.size
    hy = FD_REL * max(abs(y), min(lim, 0.01))
    hv = FD_REL * max(abs(v), 0.01)
    for k in range(nz):
        zp[k] = z[k]
    for k in range(nz):
        h = FD_REL * max(abs(z[k]), ep[N_EP + k])
        zp[k] = z[k] + h
        fp = model_force(spec, zp, y, v, 0.0, prm, ep, True)
        zp[k] = z[k] - h
        fm = model_force(spec, zp, y, v, 0.0, prm, ep, True)
        zp[k] = z[k]
        dFdz[k] = (fp - fm) / (2.0 * h)
    dFdy = (model_force(spec, z, y + hy, v, 0.0, prm, ep, True)
            - model_force(spec, z, y - hy, v, 0.0, prm, ep, True)) / (2.0 * hy)
    dFdv = (model_force(spec, z, y, v + hv, 0.0, prm, ep, True)
            - model_force(spec, z, y, v - hv, 0.0, prm, ep, True)) / (2.0 * hv)
    if nz:
        model_jac(spec, z, y, v, prm, ep, dfdz)
        model_rhs(spec, z, y + hy, v, prm, ep, f1)
        model_rhs(spec, z, y - hy, v, prm, ep, f2)
        for k in range(nz):
            dfdy[k] = (f1[k] - f2[k]) / (2.0 * hy)
        model_rhs(spec, z, y, v + hv, prm, ep, f1)
        model_rhs(spec, z, y, v - hv, prm, ep, f2)
        for k in range(nz):
            dfdv[k] = (f1[k] - f2[k]) / (2.0 * hv)
    return dFdy, dFdv


@njit(cache=True, error_model="numpy")
def rotor_variation(t, X, nx, W, HI, HV, PI, PV, DSPEC, doff, PRM, DEP, lim, M, piv, wk, out):
    """Variational equations Phi' = J(t, x) Phi of :func:`rotor_rhs` into ``out[nx:]``.

    ``X[:nx]`` is the state, ``X[nx:]`` the matrix Phi (nx x nx, row major);
    ``M`` must hold the LU factors of M(psi) left by :func:`rotor_rhs` at the
    same (t, X).  The host's variation is M dq'' = -C dq' - K dq + G_F dF
    with dF_j = dF/dz dz_j + dF/dy dy_j + dF/dv dv_j, the device's dz' =
    d rhs/dz dz + d rhs/dy dy + d rhs/dv dv (:func:`device_derivatives`).
    ``wk`` holds the work arrays (see :func:`rotor_integrate`).
    """
    Cm, Km, yv, DFZ, DFYV, DZZ, DZY, DZV, zp, f1, f2, bv, dF, dyv = wk
    n = M.shape[0]
    nh = 2 * n
    nd = DSPEC.shape[0]
    psi = W * t
    cp = math.cos(psi)
    sp = math.sin(psi)
    for i in range(n):
        for k in range(n):
            Cm[i, k] = 0.0
            Km[i, k] = 0.0
    for e in range(HI.shape[0]):
        m = HI[e, 0]
        if m < 3:
            continue
        h = m % 3
        w = HV[e] if h == 0 else (HV[e] * cp if h == 1 else HV[e] * sp)
        if m < 6:
            Cm[HI[e, 1], HI[e, 2]] += w
        else:
            Km[HI[e, 1], HI[e, 2]] += w
    npi = PI.shape[0]
    for j in range(2 * nd):
        yv[j] = 0.0
    for e in range(npi):
        if PI[e, 0] < 2:
            yv[2 * PI[e, 1] + PI[e, 0]] += PV[e] * X[PI[e, 2]]
    for j in range(nd):
        a0 = nh + doff[j]
        nz = doff[j + 1] - doff[j]
        dy, dv = device_derivatives(DSPEC[j], X[a0:a0 + nz], yv[2 * j], yv[2 * j + 1], PRM[j],
                                    DEP[j], lim[j], DFZ[j], DZZ[j], DZY[j], DZV[j], zp, f1, f2)
        DFYV[j, 0] = dy
        DFYV[j, 1] = dv
    for c in range(nx):
        for j in range(2 * nd):
            dyv[j] = 0.0
        for e in range(npi):
            if PI[e, 0] < 2:
                dyv[2 * PI[e, 1] + PI[e, 0]] += PV[e] * X[nx + PI[e, 2] * nx + c]
        for j in range(nd):
            a0 = nh + doff[j]
            acc = DFYV[j, 0] * dyv[2 * j] + DFYV[j, 1] * dyv[2 * j + 1]
            for k in range(doff[j + 1] - doff[j]):
                acc += DFZ[j, k] * X[nx + (a0 + k) * nx + c]
            dF[j] = acc
        for i in range(n):
            acc = 0.0
            for k in range(n):
                acc -= Cm[i, k] * X[nx + (n + k) * nx + c] + Km[i, k] * X[nx + k * nx + c]
            bv[i] = acc
        for e in range(npi):
            if PI[e, 0] == 2:
                bv[PI[e, 2]] += PV[e] * dF[PI[e, 1]]
        lu_solve(M, piv, bv)
        for i in range(n):
            out[nx + i * nx + c] = X[nx + (n + i) * nx + c]
            out[nx + (n + i) * nx + c] = bv[i]
        for j in range(nd):
            a0 = nh + doff[j]
            nz = doff[j + 1] - doff[j]
            for r in range(nz):
                acc = DZY[j, r] * dyv[2 * j] + DZV[j, r] * dyv[2 * j + 1]
                for k in range(nz):
                    acc += DZZ[j, r, k] * X[nx + (a0 + k) * nx + c]
                out[nx + (a0 + r) * nx + c] = acc


@njit(cache=True, error_model="numpy")
def _rhs_any(t, X, nx, W, HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP, lim, M, b, piv, Fk,
             wk, out):
    """:func:`rotor_rhs` on ``X[:nx]``, and :func:`rotor_variation` when X holds Phi too."""
    rotor_rhs(t, X[:nx], W, HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP, M, b, piv, Fk,
              out[:nx])
    if X.size > nx:
        rotor_variation(t, X, nx, W, HI, HV, PI, PV, DSPEC, doff, PRM, DEP, lim, M, piv, wk,
                        out)


@njit(cache=True, error_model="numpy")
def rotor_integrate(W, HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP, fi, lim, pfloor, x0, nx,
                    t_end, teval, rtol, atol, hmax, max_steps, RA, RB, RC, E3, E5, RAX, RCX, RD,
                    out, info):
    """DOP853 (Dormand-Prince 8(5,3), scipy's coefficients and step control) of :func:`rotor_rhs`.

    Output at ``teval`` by the 7th-order continuous extension (three extra
    stages on the steps that hold output times, as scipy) into
    ``out[:, i]``; stops at the end of the step where a stroke reaches its
    chamber end (``lim``) or a watched pressure (``fi``) the floor.
    ``info``: status, time reached, steps, rhs evaluations, samples written.
    ``nx``: the number of states; when ``x0`` is longer (nx + nx^2), its tail is
    the matrix Phi of the variational equations (:func:`rotor_variation`),
    integrated with the state under the same error control.
    """
    n = x0.size
    nb = int(nx - doff[-1]) // 2
    nh = 2 * nb
    nd = DSPEC.shape[0]
    nzm = 1
    for j in range(nd):
        nzm = max(nzm, doff[j + 1] - doff[j])
    wk = (np.empty((nb, nb)), np.empty((nb, nb)), np.empty(max(2 * nd, 1)),
          np.zeros((max(nd, 1), nzm)), np.zeros((max(nd, 1), 2)),
          np.zeros((max(nd, 1), nzm, nzm)), np.zeros((max(nd, 1), nzm)),
          np.zeros((max(nd, 1), nzm)), np.empty(nzm), np.empty(nzm), np.empty(nzm),
          np.empty(nb), np.empty(max(nd, 1)), np.empty(max(2 * nd, 1)))
    ns = 12
    K = np.empty((ns + 4, n))
    Fd = np.empty((7, n))
    M = np.empty((nb, nb))
    b = np.empty(nb)
    piv = np.empty(nb, np.int64)
    Fk = np.empty(max(2 * nd, 1))
    y = x0.copy()
    ynew = np.empty(n)
    ytmp = np.empty(n)
    f = np.empty(n)
    fnew = np.empty(n)
    t = 0.0
    _rhs_any(t, y, nx, W, HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP, lim, M, b, piv, Fk, wk,
             f)
    nfev = 1
    # initial step (Hairer, Norsett & Wanner I, II.4; as scipy)
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = atol[i] + abs(y[i]) * rtol
        d0 += (y[i] / sc) ** 2
        d1 += (f[i] / sc) ** 2
    d0 = math.sqrt(d0 / n)
    d1 = math.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, t_end, hmax)
    for i in range(n):
        ytmp[i] = y[i] + h0 * f[i]
    _rhs_any(h0, ytmp, nx, W, HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP, lim, M, b, piv, Fk, wk,
             K[1])
    nfev += 1
    d2 = 0.0
    for i in range(n):
        sc = atol[i] + abs(y[i]) * rtol
        d2 += ((K[1, i] - f[i]) / sc) ** 2
    d2 = math.sqrt(d2 / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    h = min(100.0 * h0, h1, hmax)
    ne = teval.size
    ie = 0
    while ie < ne and teval[ie] <= t:
        for i in range(n):
            out[i, ie] = y[i]
        ie += 1
    status = ST_OK
    nstep = 0
    rejected = False
    expo = -1.0 / 8.0
    while t < t_end:
        if nstep >= max_steps:
            status = ST_TOO_MANY_STEPS
            break
        if h > hmax:
            h = hmax
        min_step = 10.0 * 2.220446049250313e-16 * max(abs(t), 1e-300)
        if h < min_step:
            status = ST_STEP_TOO_SMALL
            break
        tn = t + h
        if tn > t_end:
            tn = t_end
            h = tn - t
        for i in range(n):
            K[0, i] = f[i]
        for s in range(1, ns):
            for i in range(n):
                acc = 0.0
                for r in range(s):
                    acc += RA[s, r] * K[r, i]
                ytmp[i] = y[i] + h * acc
            _rhs_any(t + RC[s] * h, ytmp, nx, W, HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP,
                     lim, M, b, piv, Fk, wk, K[s])
        for i in range(n):
            acc = 0.0
            for r in range(ns):
                acc += RB[r] * K[r, i]
            ynew[i] = y[i] + h * acc
        _rhs_any(tn, ynew, nx, W, HI, HV, PI, PV, UI, UV, DSPEC, doff, PRM, DEP, lim, M, b, piv,
                 Fk, wk, fnew)
        for i in range(n):
            K[ns, i] = fnew[i]
        nfev += ns
        nstep += 1
        e5 = 0.0
        e3 = 0.0
        for i in range(n):
            sc = atol[i] + max(abs(y[i]), abs(ynew[i])) * rtol
            a5 = 0.0
            a3 = 0.0
            for r in range(ns + 1):
                a5 += E5[r] * K[r, i]
                a3 += E3[r] * K[r, i]
            e5 += (a5 / sc) ** 2
            e3 += (a3 / sc) ** 2
        if e5 == 0.0 and e3 == 0.0:
            err = 0.0
        else:
            err = h * e5 / math.sqrt((e5 + 0.01 * e3) * n)
        if err < 1.0:
            if err == 0.0:
                factor = 10.0
            else:
                factor = min(10.0, 0.9 * err ** expo)
            if rejected:
                factor = min(1.0, factor)
            if ie < ne and teval[ie] <= tn:
                for s in range(ns + 1, ns + 4):
                    for i in range(n):
                        acc = 0.0
                        for r in range(s):
                            acc += RAX[s - ns - 1, r] * K[r, i]
                        ytmp[i] = y[i] + h * acc
                    _rhs_any(t + RCX[s - ns - 1] * h, ytmp, nx, W, HI, HV, PI, PV, UI, UV,
                             DSPEC, doff, PRM, DEP, lim, M, b, piv, Fk, wk, K[s])
                nfev += 3
                for i in range(n):
                    dy = ynew[i] - y[i]
                    Fd[0, i] = dy
                    Fd[1, i] = h * f[i] - dy
                    Fd[2, i] = 2.0 * dy - h * (fnew[i] + f[i])
                    for q in range(4):
                        acc = 0.0
                        for r in range(ns + 4):
                            acc += RD[q, r] * K[r, i]
                        Fd[3 + q, i] = h * acc
            while ie < ne and teval[ie] <= tn:
                th = (teval[ie] - t) / h
                for i in range(n):
                    acc = 0.0
                    for q in range(6, -1, -1):
                        acc += Fd[q, i]
                        if (6 - q) % 2 == 0:
                            acc *= th
                        else:
                            acc *= 1.0 - th
                    out[i, ie] = y[i] + acc
                ie += 1
            t = tn
            for i in range(n):
                y[i] = ynew[i]
                f[i] = fnew[i]
            h *= factor
            rejected = False
            for j in range(nd):
                ys = 0.0
                for e in range(PI.shape[0]):
                    if PI[e, 0] == 0 and PI[e, 1] == j:
                        ys += PV[e] * y[PI[e, 2]]
                if abs(ys) >= lim[j]:
                    status = ST_STROKE_LIMIT
                if fi[j, 0] >= 0:
                    a0 = nh + doff[j]
                    if min(y[a0 + fi[j, 0]], y[a0 + fi[j, 1]]) <= pfloor:
                        status = ST_PRESSURE
            if status != ST_OK:
                break
        else:
            if math.isfinite(err):
                h *= max(0.2, 0.9 * err ** expo)
            else:
                h *= 0.2
            rejected = True
    info[0] = status
    info[1] = t
    info[2] = nstep
    info[3] = nfev
    info[4] = ie
