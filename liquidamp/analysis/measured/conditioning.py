"""Condition a record before fitting: zero-phase force filter, anti-alias filter and decimation.

A test machine samples at 1-3 kHz while a damper loop at 0.5-10 Hz is described by a few
tens of harmonics of the stroke frequency; fitting every sample costs time and fits rig
ringing and load-cell noise as if it were the device.  :func:`condition` returns a new
:class:`~liquidamp.analysis.measured.records.Record` and a :class:`Conditioning` that states
what was done and what it removed:

1. **Force filter** (optional, ``force_cutoff`` [Hz]): a Butterworth low-pass of order
   ``filter_order`` (4) run forward and backward (:func:`scipy.signal.sosfiltfilt`): zero
   phase, so the loop is not distorted in time; the magnitude response is |H|^2 of the
   Butterworth (-6 dB at the cut-off, flat below).  Only the force is filtered.  Use it to
   keep rig ringing out of the fit (e.g. the 10-50 Hz ringing of the friction-damper
   records); the model's force is not filtered, so keep the cut-off well above the
   harmonics that carry the loop's shape.
2. **Decimation** (``decimate``, default ``"auto"``): the factor q is the largest integer
   with fs / q >= 2.5 ``harmonics`` f (f the stroke frequency), so that at least
   ``harmonics`` (30) harmonics lie below the anti-alias cut-off; before every q-th sample
   is kept, every channel (force, displacement and its Savitzky-Golay smoothing, velocity
   and acceleration, which were computed at the full rate) passes the same zero-phase
   Butterworth low-pass of order 8 at 0.8 x the new Nyquist frequency (0.4 fs / q), as
   :func:`scipy.signal.decimate` places its cut-off.  The same linear filter on all
   channels keeps them aligned and keeps v = dy/dt.  A record already sampled at fewer
   than 2.5 ``harmonics`` f x 2 samples per second is left as it is (q = 1: nothing is
   filtered).

What the conditioning removed is measured on the force at the kept samples: the RMS of
(recorded - conditioned) [N] and its share of the recorded force's variance [-], in total
and by stage.

**Like with like.**  A model is compared with a conditioned record only after its force
has been conditioned the same way: :func:`liquidamp.analysis.measured.record_model.simulate_record`
computes the model force on a fine grid (every ``fine_step``-th sample of the record given,
at least 8 fine samples per kept one, so that the model's own content above the cut-off is
resolved), applies the same filters there and keeps the same samples
(:meth:`Conditioning.model_force`).  Without it a Coulomb friction jump in the model, sharp,
met a recorded jump rounded by the filter, and the residual kept a ringing edge at every
reversal (a 1 Hz record at 3 kHz with 30 N of Coulomb friction: calibration NRMSE 0.05
against a noise floor of 0.002, and smooth friction, Coulomb friction and a series spring
were added where Coulomb friction alone was true).

Sample i of a conditioned record is sample ``i * factor`` of the record given (its
``line`` numbers refer to the record given only when ``factor`` is 1); samples after the
last kept one are dropped before filtering, so that record and model are filtered over the
same span.  The record's ``meta["conditioning"]`` holds the :class:`Conditioning`.

References
----------
.. [1] S. Butterworth, "On the theory of filter amplifiers", Wireless Engineer 7, 1930.
.. [2] F. Gustafsson, "Determining the initial states in forward-backward filtering",
   IEEE Trans. Signal Process. 44(4), 1996 (zero-phase filtering, as ``sosfiltfilt``).
.. [3] A. V. Oppenheim, R. W. Schafer, Discrete-Time Signal Processing, 3rd ed., 2010,
   Sec. 4.6 (anti-alias filtering before downsampling).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.records import Record
from liquidamp.errors import ParameterError, check_finite

__all__ = ["Conditioning", "condition", "decimation_factor", "lowpass", "HARMONICS"]

#: Default number of harmonics of the stroke frequency kept below the anti-alias cut-off.
HARMONICS = 30.0

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
    fine_step : int
        The model force is computed on every ``fine_step``-th sample of the record given
        (a divisor of ``factor``) before it is conditioned like the record [-].
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
    fine_step: int = 1

    @property
    def changed(self) -> bool:
        """Whether the record was filtered or decimated."""
        return self.force_cutoff is not None or self.factor > 1

    def describe(self) -> str:
        """One line: what was done and what it removed."""
        parts = []
        if self.force_cutoff is not None:
            parts.append(f"force low-pass {self.force_cutoff:.4g} Hz (zero-phase Butterworth, "
                         f"order {self.filter_order} forward and backward)")
        if self.factor > 1:
            parts.append(f"decimated {self.factor}x to {self.fitted_rate:.4g} Hz after a "
                         f"zero-phase anti-alias low-pass at {self.anti_alias_cutoff:.4g} Hz")
        if not parts:
            return f"{self.source}: as recorded ({self.sampling_rate:.4g} Hz)"
        return (f"{self.source}: " + "; ".join(parts) + f"; removed {self.removed_rms:.4g} N "
                f"RMS ({self.removed_share:.2%} of the force variance), "
                f"{self.harmonics_kept:.3g} harmonics of {self.stroke_frequency:.4g} Hz kept")

    def fine_times(self, time) -> np.ndarray:
        """The fine grid [s] on which a model force is conditioned, for kept samples ``time``.

        Uniform at ``sampling_rate / fine_step`` from ``time[0]`` to ``time[-1]``; every
        ``factor // fine_step``-th point is a kept sample.
        """
        time = np.asarray(time, float)
        sub = self.factor // self.fine_step
        n = (time.size - 1) * sub + 1
        return time[0] + np.arange(n) * (self.fine_step / self.sampling_rate)

    def model_force(self, force_fine) -> np.ndarray:
        """Condition a model force given on :meth:`fine_times` as the record's was [N].

        The force filter and the anti-alias filter, with the record's cut-offs and orders,
        then every ``factor // fine_step``-th sample.
        """
        f = np.asarray(force_fine, float)
        rate = self.sampling_rate / self.fine_step
        if self.force_cutoff is not None:
            f = lowpass(f, rate, self.force_cutoff, self.filter_order)
        if self.anti_alias_cutoff is not None:
            f = lowpass(f, rate, self.anti_alias_cutoff, _AA_ORDER)
        return f[::self.factor // self.fine_step]

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
                "model_force_fine_step": self.fine_step,
                "description": self.describe()}


def lowpass(x, sampling_rate: float, cutoff: float, order: int = 4) -> np.ndarray:
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
    # odd extension over 6 / cutoff seconds (or the whole record): the start-up transient of
    # a low cut-off outlasts scipy's default pad of 3 x the filter length by far and would
    # bend the ends (2 mm at the end of a 0.25 Hz stroke decimated 54x)
    padlen = min(int(math.ceil(6.0 * fs / fc)), x.size - 1)
    return sosfiltfilt(sos, x, padlen=padlen)


@functools.lru_cache(maxsize=64)
def _butter(order: int, wn: float) -> np.ndarray:
    """Second-order sections of a Butterworth low-pass (designed once per order and cut-off:
    the design costs more than filtering a few thousand samples)."""
    from scipy.signal import butter

    return butter(order, wn, output="sos")


def decimation_factor(record: Record, harmonics: float = HARMONICS) -> int:
    """The automatic decimation factor: largest q with fs / q >= 2.5 ``harmonics`` f [-].

    Examples
    --------
    >>> t = np.arange(0, 6.0, 1 / 1024)
    >>> r = Record.from_arrays(t, 0.0127 * np.sin(np.pi * t), 1e4 * np.cos(np.pi * t))
    >>> decimation_factor(r), decimation_factor(r, 40.0)
    (27, 20)
    """
    h = check_finite("harmonics", harmonics, "-")
    if not 2.0 <= h <= 1e4:
        raise ParameterError(f"harmonics kept must lie between 2 and 1e4, got {h:g}")
    return max(1, int(record.sampling_rate / (_RATE_MARGIN * h * record.frequency)))


def _removed(raw, kept) -> tuple[float, float]:
    d = raw - kept
    var = float(np.var(raw))
    rms = float(np.sqrt(np.mean(d * d)))
    return rms, (float(np.var(d)) / var if var > 0 else 0.0)


def condition(record: Record, *, force_cutoff: float | None = None, filter_order: int = 4,
              decimate="auto", harmonics: float = HARMONICS) -> tuple[Record, Conditioning]:
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
    >>> c.factor, round(c.fitted_rate, 2), round(c.anti_alias_cutoff, 2), r.time.size
    (27, 37.93, 15.17, 227)
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
        force = lowpass(F0, fs, force_cutoff, filter_order)
        stages["force filter"] = _removed(F0, force)
    channels = {k: getattr(record, k)[:n] for k in ("displacement", "smoothed", "velocity",
                                                       "acceleration")}
    aa = None
    if q > 1:
        aa = 0.4 * fs / q
        before = force
        force = lowpass(force, fs, aa, _AA_ORDER)
        stages["anti-alias"] = _removed(before, force)
        channels = {k: lowpass(v, fs, aa, _AA_ORDER) for k, v in channels.items()}
    sl = slice(None, None, q)
    cut = min(c for c in (force_cutoff, aa) if c is not None) if stages else 0.5 * fs / q
    rms, share = _removed(F0[sl], force[sl]) if stages else (0.0, 0.0)
    # the fine grid of the model force: at least 8 fine samples per kept one where the
    # record allows (a divisor of q, so that the kept samples lie on it)
    fine = max((d for d in range(1, q + 1) if q % d == 0 and q // d >= min(8, q)), default=1)
    cond = Conditioning(
        source=record.label, sampling_rate=fs, stroke_frequency=f,
        force_cutoff=None if force_cutoff is None else float(force_cutoff),
        filter_order=int(filter_order), factor=q, anti_alias_cutoff=aa,
        fitted_rate=fs / q, harmonics_kept=float(cut / f), removed_rms=rms,
        removed_share=share, removed_by_stage=stages, fine_step=fine)
    if not cond.changed:
        return record, cond
    n0 = record.time.size
    meta = {k: (v[:n][sl] if isinstance(v, np.ndarray) and v.shape == (n0,) else v)
            for k, v in record.meta.items()}
    meta["conditioning"] = cond
    out = Record(time=record.time[:n][sl], displacement=channels["displacement"][sl],
                 force=force[sl], velocity=channels["velocity"][sl],
                 acceleration=channels["acceleration"][sl], smoothed=channels["smoothed"][sl],
                 frequency=f, amplitude=record.amplitude, phase=record.phase,
                 offset=record.offset, source=record.source, window=record.window,
                 order=record.order, meta=meta, first_line=record.first_line)
    return out, cond

