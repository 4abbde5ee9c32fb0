"""Where a calibration starts: a device sized to the records, the physics start, the trials.

:func:`~liquidamp.analysis.measured.calibration.calibrate` starts from the
device it is given (a published preset by default) when the records are near
it, and from a device sized to the records otherwise; it then evaluates the
physics start (air ratios and loss coefficients read off the records' first
harmonic) and keeps the best start.  Every start tried is a
:class:`StartTrial` with the figures a refusal names.

Near a preset
    The records are *near* the starting device when (i) the device runs under
    every record's stroke, (ii) the RMS of its force is within a factor
    :data:`NEAR_FORCE_RATIO` (4) of the RMS of the measured force (pooled,
    about the means), and (iii) the largest stroke of every record, about its
    mean, is at most :data:`NEAR_STROKE_SHARE` (half) of the chamber length
    V0/A_p.  Records made with any published preset from 1 to 4 Hz and 1 to
    3 mm are near ``paper_initial`` (force ratios 0.35 to 3.7) except the
    spring and inerter designs at 1 Hz; the physics start then corrects the
    stiffness and damping by multipliers.

Sizing rule: a similar device
    :func:`similar_device` scales a device by a force factor ``a`` and a stroke
    factor ``s`` at the same frequency:

    ====================  ===============  =========================================
    quantity              factor           why
    ====================  ===============  =========================================
    A_p                   a                a times the force at the same pressures
    V01, V02              a s              same volumetric strain A_p y / V0
    c1 (its factor)       1 / (a s)        same pressure drop at a s times the flow
    c2 (its factor)       1 / (a s)^2
    S_t (its factor)      1 / (a s)        same inertial pressure
    friction_N            a
    effect parameters     by their unit    N: a; N/m, kg: a / s; m, m/s: s;
                                           m^3/(s Pa): a s; Pa, -: 1
    ====================  ===============  =========================================

    Under the stroke s y(t) the similar device then holds exactly the pressures
    the original holds under y(t), so its force is exactly ``a`` times the
    original's (no new cavitation, the same loop shape; with s = 1 this is
    :func:`liquidamp.analysis.stability.sizing.scale_device`, written with the
    calibration factors so that no input becomes unused).  The records fix
    the factors: ``s = max(1, peak stroke / (NEAR_STROKE_SHARE x V0/A_p))``
    (the chamber keeps the stroke within half its length), and ``a`` the ratio
    of the RMS measured force to the RMS force of the device scaled by (1, s)
    under the records (one model run; if that run fails, the first-harmonic
    |K*| of the device's linear model, k_D in series with the channel, eq. 16,
    with c_eq = A_p^2 (c1 + 8 c2 Q / (3 pi)), stands in for it).  So the
    sized start's RMS force equals the measured RMS, and its peak force and
    first-harmonic |K*| are within a factor of two of the record's unless the
    loop shape differs wildly; the physics start then matches the storage and
    loss stiffness K', K'' by the air ratios and the loss coefficients.  The fit's
    multipliers and their bounds apply to the sized device, so the bounds scale
    with it; the effect parameters' catalogue bounds scale with the records
    (:func:`liquidamp.analysis.measured.fit_spec.scale_effect_bounds`).

Non-periodic records
    The first-harmonic dynamic stiffness K* = F1 / Y1 needs one stroke
    frequency.  A tapered stroke has one (its K* averages over the amplitudes
    it passes); for a broadband stroke :func:`first_harmonic_stiffness` falls
    back on the linear regression F ~ F0 + k y + c v + m a over the whole
    record and returns K* = k - w^2 m + i w c at the record's dominant
    frequency w (the periodogram peak).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (16), (19), Sec. IV.C.
.. [2] E. Buckingham, "On physically similar systems; illustrations of the use of
   dimensional equations", Phys. Rev. 4(4), 345-376, 1914 (similarity).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.measured.record_quality import loop_power
from liquidamp.analysis.measured.records import Record
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, PressureError

__all__ = ["NEAR_FORCE_RATIO", "NEAR_STROKE_SHARE", "similarity_factors", "similar_device",
           "first_harmonic_stiffness", "linear_fit", "linear_stiffness", "physics_factors",
           "StartTrial",
           "Sizing", "stroke_factor", "stroke_share", "refusal_message", "SIZING_CHOICES"]

#: Largest ratio (either way) of the measured to the model RMS force of a record near the
#: starting device [-].
NEAR_FORCE_RATIO = 4.0
#: Largest share of the chamber length V0/A_p the peak stroke of a record near the starting
#: device may use [-].
NEAR_STROKE_SHARE = 0.5
#: ``sizing`` choices of calibrate: size when far (auto), never (preset), always (data).
SIZING_CHOICES = ("auto", "preset", "data")

_UNIT_POWERS = {"N": (1, 0), "N/m": (1, -1), "kg": (1, -1), "m": (0, 1), "m/s": (0, 1),
                "m^3/(s Pa)": (1, 1), "Pa": (0, 0), "-": (0, 0)}


def similarity_factors(force: float, stroke: float = 1.0) -> dict:
    """Factor of each parameter unit under the similarity (force a, stroke s) [-].

    Examples
    --------
    >>> f = similarity_factors(10.0, 2.0)
    >>> f["N"], f["N/m"], f["m"], f["Pa"]
    (10.0, 5.0, 2.0, 1.0)
    """
    return {u: force ** p * stroke ** q for u, (p, q) in _UNIT_POWERS.items()}


def similar_device(params: DeviceParams, effects=(), *, force: float = 1.0,
                   stroke: float = 1.0) -> tuple[DeviceParams, tuple]:
    """The device (and its effects) scaled to ``force`` x the force under ``stroke`` x the stroke.

    See the module docstring's table.  The name records the scale.

    Parameters
    ----------
    params : DeviceParams
        The device.
    effects : sequence of Effect
        Its effects (parameters scaled by their unit).
    force, stroke : float
        Force factor a and stroke factor s [-], > 0.

    Returns
    -------
    (DeviceParams, tuple of Effect)

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("paper_initial")
    >>> q, _ = similar_device(p, force=8.0, stroke=2.0)
    >>> [round(getattr(q, k) / getattr(p, k), 12) for k in ("k_D", "c_L", "b_L", "stroke_limit")]
    [4.0, 4.0, 4.0, 2.0]
    >>> q.name, q.unused()
    ('paper_initial sized (force x8, stroke x2)', {})
    """
    for name, v in (("force", force), ("stroke", stroke)):
        if not (math.isfinite(v) and v > 0):
            raise ParameterError(f"similar_device: {name} factor must be finite and > 0 [-], "
                                 f"got {v!r}")
    a, s = float(force), float(stroke)
    q = params.scaled(A_p=a, V01=a * s, V02=a * s, c1=1.0 / (a * s), c2=1.0 / (a * s) ** 2,
                      S_t=1.0 / (a * s), friction_N=a)
    q = q.replace(name=f"{params.name or 'device'} sized (force x{a:.4g}, stroke x{s:.4g})")
    fac = similarity_factors(a, s)
    out = []
    for e in effects:
        out.append(e.replace(**{k: getattr(e, k) * fac.get(e.units.get(k, "-"), 1.0)
                                for k in e.parameters}))
    return q, tuple(out)


def stroke_share(records, params: DeviceParams, absolute: bool = False) -> float:
    """Largest share of its chamber length the records' stroke uses [-].

    Peak |y - mean| / (V0/A_p) with V0 = min(V01, V02); ``absolute``: the chambers follow
    the records' absolute stroke (a gas-charged device,
    :func:`~liquidamp.device.effects_damper.on_absolute_stroke`; V01, V02 at the datum
    y = 0), so about a record's mean y_m they hold V01 - A_p y_m and V02 + A_p y_m."""
    if absolute:
        A = params.A_p
        return max(float(np.max(np.abs(r.displacement - r.offset))) * A
                   / max(min(params.V01 - A * r.offset, params.V02 + A * r.offset), 1e-300)
                   if min(params.V01 - A * r.offset, params.V02 + A * r.offset) > 0
                   else float("inf") for r in records)
    return max(float(np.max(np.abs(r.displacement - r.offset)))
               for r in records) / params.stroke_limit


