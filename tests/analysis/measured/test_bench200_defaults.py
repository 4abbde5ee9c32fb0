"""The default diagnosis of the short 200 Hz bench records (``liquidamp bench --cases
diagnosis_200hz_10_cycles``, issue 19): the right effect first and alone, its parameter near
the truth."""

import pytest

from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

CASE = "diagnosis_200hz_10_cycles"


def test_a_leak_is_found_alone_through_the_valves_that_reduce_to_it():
    # The paper's device with a laminar bypass (2e-11 m^3/(s Pa), half the piston's flow at
    # the peak pressure): the fluid start's fit without it puts c1 at its lower bound, and
    # the score test ranks the digressive and the relief valve above the leak.  The
    # digressive valve's refit reaches the noise with its cracking pressures at their least
    # (the leak's limit) and is rejected at the bound; before the rule that refits the
    # candidates a rejected one reduces to, that refit "explained" the round, the leak was
    # never refitted, and the loop added backlash, a groove and the leak (48 s).
    cal, val = real_rate_records(CASE, "leakage")
    d = diagnose([cal], [val])
    assert d.added == ("leakage",), d.summary()
    truth = REAL_RATE_RECORDS[CASE][-1]["leakage"]["coefficient_m3_per_s_Pa"]
    assert d.steps[0].parameters["coefficient_m3_per_s_Pa"] == pytest.approx(truth, rel=0.05)
    leak = next(c for c in d.steps[0].candidates if c.effect == "leakage")
    assert "reduction" in leak.note and leak.accepted
    assert d.stop_reason.startswith("residual is noise")
    # the true multipliers (paper_calibrated: air x0.75 and x1.22, losses x3.56 and x4.04)
    v = d.final.values
    assert v["c1"] == pytest.approx(3.56, rel=0.05)
    assert v["inv_gamma2"] == pytest.approx(1.22, rel=0.02)
