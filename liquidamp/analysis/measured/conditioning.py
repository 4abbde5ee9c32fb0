"""Condition a record before fitting: force filter, anti-alias decimation, cycle average.

A test machine samples at 1-3 kHz while a damper loop at 0.5-10 Hz is described by a few
tens of harmonics of the stroke frequency, and a steady record repeats the same cycle many
times; fitting every sample of every cycle costs time and fits rig ringing and load-cell
noise as if it were the device.  :func:`condition` returns a new
:class:`~liquidamp.analysis.measured.records.Record` and a :class:`Conditioning` that states
what was done and what it removed:

1. **Force filter** (optional, ``force_cutoff`` [Hz]): a Butterworth low-pass of order
   ``filter_order`` (4) run forward and backward (:func:`scipy.signal.sosfiltfilt`): zero
   phase, so the loop is not distorted in time; the magnitude response is |H|^2 of the
   Butterworth (-6 dB at the cut-off, flat below).  Only the force is filtered.  Use it to
   keep rig ringing out of the fit (e.g. the 10-50 Hz ringing of the friction-damper
   records).
2. **Decimation** (``decimate``, default ``"auto"``): the factor q is the largest integer
   with fs / q >= 2.5 ``harmonics`` f (f the stroke frequency), so that at least
   ``harmonics`` (30) harmonics lie below the anti-alias cut-off (a tapered stroke: those
   of its carrier plus its envelope's bandwidth; broadband: of its band's upper edge,
   :func:`decimation_factor`); before every q-th sample
   is kept, every channel (force, displacement and its Savitzky-Golay smoothing, velocity
   and acceleration, which were computed at the full rate) passes the same zero-phase
   Butterworth low-pass of order 8 at 0.8 x the new Nyquist frequency (0.4 fs / q), as
   :func:`scipy.signal.decimate` places its cut-off.  A record sampled at fewer than
   2 x 2.5 ``harmonics`` f samples per second is left as it is (q = 1: nothing is
   filtered).
3. **Cycle average** (``average``, default ``"auto"``: a stroke that repeats, over at
   least :data:`AVERAGE_MIN_CYCLES` (4) whole cycles): the force at M phases of a cycle (M
   samples per cycle at the fitted rate) is interpolated linearly between the samples of
   every whole cycle and averaged; the stroke is the periodic least-squares fit of the
   displacement and its exact derivatives.  For a model at its periodic steady state, least
   squares on the average is least squares on every cycle (the two sums of squares differ
   by the scatter about the average, a constant), at the cost of one simulated cycle
   instead of all; the noise floor of the average is the record's divided by about the
   square root of the cycles.  The partial cycle at the end is left out.

What the conditioning removed is measured on the force at the kept samples: the RMS of
(recorded - conditioned) [N] and its share of the recorded force's variance [-], in total
and by stage ("cycle average": the scatter of the cycles about their average).

**Like with like.**  A model is compared with a conditioned record only after its force
has been conditioned the same way: :func:`liquidamp.analysis.measured.record_model.simulate_record`
takes the model force at every sample instant of the record given (averaged: at the phases
of those instants, over one steady cycle), applies the same filters, keeps the same samples
and averages them the same way (:meth:`Conditioning.model_force`).  So a force jump falls
between the same two samples in both.  Without it, a Coulomb friction jump in the model,
sharp, met a recorded jump rounded by the filter, and the residual kept a ringing edge at
every reversal (a 1 Hz record at 3 kHz with 30 N of Coulomb friction: calibration NRMSE
0.05 against a noise floor of 0.002, and smooth friction, Coulomb friction and a series
spring were added where Coulomb friction alone was true); on a model grid 8x coarser than
the record's the jump's time was off by up to 4 samples (1.3 N of residual at each 60 N
jump filtered at 30 Hz).

Sample i of a decimated record is sample ``(i + trimmed) * factor`` of the record given
(its ``line`` numbers refer to the record given only when nothing was filtered); samples
after the last kept one are dropped before filtering, so that record and model are filtered
over the same span; of a filtered record, the first and last 3 periods of the lowest cut-off
(``trimmed`` fitted samples each), where the zero-phase filters' start-up transients bend
the force, are not fitted (a friction jump next to an end otherwise left a spike there),
while the model is driven through them by the record's stroke.
The record's ``meta["conditioning"]`` holds the :class:`Conditioning`.

References
----------
.. [1] S. Butterworth, "On the theory of filter amplifiers", Wireless Engineer 7, 1930.
.. [2] F. Gustafsson, "Determining the initial states in forward-backward filtering",
   IEEE Trans. Signal Process. 44(4), 1996 (zero-phase filtering, as ``sosfiltfilt``).
.. [3] A. V. Oppenheim, R. W. Schafer, Discrete-Time Signal Processing, 3rd ed., 2010,
   Sec. 4.6 (anti-alias filtering before downsampling).
.. [4] S. Braun, "The extraction of periodic waveforms by time domain averaging",
   Acustica 32(2), 1975 (synchronous averaging of a periodic record).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from liquidamp.analysis.measured.drift import ALPHA
from liquidamp.analysis.measured.record_quality import (
    NoiseFloor,
    high_band_std,
    line_coefficients,
    noise_floor,
)
from liquidamp.analysis.measured.records import Record
from liquidamp.errors import ParameterError, check_choice, check_finite
from liquidamp.structure.testmachine import harmonics_tested, savgol_derivatives

__all__ = ["Conditioning", "condition", "recondition", "decimation_factor", "lowpass",
           "rate_noise_gain",
           "stroke_threshold",
           "HARMONICS", "AVERAGE_MIN_CYCLES"]

#: Default number of harmonics of the stroke frequency kept below the anti-alias cut-off.
HARMONICS = 30.0

#: Whole cycles from which a periodic record is averaged into one by default (fewer: the
#: partial cycle left out would be a large share of the record).
AVERAGE_MIN_CYCLES = 4

#: New rate over (harmonics x stroke frequency) for the automatic factor: 2.5 puts the
#: anti-alias cut-off (0.4 x the new rate) at or above the last harmonic kept.
_RATE_MARGIN = 2.5

#: Order of the anti-alias Butterworth (applied forward and backward: |H|^2 falls by
#: about 60 dB from the cut-off to the new Nyquist frequency, 1.25 x the cut-off).
_AA_ORDER = 8


@dataclass(frozen=True)
class Conditioning:
    """What :func:`condition` did to one record.

    Attributes
    ----------
    source : str
        The record's label.
    sampling_rate : float
        Rate of the record given [Hz].
    stroke_frequency : float
        Stroke frequency f of the record [Hz].
    force_cutoff : float or None
        Cut-off of the zero-phase force filter [Hz] (None: not filtered).
    filter_order : int
        Butterworth order of the force filter (run forward and backward) [-].
    factor : int
        Decimation factor q (1: not decimated) [-].
    anti_alias_cutoff : float or None
        Cut-off of the anti-alias filter, 0.4 x the new rate [Hz] (None when q = 1).
    fitted_rate : float
        Rate of the conditioned record [Hz].
    harmonics_kept : float
        Lowest cut-off applied to the force over the stroke frequency [-] (the harmonics of
        the loop the conditioned force still holds; the new Nyquist harmonic when nothing
        was filtered).
    removed_rms : float
        RMS of (recorded - conditioned force) at the kept samples [N].
    removed_share : float
        Its share of the recorded force's variance [-].
    removed_by_stage : dict
        ``{"force filter": (rms [N], share [-]), "anti-alias": (rms, share)}`` for the
        stages applied.
    cycles_averaged : int
        Whole stroke cycles averaged into the conditioned record (1: not averaged) [-].
    samples : int
        Samples of the conditioned record [-].
    trimmed : int
        Fitted samples left out at each end of a filtered record, where the zero-phase
        filters' start-up transients bend the force (3 periods of the lowest cut-off); the
        model runs through them [-].
    noise : NoiseFloor or None
        Noise floor of the conditioned record
        (:func:`~liquidamp.analysis.measured.record_quality.noise_floor` before averaging,
        its standard deviations divided by sqrt(``cycles_averaged``) after).
    record : Record or None
        The record as given to :func:`condition` (as read): the data checks
        (:func:`~liquidamp.analysis.measured.calibration.check_records`) run on it, never
        on the samples the conditioning made.
    """

    source: str
    sampling_rate: float
    stroke_frequency: float
    force_cutoff: float | None
    filter_order: int
    factor: int
    anti_alias_cutoff: float | None
    fitted_rate: float
    harmonics_kept: float
    removed_rms: float
    removed_share: float
    removed_by_stage: dict
    cycles_averaged: int = 1
    noise: NoiseFloor | None = None
    trimmed: int = 0
    samples: int = 0
    record: Record | None = field(default=None, repr=False, compare=False)
    _stroke: tuple | None = field(default=None, repr=False, compare=False)
    _average: dict | None = field(default=None, repr=False, compare=False)

    @property
    def changed(self) -> bool:
        """Whether the record was filtered, decimated or averaged."""
        return self.force_cutoff is not None or self.factor > 1 or self.cycles_averaged > 1

    def describe(self) -> str:
        """One line: what was done and what it removed."""
        parts = []
        if self.force_cutoff is not None:
            parts.append(f"force low-pass {self.force_cutoff:.4g} Hz (zero-phase Butterworth, "
                         f"order {self.filter_order} forward and backward)")
        if self.factor > 1:
            parts.append(f"decimated {self.factor}x to {self.fitted_rate:.4g} Hz after a "
                         f"zero-phase anti-alias low-pass at {self.anti_alias_cutoff:.4g} Hz")
        if self.trimmed:
            parts.append(f"{self.trimmed} samples at each end not fitted (filter start-up)")
        if self.cycles_averaged > 1:
            parts.append(f"{self.cycles_averaged} whole cycles averaged into one of "
                         f"{self._average['points']} samples")
        if not parts:
            return f"{self.source}: as recorded ({self.sampling_rate:.4g} Hz)"
        return (f"{self.source}: " + "; ".join(parts) + f"; removed {self.removed_rms:.4g} N "
                f"RMS ({self.removed_share:.2%} of the force variance), "
                f"{self.harmonics_kept:.3g} harmonics of {self.stroke_frequency:.4g} Hz kept")

    def model_times(self, time) -> tuple[np.ndarray, np.ndarray]:
        """Times [s] to run a model over for a conditioned record with samples ``time``, and
        the indices of those samples among them.

        Not averaged: every sample of the record given, over the whole span the filters
        saw (the ``trimmed`` ends included; the kept samples every ``factor``-th).
        Averaged: the phases of every sample of the record given and of the averaged
        samples, within one cycle from ``time[0]`` (the model is run over one steady
        cycle).
        """
        time = np.asarray(time, float)
        if time.size != self.samples:
            raise ParameterError(
                f"{self.source}: the record holds {time.size} samples, its conditioning made "
                f"{self.samples}: a conditioned record cannot be cut or changed (condition "
                "the record as read again)")
        if self._average is not None:
            a = self._average
            return a["t_start"] + a["period"] * a["grid"], a["record_index"]
        start = time[0] - self.trimmed * self.factor / self.sampling_rate
        n = (time.size + 2 * self.trimmed - 1) * self.factor + 1
        return (start + np.arange(n) / self.sampling_rate,
                (np.arange(time.size) + self.trimmed) * self.factor)

    def model_inputs(self):
        """(y, v, a) of :meth:`model_stroke` at :meth:`model_times` for an averaged record
        (computed once), else None."""
        return None if self._average is None else self._average["inputs"]

    def model_stroke(self) -> tuple:
        """(time [s], y [m], v [m/s], a [m/s^2]) of the stroke that drives a model for the
        conditioned record: the record's own (as :meth:`Record.stroke` makes it) over the
        whole span its filters saw, or for an averaged record the periodic fit of its
        stroke at 8 points per fitted sample over one period, both ends included."""
        return self._stroke

    def fourier_stroke(self):
        """For an averaged record: its stroke's periodic fit as a
        :class:`~liquidamp.structure.testmachine.FourierStroke` about the mean, time origin
        the averaged cycle's start (exact derivatives); None otherwise."""
        if self._average is None:
            return None
        from liquidamp.structure.testmachine import FourierStroke

        series = self._average["series"]
        K = max(k for k, _, _ in series)
        sine, cosine = np.zeros(K), np.zeros(K)
        for k, a_k, b_k in series:
            sine[k - 1], cosine[k - 1] = a_k, b_k
        return FourierStroke(self.stroke_frequency, sine, cosine, 0.0, self._average["t_start"])

    def model_force(self, force) -> np.ndarray:
        """Condition a model force given at :meth:`model_times` as the record's was [N].

        The force filter and the anti-alias filter, with the record's cut-offs and orders,
        then the record's samples; averaged: the force of the steady cycle is first laid
        out at every sample of the record given, and the average over cycles follows.
        """
        f = np.asarray(force, float)
        a = self._average
        if a is not None:
            f = f[a["sample_index"]]
        if self.force_cutoff is not None:
            f = lowpass(f, self.sampling_rate, self.force_cutoff, self.filter_order,
                        pad="even")
        if self.anti_alias_cutoff is not None:
            f = lowpass(f, self.sampling_rate, self.anti_alias_cutoff, _AA_ORDER, pad="even")
        f = f[::self.factor]
        if self.trimmed:
            f = f[self.trimmed:f.size - self.trimmed]
        if a is not None:
            i, w = a["i"], a["a"]
            f = ((1.0 - w) * f[i] + w * f[i + 1]).mean(axis=0)
        return f

    def as_dict(self) -> dict:
        """JSON-ready summary (units in the keys)."""
        return {"source": self.source, "sampling_rate [Hz]": self.sampling_rate,
                "stroke_frequency [Hz]": self.stroke_frequency,
                "force_cutoff [Hz]": self.force_cutoff, "filter_order": self.filter_order,
                "decimation_factor": self.factor,
                "anti_alias_cutoff [Hz]": self.anti_alias_cutoff,
                "fitted_rate [Hz]": self.fitted_rate, "harmonics_kept": self.harmonics_kept,
                "removed_rms [N]": self.removed_rms, "removed_share": self.removed_share,
                "removed_by_stage": {k: {"rms [N]": v[0], "share": v[1]}
                                     for k, v in self.removed_by_stage.items()},
                "cycles_averaged": self.cycles_averaged,
                "trimmed_samples_each_end": self.trimmed,
                "noise_floor": (None if self.noise is None else
                                {"force_std [N]": self.noise.force_std,
                                 "rate_force_std [N]": self.noise.rate_force_std,
                                 "nrmse": self.noise.nrmse, "method": self.noise.method}),
                "description": self.describe()}


