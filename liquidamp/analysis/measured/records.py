"""Measured test-machine records: the file format, read, write, differentiate.

A record is a CSV file with one header row naming each column with its unit
(the measured-data format of liquidamp; columns in any order, extra spaces
allowed; ``;``-, tab- or space-separated files, the first two may use a decimal comma; a
UTF-8 byte-order mark is ignored; lines starting with ``#`` are comments, and a test
machine's preamble before the header (``Specimen: ...``) is passed over):

=====================  ==================================================
column                 units accepted
=====================  ==================================================
``time``               ``[s]``, ``[ms]``
``displacement``       ``[m]``, ``[cm]``, ``[mm]``, ``[um]`` (``[µm]``), ``[in]``
``force``              ``[N]``, ``[daN]``, ``[kN]``, ``[kgf]``, ``[lbf]``, ``[kip]``
=====================  ==================================================

(US test laboratories record inches and pounds-force or kips: 1 in = 25.4 mm exactly,
1 lbf = 4.4482216152605 N exactly by definition; the unit may also be written in
parentheses, ``force (kip)``.)  A column may go by another name laboratories use
(:data:`~liquidamp.analysis.measured.record_format.COLUMN_NAMES`: ``stroke``,
``position``, ``disp``, ``load``, ...) or by a longer name ending in one (``load cell
force``, ``piston stroke``); a column the format does not read (``velocity``, ``cycle``)
is passed over with a warning that names it.

and, optionally, measured channels carried beside them (:data:`CHANNEL_UNITS`; read with
their units, kept in SI in :attr:`Record.channels`, filtered, decimated and averaged as
the force is by the conditioning, not used by the device models):

=====================  ==============================================
channel                units accepted (SI inside)
=====================  ==============================================
``temperature``        ``[K]``, ``[C]`` (``[°C]``, ``[degC]``), ``[F]`` (kept in K)
``voltage``            ``[V]``, ``[mV]``
``current``            ``[A]``, ``[mA]``
``pressure``           ``[Pa]``, ``[kPa]``, ``[MPa]``, ``[bar]``, ``[psi]``
=====================  ==============================================

Anything that cannot be read honestly (a missing or unknown column or unit,
a non-numeric or non-finite value, time that does not increase or is not
uniformly sampled, fewer samples than the filter window, less than one
excitation cycle) raises :class:`~liquidamp.errors.DataFileError` naming
the row (line number in the file) or column.  Each sample keeps the line of the file it
was read from (:meth:`Record.line`), so that every message can name it.

The stroke is differentiated as in the paper (Savitzky-Golay, 21 points,
4th order by default, Sec. IV.B); the excitation frequency, amplitude and
phase are inferred from the displacement (periodogram peak refined by a
least-squares sine fit).  The model is driven by the recorded stroke about
its mean (the LVDT zero is arbitrary; the mean stroke is taken as the
mid-position where the chambers hold V01 and V02).

Sign convention: liquidamp's force is the force the device exerts on the test
machine's load cell, positive when it resists a positive stroke (a positive
displacement compresses chamber 1, V1 = V01 - A_p y, and F = A_p (p1 - p2) +
...; DESIGN.md, eq. 10).  A passive device therefore absorbs energy: the loop
integral of F dy over a cycle is positive (a damper's force is in phase with
the stroke rate).  :func:`~liquidamp.analysis.measured.record_quality.check_record`
refuses a loop that delivers energy beyond its noise, naming the sign.

Periodic or not: :func:`stroke_shape` classifies the stroke
(:class:`StrokeShape`) as ``periodic`` (one sine and its harmonics of
constant amplitude hold at least 95 % of the stroke variance and the
cycle-by-cycle amplitude varies by at most 10 %), ``tapered`` (one frequency
cycle by cycle, the amplitude ramping: each whole cycle's sine holds at least
90 % of its variance, in phase from cycle to cycle) or ``broadband`` (any
other stroke, e.g. random).  The harmonic summaries (frequency, amplitude,
first-harmonic K*) mean something only for a periodic stroke; the others are
summarized by their RMS and band (:meth:`Record.describe`).  Every record is
fitted on its recorded stroke as it is, whatever its shape.

Checking a record for noise and outliers is
:mod:`liquidamp.analysis.measured.record_quality`; driving a model with it is
:mod:`liquidamp.analysis.measured.record_model`.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B-C.
.. [2] A. Savitzky, M. J. E. Golay, Anal. Chem. 36(8), 1964.
"""

