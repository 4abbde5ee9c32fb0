"""Sizing the liquid device for a host: a lag damper for a rotor, a flutter damper for a wing.

Scaling rule: s identical devices in parallel
    :func:`scale_device` turns a device into ``s`` copies of itself acting
    in parallel on the same stroke (``s`` may be any positive real):

    ==========================  =========  =====================================
    quantity                    factor     why
    ==========================  =========  =====================================
    A_p, V01, V02, A_t          s          s pistons, chambers and channels
    c1                          1/s        s laminar channels in parallel
    c2                          1/s^2      same pressure drop at s times the flow
    S_t = l_t/A_t               1/s        s channels in parallel
    friction_N                  s          s seals
    ==========================  =========  =====================================

    Then every chamber sees the same volumetric strain A_p y/V0 and the same
    pressures at the same stroke, so the stroke limit V0/A_p, the pressure
    swings, the cavitation margin and every corner frequency (T_D = c1/B,
    sqrt(B/L_t), c1/L_t) are unchanged, while k_D, c_L, b_L and the whole
    nonlinear force scale by exactly ``s``: K*_s(omega, Y) = s K*(omega, Y)
    for the full model (eq. 10) at every frequency and amplitude.  (Scaling
    A_p alone by s scales k_D, c_L and b_L by s^2 but shrinks the stroke
    limit and raises the pressure per stroke; scaling V0 with it, the force
    scales by s.)

Lag damper (:func:`size_lag_damper`)
    The device replaces the rotor's viscous lag damper C_lag [N m s/rad]
    acting through the arm a [m], i.e. a linear damper c = C_lag/a^2
    [N s/m] on the stroke.  The scale s is chosen so that the device's
    equivalent damping Im K*/omega [N s/m] -- the equivalent linearization
    of :mod:`liquidamp.analysis.response.equivalent` at the stated stroke amplitude
    -- equals c at the blade's rotating-frame lag frequency omega = nu Omega
    at the nominal rotor speed (the frequency at which the damper works in
    the regressing lag mode that drives ground resonance).  Closed form:
    s = c / (Im K*_1/omega), K*_1 of the unscaled device.

    Nominal speed of the Hammond (1974) rotor: the preset defines none.
    :data:`HAMMOND_NOMINAL_RPM` = 250 rpm is chosen near the coalescence of
    the regressing lag mode with the lateral (y) body mode,
    Omega (1 - nu) = omega_y (246 rpm), inside the band where the rotor with
    one failed viscous damper is unstable (210-307 rpm): the damper is
    sized where it matters most.  (Hammond reports stability against rotor
    speed without one operating speed.)

Ideal Maxwell comparison (:func:`maxwell_equivalent`)
    The Maxwell unit of eq. (16) with the sized device's stiffness k_D and
    the relaxation time chosen so that it gives the same damping at the
    sizing frequency: k T/(1 + omega^2 T^2) = c, the smaller root
    T = (k - sqrt(k^2 - 4 c^2 omega^2))/(2 c omega^2) (the damper branch).

Flutter damper (:func:`size_flutter_damper`)
    The device on the section's plunge (arm 1) or pitch (arm pitch_arm)
    port gives the damping ratio zeta of the uncoupled port mode at the
    bare section's flutter frequency omega_F: c = 2 zeta m_port omega_F
    with m_port = m s_span (plunge) or I_theta s_span/a^2 (pitch).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (10), (16), (18).
.. [2] C. E. Hammond, J. American Helicopter Society 19(4), 14-23, 1974.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from liquidamp._compat import renamed
from liquidamp.analysis.response.equivalent import equivalent_linearization
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, check_positive

__all__ = [
    "HAMMOND_NOMINAL_RPM",
    "nominal_speed",
    "scale_device",
    "DeviceSizing",
    "size_lag_damper",
    "maxwell_equivalent",
    "size_flutter_damper",
    "DAMPER_CHOICES",
    "lag_damper_device",
    "flutter_damper_device",
]

#: Special damper names besides device presets and files: the rotor's own
#: viscous damper and the ideal Maxwell unit sized from the reference design.
DAMPER_CHOICES = ("viscous", "maxwell")

#: Chosen nominal speed of the Hammond (1974) rotor [rpm] (module notes).
HAMMOND_NOMINAL_RPM = 250.0


def nominal_speed(rotor) -> float:
    """Nominal rotor speed [rad/s]: ``rotor.nominal_speed`` if defined, else the documented choice.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> round(nominal_speed(load_rotor("hammond1974")), 4)   # 250 rpm
    26.1799
    """
    W = getattr(rotor, "nominal_speed", None)
    if W:
        return float(W)
    return HAMMOND_NOMINAL_RPM * 2.0 * math.pi / 60.0


def scale_device(params: DeviceParams, s: float) -> DeviceParams:
    """``s`` copies of the device in parallel (module notes); K* scales by exactly ``s``.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> q = scale_device(p, 4.0)
    >>> [round(getattr(q, k) / getattr(p, k), 12) for k in ("k_D", "c_L", "b_L", "T_D")]
    [4.0, 4.0, 4.0, 1.0]
    >>> round(q.stroke_limit / p.stroke_limit, 12)
    1.0
    """
    s = check_positive("device scale s", s, "-")
    return params.replace(
        A_p=params.A_p * s, V01=params.V01 * s, V02=params.V02 * s, A_t=params.A_t * s,
        c1=params.c1 / s, c2=params.c2 / s**2, S_t=params.S_t / s,
        friction_N=params.friction_N * s,
        name=f"{params.name} x{s:.4g}" if params.name else f"x{s:.4g}")


@dataclass(frozen=True)
class DeviceSizing:
    """A device scaled to a host.

    Attributes
    ----------
    params : DeviceParams
        The scaled device.
    scale : float
        Parallel-copy factor s [-].
    arm : float
        Port arm [m] (1 for a translational port).
    frequency_hz : float
        Sizing frequency [Hz].
    amplitude_m : float
        Stroke amplitude of the equivalent linearization [m].
    target_damping : float
        Linear damping to match, Im K*/omega [N s/m].
    achieved_damping : float
        Im K*/omega of the scaled device at the sizing point [N s/m].
    storage_stiffness : float
        Re K* of the scaled device there [N/m].
    model : str
        Model whose equivalent linearization was used.
    rule : str
        The rule in words.
    """

    params: DeviceParams
    scale: float
    arm: float
    frequency_hz: float
    amplitude_m: float
    target_damping: float
    achieved_damping: float
    storage_stiffness: float
    model: str
    rule: str

    def as_dict(self) -> dict:
        """JSON-ready dictionary with unit-named keys."""
        return {"scale [-]": self.scale, "arm [m]": self.arm,
                "frequency [Hz]": self.frequency_hz, "amplitude [m]": self.amplitude_m,
                "target_damping [N s/m]": self.target_damping,
                "achieved_damping [N s/m]": self.achieved_damping,
                "storage_stiffness [N/m]": self.storage_stiffness, "model": self.model,
                "rule": self.rule, "params": self.params.derived()}


def _size(params, c_target, f_hz, amplitude, model, arm, rule) -> DeviceSizing:
    eq = equivalent_linearization(params, f_hz, amplitude, model)
    w = 2.0 * math.pi * f_hz
    c1 = eq.stiffness.value.imag / w
    if not c1 > 0.0:
        raise ParameterError(f"the device has no damping at {f_hz:g} Hz (Im K* = "
                             f"{eq.stiffness.value.imag:g} N/m); cannot size it")
    s = c_target / c1
    q = scale_device(params, s)
    K = equivalent_linearization(q, f_hz, amplitude, model).stiffness.value
    return DeviceSizing(q, s, arm, f_hz, amplitude, c_target, K.imag / w, K.real, model, rule)


def size_lag_damper(params: DeviceParams, rotor, arm: float | None = None,
                    Omega_nominal: float | None = None, amplitude: float = 1e-4, *,
                    model: str = "full") -> DeviceSizing:
    """Scale a device to replace the rotor's viscous lag damper (module notes).

    Parameters
    ----------
    params : DeviceParams
        Device to scale (a preset).
    rotor : GroundResonanceRotor
        Supplies C_lag = ``rotor.blade.lag_damping`` [N m s/rad] and the lag
        frequency.
    arm : float, optional
        Damper arm [m] (default ``rotor.blade.damper_arm``).
    Omega_nominal : float, optional
        Nominal rotor speed [rad/s] (default :func:`nominal_speed`).
    amplitude : float
        Stroke amplitude of the equivalent linearization [m] (default 0.1 mm:
        practically the small-signal damping, so that the linear stability
        comparisons are like for like; the quadratic loss then adds damping
        with amplitude).
    model : str
        Device model whose equivalent linearization is used (default full).

    Returns
    -------
    DeviceSizing

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.structure.hostio import load_rotor
    >>> sz = size_lag_damper(preset("reference"), load_rotor("hammond1974"))
    >>> round(sz.achieved_damping / (4067.5 / 0.25**2), 9), round(sz.frequency_hz, 4)
    (1.0, 1.1876)
    """
    a = rotor.blade.damper_arm if arm is None else check_positive("damper arm", arm, "m")
    W = nominal_speed(rotor) if Omega_nominal is None else check_positive(
        "nominal rotor speed", Omega_nominal, "rad/s")
    C = rotor.blade.lag_damping
    if not C > 0.0:
        raise ParameterError(f"the rotor's blade has no lag damper to replace (lag_damping = "
                             f"{C:g} N m s/rad)")
    f = rotor.blade.lag_frequency(W) / (2.0 * math.pi)
    rule = (f"s parallel copies with Im K*/omega = C_lag/arm^2 = {C / a**2:.6g} N s/m at the "
            f"lag frequency {f:.4g} Hz (Omega = {W:.4g} rad/s), stroke amplitude "
            f"{amplitude:g} m, equivalent linearization of model {model!r}")
    return _size(params, C / a**2, f, amplitude, model, a, rule)


@renamed(frequency_hz="frequency")
def maxwell_equivalent(params: DeviceParams, damping: float, frequency: float
                       ) -> DeviceParams:
    """Parameters whose Maxwell unit (eq. 16) has stiffness k_D and damping ``damping`` at f.

    Keeps k_D [N/m]; sets c1 so that T_D = c1/B gives Im K/omega =
    ``damping`` [N s/m] at ``frequency`` [Hz] (the smaller root; module
    notes), c2 = 0.  Use with model ``maxwell``.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> q = maxwell_equivalent(p, 1000.0, 2.0)
    >>> w = 4 * math.pi
    >>> round(q.k_D * q.T_D / (1 + (w * q.T_D) ** 2), 6)
    1000.0
    """
    c = check_positive("damping", damping, "N s/m")
    w = 2.0 * math.pi * check_positive("frequency", frequency, "Hz")
    k = params.k_D
    disc = k * k - 4.0 * c * c * w * w
    if disc < 0.0:
        raise ParameterError(f"a Maxwell unit of stiffness k_D = {k:.6g} N/m gives at most "
                             f"k_D/(2 omega) = {k / (2 * w):.6g} N s/m at {frequency:g} Hz; "
                             f"asked for {c:.6g} N s/m")
    T = (k - math.sqrt(disc)) / (2.0 * c * w * w)
    return params.replace(c1=T * params.B_eff, c2=0.0,
                          name=f"maxwell({params.name})" if params.name else "maxwell")


def size_flutter_damper(params: DeviceParams, section, *, port: str = "plunge",
                        zeta: float = 0.05, amplitude: float = 1e-4,
                        flutter_frequency: float | None = None, model: str = "full"
                        ) -> DeviceSizing:
    """Scale a device to damp the section's plunge or pitch (module notes).

    Parameters
    ----------
    params : DeviceParams
    section : TypicalSection
    port : {"plunge", "pitch"}
    zeta : float
        Damping ratio of the uncoupled port mode to provide [-].
    amplitude : float
        Stroke amplitude of the equivalent linearization [m].
    flutter_frequency : float, optional
        Sizing frequency [rad/s] (default: the bare section's flutter
        frequency, p method with Jones' aerodynamics).
    model : str

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.structure.hostio import load_section
    >>> sz = size_flutter_damper(preset("reference"), load_section("hodges-pierce"))
    >>> round(sz.frequency_hz, 3), round(sz.target_damping, 3)
    (2.577, 31.161)
    """
    z = check_positive("damping ratio zeta", zeta, "-")
    if port not in ("plunge", "pitch"):
        raise ParameterError(f"unknown port {port!r}; valid: plunge, pitch")
    if flutter_frequency is None:
        from liquidamp.analysis.stability.flutter import flutter_analysis

        r = flutter_analysis(section, "jones", "p")
        if r.flutter_frequency is None:
            raise ParameterError("the bare section does not flutter in 0.05-3.5; give "
                             "flutter_frequency [rad/s]")
        wF = r.flutter_frequency * section.omega_theta
    else:
        wF = check_positive("flutter frequency", flutter_frequency, "rad/s")
    if port == "plunge":
        m_port, arm = section.mass * section.span, 1.0
    else:
        arm = section.pitch_arm
        m_port = section.inertia * section.span / arm**2
    c = 2.0 * z * m_port * wF
    f = wF / (2.0 * math.pi)
    rule = (f"s parallel copies with Im K*/omega = 2 zeta m_port omega_F = {c:.6g} N s/m "
            f"(zeta = {z:g}, {port}) at {f:.4g} Hz, stroke amplitude {amplitude:g} m")
    return _size(params, c, f, amplitude, model, arm, rule)


def _device_params(spec: str) -> DeviceParams:
    from pathlib import Path

    from liquidamp.device import load_device_file, preset, preset_names

    if spec in preset_names():
        return preset(spec)
    if Path(spec).suffix.lower() in (".toml", ".json"):
        dev = load_device_file(spec)
        if dev.effects:  # never dropped silently: sizing scales the fluid device only
            names = ", ".join(e.name for e in dev.effects)
            raise ParameterError(
                f"device file {spec!r} has effects ({names}) that the sizing of a damper "
                "(parallel copies of the fluid device) cannot carry; give a device file "
                "without [effects.NAME] tables")
        return dev.params
    raise ParameterError(f"unknown damper {spec!r}; valid: {', '.join(DAMPER_CHOICES)}, "
                         f"{', '.join(preset_names())} or a .toml/.json device file")


def lag_damper_device(spec: str, rotor, *, arm: float | None = None, model: str = "full",
                      amplitude: float = 1e-4):
    """The lag damper named ``spec`` for ``rotor``, sized by :func:`size_lag_damper`.

    Parameters
    ----------
    spec : str
        ``viscous`` (the rotor's own damper C_lag/arm^2 [N s/m] as a device),
        ``maxwell`` (ideal Maxwell unit with the sized reference design's
        stiffness and the same damping at the sizing point), a device preset
        name or a .toml/.json device file.
    rotor : GroundResonanceRotor
    arm : float, optional
        Damper arm [m]; replaces the blade's ``damper_arm``.
    model : str
        Device model for presets and files (default full).
    amplitude : float
        Sizing stroke amplitude [m].

    Returns
    -------
    device : Device
    rotor : GroundResonanceRotor
        With the arm applied.
    sizing : DeviceSizing or None
        None for ``viscous``.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> d, r, s = lag_damper_device("viscous", load_rotor("hammond1974"))
    >>> d.params.c, s
    (65080.0, None)
    """
    from liquidamp.coupled.assembly import Device, viscous

    if arm is not None:
        rotor = rotor.replace(blade=rotor.blade.replace(
            damper_arm=check_positive("damper arm", arm, "m")))
    a = rotor.blade.damper_arm
    if spec == "viscous":
        return viscous(rotor.blade.lag_damping / a**2, "viscous"), rotor, None
    if spec == "maxwell":
        from liquidamp.device import preset

        sz = size_lag_damper(preset("reference"), rotor, amplitude=amplitude, model=model)
        mp = maxwell_equivalent(sz.params, sz.target_damping, sz.frequency_hz)
        return Device("maxwell", mp, "maxwell"), rotor, sz
    params = _device_params(spec)
    sz = size_lag_damper(params, rotor, amplitude=amplitude, model=model)
    return Device(model, sz.params, spec), rotor, sz


def flutter_damper_device(spec: str, section, *, port: str = "plunge", zeta: float = 0.05,
                          model: str = "full", amplitude: float = 1e-4):
    """A flutter damper named ``spec`` (``viscous``, ``maxwell``, preset or file) for the section.

    Sized by :func:`size_flutter_damper`; ``viscous`` is c = 2 zeta m_port
    omega_F [N s/m] itself.  Returns ``(Device, DeviceSizing or None)``.
    """
    from liquidamp.coupled.assembly import Device, viscous
    from liquidamp.device import preset

    if spec == "viscous":
        sz = size_flutter_damper(preset("reference"), section, port=port, zeta=zeta,
                                 amplitude=amplitude, model=model)
        return viscous(sz.target_damping, "viscous"), None
    if spec == "maxwell":
        sz = size_flutter_damper(preset("reference"), section, port=port, zeta=zeta,
                                 amplitude=amplitude, model=model)
        mp = maxwell_equivalent(sz.params, sz.target_damping, sz.frequency_hz)
        return Device("maxwell", mp, "maxwell"), sz
    sz = size_flutter_damper(_device_params(spec), section, port=port, zeta=zeta,
                             amplitude=amplitude, model=model)
    return Device(model, sz.params, spec), sz
