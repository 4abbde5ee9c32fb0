"""Measured test-machine records: read, check, differentiate, and drive a model with them.

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

Start-up transients: :func:`simulate_record` pre-rolls the model over the
record's first cycle ``preroll`` times (each pass restarting at the record's
first sample from the state the previous pass ended with), then runs the
whole record.  Each pass is one excitation cycle of the periodic march of
:func:`liquidamp.coupled.testrig.steady_state`, driven by the measured
stroke, so the comparison starts close to the periodic steady state.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B-C.
.. [2] A. Savitzky, M. J. E. Golay, Anal. Chem. 36(8), 1964.
"""

from __future__ import annotations

import bisect
import csv
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from liquidamp.coupled.testrig import DeviceResponse
from liquidamp.device.models import DeviceModel, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ConvergenceError, DataFileError, ParameterError, PressureError
from liquidamp.options import SolverOptions, resolve_options
from liquidamp.structure.testmachine import RecordedStroke, savgol_derivatives

__all__ = ["Record", "NoiseFloor", "read_record", "write_record", "simulate_record",
           "noise_floor", "nrmse", "COLUMN_UNITS", "Outlier", "DataQuality", "check_record"]

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


class _Interp:
    """Fast scalar linear interpolation of (y, v, a) on a sample grid (clamped ends)."""

    def __init__(self, t, y, v, a):
        self.t = [float(x) for x in t]
        self.y, self.v, self.a = (list(map(float, q)) for q in (y, v, a))
        self.n = len(self.t)

    def __call__(self, t):
        tt = self.t
        i = bisect.bisect_right(tt, t) - 1
        if i < 0:
            i = 0
        elif i > self.n - 2:
            i = self.n - 2
        w = (t - tt[i]) / (tt[i + 1] - tt[i])
        w = 0.0 if w < 0.0 else (1.0 if w > 1.0 else w)
        y, v, a = self.y, self.v, self.a
        return (y[i] + w * (y[i + 1] - y[i]), v[i] + w * (v[i + 1] - v[i]),
                a[i] + w * (a[i + 1] - a[i]))


def integrate(model: DeviceModel, params: DeviceParams, stroke, t_eval, x0, *,
              rtol: float, atol_scale: float, hmax: float = 0.0) -> np.ndarray:
    """Integrate ``model`` under the scalar ``stroke(t) -> (y, v, a)`` with LSODA (odeint).

    Returns the states at ``t_eval``, shape (n_states, len(t_eval)).  LSODA
    switches between Adams and BDF as the device's stiffness changes; its
    Fortran driver costs far less per step than ``solve_ivp``, which is
    what makes fitting many records affordable in pure Python.

    Raises
    ------
    ConvergenceError
        If LSODA reports failure or the states are not finite.
    """
    from scipy.integrate import odeint

    rhs = model.rhs
    jac = model.jacobian
    t_eval = np.asarray(t_eval, float)
    if model.n_states == 0:
        return np.zeros((0, t_eval.size))

    def f(t, x):
        return rhs(t, x, stroke(t), params)

    dfun = None
    if jac is not None:
        def dfun(t, x):
            return jac(t, x, stroke(t), params)

    atol = atol_scale * np.asarray(model.state_scales(params), float)
    X, info = odeint(f, np.asarray(x0, float), t_eval, Dfun=dfun, tfirst=True, rtol=rtol,
                     atol=atol, hmax=hmax, mxstep=50000, full_output=True)
    if info.get("message") != "Integration successful." or not np.all(np.isfinite(X)):
        raise ConvergenceError(
            f"model {model.name!r}: time integration failed between t = {t_eval[0]:.6g} s and "
            f"{t_eval[-1]:.6g} s: {info.get('message')}")
    return X.T


def _engine(options) -> str:
    return getattr(options, "engine", "scipy")


