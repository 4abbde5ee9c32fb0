"""Quality of a measured record: noise floor, outliers, spikes, before any model run.

:func:`noise_floor` estimates the force a model driven by the stroke cannot reproduce
(cycle-to-cycle scatter; load-cell noise from the high-frequency content where the
stroke is not periodic) and the NRMSE a perfect model would reach;
:func:`check_record` finds isolated force spikes and other outliers
(:class:`Outlier`) and summarizes them (:class:`DataQuality`).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B-C.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.records import Record
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError

__all__ = ["NoiseFloor", "noise_floor", "Outlier", "DataQuality", "check_record"]


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
        ``"cycle scatter"``: the force less its best periodic fit (all harmonics of
        the stroke frequency up to 0.45 x the sampling rate, at most 64), robust
        scale: the cycle-to-cycle scatter at the same phase plus what lies above the
        harmonics fitted; ``"high band"``: the
        4th differences of the force less its first 12 harmonics (a stroke that is
        not periodic, or fewer than two cycles).
    harmonics : int
        Harmonics fitted by the cycle-scatter estimate (0 for ``"high band"``).
    rate_force_std : float
        Force error [N] that the scatter of the recorded stroke rate causes in a model
        driven by it (:func:`noise_floor`; 0 for ``"high band"``).
    rate_std : float
        That scatter of the stroke rate [m/s] (0 for ``"high band"``).
    """

    force_std: float
    displacement_std: float
    nrmse: float
    method: str = "high band"
    harmonics: int = 0
    rate_force_std: float = 0.0
    rate_std: float = 0.0

    @property
    def std(self) -> float:
        """hypot(force_std, rate_force_std) [N]: the force error a perfect model would show."""
        return math.hypot(self.force_std, self.rate_force_std)


def _hf_std(t, s, f, harmonics=12):
    """Robust white-noise std: 4th differences of the signal less its first harmonics."""
    w = 2 * math.pi * f * (t - t[0])
    cols = [np.ones_like(t)]
    nyq = 0.5 / float(np.median(np.diff(t)))
    for k in range(1, harmonics + 1):
        if k * f < 0.8 * nyq:
            cols += [np.sin(k * w), np.cos(k * w)]
    A = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(A, s, rcond=None)
    d4 = np.diff(s - A @ coef, 4)
    mad = float(np.median(np.abs(d4 - np.median(d4))))
    return 1.4826 * mad / math.sqrt(70.0)


def _periodic_scatter(record: Record, max_harmonics: int = 64):
    """(force scatter [N], rate-driven force scatter [N], harmonics) or None (noise_floor)."""
    t = record.time - record.time[0]
    f, n = record.frequency, record.time.size
    H = min(int(0.45 * record.sampling_rate / f), max_harmonics)
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
    # robust scale: each residual has variance sigma^2 (1 - h_ii), dof / n on average
    mad = np.median(np.abs(res - np.median(res, axis=0)), axis=0)
    force_std, rate_std = 1.4826 * mad[1:] / math.sqrt(dof / n)
    # the stroke rate's scatter reaches the force through the loss part of the first-harmonic
    # dynamic stiffness, c_eq = Im(K*) / w (the model's stroke is the integral of the rate)
    K = complex(coef[1, 1], coef[2, 1]) / complex(coef[1, 0], coef[2, 0])
    return (float(force_std), float(abs(K.imag) / (2 * math.pi * f) * rate_std), H,
            float(rate_std))


def noise_floor(record: Record) -> NoiseFloor:
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
    Otherwise (``"high band"``) the first 12 harmonics are removed
    and the median absolute deviation of the 4th differences of what is left
    (variance 70 sigma^2 for white noise) is used, which sees only the white part
    of the force (``rate_force_std`` = 0).
    The displacement noise is always the high-band estimate.

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
    ys = _hf_std(t, record.displacement, record.frequency)
    scatter = _periodic_scatter(record)
    if scatter is None:
        fs, rs, method, H, vs = (_hf_std(t, record.force, record.frequency), 0.0, "high band",
                                 0, 0.0)
    else:
        (fs, rs, H, vs), method = scatter, "cycle scatter"
    F = record.force
    return NoiseFloor(force_std=fs, displacement_std=ys,
                      nrmse=math.hypot(fs, rs) / float(np.sqrt(np.mean((F - F.mean()) ** 2))),
                      method=method, harmonics=H, rate_force_std=rs, rate_std=vs)