def lowpass(x, sampling_rate: float, cutoff: float, order: int = 4, *,
            pad: str = "odd") -> np.ndarray:
    """Zero-phase Butterworth low-pass: ``sosfiltfilt`` of an order-``order`` design.

    Parameters
    ----------
    x : array
        Uniformly sampled signal.
    sampling_rate : float
        Samples per second [Hz].
    cutoff : float
        Cut-off frequency [Hz], 0 < cutoff < sampling_rate / 2 (the magnitude is
        1/2, -6 dB, there: the Butterworth's -3 dB applied twice).
    order : int
        Butterworth order (1-20) [-].
    pad : {'odd', 'even'}
        How the ends are extended over 6 / cutoff seconds before filtering: ``'odd'``
        (default) point-symmetric about a straight line fitted over half a cut-off period
        at each end, which continues a smooth signal with its slope (the stroke);
        ``'even'`` mirror-symmetric, which never puts a step at the ends (a force whose
        friction jump lies next to an end: the odd extension about a line fitted across the
        jump leaves a spike at the end).

    Returns
    -------
    ndarray
        The filtered signal (same length, no delay).

    Examples
    --------
    >>> t = np.arange(2000) / 1000.0
    >>> x = np.sin(2 * np.pi * 2 * t) + 0.5 * np.sin(2 * np.pi * 200 * t)
    >>> y = lowpass(x, 1000.0, 20.0)
    >>> bool(np.max(np.abs(y - np.sin(2 * np.pi * 2 * t))[100:-100]) < 1e-3)
    True
    """
    from scipy.signal import sosfiltfilt

    fs = check_finite("sampling_rate", sampling_rate, "Hz")
    fc = check_finite("cutoff", cutoff, "Hz")
    if not 0 < fc < 0.5 * fs:
        raise ParameterError(f"low-pass cut-off must lie between 0 and the Nyquist frequency "
                             f"{0.5 * fs:.6g} Hz, got {fc:.6g} Hz")
    if int(order) != order or not 1 <= order <= 20:
        raise ParameterError(f"low-pass order must be an integer 1-20, got {order!r}")
    sos = _butter(int(order), fc / (0.5 * fs)).copy()  # sosfilt needs it writable
    x = np.asarray(x, float)
    n = x.size
    if n < 4:
        raise ParameterError(f"low-pass needs at least 4 samples, got {n}")
    # odd extension over 6 / cutoff seconds (or the whole record): the start-up transient of
    # a low cut-off outlasts scipy's default pad of 3 x the filter length by far and would
    # bend the ends (2 mm at the end of a 0.25 Hz stroke decimated 54x); the pivot is a
    # straight line fitted over half a cut-off period at each end, not the end sample,
    # whose noise the odd extension would otherwise carry into the ends
    check_choice("pad", pad, ("odd", "even"))
    npad = min(int(math.ceil(6.0 * fs / fc)), n - 1)
    if pad == "even":
        ext = np.concatenate((x[1:npad + 1][::-1], x, x[::-1][1:npad + 1]))
        return sosfiltfilt(sos, ext, padlen=0)[npad:npad + n]
    m = min(max(int(math.ceil(0.5 * fs / fc)), 3), n)
    k = np.arange(m, dtype=float) - 0.5 * (m - 1)  # centred: slope = sum k x / sum k^2
    kk = float(k @ k)
    left = float(np.mean(x[:m]) - 0.5 * (m - 1) * (k @ x[:m]) / kk)
    right = float(np.mean(x[n - m:]) + 0.5 * (m - 1) * (k @ x[n - m:]) / kk)
    ext = np.concatenate((2.0 * left - x[1:npad + 1][::-1], x,
                          2.0 * right - x[::-1][1:npad + 1]))
    return sosfiltfilt(sos, ext, padlen=0)[npad:npad + n]