from __future__ import annotations

import csv
import math
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from liquidamp.analysis.measured.record_format import (
    CHANNEL_SI,
    CHANNEL_UNITS,
    COLUMN_UNITS,
    decode_text,
    find_header,
    parse_header,
    read_rows,
)
from liquidamp.analysis.measured.tones import tone_fit
from liquidamp.errors import DataFileError, LiquidampWarning, ParameterError
from liquidamp.structure.testmachine import RecordedStroke, savgol_derivatives

__all__ = ["Record", "StrokeShape", "stroke_shape", "read_record", "write_record", "COLUMN_UNITS",
           "CHANNEL_UNITS", "infer_excitation", "PERIODIC_SHARE", "AMPLITUDE_VARIATION",
           "TAPERED_SHARE"]


def _fit_sine(t, y, f):
    w = 2.0 * math.pi * f
    A = np.column_stack((np.sin(w * t), np.cos(w * t), np.ones_like(t)))
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    res = y - A @ coef
    return coef, float(res @ res)


def infer_excitation(t, y) -> tuple[float, float, float, float]:
    """Frequency [Hz], amplitude [m], phase [rad] and mean [m] of the stroke's fundamental.

    y ~ offset + Y sin(2 pi f (t - t0) + phase), t0 the first sample.  The
    periodogram peak (zero-padded 8x) is refined by minimizing the residual
    of a least-squares sine fit over the frequency.

    Examples
    --------
    >>> t = np.arange(0, 2.5, 0.005)
    >>> f, Y, ph, y0 = infer_excitation(t, 0.003 * np.sin(2 * np.pi * 3.1 * t + 1.0) + 1e-4)
    >>> round(f, 6), round(Y, 6), round(ph, 6), round(y0, 9)
    (3.1, 0.003, 1.0, 0.0001)
    """
    from scipy.optimize import minimize_scalar

    t = np.asarray(t, float) - t[0]
    ymean = float(np.mean(y))
    y = np.asarray(y, float) - ymean
    n = t.size
    dt = t[-1] / (n - 1)
    nfft = 8 * (1 << int(math.ceil(math.log2(n))))
    spec = np.abs(np.fft.rfft(y * np.hanning(n), nfft))
    freqs = np.fft.rfftfreq(nfft, dt)
    spec[0] = 0.0
    k = int(np.argmax(spec))
    f0 = float(freqs[k])
    df = 1.0 / (nfft * dt)
    if f0 <= 0:
        raise DataFileError("displacement column: no excitation frequency found (constant?)")
    sol = minimize_scalar(lambda f: _fit_sine(t, y, f)[1], bounds=(max(f0 - 2 * df, 1e-9),
                          f0 + 2 * df), method="bounded", options={"xatol": 1e-10 * f0})
    f = float(sol.x)
    (a, b, c), _ = _fit_sine(t, y, f)
    return f, float(math.hypot(a, b)), float(math.atan2(b, a)), ymean + float(c)


#: Least share of the stroke variance in a constant-amplitude sine and its harmonics for a
#: periodic stroke [-].
PERIODIC_SHARE = 0.95
#: Largest cycle-to-cycle variation of the first-harmonic amplitude, (max - min) / max, of a
#: periodic stroke [-].
AMPLITUDE_VARIATION = 0.10
#: Least share of each whole cycle's variance in that cycle's own sine (and least phase
#: coherence from cycle to cycle) for a tapered stroke [-].
TAPERED_SHARE = 0.90


