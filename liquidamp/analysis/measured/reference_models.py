"""Reference models fitted beside the physics model: the line and the dyno's two-slope map.

A physics model earns its parameters only if it predicts held-out records better than what
an engineer gets without it.  Every calibration and diagnosis therefore also fits, on the
same calibration records (as conditioned) and judges on the same held-out records:

(a) the linear regression ``line``

        F = c v + k y + F0,

    c [N s/m], k [N/m], F0 [N], y the stroke as recorded (not centred: a gas spring's
    preload depends on the mean stroke), v the stroke rate; ordinary least squares over
    the pooled calibration samples;

(b) the two-slope force-velocity map ``two_slope`` per direction with its knee, what a
    damper dynamometer reports (bleed below the knee, blow-off above it):

        F = F0 + c_lo v                                  0 <= v <= v_k+
        F = F0 + c_lo v_k+ + c_hi (v - v_k+)              v > v_k+

    and likewise for v < 0 with its own (c_lo-, c_hi-, v_k-); seven parameters.  For given
    knees the map is linear in (F0, c_lo+, c_hi+, c_lo-, c_hi-); the knees are chosen on a
    grid of the quantiles of |v| in each direction (5 % to 95 %) by the least calibration
    sum of squares.

Both are judged by the NRMSE of :func:`~liquidamp.analysis.measured.record_model.nrmse` on
each record (held-out records one by one, the pooled figure beside them).

References
----------
.. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5 and 7
   (force-velocity characteristics, knee and blow-off; dynamometer practice).
.. [2] SAE J2855, "Shock absorber dynamometer test procedure" (peak force against peak
   velocity per direction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from liquidamp.analysis.measured.record_model import nrmse
from liquidamp.analysis.measured.record_quality import line_coefficients
from liquidamp.errors import ParameterError

__all__ = ["ReferenceFit", "fit_line", "fit_two_slope", "reference_models", "comparison"]

_KNEE_GRID = 15


@dataclass(frozen=True)
class ReferenceFit:
    """One reference model fitted on the calibration records and judged on every record.

    Attributes
    ----------
    name : str
        ``"line"`` or ``"two_slope"``.
    formula : str
        The model in words.
    parameters : dict
        Fitted parameters, SI, unit in the key.
    calibration, validation : tuple of (str, float)
        (record label, NRMSE [-]) per record.
    nrmse_calibration, nrmse_validation : float or None
        Pooled NRMSE of each set [-] (None: no record).
    """

    name: str
    formula: str
    parameters: dict
    calibration: tuple
    validation: tuple
    nrmse_calibration: float
    nrmse_validation: float | None

    def validation_of(self, label: str) -> float | None:
        """Held-out NRMSE on record ``label`` (None if not held out)."""
        return dict(self.validation).get(label)

    def as_dict(self) -> dict:
        """JSON-ready: formula, parameters, NRMSE per record and pooled."""
        return {"formula": self.formula, "parameters": dict(self.parameters),
                "nrmse": {"calibration": self.nrmse_calibration,
                          "validation": self.nrmse_validation},
                "records": ([{"record": lab, "role": "calibration", "nrmse": v}
                             for lab, v in self.calibration]
                            + [{"record": lab, "role": "validation", "nrmse": v}
                               for lab, v in self.validation])}


def _arrays(records):
    if not records:
        raise ParameterError("reference models need at least one calibration record")
    v = np.concatenate([np.asarray(r.velocity, float) for r in records])
    y = np.concatenate([np.asarray(r.smoothed, float) for r in records])
    F = np.concatenate([np.asarray(r.force, float) for r in records])
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(y)) and np.all(np.isfinite(F))):
        raise ParameterError("reference models: a record holds NaN or inf in its stroke, "
                             "stroke rate or force")
    return v, y, F


def _judge(name, formula, params, predict, calibration, validation) -> ReferenceFit:
    def per(recs):
        return tuple((r.label, nrmse(predict(r), r.force)) for r in recs)

    def pooled(recs):
        return nrmse([predict(r) for r in recs], [r.force for r in recs]) if recs else None

    return ReferenceFit(name, formula, params, per(calibration), per(validation),
                        pooled(calibration), pooled(validation))


def fit_line(calibration, validation=()) -> ReferenceFit:
    """Least-squares line F = c v + k y + F0 on the calibration records (module docstring).

    Parameters
    ----------
    calibration, validation : sequence of Record
        Records fitted, and held-out records judged.

    Returns
    -------
    ReferenceFit
        Parameters ``c [N s/m]``, ``k [N/m]``, ``F0 [N]``.

    Examples
    --------
    A pure dashpot with a spring and an offset is reproduced exactly:

    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 2, 0.005)
    >>> y = 0.003 * np.sin(2 * np.pi * 2 * t)
    >>> v = 0.003 * 2 * np.pi * 2 * np.cos(2 * np.pi * 2 * t)
    >>> r = Record.from_arrays(t, y, 2000 * v + 1e4 * y + 5.0)
    >>> f = fit_line([r], [r])
    >>> round(f.parameters["k [N/m]"] / 1e4, 3), round(f.parameters["F0 [N]"], 3)
    (1.0, 5.0)
    >>> f.nrmse_validation < 0.01
    True
    """
    calibration, validation = tuple(calibration), tuple(validation)
    c, k, f0 = line_coefficients(*_arrays(calibration))

    def predict(r):
        return c * np.asarray(r.velocity) + k * np.asarray(r.smoothed) + f0

    return _judge("line", "F = c v + k y + F0",
                  {"c [N s/m]": c, "k [N/m]": k, "F0 [N]": f0}, predict, calibration,
                  validation)


def _basis(v, kp, kn):
    pos = np.maximum(v, 0.0)
    neg = np.minimum(v, 0.0)
    return np.column_stack([np.ones_like(v), np.minimum(pos, kp), np.maximum(pos - kp, 0.0),
                            np.maximum(neg, -kn), np.minimum(neg + kn, 0.0)])


def _knees(speeds) -> np.ndarray:
    if speeds.size < 4:
        return np.array([math.inf])
    return np.unique(np.quantile(speeds, np.linspace(0.05, 0.95, _KNEE_GRID)))


def fit_two_slope(calibration, validation=()) -> ReferenceFit:
    """Two-slope force-velocity map per direction with its knee (module docstring).

    Parameters
    ----------
    calibration, validation : sequence of Record
        Records fitted, and held-out records judged.

    Returns
    -------
    ReferenceFit
        Parameters ``F0 [N]``, ``c_low_compression [N s/m]``, ``c_high_compression [N s/m]``,
        ``knee_compression [m/s]`` and the same for rebound (v < 0).

    Examples
    --------
    A map with a knee at 0.02 m/s each way is recovered on its own samples:

    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 2, 0.002)
    >>> y = 0.003 * np.sin(2 * np.pi * 3 * t)
    >>> v = np.gradient(y, t)
    >>> F = np.where(v > 0, np.minimum(v, 0.02) * 4e4 + np.maximum(v - 0.02, 0) * 1e4,
    ...              np.maximum(v, -0.02) * 3e4 + np.minimum(v + 0.02, 0) * 5e3)
    >>> f = fit_two_slope([Record.from_arrays(t, y, F)])
    >>> f.nrmse_calibration < 0.02
    True
    """
    calibration, validation = tuple(calibration), tuple(validation)
    v, _, F = _arrays(calibration)
    best = None
    for kp in _knees(v[v > 0]):
        for kn in _knees(-v[v < 0]):
            A = _basis(v, kp, kn)
            coef, *_ = np.linalg.lstsq(A, F, rcond=None)
            rss = float(np.sum((A @ coef - F) ** 2))
            if best is None or rss < best[0]:
                best = (rss, kp, kn, coef)
    _, kp, kn, coef = best
    f0, clp, chp, cln, chn = (float(x) for x in coef)

    def predict(r):
        return _basis(np.asarray(r.velocity, float), kp, kn) @ coef

    params = {"F0 [N]": f0, "c_low_compression [N s/m]": clp,
              "c_high_compression [N s/m]": chp, "knee_compression [m/s]": float(kp),
              "c_low_rebound [N s/m]": cln, "c_high_rebound [N s/m]": chn,
              "knee_rebound [m/s]": float(kn)}
    return _judge("two_slope", "F = F0 + two-slope force-velocity map per direction "
                  "(slopes below and above a knee, compression v > 0 and rebound v < 0)",
                  params, predict, calibration, validation)


def reference_models(calibration, validation=()) -> dict:
    """Both reference models on one split: ``{"line": ReferenceFit, "two_slope": ...}``.

    Parameters
    ----------
    calibration, validation : sequence of Record
        The records the physics model was fitted on and judged by (as conditioned).

    Returns
    -------
    dict of str to ReferenceFit
    """
    return {"line": fit_line(calibration, validation),
            "two_slope": fit_two_slope(calibration, validation)}


_NAMES = {"line": "the line F = c v + k y + F0",
          "two_slope": "the dyno's two-slope force-velocity map"}


def comparison(physics_validation: dict, refs: dict, tolerance: float = 0.0,
               name: str = "line") -> str:
    """Where the physics model does not beat a reference model on held-out records ('' when
    it does).

    Parameters
    ----------
    physics_validation : dict
        Record label -> held-out NRMSE of the physics model [-].
    refs : dict
        :func:`reference_models` output.
    tolerance : float
        Relative margin the physics model must win by [-].
    name : {'line', 'two_slope'}
        The reference model to compare with.

    Returns
    -------
    str
        E.g. ``"the physics model does not beat the line F = c v + k y + F0 on held-out
        record b.csv (0.63 vs 0.51)"``.

    Examples
    --------
    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 2, 0.005)
    >>> y = 0.003 * np.sin(2 * np.pi * 2 * t)
    >>> r = Record.from_arrays(t, y, 2000 * np.gradient(y, t) + 1e4 * y)  # a spring too
    >>> refs = reference_models([r], [r])
    >>> comparison({r.label: 0.99}, refs, name="two_slope")[:63]
    "the physics model does not beat the dyno's two-slope force-velo"
    >>> comparison({r.label: 0.01}, refs, name="two_slope")
    ''
    """
    if name not in _NAMES:
        raise ParameterError(f"comparison: reference model must be one of {sorted(_NAMES)}, "
                             f"got {name!r}")
    ref = refs.get(name)
    if ref is None or not physics_validation:
        return ""
    lost = [(lab, p, ref.validation_of(lab)) for lab, p in physics_validation.items()
            if ref.validation_of(lab) is not None
            and not p < (1.0 - tolerance) * ref.validation_of(lab)]
    if not lost:
        return ""
    return (f"the physics model does not beat {_NAMES[name]} on held-out "
            + ("record " if len(lost) == 1 else "records ")
            + ", ".join(f"{lab} ({p:.3g} vs {q:.3g})" for lab, p, q in lost))