def stroke_factor(records, params: DeviceParams, absolute: bool = False) -> float:
    """s = max(1, :func:`stroke_share` / NEAR_STROKE_SHARE) over ``records`` [-].

    ``absolute`` (chambers on the absolute stroke): a similar device of stroke factor s
    holds s V0i / A_p of chamber length at the datum while a record's mean y_m is not
    scaled, so each record of amplitude Y asks s >= (Y / NEAR_STROKE_SHARE + y_m) A_p / V01
    and s >= (Y / NEAR_STROKE_SHARE - y_m) A_p / V02.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> t = np.arange(0.0, 2.0, 0.005)
    >>> r = Record.from_arrays(t, -0.03 + 0.01 * np.sin(4 * np.pi * t), 0 * t)
    >>> p = preset("reference").replace(V01=6e-5, V02=6e-5)     # 86.8 mm each
    >>> round(stroke_factor([r], p), 6), round(stroke_factor([r], p, True), 4)
    (1.0, 1.0)
    >>> q = p.replace(V01=2e-5, V02=2e-5)                        # 28.9 mm each
    >>> round(stroke_factor([r], q, True), 4)          # (2 x 10 mm + 30 mm) / 28.9 mm
    1.7279
    """
    if not absolute:
        return max(1.0, stroke_share(records, params) / NEAR_STROKE_SHARE)
    A, s = params.A_p, 1.0
    for r in records:
        Y = float(np.max(np.abs(r.displacement - r.offset))) / NEAR_STROKE_SHARE
        s = max(s, (Y + r.offset) * A / params.V01, (Y - r.offset) * A / params.V02)
    return s


