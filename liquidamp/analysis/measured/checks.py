"""The data checks of a fit: every record checked as read, before any model run.

Stage "check" of the measured-data pipeline (read, check, condition, start, fit, select,
report): :func:`check_records` runs
:func:`~liquidamp.analysis.measured.record_quality.check_record` on each record as read
(a conditioned record's checks run on the record it was made from:
:func:`~liquidamp.analysis.measured.record_quality.as_read`; filtering and decimation come
after and cannot manufacture a spike), and lists everything that cannot be fitted in one
error, each problem with its record, count and the file's own line numbers.  What to do with
spikes is ``outliers`` (``--outliers`` on the command line): ``'refuse'`` (default),
``'drop'`` (:func:`drop_outliers`) or ``'keep'``.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B (the measured data).
"""

from __future__ import annotations

import dataclasses
import math
import weakref

import numpy as np

from liquidamp.analysis.measured.record_quality import (
    DataQuality,
    as_read,
    check_record,
    check_record_stroke,
)
from liquidamp.analysis.measured.records import Record
from liquidamp.device.params import DeviceParams
from liquidamp.errors import DataFileError, check_choice

__all__ = ["check_records", "drop_outliers", "keep_outliers", "dropped_outliers",
           "OUTLIER_CHOICES", "orient_force", "FORCE_SIGNS", "FLIP_SHARE"]


#: What to do with the spikes :func:`check_records` finds (``outliers=``; ``--outliers`` on
#: the command line): refuse the records, drop the force spikes, or keep them as recorded.
OUTLIER_CHOICES = ("refuse", "drop", "keep")


#: How a record's force sign is read (``force_sign=`` of :func:`orient_force`;
#: ``--force-sign`` on the command line): ``'auto'`` negates a loop that runs a damper
#: backwards, ``'as-read'`` keeps every sign as recorded, ``'flip'`` negates every force.
FORCE_SIGNS = ("auto", "as-read", "flip")

#: Least share of RMS(F) RMS(v) a recorded loop must deliver (and more than
#: :data:`FLIP_SIGMAS` standard errors) for ``force_sign='auto'`` to read its force negated
#: [-].  A damper recorded with the other sign convention delivers nearly all of it (the
#: shared relief-valve record, negated: 79-88 %); a stiff device whose channels are a few
#: samples apart delivers a few percent, and stays refused by the data checks (they refuse
#: from 5 %), not turned into a negative stiffness.
FLIP_SHARE = 0.25
#: Standard errors of the delivered power ``force_sign='auto'`` needs besides [-].
FLIP_SIGMAS = 5.0


def orient_force(record: Record, force_sign: str = "auto") -> Record:
    """The record with its force in liquidamp's sign convention (stage "check", first).

    liquidamp reads the force the device exerts on the load cell, positive where it resists
    a positive stroke: a passive device absorbs energy, the loop integral of F dy is
    positive.  Laboratories record either sign (tension or compression positive); a damper
    recorded with the other one draws its loop backwards and delivers energy, which no
    passive device does.  ``'auto'`` reads such a record with its force negated where the
    loop delivers at least :data:`FLIP_SHARE` of RMS(F) x RMS(v) of power, beyond
    :data:`FLIP_SIGMAS` standard errors of its noise (the energy test of
    :func:`~liquidamp.analysis.measured.record_quality.check_record`, stricter); a loop
    that delivers less stays as read (and is refused by :func:`check_records` where it
    delivers energy at all).  A negated stroke would do the same for a symmetric device;
    for an asymmetric one the two readings are mirror images (compression and rebound
    swapped), and the force is the one negated.  What was done is kept in
    ``meta["force_sign"]`` (the reason, with the figures), reported by the data checks
    (:attr:`DataQuality.force_negated
    <liquidamp.analysis.measured.record_quality.DataQuality.force_negated>`) and led by
    ``FORCE NEGATED`` in the calibration's and the diagnosis's summaries.

    Parameters
    ----------
    record : Record
        A record as read (not conditioned).
    force_sign : {'auto', 'as-read', 'flip'}
        ``'auto'`` (default): negate a loop run backwards; ``'as-read'``: keep the sign;
        ``'flip'``: negate the force.

    Returns
    -------
    Record
        ``record`` itself, or a copy with the force negated.

    Raises
    ------
    ParameterError
        ``force_sign`` not one of :data:`FORCE_SIGNS`.

    References
    ----------
    .. [1] J. C. Dixon, The Shock Absorber Handbook, 2nd ed., Wiley, 2007, Ch. 5 (the loop
       of a damper and its work per cycle).

    Examples
    --------
    >>> t = np.arange(0, 2.0, 0.005)
    >>> y = 0.003 * np.sin(6 * np.pi * t)
    >>> backwards = Record.from_arrays(t, y, -500 * np.cos(6 * np.pi * t), source="b.csv")
    >>> r = orient_force(backwards)
    >>> bool(np.all(r.force == -backwards.force)), r.meta["force_sign"][:46]
    (True, 'the loop as recorded delivers 14.1 W (100% of ')
    >>> orient_force(backwards, "as-read") is backwards
    True
    """
    check_choice("force_sign", force_sign, FORCE_SIGNS)
    if force_sign == "as-read" or "force_sign" in record.meta:
        return record
    if force_sign == "auto":
        q = _checked(record, None)  # cached: the data checks reuse it for a record kept
        P, sP, share = q.dissipated_power, q.dissipated_power_std, q.loss_share
        if not (share < -FLIP_SHARE and P < -FLIP_SIGMAS * sP):
            return record
        why = (f"the loop as recorded delivers {-P:.4g} W ({-share:.0%} of RMS(F) x RMS(v), "
               f"{-P / sP if sP > 0 else math.inf:.3g} standard errors), a damper's loop drawn "
               "backwards: the force was recorded with the other sign convention; read "
               "negated (force_sign 'auto'; 'as-read' keeps it and refuses the record)")
    else:
        why = "force_sign 'flip': every force read negated"
    return dataclasses.replace(record, force=-record.force,
                               meta={**record.meta, "force_sign": why})


