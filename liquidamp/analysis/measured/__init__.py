"""Measured data and identification: records, calibration, residual diagnosis, synthetic data.

* :mod:`.records` -- read, write and check test-machine records (CSV with units in the header);
  periodic, tapered or broadband strokes (:func:`~.records.stroke_shape`).
* :mod:`.record_quality` -- noise floor, spikes, energy sign, sampling, stroke against the
  chamber, before any fit.
* :mod:`.conditioning` -- before a fit: zero-phase force filter, anti-alias decimation, cycle
  average; the model force conditioned like the record's.
* :mod:`.record_model` -- drive a device model with a measured stroke; force error measures.
* :mod:`.fit_spec` -- what a calibration varies: :class:`~.fit_spec.Parameter`,
  :class:`~.fit_spec.FitSpec` (multipliers alpha_j of Table 2, effect parameters).
* :mod:`.start` -- where a calibration starts: a device sized to the records (similarity),
  the physics start, the trials and the refusal.
* :mod:`.calibration` -- least-squares fit of device parameters to records (Titurus 2018,
  Sec. IV.C, eq. 10 models); :mod:`.calibration_result` -- the result it returns.
* :mod:`.diagnosis` -- trace what a calibrated model misses to a catalogue effect, add it;
  its evidence (signatures, score test, confounded pairs) in :mod:`.diagnosis_evidence`, its
  selection rule (BIC over the effective number of samples) in :mod:`.selection`.
* :mod:`.synthetic` -- realistic synthetic records from a known model, with noise and distortion.
* ``data/`` -- bundled synthetic records (their recipe is in ``data/README.md``).
"""