# ---------------------------------------------------------------------------
# data quality before a fit


@dataclass(frozen=True)
class Outlier:
    """One sample that stands out of its neighbours (:func:`check_record`).

    Attributes
    ----------
    column : str
        ``"force"`` or ``"displacement"``.
    index : int
        Sample index in the record.
    line : int
        Line of the source file (header = line 1).
    time : float
        Sample time [s].
    value : float
        Recorded value [N] or [m].
    expected : float
        Median of its ``width`` neighbours that are not spikes themselves [N] or [m].
    """

    column: str
    index: int
    line: int
    time: float
    value: float
    expected: float

    def describe(self) -> str:
        """'line L (t = ... s): force 5e+04 N, neighbours ~ 312 N'."""
        unit, k = ("N", 1.0) if self.column == "force" else ("mm", 1e3)
        return (f"line {self.line} (t = {self.time:.6g} s): {self.column} {self.value * k:.6g} "
                f"{unit}, its neighbours' median {self.expected * k:.6g} {unit}")


@dataclass(frozen=True)
class DataQuality:
    """What :func:`check_record` found in one record before any fit.

    Attributes
    ----------
    source : str
        The record's label.
    force_first_harmonic : float
        |F1|, first-harmonic force amplitude at the stroke frequency [N].
    force_noise_std : float
        Standard deviation of the force about its first ten harmonics [N].
    force_snr : float
        |F1| over its standard error sigma sqrt(2/N) [-]; pure noise gives
        about 1 (Rayleigh distributed), a usable record hundreds.
    periodic_fraction : float
        Share of the force variance in the first ten harmonics of the
        excitation [-] (pure noise: about 20/N).
    max_stroke : float
        Largest recorded |displacement - mean| [m].
    stroke_limit : float or None
        Chamber end V0/A_p of the device checked against [m].
    outliers : tuple of Outlier
        Isolated spikes in the force or the displacement.
    problems : tuple of str
        Reasons to refuse the record (noise only, stroke past the chamber end).
    notes : tuple of str
        Weaker flags (a force that is mostly not periodic).
    """

    source: str
    force_first_harmonic: float
    force_noise_std: float
    force_snr: float
    periodic_fraction: float
    max_stroke: float
    stroke_limit: float | None
    outliers: tuple = ()
    problems: tuple = ()
    notes: tuple = ()

    @property
    def ok(self) -> bool:
        """No problem and no outlier."""
        return not self.problems and not self.outliers

    def outlier_text(self, column: str | None = None) -> str:
        """The outliers of ``column`` (or all), one per clause."""
        return "; ".join(o.describe() for o in self.outliers
                         if column is None or o.column == column)

    def as_dict(self) -> dict:
        """JSON-ready summary (SI)."""
        return {"source": self.source, "force_first_harmonic [N]": self.force_first_harmonic,
                "force_noise_std [N]": self.force_noise_std, "force_snr": self.force_snr,
                "periodic_fraction": self.periodic_fraction, "max_stroke [m]": self.max_stroke,
                "stroke_limit [m]": self.stroke_limit,
                "outliers": [dict(o.__dict__) for o in self.outliers],
                "problems": list(self.problems), "notes": list(self.notes)}