@functools.lru_cache(maxsize=64)
def _butter(order: int, wn: float) -> np.ndarray:
    """Second-order sections of a Butterworth low-pass (designed once per order and cut-off:
    the design costs more than filtering a few thousand samples)."""
    from scipy.signal import butter

    return butter(order, wn, output="sos")


def decimation_factor(record: Record, harmonics: float = HARMONICS) -> int:
    """The automatic decimation factor: largest q with fs / q >= 2.5 f_h (to 0.1 %) [-].

    f_h is the highest frequency to keep: ``harmonics`` x f for a periodic stroke (f its
    frequency).  A broadband stroke has no harmonics: f_h is ``harmonics`` x the upper
    edge of its band (``record.shape.band``, 95 % of the stroke power below it).  A
    tapered stroke is one carrier f whose amplitude changes slowly (ramps): a
    device's force to it holds the carrier's harmonics k f, each spread by the envelope's
    bandwidth B = band edge - f (a force g(y) of the stroke y = A(t) sin(2 pi f t) is
    sum_k c_k(A(t)) sin(2 pi k f t), whose k-th term spreads about k f by the bandwidth
    of c_k(A(t)), about that of A(t)), not by k B; so f_h = ``harmonics`` x f + B, and a
    tapered record keeps the harmonics its steady part would keep (the 1 Hz friction-damper
    ramps: 31.4 Hz, not 34.4 Hz).

    Examples
    --------
    >>> t = np.arange(0, 6.0, 1 / 1024)
    >>> r = Record.from_arrays(t, 0.0127 * np.sin(np.pi * t), 1e4 * np.cos(np.pi * t))
    >>> decimation_factor(r), decimation_factor(r, 40.0)
    (27, 20)
    >>> env = np.minimum(1.0, np.minimum(t, 6.0 - t))  # 1 Hz, ramps over the end cycles
    >>> tap = Record.from_arrays(t, env * 0.0127 * np.sin(2 * np.pi * t), np.cos(2 * np.pi * t))
    >>> tap.shape.kind, decimation_factor(tap)
    ('tapered', 13)
    """
    h = check_finite("harmonics", harmonics, "-")
    if not 2.0 <= h <= 1e4:
        raise ParameterError(f"harmonics kept must lie between 2 and 1e4, got {h:g}")
    f = record.frequency
    top = h * f
    if not record.periodic and record.shape is not None:
        edge = max(f, float(record.shape.band[1]))
        # tapered: the carrier's harmonics, each spread by the envelope's bandwidth;
        # broadband: the harmonics of the band's upper edge
        top = h * f + (edge - f) if record.shape.kind == "tapered" else h * edge
    # to 0.1 %: a stroke frequency inferred a hair above a round value keeps its round factor
    return max(1, int(1.001 * record.sampling_rate / (_RATE_MARGIN * top)))


