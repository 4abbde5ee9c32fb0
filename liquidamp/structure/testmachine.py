"""The test machine: a host that prescribes the device stroke.

A stroke is a callable ``stroke(t) -> (y, v, a)`` returning the piston
displacement [m], velocity [m/s] and acceleration [m/s^2].  The harmonic
stroke is the paper's ``y = Y sin(2 pi f t)`` (Sec. IV.B); the two-frequency
stroke adds a second sinusoid (a lag damper in forward flight moves at the
rotor's 1/rev frequency and at the lag frequency at once); a recorded stroke
interpolates a measured LVDT signal whose rate and acceleration come from a
Savitzky-Golay filter, as in the paper (21 points, 4th order).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B.
.. [2] A. Savitzky, M. J. E. Golay, Anal. Chem. 36(8), 1964.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from liquidamp.errors import ParameterError, check_finite, check_positive

__all__ = ["HarmonicStroke", "TwoFrequencyStroke", "FourierStroke", "RecordedStroke",
           "savgol_derivatives",
           "MAX_COMMON_MULTIPLE"]

#: Largest multiple of either frequency's period a common period may be: two frequencies
#: whose ratio is a / b in lowest terms with a, b <= this are commensurate
#: (:attr:`TwoFrequencyStroke.common_period`).
MAX_COMMON_MULTIPLE = 100

#: Highest stroke frequency of a lumped device model [Hz].
_MAX_FREQUENCY = 1.0e4


@dataclass(frozen=True)
class HarmonicStroke:
    """Harmonic stroke y(t) = offset + Y sin(2 pi f t + phase).

    Parameters
    ----------
    amplitude : float
        Y > 0 [m].
    frequency : float
        f > 0 [Hz] (the only Hz quantity inside: it is the test machine's dial).
    offset : float
        Mean stroke [m].
    phase : float
        Phase [rad].

    Examples
    --------
    >>> s = HarmonicStroke(0.003, 3.0)
    >>> y, v, a = s(0.0)
    >>> y, round(v, 6)
    (0.0, 0.056549)
    """

    amplitude: float
    frequency: float
    offset: float = 0.0
    phase: float = 0.0

    def __post_init__(self) -> None:
        check_positive("stroke amplitude", self.amplitude, "m")
        _check_frequency("stroke frequency", self.frequency)
        check_finite("stroke offset", self.offset, "m")
        check_finite("stroke phase", self.phase, "rad")

    @property
    def omega(self) -> float:
        """Circular frequency [rad/s]."""
        return 2.0 * math.pi * self.frequency

    @property
    def period(self) -> float:
        """Period 1/f [s]."""
        return 1.0 / self.frequency

    @property
    def max_abs(self) -> float:
        """Largest |y| reached [m]."""
        return abs(self.offset) + self.amplitude

    def describe(self) -> str:
        """The stroke in a few words, for messages.

        Examples
        --------
        >>> HarmonicStroke(0.003, 3.0).describe()
        '3 Hz, 0.003 m'
        """
        return f"{self.frequency:g} Hz, {self.amplitude:g} m"

    def __call__(self, t):
        """Stroke, rate and acceleration at time ``t`` [s] (scalar or array)."""
        w = self.omega
        if np.ndim(t):
            s, c = np.sin(w * t + self.phase), np.cos(w * t + self.phase)
        else:
            s, c = math.sin(w * t + self.phase), math.cos(w * t + self.phase)
        Y = self.amplitude
        return self.offset + Y * s, Y * w * c, -Y * w * w * s


def _check_frequency(name: str, value) -> float:
    f = check_positive(name, value, "Hz")
    if f > _MAX_FREQUENCY:
        raise ParameterError(
            f"{name} must lie in (0, 1e4] [Hz] for a lumped device model, got {f:g}")
    return f


@dataclass(frozen=True)
class TwoFrequencyStroke:
    """Two-frequency stroke y(t) = offset + Y1 sin(2 pi f1 t + phase1) + Y2 sin(2 pi f2 t + phase2).

    A lag damper in forward flight: a large motion at the rotor's 1/rev
    frequency (``amplitude1``, ``frequency1``) and a small one at the lag
    frequency (``amplitude2``, ``frequency2``).  Both engines run it (the
    compiled one evaluates it analytically, like :class:`HarmonicStroke`).
    Where the frequency ratio is rational, f1 / f2 = a / b in lowest terms
    with a, b <= :data:`MAX_COMMON_MULTIPLE`, the stroke is periodic with the
    common period a / f1 = b / f2 (:attr:`common_period`), and
    :func:`liquidamp.coupled.testrig.steady_state` finds its periodic steady
    state over that period.

    Parameters
    ----------
    amplitude1, amplitude2 : float
        Y1, Y2 >= 0 [m], not both 0.
    frequency1, frequency2 : float
        f1, f2 in (0, 1e4] [Hz].
    offset : float
        Mean stroke [m].
    phase1, phase2 : float
        Phases [rad].

    Examples
    --------
    >>> s = TwoFrequencyStroke(0.002, 4.2, 0.0005, 1.26)
    >>> round(s.common_period, 12), s.max_abs          # 4.2 / 1.26 = 10 / 3
    (2.380952380952, 0.0025)
    >>> y, v, a = s(0.0)
    >>> y, round(v, 6)                                 # 2 pi (4.2 x 2 + 1.26 x 0.5) mm/s
    (0.0, 0.056737)
    >>> TwoFrequencyStroke(0.002, 4.2, 0.0005, 4.2 / math.sqrt(2)).common_period is None
    True
    """

    amplitude1: float
    frequency1: float
    amplitude2: float
    frequency2: float
    offset: float = 0.0
    phase1: float = 0.0
    phase2: float = 0.0

    def __post_init__(self) -> None:
        a1 = check_finite("stroke amplitude1", self.amplitude1, "m")
        a2 = check_finite("stroke amplitude2", self.amplitude2, "m")
        if a1 < 0.0 or a2 < 0.0 or a1 + a2 <= 0.0:
            raise ParameterError(
                f"two-frequency stroke amplitudes must be >= 0 [m] and not both 0, got "
                f"amplitude1 = {a1:g}, amplitude2 = {a2:g}")
        _check_frequency("stroke frequency1", self.frequency1)
        _check_frequency("stroke frequency2", self.frequency2)
        check_finite("stroke offset", self.offset, "m")
        check_finite("stroke phase1", self.phase1, "rad")
        check_finite("stroke phase2", self.phase2, "rad")

    @property
    def omega1(self) -> float:
        """Circular frequency of the first component [rad/s]."""
        return 2.0 * math.pi * self.frequency1

    @property
    def omega2(self) -> float:
        """Circular frequency of the second component [rad/s]."""
        return 2.0 * math.pi * self.frequency2

    @property
    def max_abs(self) -> float:
        """Largest |y| the stroke can reach, |offset| + Y1 + Y2 [m]."""
        return abs(self.offset) + self.amplitude1 + self.amplitude2

    @property
    def ratio(self) -> tuple[int, int] | None:
        """(a, b) with f1 / f2 = a / b in lowest terms, both <= :data:`MAX_COMMON_MULTIPLE`,
        to 1e-9 relative; None where the frequencies are incommensurate in that sense."""
        from fractions import Fraction

        r = self.frequency1 / self.frequency2
        q = Fraction(r).limit_denominator(MAX_COMMON_MULTIPLE)
        a, b = q.numerator, q.denominator
        if a < 1 or a > MAX_COMMON_MULTIPLE or abs(a / b - r) > 1e-9 * r:
            return None
        return a, b

    @property
    def common_period(self) -> float | None:
        """Common period a / f1 = b / f2 [s] (:attr:`ratio`), or None if incommensurate."""
        ab = self.ratio
        return None if ab is None else ab[0] / self.frequency1

    @property
    def period(self) -> float:
        """The common period [s]; raises ParameterError where there is none.

        Raises
        ------
        ParameterError
            Naming the frequencies, where f1 / f2 is not a / b with a, b <=
            :data:`MAX_COMMON_MULTIPLE`.
        """
        T = self.common_period
        if T is None:
            raise ParameterError(
                f"two-frequency stroke at {self.frequency1:g} Hz and {self.frequency2:g} Hz has "
                f"no common period: their ratio is not a / b with a, b <= "
                f"{MAX_COMMON_MULTIPLE}; allowed: commensurate frequencies (e.g. 4.2 Hz and "
                "1.26 Hz, ratio 10/3)")
        return T

    @property
    def frequency(self) -> float:
        """Fundamental frequency of the common period 1 / :attr:`period` [Hz]."""
        return 1.0 / self.period

    @property
    def shortest_period(self) -> float:
        """Period of the faster component 1 / max(f1, f2) [s] (sizes the largest time step)."""
        return 1.0 / max(self.frequency1, self.frequency2)

    def describe(self) -> str:
        """The stroke in a few words, for messages.

        Examples
        --------
        >>> TwoFrequencyStroke(0.002, 4.2, 0.0005, 1.26).describe()
        '0.002 m at 4.2 Hz + 0.0005 m at 1.26 Hz'
        """
        return (f"{self.amplitude1:g} m at {self.frequency1:g} Hz + {self.amplitude2:g} m at "
                f"{self.frequency2:g} Hz")

    def __call__(self, t):
        """Stroke, rate and acceleration at time ``t`` [s] (scalar or array)."""
        trig = (np.sin, np.cos) if np.ndim(t) else (math.sin, math.cos)
        y, v, a = self.offset, 0.0, 0.0
        for Y, w, ph in ((self.amplitude1, self.omega1, self.phase1),
                         (self.amplitude2, self.omega2, self.phase2)):
            s, c = trig[0](w * t + ph), trig[1](w * t + ph)
            y = y + Y * s
            v = v + Y * w * c
            a = a - Y * w * w * s
        return y, v, a


#: Samples from which :meth:`FourierStroke.fit` solves by power-sum normal equations
#: (:func:`_harmonic_normal_fit`) instead of the SVD: a long record (a 3 kHz, 20 s record is
#: 60 000 samples, its SVD seconds).  Below it the SVD as before: the diagnosis's answers
#: on short records move with the stroke's last digits (runs/s8_speed/README.md).
#: Highest harmonic frequency a record's Fourier fit tests, as a fraction of its sampling
#: rate [-]: below the Nyquist frequency 0.5 fs by the anti-alias filter's roll-off.
HARMONIC_RATE_FRACTION = 0.45


def harmonics_tested(sampling_rate: float, frequency: float, max_harmonics: int = 64) -> int:
    """How many harmonics of ``frequency`` a record's Fourier fit tests [-].

    Harmonics k f up to :data:`HARMONIC_RATE_FRACTION` x the sampling rate, at most
    ``max_harmonics``; 0 where even the fundamental lies above that (the one rule of
    :meth:`FourierStroke.fit`, the records' stroke series and their noise floors).

    Parameters
    ----------
    sampling_rate : float
        Samples per second [Hz].
    frequency : float
        Fundamental [Hz].
    max_harmonics : int
        Cap [-].

    Returns
    -------
    int
        ``min(floor(0.45 fs / f), max_harmonics)`` [-].

    Examples
    --------
    >>> harmonics_tested(200.0, 3.5), harmonics_tested(2000.0, 3.5), harmonics_tested(5.0, 3.0)
    (25, 64, 0)
    """
    return min(int(HARMONIC_RATE_FRACTION * sampling_rate / frequency), int(max_harmonics))


_NORMAL_FIT_SAMPLES = 20000


def _harmonic_normal_fit(w, ks, y):
    """Least squares of ``y`` on ``[1, sin k w, cos k w for k in ks]`` by the normal
    equations built from power sums, without the design matrix; None where they are
    ill conditioned (the caller then solves by the SVD).

    With E = exp(i w) per sample, the Gram matrix needs only S_m = sum E^m
    (m = 0..2 max ks: sin j w sin k w = (cos (j-k) w - cos (j+k) w) / 2 and the like)
    and the right-hand side sum y E^k, O(N K) operations and no BLAS product of the
    long N x (2K + 1) matrix (whose threads crowd a loaded machine); the residual is
    formed explicitly (Horner in E), not from the normal equations, so that its sum of
    squares keeps its digits.  Returns ``(c, rss, rank)`` as the SVD route does.
    """
    n = y.size
    K = max(ks)
    m = 2 * len(ks) + 1
    if n < 4 * m:
        return None
    E = np.exp(1j * w)
    S = np.empty(2 * K + 1, complex)
    Y = np.empty(K + 1, complex)
    S[0] = n
    Y[0] = y.sum()
    p = np.ones(n, complex)
    for j in range(1, 2 * K + 1):
        p *= E
        S[j] = p.sum()
        if j <= K:
            Y[j] = complex(p.real @ y, p.imag @ y)

    def sc(j):  # (sum sin j w, sum cos j w) for any integer j
        return (S[j].imag, S[j].real) if j >= 0 else (-S[-j].imag, S[-j].real)

    G = np.empty((m, m))
    b = np.empty(m)
    G[0, 0], b[0] = n, Y[0].real
    for a, j in enumerate(ks):
        sj, cj = sc(j)
        G[0, 2 * a + 1] = G[2 * a + 1, 0] = sj
        G[0, 2 * a + 2] = G[2 * a + 2, 0] = cj
        b[2 * a + 1], b[2 * a + 2] = Y[j].imag, Y[j].real
        for q, k in enumerate(ks):
            sm, cm = sc(j - k)
            sp, cp = sc(j + k)
            G[2 * a + 1, 2 * q + 1] = 0.5 * (cm - cp)  # sin j sin k
            G[2 * a + 2, 2 * q + 2] = 0.5 * (cm + cp)  # cos j cos k
            G[2 * a + 1, 2 * q + 2] = 0.5 * (sp + sm)  # sin j cos k
            G[2 * q + 2, 2 * a + 1] = 0.5 * (sp + sm)
    d = np.sqrt(np.diag(G))
    if not np.all(d > 0.0):
        return None
    Gs = G / np.outer(d, d)
    ev = np.linalg.eigvalsh(Gs)
    if not ev[0] > 1e-6 * ev[-1]:
        return None
    c = np.linalg.solve(Gs, b / d) / d
    a_k = np.zeros(K + 1, complex)  # c_k - i s_k: sum Re(a_k E^k) is the series
    for q, k in enumerate(ks):
        a_k[k] = c[2 * q + 2] - 1j * c[2 * q + 1]
    acc = np.full(n, a_k[K])
    for k in range(K - 1, 0, -1):
        acc = acc * E + a_k[k]
    r = y - c[0] - (acc * E).real
    return c, float(r @ r), m


@dataclass(frozen=True, eq=False)
class FourierStroke:
    """Periodic stroke given by its Fourier series: displacement, velocity and acceleration exact.

    y(t) = offset + sum_k [s_k sin(k w (t - t0)) + c_k cos(k w (t - t0))], k = 1..K,
    w = 2 pi f; v and a are the series' exact derivatives (no filter gain, no
    interpolation).  A periodic record's stroke drives a model through it
    (:func:`liquidamp.analysis.measured.record_model.simulate_record`).

    Parameters
    ----------
    frequency : float
        Fundamental f > 0 [Hz].
    sine, cosine : array
        s_k and c_k [m] for k = 1..K (equal lengths, K >= 1, finite).
    offset : float
        Mean stroke [m].
    t0 : float
        Time origin of the series [s].

    Examples
    --------
    >>> s = FourierStroke(2.0, [0.003, 0.0], [0.0, 0.0002])
    >>> y, v, a = s(0.0)
    >>> round(y, 6), round(v / (2 * math.pi * 2.0 * 0.003), 9), s.amplitude
    (0.0002, 1.0, 0.003)
    """

    frequency: float
    sine: np.ndarray
    cosine: np.ndarray
    offset: float = 0.0
    t0: float = 0.0

    def __post_init__(self) -> None:
        _check_frequency("stroke frequency", self.frequency)
        check_finite("stroke offset", self.offset, "m")
        check_finite("stroke time origin t0", self.t0, "s")
        for name in ("sine", "cosine"):
            arr = np.array(getattr(self, name), dtype=float).ravel()
            if arr.size < 1:
                raise ParameterError(f"Fourier stroke {name} coefficients: at least one "
                                     "harmonic needed")
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise ParameterError(f"Fourier stroke {name} coefficient of harmonic "
                                     f"{bad[0] + 1} is not finite ({arr[bad[0]]!r}) [m]")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        if self.sine.size != self.cosine.size:
            raise ParameterError(f"Fourier stroke: {self.sine.size} sine and "
                                 f"{self.cosine.size} cosine coefficients; they must match")
        if not np.any(self.sine) and not np.any(self.cosine):
            raise ParameterError("Fourier stroke: every coefficient is 0 (no stroke)")

    @classmethod
    def fit(cls, time, displacement, frequency: float, *, max_harmonics: int = 64,
            threshold: float = 4.0, t0: float | None = None,
            refine_frequency: bool = False):
        """Least-squares periodic fit of a sampled stroke; the harmonics that stand out.

        Harmonics k f up to the lesser of ``max_harmonics`` and 0.45 x the sampling
        rate are fitted with the mean; those whose amplitude exceeds ``threshold``
        standard errors (sigma sqrt(2 / N), sigma the residual's standard
        deviation, N the samples) and 1e-9 of the largest are kept, the fundamental
        always.

        Parameters
        ----------
        time, displacement : array
            Uniform samples [s], [m].
        frequency : float
            Fundamental [Hz].
        max_harmonics : int
            Highest harmonic fitted [-].
        threshold : float
            Kept above this many standard errors [-].
        t0 : float, optional
            Time origin of the series [s] (default ``time[0]``).
        refine_frequency : bool
            Also fit the fundamental: the residual of the harmonics kept at
            ``frequency`` is minimized over f within 0.1 / span of it (Brent),
            then the series is fitted again at that f.  An estimate off by
            df turns the phase by 2 pi df t: over 8 cycles at 7 Hz, 3e-4 Hz
            is a force error of 0.2 % of its amplitude at the end.

        Returns
        -------
        FourierStroke
            With attribute ``rate_std`` [m/s]: the standard deviation of the kept
            harmonics' noise in the velocity, w sigma sqrt(2 / N sum k^2).

        Examples
        --------
        >>> t = np.arange(400) / 200.0
        >>> s = FourierStroke.fit(t, 0.003 * np.sin(2 * np.pi * 2 * t) + 1e-3, 2.0)
        >>> round(s.amplitude, 9), round(s.offset, 9), s.harmonics
        (0.003, 0.001, 1)
        """
        t = np.asarray(time, float)
        y = np.asarray(displacement, float)
        f = _check_frequency("stroke frequency", frequency)
        n = t.size
        if n < 4 or y.shape != t.shape:
            raise ParameterError(f"Fourier fit needs matching 1-D time and displacement of >= 4 "
                                 f"samples, got {t.shape} and {y.shape}")
        origin = float(t[0]) if t0 is None else float(t0)
        rate = (n - 1) / (t[-1] - t[0])
        H = max(1, harmonics_tested(rate, f, max_harmonics))

        def lsq(fk, ks):
            w = 2 * math.pi * fk * (t - origin)
            if n >= _NORMAL_FIT_SAMPLES:  # where the SVD would dominate the fit's cost
                quick = _harmonic_normal_fit(w, list(ks), y)
                if quick is not None:
                    return quick
            A = np.empty((n, 2 * len(ks) + 1))
            A[:, 0] = 1.0
            for j, k in enumerate(ks):
                A[:, 2 * j + 1], A[:, 2 * j + 2] = np.sin(k * w), np.cos(k * w)
            c, _, rank, _ = np.linalg.lstsq(A, y, rcond=None)
            r = y - A @ c
            return c, float(r @ r), int(rank)

        def select(fk):
            c, rss, rank = lsq(fk, range(1, H + 1))
            sigma = math.sqrt(rss / max(n - rank, 1))
            se = sigma * math.sqrt(2.0 / n)
            amp = np.hypot(c[1::2], c[2::2])
            floor = max(threshold * se, 1e-9 * float(np.max(amp)))  # 1e-9: clean round-off
            return c, se, [k for k in range(1, H + 1) if k == 1 or amp[k - 1] > floor]

        c, se, keep = select(f)
        if refine_frequency:
            from scipy.optimize import minimize_scalar

            span = (t[-1] - t[0]) * n / (n - 1)
            d = 0.1 / span
            best = minimize_scalar(lambda fk: lsq(fk, keep)[1], bounds=(f - d, f + d),
                                   method="bounded", options={"xatol": 1e-10 * f})
            if best.fun < lsq(f, keep)[1]:
                f = float(best.x)
                c, se, keep = select(f)
        K = keep[-1]
        sine, cosine = np.zeros(K), np.zeros(K)
        for k in keep:
            sine[k - 1], cosine[k - 1] = c[2 * k - 1], c[2 * k]
        out = cls(f, sine, cosine, float(c[0]), origin)
        object.__setattr__(out, "rate_std",
                           2 * math.pi * f * se * math.sqrt(sum(k * k for k in keep)))
        return out

    @property
    def omega(self) -> float:
        """Fundamental circular frequency [rad/s]."""
        return 2.0 * math.pi * self.frequency

    @property
    def period(self) -> float:
        """Period 1/f [s]."""
        return 1.0 / self.frequency

    @property
    def harmonics(self) -> int:
        """Highest harmonic K of the series [-]."""
        return int(self.sine.size)

    @property
    def amplitude(self) -> float:
        """First-harmonic amplitude hypot(s_1, c_1) [m]."""
        return float(math.hypot(self.sine[0], self.cosine[0]))

    @property
    def max_abs(self) -> float:
        """Largest |y| over a period [m] (on 64 points per highest harmonic)."""
        t = self.t0 + np.arange(64 * self.harmonics) / (64 * self.harmonics) * self.period
        return float(np.max(np.abs(self(t)[0])))

    def describe(self) -> str:
        """The stroke in a few words, for messages.

        Examples
        --------
        >>> FourierStroke(3.0, [0.003], [0.0]).describe()
        '3 Hz, 0.003 m (Fourier series of 1 harmonic(s))'
        """
        return (f"{self.frequency:g} Hz, {self.amplitude:.4g} m (Fourier series of "
                f"{self.harmonics} harmonic(s))")

    def packed(self) -> np.ndarray:
        """``[offset, w, t0, K, s_1, c_1, ..., s_K, c_K]``: the compiled engine's stroke array."""
        sc = np.column_stack((self.sine, self.cosine)).ravel()
        return np.concatenate(([self.offset, self.omega, self.t0, float(self.harmonics)], sc))

    def __call__(self, t):
        """Stroke, rate and acceleration at time ``t`` [s] (scalar or array)."""
        tt = np.asarray(t, float) - self.t0
        w = self.omega
        y = np.full(tt.shape, self.offset)
        v = np.zeros(tt.shape)
        a = np.zeros(tt.shape)
        for k in range(1, self.harmonics + 1):
            s_k, c_k = self.sine[k - 1], self.cosine[k - 1]
            if s_k == 0.0 and c_k == 0.0:
                continue
            kw = k * w
            sn, cs = np.sin(kw * tt), np.cos(kw * tt)
            y = y + s_k * sn + c_k * cs
            v = v + kw * (s_k * cs - c_k * sn)
            a = a - kw * kw * (s_k * sn + c_k * cs)
        if np.ndim(t) == 0:
            return float(y), float(v), float(a)
        return y, v, a


def savgol_derivatives(t, y, window: int = 21, order: int = 4):
    """Smoothed displacement, velocity and acceleration of a uniformly sampled record.

    Parameters
    ----------
    t : array
        Sample times, uniform spacing [s].
    y : array
        Displacement [m].
    window : int
        Savitzky-Golay window length (odd) [samples]; the paper uses 21.
    order : int
        Polynomial order; the paper uses 4.

    Returns
    -------
    y, v, a : ndarray
        Smoothed displacement [m], velocity [m/s], acceleration [m/s^2].

    Raises
    ------
    ParameterError
        If ``t`` or ``y`` holds NaN or inf (named with the first bad index
        and the count), if their shapes differ, or if the window is invalid.

    Examples
    --------
    >>> t = np.arange(400) / 200.0
    >>> y, v, a = savgol_derivatives(t, 0.002 * np.sin(2 * np.pi * 3 * t))
    >>> exact = 0.002 * 2 * np.pi * 3 * np.cos(2 * np.pi * 3 * t[200])
    >>> bool(abs(v[200] / exact - 1) < 3e-3)  # 21-point window: 0.2 % attenuation at 3 Hz
    True
    """
    from scipy.signal import savgol_filter

    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    for name, arr, unit in (("t", t, "s"), ("y", y, "m")):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise ParameterError(
                f"savgol_derivatives: {name} holds {bad.size} non-finite sample(s) of "
                f"{arr.size}, the first at index {int(bad[0])} "
                f"({float(arr.flat[bad[0]])!r}); every sample must be a finite number [{unit}]")
    if t.shape != y.shape or t.ndim != 1:
        raise ParameterError(f"savgol_derivatives: t and y must be 1-D arrays of one length, "
                             f"got shapes {t.shape} and {y.shape}")
    if window % 2 == 0 or window <= order:
        raise ParameterError(
            f"Savitzky-Golay window must be odd and > order={order}, got window={window}"
        )
    if y.size < window:
        raise ParameterError(f"record has {y.size} samples, fewer than the filter window {window}")
    dt = float(np.mean(np.diff(t)))
    ys = savgol_filter(y, window, order, deriv=0)
    v = savgol_filter(y, window, order, deriv=1, delta=dt)
    a = savgol_filter(y, window, order, deriv=2, delta=dt)
    return ys, v, a


@dataclass(frozen=True, eq=False)
class RecordedStroke:
    """A measured stroke, linearly interpolated between samples.

    Parameters
    ----------
    time : array
        Strictly increasing sample times [s].
    displacement, velocity, acceleration : array
        Samples [m], [m/s], [m/s^2] (see :func:`savgol_derivatives`).
    channels : dict, optional
        Measured input channels on the same time grid, name -> samples in SI (e.g.
        ``{"voltage": volts}``), for a device model that reads them (issue #20; the
        engines interpolate them linearly between the samples, as the stroke, and pass
        them to the model at every stage: :class:`liquidamp.device.effects_base.Effect`).

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 201)
    >>> s = RecordedStroke.from_displacement(t, 0.001 * np.sin(2 * np.pi * 2 * t))
    >>> round(float(s(0.125)[0]), 6)
    0.001
    >>> s = RecordedStroke(t, 0 * t, 0 * t, 0 * t, channels={"voltage": 2 * t})
    >>> float(s.channel_values(0.25)["voltage"])
    0.5
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    channels: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        chans = {}
        n_t = np.size(self.time)
        for name, arr in dict(self.channels).items():
            a = np.array(arr, dtype=float)
            if a.shape != (n_t,):
                raise ParameterError(f"recorded stroke channel {name!r} must hold one sample "
                                     f"per time ({n_t}), got shape {a.shape}")
            bad = np.flatnonzero(~np.isfinite(a))
            if bad.size:
                raise ParameterError(f"recorded stroke channel {name!r} is not finite at "
                                     f"sample {bad[0]}")
            a.setflags(write=False)
            chans[str(name)] = a
        object.__setattr__(self, "channels", chans)
        arrays = {}
        for name in ("time", "displacement", "velocity", "acceleration"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.setflags(write=False)
            if arr.ndim != 1 or arr.size < 2:
                raise ParameterError(f"recorded stroke {name} must be a 1-D array of >= 2 samples")
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise ParameterError(f"recorded stroke {name} is not finite at sample {bad[0]}")
            arrays[name] = arr
            object.__setattr__(self, name, arr)
        n = arrays["time"].size
        for name, arr in arrays.items():
            if arr.size != n:
                raise ParameterError(
                    f"recorded stroke {name} has {arr.size} samples, time has {n}"
                )
        dt = np.diff(arrays["time"])
        if np.any(dt <= 0):
            i = int(np.flatnonzero(dt <= 0)[0])
            raise ParameterError(f"recorded stroke time is not increasing at sample {i + 1}")

    @classmethod
    def from_displacement(cls, time, displacement, window: int = 21, order: int = 4):
        """Build from displacement alone, differentiating with Savitzky-Golay."""
        y, v, a = savgol_derivatives(time, displacement, window, order)
        return cls(np.asarray(time, float), y, v, a)

    @property
    def max_abs(self) -> float:
        """Largest |y| in the record [m]."""
        return float(np.max(np.abs(self.displacement)))

    def __call__(self, t):
        """Interpolated stroke, rate and acceleration at ``t`` [s]."""
        tt = self.time
        return (
            np.interp(t, tt, self.displacement),
            np.interp(t, tt, self.velocity),
            np.interp(t, tt, self.acceleration),
        )

    def channel_values(self, t) -> dict:
        """The measured channels interpolated linearly at ``t`` [s] (ends held): name ->
        value(s) in SI."""
        return {k: np.interp(t, self.time, v) for k, v in self.channels.items()}

    def channel_rates(self, t) -> dict:
        """Slopes of the channels' linear interpolant on the segment holding ``t`` (0 outside
        the samples) [unit/s], name -> value(s)."""
        tt = self.time
        tq = np.asarray(t, float)
        i = np.clip(np.searchsorted(tt, tq, side="right") - 1, 0, tt.size - 2)
        inside = (tq >= tt[0]) & (tq < tt[-1])
        out = {}
        for k, v in self.channels.items():
            r = np.where(inside, (v[i + 1] - v[i]) / (tt[i + 1] - tt[i]), 0.0)
            out[k] = float(r) if r.ndim == 0 else r
        return out
