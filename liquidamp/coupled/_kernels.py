"""Compiled (numba) integrators of the device models on the test machine.

Private module: use it through :mod:`liquidamp.coupled.fast` or through
``SolverOptions(engine="compiled")``.  The rotor with devices has its own kernel
(:mod:`liquidamp.coupled._rotor_kernel`), the dense LU lives in
:mod:`liquidamp.coupled._linalg`.  The physics is not here: the
right-hand side, Jacobian, time derivative and force of every model and
effect are those of :mod:`liquidamp.device.kernels` (the one copy both
engines run), called on the arrays of
:meth:`~liquidamp.device.models.DeviceModel.packed`:

* ``spec`` describes the composed model (base id, states, effect slots);
* ``prm`` is the packed parameter vector;
* ``ep`` the effect parameters and state scales;
* measured input channels (issue #20) ride with a recorded stroke (the blocks after the
  acceleration in ``sa``) and are written into ``prm``'s channel slots at every stage
  time (:func:`~liquidamp.coupled._stroke_kernels.channel_eval`);
* the stroke is ``kind`` 0 (harmonic, evaluated analytically from
  ``sp = [Y, omega, offset, phase]``), 1 (recorded, linear interpolation of
  the arrays ``st, sy, sv, sa`` with the end values held outside, like
  :func:`numpy.interp`), 2 (two frequencies, evaluated analytically from
  ``sp = [offset, Y1, omega1, phase1, Y2, omega2, phase2]``) or 3 (a Fourier
  series, evaluated analytically from ``sp = [offset, omega, t0, K, s_1, c_1,
  ..., s_K, c_K]``, :class:`~liquidamp.structure.testmachine.FourierStroke`).

Two steppers share one loop, one error norm ``atol_i + rtol max(|x_i|,
|x_new,i|)``, one largest step and one polynomial form of the continuous
extension (output, pressure-floor location and steady-state test do not
depend on the method):

* the explicit Dormand-Prince 5(4) pair (FSAL, Shampine's 4th-order
  continuous extension, scipy's RK45 step control), which needs only six
  right-hand sides per step: most working points are not stiff (the
  reference design at 3 Hz: fluid mode near -127 +/- 133j 1/s against a
  0.33 s period);
* the L-stable, stiffly accurate Rosenbrock method RODAS4 of Hairer & Wanner
  (order 4, embedded order 3, continuous extension of order 3) with the
  analytic Jacobian of each model and the predictive step-size control of
  ``rodas.f``: one LU factorisation of ``I/(h gamma) - J`` per step and no
  Newton iteration, which suits these small (1-5 state), very stiff systems
  (the inerter preset as a Maxwell unit: T_D = 1.5e-4 s under a 2 s
  excitation).

``meth = METH_AUTO`` starts with Dormand-Prince and switches to RODAS4 when
the stiffness test of Hairer's ``dopri5.f`` fires (h |lambda| > 3.25 on 15
accepted steps), the way LSODA switches from Adams to BDF.

Speed and compile time: the integrator source :func:`_integrate_source` is
compiled twice from one text, as :data:`integrate` (both steppers) and as
:data:`integrate_explicit` (the RODAS4 branches pruned at compile time through
a global flag), so that a non-stiff first call compiles about half the code;
each serves a single span and, with ``max_cycles > 0``, the whole
periodic-steady-state loop.  The integrators (and the force series of
:mod:`liquidamp.device.kernels_model`) are compiled ``nogil``: a fit runs the columns of
its finite-difference Jacobian on several threads
(:mod:`liquidamp.analysis.measured.fit_objective`).  The linear algebra is one 5 x 5 LU
specialisation for every base model (smaller systems padded with the identity);
the full model evaluates f, J and df/dt at the start of a RODAS4 step
together (``device.kernels.full_all``); the stage times t + h share one stroke
evaluation.  A composition with more than five states (effect states) uses
the general LU.

References
----------
.. [1] E. Hairer, G. Wanner, Solving Ordinary Differential Equations II, 2nd ed.,
   Springer 1996, Sec. IV.7 (RODAS, coefficients of the code ``rodas.f``).
.. [2] B. Titurus, AIAA J. 56(10), 2018, eqs. (2), (5), (10)-(18).
.. [3] J. R. Dormand, P. J. Prince, A family of embedded Runge-Kutta formulae,
   J. Comput. Appl. Math. 6(1), 1980, 19-26.
.. [4] L. F. Shampine, Some practical Runge-Kutta formulas, Math. Comp. 46(173),
   1986, 135-150 (the continuous extension).
.. [5] E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I,
   2nd ed., Springer 1993, Sec. II.5 and IV.2 of vol. II (stiffness detection in
   ``dopri5.f``).
"""

