"""What a damper engineer reads off a test record, as numbers and arrays (no plotting).

A damper dynamometer reports [1]_ [2]_, per direction (compression: stroke rate v > 0, the
rod going into the damper; rebound: v < 0):

- the force-velocity loop split into its compression and rebound halves;
- the peak force against the peak velocity, one point per stroke (half cycle), with the
  knee between the low-speed (bleed) and the high-speed (blow-off) slope;
- the cycle-averaged force-velocity curve (the loop averaged over the cycles at equal phase);
- the gas force: the force at zero velocity at mid stroke, i.e. the offset of the loop at
  mid stroke with the damping removed;
- the low- and high-speed damping coefficients and the knee;
- for a model with a fitted ``gas_charge``, the model's gas force and gas rate at each
  record's mean stroke with their 95 % intervals (:func:`gas_charge_characteristics`).

The slopes and knees are those of the two-slope map per direction
(:func:`liquidamp.analysis.measured.reference_models.fit_two_slope`, reused here, not
refitted another way).  The gas force is the mean, over every crossing of the mid stroke
(half way between the extreme smoothed strokes), of F - (map(v) - F0): the measured force
with the map's damping force removed, so that an offset damper F = F_g + map(v) - F0 gives
F_g exactly whatever its asymmetry.

Everything here returns data; :mod:`liquidamp.analysis.reports.damper_plots` draws it.

References
----------
.. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5 and 7.
.. [2] SAE J2855, "Shock absorber dynamometer test procedure".
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from liquidamp.analysis.measured.reference_models import _basis, fit_two_slope
from liquidamp.errors import ParameterError

__all__ = ["damper_characteristics", "result_characteristics", "gas_charge_characteristics",
           "gas_line",
           "two_slope_curve",
           "peak_points", "cycle_average", "cycle_table", "KELVIN"]

#: 0 C in kelvin [K].
KELVIN = 273.15


def _check(record, force=None):
    F = np.asarray(record.force if force is None else force, float)
    v = np.asarray(record.velocity, float)
    if F.shape != v.shape:
        raise ParameterError(f"force has {F.size} samples, the record {v.size}; a model "
                             "force must be predicted on the record's samples")
    if not np.all(np.isfinite(F)):
        raise ParameterError("force holds NaN or inf; damper characteristics need finite "
                             "forces")
    return v, F


def _as_fit_input(record, force=None):
    """A record (or the same record with a model's force) as fit_two_slope reads it."""
    _, F = _check(record, force)
    return SimpleNamespace(velocity=np.asarray(record.velocity, float),
                           smoothed=np.asarray(record.smoothed, float), force=F,
                           label=getattr(record, "label", "record"))


def two_slope_curve(params: dict, v) -> np.ndarray:
    """Force of a fitted two-slope map at stroke rates ``v`` [m/s] -> [N].

    Parameters
    ----------
    params : dict
        ``ReferenceFit.parameters`` of :func:`fit_two_slope`.
    v : array_like
        Stroke rate [m/s].

    Examples
    --------
    >>> p = {"F0 [N]": 1.0, "c_low_compression [N s/m]": 10.0,
    ...      "c_high_compression [N s/m]": 2.0, "knee_compression [m/s]": 1.0,
    ...      "c_low_rebound [N s/m]": 10.0, "c_high_rebound [N s/m]": 2.0,
    ...      "knee_rebound [m/s]": 1.0}
    >>> two_slope_curve(p, [2.0, -0.5]).tolist()
    [13.0, -4.0]
    """
    v = np.atleast_1d(np.asarray(v, float))
    coef = np.array([params["F0 [N]"], params["c_low_compression [N s/m]"],
                     params["c_high_compression [N s/m]"], params["c_low_rebound [N s/m]"],
                     params["c_high_rebound [N s/m]"]])
    return _basis(v, params["knee_compression [m/s]"], params["knee_rebound [m/s]"]) @ coef


def _runs(sign):
    """(start, stop) index pairs of the runs of constant nonzero ``sign``."""
    edges = np.flatnonzero(np.diff(sign) != 0) + 1
    bounds = np.concatenate([[0], edges, [sign.size]])
    return [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:], strict=True)
            if sign[a] != 0]


