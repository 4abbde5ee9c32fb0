"""Quality of a measured record: noise floor, outliers, spikes, before any model run.

:func:`noise_floor` estimates the force a model driven by the stroke cannot reproduce
(cycle-to-cycle scatter; load-cell noise from the high-frequency content where the
stroke is not periodic) and the NRMSE a perfect model would reach;
:func:`check_record` finds isolated force and displacement spikes judged against the
record's own local rates (:func:`~liquidamp.analysis.measured.spikes.find_spikes`,
:class:`Outlier`), tests the force for a drift over the record
(:func:`~liquidamp.analysis.measured.drift.record_drift`), checks the loop's energy sign,
the sampling and the stroke against the chamber, and summarizes them
(:class:`DataQuality`).  Run it on the record as read (:func:`as_read`), never on samples
the conditioning made.

Periodic and non-periodic strokes (:attr:`Record.periodic
<liquidamp.analysis.measured.records.Record.periodic>`): the checks that rest on
one stroke frequency (the force's first harmonic, the harmonics removed before a
spike search or a noise estimate, the energy per cycle) have a fallback for a
tapered or broadband stroke, stated in each function: the force is then
regressed on the stroke, its rate and its acceleration (a linear device,
F ~ F0 + k y + c v + m a) instead of on the harmonics.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B-C.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from liquidamp.analysis.measured.drift import Drift, drift_columns, record_drift
from liquidamp.analysis.measured.drift import regressors as _regressors
from liquidamp.analysis.measured.records import CHANNEL_SI, Record
from liquidamp.analysis.measured.spikes import (
    SPIKE_LOCAL,
    SPIKE_NOISE,
    SPIKE_WIDTH,
    Outlier,
    find_spikes,
)
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError
from liquidamp.structure.testmachine import harmonics_tested

__all__ = ["NoiseFloor", "noise_floor", "high_band_std", "line_coefficients", "Outlier",
           "DataQuality", "check_record",
           "check_record_stroke", "velocity_gain", "loop_power", "find_spikes", "as_read",
           "channel_summary", "Drift"]


@dataclass(frozen=True)
class NoiseFloor:
    """Noise estimated from a record.

    Attributes
    ----------
    force_std : float
        Standard deviation of the force that no model driven by the stroke can
        reproduce [N] (see ``method``).
    displacement_std : float
        Standard deviation of the LVDT noise [m].
    nrmse : float
        The NRMSE a perfect model driven by the recorded stroke would reach,
        hypot(force_std, rate_force_std) over the force's RMS about its mean [-].
    method : str
        ``"cycle scatter"`` (``"cycle scatter, drift removed (degree D in time)"`` for a
        drifting record): the force less its best periodic fit (all harmonics of
        the stroke frequency up to 0.45 x the sampling rate, at most 64), robust
        scale: the cycle-to-cycle scatter at the same phase plus what lies above the
        harmonics fitted; ``"high band"``: the
        4th differences of the force less its first 12 harmonics (a stroke that is
        not periodic, or fewer than two cycles).
    harmonics : int
        Harmonics fitted by the cycle-scatter estimate (0 for ``"high band"``).
    rate_force_std : float
        Force error [N] that the scatter of the recorded stroke rate causes in a model
        driven by it (:func:`noise_floor`; 0 for ``"high band"``, which
        :func:`~liquidamp.analysis.measured.conditioning.condition` completes with the rate
        term of a stroke that does not repeat: method ``"high band, with the stroke rate's
        noise"``).
    rate_std : float
        That scatter of the stroke rate [m/s] (0 for ``"high band"``, as above).
    drift : Drift or None
        The record's non-stationarity test
        (:func:`~liquidamp.analysis.measured.drift.record_drift`).
    drift_std : float
        RMS of the force drift kept out of ``force_std`` [N] (0 when stationary).
    drift_nrmse : float
        ``drift_std`` over the force's RMS about its mean [-]: the NRMSE a model of a
        stationary device would keep from the drift alone (0 when stationary).
    """

    force_std: float
    displacement_std: float
    nrmse: float
    method: str = "high band"
    harmonics: int = 0
    rate_force_std: float = 0.0
    rate_std: float = 0.0
    drift: Drift | None = None
    drift_std: float = 0.0
    drift_nrmse: float = 0.0

    @property
    def std(self) -> float:
        """hypot(force_std, rate_force_std) [N]: the force error a perfect model would show."""
        return math.hypot(self.force_std, self.rate_force_std)


def line_coefficients(v, y, F) -> tuple[float, float, float]:
    """Least-squares (c [N s/m], k [N/m], F0 [N]) of the line F = c v + k y + F0 on the stroke
    rate v [m/s], stroke y [m] and force F [N] (the reference model of
    :func:`~liquidamp.analysis.measured.reference_models.fit_line`, and the damping the
    floor of a stroke that does not repeat carries the rate's noise through).

    >>> v = np.array([0.1, -0.1, 0.0, 0.05]); y = np.array([0.0, 1e-3, -1e-3, 2e-3])
    >>> [round(x, 6) for x in line_coefficients(v, y, 2000 * v + 1e4 * y + 5.0)]
    [2000.0, 10000.0, 5.0]
    """
    A = np.column_stack([v, y, np.ones_like(v)])
    coef, *_ = np.linalg.lstsq(A, F, rcond=None)
    return float(coef[0]), float(coef[1]), float(coef[2])


def high_band_std(t, s, f, harmonics=12, periodic=True):
    """Robust white-noise standard deviation of a uniformly sampled signal [its unit].

    The signal less its mean and, for a periodic stroke, its first ``harmonics`` harmonics
    of ``f`` [Hz] below 0.8 x the Nyquist frequency; then 1.4826 x the median absolute
    deviation of its 4th differences over sqrt(70) (their variance for white noise of
    unit variance).  A component at frequency f' is suppressed by (2 sin(pi f' / fs))^4,
    so the estimate holds while the signal's own band lies well below the sampling rate.

    Parameters
    ----------
    t : array
        Sample times, uniform [s].
    s : array
        The signal (a force [N] or a displacement [m]).
    f : float
        Stroke frequency [Hz].
    harmonics : int
        Harmonics of ``f`` removed first (periodic strokes only).
    periodic : bool
        Whether the stroke repeats (False: only the mean is removed).

    Examples
    --------
    >>> rng = np.random.default_rng(3)
    >>> t = np.arange(4000) / 1000.0
    >>> s = 2e-3 * np.sin(2 * np.pi * 2.0 * t) + rng.normal(0.0, 1e-6, t.size)
    >>> bool(abs(high_band_std(t, s, 2.0) / 1e-6 - 1) < 0.1)
    True
    """
    w = 2 * math.pi * f * (t - t[0])
    cols = [np.ones_like(t)]
    nyq = 0.5 / float(np.median(np.diff(t)))
    for k in range(1, harmonics + 1 if periodic else 1):
        if k * f < 0.8 * nyq:
            cols += [np.sin(k * w), np.cos(k * w)]
    A = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(A, s, rcond=None)
    d4 = np.diff(s - A @ coef, 4)
    mad = float(np.median(np.abs(d4 - np.median(d4))))
    return 1.4826 * mad / math.sqrt(70.0)


def _periodic_scatter(record: Record, max_harmonics: int = 64, drift: Drift | None = None):
    """(force scatter [N], rate-driven force scatter [N], harmonics, rate scatter [m/s],
    drift std [N]) or None (noise_floor)."""
    t = record.time - record.time[0]
    f, n = record.frequency, record.time.size
    H = harmonics_tested(record.sampling_rate, f, max_harmonics)
    if record.cycles < 2.0 or H < 1:
        return None
    w = 2 * math.pi * f * t
    A = np.empty((n, 2 * H + 1))
    A[:, 0] = 1.0
    for k in range(1, H + 1):
        A[:, 2 * k - 1], A[:, 2 * k] = np.sin(k * w), np.cos(k * w)
    data = np.column_stack((record.displacement, record.force, record.velocity))
    coef, _, rank, _ = np.linalg.lstsq(A, data, rcond=None)
    res = data - A @ coef
    dof = n - int(rank)
    # the stroke must repeat: a tapered or broadband stroke has no phase to compare at
    if dof < max(20, n // 4) or np.sqrt(np.mean(res[:, 0] ** 2)) > 0.05 * record.amplitude:
        return None
    drift_std = 0.0
    if drift is not None and drift.nonstationary:
        # the drift is not noise: every harmonic holding more than 0.2 % of the largest
        # (at most 32), modulated by Legendre polynomials of time up to the drift's degree
        amp = np.hypot(coef[1::2, 1], coef[2::2, 1])
        big = [k for k in range(1, H + 1) if amp[k - 1] >= 2e-3 * amp.max()][:32]
        cols = [0] + [c for k in big for c in (2 * k - 1, 2 * k)]
        B = np.hstack((A, drift_columns(A[:, cols], t, drift.degree)))
        cf, _, rk, _ = np.linalg.lstsq(B, record.force, rcond=None)
        rf = record.force - B @ cf
        drift_std = float(np.std(B[:, A.shape[1]:] @ cf[A.shape[1]:]))
        if n - int(rk) >= max(20, n // 4):
            res[:, 1] = rf * math.sqrt(dof / (n - int(rk)))  # same scale as the others below
    # robust scale: each residual has variance sigma^2 (1 - h_ii), dof / n on average
    mad = np.median(np.abs(res - np.median(res, axis=0)), axis=0)
    force_std, rate_std = 1.4826 * mad[1:] / math.sqrt(dof / n)
    # the stroke rate's scatter reaches the force through the loss part of the first-harmonic
    # dynamic stiffness, c_eq = Im(K*) / w (the model's stroke is the integral of the rate)
    K = complex(coef[1, 1], coef[2, 1]) / complex(coef[1, 0], coef[2, 0])
    return (float(force_std), float(abs(K.imag) / (2 * math.pi * f) * rate_std), H,
            float(rate_std), drift_std)


def noise_floor(record: Record, drift: Drift | None = None) -> NoiseFloor:
    """Estimate the force error a model driven by the recorded stroke cannot avoid.

    For a periodic stroke over at least two cycles (``method = "cycle scatter"``)
    the force is fitted by least squares with a constant and every harmonic of the
    stroke frequency up to 0.45 x the sampling rate (at most 64); what is left is
    the cycle-to-cycle scatter of the force at the same phase, plus the content
    above the harmonics fitted: load-cell noise, rig vibration that is not locked to
    the stroke, drift.  Its scale is taken robustly, 1.4826 x the median absolute
    deviation over sqrt(dof / N) (dof = samples less the fitted columns): a force
    jump (Coulomb friction) sampled at another phase in every cycle leaves large
    residuals next to each jump that are not noise (they still raise the estimate,
    about 1.6 x the load-cell noise for 30 N of Coulomb friction at 3 Hz, 200 Hz).
    The model is driven by the recorded stroke rate (Savitzky-Golay derivative of a
    noisy LVDT signal), so its scatter, found the same way, reaches the model force
    through the device's equivalent damping c_eq = Im(K*) / w (K* = F1 / Y1, the
    first-harmonic dynamic stiffness): ``rate_force_std`` = c_eq x that scatter (a
    3 kHz record with 2 um of LVDT noise: 0.0023 in NRMSE, more than the load-cell
    noise left after decimation).  ``nrmse`` combines both in quadrature.
    Otherwise (``"high band"``: a stroke that does not repeat, or fewer than two
    cycles) the first 12 harmonics are removed and the median absolute deviation of
    the 4th differences of what is left (variance 70 sigma^2 for white noise) is
    used, which sees only the white part of the force (``rate_force_std`` = 0).  For
    a stroke that is not periodic
    (:attr:`Record.periodic <liquidamp.analysis.measured.records.Record.periodic>`)
    there are no harmonics to remove: the 4th differences of the signal itself are
    used, which suppress a component at frequency f by (2 sin(pi f / fs))^4 (below
    1 % of its amplitude for f < fs / 20), so the estimate holds while the stroke's
    band lies well below the sampling rate fs.
    The displacement noise is always the high-band estimate.

    A record whose force drifts (``drift``, by default
    :func:`~liquidamp.analysis.measured.drift.record_drift` of the record;
    ``drift.nonstationary``): the cycle-scatter fit also holds every
    harmonic above 0.2 % of the largest (at most 32) and the constant, modulated by
    Legendre polynomials of time up to the drift's degree, so that the drift is kept out of
    the floor (``drift_std``: the RMS force it took; ``method`` says so).  A thermal drift
    that fades the force 13 % over 30 s raised the floor 20x before.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> t = np.arange(0, 3.0, 0.005)
    >>> F = 500 * np.sin(2 * np.pi * 3 * t) + rng.normal(0, 2.0, t.size)
    >>> rec = Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), F)
    >>> nf = noise_floor(rec)
    >>> bool(abs(nf.force_std / 2.0 - 1) < 0.1), nf.method, nf.harmonics
    (True, 'cycle scatter', 29)
    """
    t = record.time
    ys = high_band_std(t, record.displacement, record.frequency, periodic=record.periodic)
    drift = record_drift(record) if drift is None else drift
    scatter = _periodic_scatter(record, drift=drift) if record.periodic else None
    if scatter is None:
        fs, rs, method, H, vs, ds = (high_band_std(t, record.force, record.frequency,
                                             periodic=record.periodic), 0.0, "high band", 0,
                                     0.0, 0.0)
    else:
        (fs, rs, H, vs, ds), method = scatter, "cycle scatter"
        if drift.nonstationary:
            method += f", drift removed (degree {drift.degree} in time)"
    F = record.force
    rms = float(np.sqrt(np.mean((F - F.mean()) ** 2)))
    return NoiseFloor(force_std=fs, displacement_std=ys, nrmse=math.hypot(fs, rs) / rms,
                      method=method, harmonics=H, rate_force_std=rs, rate_std=vs,
                      drift=drift, drift_std=ds, drift_nrmse=ds / rms)


# ---------------------------------------------------------------------------
# data quality before a fit


@dataclass(frozen=True)
class DataQuality:
    """What :func:`check_record` found in one record before any fit.

    Attributes
    ----------
    source : str
        The record's label.
    force_first_harmonic : float or None
        |F1|, first-harmonic force amplitude at the stroke frequency [N]; None
        when the stroke is not periodic.
    force_noise_std : float
        Standard deviation of the force about its first ten harmonics (about
        its linear regression on stroke, rate and acceleration when the
        stroke is not periodic) [N].
    force_snr : float
        |F1| over its standard error sigma sqrt(2/N) [-]; pure noise gives
        about 1 (Rayleigh distributed), a usable record hundreds.  Not
        periodic: sqrt(N var(fitted) / var(residual)) of the linear
        regression, the same measure (pure noise: about sqrt(3)).
    periodic_fraction : float or None
        Share of the force variance in the first ten harmonics of the
        excitation [-] (pure noise: about 20/N); None when the stroke is not
        periodic.
    max_stroke : float
        Largest recorded |displacement - mean| [m].
    stroke_limit : float or None
        Chamber end V0/A_p of the device checked against [m].
    outliers : tuple of Outlier
        Isolated spikes in the force or the displacement.
    problems : tuple of str
        Reasons to refuse the record (noise only, a loop that delivers
        energy, a stroke past the chamber end, too few samples per cycle).
    notes : tuple of str
        Weaker flags (a force that is mostly not periodic, a stroke that is not
        periodic, a coarse sampling).
    stroke : dict
        :meth:`Record.summary <liquidamp.analysis.measured.records.Record.summary>`:
        periodic or not, and the harmonic summary only where periodic.
    energy_per_cycle : float or None
        Loop energy the device absorbs per cycle, the integral of
        (F - mean F) dy over the whole cycles divided by their number [J]
        (positive for a passive device); None when the stroke is not periodic.
    dissipated_power : float
        Mean power the device absorbs [W]: energy per cycle x frequency
        (periodic), else c mean(v^2) with c the damping of the linear
        regression (the conservative parts k y and m a do no work on average).
    dissipated_power_std : float
        Standard error of ``dissipated_power`` from the force noise [W].
    loss_share : float
        dissipated_power / (RMS(F - mean F) RMS(v)) [-]: +1 for a pure damper,
        0 for a spring, -1 for a damper whose force sign is flipped.
    samples_per_cycle : float
        Sampling rate over the stroke frequency (over the top of the stroke's
        band when not periodic) [-].
    velocity_gain : float
        Gain of the Savitzky-Golay velocity at that frequency [-] (1 exact;
        0.998 for the paper's 21 points at 67 samples per cycle).
    harmonics_resolved : int
        Harmonics of the stroke frequency below 0.8 x Nyquist [-].
    drift : Drift or None
        The non-stationarity test (:func:`~liquidamp.analysis.measured.drift.record_drift`):
        ``drift.nonstationary`` (bool), ``drift.amplitude_trend`` [%/cycle] of the
        first-harmonic force amplitude with ``drift.amplitude_t`` and
        ``drift.amplitude_p``, ``drift.amplitude_change`` over the record [-],
        ``drift.mean_trend`` [N/cycle], ``drift.reason`` (one sentence).
    channels : dict
        Measured channels of the record (:attr:`Record.channels
        <liquidamp.analysis.measured.records.Record.channels>`): name -> {"unit",
        "min", "max", "mean"} in SI.
    force_negated : str
        Why the record's force was read negated
        (:func:`~liquidamp.analysis.measured.checks.orient_force`), else "".
    """

    source: str
    force_first_harmonic: float | None
    force_noise_std: float
    force_snr: float
    periodic_fraction: float | None
    max_stroke: float
    stroke_limit: float | None
    outliers: tuple = ()
    problems: tuple = ()
    notes: tuple = ()
    stroke: dict = field(default_factory=dict)
    energy_per_cycle: float | None = None
    dissipated_power: float = 0.0
    dissipated_power_std: float = 0.0
    loss_share: float = 0.0
    samples_per_cycle: float = math.inf
    velocity_gain: float = 1.0
    harmonics_resolved: int = 0
    drift: Drift | None = None
    channels: dict = field(default_factory=dict)
    force_negated: str = ""

    @property
    def nonstationary(self) -> bool:
        """True when the force drifts over the record (``drift.nonstationary``)."""
        return self.drift is not None and self.drift.nonstationary

    @property
    def ok(self) -> bool:
        """No problem and no outlier."""
        return not self.problems and not self.outliers

    @property
    def delivers_energy(self) -> bool:
        """True when the loop delivers energy beyond its noise (sign check of
        :func:`check_record`)."""
        return any("runs against the stroke rate" in p for p in self.problems)

    def outlier_text(self, column: str | None = None) -> str:
        """The outliers of ``column`` (or all), one per clause."""
        return "; ".join(o.describe() for o in self.outliers
                         if column is None or o.column == column)

    def as_dict(self) -> dict:
        """JSON-ready summary (SI)."""
        return {"source": self.source, "stroke": dict(self.stroke),
                "force_first_harmonic [N]": self.force_first_harmonic,
                "force_noise_std [N]": self.force_noise_std, "force_snr": self.force_snr,
                "periodic_fraction": self.periodic_fraction, "max_stroke [m]": self.max_stroke,
                "stroke_limit [m]": self.stroke_limit,
                "energy_per_cycle [J]": self.energy_per_cycle,
                "dissipated_power [W]": self.dissipated_power,
                "dissipated_power_std [W]": self.dissipated_power_std,
                "loss_share": self.loss_share, "samples_per_cycle": self.samples_per_cycle,
                "velocity_gain": self.velocity_gain,
                "harmonics_resolved": self.harmonics_resolved,
                "outliers": [dict(o.__dict__) for o in self.outliers],
                "outlier_counts": {c: sum(1 for o in self.outliers if o.column == c)
                                   for c in ("force", "displacement")},
                "nonstationary": self.nonstationary,
                "drift": None if self.drift is None else self.drift.as_dict(),
                "channels": {k: dict(v) for k, v in self.channels.items()},
                "force_negated": self.force_negated,
                "problems": list(self.problems), "notes": list(self.notes)}


#: Least samples per cycle the Savitzky-Golay velocity needs, as the largest loss of its
#: gain at the stroke frequency: a note beyond 1 %, a problem beyond 10 % [-].
VELOCITY_GAIN_NOTE, VELOCITY_GAIN_PROBLEM = 0.01, 0.10
#: Harmonics of the stroke frequency below 0.8 x Nyquist under which a note says the loop's
#: sharp features (friction reversals, a dead band) are not resolved [-].
MIN_HARMONICS = 10


def velocity_gain(frequency: float, sampling_rate: float, window: int = 21,
                  order: int = 4) -> float:
    """Gain of the Savitzky-Golay velocity at ``frequency`` [-] (1: exact).

    |H(w)| / w of the derivative filter's frequency response H; the filter's
    phase is exact (it is antisymmetric).

    Examples
    --------
    >>> round(velocity_gain(3.0, 200.0), 4)   # the paper's rig: 0.2 % low at 3 Hz
    0.998
    >>> round(velocity_gain(10.0, 200.0), 3)  # 20 samples per cycle: 16 % low
    0.836
    """
    from scipy.signal import savgol_coeffs

    if not frequency > 0:
        return 1.0
    h = savgol_coeffs(window, order, deriv=1, delta=1.0, use="dot")
    w = 2 * math.pi * frequency / sampling_rate
    kk = np.arange(window) - window // 2
    return float(abs(np.sum(h * np.exp(1j * w * kk))) / w)


def loop_power(record: Record, force, sigma: float = 0.0):
    """Energy a force absorbs under a record's stroke: (per cycle [J] or None, mean power [W],
    its standard error [W], loss share [-]).

    Periodic stroke: the loop integral of (F - mean F) dy over the whole
    cycles (the conservative parts cancel over whole cycles) per cycle, its
    standard error from a white force noise of standard deviation ``sigma``
    [N]; mean power = that x the frequency.  Not periodic: c mean(v^2), c the
    rate coefficient of the regression F ~ F0 + k y + c v + m a (its standard
    error from the regression).  Loss share: power / (RMS(F - mean F) RMS(v)),
    +1 for a pure damper, -1 for one whose force sign is flipped.

    Examples
    --------
    >>> t = np.arange(0, 2.0, 0.005)
    >>> y = 0.003 * np.sin(2 * np.pi * 3 * t)
    >>> rec = Record.from_arrays(t, y, np.zeros_like(t))
    >>> E, P, _, share = loop_power(rec, 1e3 * rec.velocity)   # a 1 kN s/m dashpot
    >>> round(E / (np.pi * 1e3 * 2 * np.pi * 3 * 0.003 ** 2), 3), round(share, 3)
    (1.0, 1.0)
    """
    F = np.asarray(force, float)
    t, v = record.time, record.velocity
    Fc = F - float(np.mean(F))
    scale = float(np.sqrt(np.mean(Fc * Fc)) * np.sqrt(np.mean(v * v)))
    dt = 1.0 / record.sampling_rate
    if record.periodic and record.cycles >= 1.0:
        # whole cycles only (rectangle rule: exact to a sample for a periodic integrand); the
        # RMS of the share over the same cycles, so that it does not depend on where the
        # record starts and stops
        n = int(math.floor(record.cycles + 1e-9))
        m = (t - t[0]) < n * record.period - 0.5 * dt
        vm = v[m]
        Fm = F[m] - float(np.mean(F[m]))
        E = float(np.sum(Fm * vm)) * dt / n
        sE = sigma * float(np.sqrt(np.sum(vm * vm))) * dt / n
        P, sP = E * record.frequency, sE * record.frequency
        scale = float(np.sqrt(np.mean(Fm * Fm)) * np.sqrt(np.mean(vm * vm)))
    else:
        X = _regressors(record)
        coef, *_ = np.linalg.lstsq(X, F, rcond=None)
        res = F - X @ coef
        s2 = float(res @ res) / max(F.size - X.shape[1], 1)
        cov = s2 * np.linalg.pinv(X.T @ X)
        sd_v = float(np.std(v))
        c = coef[2] / sd_v if sd_v > 0 else 0.0
        sc = math.sqrt(max(float(cov[2, 2]), 0.0)) / sd_v if sd_v > 0 else 0.0
        P, sP, E = c * float(np.mean(v * v)), sc * float(np.mean(v * v)), None
    share = P / scale if scale > 0 else 0.0
    return E, float(P), float(sP), float(share)


def check_record(record: Record, params: DeviceParams | None = None, *,
                 k: float = SPIKE_NOISE, width: int = SPIKE_WIDTH, k_local: float = SPIKE_LOCAL,
                 min_snr: float = 8.0, min_periodic: float = 0.5,
                 max_delivered: float = 0.05, energy_sigmas: float = 5.0) -> DataQuality:
    """Check a record before fitting: signal, energy sign, sampling, spikes, stroke, shape.

    * **Noise only.**  The force's first harmonic at the stroke frequency is
      fitted by least squares with nine more harmonics and a constant; its
      amplitude |F1| over its standard error sigma sqrt(2/N) (sigma the
      standard deviation of what the harmonics leave) must reach ``min_snr``
      (pure noise gives about 1; the bundled records several thousand).  A
      periodic share of the force variance below ``min_periodic`` is a note.
      A tapered stroke (one frequency, the amplitude ramping) is tested the
      same way; a broadband stroke's force is regressed on the stroke, its
      rate and acceleration instead (F ~ F0 + k y + c v + m a) and the same
      measure, sqrt(N var(fitted) / var(residual)), must reach ``min_snr``.
    * **Energy sign.**  A passive device absorbs energy (sign convention of
      :mod:`liquidamp.analysis.measured.records`): the loop integral of
      F dy per cycle (periodic), or c mean(v^2) of the regression (not
      periodic), must not be negative beyond its noise.  A loop that delivers
      more than ``max_delivered`` x RMS(F) RMS(v) of power and more than
      ``energy_sigmas`` standard errors is a problem naming the sign: the force
      or the displacement column is flipped.
    * **Sampling.**  The Savitzky-Golay velocity's gain at the stroke
      frequency (at the top of the stroke's band when not periodic) must be
      within 10 % of 1 (a problem; 1 % a note: about 23 and 40 samples per
      cycle with the 21-point window); fewer than 10 harmonics of the stroke
      frequency below 0.8 x Nyquist is a note (a friction reversal or a
      dead band needs them).
    * **Spikes**, judged against the record's own local rates
      (:func:`find_spikes`): a force or displacement sample (or a run of up to
      three) that leaves both its neighbours on the same side and comes back, by
      more than ``k_local`` times the largest sample-to-sample change around it
      (and than the change across it), more than ``k`` robust standard deviations
      of the sample noise and more than 2 % of the signal's half range.  A kink
      on a fast stroke, a friction reversal or an MR fluid's yield step is not a
      spike; a single 30 mm sample on a 3 mm stroke is.  The samples are read as
      recorded: run this on the record as read, never on one the tool filtered or
      decimated (:func:`~liquidamp.analysis.measured.calibration.check_records`
      does so), where the filter's own ringing is not the file's.
    * **Drift** (:func:`~liquidamp.analysis.measured.drift.record_drift`): a
      force whose first-harmonic amplitude or mean changes steadily over the
      record, beyond the cycle-to-cycle scatter, is a note (non-stationary), with
      its figures in ``drift``.
    * **Stroke past the chamber end.**  With ``params``, a recorded
      |displacement - mean| at or beyond ``params.stroke_limit`` (V0/A_p) is
      a problem naming the line.
    * **Periodicity.**  A stroke that is not periodic is a note (its
      summaries are RMS and band, not frequency and amplitude; it is fitted on
      the recorded stroke as it is).

    Parameters
    ----------
    record : Record
        The record.
    params : DeviceParams, optional
        Device whose chamber length bounds the stroke.
    k : float
        Spike threshold in robust standard deviations of the sample noise [-].
    width : int
        Sample-to-sample changes on each side of a spike that set the local rate
        [samples], at least 2.
    k_local : float
        Spike threshold in local rates [-].
    min_snr, min_periodic : float
        Thresholds of the noise test [-].
    max_delivered, energy_sigmas : float
        Thresholds of the energy-sign test: delivered power as a share of
        RMS(F) RMS(v) [-], and in standard errors [-].

    Returns
    -------
    DataQuality
        Nothing is raised here; :func:`liquidamp.analysis.measured.calibration.calibrate`
        refuses records with problems or outliers.

    References
    ----------
    .. [1] R. K. Pearson, "Outliers in process modeling and identification",
       IEEE Trans. Control Syst. Technol. 10(1), 2002 (local outlier scales).
    .. [2] J. S. Bendat, A. G. Piersol, Random Data, 4th ed., Wiley, 2010, Sec. 4.5
       (stationarity from segment statistics).

    Examples
    --------
    >>> t = np.arange(0, 2.0, 0.005)
    >>> F = 500 * np.sin(2 * np.pi * 3 * t + 0.3)
    >>> F[[100, 200, 300]] = 5e4
    >>> q = check_record(Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), F))
    >>> [o.line for o in q.outliers], q.problems
    ([102, 202, 302], ())
    >>> flipped = Record.from_arrays(t, 0.003 * np.sin(6 * np.pi * t), -500 * np.cos(6 * np.pi * t))
    >>> print(check_record(flipped).problems[0][:66])
    3 Hz, 3 mm: the force runs against the stroke rate: the loop deliv
    """
    if isinstance(width, bool) or int(width) != width or not 2 <= width <= 1000:
        raise ParameterError(f"check_record: width must be an integer from 2 to 1000 "
                             f"[samples], got {width!r}")
    for name, val in (("k", k), ("k_local", k_local)):
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            raise ParameterError(f"check_record: {name} must be a positive number [-], got "
                                 f"{val!r}")
    t, F, y = record.time, record.force, record.displacement
    n = t.size
    periodic = record.periodic
    # one frequency throughout (periodic, or tapered cycle by cycle): the harmonics of the
    # stroke frequency hold the force's smooth part; broadband: the linear-device regression
    harmonic = periodic or record.shape.kind == "tapered"
    nyq = 0.5 * record.sampling_rate
    if harmonic:
        w = 2 * math.pi * record.frequency * (t - t[0])
        cols = [np.ones_like(t)]
        for j in range(1, 11):
            if j == 1 or j * record.frequency < 0.8 * nyq:
                cols += [np.sin(j * w), np.cos(j * w)]
        A = np.column_stack(cols)
    else:  # no harmonics to remove: the linear device
        A = _regressors(record)

    outliers = []
    for column, x in (("force", F), ("displacement", y)):
        idx, expected = find_spikes(x, k_local=k_local, k_noise=k, width=int(width))
        outliers += [Outlier(column, int(i), record.line(int(i)), float(t[i]), float(x[i]),
                             float(e)) for i, e in zip(idx, expected, strict=True)]
    # a force that drifts over the record: the drift is not noise (its harmonics modulated
    # by a polynomial in time are fitted with them)
    drift = record_drift(record)
    if drift.nonstationary and periodic:
        A = np.hstack((A, drift_columns(A, t, drift.degree)))
    # the force's harmonics without its spikes, so that three spikes do not pass for signal
    keep = np.ones(n, bool)
    keep[[o.index for o in outliers if o.column == "force"]] = False
    c, *_ = np.linalg.lstsq(A[keep], F[keep], rcond=None)
    res = F[keep] - A[keep] @ c
    m = int(keep.sum())
    sigma = float(np.sqrt(res @ res / max(m - A.shape[1], 1)))
    var = float(np.var(F[keep]))
    explained = 1.0 - float(np.mean(res * res)) / var if var > 0 else 0.0
    problems, notes = [], []
    label = record.source or record.label
    if harmonic:
        F1 = float(math.hypot(c[1], c[2]))
        se = sigma * math.sqrt(2.0 / m)
        snr = F1 / se if se > 0 else math.inf
        periodic_fraction = explained
        if snr < min_snr:
            problems.append(
                f"{label}: the force's first harmonic at the stroke frequency "
                f"{record.frequency:.4g} Hz (|F1| = {F1:.4g} N) is not distinguishable from the "
                f"noise (standard deviation {sigma:.4g} N, standard error of |F1| {se:.3g} N: "
                f"|F1| is {snr:.3g} standard errors, at least {min_snr:g} needed); the record "
                "holds no force response to fit")
        elif periodic and periodic_fraction < min_periodic:
            notes.append(f"{label}: only {periodic_fraction:.0%} of the force variance is "
                         f"periodic at the stroke frequency and its harmonics (at least "
                         f"{min_periodic:.0%} expected): the noise dominates the fit")
    else:
        fitted = max(var - float(np.mean(res * res)), 0.0)
        snr = math.sqrt(m * fitted) / sigma if sigma > 0 else math.inf
        if snr < min_snr:
            problems.append(
                f"{label}: the force does not follow the stroke above the noise: regressed on "
                f"the stroke, its rate and acceleration (the stroke is not periodic) it keeps "
                f"{explained:.2%} of its variance, {snr:.3g} standard errors (at least "
                f"{min_snr:g} needed; noise standard deviation {sigma:.4g} N); the record "
                "holds no force response to fit")
    if not periodic:  # harmonic summaries only for a periodic stroke
        F1 = periodic_fraction = None
        notes.append(f"{label}: the stroke is not periodic ({record.describe()}): no frequency "
                     "or amplitude summary; the model is driven by the recorded stroke as it "
                     "is, from rest at its first sample (no pre-roll)")
    if drift.nonstationary:
        notes.append(f"{label}: {drift.reason}; no model of a stationary device follows it")
    negated = str(record.meta.get("force_sign", ""))
    if negated:
        notes.append(f"{label}: force read negated: {negated}")
    # energy sign: a passive device absorbs energy
    E, P, sP, share = loop_power(record, F, sigma)
    if not problems and share < -max_delivered and P < -energy_sigmas * sP:
        amount = (f"the loop delivers {-E:.4g} J per cycle ({-P:.4g} W)" if E is not None
                  else f"the device delivers {-P:.4g} W on average")
        problems.append(
            f"{label}: the force runs against the stroke rate: {amount}, "
            f"{-share:.0%} of RMS(F) x RMS(v) and {-P / sP if sP > 0 else math.inf:.3g} "
            "standard errors beyond its noise, where a passive device absorbs energy. "
            "liquidamp expects the force the device exerts on the load cell positive when it "
            "resists a positive stroke (a positive displacement compresses chamber 1; a "
            "damper's force is in phase with the stroke rate, so the loop integral of F dy "
            "is positive): the force or the displacement sign is flipped in the file; flip "
            "the force column (multiply it by -1)")
    # sampling: the SG velocity and the harmonics the loop needs
    f_top = record.frequency if periodic else max(record.shape.band[1], record.frequency)
    spc = record.sampling_rate / f_top
    gain = velocity_gain(f_top, record.sampling_rate, record.window, record.order)
    n_harm = int(math.floor(0.8 * nyq / record.frequency + 1e-9))
    where = "the stroke frequency" if periodic else "the top of the stroke's band"
    sg = (f"{spc:.3g} samples per cycle at {where} ({f_top:.4g} Hz, sampling "
          f"{record.sampling_rate:.4g} Hz): the {record.window}-point Savitzky-Golay velocity "
          f"is {1 - gain:.1%} low there")
    if 1.0 - gain > VELOCITY_GAIN_PROBLEM and periodic:
        problems.append(f"{label}: {sg} (at most {VELOCITY_GAIN_PROBLEM:.0%} allowed): the "
                        "model would be driven by a wrong stroke rate; read the record with a "
                        "shorter Savitzky-Golay window or use one sampled faster")
    elif 1.0 - gain > VELOCITY_GAIN_NOTE:
        notes.append(f"{label}: {sg}; the damping fitted is biased by about as much (a shorter "
                     "Savitzky-Golay window reduces it)")
    if periodic and n_harm < MIN_HARMONICS:
        notes.append(f"{label}: only {n_harm} harmonics of the stroke frequency "
                     f"{record.frequency:.4g} Hz lie below 0.8 x Nyquist "
                     f"({0.8 * nyq:.4g} Hz; {MIN_HARMONICS} expected): a friction reversal or a "
                     "dead band is not resolved")
    dev = np.abs(y - float(np.median(y)))
    i_max = int(np.argmax(dev))
    limit = None if params is None else float(params.stroke_limit)
    if params is not None:
        problems += check_record_stroke(record, params)
    return DataQuality(source=label, force_first_harmonic=F1, force_noise_std=sigma,
                       force_snr=float(snr), periodic_fraction=periodic_fraction,
                       max_stroke=float(dev[i_max]), stroke_limit=limit,
                       outliers=tuple(outliers), problems=tuple(problems), notes=tuple(notes),
                       stroke=record.summary(), energy_per_cycle=E, dissipated_power=P,
                       dissipated_power_std=sP, loss_share=share, samples_per_cycle=float(spc),
                       velocity_gain=gain, harmonics_resolved=n_harm, drift=drift,
                       channels=channel_summary(record), force_negated=negated)


def check_record_stroke(record: Record, params: DeviceParams) -> list[str]:
    """The stroke-past-the-chamber-end problem of :func:`check_record` (empty if none).

    A recorded |displacement - median| at or beyond ``params.stroke_limit``
    (V0/A_p) names the line of the largest and of the first sample beyond.
    """
    t, y = record.time, record.displacement
    dev = np.abs(y - float(np.median(y)))
    i_max = int(np.argmax(dev))
    limit = float(params.stroke_limit)
    if dev[i_max] < limit:
        return []
    label = record.source or record.label
    beyond = np.flatnonzero(dev >= limit)
    return [f"{label}, line {record.line(i_max)} (t = {t[i_max]:.6g} s): displacement "
            f"{(y[i_max] - np.median(y)) * 1e3:+.4g} mm from the mid-position, past the chamber "
            f"end at {limit * 1e3:.4g} mm (V0/A_p; allowed |y| < {limit * 1e3:.4g} mm); "
            f"{beyond.size} sample(s) beyond it, the first on line {record.line(int(beyond[0]))}"]


def as_read(record: Record) -> Record:
    """The record as read: the record a conditioned record was made from (its
    ``meta["conditioning"].record``, followed back), else the record itself.

    The data checks run on it, never on samples the tool made by filtering,
    decimating or averaging.
    """
    seen = 0
    while seen < 16:
        cond = record.meta.get("conditioning")
        prior = getattr(cond, "record", None)
        if prior is None or prior is record:
            return record
        record, seen = prior, seen + 1
    return record


def channel_summary(record: Record) -> dict:
    """Measured channels of a record: name -> {"unit", "min", "max", "mean"} (SI)."""
    return {k: {"unit": CHANNEL_SI[k], "min": float(np.min(v)), "max": float(np.max(v)),
                "mean": float(np.mean(v))} for k, v in record.channels.items()}