def _spikes(x, A, width: int, k: float, frac: float):
    """Isolated spikes of ``x``: (indices, expected values).

    The smooth periodic part (least squares on the columns of ``A``, refitted
    without the spikes found) is removed, then a Hampel filter runs on what is
    left: a sample departing from the running median of ``width`` samples by
    more than max(k * 1.4826 * MAD, frac * first-harmonic amplitude, 3 * the 98th
    percentile of those departures) is a spike (the last term keeps a record's own
    high-frequency texture, e.g. rig ringing on a friction loop, from passing for
    spikes: a spike is rare by definition);
    the largest departures are replaced by their median and the filter is rerun
    (a spike also shifts its neighbours' medians by one sample).
    """
    from scipy.ndimage import maximum_filter, median_filter

    bad = np.zeros(x.size, bool)
    for _ in range(2):  # fit, find the spikes, refit without them, find them again
        c, *_ = np.linalg.lstsq(A[~bad], x[~bad], rcond=None)
        r = x - A @ c
        floor = frac * float(math.hypot(c[1], c[2]))
        d = r - median_filter(r, size=width, mode="mirror")
        sigma = 1.4826 * float(np.median(np.abs(d - np.median(d))))
        texture = 3.0 * float(np.percentile(np.abs(d), 98.0))
        thr = max(k * sigma, floor, texture)
        bad = np.zeros(x.size, bool)
        rr = r.copy()
        for _ in range(50):
            med = median_filter(rr, size=width, mode="mirror")
            d = np.abs(rr - med)
            peak = d >= maximum_filter(d, size=width, mode="mirror")  # largest nearby
            new = np.flatnonzero((d > thr) & peak & ~bad)
            if not new.size:
                break
            bad[new] = True
            rr[new] = med[new]
    idx = np.flatnonzero(bad)
    h = width // 2
    expected = [float(np.median(np.delete(x[max(i - h, 0):i + h + 1],
                                          np.flatnonzero(bad[max(i - h, 0):i + h + 1]))))
                if (~bad[max(i - h, 0):i + h + 1]).any() else math.nan for i in idx]
    return idx, np.array(expected)