def peak_points(record, force=None) -> dict:
    """Peak velocity and the force at it, one point per stroke, per direction.

    A stroke is a run of samples of one sign of the stroke rate; runs cut by the record's
    ends are dropped (their peak may be missing), and so are flickers about zero rate (runs
    shorter than a tenth of the median run, or peaking below 5 % of the largest |v|).

    Parameters
    ----------
    record : Record
    force : array_like, optional
        A model's force on the record's samples [N] (default the measured force).

    Returns
    -------
    dict
        ``{"compression": (v_peak [m/s], F [N]), "rebound": (...)}`` as arrays (rebound
        velocities negative).
    """
    v, F = _check(record, force)
    out = {"compression": ([], []), "rebound": ([], [])}
    runs = _runs(np.sign(v))[1:-1]
    shortest = 0.1 * float(np.median([b - a for a, b in runs])) if runs else 0.0
    floor = 0.05 * float(np.max(np.abs(v)))
    for a, b in runs:
        i = a + int(np.argmax(np.abs(v[a:b])))
        if b - a < shortest or abs(v[i]) < floor:
            continue
        key = "compression" if v[i] > 0 else "rebound"
        out[key][0].append(v[i])
        out[key][1].append(F[i])
    return {k: (np.array(x), np.array(y)) for k, (x, y) in out.items()}


def cycle_average(record, force=None, bins: int = 100) -> dict:
    """The loop averaged over the cycles at equal phase (periodic records).

    Parameters
    ----------
    record : Record
        A periodic record (``record.periodic``).
    force : array_like, optional
        A model's force on the record's samples [N].
    bins : int
        Phase bins per cycle (>= 8).

    Returns
    -------
    dict
        ``velocity`` [m/s], ``force`` [N], ``displacement`` [m] (smoothed), one value per
        occupied phase bin, in phase order.
    """
    if bins < 8:
        raise ParameterError(f"cycle_average: bins = {bins}; at least 8 allowed")
    if not record.periodic:
        raise ParameterError("cycle_average needs a periodic record; this stroke is "
                             f"{record.shape.kind if record.shape else 'not periodic'}")
    v, F = _check(record, force)
    t = np.asarray(record.time, float)
    k = np.floor(((t - t[0]) * record.frequency % 1.0) * bins).astype(int).clip(0, bins - 1)
    n = np.bincount(k, minlength=bins)
    ok = n > 0

    def mean(x):
        return np.bincount(k, weights=x, minlength=bins)[ok] / n[ok]

    return {"velocity": mean(v), "force": mean(F),
            "displacement": mean(np.asarray(record.smoothed, float))}


def _mid_stroke_offset(record, F, params) -> float:
    y = np.asarray(record.smoothed, float)
    v = np.asarray(record.velocity, float)
    mid = 0.5 * (float(np.max(y)) + float(np.min(y)))
    r = F - (two_slope_curve(params, v) - params["F0 [N]"])
    s = y - mid
    i = np.flatnonzero(np.sign(s[:-1]) * np.sign(s[1:]) < 0)
    if i.size == 0:
        raise ParameterError("the stroke never crosses its mid point; no gas force")
    w = s[i] / (s[i] - s[i + 1])
    return float(np.mean(r[i] + w * (r[i + 1] - r[i])))


def cycle_table(record, force=None) -> dict:
    """Force amplitude and mean temperature cycle by cycle.

    A cycle is one excitation period (``1 / record.frequency``; for a broadband record the
    periodogram peak's period, a window of the same length); incomplete last windows are
    dropped.

    Returns
    -------
    dict
        ``time`` (window centre) [s], ``force_amplitude`` (half the peak-to-peak force)
        [N], ``temperature`` [K] or None without a ``temperature`` channel.
    """
    _, F = _check(record, force)
    t = np.asarray(record.time, float)
    k = np.floor((t - t[0]) * record.frequency).astype(int)
    ncyc = int(k[-1])  # the last, incomplete window dropped
    if ncyc < 1:
        raise ParameterError("cycle_table: the record holds less than one whole cycle")
    T = record.channels.get("temperature")
    rows = [np.flatnonzero(k == j) for j in range(ncyc)]
    return {"time": np.array([t[i].mean() for i in rows]),
            "force_amplitude": np.array([0.5 * np.ptp(F[i]) for i in rows]),
            "temperature": None if T is None else np.array([T[i].mean() for i in rows])}


