"""Modal damping from a free decay: the matrix-pencil (Prony) and moving-block methods.

Rotorcraft stability testing measures the damping of a mode from the decay
of the response after an excitation stops.  Two estimators of the decay of
a uniformly sampled signal ``y_k = y(t_0 + k dt)``:

Matrix pencil (:func:`matrix_pencil`)
    Prony's model ``y_k = sum_i a_i z_i^k`` with poles ``z_i = exp(s_i dt)``,
    solved by the matrix-pencil method of Hua & Sarkar: the Hankel matrix
    of the samples (pencil parameter ``L``, rows ``N - L``) is reduced by its
    singular value decomposition to the ``M`` dominant right singular
    vectors ``V``; the poles are the eigenvalues of ``pinv(V_1) V_2`` (``V``
    without its last and first rows), the amplitudes the least-squares
    solution of the Vandermonde system.  ``M`` is the number of singular
    values above ``rtol`` times the largest (the signal's rank) unless given.
    More robust to noise than the original Prony polynomial and needs no
    model order guessed in advance.

Moving block (:func:`moving_block`)
    Bousman & Winkler's moving-block analysis: the Fourier coefficient at
    the mode's frequency ``omega`` of a block of fixed length (an integer
    number of the mode's cycles) is computed for block starts ``tau``
    moving along the record.  For one decaying mode ``A e^{-sigma t}
    cos(omega_d t + phi)`` the coefficient's magnitude is ``C e^{-sigma
    tau}`` (up to the small image of the negative frequency), so the slope
    of ``ln |F(tau)|`` fitted by least squares is ``-sigma`` and ``zeta =
    sigma / sqrt(sigma^2 + omega_d^2)``.  Here the block is weighted by a Hann
    window, which keeps the exact ``e^{-sigma tau}`` law for one mode and
    suppresses the leakage of other components (the 1/rev-modulated
    harmonics ``omega_d +- k Omega`` of a Floquet mode) by its low side lobes;
    the frequency is the spectral peak of the first block (zero-padded FFT,
    parabolic interpolation of the log magnitude).

References
----------
.. [1] Y. Hua, T. K. Sarkar, "Matrix pencil method for estimating parameters
   of exponentially damped/undamped sinusoids in noise", IEEE Trans.
   Acoust. Speech Signal Process. 38(5), 814-824, 1990.
.. [2] W. G. Bousman, D. J. Winkler, "Application of the moving-block analysis",
   AIAA Paper 81-0653, 22nd Structures, Structural Dynamics and Materials
   Conference, 1981.
.. [3] R. Prony, J. Ecole Polytechnique 1(22), 24-76, 1795.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.errors import ParameterError, check_positive

__all__ = ["DecayEstimate", "matrix_pencil", "dominant_mode", "pencil_damping", "moving_block"]


@dataclass(frozen=True)
class DecayEstimate:
    """Decay rate, frequency and damping ratio of one mode from a free decay.

    Attributes
    ----------
    method : str
        ``matrix pencil`` or ``moving block``.
    sigma : float
        Decay rate (> 0 decaying) [1/s].
    frequency : float
        Damped circular frequency omega_d [rad/s].
    damping_ratio : float
        sigma / sqrt(sigma^2 + omega_d^2) [-].
    detail : str
        Settings and fit quality in words.
    """

    method: str
    sigma: float
    frequency: float
    damping_ratio: float
    detail: str

    @property
    def exponent(self) -> complex:
        """-sigma + i omega_d [1/s]."""
        return complex(-self.sigma, self.frequency)


def _samples(signal, dt):
    y = np.asarray(signal, float).reshape(-1)
    if y.size < 16 or not np.all(np.isfinite(y)):
        raise ParameterError(f"the decay signal needs at least 16 finite samples, got {y.size}")
    return y, check_positive("sample interval dt", dt, "s")


def matrix_pencil(signal, dt: float, *, order: int | None = None, pencil: int | None = None,
                  rtol: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """Poles and amplitudes of ``signal`` ~ sum a_i exp(s_i k dt) (module notes).

    Parameters
    ----------
    signal : array
        Uniform samples (at least 16).
    dt : float
        Sample interval [s].
    order : int, optional
        Number of poles M (default: singular values above ``rtol`` x the largest).
    pencil : int, optional
        Pencil parameter L, between M and N - M (default N // 3, at most 120:
        plenty for the few components of a modal decay, and the SVD stays small).
    rtol : float
        Rank threshold [-].

    Returns
    -------
    poles : ndarray of complex
        s_i [1/s], sorted by decreasing energy over the record,
        |a_i|^2 sum_k |z_i|^(2k).
    amplitudes : ndarray of complex
        a_i [signal units], the value of each component at the first sample.

    Examples
    --------
    >>> t = np.arange(400) * 0.01
    >>> s, a = matrix_pencil(np.exp(-0.3 * t) * np.cos(7.0 * t), 0.01)
    >>> np.round(np.sort_complex(s), 9)
    array([-0.3-7.j, -0.3+7.j])
    """
    y, h = _samples(signal, dt)
    N = y.size
    L = min(N // 3, 120) if pencil is None else int(pencil)
    if not 2 <= L <= N - 2:
        raise ParameterError(f"pencil parameter must lie in [2, {N - 2}], got {L}")
    H = np.lib.stride_tricks.sliding_window_view(y, L + 1)  # (N - L) x (L + 1)
    _, sv, Vh = np.linalg.svd(H, full_matrices=False)
    M = int(np.sum(sv > rtol * sv[0])) if order is None else int(order)
    if not 1 <= M <= min(L, N - L):
        raise ParameterError(f"model order must lie in [1, {min(L, N - L)}], got {M}")
    V = Vh[:M].conj().T
    z = np.linalg.eigvals(np.linalg.pinv(V[:-1]) @ V[1:])
    z = z[np.abs(z) > 0.0]
    k = np.arange(N)[:, None]
    A = z[None, :] ** k
    amp = np.linalg.lstsq(A, y.astype(complex), rcond=None)[0]
    energy = np.abs(amp) ** 2 * np.sum(np.abs(A) ** 2, axis=0)
    order_ = np.argsort(-energy)
    return np.log(z[order_]) / h, amp[order_]


def dominant_mode(poles, *, near: float | None = None) -> complex:
    """The first pole with positive frequency of ``poles`` (sorted as :func:`matrix_pencil`
    returns them: the one carrying most of the signal), within half of ``near`` [rad/s] of it
    if given.
    """
    s = np.asarray(poles, complex)
    up = s.imag > 0.0
    if near is not None:
        up &= np.abs(s.imag - near) < 0.5 * near
    if not np.any(up):
        raise ParameterError("no oscillating pole in the decay signal"
                             + (f" near {near:.4g} rad/s" if near is not None else ""))
    return complex(s[np.flatnonzero(up)[0]])


def pencil_damping(signal, dt: float, *, near: float | None = None,
                   rtol: float = 1e-6) -> DecayEstimate:
    """Damping of the dominant oscillating pole of :func:`matrix_pencil` (``near`` [rad/s]).

    Examples
    --------
    >>> t = np.arange(600) * 0.01
    >>> y = np.exp(-0.2 * t) * np.sin(5.0 * t) + 0.1 * np.exp(-3.0 * t) * np.cos(20.0 * t)
    >>> est = pencil_damping(y, 0.01)
    >>> round(est.damping_ratio * math.hypot(0.2, 5.0), 9), round(est.frequency, 9)
    (0.2, 5.0)
    """
    s, _ = matrix_pencil(signal, dt, rtol=rtol)
    p = dominant_mode(s, near=near)
    sig, w = -p.real, p.imag
    return DecayEstimate("matrix pencil", sig, w, sig / math.hypot(sig, w),
                         f"{s.size} poles (rank threshold {rtol:g}), {len(signal)} samples")


def _peak_frequency(y, dt, pad: int = 16) -> float:
    n = y.size
    Y = np.abs(np.fft.rfft(y * np.hanning(n), pad * n))
    k = int(np.argmax(Y[1:-1])) + 1
    a, b, c = np.log(Y[k - 1:k + 2] + 1e-300)
    den = a - 2.0 * b + c
    shift = 0.5 * (a - c) / den if den != 0.0 else 0.0
    return float(2.0 * math.pi * (k + shift) / (pad * n * dt))


def moving_block(signal, dt: float, *, frequency: float | None = None,
                 block_cycles: int = 4, stride: int = 1) -> DecayEstimate:
    """Damping of the dominant mode of a free decay by the moving-block analysis.

    Parameters
    ----------
    signal : array
        Uniform samples of the decay.
    dt : float
        Sample interval [s].
    frequency : float, optional
        Analysis frequency omega [rad/s] (default: spectral peak of the
        first block, itself ``block_cycles`` cycles of the record's peak).
    block_cycles : int
        Block length in cycles of the analysis frequency (>= 2).
    stride : int
        Samples between block starts.

    Returns
    -------
    DecayEstimate

    Examples
    --------
    >>> t = np.arange(4000) * 0.005
    >>> est = moving_block(np.exp(-0.3 * t) * np.cos(7.0 * t + 0.4), 0.005)
    >>> round(est.sigma, 4), round(est.frequency, 2)
    (0.3, 7.0)
    """
    y, h = _samples(signal, dt)
    if not (isinstance(block_cycles, int) and block_cycles >= 2):
        raise ParameterError(f"block_cycles must be an integer >= 2, got {block_cycles!r}")
    w = _peak_frequency(y, h) if frequency is None else check_positive(
        "analysis frequency", frequency, "rad/s")
    nb = int(round(block_cycles * 2.0 * math.pi / w / h))
    if frequency is None and 16 <= nb < y.size:
        w = _peak_frequency(y[:nb], h)
        nb = int(round(block_cycles * 2.0 * math.pi / w / h))
    if nb < 8 or y.size - nb < 8 * stride:
        raise ParameterError(
            f"the record ({y.size} samples, {y.size * h:.4g} s) is too short for blocks of "
            f"{block_cycles} cycles at {w:.4g} rad/s ({nb} samples): lengthen the record")
    win = np.hanning(nb)
    kern = win * np.exp(-1j * w * h * np.arange(nb))
    starts = np.arange(0, y.size - nb + 1, stride)
    F = np.abs(np.array([kern @ y[k:k + nb] for k in starts]))
    tau = starts * h
    slope, icpt = np.polyfit(tau, np.log(F), 1)
    fit = np.log(F) - (slope * tau + icpt)
    sig = -float(slope)
    return DecayEstimate("moving block", sig, w, sig / math.hypot(sig, w),
                         f"Hann-weighted blocks of {block_cycles} cycles ({nb} samples), "
                         f"{starts.size} positions; rms deviation of ln|F| from the line "
                         f"{float(np.sqrt(np.mean(fit**2))):.2g}")
