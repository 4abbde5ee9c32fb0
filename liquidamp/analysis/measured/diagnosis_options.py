"""The knobs of :func:`~liquidamp.analysis.measured.diagnosis.diagnose`, as options objects.

As lmfit keeps the minimizer's options apart from the model, the diagnosis keeps its knobs
in three frozen, validated dataclasses, grouped by :class:`DiagnoseOptions`:

* :class:`SelectionRule` -- when an effect is kept and when the loop stops;
* :class:`Budget` -- how much work each step may do;
* :class:`ConditioningOptions` -- what is done to the records before any fit.

Unknown options raise (naming the valid ones); a bad value raises naming the quantity, its
value and what is allowed.  ``DiagnoseOptions.from_keywords`` maps the flat keywords of the
earlier ``diagnose(..., max_steps=3, bic_threshold=10, ...)`` onto the objects, so old
callers keep working; the command line maps its flags the same way.

Examples
--------
>>> o = DiagnoseOptions.from_keywords(max_steps=2, validation_tolerance=0.05)
>>> o.budget.max_steps, o.selection.validation_tolerance, o.selection.sample_count
(2, 0.05, 'bandwidth')
>>> try:
...     DiagnoseOptions.from_keywords(max_step=2)
... except ParameterError as exc:
...     print(str(exc)[:60])
diagnose: unknown option 'max_step'; valid: average, bic_thr
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from liquidamp.analysis.measured.conditioning import HARMONICS
from liquidamp.errors import ParameterError
from liquidamp.options import resolve_options

__all__ = ["SelectionRule", "Budget", "ConditioningOptions", "DiagnoseOptions",
           "BROADBAND_RTOL", "BROADBAND_TOP", "broadband", "march_options"]


def _finite(owner: str, name: str, v, lo: float, hi: float = math.inf, unit: str = "-"):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (
            math.isfinite(v) and lo <= v <= hi):
        raise ParameterError(f"{owner}: {name} must be a finite number in [{lo:g}, {hi:g}] "
                             f"[{unit}], got {v!r}")


def _count(owner: str, name: str, v, lo: int, hi: int):
    if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
        raise ParameterError(f"{owner}: {name} must be an integer in [{lo}, {hi}], got {v!r}")


class _Options:
    """Shared: ``replace`` that refuses unknown names, ``as_dict``."""

    def replace(self, **changes):
        """A copy with ``changes`` (unknown names raise :class:`ParameterError`)."""
        names = {f.name for f in dataclasses.fields(self)}
        bad = sorted(set(changes) - names)
        if bad:
            raise ParameterError(f"{type(self).__name__}: unknown option {bad[0]!r}; valid: "
                                 + ", ".join(sorted(names)))
        return dataclasses.replace(self, **changes)

    def as_dict(self) -> dict:
        """JSON-ready."""
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            out[f.name] = v.as_dict() if isinstance(v, _Options) else (
                list(v) if isinstance(v, tuple) else v)
        return out


@dataclass(frozen=True)
class SelectionRule(_Options):
    """When the diagnosis keeps an effect, and when it stops.

    A candidate is kept only if all hold (see the diagnosis module, step 5):

    * held out, record by record: no held-out record gets worse by more than
      ``validation_tolerance`` (relative), and the held-out records together get better
      by more than it (the geometric mean of the per-record NRMSE ratios below
      1 - ``validation_tolerance``);
    * the calibration BIC, counted with an honest sample count (``sample_count``), falls
      by more than ``bic_threshold``;
    * none of the parameters it frees ends at a bound (``reject_at_bound``): there the
      value is the bound's, not the data's.

    Among the candidates kept, the best held-out one is added; the others within
    ``tie_tolerance`` of it are reported as tied.

    Attributes
    ----------
    bic_threshold : float
        Least fall of the BIC [-] (10: "very strong" evidence, Kass and Raftery).
    validation_tolerance : float
        Largest relative rise of any held-out record's NRMSE, and least relative fall of
        their geometric mean [-].
    tie_tolerance : float
        Held-out NRMSE (geometric mean) within this relative margin of the best: a tie [-].
    noise_factor : float
        Stop when the calibration NRMSE is at most this times the noise floor [-].
    structure_factor : float
        Above this times the noise floor the residual is called structured [-].
    sample_count : {'bandwidth', 'correlation', 'samples'}
        Samples counted in the BIC: ``'bandwidth'`` the independent values the kept band
        of each record can hold, min(N, 2 B T + 1) (B the kept force bandwidth [Hz], T the
        record's span [s]: an averaged cycle with 30 harmonics counts 61, not N);
        ``'correlation'`` N / tau of the refit's residual (Geyer); ``'samples'`` N.
    reject_at_bound : bool
        Refuse a candidate whose freed parameter ends at a bound.
    """

    bic_threshold: float = 10.0
    validation_tolerance: float = 0.02
    tie_tolerance: float = 0.10
    noise_factor: float = 1.5
    structure_factor: float = 2.0
    sample_count: str = "bandwidth"
    reject_at_bound: bool = True

    def __post_init__(self):
        o = "SelectionRule"
        _finite(o, "bic_threshold", self.bic_threshold, 0.0)
        _finite(o, "validation_tolerance", self.validation_tolerance, 0.0, 1.0)
        _finite(o, "tie_tolerance", self.tie_tolerance, 0.0, 10.0)
        _finite(o, "noise_factor", self.noise_factor, 1.0)
        _finite(o, "structure_factor", self.structure_factor, 1.0)
        if self.sample_count not in ("bandwidth", "correlation", "samples"):
            raise ParameterError(f"{o}: sample_count must be 'bandwidth', 'correlation' or "
                                 f"'samples', got {self.sample_count!r}")
        if not isinstance(self.reject_at_bound, bool):
            raise ParameterError(f"{o}: reject_at_bound must be True or False, got "
                                 f"{self.reject_at_bound!r}")


@dataclass(frozen=True)
class Budget(_Options):
    """How much work the diagnosis may do.

    Attributes
    ----------
    max_steps : int
        Effects added at most (0-8; default 5).  A budget, not the stopping rule: the loop
        stops at the noise floor or where no candidate passes the selection rule, which
        guards against over-fitting; 3 cut a real friction damper's tapered record while
        each step still predicted the held-out records better.
    top : int
        Best-scoring candidates refitted per step at least (1-16).
    score_ratio : float
        When the ``top`` refits leave the residual structured, the next candidate is
        refitted too if it scores at least 1/``score_ratio`` of the best [-].
    max_nfev : int
        Model evaluations of each fit (60: also ``liquidamp diagnose``'s ``--max-nfev``
        default; session 18 measured B_digressive40 read wrongly at 80, session 19 every
        held-out set at both, runs/s19_lead/README.md).
    tol : float
        Fit tolerance (ftol = xtol of least squares) [-].
    preroll : int
        Pre-roll cycles of each record simulation [-].
    """

    max_steps: int = 5
    top: int = 2
    score_ratio: float = 3.0
    max_nfev: int = 60
    tol: float = 1e-5
    preroll: int = 1

    def __post_init__(self):
        o = "Budget"
        _count(o, "max_steps", self.max_steps, 0, 8)
        _count(o, "top", self.top, 1, 16)
        _finite(o, "score_ratio", self.score_ratio, 1.0)
        _count(o, "max_nfev", self.max_nfev, 1, 100000)
        _finite(o, "tol", self.tol, 1e-15, 1.0)
        _count(o, "preroll", self.preroll, 0, 1000)


@dataclass(frozen=True)
class ConditioningOptions(_Options):
    """What is done to every record before fitting
    (:func:`~liquidamp.analysis.measured.conditioning.condition`).

    Attributes
    ----------
    force_cutoff : float or None
        Zero-phase force low-pass cut-off [Hz] (None: none).
    decimate : 'auto' or int
        Decimation factor (``'auto'``: keep ``harmonics`` harmonics; 1: none).
    harmonics : float
        Harmonics of the stroke frequency kept by ``decimate='auto'`` [-].
    average : 'auto', True or False
        Average the whole cycles of a periodic record into one.
    """

    force_cutoff: float | None = None
    decimate: object = "auto"
    harmonics: float = HARMONICS
    average: object = "auto"

    def __post_init__(self):
        o = "ConditioningOptions"
        if self.force_cutoff is not None:
            _finite(o, "force_cutoff", self.force_cutoff, 0.0, unit="Hz")
        _finite(o, "harmonics", self.harmonics, 1.0)
        if self.average not in ("auto", True, False):
            raise ParameterError(f"{o}: average must be 'auto', True or False, got "
                                 f"{self.average!r}")
        if self.decimate != "auto":
            _count(o, "decimate", self.decimate, 1, 10**6)

    def keywords(self) -> dict:
        """Keywords of :func:`~liquidamp.analysis.measured.conditioning.condition`."""
        return {"force_cutoff": self.force_cutoff, "decimate": self.decimate,
                "harmonics": self.harmonics, "average": self.average}


@dataclass(frozen=True)
class DiagnoseOptions(_Options):
    """Every knob of the diagnosis: selection rule, budget, conditioning, candidates, start.

    Attributes
    ----------
    selection : SelectionRule
    budget : Budget
    conditioning : ConditioningOptions
    candidates : tuple of str or None
        Candidates considered (None: every catalogue effect with fitted parameters and
        every composite).
    sizing : {'auto', 'preset', 'data'}
        The device the baseline calibration starts from (as for ``calibrate``).
    outliers : {'refuse', 'drop', 'keep'}
        Spikes found in the records as read
        (:func:`~liquidamp.analysis.measured.checks.check_records`): refuse the records
        (default), drop the force spikes before conditioning, or keep them.
    """

    selection: SelectionRule = field(default_factory=SelectionRule)
    budget: Budget = field(default_factory=Budget)
    conditioning: ConditioningOptions = field(default_factory=ConditioningOptions)
    candidates: tuple | None = None
    sizing: str = "auto"
    outliers: str = "refuse"

    def __post_init__(self):
        for name, cls in (("selection", SelectionRule), ("budget", Budget),
                          ("conditioning", ConditioningOptions)):
            if not isinstance(getattr(self, name), cls):
                raise ParameterError(f"DiagnoseOptions: {name} must be a {cls.__name__}, "
                                     f"got {type(getattr(self, name)).__name__}")
        if self.candidates is not None:
            if isinstance(self.candidates, str):
                raise ParameterError("DiagnoseOptions: candidates must be a sequence of "
                                     f"names, got the string {self.candidates!r}")
            object.__setattr__(self, "candidates", tuple(self.candidates))
        if self.sizing not in ("auto", "preset", "data"):
            raise ParameterError("DiagnoseOptions: sizing must be 'auto', 'preset' or "
                                 f"'data', got {self.sizing!r}")
        if self.outliers not in ("refuse", "drop", "keep"):
            raise ParameterError("DiagnoseOptions: outliers must be 'refuse', 'drop' or "
                                 f"'keep', got {self.outliers!r}")

    @classmethod
    def from_keywords(cls, base: DiagnoseOptions | None = None, **keywords) -> DiagnoseOptions:
        """Options from flat keywords (``max_steps=2``, ``bic_threshold=6``, ...) on top of
        ``base``; sub-objects may be given whole (``selection=SelectionRule(...)``).

        Raises
        ------
        ParameterError
            An unknown keyword (the valid ones listed) or a bad value.
        """
        base = base or cls()
        groups = {"selection": SelectionRule, "budget": Budget,
                  "conditioning": ConditioningOptions}
        where = {f.name: g for g, c in groups.items() for f in dataclasses.fields(c)}
        own = {f.name for f in dataclasses.fields(cls)}
        bad = sorted(set(keywords) - set(where) - own)
        if bad:
            raise ParameterError(f"diagnose: unknown option {bad[0]!r}; valid: "
                                 + ", ".join(sorted(set(where) | own)))
        top = {k: v for k, v in keywords.items() if k in own}
        out = base.replace(**top) if top else base
        for g in groups:
            sub = {k: v for k, v in keywords.items() if where.get(k) == g}
            if sub:
                out = dataclasses.replace(out, **{g: getattr(out, g).replace(**sub)})
        return out


#: Relative tolerance of the compiled march of records without periodic structure in a
#: diagnosis whose caller gave no solver options (the ``"fit"`` preset otherwise) [-].
#: Such a record is marched from rest over its whole span for every model run; its
#: integration error need only stay far below the record's noise: on the independent MR
#: record d10 (20 000 samples, true parameters) the force at rtol 1e-4 differs from the
#: force at 1e-6 by 6.4e-7 of its RMS (the noise floor is 8.8e-3) in 26 000 steps instead
#: of 59 000 (a third of the time).
BROADBAND_RTOL = 1e-4
#: Candidates refitted per step for records without periodic structure (the best score).
BROADBAND_TOP = 1


def broadband(records) -> bool:
    """Whether no record has periodic structure (every stroke broadband, none periodic or
    tapered).

    Such records have no periodic orbit to solve once and reuse: every model run marches
    each whole record from rest.  The diagnosis then marches at :data:`BROADBAND_RTOL`
    (where the caller gave no solver options, :func:`march_options`), refits the
    best-scoring candidate of each step alone (:data:`BROADBAND_TOP`; the score test ranks
    the rest) and restarts no refit from the physics start (it reads K', K'' at a stroke
    frequency such a record does not have).
    """
    return bool(records) and all(r.shape is not None and r.shape.kind == "broadband"
                                 for r in records)


def march_options(options, records):
    """The solver options of the diagnosis's fits: the caller's, else the ``"fit"`` preset,
    at :data:`BROADBAND_RTOL` where every record is broadband.

    Examples
    --------
    >>> import numpy as np
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 2.0, 1e-3)
    >>> sine = Record.from_arrays(t, 1e-3 * np.sin(2 * np.pi * 3 * t), 0 * t + 1.0)
    >>> multi = Record.from_arrays(t, sum(1e-3 / f * np.sin(2 * np.pi * f * t + f)
    ...                                   for f in (3.1, 4.7, 7.3, 11.9, 17.1)), 0 * t + 1.0)
    >>> broadband([sine]), broadband([multi]), broadband([sine, multi])
    (False, True, False)
    >>> march_options(None, [sine]).rtol, march_options(None, [multi]).rtol
    (1e-06, 0.0001)
    """
    given = options is not None
    options = resolve_options(options, "fit")
    if not given and broadband(records) and options.rtol < BROADBAND_RTOL:
        options = dataclasses.replace(options, rtol=BROADBAND_RTOL)
    return options
