"""A stroke made of a few sinusoids: its least-squares line-spectrum fit, exact derivatives.

A test machine driven by a sum of a few sines (a rotorcraft lag-damper test: the 1/rev
frequency and the lag frequency together) makes a stroke that is not periodic over the
record, so it has no periodic orbit and no Fourier series of one period; the
Savitzky-Golay derivative of its samples is then what drives a model, and that filter
attenuates the rate (0.5 % RMS on a 4 Hz + 1.3 Hz stroke at 200 Hz), which a fluid device
turns into a force error of the same share, several times its load-cell noise.  A stroke
that IS a few sinusoids is known exactly from its samples: :func:`tone_fit` finds its
lines one at a time (the largest peak of the residual's zero-padded, Hann-windowed
periodogram), refines each frequency by a bounded search of the residual sum of squares
with the amplitudes solved linearly (variable projection; near acceptance every line jointly), and
accepts the fit only where what it leaves is the displacement sensor's white noise: the
residual's RMS at most :data:`ACCEPT` (1.5, the diagnosis's own factor between a residual
and the noise floor) times its white part (robust scale of its 4th differences, variance
70 sigma^2 for white noise). A stroke the lines do not explain (broadband, tapered, a few
harmonics too many) gets None and keeps the Savitzky-Golay derivatives.

References
----------
.. [1] G. H. Golub, V. Pereyra, "The differentiation of pseudo-inverses and nonlinear least
   squares problems whose variables separate", SIAM J. Numer. Anal. 10(2), 1973.
.. [2] P. Stoica, R. Moses, Spectral Analysis of Signals, Prentice Hall, 2005, Ch. 4.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ToneFit", "tone_fit", "white_std", "ACCEPT", "MAX_TONES", "CACHE_SIZE"]

#: The residual of an accepted fit is at most this many times its white part [-].
ACCEPT = 1.5
#: Most lines tried [-].
MAX_TONES = 8
#: Where the residual is within this factor of acceptance every line is refined jointly (a
#: computational shortcut: a tapered or broadband stroke never gets near) [-].
POLISH = 10.0
#: A stroke whose :data:`MAX_TONES` largest lines hold less than this share of its variance
#: (their Hann lobes: all but 0.1 % of a line's energy) is not tried: the white noise it
#: would have to leave is about 1e-6 of a stroke's variance (2 um on 2 mm) [-].
LINE_SHARE = 0.9


@dataclass(frozen=True)
class ToneFit:
    """y(t) = mean + sum_k (s_k sin(w_k (t - t0)) + c_k cos(w_k (t - t0))) [m].

    Attributes
    ----------
    t0 : float
        Time origin [s].
    mean : float
        Constant [m].
    frequencies : tuple of float
        Line frequencies [Hz].
    sine, cosine : tuple of float
        Amplitudes s_k, c_k [m].
    residual_rms, noise_std : float
        RMS of the fit's residual and of its white part [m].
    """

    t0: float
    mean: float
    frequencies: tuple
    sine: tuple
    cosine: tuple
    residual_rms: float
    noise_std: float

    def arrays(self, t):
        """(y - mean [m], v [m/s], a [m/s^2]) at times ``t`` [s]."""
        tt = np.asarray(t, float) - self.t0
        y, v, a = np.zeros_like(tt), np.zeros_like(tt), np.zeros_like(tt)
        for f, s, c in zip(self.frequencies, self.sine, self.cosine, strict=True):
            w = 2.0 * math.pi * f
            sn, cs = np.sin(w * tt), np.cos(w * tt)
            y += s * sn + c * cs
            v += w * (s * cs - c * sn)
            a -= w * w * (s * sn + c * cs)
        return y, v, a


def white_std(x) -> float:
    """Robust standard deviation of the white part of ``x`` [units of ``x``]: 1.4826 MAD of
    its 4th differences / sqrt(70) (a component at f is suppressed by (2 sin(pi f / fs))^4).

    Examples
    --------
    >>> x = np.random.default_rng(1).normal(0.0, 2e-6, 4000) + 1e-3 * np.sin(np.arange(4000) / 50)
    >>> round(white_std(x) * 1e6, 1)  # the 2 um noise under a 1 mm slow sine
    2.0
    """
    d4 = np.diff(np.asarray(x, float), 4)
    return 1.4826 * float(np.median(np.abs(d4 - np.median(d4)))) / math.sqrt(70.0)


def _design(tt, freqs):
    cols = [np.ones_like(tt)]
    for f in freqs:
        w = 2.0 * math.pi * f * tt
        cols += [np.sin(w), np.cos(w)]
    return np.column_stack(cols)


def _residual(tt, y, freqs):
    A = _design(tt, freqs)
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    return y - A @ coef, coef


def _line_share(xw, nfft, grid, span, k) -> float:
    """Share of the windowed signal's periodogram energy within +-2 bins (1 / span) of its
    ``k`` largest peaks (a Hann-windowed line keeps all but 0.1 % of its energy there)."""
    power = np.abs(np.fft.rfft(xw, nfft)) ** 2
    total = float(power.sum())
    left = power.copy()
    for _ in range(k):
        j = int(np.argmax(left))
        left[np.abs(grid - grid[j]) <= 2.0 / span] = 0.0
    return 1.0 - float(left.sum()) / total if total > 0 else 0.0


def _refine(tt, y, freqs, i, half_width):
    """Move ``freqs[i]`` to the least residual sum of squares within +-``half_width`` [Hz]
    (bounded Brent search; the other lines and the amplitudes solved linearly)."""
    from scipy.optimize import minimize_scalar

    def cost(f):
        trial = list(freqs)
        trial[i] = f
        r = _residual(tt, y, trial)[0]
        return float(r @ r)

    lo, hi = max(freqs[i] - half_width, 1e-9), freqs[i] + half_width
    freqs[i] = float(minimize_scalar(cost, bounds=(lo, hi), method="bounded",
                                     options={"xatol": 1e-6 * half_width}).x)


#: Fits made, by the samples' content: the fits' conditioning re-makes a record with the same
#: samples for every model run (a tapered record's diagnosis asked for its fit 2264 times, 95
#: of its 182 s), so a fit is made once per distinct stroke; the oldest is dropped beyond
#: :data:`CACHE_SIZE` (a ToneFit is immutable, so sharing it is safe).
_CACHE: dict = {}
#: Most fits kept [-].
CACHE_SIZE = 64


def tone_fit(t, y, max_tones: int = MAX_TONES) -> ToneFit | None:
    """The line-spectrum fit of samples ``y`` [m] at uniform times ``t`` [s], or None
    where at most ``max_tones`` lines leave more than the white noise (module docstring).

    The fit is a pure function of ``t``, ``y`` and ``max_tones``; a fit already made for the
    same samples (equal content, any array object) is returned as made.

    Parameters
    ----------
    t : array_like
        Uniform sample times [s].
    y : array_like
        Stroke samples [m].
    max_tones : int
        Most lines tried [-].

    Returns
    -------
    ToneFit or None
        The lines (frequencies [Hz], amplitudes [m]), or None where they leave more than the
        white noise.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(0.0, 7.7, 0.005)
    >>> y = 1.5e-3 * np.sin(8 * np.pi * t + 0.3) + 1.8e-3 * np.sin(2.6 * np.pi * t - 1.0)
    >>> fit = tone_fit(t, y + rng.normal(0.0, 2e-6, t.size))
    >>> sorted(round(f, 4) for f in fit.frequencies)
    [1.3, 4.0]
    >>> v = fit.arrays(t)[1]
    >>> exact = 1.5e-3 * 8 * np.pi * np.cos(8 * np.pi * t + 0.3) \\
    ...     + 1.8e-3 * 2.6 * np.pi * np.cos(2.6 * np.pi * t - 1.0)
    >>> bool(np.max(np.abs(v - exact)) < 1e-3 * np.max(np.abs(exact)))
    True
    >>> tone_fit(t, rng.normal(0.0, 1e-3, t.size).cumsum() * 1e-2) is None  # a random walk
    True
    """
    t = np.ascontiguousarray(t, float)
    y = np.ascontiguousarray(y, float)
    digest = hashlib.blake2b(t.tobytes(), digest_size=16)
    digest.update(y.tobytes())
    key = (t.size, y.size, int(max_tones), digest.digest())
    if key in _CACHE:
        return _CACHE[key]
    fit = _tone_fit(t, y, max_tones)
    while len(_CACHE) >= CACHE_SIZE:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = fit
    return fit


def _tone_fit(t, y, max_tones):
    """:func:`tone_fit` without the cache."""
    from scipy.optimize import least_squares

    n = t.size
    if n < 16:
        return None
    tt = t - t[0]
    span = float(tt[-1])
    fs = (n - 1) / span
    nfft = 8 * (1 << int(math.ceil(math.log2(n))))
    grid = np.fft.rfftfreq(nfft, 1.0 / fs)
    window = np.hanning(n)
    freqs: list = []
    r = y - y.mean()
    if _line_share(r * window, nfft, grid, span, max_tones) < LINE_SHARE:
        return None  # broadband: the lines' lobes cannot hold the stroke
    for _ in range(max_tones):
        spec = np.abs(np.fft.rfft(r * window, nfft))
        spec[grid < 1.0 / span] = 0.0  # no line below one cycle per record
        freqs.append(float(grid[int(np.argmax(spec))]))
        _refine(tt, y, freqs, len(freqs) - 1, 1.0 / span)
        r, coef = _residual(tt, y, freqs)
        rms, white = float(np.sqrt(np.mean(r * r))), white_std(r)
        if len(freqs) > 1 and ACCEPT * white < rms <= POLISH * ACCEPT * white:
            # near the noise: the earlier lines' estimates carried the later ones' leakage;
            # every line refined jointly (Levenberg-Marquardt, the amplitudes linear)
            freqs = [float(f) for f in least_squares(
                lambda f: _residual(tt, y, f)[0], np.array(freqs), x_scale=1.0 / span,
                method="lm").x]
            r, coef = _residual(tt, y, freqs)
            rms, white = float(np.sqrt(np.mean(r * r))), white_std(r)
        if rms <= ACCEPT * white:
            return ToneFit(float(t[0]), float(coef[0]), tuple(freqs), tuple(coef[1::2]),
                           tuple(coef[2::2]), rms, white)
    return None