# ---------------------------------------------------------------------------
# first harmonic and the linear device


def _harmonic(t, s, f):
    w = 2 * math.pi * f * (t - t[0])
    A = np.column_stack((np.sin(w), np.cos(w), np.ones_like(w)))
    (a, b, _), *_ = np.linalg.lstsq(A, s, rcond=None)
    return complex(a, b)


def first_harmonic_stiffness(record: Record) -> complex:
    """K* = K' + i K'' of a record at its stroke frequency [N/m] (fallback: module docstring).

    Periodic or tapered stroke (one frequency): F1 / Y1, the complex first
    harmonics of force and displacement fitted over the whole record (for a
    tapered stroke, an average over its amplitudes).  Broadband: k - w^2 m +
    i w c of the regression F ~ F0 + k y + c v + m a at the dominant frequency
    w (at one frequency y and a are collinear and the regression could not
    separate k from m).

    Examples
    --------
    >>> t = np.arange(0, 3.0, 0.005)
    >>> y = 0.003 * np.sin(2 * np.pi * 3 * t)
    >>> r = Record.from_arrays(t, y, 2e5 * y + 3e3 * np.gradient(y, t))
    >>> K = first_harmonic_stiffness(r)
    >>> round(K.real / 1e5, 2), round(K.imag / (2 * np.pi * 3 * 3e3), 2)
    (2.0, 1.0)
    """
    if record.periodic or record.shape.kind == "tapered":
        return _harmonic(record.time, record.force, record.frequency) / _harmonic(
            record.time, record.displacement, record.frequency)
    X = np.column_stack((np.ones_like(record.time), record.smoothed - record.offset,
                         record.velocity, record.acceleration))
    (_, k, c, m), *_ = np.linalg.lstsq(X, record.force, rcond=None)
    w = 2 * math.pi * record.frequency
    return complex(k - w * w * m, w * c)


def linear_fit(record: Record, b_L: float,
               stiffness: complex | None = None) -> tuple[float, float]:
    """k_D [N/m] and c [N s/m] of a spring in series with (dashpot c + inerter b_L).

    Solved from the record's first-harmonic dynamic stiffness
    K* (:func:`first_harmonic_stiffness`), or from ``stiffness`` [N/m] when given (a
    target at the record's frequency): 1/K = 1/k_D + 1/Z, Z = i w c - w^2 b_L.
    """
    K = first_harmonic_stiffness(record) if stiffness is None else complex(stiffness)
    w = 2 * math.pi * record.frequency
    W = 1.0 / K
    beta = w * w * b_L
    disc = 1.0 - 4.0 * beta * beta * W.imag ** 2
    u = (-1.0 + math.sqrt(disc)) / (2.0 * beta) if (beta > 0 and disc > 0) else 0.0
    s = W.real - u
    k_D = 1.0 / s if s > 0 else math.inf
    c = -W.imag / (w * (u * u + W.imag ** 2))
    return k_D, c