@dataclass(frozen=True)
class StrokeShape:
    """Whether a stroke is periodic, and its summary (:func:`stroke_shape`).

    Attributes
    ----------
    kind : str
        ``"periodic"``, ``"tapered"`` or ``"broadband"`` (module docstring).
    periodicity : float
        Share of the stroke variance held by the fitted sine of constant
        amplitude at the stroke frequency and its harmonics (up to the 5th
        below 0.8 x Nyquist) [-]: 1 for a steady sine, about 0 for noise.
    cycle_share : float
        Share of the variance of the whole cycles held by a sine fitted to each
        cycle on its own (amplitude and phase free per cycle) [-]; 1 for a
        tapered sine.
    phase_coherence : float
        |mean of the unit phasors| of those per-cycle sines [-]: 1 when every
        cycle has the same phase (one frequency throughout).
    amplitude_variation : float
        (max - min) / max of the per-cycle first-harmonic amplitudes [-]
        (0 with fewer than two whole cycles).
    cycle_amplitudes : tuple of float
        First-harmonic amplitude of each whole cycle [m].
    rms : float
        RMS of the stroke about its mean [m].
    band : (float, float)
        Frequencies below which 5 % and 95 % of the stroke's power lie [Hz].
    """

    kind: str
    periodicity: float
    cycle_share: float
    phase_coherence: float
    amplitude_variation: float
    cycle_amplitudes: tuple
    rms: float
    band: tuple

    @property
    def periodic(self) -> bool:
        """True for a periodic stroke."""
        return self.kind == "periodic"


def stroke_shape(t, y, frequency: float) -> StrokeShape:
    """Classify a stroke as periodic, tapered or broadband (module docstring).

    Parameters
    ----------
    t : array
        Sample times, uniform [s].
    y : array
        Displacement [m].
    frequency : float
        Stroke frequency (the periodogram peak, :func:`infer_excitation`) [Hz].

    Returns
    -------
    StrokeShape

    Examples
    --------
    >>> t = np.arange(0, 4.0, 0.005)
    >>> stroke_shape(t, 0.003 * np.sin(2 * np.pi * 3 * t), 3.0).kind
    'periodic'
    >>> ramp = np.minimum(1.0, t / 2.0)              # amplitude ramping over 6 cycles
    >>> stroke_shape(t, ramp * 0.003 * np.sin(2 * np.pi * 3 * t), 3.0).kind
    'tapered'
    >>> y = np.random.default_rng(0).normal(0, 1e-3, t.size)
    >>> stroke_shape(t, y, infer_excitation(t, y)[0]).kind
    'broadband'
    """
    t = np.asarray(t, float)
    y = np.asarray(y, float) - float(np.mean(y))
    n = t.size
    dt = float((t[-1] - t[0]) / (n - 1))
    var = float(y @ y)
    tt = t - t[0]
    w = 2 * math.pi * frequency
    cols = [np.ones_like(t)]
    for k in range(1, 6):
        if k == 1 or k * frequency < 0.4 / dt:
            cols += [np.sin(k * w * tt), np.cos(k * w * tt)]
    A = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    res = y - A @ coef
    share = 1.0 - float(res @ res) / var if var > 0 else 0.0
    # cycle by cycle: a sine of free amplitude and phase per whole cycle
    T = 1.0 / frequency
    ncyc = int(math.floor((tt[-1] + dt) / T + 1e-9))
    amps, phasors, r2, v2 = [], [], 0.0, 0.0
    for k in range(ncyc):
        m = (tt >= k * T - 0.5 * dt) & (tt < (k + 1) * T - 0.5 * dt)
        if m.sum() < 4:
            continue
        B = np.column_stack((np.sin(w * tt[m]), np.cos(w * tt[m]), np.ones(int(m.sum()))))
        c, *_ = np.linalg.lstsq(B, y[m], rcond=None)
        e = y[m] - B @ c
        d = y[m] - y[m].mean()
        r2 += float(e @ e)
        v2 += float(d @ d)
        amps.append(float(math.hypot(c[0], c[1])))
        phasors.append(complex(c[0], c[1]) / max(amps[-1], 1e-300))
    cycle_share = 1.0 - r2 / v2 if v2 > 0 else share
    coherence = float(abs(np.mean(phasors))) if phasors else 1.0
    variation = (max(amps) - min(amps)) / max(amps) if len(amps) >= 2 and max(amps) > 0 else 0.0
    spec = np.abs(np.fft.rfft(y * np.hanning(n))) ** 2
    spec[0] = 0.0
    cum = np.cumsum(spec)
    freqs = np.fft.rfftfreq(n, dt)
    if cum[-1] > 0:
        band = (float(freqs[np.searchsorted(cum, 0.05 * cum[-1])]),
                float(freqs[np.searchsorted(cum, 0.95 * cum[-1])]))
    else:
        band = (0.0, 0.0)
    if share >= PERIODIC_SHARE and variation <= AMPLITUDE_VARIATION:
        kind = "periodic"
    elif len(amps) >= 2 and cycle_share >= TAPERED_SHARE and coherence >= TAPERED_SHARE:
        kind = "tapered"
    else:
        kind = "broadband"
    return StrokeShape(kind=kind, periodicity=float(share), cycle_share=float(cycle_share),
                       phase_coherence=coherence, amplitude_variation=float(variation),
                       cycle_amplitudes=tuple(amps), rms=float(math.sqrt(var / n)), band=band)


