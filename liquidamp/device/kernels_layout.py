"""The layout of the packed arrays of the compiled device physics: model ids (``M_*``),
parameter slots (``P_*``, :func:`pack_params`), composition slots (``S_*``), effect slots
(``E_*``).  Part of :mod:`liquidamp.device.kernels` (the public face, which re-exports
every name and documents the layout).
"""

from __future__ import annotations

import numpy as np

#: Fast-math flags of the pure arithmetic kernels: reciprocal and contraction only
#: (no assumption of finite values, so NaN/inf checks keep working).
_FM = {"arcp", "contract"}

# ---------------------------------------------------------------- model ids
M_FULL = 0
M_NO_INERTIA = 1
M_CONSTANT_BULK = 2
M_VOLUMETRIC = 3
M_SINGLE_STATE = 4
M_INERTIAL = 5
M_INERTIAL_2STATE = 6
M_MAXWELL = 7
M_DASHPOT = 8
M_SPRING = 9
M_DASHPOT_INERTER = 10
M_INERTER = 11
M_VISCOUS = 12

#: Base equation name -> compiled id.
MODEL_IDS = {
    "full": M_FULL,
    "no_inertia": M_NO_INERTIA,
    "constant_bulk": M_CONSTANT_BULK,
    "volumetric": M_VOLUMETRIC,
    "single_state": M_SINGLE_STATE,
    "inertial": M_INERTIAL,
    "inertial_2state": M_INERTIAL_2STATE,
    "maxwell": M_MAXWELL,
    "dashpot": M_DASHPOT,
    "spring": M_SPRING,
    "dashpot_inerter": M_DASHPOT_INERTER,
    "inerter": M_INERTER,
    "viscous": M_VISCOUS,
}
#: Compiled id -> number of base states.
BASE_STATES = {0: 5, 1: 4, 2: 2, 3: 2, 4: 1, 5: 3, 6: 2, 7: 1, 8: 0, 9: 0, 10: 0, 11: 0, 12: 0}

# ------------------------------------------------------- parameter vector
P_AP, P_V01, P_V02, P_BL, P_X01, P_X02, P_P0, P_N, P_RHO0 = range(9)
P_G1, P_G2, P_C1, P_C2, P_ST, P_LT, P_B01, P_B02, P_KD, P_TD = range(9, 19)
P_CONSTB, P_FRIC, P_CV, P_CL, P_BLM = 19, 20, 21, 22, 23
#: Quadratic coefficient c2 [N s^2/m^2] of the viscous damper F = c v + c2 v|v|.
P_CV2 = 24
N_PRM = 25

# ------------------------------------------------------------ composition
S_MID, S_N, S_NB, S_ICAV, S_IC, S_IFP, S_IZ = range(7)
S_LEAK, S_COUL, S_MASS, S_OFF, S_ANALYTIC, S_I1, S_I2, S_EFFECTS = range(7, 15)
#: Composition flags of issue #12 (slots 15-20): friction behind the kinematic effects
#: (Coulomb, smooth), relief valve, direction-dependent losses, the elastomer branch's
#: state index, end stops.
S_CPIST, S_ZPIST, S_RELIEF, S_ASYM, S_IEL, S_STOP = range(15, 21)
#: Rotating frame (centrifugal field along the device axis): 1 when composed, else -1.
S_ROT = 21
#: Gas charge (accumulator on a single-rod device): 1 when composed, else 0 (issue #20).
S_GAS = 22
#: Field-dependent yield (MR/ER valve): state index of its field lag u_f, else -1 (issue #20).
S_FY = 23
#: Self-heating (issue #20 item 5): index of the fluid temperature state T [K], else -1.
S_TH = 24
#: Freeplay that drives only the friction at ``location="piston"`` (the fluid stays on the rod:
#: a friction element behind its own dead band): 1 when so composed, else 0 or -1.
S_FPFRIC = 25
#: Position-dependent channel losses (``bypass_groove``): 1 when composed, else 0 or -1
#: (tested as ``> 0``).
S_GROOVE = 26
#: Slip weakening of smooth friction: state index of its slip memory w, else -1.
S_IW = 27
N_SPEC = 28