def physics_factors(records, params: DeviceParams, air=("inv_gamma1", "inv_gamma2"),
                    targets=None) -> tuple[float | None, float | None]:
    """Common factors on the air ratios and on c1, c2 that match the records' K' and K''.

    Each record's K* (:func:`first_harmonic_stiffness`; or ``targets``, one complex
    stiffness [N/m] per record, the part of the loop the fluid is to carry) is solved for the
    linear device's k_D and c (:func:`linear_fit`, with the device's b_L).
    The air factor (on the ratios named in ``air``) makes the device's k_D
    (eq. 2 at p0) the geometric mean of the records' (bracketed in
    [0.01, 100]); the loss factor makes its describing-function damping
    c_eq = A_p^2 (c1 + 8 c2 Q / (3 pi)), Q = A_p w Y, the geometric mean of
    c / c_eq over the records.  None where the records do not determine it
    (no finite positive k_D or c, or no bracket).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.analysis.measured.synthetic import synthetic_record
    >>> rec = synthetic_record(frequency=3.0, amplitude=0.003, cycles=2, seed=1)
    >>> f_air, f_loss = physics_factors([rec], preset("paper_initial"))
    >>> round(f_air, 2), round(f_loss, 2)   # a linear estimate (Table 2: 0.75/1.22, 3.56/4.04)
    (0.27, 3.8)
    """
    from scipy.optimize import brentq

    from liquidamp.errors import LiquidampError

    kds, cs = [], []
    targets = [None] * len(records) if targets is None else list(targets)
    if len(targets) != len(records):
        raise ParameterError(f"physics_factors: {len(targets)} target stiffnesses for "
                             f"{len(records)} records (one per record)")
    for r, K in zip(records, targets, strict=True):
        k_D, c = linear_fit(r, params.b_L if params.S_t else 0.0, K)
        if math.isfinite(k_D) and k_D > 0 and c > 0:
            kds.append(k_D)
            cs.append((c, r))
    f_air = f_loss = None
    if kds and air:
        target = float(np.exp(np.mean(np.log(kds))))

        def g(logf):
            f = math.exp(logf)
            return math.log(params.scaled(**dict.fromkeys(air, f)).k_D / target)
        try:
            lo, hi = math.log(0.01), math.log(100.0)
            f_air = math.exp(brentq(g, lo, hi)) if g(lo) * g(hi) < 0 else None
        except (ValueError, LiquidampError):
            f_air = None
    if cs:
        fs = []
        for c, r in cs:
            w = 2 * math.pi * r.frequency
            Q = params.A_p * w * r.stroke_scale
            ceq = params.A_p ** 2 * (params.c1 + 8.0 / (3.0 * math.pi) * params.c2 * Q)
            fs.append(c / ceq)
        f_loss = float(np.exp(np.mean(np.log(fs))))
    return f_air, f_loss


def linear_stiffness(params: DeviceParams, frequency: float, amplitude: float) -> complex:
    """K* [N/m] of the device's linear model at ``frequency`` [Hz] and ``amplitude`` [m].

    k_D in series with the channel (c_eq = A_p^2 (c1 + 8 c2 Q / (3 pi)),
    Q = A_p w Y, and b_L), eq. (16) with inertia.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> K = linear_stiffness(preset("reference"), 3.0, 0.001)
    >>> 0 < K.real < K.imag
    True
    """
    w = 2 * math.pi * frequency
    Q = params.A_p * w * amplitude
    ceq = params.A_p ** 2 * (params.c1 + 8.0 / (3.0 * math.pi) * params.c2 * Q)
    Z = 1j * w * ceq - w * w * params.b_L
    return 1.0 / (1.0 / params.k_D + 1.0 / Z)


# ---------------------------------------------------------------------------
# start trials


def _rms(x):
    return float(np.sqrt(np.mean((x - x.mean()) ** 2)))