from __future__ import annotations

import math
import types

import numpy as np
from numba import njit

from liquidamp._numba_cache import drop_stale
from liquidamp.coupled._linalg import lu5_factor, lu5_solve, lu_factor, lu_solve
from liquidamp.coupled._stroke_kernels import (  # noqa: F401 (re-exported)
    _next_break,
    _segment,
    channel_eval,
    stroke_eval,
    stroke_rate,
)
from liquidamp.device.kernels import (
    E_LEAK,
    M_FULL,
    P_FRIC,
    S_ANALYTIC,
    S_ASYM,
    S_COUL,
    S_GAS,
    S_GROOVE,
    S_IC,
    S_IEL,
    S_IFP,
    S_IZ,
    S_LEAK,
    S_MASS,
    S_MID,
    S_N,
    S_NB,
    S_OFF,
    S_ROT,
    S_STOP,
    base_force,
    base_jac,
    base_rhs,
    base_rhs_inline,
    base_rhs_t,
    full_all,
    model_force,
    model_jac,
    model_rhs,
    model_rhs_t,
)

drop_stale(__file__)  # before any kernel of this module loads from the cache


#: Compile-time flag of the plain-model kernels (see :data:`integrate_plain`).
_PLAIN_ONLY = False

#: Fast-math flags of the pure arithmetic kernels: reciprocal and contraction only
#: (no assumption of finite values, so NaN/inf checks keep working).
_FM = {"arcp", "contract"}

# ----------------------------------------------------------- status codes
ST_OK = 0
ST_PRESSURE = 1
ST_STEP_TOO_SMALL = 2
ST_TOO_MANY_STEPS = 3
ST_NOT_CONVERGED = 4
#: The explicit-only kernel met a stiff stretch (the caller reruns with RODAS4 compiled in).
ST_STIFF = 6

# ----------------------------------------------------- RODAS4 coefficients
_C2, _C3, _C4 = 0.386, 0.21, 0.63
_GAM = 0.25
_D1, _D2, _D3, _D4 = 0.25, -0.1043, 0.1035, -0.3620000000000023e-01
_A21 = 0.1544e01
_A31, _A32 = 0.9466785280815826, 0.2557011698983284
_A41, _A42, _A43 = 0.3314825187068521e01, 0.2896124015972201e01, 0.9986419139977817
_A51, _A52, _A53, _A54 = (0.1221224509226641e01, 0.6019134481288629e01,
                          0.1253708332932087e02, -0.6878860361058950)
_C21 = -0.56688e01
_C31, _C32 = -0.2430093356833875e01, -0.2063599157091915
_C41, _C42, _C43 = -0.1073529058151375, -0.9594562251023355e01, -0.2047028614809616e02
_C51, _C52, _C53, _C54 = (0.7496443313967647e01, -0.1024680431464352e02,
                          -0.3399990352819905e02, 0.1170890893206160e02)
_C61, _C62, _C63, _C64, _C65 = (0.8083246795921522e01, -0.7981132988064893e01,
                                -0.3152159432874371e02, 0.1631930543123136e02,
                                -0.6058818238834054e01)
_D21, _D22, _D23, _D24, _D25 = (0.1012623508344586e02, -0.7487995877610167e01,
                                -0.3480091861555747e02, -0.7992771707568823e01,
                                0.1025137723295662e01)
_D31, _D32, _D33, _D34, _D35 = (-0.6762803392801253, 0.6087714651680015e01,
                                0.1643084320892478e02, 0.2476722511418386e02,
                                -0.6594389125716872e01)


_RA = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [_A21, 0.0, 0.0, 0.0, 0.0],
    [_A31, _A32, 0.0, 0.0, 0.0],
    [_A41, _A42, _A43, 0.0, 0.0],
    [_A51, _A52, _A53, _A54, 0.0],
    [_A51, _A52, _A53, _A54, 1.0],
])
_RCC = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [_C21, 0.0, 0.0, 0.0, 0.0],
    [_C31, _C32, 0.0, 0.0, 0.0],
    [_C41, _C42, _C43, 0.0, 0.0],
    [_C51, _C52, _C53, _C54, 0.0],
    [_C61, _C62, _C63, _C64, _C65],
])
_RC = np.array([0.0, _C2, _C3, _C4, 1.0, 1.0])
_RD = np.array([_D1, _D2, _D3, _D4, 0.0, 0.0])