E_LEAK, E_PV, E_KC, E_GAP, E_SFC, E_SIG, E_VS, E_SR, E_CF, E_MASS, E_OFF = range(11)
E_PR, E_GR = 11, 12  # relief valve: cracking pressure [Pa], conductance [m^3/(s Pa)]
E_RR = 13  # direction-dependent losses: rebound ratio [-]
E_K0, E_K1, E_C1E = 14, 15, 16  # elastomer: k0, k1 [N/m], c1 [N s/m]
E_KS, E_CS, E_CLR, E_CTR = 17, 18, 19, 20  # end stops: k [N/m], c [N s/m], clearance, centre [m]
#: Direction-dependent friction: reverse-to-forward level ratio of smooth friction (slot 21)
#: and of Coulomb friction (slot 22) [-] (:func:`friction_level`).
E_FRQ, E_CRQ = 21, 22
#: Rotating frame: rotor speed [rad/s], radius of the device mid-point [m], cos(axis angle) [-].
E_OMEGA, E_RM, E_COSA = 23, 24, 25
#: Smooth friction's transition exponent n [-] (:func:`lugre_rate`).
E_FEX = 26
#: Gas charge: rod area [m^2], charge pressure [Pa], gas volume [m^3], polytropic index [-],
#: absolute stroke of the model's zero (the record's mean stroke) [m] (:func:`gas_force`).
E_AR, E_PCH, E_VG, E_NG, E_Y0G = 27, 28, 29, 30, 31
#: Rebound-direction cracking pressure [Pa] and conductance [m^3/(s Pa)] of the valve in
#: the ``S_RELIEF`` slot (``relief_valve``: equal to E_PR, E_GR; ``digressive_valve``: its own).
E_PR2, E_GR2 = 32, 33
#: Gas charge: ambient pressure on the rod's outer end [Pa] (the charge is gauge above it).
E_PAT = 34
#: Field-dependent yield: yield pressure drop at zero input [Pa] and per unit input
#: [Pa/V or Pa/A], lag rate of the field [1/s], smoothing mass flow [kg/s], slot index of
#: the input channel it reads (``CHANNELS``) (:func:`yield_drop`).
E_DPY0, E_DPY1, E_ETA, E_MEPS, E_FYCH = 35, 36, 37, 38, 39
#: Self-heating (:mod:`liquidamp.device.kernels_thermal`): heat capacity [J/K] (inf: the
#: temperature held), conductance to ambient [W/K], ambient temperature [K], reference
#: temperature of the loss coefficients [K], the exponential law's beta [1/K], the exponent
#: of the viscosity ratio on the quadratic loss [-], the law id [-] and its two constants.
E_TC, E_THA, E_TAMB, E_TREF, E_TBETA, E_TG2, E_TLAW, E_TA, E_TB = range(40, 49)
#: Self-heating: where the law's temperature comes from (0: the thermal state; 1: the
#: measured ``temperature`` channel, ``prm[P_CH + 0]``).
E_TSRC = 49
#: Bypass groove (:func:`~liquidamp.device.kernels_position.groove_scale`): depth d [-],
#: centre y_c [m] and half-width w [m] of the Gaussian band of the ABSOLUTE stroke where the
#: channel's loss coefficients are scaled by 1 - d exp(-((y + y_0 - y_c) / w)^2), and the
#: absolute stroke y_0 of the model's zero (the record's mean stroke) [m].
E_GD, E_GC, E_GW, E_GY0 = 50, 51, 52, 53
#: Slip weakening of smooth friction: excess of the breakaway level over the sliding one
#: [-] and the weakening (slip) distance [m] (:func:`slip_memory_rate`, :func:`weakening`).
E_WB, E_WD = 54, 55
#: Floating freeplay: dead-band half-width of the series contact [m] (0: none, the
#: series spring as it is) (:func:`~liquidamp.device.kernels_laws.float_contact`).
E_KCG = 56
#: The effect slots; the state scales follow from ``ep[N_EP]`` on.
N_EP = 57

# ------------------------------------------------------- measured input channels
#: Measured input channels a model may read by name (issue #20), in their slot order: an
#: effect declares the ones it reads (``Effect.input_channels``); the driver writes channel
#: k's value at the current time (every Runge-Kutta stage) into ``prm[P_CH + k]`` (SI:
#: temperature [K], voltage [V], current [A], pressure [Pa]) and its time derivative into
#: ``prm[P_CHD + k]`` (the recorded series is interpolated linearly, like the stroke).
CHANNELS = ("temperature", "voltage", "current", "pressure")
#: Number of input channel slots.
N_CH = 4
#: First slot of the channel values in the packed parameter vector (after the N_PRM
#: parameter slots; 0 until a driver writes them).
P_CH = N_PRM
#: First slot of the channel rates [unit/s].
P_CHD = N_PRM + N_CH
#: Length of the packed parameter vector: the parameters and the input channel slots.
N_PRM_ALL = N_PRM + 2 * N_CH


def channel_index(name: str) -> int:
    """Slot index k of the input channel ``name`` (``prm[P_CH + k]``).

    Examples
    --------
    >>> channel_index("voltage"), CHANNELS[channel_index("current")]
    (1, 'current')
    """
    from liquidamp.errors import check_choice

    check_choice("input channel", name, CHANNELS)
    return CHANNELS.index(name)


def pack_params(params) -> np.ndarray:
    """Packed parameter vector (``P_*`` order) of a parameter set.

    Parameters
    ----------
    params : DeviceParams or ViscousParams
        Device parameters (SI); a ViscousParams fills only the damping
        coefficients ``c`` (slot ``P_CV``) and ``c2`` (slot ``P_CV2``).

    Returns
    -------
    ndarray
        Shape (N_PRM_ALL,): the N_PRM parameter slots, then the input channel slots
        (``P_CH``, ``P_CHD``: zero until a driver writes them).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> v = pack_params(preset("reference"))
    >>> v.shape, bool(v[P_AP] == preset("reference").A_p), N_PRM
    ((33,), True, 25)
    """
    v = np.zeros(N_PRM_ALL)
    if not hasattr(params, "A_p"):  # the viscous damper F = c v + c2 v|v|
        v[P_CV] = float(params.c)
        v[P_CV2] = float(getattr(params, "c2", 0.0))
        v[P_FRIC] = float(getattr(params, "friction_N", 0.0))
        return v
    p = params
    v[P_AP], v[P_V01], v[P_V02], v[P_BL] = p.A_p, p.V01, p.V02, p.B_l
    v[P_X01], v[P_X02], v[P_P0], v[P_N] = p.X01, p.X02, p.p0, p.n
    v[P_RHO0], v[P_G1], v[P_G2] = p.rho0, p.g1, p.g2
    v[P_C1], v[P_C2], v[P_ST], v[P_LT] = p.c1, p.c2, p.S_t, p.L_t
    v[P_B01], v[P_B02], v[P_KD] = p.B01, p.B02, p.k_D
    v[P_TD] = p.T_D if p.c1 > 0.0 else np.inf
    v[P_CONSTB] = 1.0 if p.bulk_law == "constant" else 0.0
    v[P_FRIC] = p.friction_N
    v[P_CL], v[P_BLM] = p.c_L, p.b_L
    return v
