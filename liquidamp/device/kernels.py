"""The device physics, written once: every model of the family and every add-on effect.

This module holds the right-hand side, the Jacobian, the time derivative
along the stroke and the load-cell force of each model of Titurus (2018),
eqs. (10)-(20), and of each add-on effect, as numba-compiled functions on
plain float arrays.  Both engines call these same functions: the compiled
integrators of :mod:`liquidamp.coupled.fast` from inside their loops, the
scipy reference engine through :class:`~liquidamp.device.models.DeviceModel`'s
methods (``rhs``, ``jacobian``, ``force``).  There is no second copy of the
physics; independent checks come from closed forms, limits between models,
conservation laws, finite differences and a different integrator (scipy's
Radau) on the same equations.

A composed model travels as three arrays, built by
:meth:`~liquidamp.device.models.DeviceModel.packed`:

``spec`` (int64, ``S_*`` slots)
    the base model id (``M_*``), the state count, the base state count, the
    state index of each effect's states (-1: absent), the flags of the
    stateless effects and whether the analytic Jacobian applies;
``prm`` (float64, ``P_*`` slots)
    the device parameters (:func:`pack_params`);
``ep`` (float64, ``E_*`` slots, then one scale per state)
    the effect parameters and the state scales that size the
    finite-difference increments.

Composition (the order of :mod:`liquidamp.device.effects`): the kinematic
effects turn the measured rod stroke into the piston stroke the fluid sees
(freeplay outermost, then series compliance); the fluid effects act on the
chamber equations (direction-dependent loss coefficients ``S_ASYM``,
:func:`loss_params`; the bypass groove's position-dependent scale ``S_GROOVE``,
:func:`channel_params`, :mod:`~liquidamp.device.kernels_position`; leakage and the relief
valve ``S_RELIEF`` as second flow paths, :func:`relief_flow`; cavitation on the pressure
rates); on the stateless dashpot-type bases the relief valve and the rebound ratio are
the exact force law :func:`relief_force`; smooth friction's bristle state
is driven by the rod velocity, or by the piston's behind a dead band (``S_ZPIST``: friction at
the piston, :func:`piston_contact`); the force effects add to the load-cell
force (Coulomb friction at the piston through the dead band's contact
factor, ``S_CPIST``; the elastomer branch ``S_IEL``, :func:`elastomer_rate`;
end stops ``S_STOP``, :func:`stop_force`).

The Jacobian is analytic for every base model, with leakage on ``full`` and
``no_inertia``, with smooth friction, the elastomer, direction-dependent
losses and the bypass groove; compositions with cavitation, series compliance, freeplay, a relief
valve or leakage on the reductions use central differences of the same
compiled right-hand side (exact to about 1e-10 relative, which the
Rosenbrock stepper's error control absorbs).

References
----------
.. [1] B. Titurus, "Generalized Liquid-Based Damping Device for Passive
   Vibration Control", AIAA J. 56(10), 4134-4145, 2018, eqs. (2), (5),
   (10)-(20).
.. [2] C. Canudas de Wit et al., "A new model for control of systems with
   friction", IEEE TAC 40(3), 1995 (LuGre bristle state).
.. [3] M. A. Krasnosel'skii, A. V. Pokrovskii, Systems with Hysteresis,
   Springer, 1989 (play operator).
.. [4] H. E. Merritt, Hydraulic Control Systems, Wiley, 1967 (leakage,
   cavitation).
"""