# ------------------------------------------------------------------ integrator
# ------------------------------------------- Dormand-Prince 5(4) coefficients
#: Method codes of :func:`integrate`: explicit start with stiffness switching,
#: RODAS4 throughout, Dormand-Prince 5(4) throughout.
METH_AUTO, METH_RODAS4, METH_DOPRI5 = 0, 1, 2
_EC = np.array([0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0])
_EA = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0],
])
_EB = np.array([35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0,
                11.0 / 84.0])
#: b - b_hat (order-5 minus the embedded order-4 weights), the last on the FSAL stage
_EE = np.array([71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0,
                22.0 / 525.0, -1.0 / 40.0])
#: Shampine's free 4th-order continuous extension: x(t + s h) = x + h sum_j K_j P_j(s)
_EP = np.array([
    [1.0, -2.8535800653862835, 3.0717434641059005, -1.1270175653862835],
    [0.0, 0.0, 0.0, 0.0],
    [0.0, 4.023133379230305, -6.249321565289, 2.675424484351598],
    [0.0, -3.7324019615885042, 10.068970589843675, -5.685526961588504],
    [0.0, 2.5548038301849423, -6.399112377351017, 3.5219323679207912],
    [0.0, -1.3744241142186024, 3.272657752246729, -1.7672812570757455],
    [0.0, 1.3824689317781436, -3.764937863556287, 2.382468931778144],
])
#: Stiffness test of ``dopri5.f``: h |lambda| above this on 15 accepted steps
#: (6 steps below it reset the count) switches the method to RODAS4.
_STIFF_HLAMBDA = 3.25
_STIFF_COUNT = 15
_NONSTIFF_RESET = 6


@njit(cache=True, error_model="numpy")
def _dp5_attempt(spec, prm, ep, kind, sp, st, sy, sv, sa, x, t, h, y0, v0, fsal, atol, rtol,
                 kk, ys, y6, xn, sc, ft):
    """One Dormand-Prince 5(4) step attempt of size h from (t, x); return its error norm.

    ``kk[0]`` must hold f(t, x) when ``fsal``; on return ``kk[0..6]`` hold the
    stages (``kk[6]`` = f(t + h, x_new), first same as last), ``xn`` the new
    state, ``y6`` the stage-6 state and ``sc`` the error scales (for the
    stiffness test).
    """
    n = x.size
    mid = spec[S_MID]
    y, v = y0, v0
    for s_i in range(1 if fsal else 0, 7):
        if s_i == 0:
            for i in range(n):
                ys[i] = x[i]
            channel_eval(kind, t, st, sa, prm)  # measured inputs at the stage time
        elif s_i < 6:
            for i in range(n):
                acc = 0.0
                for j in range(s_i):
                    acc += _EA[s_i, j] * kk[j, i]
                ys[i] = x[i] + h * acc
            y, v, a = stroke_eval(kind, t + _EC[s_i] * h, sp, st, sy, sv, sa)
            channel_eval(kind, t + _EC[s_i] * h, st, sa, prm)
        else:  # the new solution; its f (at t + h, as stage 6) is FSAL
            for i in range(n):
                y6[i] = ys[i]
                acc = 0.0
                for j in range(6):
                    acc += _EB[j] * kk[j, i]
                xn[i] = x[i] + h * acc
                ys[i] = xn[i]
        if _PLAIN_ONLY:  # the base equation alone (no effects): inlined
            base_rhs_inline(mid, ys, y, v, prm, 0.0, 0.0, ft)
        else:
            model_rhs(spec, ys, y, v, prm, ep, ft)
        for i in range(n):
            kk[s_i, i] = ft[i]
    err = 0.0
    for i in range(n):
        sc[i] = atol[i] + rtol * max(abs(x[i]), abs(xn[i]))
        acc = 0.0
        for j in range(7):
            acc += _EE[j] * kk[j, i]
        err += (h * acc / sc[i]) ** 2
    return math.sqrt(err / n)


