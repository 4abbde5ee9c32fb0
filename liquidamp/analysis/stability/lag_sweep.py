"""Lag damping against the 1/rev stroke: Floquet points and the K_lag prediction.

For each device and 1/rev damper stroke amplitude A1, the lag mode's damping
ratio on top of the forced 1/rev orbit
(:func:`~liquidamp.analysis.stability.forced_lag.forced_lag_damping`, Floquet;
an infinitesimal lag motion) and its prediction from the dual-frequency
dynamic stiffness K_lag at the lag amplitude A2
(:func:`~liquidamp.analysis.response.dual_frequency.dual_frequency_stiffness`
as a function of omega, passed through
:func:`~liquidamp.analysis.stability.forced_lag.lag_damping_from_stiffness`,
which iterates omega to the damped lag frequency of the prediction),
an equivalent linearization.  A quadratic (orifice) loss gains lag damping
under 1/rev motion (its slope 2 c2 |q| grows with the 1/rev flow); Coulomb
friction loses it (2 Fc / (pi Omega A1) against 4 Fc / (pi omega A2) alone).

:func:`friction_damper` builds the comparison friction damper: a dashpot
with a negligible laminar loss plus the ``smooth_friction`` effect (Floquet
refuses the non-smooth Coulomb law), its sliding force sized by the Coulomb
describing function so that its single-frequency lag damping equals a
reference device's.

References
----------
.. [1] K. Felker, B. Lau, S. McLaughlin, W. Johnson, J. American Helicopter
   Society 32(4), 45-53, 1987 (dual-frequency damper behaviour).
.. [2] A. Gelb, W. E. Vander Velde, *Multiple-Input Describing Functions and
   Nonlinear System Design*, McGraw-Hill, 1968 (describing functions).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from liquidamp.analysis.response.dual_frequency import dual_frequency_stiffness
from liquidamp.analysis.stability.forced_lag import forced_lag_damping, lag_damping_from_stiffness
from liquidamp.coupled.assembly import Device
from liquidamp.errors import ParameterError, check_positive

__all__ = ["friction_damper", "lag_damping_sweep"]

#: Pre-sliding stroke Fc / sigma0 of the comparison friction damper [m].
PRESLIDING_STROKE = 2e-5
#: Laminar loss c_L kept in the friction damper's dashpot base [N s/m].
FRICTION_BASE_DAMPING = 1.0


def friction_damper(reference: Device, lag_frequency: float, amplitude: float,
                    label: str = "smooth friction") -> tuple[Device, float]:
    """A friction damper with the single-frequency damping of ``reference`` at (omega, Y).

    The reference's equivalent damping c_eq = K''(omega, Y) / omega [N s/m]
    (:func:`~liquidamp.analysis.response.dual_frequency.dual_frequency_stiffness`
    with the lag motion alone) sets the sliding force by the Coulomb
    describing function c_eq = 4 Fc / (pi omega Y).  The damper is a
    ``dashpot`` of c_L = :data:`FRICTION_BASE_DAMPING` with the
    ``smooth_friction`` effect (sigma0 = Fc / :data:`PRESLIDING_STROKE`).

    Parameters
    ----------
    reference : Device
        A liquid device (``DeviceParams``).
    lag_frequency : float
        omega > 0 [rad/s].
    amplitude : float
        Lag stroke amplitude Y > 0 [m].
    label : str
        Label of the returned device.

    Returns
    -------
    device : Device
    force : float
        Fc [N].

    Examples
    --------
    A dashpot reference (c_eq = c_L at every amplitude): Fc = c_L pi omega Y / 4.

    >>> from liquidamp.device import preset
    >>> ref = Device("dashpot", preset("paper_calibrated"))
    >>> dev, Fc = friction_damper(ref, 7.5, 5e-4)
    >>> c_L = ref.params.c1 * ref.params.A_p**2
    >>> round(Fc / (c_L * math.pi * 7.5 * 5e-4 / 4.0), 9), dev.model.name
    (1.0, 'dashpot+smooth_friction')
    """
    from liquidamp.device.effects import SmoothFriction, with_effects
    from liquidamp.device.models import DeviceParams, get_model

    w = check_positive("lag frequency", lag_frequency, "rad/s")
    Y = check_positive("lag stroke amplitude", amplitude, "m")
    p = reference.params
    if not isinstance(p, DeviceParams):
        raise ParameterError(f"reference must be a liquid device (DeviceParams), "
                             f"got {type(p).__name__}")
    d = dual_frequency_stiffness(reference.model, p, 1.0, w / (2.0 * math.pi), 0.0, Y)
    c_eq = d.K_lag.imag / w
    Fc = c_eq * math.pi * w * Y / 4.0
    model = with_effects(get_model("dashpot"), SmoothFriction(Fc, Fc / PRESLIDING_STROKE))
    params = p.replace(c1=FRICTION_BASE_DAMPING / p.A_p**2)
    return Device(model, params, label), Fc


def lag_damping_sweep(blade, Omega: float, devices: dict, strokes: Sequence[float], *,
                      lag_amplitudes: Sequence[float] = (1e-4,), progress=None) -> dict:
    """Lag damping ratio against the 1/rev damper stroke: Floquet and the K_lag prediction.

    Parameters
    ----------
    blade : ArticulatedBlade
        The host (its own lag damper kept: set ``lag_damping=0`` for the
        device alone).
    Omega : float
        Rotor speed > 0 [rad/s].
    devices : dict
        Label -> :class:`~liquidamp.coupled.assembly.Device` (liquid models,
        smooth effects).
    strokes : sequence of float
        1/rev damper stroke amplitudes A1 >= 0 [m] (0: the rest state,
        ``moment=0``).
    lag_amplitudes : sequence of float
        Lag stroke amplitudes A2 > 0 of the K_lag prediction [m].
    progress : callable, optional
        Called with a one-line message per device.

    Returns
    -------
    dict
        JSON-ready: ``"rev_stroke [m]"``, ``"lag_amplitudes [m]"`` and, per
        label under ``"devices"``, ``"floquet_damping_ratio [-]"``,
        ``"floquet_frequency [rad/s]"``, ``"moment_amplitude [N m]"`` (lists
        over the strokes) and ``"klag_damping_ratio [-]"`` (one list per
        lag amplitude).

    Raises
    ------
    ParameterError
        A negative stroke, a non-positive lag amplitude, no devices.
    ConvergenceError
        From the orbit or the harmonic balance (the message names the point).

    Examples
    --------
    A linear viscous damper has no amplitude dependence, and K_lag = i c omega predicts
    the Floquet damping exactly (a liquid device takes seconds: see the tests).

    >>> from liquidamp.coupled.assembly import viscous
    >>> from liquidamp.structure.hostio import load_blade
    >>> b = load_blade("hammond1974").replace(lag_damping=0.0)
    >>> d = lag_damping_sweep(b, 26.0, {"v": viscous(5e3)}, [0.0, 1e-3], lag_amplitudes=[])
    >>> z = d["devices"]["v"]["floquet_damping_ratio [-]"]
    >>> round(z[1] / z[0], 9)
    1.0
    """
    W = check_positive("rotor speed Omega", Omega, "rad/s")
    A1s = [float(a) for a in strokes]
    for a in A1s:
        if not (math.isfinite(a) and a >= 0.0):
            raise ParameterError(f"1/rev stroke amplitudes must be finite and >= 0 [m], got {a!r}")
    A2s = [check_positive("lag stroke amplitude", a, "m") for a in lag_amplitudes]
    if not devices:
        raise ParameterError("devices must name at least one Device, got none")
    out = {"rotor_speed [rad/s]": W, "rev_stroke [m]": A1s, "lag_amplitudes [m]": A2s,
           "devices": {}}
    for label, dev in devices.items():
        floq, freq, moments, pred = [], [], [], [[] for _ in A2s]
        for A1 in A1s:
            r = (forced_lag_damping(blade, W, dev, stroke=A1) if A1 > 0.0
                 else forced_lag_damping(blade, W, dev, moment=0.0))
            floq.append(r.damping_ratio)
            freq.append(r.frequency)
            moments.append(r.moment_amplitude)
            for j, A2 in enumerate(A2s):
                def K(w, A1=A1, A2=A2, dev=dev):
                    return dual_frequency_stiffness(dev.model, dev.params, W / (2.0 * math.pi),
                                                    w / (2.0 * math.pi), A1, A2).K_lag

                pred[j].append(lag_damping_from_stiffness(blade, W, K, frequency=r.frequency)[0])
        out["devices"][label] = {"floquet_damping_ratio [-]": floq,
                                 "floquet_frequency [rad/s]": freq,
                                 "moment_amplitude [N m]": moments,
                                 "klag_damping_ratio [-]": pred}
        if progress is not None:
            progress(f"lag damping of {label}: " + ", ".join(
                f"{1e3 * a:g} mm {100 * z:.2f} %" for a, z in zip(A1s, floq, strict=True)))
    return out
