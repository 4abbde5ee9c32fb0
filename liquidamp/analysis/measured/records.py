"""Measured test-machine records: the file format, read, write, differentiate.

A record is a CSV file with one header row naming each column with its unit
(the measured-data format of liquidamp; columns in any order, extra spaces
allowed; ``;``- or tab-separated files may use a decimal comma, a UTF-8
byte-order mark is ignored):

=====================  =====================================
column                 units accepted
=====================  =====================================
``time``               ``[s]``, ``[ms]``
``displacement``       ``[m]``, ``[mm]``, ``[um]``
``force``              ``[N]``, ``[kN]``
=====================  =====================================

Anything that cannot be read honestly (a missing or unknown column or unit,
a non-numeric or non-finite value, time that does not increase or is not
uniformly sampled, fewer samples than the filter window, less than one
excitation cycle) raises :class:`~liquidamp.errors.DataFileError` naming
the row (line number in the file) or column.

The stroke is differentiated as in the paper (Savitzky-Golay, 21 points,
4th order by default, Sec. IV.B); the excitation frequency, amplitude and
phase are inferred from the displacement (periodogram peak refined by a
least-squares sine fit).  The model is driven by the recorded stroke about
its mean (the LVDT zero is arbitrary; the mean stroke is taken as the
mid-position where the chambers hold V01 and V02).

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
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from liquidamp.errors import DataFileError, ParameterError
from liquidamp.structure.testmachine import RecordedStroke, savgol_derivatives

__all__ = ["Record", "read_record", "write_record", "COLUMN_UNITS", "infer_excitation"]


COLUMN_UNITS: dict[str, dict[str, float]] = {
    "time": {"s": 1.0, "ms": 1e-3},
    "displacement": {"m": 1.0, "mm": 1e-3, "um": 1e-6},
    "force": {"N": 1.0, "kN": 1e3},
}
"""Accepted columns and units: name -> {unit: factor to SI}."""

_HEADER = re.compile(r"^\s*([A-Za-z_ ]+?)\s*\[\s*([^\]]*?)\s*\]\s*$")


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
        Line of the source file that holds ``time[0]`` (header = line 1);
        :meth:`line` maps a sample index to its line.
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

    def line(self, i: int) -> int:
        """Line of the source file holding sample ``i`` (header = line 1; for arrays: the
        array index + 2, as if written to a file)."""
        return int(self.first_line + i)

    def __post_init__(self) -> None:
        for name in ("time", "displacement", "force", "velocity", "acceleration", "smoothed"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @classmethod
    def from_arrays(cls, time, displacement, force, *, window: int = 21, order: int = 4,
                    source: str = "", meta: dict | None = None, first_line: int = 2) -> Record:
        """Check, differentiate and characterize arrays in SI (time [s], stroke [m], force [N]).

        Raises
        ------
        DataFileError
            As :func:`read_record` (rows counted from 0 as array indices + 2,
            i.e. the line a CSV file would hold them on).

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
        for name, arr in (("time", t), ("displacement", y), ("force", F)):
            if arr.ndim != 1:
                raise DataFileError(f"{name} must be one column{where}")
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise DataFileError(f"row {bad[0] + 2}{where}: {name} is not a finite number "
                                    f"({arr[bad[0]]!r})")
        if not t.size == y.size == F.size:
            raise DataFileError(f"columns differ in length{where}: time {t.size}, "
                                f"displacement {y.size}, force {F.size}")
        if t.size < 2 * window:
            raise DataFileError(f"record{where} has {t.size} rows, fewer than twice the "
                                f"Savitzky-Golay window ({window})")
        dt = np.diff(t)
        bad = np.flatnonzero(dt <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            raise DataFileError(f"row {i + 2}{where}: time {t[i]:.9g} s does not increase "
                                f"(previous {t[i - 1]:.9g} s)")
        med = float(np.median(dt))
        jitter = np.abs(dt - med) / med
        bad = np.flatnonzero(jitter > 0.01)
        if bad.size:
            i = int(bad[0]) + 1
            raise DataFileError(f"row {i + 2}{where}: time step {dt[i - 1]:.6g} s differs from "
                                f"the median {med:.6g} s by more than 1%; the Savitzky-Golay "
                                "derivatives need uniform sampling")
        if np.ptp(y) <= 0:
            raise DataFileError(f"displacement column{where} is constant: no stroke")
        try:
            ys, v, a = savgol_derivatives(t, y, window, order)
        except ParameterError as exc:
            raise DataFileError(f"record{where}: {exc}") from None
        h = window // 2  # one-sided Savitzky-Golay fits at the ends: drop those samples
        t, y, F, ys, v, a = (q[h:q.size - h] for q in (t, y, F, ys, v, a))
        f, Y, phase, y_mean = infer_excitation(t, y)
        duration = t[-1] - t[0] + med
        if duration * f < 1.0:
            raise DataFileError(
                f"record{where} lasts {duration:.4g} s, less than one cycle of its "
                f"{f:.4g} Hz excitation ({1 / f:.4g} s)")
        return cls(time=t, displacement=y, force=F, velocity=v, acceleration=a, smoothed=ys,
                   frequency=f, amplitude=Y, phase=phase, offset=y_mean,
                   source=str(source), window=window, order=order, meta=dict(meta or {}),
                   first_line=int(first_line) + h)

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
        """Short name: the file stem or 'f Hz, Y mm'."""
        if self.source:
            return Path(self.source).stem
        return f"{self.frequency:.3g} Hz, {self.amplitude * 1e3:.3g} mm"

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
        """
        from scipy.integrate import cumulative_trapezoid

        t = self.time
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
                                  meta=self.meta, first_line=self.first_line)


def _parse_header(row, where):
    cols = {}
    for j, cell in enumerate(row):
        m = _HEADER.match(cell)
        if not m:
            raise DataFileError(
                f"{where}, line 1, column {j + 1}: header {cell!r} must read 'name [unit]' "
                f"with name one of {', '.join(COLUMN_UNITS)}")
        name, unit = m.group(1).strip().lower(), m.group(2).strip()
        if name not in COLUMN_UNITS:
            raise DataFileError(
                f"{where}, line 1, column {j + 1}: unknown column {name!r}; valid: "
                f"{', '.join(COLUMN_UNITS)}")
        units = COLUMN_UNITS[name]
        if unit not in units:
            raise DataFileError(
                f"{where}, line 1, column {j + 1} ({name}): unknown unit [{unit}]; valid: "
                + ", ".join(f"[{u}]" for u in units))
        if name in cols:
            raise DataFileError(f"{where}, line 1, column {j + 1}: column {name!r} given twice")
        cols[name] = (j, units[unit])
    missing = [c for c in COLUMN_UNITS if c not in cols]
    if missing:
        raise DataFileError(f"{where}: missing column(s) {', '.join(missing)}; the header must "
                            "name time [s], displacement [mm] or [m], force [N] or [kN]")
    return cols


_DECIMAL_COMMA = re.compile(r"^[+-]?(\d+,\d*|,\d+)([eE][+-]?\d+)?$")


def _decode(raw: bytes, where: str) -> str:
    """Text of a record file: UTF-8 (a byte-order mark is dropped), UTF-16 with its BOM, or
    Latin-1 for a text file that is not UTF-8; a binary file raises naming the file."""
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError:
            pass
    head = raw[:4096]
    nul = head.find(b"\x00")
    control = sum(1 for c in head if c < 32 and c not in (9, 10, 13))
    if nul >= 0 or (head and control > 0.05 * len(head)):
        at = f"NUL byte at offset {nul}" if nul >= 0 else f"{control} control bytes"
        raise DataFileError(
            f"{where} is not a text CSV file (binary content: {at} in its first "
            f"{len(head)} bytes); a record is a CSV text file whose header row names "
            "time [s], displacement [mm] or [m], force [N] or [kN]")
    try:
        return raw.decode("utf-8-sig")  # a UTF-8 byte-order mark (Excel) is dropped
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def _delimiter(header: str) -> str:
    """Column separator: ',' unless the header is separated by ';' or tabs instead."""
    outside = re.sub(r"\[[^\]]*\]", "", header)  # units may hold anything
    counts = {d: outside.count(d) for d in (",", ";", "\t")}
    if counts[","] == 0 and (counts[";"] or counts["\t"]):
        return ";" if counts[";"] >= counts["\t"] else "\t"
    return ","


def _number(cell: str, decimal_comma: bool):
    """float of ``cell`` (a decimal comma allowed when the columns are not comma-separated)."""
    try:
        return float(cell)
    except ValueError:
        if decimal_comma and _DECIMAL_COMMA.match(cell):
            return float(cell.replace(",", "."))
        raise


def read_record(path, window: int = 21, order: int = 4) -> Record:
    """Read a record CSV (see module docstring) into a :class:`Record` (SI).

    Accepted beside plain comma-separated UTF-8: a UTF-8 byte-order mark (as
    Excel writes it) or UTF-16 with its mark; columns separated by ``;`` or
    tabs (detected from the header row), in which case numbers may use a
    decimal comma (``0,005``).  A thousands separator is not accepted.

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
    text = _decode(raw, where)
    lines = text.splitlines()
    if not lines or not any(line.strip() for line in lines):
        raise DataFileError(f"{where} is empty: expected a header row")
    delim = _delimiter(lines[0])
    decimal_comma = delim != ","
    rows = list(csv.reader(lines, delimiter=delim))
    cols = _parse_header([c.strip() for c in rows[0]], where)
    ncol = len(rows[0])
    data = {name: [] for name in cols}
    sep = {",": "','", ";": "';'", "\t": "tab"}[delim]
    for i, row in enumerate(rows[1:], start=2):
        if not row or all(not c.strip() for c in row):
            continue
        if len(row) != ncol:
            hint = ""
            if delim == "," and len(row) == 2 * ncol and all(
                    re.fullmatch(r"[+-]?\d*([eE][+-]?\d+)?", c.strip()) for c in row):
                hint = ("; the values seem to use a decimal comma, which needs the columns "
                        "separated by ';' (or tabs), as in the header")
            raise DataFileError(f"{where}, line {i}: {len(row)} fields separated by {sep}, "
                                f"the header has {ncol}{hint}")
        for name, (j, factor) in cols.items():
            cell = row[j].strip()
            try:
                value = _number(cell, decimal_comma)
            except ValueError:
                why = "is not a number"
                if "," in cell and "." in cell:
                    why = ("is not a number (it holds both '.' and ','; write numbers without "
                           "a thousands separator)")
                raise DataFileError(
                    f"{where}, line {i}, column {j + 1} ({name}): {cell!r} {why}") from None
            if not math.isfinite(value):
                raise DataFileError(
                    f"{where}, line {i}, column {j + 1} ({name}): {cell!r} is not finite")
            data[name].append(value * factor)
    return Record.from_arrays(data["time"], data["displacement"], data["force"], window=window,
                              order=order, source=where)


def write_record(path, record=None, *, time=None, displacement=None, force=None,
                 displacement_unit: str = "mm") -> Path:
    """Write a record CSV: ``time [s]``, ``displacement [mm]`` (or [m]), ``force [N]``.

    Give a :class:`Record` or the three SI arrays.  No comment lines (the
    format has none); keep a recipe in a README or JSON sidecar.
    """
    if record is not None:
        time, displacement, force = record.time, record.displacement, record.force
    if time is None or displacement is None or force is None:
        raise ParameterError("write_record needs a Record or time, displacement and force")
    units = COLUMN_UNITS["displacement"]
    if displacement_unit not in units:
        raise ParameterError(f"displacement_unit must be one of {', '.join(units)}, "
                             f"got {displacement_unit!r}")
    k = units[displacement_unit]
    path = Path(path)
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time [s]", f"displacement [{displacement_unit}]", "force [N]"])
        for t, y, f in zip(np.asarray(time, float), np.asarray(displacement, float) / k,
                           np.asarray(force, float), strict=True):
            w.writerow([f"{t:.6f}", f"{y:.7g}", f"{f:.6g}"])
    return path


# ---------------------------------------------------------------------------
# driving a model with a record
