"""Model selection on densely sampled records: BIC with the effective number of samples.

A record sampled at tens of samples per cycle gives a residual that is correlated in time:
a misfit that lasts a tenth of a cycle spans many samples.  The Bayesian information
criterion

    BIC = N ln(RSS / N) + k ln N

assumes N independent residuals; with N samples of a correlated residual the evidence
N ln(RSS_1 / RSS_0) for an extra parameter is overstated by the correlation time tau (in
samples), and any parameter that absorbs a little systematic misfit passes (an offset that
lowers the held-out error by 9 % came out at delta-BIC -3860 on a 6 000-sample record).
The diagnosis counts, by default, the independent values the kept band of each record can
hold (:func:`bandwidth_samples`: min(N, 2 B T + 1), B the force bandwidth the conditioning
kept, T the span of the record fitted; an averaged cycle of 30 harmonics counts 61 whatever
its sampling rate), because the residual of a misfit is smooth by construction and its
correlation time measures the misfit, not the noise: Geyer's count below on an averaged
cycle came out near 10 and rejected a gas preload that cut the held-out error by a third.
The alternative, ``sample_count="correlation"`` of the selection rule, uses the effective
number of independent samples

    N_eff = sum over records of N_i / tau_i,

tau_i the integrated autocorrelation time of record i's residual, estimated by Geyer's
initial positive sequence: with rho_k the sample autocorrelation at lag k and
Gamma_m = rho_2m + rho_2m+1, tau = -1 + 2 sum_{m <= M} Gamma_m, summed while Gamma_m > 0
(and made non-increasing), clipped to [1, N_i] (an anti-correlated residual is not credited
with more than N_i samples).  White noise gives tau = 1 (N_eff = N); an AR(1) residual
with coefficient a gives (1 + a) / (1 - a).  Then

    delta BIC = N_eff ln(RSS_1 / RSS_0) + (k_1 - k_0) ln N_eff,

with RSS over the calibration samples and tau taken from the residual of the larger model
(the model under test: under its hypothesis, that residual is the noise; the residual of the
smaller model also holds the missing effect's deterministic signature, which is not noise).

BIC rather than AICc: the diagnosis asks which physical effects are present, not which
model predicts best; BIC is consistent (it picks the true model among the candidates as the
data grow) and its differences read on the Bayes-factor scale of Kass and Raftery (a
difference of 10 is "very strong" evidence), while AIC's penalty 2 per parameter keeps a
fixed chance of adding a spurious parameter however long the record.

References
----------
.. [1] G. Schwarz, "Estimating the dimension of a model", Ann. Stat. 6(2), 1978.
.. [2] R. E. Kass, A. E. Raftery, "Bayes factors", JASA 90(430), 1995.
.. [3] C. J. Geyer, "Practical Markov chain Monte Carlo", Stat. Sci. 7(4), 1992, Sec. 3.3
   (initial positive and monotone sequence estimators).
.. [4] C. S. Bretherton et al., "The effective number of spatial degrees of freedom of a
   time-varying field", J. Climate 12(7), 1999 (effective sample size of correlated series).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.errors import ParameterError

__all__ = ["correlation_time", "correlation_inflation", "effective_samples", "delta_bic",
           "Verdict", "judge", "bandwidth_samples", "sample_count"]


def correlation_time(residual) -> float:
    """Integrated autocorrelation time tau of a residual [samples] (Geyer's estimator).

    Parameters
    ----------
    residual : array
        One record's residual, uniformly sampled (at least 4 samples).

    Returns
    -------
    float
        tau in [1, N]: N / tau independent samples carry the same information.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> e = rng.normal(size=20000)
    >>> round(correlation_time(e), 1)
    1.0
    >>> x = np.zeros_like(e)
    >>> for i in range(1, e.size):
    ...     x[i] = 0.8 * x[i - 1] + e[i]
    >>> bool(abs(correlation_time(x) / 9.0 - 1) < 0.15)   # (1 + 0.8) / (1 - 0.8)
    True
    """
    r = np.asarray(residual, float)
    n = r.size
    if r.ndim != 1 or n < 4:
        raise ParameterError(f"correlation_time needs a 1-D residual of at least 4 samples, "
                             f"got shape {r.shape}")
    if not np.all(np.isfinite(r)):
        raise ParameterError("correlation_time: the residual holds NaN or inf")
    r = r - r.mean()
    var = float(r @ r)
    if var == 0.0:
        return 1.0
    m = 1 << int(math.ceil(math.log2(2 * n)))
    spec = np.fft.rfft(r, m)
    acf = np.fft.irfft(spec * np.conj(spec), m)[:n] / var  # biased estimator, rho_0 = 1
    pairs = acf[: 2 * (n // 2)].reshape(-1, 2).sum(axis=1)  # Gamma_m = rho_2m + rho_2m+1
    neg = np.flatnonzero(pairs <= 0.0)
    pairs = pairs[: neg[0]] if neg.size else pairs
    pairs = np.minimum.accumulate(pairs)  # initial monotone sequence
    tau = -1.0 + 2.0 * float(pairs.sum())
    return float(min(max(tau, 1.0), n))


def correlation_inflation(residuals) -> float:
    """Variance inflation N / N_eff of a fit's residuals, at least 1 [-].

    A least-squares covariance s^2 (J^T J)^-1 assumes independent residuals.  Residuals
    correlated in time (a filtered, decimated or cycle-averaged record; a misfit that
    follows the stroke) carry the information of N_eff = sum N_i / tau_i samples only
    (tau_i each record's integrated autocorrelation time, :func:`correlation_time`), so
    the covariance is scaled by N / N_eff (Bayley & Hammersley 1946; Zieba 2010, Metrol.
    Meas. Syst. 17(1)).

    Parameters
    ----------
    residuals : sequence of array
        The residual of each record (fewer than 4 samples or all zero: left out).

    Returns
    -------
    float
        N / N_eff (1 for white residuals or when nothing is left).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> round(correlation_inflation([rng.normal(size=4000)]), 1)
    1.0
    """
    n = n_eff = 0.0
    for r in residuals:
        r = np.asarray(r, float)
        if r.size >= 4 and np.any(r != 0.0):
            n += r.size
            n_eff += r.size / correlation_time(r)
    return max(n / n_eff, 1.0) if n_eff > 0 else 1.0


def effective_samples(residuals) -> tuple[float, tuple[float, ...]]:
    """N_eff = sum N_i / tau_i over records, and each record's tau_i (module docstring).

    Parameters
    ----------
    residuals : sequence of array
        The residual of each record (records are independent of each other).

    Returns
    -------
    (float, tuple of float)
        N_eff [-] and tau_i [samples].
    """
    taus = tuple(correlation_time(r) for r in residuals)
    if not taus:
        raise ParameterError("effective_samples needs at least one residual")
    return float(sum(np.size(r) / t for r, t in zip(residuals, taus, strict=True))), taus


def delta_bic(rss_before: float, rss_after: float, k_added: int, n_eff: float) -> float:
    """BIC change N_eff ln(RSS_after / RSS_before) + k_added ln N_eff (negative favours after).

    Examples
    --------
    >>> round(delta_bic(100.0, 50.0, 1, 200.0), 3)   # 200 ln(0.5) + ln(200)
    -133.331
    """
    for name, v in (("rss_before", rss_before), ("rss_after", rss_after)):
        if not (math.isfinite(v) and v > 0):
            raise ParameterError(f"delta_bic: {name} must be a positive finite sum of squares, "
                                 f"got {v!r}")
    if not (math.isfinite(n_eff) and n_eff > 1):
        raise ParameterError(f"delta_bic: n_eff must be > 1, got {n_eff!r}")
    return float(n_eff * math.log(rss_after / rss_before) + k_added * math.log(n_eff))


@dataclass(frozen=True)
class Verdict:
    """The selection rule's decision on one candidate (:func:`judge`).

    Attributes
    ----------
    accepted : bool
        Both tests passed.
    delta_bic : float
        BIC change counted with ``n_effective`` samples (negative favours the candidate).
    n_effective : float
        Effective number of independent calibration samples of the candidate's residual.
    relative_reduction : float
        1 - (held-out NRMSE with the candidate) / (without) [-].
    reasons : tuple of str
        The tests failed, in words (empty when accepted).
    """

    accepted: bool
    delta_bic: float
    n_effective: float
    relative_reduction: float
    reasons: tuple


def bandwidth_samples(record) -> float:
    """Independent values the kept band of a (conditioned) record can hold [-].

    A force low-passed to a bandwidth B [Hz] over a span T [s] is fixed by 2 B T + 1
    values (the sampling theorem; for a periodic record its Fourier coefficients up to the
    kept harmonic), however densely it is sampled: an averaged cycle of a 300 Hz record kept
    to 30 harmonics counts 61, a 10-cycle record 601, never more than its N samples.  B is
    the conditioning's ``harmonics_kept`` times the stroke frequency (``meta["conditioning"]``
    of :func:`~liquidamp.analysis.measured.conditioning.condition`); a record that was not
    conditioned keeps its Nyquist band and counts N.

    Parameters
    ----------
    record : Record

    Returns
    -------
    float
        min(N, 2 B T + 1).

    Examples
    --------
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 2, 0.005)
    >>> r = Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 2 * t), np.cos(2 * np.pi * 2 * t))
    >>> bandwidth_samples(r) == r.time.size
    True
    """
    n = int(np.size(record.time))
    cond = (getattr(record, "meta", None) or {}).get("conditioning")
    if cond is None or not getattr(cond, "harmonics_kept", None):
        return float(n)
    dt = float(np.median(np.diff(record.time))) if n > 1 else 0.0
    span = float(record.time[-1] - record.time[0]) + dt
    band = float(cond.harmonics_kept) * float(record.frequency)
    return float(min(n, 2.0 * band * span + 1.0))


def sample_count(records, residuals, how: str = "bandwidth") -> float:
    """Samples the BIC counts over a set of records (``how``: 'bandwidth', 'correlation',
    'samples'; see :class:`~liquidamp.analysis.measured.diagnosis_options.SelectionRule`)."""
    if how == "bandwidth":
        return float(sum(bandwidth_samples(r) for r in records))
    if how == "correlation":
        return effective_samples(residuals)[0]
    if how == "samples":
        return float(sum(np.size(r) for r in residuals))
    raise ParameterError(f"sample_count must be 'bandwidth', 'correlation' or 'samples', "
                         f"got {how!r}")


def _per_record(x) -> tuple:
    return (float(x),) if np.ndim(x) == 0 else tuple(float(v) for v in x)


def judge(residuals_now, residuals_new, k_added: int, validation_now,
          validation_new, *, bic_threshold: float = 10.0,
          validation_tolerance: float = 0.02, n_eff: float | None = None) -> Verdict:
    """Accept a candidate model over the current one (the diagnosis' selection rule).

    Accepted when all hold:

    * delta BIC (module docstring) is below ``-bic_threshold``, counted with ``n_eff``
      samples (default: N_eff of ``residuals_new``, Geyer's estimator; the diagnosis passes
      the kept-bandwidth count of :func:`bandwidth_samples`);
    * no held-out record gets worse by more than ``validation_tolerance`` (relative):
      new_i <= (1 + tol) now_i for every record i;
    * the held-out records get better together by more than it: the geometric mean of
      new_i / now_i is at most 1 - tol (an effect is kept only if it predicts held-out data
      better).

    Parameters
    ----------
    residuals_now, residuals_new : sequence of array
        Calibration residual of each record [N], current model and candidate.
    k_added : int
        Parameters the candidate adds.
    validation_now, validation_new : float or sequence of float
        Held-out NRMSE of the two models, per held-out record (or one pooled figure) [-].
    bic_threshold : float
        Least fall of the BIC (10: "very strong" evidence, Kass and Raftery) [-].
    validation_tolerance : float
        Largest relative rise of a held-out record's NRMSE [-].
    n_eff : float, optional
        Samples counted in the BIC (> 1).

    Returns
    -------
    Verdict
        ``relative_reduction`` is 1 - the geometric mean of the per-record ratios.

    Examples
    --------
    A fit that halves the residual of 200 white-noise samples with one parameter more and
    lowers the held-out error: accepted; the same with a held-out error 5 % worse: not.

    >>> rng = np.random.default_rng(0)
    >>> e = rng.normal(size=200)
    >>> v = judge([2 * e], [e], 1, 0.30, 0.27)
    >>> v.accepted, round(v.relative_reduction, 2), v.delta_bic < -100
    (True, 0.1, True)
    >>> for reason in judge([2 * e], [e], 1, 0.30, 0.315).reasons:
    ...     print(reason)
    held-out NRMSE 0.315 worse than 0.3 by more than 2%
    held-out NRMSE not better by more than 2% (ratio 1.05)

    Record by record: one held-out record 10 % worse vetoes a step that halves another.

    >>> judge([2 * e], [e], 1, [0.30, 0.20], [0.15, 0.22]).reasons
    ('held-out NRMSE 0.22 worse than 0.2 by more than 2%',)
    """
    rss_now = float(sum(float(np.dot(r, r)) for r in residuals_now))
    rss_new = float(sum(float(np.dot(r, r)) for r in residuals_new))
    if n_eff is None:
        n_eff, _ = effective_samples(residuals_new)
    dbic = delta_bic(rss_now, rss_new, k_added, n_eff)
    now, new = _per_record(validation_now), _per_record(validation_new)
    if len(now) != len(new) or not now:
        raise ParameterError(f"judge: {len(now)} held-out NRMSE now, {len(new)} new; give "
                             "one per held-out record")
    reasons = []
    if not dbic < -bic_threshold:
        reasons.append(f"delta BIC {dbic:.3g} (N_eff {n_eff:.4g}) not below -{bic_threshold:g}")
    for a, b in zip(now, new, strict=True):
        if not b <= (1.0 + validation_tolerance) * a:
            reasons.append(f"held-out NRMSE {b:.4g} worse than {a:.4g} "
                           f"by more than {validation_tolerance:.0%}")
    ratio = float(np.exp(np.mean(np.log(np.maximum(new, 1e-300))
                                 - np.log(np.maximum(now, 1e-300)))))
    if not ratio <= 1.0 - validation_tolerance:
        reasons.append(f"held-out NRMSE not better by more than {validation_tolerance:.0%} "
                       f"(ratio {ratio:.3g})")
    return Verdict(accepted=not reasons, delta_bic=dbic, n_effective=float(n_eff),
                   relative_reduction=1.0 - ratio, reasons=tuple(reasons))