def damper_characteristics(record, force=None) -> dict:
    """Gas force, low- and high-speed damping and knees of a record (module docstring).

    Parameters
    ----------
    record : Record or sequence of Record
        One record, or several (one map fitted on them together; the gas force is then
        the mean of the records' mid-stroke offsets).
    force : array_like or sequence of array_like, optional
        A model's force on each record's samples [N] (the model's characteristics).

    Returns
    -------
    dict
        JSON-ready, SI with the unit in each key: ``gas_force [N]`` (mid-stroke offset),
        ``zero_velocity_force [N]`` (the map's F0), and per direction ``compression`` /
        ``rebound``: ``c_low [N s/m]``, ``c_high [N s/m]``, ``knee_velocity [m/s]``,
        ``knee_force [N]`` (F0 + c_low x knee, signed), ``peak_velocity [m/s]``;
        ``two_slope`` the fitted map's parameters; ``reference`` the method.

    Examples
    --------
    An offset two-slope damper gives back its numbers:

    >>> from liquidamp.analysis.measured.records import Record
    >>> t = np.arange(0, 2, 0.001)
    >>> y = 0.01 * np.sin(2 * np.pi * 2 * t)
    >>> v = 0.01 * 2 * np.pi * 2 * np.cos(2 * np.pi * 2 * t)
    >>> F = 150 + np.where(v > 0, 4e3 * np.minimum(v, .05) + 1e3 * np.maximum(v - .05, 0),
    ...                    2e3 * np.maximum(v, -.05) + 5e2 * np.minimum(v + .05, 0))
    >>> d = damper_characteristics(Record.from_arrays(t, y, F))
    >>> abs(d["gas_force [N]"] - 150) < 2, abs(d["compression"]["c_low [N s/m]"] / 4e3 - 1) < 0.1
    (True, True)
    """
    recs = [record] if hasattr(record, "velocity") else list(record)
    if not recs:
        raise ParameterError("damper_characteristics: no record given")
    if force is None:
        forces = [None] * len(recs)
    elif hasattr(record, "velocity"):
        forces = [force]
    else:
        forces = list(force)
    if len(forces) != len(recs):
        raise ParameterError(f"damper_characteristics: {len(forces)} model forces for "
                             f"{len(recs)} records")
    fit = fit_two_slope([_as_fit_input(r, f) for r, f in zip(recs, forces, strict=True)])
    p = fit.parameters
    gas = float(np.mean([_mid_stroke_offset(r, _check(r, f)[1], p)
                         for r, f in zip(recs, forces, strict=True)]))
    vmax = max(float(np.max(r.velocity)) for r in recs)
    vmin = min(float(np.min(r.velocity)) for r in recs)
    out = {"gas_force [N]": gas, "zero_velocity_force [N]": p["F0 [N]"]}
    for d, sign, peak in (("compression", 1.0, vmax), ("rebound", -1.0, vmin)):
        knee = p[f"knee_{d} [m/s]"]
        out[d] = {"c_low [N s/m]": p[f"c_low_{d} [N s/m]"],
                  "c_high [N s/m]": p[f"c_high_{d} [N s/m]"],
                  "knee_velocity [m/s]": sign * knee,
                  "knee_force [N]": float(two_slope_curve(p, [sign * knee])[0]),
                  "peak_velocity [m/s]": peak}
    out["two_slope"] = dict(p)
    out["reference"] = ("two-slope map per direction (reference_models.fit_two_slope); gas "
                        "force = mean over the mid-stroke crossings of F minus the map's "
                        "damping force")
    return out


def result_characteristics(result) -> dict:
    """Measured and model damper characteristics of a calibration, JSON-ready.

    Parameters
    ----------
    result : CalibrationResult
        Its calibration records (as fitted) and its model's predictions on them.

    Returns
    -------
    dict
        ``{"records": [labels], "measured": {...}, "model": {...}}`` as
        :func:`damper_characteristics`, or ``{"records": [...], "error": message}`` when
        the records do not allow them (e.g. a stroke that never crosses its mid point).
    """
    recs = list(result.calibration)
    out = {"records": [r.label for r in recs]}
    gas = gas_charge_characteristics(result)
    try:
        out["measured"] = damper_characteristics(recs)
        out["model"] = damper_characteristics(recs, list(result.predictions_calibration))
    except ParameterError as exc:
        out = {"records": out["records"], "error": str(exc)}
    if gas is not None:
        out["gas_charge"] = gas
    return out


#: Gas-charge parameters whose fit covariance enters the gas force's interval.
_GAS_KEYS = ("charge_pressure_Pa", "rod_area_m2", "gas_volume_m3", "polytropic_index")