@dataclass(frozen=True)
class StartTrial:
    """One start a calibration evaluated, and what was off there.

    Attributes
    ----------
    label : str
        ``"preset NAME"`` (the device as given, when the fit starts from a
        sized one), ``"spec"`` / ``"sized"`` (the specification's start on
        the starting device), ``"physics"``, ``"geometric mean"``.
    values : dict
        The fit parameters there (multipliers [-] on the starting device,
        effect parameters [SI]).
    device : str
        Name of the device the multipliers apply to.
    nrmse : float or None
        Pooled NRMSE over the calibration records [-]; None if the model
        could not be run.
    peak_model, peak_measured : float
        Largest |F - mean F| of the model and of the records [N].
    rms_ratio : float or None
        RMS(model force) / RMS(measured force), about the means [-].
    loss_share_model, loss_share_measured : float
        Mean power absorbed over RMS(F) RMS(v) of the model and of the records
        [-] (:func:`~liquidamp.analysis.measured.record_quality.loop_power`):
        positive where energy is absorbed.
    correlation : float or None
        Correlation of the model force with the measured [-].
    error : str
        Why the model could not be run ('' when it ran).
    forces : tuple of ndarray or None
        The model force on each record [N] (None if it could not be run; not
        in :meth:`as_dict`).
    cause : str
        ``"ok"``, ``"scale"`` (force level off by more than 2x), ``"sign"``
        (the model's force runs against the record's), ``"geometry"`` (the
        stroke passes the chamber end or the pressure reaches its floor),
        ``"integration"`` or ``"shape"`` (level and sign right, the loop's
        shape not).
    """

    label: str
    values: dict
    device: str
    nrmse: float | None
    peak_model: float = math.nan
    peak_measured: float = math.nan
    rms_ratio: float | None = None
    loss_share_model: float = math.nan
    loss_share_measured: float = math.nan
    correlation: float | None = None
    error: str = ""
    cause: str = "ok"
    forces: tuple | None = field(default=None, repr=False, compare=False)

    @classmethod
    def evaluate(cls, label, values, device, forces, records, masks):
        """The trial of model ``forces`` (one array per record, or the exception the run
        raised) against ``records`` (samples where ``masks`` is True)."""
        meas = np.concatenate([r.force[m] for r, m in zip(records, masks, strict=True)])
        peak_meas = float(np.max(np.abs(meas - meas.mean())))
        share_meas = _share(records, [r.force for r in records])
        if isinstance(forces, BaseException):
            text = str(forces)
            if isinstance(forces, PressureError) or "chamber end" in text:
                cause = "geometry"
            elif isinstance(forces, ParameterError):
                cause = "geometry" if "stroke" in text else "parameters"
            else:
                cause = "integration"
            return cls(label, dict(values), device, None, peak_measured=peak_meas,
                       loss_share_measured=share_meas,
                       error=f"{type(forces).__name__}: {text}", cause=cause)
        model = np.concatenate([f[m] for f, m in zip(forces, masks, strict=True)])
        den = _rms(meas)
        nr = float(np.sqrt(np.mean((model - meas) ** 2)) / den)
        peak_model = float(np.max(np.abs(model - model.mean())))
        ratio = _rms(model) / den
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = float(np.corrcoef(model, meas)[0, 1]) if _rms(model) > 0 else 0.0
        share_model = _share(records, forces)
        if corr < -0.3 or (share_model * share_meas < 0 and abs(share_model) > 0.05
                           and abs(share_meas) > 0.05):
            cause = "sign"
        elif not 0.5 <= ratio <= 2.0:
            cause = "scale"
        elif nr < 1.0:  # level and sign right, better than the mean force: usable
            cause = "ok"
        else:
            cause = "shape"
        return cls(label, dict(values), device, nr, peak_model, peak_meas, ratio, share_model,
                   share_meas, corr, "", cause, tuple(np.asarray(f, float) for f in forces))

    @property
    def ran(self) -> bool:
        """True when the model could be run at this start."""
        return self.nrmse is not None

    def describe(self) -> str:
        """One clause: the start, its parameters and what was off."""
        vals = ", ".join(f"{k} {v:.3g}" for k, v in self.values.items())
        head = f"{self.label} ({self.device}; {vals})"
        if not self.ran:
            return f"{head}: could not be run ({self.error}) -> {self.cause}"
        return (f"{head}: NRMSE {self.nrmse:.3g}, peak force {self.peak_model:.4g} N against "
                f"{self.peak_measured:.4g} N measured (RMS ratio {self.rms_ratio:.3g}), loss "
                f"share {self.loss_share_model:+.2f} against {self.loss_share_measured:+.2f}, "
                f"correlation {self.correlation:+.2f} -> {self.cause}")

    def as_dict(self) -> dict:
        """JSON-ready (SI)."""
        return {"start": self.label, "device": self.device, "values": dict(self.values),
                "nrmse": self.nrmse, "peak_force_model [N]": _finite(self.peak_model),
                "peak_force_measured [N]": _finite(self.peak_measured),
                "rms_ratio": self.rms_ratio,
                "loss_share_model": _finite(self.loss_share_model),
                "loss_share_measured": _finite(self.loss_share_measured),
                "correlation": self.correlation, "error": self.error, "cause": self.cause}