from liquidamp.device.kernels_base import (  # noqa: F401 (the public face)
    BASE_N,
    base_force,
    base_force_series,
    base_jac,
    base_rhs,
    base_rhs_inline,
    base_rhs_t,
    full_all,
    state_force,
)
from liquidamp.device.kernels_laws import (  # noqa: F401 (the public face)
    Z_HOLD,
    _fd_step,
    _head_mean,
    _head_min,
    _lugre_dz_dv,
    _sign,
    _smoothstep,
    _stribeck,
    bulk,
    bulk_and_dp,
    c1_ramp,
    cavity_rates,
    cavity_width,
    compliance_rate,
    elastomer_rate,
    float_contact,
    friction_level,
    gas_force,
    gas_pressure,
    gas_slope,
    loss_flow,
    loss_flow_dp,
    lugre_rate,
    piston_contact,
    play_contact,
    play_rate,
    r_const,
    relief_flow,
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
from liquidamp.device.kernels_layout import (  # noqa: F401 (the public face)
    _FM,
    BASE_STATES,
    CHANNELS,
    E_AR,
    E_C1E,
    E_CF,
    E_CLR,
    E_COSA,
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
    E_GC,
    E_GD,
    E_GR,
    E_GR2,
    E_GW,
    E_GY0,
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
    E_OMEGA,
    E_PAT,
    E_PCH,
    E_PR,
    E_PR2,
    E_PV,
    E_RM,
    E_RR,
    E_SFC,
    E_SIG,
    E_SR,
    E_TA,
    E_TAMB,
    E_TB,
    E_TBETA,
    E_TC,
    E_TG2,
    E_THA,
    E_TLAW,
    E_TREF,
    E_TSRC,
    E_VG,
    E_VS,
    E_WB,
    E_WD,
    E_Y0G,
    M_CONSTANT_BULK,
    M_DASHPOT,
    M_DASHPOT_INERTER,
    M_FULL,
    M_INERTER,
    M_INERTIAL,
    M_INERTIAL_2STATE,
    M_MAXWELL,
    M_NO_INERTIA,
    M_SINGLE_STATE,
    M_SPRING,
    M_VISCOUS,
    M_VOLUMETRIC,
    MODEL_IDS,
    N_CH,
    N_EP,
    N_PRM,
    N_PRM_ALL,
    N_SPEC,
    P_AP,
    P_B01,
    P_B02,
    P_BL,
    P_BLM,
    P_C1,
    P_C2,
    P_CH,
    P_CHD,
    P_CL,
    P_CONSTB,
    P_CV,
    P_CV2,
    P_FRIC,
    P_G1,
    P_G2,
    P_KD,
    P_LT,
    P_N,
    P_P0,
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
    S_EFFECTS,
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
    channel_index,
    pack_params,
)
from liquidamp.device.kernels_model import (  # noqa: F401 (the public face)
    _damper_force,
    _fluid_rhs,
    _fp_contact,
    _relief_differential,
    channel_params,
    dissipated_power,
    flow_direction,
    force_series,
    force_series_inputs,
    loss_params,
    model_force,
    model_jac,
    model_rhs,
    model_rhs_t,
)
from liquidamp.device.kernels_position import (  # noqa: F401 (the public face)
    groove_ep_scale,
    groove_rate_terms,
    groove_scale,
)
from liquidamp.device.kernels_thermal import (  # noqa: F401 (the public face)
    LAW_EXPONENTIAL,
    LAW_WALTHER,
    LAW_WATER,
    channel_power,
    heat_rate,
    law_temperature,
    thermal_params,
    viscosity_ratio,
)

__all__ = [
    "MODEL_IDS", "BASE_STATES", "N_PRM", "N_SPEC", "N_EP", "pack_params",
    "CHANNELS", "N_CH", "P_CH", "P_CHD", "N_PRM_ALL", "channel_index",
    "bulk", "bulk_and_dp", "loss_flow", "loss_flow_dp",
    "lugre_rate", "play_contact", "piston_contact", "play_rate", "compliance_rate",
    "float_contact",
    "cavity_width", "cavity_rates", "c1_ramp", "relief_flow", "relief_force",
    "flow_direction", "loss_params", "channel_params", "groove_scale", "elastomer_rate",
    "stop_force",
    "rotating_heads", "rotating_slope", "rotating_offset_slopes", "yield_drop",
    "model_rhs", "model_jac", "model_rhs_t", "model_force", "friction_level", "force_series",
    "slip_memory_rate", "weakening",
    "force_series_inputs", "base_force_series",
]