def _option(value: str, cli: bool) -> str:
    """How the caller spells ``outliers=value``: a keyword, or a command-line option."""
    return f"--outliers {value}" if cli else f"outliers={value!r}"


def _lines(outs, first: int = 12) -> str:
    """'line 42', or 'lines 42, 107 and 162' (the first ``first``, then how many more)."""
    lines = [str(o.line) for o in outs]
    if len(lines) == 1:
        return f"line {lines[0]}"
    more = len(lines) - first
    shown = lines[:first]
    if more > 0:
        return "lines " + ", ".join(shown) + f" and {more} more"
    return "lines " + ", ".join(shown[:-1]) + f" and {shown[-1]}"


def check_records(records, params: DeviceParams | None = None, *, outliers: str = "refuse",
                  what: str = "calibrate",
                  cli: bool = False) -> tuple[tuple[DataQuality, ...], tuple]:
    """Check records before a fit, as read; raise listing everything that cannot be fitted.

    Each record is checked as read (:func:`~liquidamp.analysis.measured.record_quality.as_read`:
    a conditioned record's checks run on the record it was made from, never on the samples
    the filters, the decimation or the average made), by
    :func:`~liquidamp.analysis.measured.record_quality.check_record`.  Every problem of
    every record is listed in one error, each with its record, its count and the file's own
    line numbers (header = line 1).

    Parameters
    ----------
    records : sequence of Record
        Every record of the fit (calibration and validation).
    params : DeviceParams, optional
        Device whose chamber end bounds the stroke.
    outliers : {'refuse', 'drop', 'keep'}
        Spikes: ``'refuse'`` (default) the records that hold any; ``'drop'`` the force
        spikes (returned, to be left out of the fit; a displacement spike is still
        refused: the stroke drives the model); ``'keep'`` every spike, fitted as recorded.
    what : str
        Name of the caller in the messages.
    cli : bool
        Spell the advice as the command-line option ``--outliers`` (else as the keyword
        ``outliers=``), so that a message names only options that exist where it is read.

    Returns
    -------
    (tuple of DataQuality, tuple of (label, Outlier))
        The checks of the records as read and the force samples to drop (empty unless
        ``'drop'``; indices and lines of the records as read).

    Raises
    ------
    DataFileError
        A record holds no force response above its noise, a loop that delivers energy, a
        stroke past the chamber end, a displacement spike (unless ``'keep'``), or a force
        spike (``'refuse'``): every such record, problem, count and line is named.

    Examples
    --------
    >>> t = np.arange(0, 2.0, 0.005)
    >>> F = 500 * np.sin(2 * np.pi * 3 * t + 0.3)
    >>> F[[100, 200]] = 5e4
    >>> rec = Record.from_arrays(t, 0.003 * np.sin(2 * np.pi * 3 * t), F, source="a.csv")
    >>> try:
    ...     check_records([rec], cli=True)
    ... except DataFileError as e:
    ...     print(str(e)[:73])
    calibrate: a.csv: 2 force outlier(s) on lines 102 and 202 (spikes against
    >>> len(check_records([rec], outliers="drop")[1])
    2
    """
    check_choice("outliers", outliers, OUTLIER_CHOICES)
    records = tuple(records)
    read = tuple(as_read(r) for r in records)
    qs = tuple(_checked(r, params) for r in read)
    items, kinds = [], set()
    for q, r in zip(qs, read, strict=True):
        items += list(q.problems)
        # spikes the user chose to keep (keep_outliers) stay kept in every later fit
        kept = {(o.column, o.index) for o in r.meta.get("kept", ())}
        disp = [o for o in q.outliers if o.column == "displacement"
                and (o.column, o.index) not in kept]
        force = [o for o in q.outliers if o.column == "force" and (o.column, o.index) not in kept]
        if disp and outliers != "keep":
            kinds.add("displacement")
            items.append(
                f"{q.source}: {len(disp)} displacement spike(s) on {_lines(disp)} (spikes "
                "against the record's local rates, check_record): "
                + _listed([f"{q.source}, {o.describe()}" for o in disp], 3))
        if force and outliers == "refuse":
            kinds.add("force")
            items.append(
                f"{q.source}: {len(force)} force outlier(s) on {_lines(force)} (spikes against "
                "the record's local rates, check_record): "
                + _listed([f"{q.source}, {o.describe()}" for o in force], 3))
    if items:
        advice = []
        if "force" in kinds:
            advice.append(f"force outliers: correct the file, or pass {_option('drop', cli)} "
                          "to leave these samples out of the fit and the error measures (the "
                          f"result lists them), or {_option('keep', cli)} to fit them as "
                          "recorded")
        if "displacement" in kinds:
            advice.append("displacement spikes: the recorded stroke drives the model, so these "
                          "samples cannot be dropped: correct or remove them in the file, or "
                          f"pass {_option('keep', cli)} to fit the stroke as recorded")
        bad = sum(1 for q in qs if any(q.source in i for i in items))
        raise DataFileError(f"{what}: " + "; ".join(items)
                            + (f" ({len(items)} problems in {bad} of {len(qs)} records)"
                               if len(items) > 1 else "")
                            + ("; " + "; ".join(advice) if advice else ""))
    force = tuple((r.label, o) for r, q in zip(records, qs, strict=True) for o in q.outliers
                  if o.column == "force") if outliers == "drop" else ()
    return qs, force