def simulate_record(model, params: DeviceParams, record: Record, *,
                    options: SolverOptions | None = None, preroll: int = 2,
                    x0=None) -> DeviceResponse:
    """Drive ``model`` with the record's stroke; the model force at the record's samples.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model or one composed with :func:`liquidamp.device.effects.with_effects`.
    params : DeviceParams
        Device parameters.
    record : Record
        The measured record (its smoothed stroke about its mean, SG velocity
        and acceleration drive the model).
    options : SolverOptions, optional
        ``rtol``, ``atol_scale``, ``max_step_fraction`` and
        ``pressure_floor`` are used.  With ``engine="compiled"`` the model,
        with any effects, runs on the compiled engine
        (:func:`liquidamp.coupled.fast.march`); the ``scipy`` engine
        integrates the same right-hand side with LSODA (:func:`integrate`).
        Default: the ``"default"`` preset of :data:`liquidamp.options.PRESETS`
        (the fitting functions pass ``"fit"``).
    preroll : int
        Passes over the first cycle discarded before the record is run
        (module docstring) [-].
    x0 : array, optional
        Initial state for the first pre-roll pass (default: rest at p0).

    Returns
    -------
    DeviceResponse
        ``time`` = record time, ``force`` the model's load-cell force [N],
        ``status = "completed"``; warnings for pressures below the vapour
        pressure.

    Raises
    ------
    PressureError
        A chamber pressure reached ``options.pressure_floor`` (models using
        the pressure-dependent bulk law), as in testrig.
    ConvergenceError
        The integration failed.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> t = np.arange(0, 1.0, 0.005)
    >>> rec = Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), 0 * t)
    >>> r = simulate_record("full", preset("paper_calibrated"), rec)
    >>> r.force.shape == rec.time.shape, bool(abs(r.force).max() > 300)
    (True, True)
    """
    model = get_model(model)
    options = resolve_options(options, "default")
    if not isinstance(params, DeviceParams):
        raise ParameterError(f"params must be DeviceParams, got {type(params).__name__}")
    model.check_params(params)
    stroke = record.stroke()
    if stroke.max_abs >= params.stroke_limit:
        raise ParameterError(
            f"record stroke reaches |y| = {stroke.max_abs:.4g} m about its mean, past the "
            f"chamber end at {params.stroke_limit:.4g} m (V0/A_p)")
    t = record.time
    n_cycle = min(int(math.ceil(record.period * record.sampling_rate)) + 1, t.size)
    y0 = float(stroke.displacement[0])
    x = model.initial_state(params, y0) if x0 is None else np.asarray(x0, float)
    engine = _engine(options)

    fast = _Interp(stroke.time, stroke.displacement, stroke.velocity, stroke.acceleration)
    # a bounded step: a state that rests while the input moves (freeplay in its gap, a
    # closed cavity) gives zero derivatives at the start, and an unbounded first step
    # can jump over the whole record without ever seeing the contact
    hmax = max(options.max_step_fraction, 1e-4) * record.period
    if engine == "compiled" and model.n_states:
        # every model with any effects runs on the compiled engine (one copy of the physics)
        from liquidamp.coupled.fast import march

        def run(t_eval, xs):
            t0, t1 = float(t_eval[0]), float(t_eval[-1])
            X, _, _ = march(model, params, stroke, xs, t0, t1, t_eval, options,
                            options.max_step_fraction * record.period)
            return X
    else:
        def run(t_eval, xs):
            return integrate(model, params, fast, t_eval, xs, rtol=options.rtol,
                             atol_scale=options.atol_scale, hmax=hmax)
    t_cycle = np.append(t[:n_cycle - 1], t[0] + record.period)  # exactly one period
    for _ in range(preroll if model.n_states else 0):
        x = run(t_cycle, x)[:, -1]
    X = run(t, x)
    u = (stroke.displacement, stroke.velocity, stroke.acceleration)
    return _response(model, params, t, X, u, options)