def gas_charge_characteristics(result) -> dict | None:
    """The fitted gas charge's force and rate at each record's mean stroke, 95 % intervals.

    A record about one mean stroke sees the gas force F_g(y) = A_r (p_g(y) - p_a) and its
    rate dF_g/dy near that stroke; the charge p_c, rod area A_r and gas volume V_g
    separately trade off (a larger charge on a smaller rod gives the same force and, with a
    smaller volume, the same rate), so these two numbers at the records' strokes are what
    the records identify (issue #20).  Their intervals are 1.96 standard errors by the delta
    method: the gradient of each in the fitted gas parameters (central differences, 1e-5
    relative) on the sub-block of the fit covariance (the gas force depends on nothing
    else).  The preload at the stroke datum (y = 0) is an extrapolation beyond the records
    when no record reaches it, and is reported with its interval too.

    Parameters
    ----------
    result : CalibrationResult
        A calibration or a diagnosis's final fit.

    Returns
    -------
    dict or None
        None without ``gas_charge``; else ``{"records": [{"record", "role",
        "mean_stroke [m]", "gas_force [N]", "gas_force_95 [N]", "gas_rate [N/m]",
        "gas_rate_95 [N/m]"}, ...], "datum": {...} (y = 0), "parameters": {...},
        "correlation": {pair: r}, "note": str}``; an interval is None where a standard
        error is not finite.

    References
    ----------
    .. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Sec. 5.9.
    """
    g = next((e for e in getattr(result, "effects", ()) if e.name == "gas_charge"), None)
    if g is None:
        return None
    g = g.replace(stroke_offset_m=0.0)
    keys = [k for k in _GAS_KEYS if f"gas_charge.{k}" in result.varying]
    idx = [list(result.varying).index(f"gas_charge.{k}") for k in keys]
    se = np.array([float(result.stderr.get(f"gas_charge.{k}", np.nan)) for k in keys])
    cov = (np.asarray(result.correlation, float)[np.ix_(idx, idx)] * np.outer(se, se)
           if keys else np.zeros((0, 0)))

    def with_interval(fn):
        v = float(fn(g))
        if not keys:
            return v, None
        grad = []
        for k in keys:
            x = float(getattr(g, k))
            h = 1e-5 * abs(x)
            grad.append((fn(g.replace(**{k: x + h})) - fn(g.replace(**{k: x - h}))) / (2 * h))
        grad = np.array(grad)
        var = float(grad @ cov @ grad)
        if not (np.all(np.isfinite(se)) and np.isfinite(var) and var >= 0):
            return v, None
        d = 1.96 * var ** 0.5
        return v, [v - d, v + d]

    def at(y, label, role):
        F, Fi = with_interval(lambda e: e.force(y))
        k, ki = with_interval(lambda e: e.stiffness(y))
        return {"record": label, "role": role, "mean_stroke [m]": float(y),
                "gas_force [N]": F, "gas_force_95 [N]": Fi,
                "gas_rate [N/m]": k, "gas_rate_95 [N/m]": ki}

    rows = [at(r.offset, r.label, "calibration") for r in result.calibration]
    rows += [at(r.offset, r.label, "validation") for r in result.validation]
    corr = {f"{keys[i]}/{keys[j]}": float(result.correlation[idx[i], idx[j]])
            for i in range(len(keys)) for j in range(i + 1, len(keys))}
    return {"records": rows, "datum": at(0.0, "stroke datum y = 0", "extrapolated"),
            "parameters": {k: float(getattr(g, k)) for k in _GAS_KEYS + ("ambient_pressure_Pa",)},
            "correlation": corr,
            "note": ("the gas force and rate at the records' mean strokes are what the records "
                     "identify; charge pressure, rod area and gas volume separately trade off "
                     "(see their correlations)")}


def gas_line(gas: dict) -> str:
    """One line of :func:`gas_charge_characteristics`: force and rate at each mean stroke.

    Examples
    --------
    >>> row = {"record": "cal", "mean_stroke [m]": -0.031, "gas_force [N]": 15.5,
    ...        "gas_force_95 [N]": [14.0, 17.0], "gas_rate [N/m]": 300.0,
    ...        "gas_rate_95 [N/m]": None}
    >>> gas_line({"records": [row], "datum": dict(row, **{"mean_stroke [m]": 0.0})})[:67]
    'gas charge: cal (mean stroke -31 mm): gas force 15.5 N (95 % 14-17)'
    """
    def one(r):
        fi, ki = r["gas_force_95 [N]"], r["gas_rate_95 [N/m]"]
        f = f"gas force {r['gas_force [N]']:.3g} N" + (
            f" (95 % {fi[0]:.3g}-{fi[1]:.3g})" if fi else "")
        k = f"rate {r['gas_rate [N/m]'] / 1e3:.3g} N/mm" + (
            f" (95 % {ki[0] / 1e3:.3g}-{ki[1] / 1e3:.3g})" if ki else "")
        return f"{r['record']} (mean stroke {r['mean_stroke [m]'] * 1e3:.3g} mm): {f}, {k}"

    d = gas["datum"]
    return ("gas charge: " + "; ".join(one(r) for r in gas["records"])
            + f"; preload at the stroke datum {d['gas_force [N]']:.3g} N (extrapolated)")