def check_record(record: Record, params: DeviceParams | None = None, *, k: float = 10.0,
                 width: int = 7, min_snr: float = 8.0, min_periodic: float = 0.5) -> DataQuality:
    """Check a record before fitting: signal against noise, spikes, stroke against the chambers.

    * **Noise only.**  The force's first harmonic at the stroke frequency is
      fitted by least squares with nine more harmonics and a constant; its
      amplitude |F1| over its standard error sigma sqrt(2/N) (sigma the
      standard deviation of what the harmonics leave) must reach ``min_snr``
      (pure noise gives about 1; the bundled records several thousand).  A
      periodic share of the force variance below ``min_periodic`` is a note.
    * **Spikes** (a Hampel-type filter): a force or displacement sample that
      departs from the median of its ``width`` neighbours by more than
      ``k`` robust standard deviations (1.4826 x the median absolute
      deviation of those departures over the record), by more than 2 %
      of the signal's first-harmonic amplitude and by more than three times
      the 98th percentile of the departures is an outlier (so that a record's
      own high-frequency content, such as rig ringing, is not taken for
      spikes).  A running
      median follows steps (friction reversals) and smooth curves exactly on
      monotone stretches, so only isolated samples stand out; up to
      ``width // 2`` adjacent ones are found.
    * **Stroke past the chamber end.**  With ``params``, a recorded
      |displacement - mean| at or beyond ``params.stroke_limit`` (V0/A_p) is
      a problem naming the line.

    Parameters
    ----------
    record : Record
        The record.
    params : DeviceParams, optional
        Device whose chamber length bounds the stroke.
    k : float
        Outlier threshold in robust standard deviations [-].
    width : int
        Running-median window [samples], odd.
    min_snr, min_periodic : float
        Thresholds of the noise test [-].

    Returns
    -------
    DataQuality
        Nothing is raised here; :func:`liquidamp.analysis.measured.calibration.calibrate`
        refuses records with problems or outliers.

    References
    ----------
    .. [1] F. R. Hampel, "The influence curve and its role in robust
       estimation", JASA 69(346), 1974.
    .. [2] R. K. Pearson, "Outliers in process modeling and identification",
       IEEE Trans. Control Syst. Technol. 10(1), 2002 (Hampel filter).

    Examples
    --------
    >>> t = np.arange(0, 2.0, 0.005)
    >>> F = 500 * np.sin(2 * np.pi * 3 * t + 0.3)
    >>> F[[100, 200, 300]] = 5e4
    >>> q = check_record(Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), F))
    >>> [o.line for o in q.outliers], q.problems
    ([102, 202, 302], ())
    """
    if width < 3 or width % 2 == 0:
        raise ParameterError(f"check_record: width must be an odd number >= 3 [samples], got "
                             f"{width!r}")
    t, F, y = record.time, record.force, record.displacement
    n = t.size
    w = 2 * math.pi * record.frequency * (t - t[0])
    nyq = 0.5 * record.sampling_rate
    cols = [np.ones_like(t)]
    for j in range(1, 11):
        if j == 1 or j * record.frequency < 0.8 * nyq:
            cols += [np.sin(j * w), np.cos(j * w)]
    A = np.column_stack(cols)

    outliers = []
    for column, x in (("force", F), ("displacement", y)):
        idx, expected = _spikes(x, A, width, k, 0.02)
        outliers += [Outlier(column, int(i), record.line(int(i)), float(t[i]), float(x[i]),
                             float(e)) for i, e in zip(idx, expected, strict=True)]
    # the force's harmonics without its spikes, so that three spikes do not pass for signal
    keep = np.ones(n, bool)
    keep[[o.index for o in outliers if o.column == "force"]] = False
    c, *_ = np.linalg.lstsq(A[keep], F[keep], rcond=None)
    res = F[keep] - A[keep] @ c
    m = int(keep.sum())
    sigma = float(np.sqrt(res @ res / max(m - A.shape[1], 1)))
    F1 = float(math.hypot(c[1], c[2]))
    se = sigma * math.sqrt(2.0 / m)
    snr = F1 / se if se > 0 else math.inf
    var = float(np.var(F[keep]))
    periodic = 1.0 - float(np.mean(res * res)) / var if var > 0 else 0.0
    problems, notes = [], []
    label = record.source or record.label
    if snr < min_snr:
        problems.append(
            f"{label}: the force's first harmonic at the stroke frequency "
            f"{record.frequency:.4g} Hz (|F1| = {F1:.4g} N) is not distinguishable from the "
            f"noise (standard deviation {sigma:.4g} N, standard error of |F1| {se:.3g} N: "
            f"|F1| is {snr:.3g} standard errors, at least {min_snr:g} needed); the record holds "
            "no force response to fit")
    elif periodic < min_periodic:
        notes.append(f"{label}: only {periodic:.0%} of the force variance is periodic at the "
                     f"stroke frequency and its harmonics (at least {min_periodic:.0%} "
                     "expected): the noise dominates the fit")
    dev = np.abs(y - float(np.median(y)))
    i_max = int(np.argmax(dev))
    limit = None if params is None else float(params.stroke_limit)
    if limit is not None and dev[i_max] >= limit:
        beyond = np.flatnonzero(dev >= limit)
        problems.append(
            f"{label}, line {record.line(i_max)} (t = {t[i_max]:.6g} s): displacement "
            f"{(y[i_max] - np.median(y)) * 1e3:+.4g} mm from the mid-position, past the chamber "
            f"end at {limit * 1e3:.4g} mm (V0/A_p; allowed |y| < {limit * 1e3:.4g} mm); "
            f"{beyond.size} sample(s) beyond it, the first on line {record.line(int(beyond[0]))}")
    return DataQuality(source=label, force_first_harmonic=F1, force_noise_std=sigma,
                       force_snr=float(snr), periodic_fraction=float(periodic),
                       max_stroke=float(dev[i_max]), stroke_limit=limit,
                       outliers=tuple(outliers), problems=tuple(problems), notes=tuple(notes))