def _response(model, params, t, X, u, options) -> DeviceResponse:
    force = np.broadcast_to(np.asarray(model.force(t, X, u, params), float), t.shape).copy()
    p1 = p2 = None
    warn = []
    if model.pressures is not None:
        p1, p2 = (np.broadcast_to(np.asarray(q, float), t.shape).copy()
                  for q in model.pressures(X, u, params))
        pmin = float(min(p1.min(), p2.min()))
        if (model.uses_bulk_law and params.bulk_law == "gholizadeh"
                and pmin <= options.pressure_floor):
            raise PressureError(
                f"model {model.name!r}: a chamber pressure fell to {pmin:.4g} Pa, at or below "
                f"the floor {options.pressure_floor:g} Pa; the liquid-air law (eq. 2) is "
                "singular at p = 0: the device cavitates (add the 'cavitation' effect)")
        if pmin <= 0.0:
            warn.append(f"absolute chamber pressure went negative (lowest {pmin:.4g} Pa): "
                        "non-physical for this model")
        elif pmin < options.vapour_pressure and model.effect("cavitation") is None:
            warn.append(f"lowest chamber pressure {pmin:.4g} Pa is below the vapour pressure "
                        f"{options.vapour_pressure:g} Pa (add the 'cavitation' effect)")
    mass_error = None
    if model.mass is not None:
        M = np.asarray(model.mass(X, u, params), float)
        mass_error = float(np.max(np.abs(M - M[0])) / M[0])
    X.setflags(write=False)
    return DeviceResponse(
        model=model.name, params=params, time=t, stroke=np.array(u[0]),
        stroke_rate=np.array(u[1]), stroke_acceleration=np.array(u[2]), force=force, states=X,
        state_names=model.state_names, state_units=model.state_units, p1=p1, p2=p2,
        mass_error=mass_error, status="completed",
        message=f"driven by the recorded stroke over {t[-1] - t[0]:.4g} s",
        warnings=tuple(warn))


# ---------------------------------------------------------------------------
# error measures and the noise floor


def nrmse(model_force, measured_force) -> float:
    """RMS(model - measured) / RMS(measured - mean(measured)) [-], pooled over sequences.

    Give arrays or equal-length sequences of arrays (one per record of a
    set); the means are pooled over the whole set.

    Raises
    ------
    ParameterError
        If either argument holds NaN or inf (the argument, the first bad index
        of the pooled samples and the count are named), if they differ in
        length, or if the measured force is constant.

    Examples
    --------
    >>> nrmse(np.array([1.0, -1.0]), np.array([2.0, -2.0]))
    0.5
    """
    from liquidamp.analysis.harmonics import check_samples

    m = np.concatenate([np.ravel(a) for a in _as_list(model_force)])
    d = np.concatenate([np.ravel(a) for a in _as_list(measured_force)])
    m = check_samples("model_force", m, "N", where="nrmse")
    d = check_samples("measured_force", d, "N", where="nrmse")
    if m.shape != d.shape:
        raise ParameterError(f"nrmse: model has {m.size} samples, measurement {d.size}")
    den = float(np.sqrt(np.mean((d - d.mean()) ** 2)))
    if den == 0:
        raise ParameterError("nrmse: the measured force is constant")
    return float(np.sqrt(np.mean((m - d) ** 2)) / den)


def _as_list(x):
    if isinstance(x, np.ndarray) and x.ndim == 1:
        return [x]
    return list(x)


@dataclass(frozen=True)
class NoiseFloor:
    """Noise estimated from a record.

    Attributes
    ----------
    force_std : float
        Standard deviation of the load-cell noise [N].
    displacement_std : float
        Standard deviation of the LVDT noise [m].
    nrmse : float
        The NRMSE a perfect model would reach against this force noise [-].
    """

    force_std: float
    displacement_std: float
    nrmse: float


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


def noise_floor(record: Record) -> NoiseFloor:
    """Estimate the force and displacement noise of a record from its high-frequency content.

    The first 12 harmonics of the excitation are removed by least squares;
    the median absolute deviation of the 4th differences of what is left
    (variance 70 sigma^2 for white noise) is robust to the few samples
    around friction jumps.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> t = np.arange(0, 3.0, 0.005)
    >>> F = 500 * np.sin(2 * np.pi * 3 * t) + rng.normal(0, 2.0, t.size)
    >>> rec = Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), F)
    >>> bool(abs(noise_floor(rec).force_std / 2.0 - 1) < 0.1)
    True
    """
    t = record.time
    fs = _hf_std(t, record.force, record.frequency)
    ys = _hf_std(t, record.displacement, record.frequency)
    F = record.force
    return NoiseFloor(force_std=fs, displacement_std=ys,
                      nrmse=fs / float(np.sqrt(np.mean((F - F.mean()) ** 2))))


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
    more than max(k * 1.4826 * MAD, frac * first-harmonic amplitude) is a spike;
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
        thr = max(k * sigma, floor)
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
      deviation of those departures over the record) and by more than 2 %
      of the signal's first-harmonic amplitude is an outlier.  A running
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
        Nothing is raised here; :func:`liquidamp.analysis.calibration.calibrate`
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
