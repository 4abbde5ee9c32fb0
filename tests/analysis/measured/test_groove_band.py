"""The bypass groove's probe is placed from the residual (``candidates.groove_band``).

A record of the toolkit's own simulator with a groove 1 mm off the model's zero, read
through an LVDT whose zero is 2 mm off (the groove then sits at 3 mm of the record's
absolute stroke, 2 mm its mean): the calibrated model without the groove leaves a residual
whose apparent damping against stroke position peaks there.  The profile's grid spacing is
a tenth of the amplitude (0.3 mm) and the signature is quasi-static (the fluid's lag moves
the apparent band by a fraction of that), so the centre is asserted within 0.2 of the
amplitude and the half-width within 30 %.  Cost: about 8 s warm (one calibration).
"""

import pytest

from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.candidates import groove_band, probe_effect
from liquidamp.analysis.measured.synthetic import synthetic_record


def test_the_band_profile_of_the_residual_peaks_at_the_groove_on_the_absolute_stroke():
    rec = synthetic_record(preset="paper_calibrated", frequency=3.0, amplitude=0.003,
                           cycles=3, seed=5, displacement_offset=2e-3,
                           effects={"bypass_groove": {"depth": 0.4, "centre_m": 1e-3,
                                                      "half_width_m": 1e-3}})
    assert rec.offset == pytest.approx(2e-3, abs=5e-5)
    res = calibrate([rec], warn=False)
    centre, width, drop = groove_band(res)
    assert centre == pytest.approx(3e-3, abs=0.2 * 3e-3)
    assert width == pytest.approx(1e-3, rel=0.3)
    assert 0.5 < drop <= 1.0       # most of the residual is the band's
    probe = probe_effect("bypass_groove", res)
    assert (probe.centre_m, probe.half_width_m) == (centre, width)