@njit(cache=True, error_model="numpy")
def _dp5_dense(x, kk, h, pc):
    """Shampine's continuous extension of the accepted step as polynomial coefficients."""
    for i in range(x.size):
        pc[0, i] = x[i]
        for q in range(4):
            acc = 0.0
            for j in range(7):
                acc += kk[j, i] * _EP[j, q]
            pc[q + 1, i] = h * acc


@njit(cache=True, error_model="numpy")
def _stiff_hlambda(kk, xn, y6, sc, h):
    """h |lambda| estimate of ``dopri5.f`` from the last two stages (error-norm scaling)."""
    num = 0.0
    den = 0.0
    for i in range(xn.size):
        num += ((kk[6, i] - kk[5, i]) / sc[i]) ** 2
        den += ((xn[i] - y6[i]) / sc[i]) ** 2
    return h * math.sqrt(num / den) if den > 0.0 else 0.0


@njit(cache=True, error_model="numpy")
def _rodas_attempt(spec, prm, ep, kind, sp, st, sy, sv, sa, x, t, h, y0, v0, reuse_f0, f0,
                   J, fdt, atol, rtol, G, piv, dinv, kk, ys, ks, ft, xn):
    """One RODAS4 step attempt of size h from (t, x); return its error norm (inf: singular).

    ``J`` and ``fdt`` are the Jacobian and df/dt at (t, x); ``f0`` holds
    f(t, x) when ``reuse_f0``, else it is computed here.  On return ``kk``
    holds the six stages and ``xn`` the new state.
    """
    n = x.size
    mid = spec[S_MID]
    nj = G.shape[0]  # 5 (padded with the identity) or the state count where larger
    fac = 1.0 / (h * _GAM)
    for i in range(nj):
        for j in range(nj):
            G[i, j] = -J[i, j]
        G[i, i] += fac
    if nj == 5:
        if not lu5_factor(G, piv, dinv):
            return np.inf
    elif not lu_factor(G, piv):
        return np.inf
    y, v = y0, v0
    for st_i in range(6):
        for i in range(n):
            acc = x[i]
            for j in range(st_i):
                acc += _RA[st_i, j] * kk[j, i]
            ys[i] = acc
        if st_i == 0 and reuse_f0:
            for i in range(n):
                ft[i] = f0[i]
        else:
            if st_i == 0:
                y, v = y0, v0
                channel_eval(kind, t, st, sa, prm)  # measured inputs at the stage time
            elif st_i != 5:  # stages 5 and 6 share the time t + h
                y, v, a = stroke_eval(kind, t + _RC[st_i] * h, sp, st, sy, sv, sa)
                channel_eval(kind, t + _RC[st_i] * h, st, sa, prm)
            if _PLAIN_ONLY:
                base_rhs(mid, ys, y, v, prm, 0.0, 0.0, ft)
            else:
                model_rhs(spec, ys, y, v, prm, ep, ft)
            if st_i == 0:
                for i in range(n):
                    f0[i] = ft[i]
        for i in range(n):
            acc = ft[i] + h * _RD[st_i] * fdt[i]
            cs = 0.0
            for j in range(st_i):
                cs += _RCC[st_i, j] * kk[j, i]
            ks[i] = acc + cs / h
        if nj == 5:
            lu5_solve(G, piv, dinv, ks)
        else:
            lu_solve(G, piv, ks)
        for i in range(n):
            kk[st_i, i] = ks[i]
    err = 0.0
    for i in range(n):
        xn[i] = ys[i] + kk[5, i]
        sci = atol[i] + rtol * max(abs(x[i]), abs(xn[i]))
        err += (kk[5, i] / sci) ** 2
    return math.sqrt(err / n)


@njit(cache=True, error_model="numpy")
def _rodas_dense(x, xn, kk, pc):
    """RODAS4 continuous extension x(1-s) + s (x_new + (1-s)(d2 + s d3)) as a polynomial."""
    for i in range(x.size):
        d2 = (_D21 * kk[0, i] + _D22 * kk[1, i] + _D23 * kk[2, i] + _D24 * kk[3, i]
              + _D25 * kk[4, i])
        d3 = (_D31 * kk[0, i] + _D32 * kk[1, i] + _D33 * kk[2, i] + _D34 * kk[3, i]
              + _D35 * kk[4, i])
        pc[0, i] = x[i]
        pc[1, i] = xn[i] - x[i] + d2
        pc[2, i] = d3 - d2
        pc[3, i] = -d3
        pc[4, i] = 0.0