#: Least unit white noise samples :func:`rate_noise_gain` pushes through the chain [-].
_GAIN_SAMPLES = 4096


def rate_noise_gain(record: Record, q: int = 1, cutoff: float | None = None) -> float:
    """Standard deviation of the stroke rate [1/s: m/s per m of noise] that unit white
    displacement noise leaves after the route the model's stroke rate takes through
    :func:`condition`: the Savitzky-Golay derivative (``record.window``, ``record.order``)
    of the displacement as read, the anti-alias low-pass at ``cutoff`` [Hz] and every
    ``q``-th sample.  Each step is linear: seeded unit white noise pushed through the same
    functions at the record's rate (the filters' ends left out, 256 samples kept at least)
    gives the gain.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(400) / 200.0
    >>> rec = Record.from_arrays(t, 1e-3 * np.sin(2 * np.pi * t), np.zeros(400))
    >>> from scipy.signal import savgol_coeffs
    >>> exact = 200.0 * np.sqrt(np.sum(savgol_coeffs(21, 4, deriv=1) ** 2))  # 18.2 [1/s]
    >>> bool(abs(rate_noise_gain(rec) / exact - 1) < 0.03)   # no filter, no decimation
    True
    """
    fs = record.sampling_rate
    filtered = q > 1 and cutoff is not None
    edge = 4 * record.window + (int(math.ceil(3.0 * fs / cutoff)) if filtered else 0)
    n = max(_GAIN_SAMPLES, 2 * edge + 256 * max(q, 1))
    noise = np.random.default_rng(0).standard_normal(n)
    v = savgol_derivatives(np.arange(n) / fs, noise, record.window, record.order)[1]
    if filtered:
        v = lowpass(v, fs, cutoff, _AA_ORDER)
    return float(np.std(v[edge:n - edge:max(q, 1)]))