def _finite(x):
    return None if x is None or not math.isfinite(x) else float(x)


def _share(records, forces) -> float:
    """Pooled loss share of ``forces`` on ``records`` (power over RMS(F) RMS(v))."""
    P = num = 0.0
    for r, f in zip(records, forces, strict=True):
        _, p, _, share = loop_power(r, np.asarray(f, float))
        P += p * r.time.size
        num += (p / share if share else 0.0) * r.time.size
    return P / num if num else 0.0


@dataclass(frozen=True)
class Sizing:
    """The device a calibration starts from, and why.

    Attributes
    ----------
    params : DeviceParams
        Starting device (the multipliers apply to it).
    effects : tuple of Effect
        Its effects (scaled with it when sized).
    sized : bool
        True when sized to the records (False: the device as given).
    force_scale, stroke_scale : float
        Similarity factors a and s (1 when not sized) [-].
    rms_ratio : float or None
        Measured over model RMS force of the device as given [-] (None if it
        could not be run).
    reason : str
        Why this start (near the given device, or what made it far).
    air_factor, loss_factor : float
        Factors on the air ratios and on c1, c2 that match the records' K',
        K'' (:func:`physics_factors`; 1 when not sized) [-].
    trials : tuple of StartTrial
        The runs that decided it (the device as given first).
    """

    params: DeviceParams
    effects: tuple
    sized: bool
    force_scale: float = 1.0
    stroke_scale: float = 1.0
    rms_ratio: float | None = None
    reason: str = ""
    trials: tuple = field(default=(), repr=False)
    air_factor: float = 1.0
    loss_factor: float = 1.0

    def as_dict(self) -> dict:
        """JSON-ready."""
        return {"device": self.params.name or "custom", "sized": self.sized,
                "force_scale": self.force_scale, "stroke_scale": self.stroke_scale,
                "air_factor": self.air_factor, "loss_factor": self.loss_factor,
                "measured_over_model_rms_force": self.rms_ratio, "reason": self.reason,
                "near_rule": f"RMS force within {NEAR_FORCE_RATIO:g}x and peak stroke within "
                             f"{NEAR_STROKE_SHARE:.0%} of the chamber length V0/A_p"}


def refusal_message(trials, records, sizing: Sizing | None = None) -> str:
    """Why no start can be used: each start tried, what was off, the likely cause."""
    recs = ", ".join(r.label for r in records)
    usable = [t for t in trials if t.ran]
    causes = [t.cause for t in trials if t.cause != "ok"]
    likely = max(set(causes), key=causes.count) if causes else "shape"
    hint = {"scale": "the model's force level is far from the record's: check the force and "
                     "displacement units of the file, or start from a device of the record's "
                     "size (sizing='data', --sizing data)",
            "sign": "the model's force runs against the record's: check the sign convention "
                    "of the force column (positive when it resists a positive stroke)",
            "geometry": "the stroke does not fit the device (chamber end or cavitation): "
                        "start from a device sized to the record (sizing='data') or with "
                        "longer chambers",
            "integration": "the model could not be integrated: loosen --rtol or check the "
                           "device parameters",
            "parameters": "the starting parameters are invalid for this model",
            "shape": "the model reaches the right force level but not the loop's shape: "
                     "add the effects the record holds (diagnose) or vary more parameters"}
    parts = [f"calibration: no start can be used on {recs} (a start must run and reach an "
             "NRMSE below 2.9: beyond it the fit would prefer points where the model cannot "
             "run, penalized at 3)"]
    if sizing is not None:
        parts.append(f"start device: {sizing.params.name or 'custom'} ({sizing.reason})")
    parts.append("tried: " + "; ".join(t.describe() for t in trials))
    if not usable:
        parts.append("the model could not be run at any start")
    parts.append(f"likely cause: {likely}: {hint.get(likely, '')}")
    return ". ".join(parts)