def _integrate_source(spec, prm, ep, kind, sp, st, sy, sv, sa, x0, t0, t1, teval, rtol, atol,
                      hmax, h0, fi1, fi2, pfloor, max_steps, steady_tol, min_cycles, max_cycles,
                      meth, out, info):
    """Integrate the composed model ``spec``, dense output at ``teval``; or march periods.

    The source of the two compiled entry points of the device integrator,
    :data:`integrate` (both methods) and :data:`integrate_explicit` (the
    same code with ``_WITH_RODAS = False``: the RODAS4 branches are pruned at
    compile time, so that a non-stiff first call compiles about half the
    code; where the stiffness test fires it returns ``ST_STIFF`` and the
    caller reruns the span with :data:`integrate`, which starts identically).
    Either serves a single span and the steady-state loop, so the stepper is
    compiled once per process.

    Method ``meth``: ``METH_RODAS4`` steps RODAS4 throughout;
    ``METH_DOPRI5`` the explicit Dormand-Prince 5(4) pair (FSAL, Shampine's
    continuous extension) throughout; ``METH_AUTO`` starts with
    Dormand-Prince and switches to RODAS4 for the rest of the span (steady
    mode: the rest of the period) when the stiffness test of Hairer's
    ``dopri5.f`` fires (h |lambda| > 3.25 estimated from the last two stages
    on 15 accepted steps), the way LSODA switches from Adams to BDF.  Both
    methods control the error on ``atol_i + rtol max(|x_i|, |x_new,i|)``,
    share the largest step ``hmax`` and the step size carried over, and
    write their continuous extension into one polynomial form, so that the
    output, the pressure-floor location and the steady-state test do not
    depend on the method.

    ``max_cycles == 0``: one span [t0, t1]; ``teval`` must be sorted within
    [t0, t1]; states go to ``out`` (n x len(teval)).

    ``max_cycles > 0``: periodic steady state of a harmonic stroke of period
    ``t1 - t0`` [s]: whole periods are marched from ``t0`` (the step size
    carried over) until the force waveform converges, with the acceptance
    rule of :func:`liquidamp.coupled.testrig.steady_state` (``steady_tol``,
    ``min_cycles``); ``teval`` is the sample grid of one period relative to
    its start (N + 1 points, the last at the period's end) and ``out``
    (n x (N + 1)) holds the last period marched.

    ``fi1, fi2`` are the indices of the chamber pressures to watch against
    ``pfloor`` (-1: none).  ``info`` (10 entries) receives [status, t_stop,
    h_last, steps, rejected, cycles, residual, last change, explicit steps,
    switches to RODAS4]; ``steps`` and ``rejected`` count the last span
    (steady mode: ``steps``, the explicit steps and the switches count all).
    Returns the final state.
    """
    n = x0.size
    ne = teval.size
    x = x0.copy()
    xn = np.empty(n)
    f0 = np.empty(n)
    ft = np.empty(n)
    fdt = np.empty(n)
    ys = np.empty(n)
    y6 = np.empty(n)
    sc = np.empty(n)
    # the linear algebra is 5 x 5 for every base model (at most 5 states): a
    # smaller system is padded with the identity (J is zero there), so that one
    # specialised factorisation serves them; a composition with more states
    # (effect states) uses the general LU
    nj = max(5, n)
    J = np.zeros((nj, nj))
    G = np.empty((nj, nj))
    piv = np.empty(nj, np.int64)
    dinv = np.empty(nj)
    kk = np.empty((7, n))
    pc = np.empty((5, n))
    ks = np.zeros(nj)
    full_fused = (spec[S_MID] == M_FULL and spec[S_N] == 5 and spec[S_ANALYTIC] != 0
                  and spec[S_ASYM] == 0  # the fused laws have no rebound ratio
                  and spec[S_GROOVE] <= 0)  # nor a position-dependent loss
    kL = ep[E_LEAK] if spec[S_LEAK] != 0 else 0.0
    # the load-cell force needs the stroke only for stateless bases and stroke-driven terms
    force_needs_stroke = (spec[S_NB] == 0 or spec[S_IFP] >= 0 or spec[S_IC] >= 0
                          or spec[S_IZ] >= 0 or spec[S_COUL] != 0 or spec[S_MASS] != 0
                          or spec[S_OFF] != 0 or spec[S_ROT] > 0 or prm[P_FRIC] > 0.0
                          or spec[S_IEL] >= 0 or spec[S_STOP] != 0 or spec[S_GAS] != 0)
    nf = max(ne - 1, 1)
    force_now = np.empty(nf)
    force_prev = np.empty(nf)
    period = t1 - t0
    ncyc = max_cycles if max_cycles > 0 else 1
    prev_change = np.inf
    residual = np.inf
    change = np.inf
    hits = 0
    hcar = h0
    total_steps = 0.0
    explicit_steps = 0.0
    switches = 0.0
    fsal = 0  # 1: kk[0] holds f(t, x) for the explicit method (int: no literal specialisation)
    for cyc in range(ncyc):
        if max_cycles > 0:
            ta = t0 + cyc * period
            te = ta + period
            off = ta
        else:
            ta = t0
            te = t1
            off = 0.0
        info[5] = cyc
        info[6] = residual
        info[7] = change
        t = ta
        span = te - ta
        ie = 0
        while ie < ne and (teval[ie] + off) <= ta:
            for i in range(n):
                out[i, ie] = x[i]
            ie += 1
        info[0] = ST_OK
        info[1] = te
        info[3] = 0.0
        info[4] = 0.0
        if span <= 0.0:
            info[2] = hcar
            return x
        # initial step: small; the controllers grow it by up to 5x (RODAS4) or
        # 10x (Dormand-Prince) per step
        h = hcar
        if not h > 0.0:
            h = 1e-5 * span
        h = min(h, hmax, span)
        hmin = 1e-14 * max(abs(ta), abs(te), span)
        steps = 0
        rejected = 0
        reject_prev = False
        hacc = 0.0
        erracc = 1.0
        expl = meth != METH_RODAS4
        iasti = 0
        nonsti = 0
        while t < te:
            if steps >= max_steps:
                info[0] = ST_TOO_MANY_STEPS
                info[1] = t
                info[2] = h
                return x
            last = False
            if t + h >= te - 1e-12 * span:
                h = te - t
                last = True
            tb = _next_break(kind, t, st, 1e-12 * span)
            hit_break = False
            if t + h >= tb:
                h = tb - t
                last = tb >= te
                hit_break = not last
            y0, v0, a0 = stroke_eval(kind, t, sp, st, sy, sv, sa)
            channel_eval(kind, t, st, sa, prm)
            if not expl:  # RODAS4: f, J and df/dt at (t, x)
                fsal = 0
                if _WITH_RODAS:
                    if kind != 1:  # analytic stroke: the rates are the evaluated (v, a)
                        yd, vd = v0, a0
                    else:
                        yd, vd = stroke_rate(kind, t, sp, st, sy, sv, sa)
                    if full_fused:  # sharing the fluid laws
                        full_all(x, y0, v0, yd, vd, prm, kL, f0, J, fdt)
                        reuse_f0 = True
                    elif _PLAIN_ONLY:  # analytic for every base equation
                        base_jac(spec[S_MID], x, y0, v0, prm, 0.0, J)
                        base_rhs_t(spec[S_MID], x, y0, v0, yd, vd, prm, 0.0, fdt)
                        reuse_f0 = False
                    else:
                        model_jac(spec, x, y0, v0, prm, ep, J)
                        model_rhs_t(spec, x, y0, v0, yd, vd, prm, ep, fdt)
                        reuse_f0 = False
            while True:  # attempts until one is accepted
                steps += 1
                if expl:
                    explicit_steps += 1.0
                    err = _dp5_attempt(spec, prm, ep, kind, sp, st, sy, sv, sa, x, t, h, y0, v0,
                                       fsal == 1, atol, rtol, kk, ys, y6, xn, sc, ft)
                    fsal = 1
                elif _WITH_RODAS:
                    err = _rodas_attempt(spec, prm, ep, kind, sp, st, sy, sv, sa, x, t, h, y0,
                                         v0, reuse_f0, f0, J, fdt, atol, rtol, G, piv, dinv, kk,
                                         ys, ks, ft, xn)
                    reuse_f0 = True
                else:  # not reached: the explicit-only kernel returns ST_STIFF instead
                    err = np.inf
                if not math.isfinite(err):
                    hnew = 0.25 * h
                elif expl:  # Dormand-Prince: error of order 5 (scipy's RK45 control)
                    if err <= 1.0:
                        hnew = h * (10.0 if err == 0.0 else min(10.0, 0.9 * err ** -0.2))
                    else:
                        hnew = h * max(0.2, 0.9 * err ** -0.2)
                else:  # RODAS4, with the predictive (Gustafsson) control of rodas.f
                    q = max(1.0 / 6.0, min(5.0, err ** 0.25 / 0.9))
                    if err <= 1.0 and hacc > 0.0:
                        qg = hacc / h * (err * err / erracc) ** 0.25 / 0.9
                        q = max(q, max(1.0 / 6.0, min(5.0, qg)))
                    hnew = h / q
                if err <= 1.0:
                    if not expl:
                        hacc = h
                        erracc = max(1e-2, err)
                    break
                rejected += 1
                reject_prev = True
                last = False
                hit_break = False
                h = hnew
                if h < hmin:
                    info[0] = ST_STEP_TOO_SMALL
                    info[1] = t
                    info[2] = h
                    return x
            if expl:
                _dp5_dense(x, kk, h, pc)
                # stiffness test of dopri5.f: 15 stiff-looking steps switch the method
                if meth == METH_AUTO:
                    if _stiff_hlambda(kk, xn, y6, sc, h) > _STIFF_HLAMBDA:
                        nonsti = 0
                        iasti += 1
                        if iasti >= _STIFF_COUNT:
                            if not _WITH_RODAS:
                                info[0] = ST_STIFF
                                info[1] = t
                                info[2] = h
                                return x
                            expl = False
                            switches += 1.0
                    else:
                        nonsti += 1
                        if nonsti >= _NONSTIFF_RESET:
                            iasti = 0
            elif _WITH_RODAS:
                _rodas_dense(x, xn, kk, pc)
            # ---------------- accepted step: output, pressure floor, advance
            tn = te if last else (tb if hit_break else t + h)
            while ie < ne and (teval[ie] + off) <= tn:
                s = ((teval[ie] + off) - t) / h
                for i in range(n):
                    out[i, ie] = pc[0, i] + s * (pc[1, i] + s * (pc[2, i] + s * (
                        pc[3, i] + s * pc[4, i])))
                ie += 1
            if fi1 >= 0 and min(xn[fi1], xn[fi2]) <= pfloor:
                # locate the crossing on the continuous extension (bisection)
                lo, hi = 0.0, 1.0
                for _ in range(60):
                    s = 0.5 * (lo + hi)
                    pm = 1e300
                    for i in (fi1, fi2):
                        pi = pc[0, i] + s * (pc[1, i] + s * (pc[2, i] + s * (
                            pc[3, i] + s * pc[4, i])))
                        pm = min(pm, pi)
                    if pm <= pfloor:
                        hi = s
                    else:
                        lo = s
                info[0] = ST_PRESSURE
                info[1] = t + hi * h
                info[2] = h
                for i in range(n):
                    x[i] = xn[i]
                return x
            t = tn
            for i in range(n):
                x[i] = xn[i]
                kk[0, i] = kk[6, i]  # FSAL (meaningful only after an explicit step)
            if reject_prev:
                hnew = min(hnew, h)
                reject_prev = False
            h = min(hnew, hmax)
            if h < hmin:
                h = hmin
        while ie < ne:  # rounding at the end point
            for i in range(n):
                out[i, ie] = x[i]
            ie += 1
        info[2] = h
        info[4] = rejected
        total_steps += steps
        info[3] = total_steps
        info[8] = explicit_steps
        info[9] = switches
        if max_cycles == 0:
            return x
        hcar = h
        # force waveform of this period against the previous one
        for j in range(nf):
            for i in range(n):
                ks[i] = out[i, j]
            if _PLAIN_ONLY:  # a force carried by the states (and the set's friction)
                fj = base_force(spec[S_MID], ks, 0.0, 0.0, 0.0, prm)
                if prm[P_FRIC] > 0.0:
                    y, v, a = stroke_eval(kind, teval[j] + off, sp, st, sy, sv, sa)
                    if v > 0.0:
                        fj += prm[P_FRIC]
                    elif v < 0.0:
                        fj -= prm[P_FRIC]
            elif force_needs_stroke:
                y, v, a = stroke_eval(kind, teval[j] + off, sp, st, sy, sv, sa)
                channel_eval(kind, teval[j] + off, st, sa, prm)
                fj = model_force(spec, ks, y, v, a, prm, ep, True)
            else:  # a force carried by the states alone
                fj = base_force(spec[S_MID], ks, 0.0, 0.0, 0.0, prm)
            force_now[j] = fj
        if cyc > 0:
            change, residual, hits = steady_rule(force_now, force_prev, prev_change, residual,
                                                 hits, cyc, rtol, steady_tol, min_cycles)
            if hits >= 2:
                info[0] = ST_OK
                info[1] = te
                info[5] = cyc + 1
                info[6] = min(residual, change)
                info[7] = change
                return x
            prev_change = change
        for j in range(nf):
            force_prev[j] = force_now[j]
    info[0] = ST_NOT_CONVERGED
    info[1] = max_cycles * period
    info[5] = max_cycles
    info[6] = residual
    info[7] = prev_change
    return x