def _with_rate_noise(nf: NoiseFloor, record: Record, dec: Record, cutoff, q) -> NoiseFloor:
    """A stroke that does not repeat: the rate-driven part of the floor.  The model runs on
    the derivative of the noisy recorded stroke, so the LVDT noise reaches its force through
    the device's damping, as the cycle-scatter floor of a periodic record states: here the
    high-band displacement noise of the record as read (the anti-alias filter would hide
    it from the 4th differences) x :func:`rate_noise_gain` x c_eq, the line's slope on the
    rate (F = c v + k y + F0).  500 Hz, 2 um of LVDT noise, 12 kN s/m: about 1.0 N beside
    the load cell's 0.6 N after decimation (without it the true device read 2.4 x its floor).
    """
    ys = high_band_std(record.time, record.displacement, record.frequency, periodic=False)
    rate_std = ys * rate_noise_gain(record, q, cutoff)
    rs = abs(line_coefficients(dec.velocity, dec.smoothed, dec.force)[0]) * rate_std
    F = dec.force
    rms = float(np.sqrt(np.mean((F - F.mean()) ** 2)))
    if not (rs > 0 and rms > 0):
        return nf
    return replace(nf, rate_force_std=rs, rate_std=rate_std,
                   nrmse=math.hypot(nf.force_std, rs) / rms,
                   method="high band, with the stroke rate's noise")


def _removed(raw, kept) -> tuple[float, float]:
    d = raw - kept
    var = float(np.var(raw))
    rms = float(np.sqrt(np.mean(d * d)))
    return rms, (float(np.var(d)) / var if var > 0 else 0.0)


