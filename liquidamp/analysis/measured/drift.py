"""Non-stationarity of a record: does the force's cycle drift over the record?

A device that warms as it works (its oil thinning), a gas charge that settles, a rig that
creeps: the force of a steady stroke then changes steadily from cycle to cycle.  No model of a
stationary device can follow it, and the cycle-to-cycle scatter that measures the noise floor
(:func:`~liquidamp.analysis.measured.record_quality.noise_floor`) takes it for noise.
:func:`record_drift` tests for it and says how large it is (:class:`Drift`):

* **Periodic stroke** (at least :data:`MIN_SEGMENTS` whole cycles): each whole cycle's force
  is fitted by least squares with a constant and its first three harmonics (those below
  0.8 x Nyquist); the first-harmonic amplitude |F1|_c and the mean M_c of each cycle c are
  the two series tested.
* **Broadband stroke** (no cycle to compare): the record is cut into
  :data:`MIN_SEGMENTS` to 20 windows of at least one period of the centre of its band
  (the geometric mean of the frequencies below which 5 % and 95 % of its power lie); the
  force is regressed once on the stroke, its rate and acceleration over the whole record
  (F ~ F0 + k y + c v + m a); in each window the gain of that fitted force (least squares of
  the window's force on it) stands for the amplitude and the window's mean residual for
  the mean.
  Not tested where the excitation itself changes: where the RMS of the stroke or of its
  rate over the same windows has a monotone trend (the Mann-Kendall test [3]_ at ``alpha``,
  a change of at least :data:`MIN_CHANGE` as below) (a dyno's test programme of
  several speeds in sequence, a sine sweep), the force's trend is the device's amplitude
  and rate dependence as much as a drift, as for a tapered stroke.
* **Tapered stroke**: not tested (the stroke amplitude changes by design, and a device's
  own amplitude dependence cannot be told from a drift without a model).

**Rule** (trend against the cycle-to-cycle scatter).  Each series is regressed on the
cycle (window) index, s = a + b c; b is significant when its t statistic b / se(b),
se(b) from the scatter about the line (Student t with N - 2 degrees of freedom), has a
two-sided p-value below ``alpha`` (default 1e-3 for each series).  A significant trend is a
drift when it matters: the change over the record, b (N - 1), is at least
:data:`MIN_CHANGE` (1 %) of the mean first-harmonic amplitude (a trend of 0.1 % in a
record of 200 Hz load-cell noise is significant and irrelevant).  Scatter about the line
that is not white (a drift that curves) only widens se(b): the test stays conservative.

The drift's shape for the noise floor: Legendre polynomials in time of the degree that
minimizes the BIC of the two series (at most :data:`MAX_DEGREE`); the noise floor removes
the force's harmonics modulated by them (:func:`drift_columns`).

References
----------
.. [1] N. R. Draper, H. Smith, Applied Regression Analysis, 3rd ed., Wiley, 1998, Sec. 3
   (the t test of a regression slope).
.. [2] J. S. Bendat, A. G. Piersol, Random Data, 4th ed., Wiley, 2010, Sec. 4.5
   (tests for stationarity of a record from its segment statistics).
.. [3] H. B. Mann, Econometrica 13(3), 245-259, 1945; M. G. Kendall, Rank Correlation
   Methods, 4th ed., Griffin, 1975 (the rank test of a monotone trend).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Drift", "record_drift", "drift_columns", "regressors", "MIN_SEGMENTS",
           "MIN_CHANGE", "ALPHA", "MAX_DEGREE"]

#: Least whole cycles (windows) for the drift test [-].
MIN_SEGMENTS = 6
#: Least change over the record of a significant trend, as a share of the mean
#: first-harmonic force amplitude, for the record to be non-stationary [-].
MIN_CHANGE = 0.01
#: Two-sided significance level of each series' trend [-].
ALPHA = 1e-3
#: Highest degree of the drift's polynomial in time [-].
MAX_DEGREE = 6


@dataclass(frozen=True)
class Drift:
    """What :func:`record_drift` found.

    Attributes
    ----------
    tested : bool
        Whether the record could be tested (``reason`` says why not).
    nonstationary : bool
        True when the force's first-harmonic amplitude or its mean drifts (module rule).
    method : str
        ``"cycles"`` (periodic stroke), ``"windows"`` (broadband) or ``"not tested"``.
    segments : int
        Whole cycles (windows) tested [-].
    amplitude_trend : float
        Trend of the first-harmonic force amplitude per cycle (window), as a share of its
        mean, in percent [%/cycle].
    amplitude_t, amplitude_p : float
        Its t statistic [-] and two-sided p-value [-].
    amplitude_change : float
        Change of the amplitude over the record on the fitted line, first to last cycle,
        as a share of its mean [-] (-0.05: it fades by 5 %).
    mean_trend : float
        Trend of the force's mean per cycle (window) [N/cycle].
    mean_t, mean_p : float
        Its t statistic [-] and two-sided p-value [-].
    mean_change : float
        Change of the mean over the record on the fitted line [N].
    amplitude : float
        Mean first-harmonic force amplitude [N] (windows: sqrt(2) x the RMS of the
        fitted force).
    degree : int
        Degree of the drift's polynomial in time used by the noise floor (0: none) [-].
    series : dict
        ``{"amplitude [N]": [...], "mean [N]": [...]}`` per cycle (window).
    alpha : float
        Significance level used [-].
    reason : str
        One sentence: the verdict and its figures, or why the record was not tested.
    """

    tested: bool
    nonstationary: bool
    method: str
    segments: int = 0
    amplitude_trend: float = 0.0
    amplitude_t: float = 0.0
    amplitude_p: float = 1.0
    amplitude_change: float = 0.0
    mean_trend: float = 0.0
    mean_t: float = 0.0
    mean_p: float = 1.0
    mean_change: float = 0.0
    amplitude: float = 0.0
    degree: int = 0
    series: dict | None = None
    alpha: float = ALPHA
    reason: str = ""
    source: str = ""
    span: float = 0.0
    noise_std: float = 0.0

    @property
    def non_stationary(self) -> bool:
        """Alias of :attr:`nonstationary` (the name of the former ``stationarity.Drift``)."""
        return self.nonstationary

    @property
    def relative_change(self) -> float:
        """Change of the first-harmonic amplitude over the record's whole span on the fitted
        line, as a share of its mean [-] (``span`` cycles or windows; without it, first to
        last whole cycle: :attr:`amplitude_change`)."""
        if self.span > 0:
            return self.amplitude_trend / 100.0 * self.span
        return self.amplitude_change

    def describe(self) -> str:
        """One phrase, e.g. ``"a.csv: first-harmonic force -18.7 % over 30 cycles"``."""
        unit = "cycles" if self.method == "cycles" else "windows"
        return (f"{self.source}: first-harmonic force {self.relative_change:+.1%} "
                f"({self.relative_change * self.amplitude:+.3g} N), mean force "
                f"{self.mean_change:+.3g} N over {self.segments} {unit}")

    def as_dict(self) -> dict:
        """JSON-ready summary (units in the keys)."""
        return {"record": self.source, "non_stationary": self.nonstationary,
                "relative_amplitude_change": self.relative_change,
                "noise_std [N]": self.noise_std,
                "tested": self.tested, "nonstationary": self.nonstationary,
                "method": self.method, "segments": self.segments,
                "amplitude_trend [%/cycle]": self.amplitude_trend,
                "amplitude_t": self.amplitude_t, "amplitude_p": self.amplitude_p,
                "amplitude_change": self.amplitude_change,
                "mean_trend [N/cycle]": self.mean_trend, "mean_t": self.mean_t,
                "mean_p": self.mean_p, "mean_change [N]": self.mean_change,
                "amplitude [N]": self.amplitude, "degree": self.degree, "alpha": self.alpha,
                "series": dict(self.series or {}), "reason": self.reason}



def regressors(record) -> np.ndarray:
    """Columns of the linear-device regression F ~ F0 + k y + c v + m a, scaled to unit RMS.

    Parameters
    ----------
    record : Record
        A record (its smoothed stroke about its offset [m], velocity [m/s], acceleration
        [m/s^2]).

    Returns
    -------
    ndarray, shape (n, 4)
        Constant, stroke, rate and acceleration columns [-]; index 2 is the rate.
    """
    cols = [np.ones_like(record.time)]
    for q in (record.smoothed - record.offset, record.velocity, record.acceleration):
        sd = float(np.std(q))
        cols.append((q - float(np.mean(q))) / sd if sd > 0 else np.zeros_like(q))
    return np.column_stack(cols)


def _trend(s):
    """(slope, t, two-sided p) of the least-squares line through s against 0..N-1."""
    from scipy.stats import t as student

    s = np.asarray(s, float)
    n = s.size
    c = np.arange(n) - 0.5 * (n - 1)
    sxx = float(c @ c)
    b = float(c @ (s - s.mean())) / sxx
    res = s - s.mean() - b * c
    s2 = float(res @ res) / (n - 2)
    se = math.sqrt(s2 / sxx)
    if se == 0.0:
        return b, (math.inf if b else 0.0), (0.0 if b else 1.0)
    tt = b / se
    return b, tt, float(2.0 * student.sf(abs(tt), n - 2))


def _degree(series, n):
    """Legendre degree (1..MAX_DEGREE) minimizing the summed BIC of the normalized series."""
    x = np.linspace(-1.0, 1.0, n)
    best, deg = math.inf, 1
    for d in range(1, min(MAX_DEGREE, n // 3) + 1):
        V = np.polynomial.legendre.legvander(x, d)
        bic = 0.0
        for s in series:
            c, *_ = np.linalg.lstsq(V, s, rcond=None)
            r = s - V @ c
            rss = max(float(r @ r), 1e-300 * max(float(s @ s), 1e-300))
            bic += n * math.log(rss / n) + (d + 1) * math.log(n)
        if bic < best - 1e-9:
            best, deg = bic, d
    return deg


def _cycles(record):
    """Per whole cycle: (first-harmonic force amplitude [N], mean force [N]), and the mean
    samples per cycle [-]."""
    t = record.time - record.time[0]
    f = record.frequency
    T = 1.0 / f
    dt = 1.0 / record.sampling_rate
    n_cyc = int(math.floor((t[-1] + dt) / T + 1e-9))
    w = 2 * math.pi * f
    nyq = 0.5 * record.sampling_rate
    amps, means, counts = [], [], []
    for c in range(n_cyc):
        m = (t >= c * T - 0.5 * dt) & (t < (c + 1) * T - 0.5 * dt)
        if m.sum() < 8:
            continue
        tc = t[m]
        cols = [np.ones_like(tc)]
        for k in range(1, 4):
            if k == 1 or k * f < 0.8 * nyq:
                cols += [np.sin(k * w * tc), np.cos(k * w * tc)]
        coef, *_ = np.linalg.lstsq(np.column_stack(cols), record.force[m], rcond=None)
        amps.append(math.hypot(coef[1], coef[2]))
        means.append(float(coef[0]))
        counts.append(int(m.sum()))
    return np.array(amps), np.array(means), (float(np.mean(counts)) if counts else 0.0)


def _windows(record):
    """Per window of a broadband record: (gain x amplitude [N], mean residual [N])."""

    n = record.time.size
    span = record.time[-1] - record.time[0]
    lo, hi = record.shape.band if record.shape is not None else (0.0, 0.0)
    fc = math.sqrt(lo * hi) if lo > 0 else record.frequency
    W = int(min(20, math.floor(span * fc)))
    if W < MIN_SEGMENTS:
        return None, None
    X = regressors(record)
    coef, *_ = np.linalg.lstsq(X, record.force, rcond=None)
    fit = X @ coef
    amp = math.sqrt(2.0) * float(np.std(fit))
    gains, means = [], []
    for idx in np.array_split(np.arange(n), W):
        g = fit[idx] - fit[idx].mean()
        F = record.force[idx]
        gg = float(g @ g)
        gains.append(float(g @ (F - F.mean())) / gg if gg > 0 else 1.0)
        means.append(float(np.mean(F - fit[idx])))
    return amp * np.array(gains), np.array(means)


def _excitation_trend(record, n: int, alpha: float, min_change: float) -> str:
    """Where the stroke's or its rate's RMS over the ``n`` windows of :func:`_windows` has a
    monotone trend (Mann-Kendall: Kendall's tau of the RMS against the window index, two-sided
    p < ``alpha``; a programme's speeds rise in steps, which a straight line fits badly) whose
    change over the record on the least-squares line is at least ``min_change`` of its mean
    (the rule the force is held to), the figures ('' otherwise)."""
    from scipy.stats import kendalltau

    if n < MIN_SEGMENTS:
        return ""
    out = []
    for name, x in (("stroke", record.displacement - np.mean(record.displacement)),
                    ("stroke rate", record.velocity)):
        rms = np.array([math.sqrt(float(np.mean(x[i] ** 2)))
                        for i in np.array_split(np.arange(x.size), n)])
        m = float(np.mean(rms))
        if not m > 0:
            continue
        b, _, _ = _trend(rms)
        change = b * (n - 1) / m
        tau, pp = kendalltau(np.arange(n), rms)
        if pp < alpha and abs(change) >= min_change:
            out.append(f"{name} RMS {100 * change:+.3g} % over {n} windows, Kendall tau "
                       f"{tau:.2g}, p = {pp:.2g}")
    return "; ".join(out)


def record_drift(record, alpha: float = ALPHA, min_change: float = MIN_CHANGE) -> Drift:
    """Test a record for a force that drifts over the record (module docstring).

    Parameters
    ----------
    record : Record
        The record (as read, or conditioned but not averaged).
    alpha : float
        Two-sided significance level of each series' trend [-].
    min_change : float
        Least change over the record, as a share of the mean first-harmonic amplitude [-].

    Returns
    -------
    Drift

    Examples
    --------
    >>> from liquidamp.analysis.measured.records import Record
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(0, 10.0, 0.005)                    # 30 cycles at 3 Hz, 200 Hz
    >>> y = 0.003 * np.sin(2 * np.pi * 3 * t)
    >>> fade = 1.0 - 0.05 * t / 10.0                     # the force fades 5 % over the record
    >>> F = fade * 500 * np.cos(2 * np.pi * 3 * t) + rng.normal(0, 1.5, t.size)
    >>> d = record_drift(Record.from_arrays(t, y, F))
    >>> d.nonstationary, round(d.amplitude_change, 3), d.segments
    (True, -0.048, 29)
    >>> record_drift(Record.from_arrays(t, y, 500 * np.cos(2 * np.pi * 3 * t)
    ...                                 + rng.normal(0, 1.5, t.size))).nonstationary
    False
    """
    kind = "periodic" if record.periodic else record.shape.kind
    if kind == "tapered":
        return Drift(False, False, "not tested", reason=(
            "not tested: the stroke amplitude changes by design (tapered), so a drift of the "
            "device cannot be told from its amplitude dependence without a model"))
    if kind == "periodic":
        amps, means, counts = _cycles(record)
        method, unit = "cycles", "cycle"
    else:
        amps, means = _windows(record)
        method, unit = "windows", "window"
        counts = record.time.size / amps.size if amps is not None and amps.size else 0.0
        changed = _excitation_trend(record, amps.size if amps is not None else 0, alpha,
                                    min_change)
        if changed:
            return Drift(False, False, "not tested", segments=amps.size, reason=(
                f"not tested: the excitation itself changes over the record ({changed}: a "
                "test programme or a sweep), so a drift of the device cannot be told from "
                "its amplitude and rate dependence without a model"))
    if amps is None or amps.size < MIN_SEGMENTS:
        got = 0 if amps is None else amps.size
        return Drift(False, False, "not tested", segments=got, reason=(
            f"not tested: {got} whole {unit}s, at least {MIN_SEGMENTS} needed to tell a "
            "trend from the scatter"))
    n = amps.size
    A = float(np.mean(amps))
    ba, ta, pa = _trend(amps)
    bm, tm, pm = _trend(means)
    ca = ba * (n - 1) / A if A > 0 else 0.0
    cm = bm * (n - 1)
    drift_a = pa < alpha and abs(ca) >= min_change
    drift_m = pm < alpha and abs(cm) >= min_change * A
    nonstat = bool(drift_a or drift_m)
    deg = _degree([amps / A, means / A], n) if nonstat and A > 0 else 0
    pct = 100.0 * ba / A if A > 0 else 0.0
    what = ("first-harmonic force amplitude" if method == "cycles" else
            "force amplitude (gain on the linear-device regression)")
    figures = (f"{what} {pct:+.3g} %/{unit} ({100 * ca:+.3g} % over "
               f"{n} {unit}s, t = {ta:.3g}, p = {pa:.2g}); mean force {bm:+.3g} N/{unit} "
               f"({cm:+.4g} N, t = {tm:.3g}, p = {pm:.2g})")
    if nonstat:
        which = " and ".join(w for w, on in (("amplitude", drift_a), ("mean", drift_m)) if on)
        reason = (f"non-stationary: the force's {which} drifts over the record: {figures}; "
                  f"the drift (degree {deg} in time) is kept out of the noise floor")
    else:
        reason = (f"stationary: no trend both significant (p < {alpha:g}) and at least "
                  f"{min_change:.0%} of the amplitude over the record: {figures}")
    # the per-sample force noise about the trend: a cycle's amplitude from n samples has
    # standard error sigma sqrt(2 / n), its mean sigma / sqrt(n)
    sa = _scatter(amps, deg if nonstat else 1)
    sm = _scatter(means, deg if nonstat else 1)
    sigma = min(sa * math.sqrt(counts / 2.0), sm * math.sqrt(counts)) if counts else 0.0
    span = ((record.time[-1] - record.time[0]) * record.frequency if method == "cycles"
            else float(n))
    return Drift(True, nonstat, method, segments=n, amplitude_trend=float(pct),
                 amplitude_t=float(ta), amplitude_p=float(pa), amplitude_change=float(ca),
                 mean_trend=float(bm), mean_t=float(tm), mean_p=float(pm),
                 mean_change=float(cm), amplitude=A, degree=deg,
                 series={"amplitude [N]": [float(a) for a in amps],
                         "mean [N]": [float(m) for m in means]},
                 alpha=float(alpha), reason=reason, source=getattr(record, "label", ""),
                 span=float(span), noise_std=float(sigma))


def _scatter(s, degree: int) -> float:
    """Standard deviation of the series ``s`` about its Legendre fit of ``degree`` [unit]."""
    n = s.size
    V = np.polynomial.legendre.legvander(np.linspace(-1.0, 1.0, n), max(degree, 1))
    c, *_ = np.linalg.lstsq(V, s, rcond=None)
    r = s - V @ c
    return math.sqrt(float(r @ r) / max(n - V.shape[1], 1))


def drift_columns(A, t, degree: int):
    """The columns of ``A`` modulated by Legendre polynomials P_1..P_degree of time.

    A drift of every column's coefficient, smooth in time, is then fitted with them: the
    noise floor of a drifting record removes it instead of counting it as noise.

    Parameters
    ----------
    A : ndarray (n, m)
        Columns to modulate (a constant and harmonics of the stroke frequency).
    t : array (n,)
        Sample times [s].
    degree : int
        Highest polynomial degree [-].
    """
    t = np.asarray(t, float)
    tau = 2.0 * (t - t[0]) / (t[-1] - t[0]) - 1.0
    V = np.polynomial.legendre.legvander(tau, degree)[:, 1:]
    return np.concatenate([A * V[:, j:j + 1] for j in range(degree)], axis=1)