@njit(cache=True, error_model="numpy")
def steady_rule(force_now, force_prev, prev_change, residual, hits, cyc, rtol, steady_tol,
                min_cycles):
    """The periodic-steady-state acceptance rule of both engines, after cycle ``cyc`` (0-based).

    ``change`` is the RMS change of the force waveform against the previous
    cycle relative to its peak; with ``rho = change / prev_change`` the
    distance still to go is estimated as ``change rho / (1 - rho)``
    (``residual``).  A cycle counts (``hits`` + 1) when that estimate is
    below ``steady_tol`` or the change is at the round-off floor 50 rtol,
    after ``min_cycles``; two in a row accept.  Returns ``(change, residual,
    hits)``.
    """
    nf = force_now.size
    fmax = 0.0
    acc = 0.0
    for j in range(nf):
        fmax = max(fmax, abs(force_now[j]))
        acc += (force_now[j] - force_prev[j]) ** 2
    change = math.sqrt(acc / nf) / max(fmax, 1e-30)
    rho = change / prev_change if prev_change > 0.0 else 0.0
    if rho < 1.0:
        residual = change * rho / (1.0 - rho) if cyc > 1 else change
    else:
        residual = max(change, residual if math.isfinite(residual) else change)
    residual = max(residual, 0.0)
    if (residual < steady_tol or change < 50.0 * rtol) and cyc + 1 >= min_cycles:
        hits += 1
    else:
        hits = 0
    return change, residual, hits