def condition(record: Record, *, force_cutoff: float | None = None, filter_order: int = 4,
              decimate="auto", harmonics: float = HARMONICS,
              average="auto") -> tuple[Record, Conditioning]:
    """Filter and decimate a record for fitting (module docstring); say what was removed.

    Parameters
    ----------
    record : Record
        The record as read.
    force_cutoff : float, optional
        Cut-off of the zero-phase force filter [Hz]; above the stroke frequency and below
        the Nyquist frequency.  None (default): the force is not filtered.
    filter_order : int
        Butterworth order of the force filter (1-20) [-].
    decimate : 'auto' or int
        ``'auto'`` (default): the factor of :func:`decimation_factor`; an integer q >= 1:
        that factor (1: no decimation), refused when the anti-alias cut-off 0.4 fs / q
        would fall below 5 harmonics of the stroke frequency.
    harmonics : float
        Harmonics of the stroke frequency to keep with ``'auto'`` [-] (default 30).
    average : 'auto', True or False
        Average the whole cycles into one (module docstring, step 3): ``'auto'``
        (default) where the stroke repeats and at least :data:`AVERAGE_MIN_CYCLES` (4)
        whole cycles are recorded; True: always (refused for a stroke that does not repeat
        or fewer than two cycles); False: never.

    Returns
    -------
    (Record, Conditioning)
        The conditioned record (``meta["conditioning"]`` set) and what was done.

    Raises
    ------
    ParameterError
        A cut-off outside (stroke frequency, Nyquist frequency), a factor that is not an
        integer >= 1 or leaves fewer than 5 harmonics, or a record too short for the filter.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(0, 6.0, 1 / 1024)
    >>> F = 1e4 * np.sign(np.cos(np.pi * t)) + rng.normal(0, 100, t.size)
    >>> r, c = condition(Record.from_arrays(t, 0.0127 * np.sin(np.pi * t), F))
    >>> c.factor, round(c.fitted_rate, 2), round(c.anti_alias_cutoff, 2), c.trimmed, r.time.size
    (27, 37.93, 15.17, 8, 211)
    >>> bool(0.005 < c.removed_share < 0.05)   # the noise and the square wave's edges
    True
    """
    if not isinstance(record, Record):
        raise ParameterError(f"condition takes a Record, got {type(record).__name__}")
    fs = record.sampling_rate
    f = record.frequency
    nyq = 0.5 * fs
    if force_cutoff is not None:
        fc = check_finite("force_cutoff", force_cutoff, "Hz")
        if not f < fc < nyq:
            raise ParameterError(
                f"force filter cut-off must lie above the stroke frequency {f:.4g} Hz and "
                f"below the Nyquist frequency {nyq:.6g} Hz of {record.label}, got {fc:.6g} Hz")
    if isinstance(decimate, str):
        if decimate != "auto":
            raise ParameterError(f"decimate must be 'auto' or an integer factor >= 1, got "
                                 f"{decimate!r}")
        q = decimation_factor(record, harmonics)
    else:
        if isinstance(decimate, bool) or int(decimate) != decimate or decimate < 1:
            raise ParameterError(f"decimate must be 'auto' or an integer factor >= 1, got "
                                 f"{decimate!r}")
        q = int(decimate)
        if q > 1 and 0.4 * fs / q < 5.0 * f:
            raise ParameterError(
                f"decimation by {q} leaves {record.label} at {fs / q:.4g} Hz: the anti-alias "
                f"cut-off {0.4 * fs / q:.4g} Hz would keep fewer than 5 harmonics of its "
                f"{f:.4g} Hz stroke; at most {max(int(0.4 * fs / (5 * f)), 1)} is allowed")
    n_new = (record.time.size - 1) // q + 1
    if q > 1 and n_new < 2 * record.window:
        raise ParameterError(f"decimation by {q} leaves {record.label} with {n_new} samples, "
                             f"fewer than twice its Savitzky-Golay window ({record.window})")
    n = (n_new - 1) * q + 1  # record and model are filtered over the same span
    F0 = record.force[:n]
    stages = {}
    force = F0
    if force_cutoff is not None:
        force = lowpass(F0, fs, force_cutoff, filter_order, pad="even")
        stages["force filter"] = _removed(F0, force)
    channels = {k: getattr(record, k)[:n] for k in ("displacement", "smoothed", "velocity",
                                                       "acceleration")}
    # measured channels (temperature, voltage, ...) are filtered and decimated as the force is
    measured = {k: v[:n] for k, v in record.channels.items()}
    if force_cutoff is not None:
        measured = {k: lowpass(v, fs, force_cutoff, filter_order, pad="even")
                    for k, v in measured.items()}
    aa = None
    if q > 1:
        aa = 0.4 * fs / q
        before = force
        force = lowpass(force, fs, aa, _AA_ORDER, pad="even")
        stages["anti-alias"] = _removed(before, force)
        channels = {k: lowpass(v, fs, aa, _AA_ORDER) for k, v in channels.items()}
        measured = {k: lowpass(v, fs, aa, _AA_ORDER, pad="even") for k, v in measured.items()}
    sl = slice(None, None, q)
    cut = min(c for c in (force_cutoff, aa) if c is not None) if stages else 0.5 * fs / q
    rms, share = _removed(F0[sl], force[sl]) if stages else (0.0, 0.0)
    n0 = record.time.size
    meta = {k: (v[:n][sl] if isinstance(v, np.ndarray) and v.shape == (n0,) else v)
            for k, v in record.meta.items()}
    ch = {k: v[sl] for k, v in channels.items()}
    # dataclasses.replace keeps every other attribute of the record (frequency, amplitude,
    # source, ...) as it was
    # the file lines of the samples kept (a filtered sample is made of its neighbours too)
    dec = replace(record, time=record.time[:n][sl], displacement=ch["displacement"],
                  force=force[sl], velocity=ch["velocity"], acceleration=ch["acceleration"],
                  smoothed=ch["smoothed"], meta=meta,
                  channels={k: v[sl] for k, v in measured.items()},
                  lines=np.array([record.line(i) for i in range(0, n, q)]))
    nf = noise_floor(dec)
    if nf.method == "high band":
        nf = _with_rate_noise(nf, record, dec, aa, q)
    drive = dec.stroke()
    # the ends where the zero-phase filters' start-up transients bend the force are not
    # fitted (3 periods of the lowest cut-off); the model runs through them all the same
    e = int(math.ceil(3.0 * fs / q / cut)) if stages else 0
    if dec.time.size - 2 * e < 2 * record.window:
        raise ParameterError(
            f"{record.label}: after leaving out the {e} filtered samples at each end (3 "
            f"periods of the {cut:.4g} Hz cut-off) fewer than {2 * record.window} remain; "
            "raise the cut-off or give a longer record")
    if e:
        keep = slice(e, dec.time.size - e)
        m = dec.time.size
        dec = replace(dec, **{k: getattr(dec, k)[keep] for k in
                              ("time", "displacement", "force", "velocity", "acceleration",
                               "smoothed")},
                      channels={k: v[keep] for k, v in dec.channels.items()},
                      lines=dec.lines[keep], first_line=dec.line(e),
                      meta={k: (v[keep] if isinstance(v, np.ndarray) and v.shape == (m,)
                                else v) for k, v in dec.meta.items()})
    cycles = int(math.floor((dec.time[-1] - dec.time[0]) * f + 1e-9))
    check_choice("average", average, ("auto", True, False))
    periodic = nf.method.startswith("cycle scatter")
    if average is True and (not periodic or cycles < 2):
        raise ParameterError(
            f"{record.label} cannot be averaged over cycles: "
            + (f"it holds {cycles} whole cycle(s), at least 2 needed" if periodic else
               "its stroke does not repeat from cycle to cycle (or it holds fewer than two "
               "cycles)"))
    avg = (average is True) or (average == "auto" and periodic
                                and cycles >= AVERAGE_MIN_CYCLES)
    cond = Conditioning(
        source=record.label, sampling_rate=fs, stroke_frequency=f,
        force_cutoff=None if force_cutoff is None else float(force_cutoff),
        filter_order=int(filter_order), factor=q, anti_alias_cutoff=aa,
        fitted_rate=fs / q, harmonics_kept=float(cut / f), removed_rms=rms,
        removed_share=share, removed_by_stage=stages, noise=nf, trimmed=e, record=record,
        _stroke=(drive.time, drive.displacement, drive.velocity, drive.acceleration))
    if avg:
        return _average(dec, cond, cycles, dict(dec.meta), record.time[:n])
    if not cond.changed:
        return record, cond
    cond = replace(cond, samples=dec.time.size)
    return replace(dec, meta={**dec.meta, "conditioning": cond}), cond