def drop_outliers(record: Record, quality: DataQuality) -> Record:
    """The record with the force spikes of ``quality`` dropped, before any conditioning.

    The record as read (:func:`~liquidamp.analysis.measured.record_quality.as_read`) gets
    each force spike replaced by the line between the samples just outside it
    (``Outlier.expected``), so that no filter spreads it, and lists them in
    ``meta["dropped"]``; a record that was conditioned is conditioned again, as it was,
    from that record.  Where the fitted samples are those of the record as read (not
    conditioned), the dropped ones are also left out of the residual and of every error
    measure (:func:`calibrate`); a filtered, decimated or averaged record fits the
    conditioned force made from the line instead.
    """
    force = tuple(o for o in quality.outliers if o.column == "force")
    if not force:
        return record
    read = as_read(record)
    F = np.array(read.force)
    idx = [o.index for o in force]
    F[idx] = [o.expected for o in force]
    fixed = dataclasses.replace(read, force=F, meta={**read.meta, "dropped": force})
    cond = record.meta.get("conditioning")
    if cond is None or record is read:
        return fixed
    from liquidamp.analysis.measured.conditioning import recondition

    return recondition(fixed, cond)


#: The checks of each record as read (a Record is immutable: its checks do not change), so
#: that a command, a diagnosis and each of its refits check a record once.
_CHECKED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _checked(record: Record, params: DeviceParams | None) -> DataQuality:
    """check_record(record, params), the part that does not depend on ``params`` computed
    once per record."""
    q = _CHECKED.get(record)
    if q is None:
        q = _CHECKED[record] = check_record(record)
    if params is None:
        return q
    return dataclasses.replace(q, problems=q.problems + tuple(check_record_stroke(record, params)),
                               stroke_limit=float(params.stroke_limit))


def keep_outliers(record: Record, quality: DataQuality) -> Record:
    """The record with the spikes of ``quality`` marked as kept (``outliers='keep'``).

    Its record as read lists them in ``meta["kept"]``, so that every later check of it
    (:func:`check_records`, e.g. in the refits of a diagnosis) accepts them; the samples
    are fitted as recorded.  A conditioned record keeps its conditioned samples.
    """
    if not quality.outliers:
        return record
    return _with_read_meta(record, "kept", tuple(quality.outliers))


def _with_read_meta(record: Record, key: str, value) -> Record:
    """``record`` whose record as read holds ``meta[key] = value`` (the chain of
    conditionings rebuilt; nothing else changes)."""
    cond = record.meta.get("conditioning")
    prior = getattr(cond, "record", None)
    if prior is None or prior is record:
        return dataclasses.replace(record, meta={**record.meta, key: value})
    cond = dataclasses.replace(cond, record=_with_read_meta(prior, key, value))
    return dataclasses.replace(record, meta={**record.meta, "conditioning": cond})


def dropped_outliers(records) -> tuple:
    """(label, Outlier) of the force samples dropped from each record (as read)."""
    return tuple((r.label, o) for r in records for o in as_read(r).meta.get("dropped", ()))


def _listed(items: list[str], first: int = 5) -> str:
    """The first ``first`` items joined by '; ', then how many more there are."""
    more = len(items) - first
    return "; ".join(items[:first]) + (f"; and {more} more" if more > 0 else "")