def _specialise(fn, name: str, **constants):
    """``fn`` compiled (and cached under ``name``) with module globals overridden.

    Numba freezes global values at compile time and prunes branches on
    constant conditions, so a global flag selects which code is compiled.
    """
    g = dict(fn.__globals__)
    g.update(constants)
    f = types.FunctionType(fn.__code__, g, name, fn.__defaults__)
    f.__qualname__ = name
    f.__doc__ = fn.__doc__
    return njit(cache=True, error_model="numpy", nogil=True)(f)


_WITH_RODAS = True
#: Compiled integrator with both steppers (``meth``: auto, rodas4 or dopri5), any model
#: with any effects.
integrate = _specialise(_integrate_source, "integrate", _WITH_RODAS=True)
#: The same without RODAS4 (``meth``: auto or dopri5; auto returns ``ST_STIFF``
#: where it would switch).
integrate_explicit = _specialise(_integrate_source, "integrate_explicit", _WITH_RODAS=False)
# the same two for a base equation without effects: the composition code is pruned at
# compile time (a first call on a bare model compiles about half as much)
_dp5_plain = _specialise(_dp5_attempt.py_func, "_dp5_attempt_plain", _PLAIN_ONLY=True)
_rodas_plain = _specialise(_rodas_attempt.py_func, "_rodas_attempt_plain", _PLAIN_ONLY=True)
#: :data:`integrate` for a model without effects (``spec[S_EFFECTS] == 0``).
integrate_plain = _specialise(_integrate_source, "integrate_plain", _WITH_RODAS=True,
                              _PLAIN_ONLY=True, _dp5_attempt=_dp5_plain,
                              _rodas_attempt=_rodas_plain)
#: :data:`integrate_explicit` for a model without effects.
integrate_explicit_plain = _specialise(_integrate_source, "integrate_explicit_plain",
                                       _WITH_RODAS=False, _PLAIN_ONLY=True,
                                       _dp5_attempt=_dp5_plain, _rodas_attempt=_rodas_plain)