def recondition(record: Record, cond: Conditioning) -> Record:
    """``record`` conditioned as ``cond`` says another record was (same force filter,
    decimation factor and averaging); e.g. a record as read whose force spikes were dropped
    (:func:`~liquidamp.analysis.measured.checks.drop_outliers`) after it was conditioned."""
    return condition(record, force_cutoff=cond.force_cutoff, filter_order=cond.filter_order,
                     decimate=cond.factor, average=cond.cycles_averaged > 1)[0]


def _average(dec: Record, cond: Conditioning, cycles: int, meta: dict, t_orig):
    """Average the whole cycles of a (filtered, decimated) record into one; the model map.

    Phase points j / M (M samples per cycle at the fitted rate) of every whole cycle c are
    interpolated linearly between the record's force samples and averaged over c.  The
    stroke is the periodic least-squares fit of the displacement over the whole record (the
    harmonics that stand out of its noise, :func:`stroke_threshold`) with its exact
    derivatives, so that the
    model is driven without the Savitzky-Golay derivative's attenuation (0.26 % on the
    rate of a 3 Hz stroke at 200 Hz) or the sample-to-sample interpolation.  The model is
    run over one steady cycle and its force taken at the phases of every sample of the
    record given (``t_orig``), so that a force jump falls between the same two samples as
    the record's; laid out in the record's order, that force goes through the record's
    filters, decimation and average (:meth:`Conditioning.model_force`).
    """
    f = dec.frequency
    T = 1.0 / f
    td = dec.time
    ts = float(td[0])
    M = int(round(T * dec.sampling_rate))
    tau = ts + (np.arange(cycles)[:, None] + np.arange(M)[None, :] / M) * T
    i = np.clip(np.searchsorted(td, tau, side="right") - 1, 0, td.size - 2)
    a = (tau - td[i]) / (td[i + 1] - td[i])

    def at_tau(x):
        return (1.0 - a) * x[i] + a * x[i + 1]

    # the stroke: its periodic fit (significant harmonics) and the exact derivatives of it,
    # on the record's phases and, for the model, on 8 M phases of one cycle
    series, y0, rate_std = _stroke_series(dec)
    phases = np.arange(M) / M
    y, v, acc = _evaluate(series, phases, f)
    ch = {"displacement": y0 + y, "smoothed": y0 + y, "velocity": v, "acceleration": acc,
          "force": at_tau(dec.force).mean(axis=0)}
    fine_phases = np.arange(8 * M + 1) / (8 * M)  # the last point closes the cycle
    stroke = (ts + fine_phases * T, *_evaluate(series, fine_phases, f))
    per_cycle = at_tau(dec.force)
    dev = per_cycle - ch["force"]
    var = float(np.var(per_cycle))
    stages = dict(cond.removed_by_stage)
    stages["cycle average"] = (float(np.sqrt(np.mean(dev * dev))),
                               float(np.var(dev)) / var if var > 0 else 0.0)
    psi = np.mod((np.asarray(t_orig) - ts) * f, 1.0)
    grid = np.unique(np.concatenate((psi, phases)))
    # the stroke at the model's phases, as the model's interpolated stroke gives it
    inputs = tuple(np.interp(ts + grid * T, stroke[0], q) for q in stroke[1:])
    # each averaged point's noise: sigma^2 mean((1 - a)^2 + a^2) / cycles
    shrink = math.sqrt(float(np.mean((1.0 - a) ** 2 + a ** 2)) / cycles)
    nf = cond.noise
    F = ch["force"]
    den = float(np.sqrt(np.mean((F - F.mean()) ** 2)))
    # the rate now comes from the stroke's periodic fit: its error reaches the force
    # through c_eq as in noise_floor (c_eq = rate_force_std / the rate's scatter there)
    c_eq = nf.rate_force_std / nf.rate_std if nf.rate_std > 0 else 0.0
    force_std = nf.force_std * shrink
    noise = replace(nf, force_std=force_std, displacement_std=nf.displacement_std * shrink,
                    rate_force_std=c_eq * rate_std,
                    nrmse=math.hypot(force_std, c_eq * rate_std) / den,
                    method=nf.method + f", averaged over {cycles}")
    cond = replace(cond, cycles_averaged=cycles, noise=noise, removed_by_stage=stages,
                   _stroke=stroke, samples=M,
                   _average={"t_start": ts, "period": T, "grid": grid, "inputs": inputs,
                             "series": tuple(series),
                             "points": M, "sample_index": np.searchsorted(grid, psi),
                             "record_index": np.searchsorted(grid, phases),
                             "i": i, "a": a})
    meta = {k: (at_tau(v).mean(axis=0) if isinstance(v, np.ndarray) and v.shape == td.shape
                else v) for k, v in meta.items()}
    meta["conditioning"] = cond
    # the averaged samples come from every cycle: no line of the file holds them
    out = replace(dec, time=ts + np.arange(M) / M * T, displacement=ch["displacement"],
                  force=F, velocity=ch["velocity"], acceleration=ch["acceleration"],
                  smoothed=ch["smoothed"], meta=meta, lines=None,
                  channels={k: at_tau(v).mean(axis=0) for k, v in dec.channels.items()})
    return out, cond