@dataclass(frozen=True, eq=False)
class Record:
    """One measured (or synthetic) test-machine record, SI, read-only arrays.

    Attributes
    ----------
    time : ndarray
        Sample times [s], uniform.
    displacement : ndarray
        Measured stroke as recorded [m].
    force : ndarray
        Load-cell force [N].
    velocity, acceleration : ndarray
        Savitzky-Golay derivatives of the displacement [m/s], [m/s^2].  The
        first and last ``window // 2`` samples of the file, where the filter
        is one-sided and its derivatives are poor (they would pump volume
        into the model), are dropped from every array.
    smoothed : ndarray
        Savitzky-Golay smoothed displacement [m].
    frequency : float
        Inferred excitation frequency [Hz].
    amplitude : float
        Inferred first-harmonic stroke amplitude [m].
    phase : float
        Phase of the fundamental at the first sample [rad].
    offset : float
        Mean displacement [m]: the constant of the sine fit (removed before
        driving the model).
    source : str
        File the record came from ('' for arrays).
    window, order : int
        Savitzky-Golay window [samples] and order used.
    first_line : int
        Line of the source file that holds ``time[0]`` (header = line 1).
    lines : ndarray of int or None
        Line of the source file holding each sample (header = line 1; blank
        lines skipped by the reader are counted), or None: ``first_line + i``.
        :meth:`line` maps a sample index to its line.
    channels : dict
        Measured channels beside the stroke and force, name -> array in SI
        (:data:`CHANNEL_UNITS`: ``temperature`` [K], ``voltage`` [V], ``current`` [A],
        ``pressure`` [Pa]), read-only; carried through the conditioning, not used
        by the device models.
    shape : StrokeShape
        Periodic, tapered or broadband (:func:`stroke_shape`); ``frequency``,
        ``amplitude`` and ``phase`` summarize the stroke only where it is
        periodic (for the others they are the periodogram peak and the sine
        fitted at it, kept as the time scale of the model runs).
    """

    time: np.ndarray
    displacement: np.ndarray
    force: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    smoothed: np.ndarray
    frequency: float
    amplitude: float
    phase: float
    offset: float
    source: str = ""
    window: int = 21
    order: int = 4
    meta: dict = field(default_factory=dict, compare=False)
    first_line: int = 2
    shape: StrokeShape | None = None
    lines: np.ndarray | None = None
    channels: dict = field(default_factory=dict, compare=False)

    def line(self, i: int) -> int:
        """Line of the source file holding sample ``i`` (header = line 1; for arrays: the
        array index + 2, as if written to a file)."""
        if self.lines is not None:
            return int(self.lines[i])
        return int(self.first_line + i)

    def __post_init__(self) -> None:
        for name in ("time", "displacement", "force", "velocity", "acceleration", "smoothed"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        if self.lines is not None:
            lines = np.array(self.lines, dtype=np.int64)
            lines.setflags(write=False)
            object.__setattr__(self, "lines", lines)
        chans = {}
        for name, arr in dict(self.channels).items():
            a = np.array(arr, dtype=float)
            a.setflags(write=False)
            chans[name] = a
        object.__setattr__(self, "channels", chans)

    @classmethod
    def from_arrays(cls, time, displacement, force, *, window: int = 21, order: int = 4,
                    source: str = "", meta: dict | None = None, first_line: int = 2,
                    lines=None, channels: dict | None = None) -> Record:
        """Check, differentiate and characterize arrays in SI (time [s], stroke [m], force [N]).

        ``lines`` (optional): the file line of each sample (header = line 1), else
        ``first_line + index``; ``channels`` (optional): measured channels in SI, name
        (one of :data:`CHANNEL_UNITS`) -> array as long as ``time``.

        Raises
        ------
        DataFileError
            As :func:`read_record` (rows counted from 0 as array indices + 2,
            i.e. the line a CSV file would hold them on, or the ``lines`` given).

        Examples
        --------
        >>> t = np.arange(0, 2.0, 0.005)
        >>> y = 0.003 * np.sin(2 * np.pi * 3 * t)
        >>> r = Record.from_arrays(t, y, 100 * np.cos(6 * np.pi * t))
        >>> round(r.frequency, 6), round(r.amplitude * 1e3, 6), r.cycles > 5
        (3.0, 3.0, True)
        """
        where = f" in {source}" if source else ""
        t = np.asarray(time, float)
        y = np.asarray(displacement, float)
        F = np.asarray(force, float)
        chans = {}
        for name, arr in dict(channels or {}).items():
            if name not in CHANNEL_UNITS:
                raise DataFileError(f"unknown measured channel {name!r}{where}; valid: "
                                    f"{', '.join(CHANNEL_UNITS)}")
            chans[name] = np.asarray(arr, float)
        rows = (np.arange(t.size) + int(first_line) if lines is None
                else np.asarray(lines, dtype=np.int64))
        for name, arr in (("time", t), ("displacement", y), ("force", F), *chans.items()):
            if arr.ndim != 1:
                raise DataFileError(f"{name} must be one column{where}")
            if arr.size != t.size or rows.size != t.size:
                raise DataFileError(f"columns differ in length{where}: time {t.size}, "
                                    f"{name} {arr.size}" + ("" if rows.size == t.size else
                                                           f", lines {rows.size}"))
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise DataFileError(f"row {rows[bad[0]]}{where}: {name} is not a finite "
                                    f"number ({arr[bad[0]]!r})")
        if t.size < 2 * window:
            raise DataFileError(f"record{where} has {t.size} rows, fewer than twice the "
                                f"Savitzky-Golay window ({window})")
        dt = np.diff(t)
        bad = np.flatnonzero(dt <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            raise DataFileError(f"row {rows[i]}{where}: time {t[i]:.9g} s does not increase "
                                f"(previous {t[i - 1]:.9g} s)")
        med = float(np.median(dt))
        jitter = np.abs(dt - med) / med
        bad = np.flatnonzero(jitter > 0.01)
        if bad.size:
            i = int(bad[0]) + 1
            raise DataFileError(f"row {rows[i]}{where}: time step {dt[i - 1]:.6g} s differs from "
                                f"the median {med:.6g} s by more than 1%; the Savitzky-Golay "
                                "derivatives need uniform sampling")
        if np.ptp(y) <= 0:
            raise DataFileError(f"displacement column{where} is constant: no stroke")
        try:
            ys, v, a = savgol_derivatives(t, y, window, order)
        except ParameterError as exc:
            raise DataFileError(f"record{where}: {exc}") from None
        h = window // 2  # one-sided Savitzky-Golay fits at the ends: drop those samples
        t, y, F, ys, v, a, rows = (q[h:q.size - h] for q in (t, y, F, ys, v, a, rows))
        chans = {k: q[h:q.size - h] for k, q in chans.items()}
        f, Y, phase, y_mean = infer_excitation(t, y)
        duration = t[-1] - t[0] + med
        if duration * f < 1.0:
            raise DataFileError(
                f"record{where} lasts {duration:.4g} s, less than one cycle of its "
                f"{f:.4g} Hz excitation ({1 / f:.4g} s)")
        return cls(time=t, displacement=y, force=F, velocity=v, acceleration=a, smoothed=ys,
                   frequency=f, amplitude=Y, phase=phase, offset=y_mean,
                   source=str(source), window=window, order=order, meta=dict(meta or {}),
                   first_line=int(rows[0]), shape=stroke_shape(t, y, f),
                   lines=None if lines is None else rows, channels=chans)

    @property
    def period(self) -> float:
        """Excitation period [s]."""
        return 1.0 / self.frequency

    @property
    def cycles(self) -> float:
        """Number of excitation cycles in the record [-]."""
        return float((self.time[-1] - self.time[0]) * self.frequency)

    @property
    def sampling_rate(self) -> float:
        """Samples per second [Hz]."""
        return float((self.time.size - 1) / (self.time[-1] - self.time[0]))

    @property
    def label(self) -> str:
        """Short name: the file stem, or 'f Hz, Y mm' for a periodic stroke, 'broadband stroke,
        RMS Y mm' (or tapered) for another."""
        if self.source:
            return Path(self.source).stem
        if self.periodic:
            return self.describe()
        return f"{self.shape.kind} stroke, RMS {self.shape.rms * 1e3:.3g} mm"

    @property
    def periodic(self) -> bool:
        """True when the stroke is periodic (:func:`stroke_shape`): only then do
        ``frequency``, ``amplitude`` and first-harmonic quantities summarize it."""
        return self.shape is None or self.shape.periodic

    @property
    def stroke_scale(self) -> float:
        """Stroke amplitude of the record [m]: the first-harmonic amplitude of a periodic
        stroke, sqrt(2) x the RMS of any other (the amplitude of a sine of that RMS)."""
        if self.periodic:
            return float(self.amplitude)
        return math.sqrt(2.0) * self.shape.rms

    def describe(self) -> str:
        """The stroke in words: '3 Hz, 3 mm' where periodic, else its kind, RMS and band.

        Examples
        --------
        >>> t = np.arange(0, 4.0, 0.005)
        >>> Record.from_arrays(t, 0.003 * np.sin(6 * np.pi * t), np.cos(6 * np.pi * t)).describe()
        '3 Hz, 3 mm'
        >>> rng = np.random.default_rng(0)
        >>> r = Record.from_arrays(t, rng.normal(0, 3e-4, t.size), rng.normal(0, 1, t.size))
        >>> r.describe()[:31]
        'broadband stroke (not periodic)'
        """
        sh = self.shape
        if self.periodic:
            return f"{self.frequency:.3g} Hz, {self.amplitude * 1e3:.3g} mm"
        if sh.kind == "tapered":
            return (f"tapered stroke (not periodic) at {self.frequency:.3g} Hz, cycle amplitude "
                    f"{min(sh.cycle_amplitudes) * 1e3:.3g}-{max(sh.cycle_amplitudes) * 1e3:.3g}"
                    f" mm over {len(sh.cycle_amplitudes)} cycles")
        return (f"broadband stroke (not periodic), RMS {sh.rms * 1e3:.3g} mm, band "
                f"{sh.band[0]:.3g}-{sh.band[1]:.3g} Hz (5-95 % of the stroke power)")

    def summary(self) -> dict:
        """JSON-ready stroke summary: kind, periodicity figures, and the harmonic summary
        (frequency, amplitude) only where the stroke is periodic (SI)."""
        sh = self.shape or stroke_shape(self.time, self.displacement, self.frequency)
        out = {"kind": sh.kind, "periodic": self.periodic, "description": self.describe(),
               "periodicity": sh.periodicity, "cycle_share": sh.cycle_share,
               "phase_coherence": sh.phase_coherence,
               "amplitude_variation": sh.amplitude_variation,
               "rms [m]": sh.rms, "band [Hz]": list(sh.band),
               "sampling_rate [Hz]": self.sampling_rate,
               "duration [s]": float(self.time[-1] - self.time[0])}
        if self.periodic:
            out.update({"frequency [Hz]": self.frequency, "amplitude [m]": self.amplitude,
                        "cycles": self.cycles})
        else:
            out["cycle_amplitudes [m]"] = list(sh.cycle_amplitudes)
        return out

    @cached_property
    def tones(self):
        """The line-spectrum fit of a stroke that is not periodic but is a few sinusoids
        (:class:`~liquidamp.analysis.measured.tones.ToneFit`, exact derivatives), or None
        (a periodic stroke, or one the lines do not explain: tapered, broadband); computed
        once per record (:func:`~liquidamp.analysis.measured.tones.tone_fit`)."""
        return None if self.periodic else tone_fit(self.time, self.displacement)

    def stroke(self) -> RecordedStroke:
        """The stroke that drives a model: consistent displacement and velocity about the mean.

        The Savitzky-Golay velocity is not exactly the derivative of the
        smoothed displacement (the filter attenuates the derivative by about
        0.2 % at 3 Hz and 200 Hz); fed to a model whose chamber volumes follow
        y while the volume flow follows v, the mismatch creates and destroys
        mass every cycle and the mean pressures drift.  The driving
        displacement is therefore the running integral of the SG velocity,
        fitted to the smoothed displacement by a constant and a trend (the
        trend's slope is added to the velocity), so that dy/dt = v holds.

        A stroke that is not periodic but is a few sinusoids (a two-frequency lag-damper
        test) is its least-squares line-spectrum fit instead, with exact derivatives
        (:func:`~liquidamp.analysis.measured.tones.tone_fit`: accepted where it leaves only
        the sensor's white noise), free of the filter's attenuation.
        """
        from scipy.integrate import cumulative_trapezoid

        t = self.time
        tones = self.tones
        if tones is not None:
            y, v, a = tones.arrays(t)
            return RecordedStroke(t, y + tones.mean - self.offset, v, a)
        yc = cumulative_trapezoid(self.velocity, t, initial=0.0)
        A = np.column_stack((np.ones_like(t), t - t[0]))
        (c0, c1), *_ = np.linalg.lstsq(A, self.smoothed - self.offset - yc, rcond=None)
        return RecordedStroke(t, yc + c0 + c1 * (t - t[0]), self.velocity + c1,
                              self.acceleration)

    def trimmed(self, cycles: float) -> Record:
        """The first ``cycles`` excitation cycles of the record (derivatives recomputed)."""
        n = int(round(cycles * self.period * self.sampling_rate)) + 1 + 2 * (self.window // 2)
        n = min(max(n, 2 * self.window), self.time.size)
        return Record.from_arrays(self.time[:n], self.displacement[:n], self.force[:n],
                                  window=self.window, order=self.order, source=self.source,
                                  meta=self.meta, first_line=self.first_line,
                                  lines=None if self.lines is None else self.lines[:n],
                                  channels={k: v[:n] for k, v in self.channels.items()})


def read_record(path, window: int = 21, order: int = 4) -> Record:
    """Read a record CSV (see module docstring) into a :class:`Record` (SI).

    Accepted beside plain comma-separated UTF-8: a UTF-8 byte-order mark (as
    Excel writes it) or UTF-16 with its mark; columns separated by ``;`` or
    tabs (detected from the header row), in which case numbers may use a
    decimal comma (``0,005``), or by spaces; ``#`` comment lines and a preamble
    before the header (:func:`~liquidamp.analysis.measured.record_format.find_header`).
    A thousands separator is not accepted.  Columns the format does not read are passed
    over with a :class:`~liquidamp.errors.LiquidampWarning` naming them.

    Parameters
    ----------
    path : str or Path
        CSV file with a header row.
    window, order : int
        Savitzky-Golay window [samples] and polynomial order (paper: 21, 4).

    Raises
    ------
    DataFileError
        Naming the file and the line (1 = header) or column at fault; a
        binary file, a decimal comma in a comma-separated file and a value
        with both ``.`` and ``,`` are named as such.

    Examples
    --------
    >>> import tempfile, os
    >>> t = np.arange(0, 1.0, 0.005)
    >>> rows = [f"{a:.3f};{3 * np.sin(6 * np.pi * a):.4f};{np.cos(6 * np.pi * a):.4f}"
    ...         for a in t]
    >>> text = "time [s];displacement [mm];force [kN]\\n" + "\\n".join(rows)
    >>> path = os.path.join(tempfile.mkdtemp(), "semicolon.csv")
    >>> _ = open(path, "w", encoding="utf-8-sig").write(text.replace(".", ","))
    >>> r = read_record(path)
    >>> round(r.frequency, 3), round(r.amplitude * 1e3, 3)
    (3.0, 3.0)
    """
    path = Path(path)
    where = str(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise DataFileError(f"cannot read record {where}: {exc.strerror or exc}") from None
    text = decode_text(raw, where)
    lines = text.splitlines()
    if not lines or not any(line.strip() for line in lines):
        raise DataFileError(f"{where} is empty: expected a header row")
    h, delim, header = find_header(lines, where)
    cols = parse_header(header, where, h + 1)
    unused = cols.pop("unused")
    if unused:
        warnings.warn(f"{where}: column(s) not read: "
                      + ", ".join(f"{j + 1} {c!r}" for j, c in unused)
                      + "; a record reads time, displacement, force and the channels "
                      + ", ".join(CHANNEL_UNITS), LiquidampWarning, stacklevel=2)
    data, line_of = read_rows(lines[h + 1:], h + 2, delim, cols, len(header), where)
    return Record.from_arrays(data["time"], data["displacement"], data["force"], window=window,
                              order=order, source=where, lines=line_of,
                              channels={k: data[k] for k in cols if k in CHANNEL_UNITS})


def write_record(path, record=None, *, time=None, displacement=None, force=None,
                 displacement_unit: str = "mm") -> Path:
    """Write a record CSV: ``time [s]``, ``displacement [mm]`` (or [m]), ``force [N]``.

    Give a :class:`Record` or the three SI arrays; a record's measured channels follow
    in SI (``temperature [K]``, ``voltage [V]``, ...).  No comment lines (the
    format has none); keep a recipe in a README or JSON sidecar.
    """
    chans = {}
    if record is not None:
        time, displacement, force = record.time, record.displacement, record.force
        chans = dict(record.channels)
    if time is None or displacement is None or force is None:
        raise ParameterError("write_record needs a Record or time, displacement and force")
    units = COLUMN_UNITS["displacement"]
    if displacement_unit not in units:
        raise ParameterError(f"displacement_unit must be one of {', '.join(units)}, "
                             f"got {displacement_unit!r}")
    k = units[displacement_unit]
    from liquidamp.atomic import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp, tmp.open("w", newline="") as fh:  # whole file or none
        w = csv.writer(fh)
        w.writerow(["time [s]", f"displacement [{displacement_unit}]", "force [N]"]
                   + [f"{c} [{CHANNEL_SI[c]}]" for c in chans])
        for i, (t, y, f) in enumerate(zip(np.asarray(time, float),
                                          np.asarray(displacement, float) / k,
                                          np.asarray(force, float), strict=True)):
            w.writerow([f"{t:.6f}", f"{y:.7g}", f"{f:.6g}"]
                       + [f"{v[i]:.7g}" for v in chans.values()])
    return path


# ---------------------------------------------------------------------------
# driving a model with a record