def stroke_threshold(harmonics: int, alpha: float = ALPHA) -> float:
    """Standard errors a stroke harmonic's amplitude must exceed to be kept [-].

    Of noise alone, a harmonic's least-squares sine and cosine coefficients are normal with
    the standard error se = sigma sqrt(2 / N), so its amplitude is Rayleigh: it exceeds t se
    with probability exp(-t^2 / 2).  Of H harmonics tested, none of noise alone is kept with
    probability at least 1 - ``alpha`` (Bonferroni) when t = sqrt(2 ln(H / alpha)), at least
    4 (the threshold of a single test).  ``alpha`` is the significance level of the
    project's drift test (:data:`~liquidamp.analysis.measured.drift.ALPHA`, 0.001): 4.0 for 3
    harmonics, 4.58 for 36.  A noise harmonic kept drives the model with a stroke the rig
    did not make, and a device that resonates near it amplifies it (the inerter design's
    channel on its liquid, near 59 Hz: a 4.1-se harmonic 28 of a 2 Hz stroke, 0.14 um,
    drew 10 N of model force no record held, 38 x the noise floor).

    Examples
    --------
    >>> round(stroke_threshold(3), 2), round(stroke_threshold(36), 2)
    (4.0, 4.58)
    """
    if harmonics < 1 or not 0.0 < alpha < 1.0:
        raise ParameterError(f"stroke_threshold needs harmonics >= 1 and 0 < alpha < 1, got "
                             f"harmonics {harmonics}, alpha {alpha:g}")
    return max(4.0, math.sqrt(2.0 * math.log(harmonics / alpha)))


def _stroke_series(rec: Record, max_harmonics: int = 64):
    """Periodic fit of the displacement: ([(k, a_k, b_k)], mean [m], rate error std [m/s]).

    Harmonics k f up to 0.45 x the sampling rate are fitted by least squares; those whose
    amplitude exceeds :func:`stroke_threshold` standard errors (sigma sqrt(2 / N), sigma the
    residual's standard deviation; 4 for a few harmonics, more the more are tested, so that
    none of noise alone is kept with probability 0.999) are kept, the fundamental always.
    The rate error is the standard deviation of the kept harmonics' noise,
    w sigma sqrt(2 / N sum k^2).
    """
    t = rec.time - rec.time[0]
    f, n = rec.frequency, rec.time.size
    H = max(1, harmonics_tested(rec.sampling_rate, f, max_harmonics))
    w = 2 * math.pi * f * t
    A = np.empty((n, 2 * H + 1))
    A[:, 0] = 1.0
    for k in range(1, H + 1):
        A[:, 2 * k - 1], A[:, 2 * k] = np.sin(k * w), np.cos(k * w)
    c, _, rank, _ = np.linalg.lstsq(A, rec.displacement, rcond=None)
    r = rec.displacement - A @ c
    sigma = float(np.sqrt(r @ r / max(n - int(rank), 1)))
    se = sigma * math.sqrt(2.0 / n)
    t_min = stroke_threshold(max(H - 1, 1))  # the harmonics tested: all but the fundamental
    keep = [(k, float(c[2 * k - 1]), float(c[2 * k])) for k in range(1, H + 1)
            if k == 1 or math.hypot(c[2 * k - 1], c[2 * k]) > t_min * se]
    rate_std = 2 * math.pi * f * se * math.sqrt(sum(k * k for k, _, _ in keep))
    return keep, float(c[0]), rate_std


def _evaluate(series, phases, f):
    """(y, v, a) of a harmonic series at phases (fractions of a cycle) [m, m/s, m/s^2]."""
    y, v, acc = (np.zeros(np.shape(phases)) for _ in range(3))
    w = 2 * math.pi * f
    for k, a_k, b_k in series:
        arg = 2 * math.pi * k * np.asarray(phases)
        s, co = np.sin(arg), np.cos(arg)
        y += a_k * s + b_k * co
        v += k * w * (a_k * co - b_k * s)
        acc -= (k * w) ** 2 * (a_k * s + b_k * co)
    return y, v, acc
