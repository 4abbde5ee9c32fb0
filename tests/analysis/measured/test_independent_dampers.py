"""Issue #20's effects on the independent records (CC0, an independent simulator).

d09, the gas charge: its absolute stroke is kept.

The two records of ``d09_gas_charge`` (an independent simulator's single-rod damper, 100 psi
on a 45 mm^2 rod, its displacement column the ABSOLUTE stroke, means -31 mm and -12 mm) are
fitted together with the gas charge given explicitly (rod area known, charge pressure and
gas volume fitted) on the truth's device geometry: the charge pressure within 10 % of the
truth's, the gas volume within 30 %, both records to an NRMSE of a few per cent.  Without
the effect the fit cannot follow the preload that changes with the mean stroke.

d02, a relief valve (0.9 MPa, 3e-11 m^3/(s Pa) both ways) fitted as a digressive valve pair:
each direction's cracking pressure and conductance recovered (within 5 % and 15 %; the
command line gives 0.899 / 0.904 MPa and 2.95e-11 / 3.05e-11 m^3/(s Pa)).
"""

import json

import pytest

from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.fit_spec import FitSpec
from liquidamp.analysis.measured.records import read_record
from liquidamp.device import preset
from liquidamp.device.effects import DigressiveValve, GasCharge


def _truth(folder, case):
    truth = json.loads((folder / "truth.json").read_text())[case]
    dev = truth["device"]
    keys = set(dev["multipliers"]) | set(dev["overrides"])
    return truth, preset(dev["preset"]).replace(**{k: dev["values"][k] for k in keys})


def test_d09_gas_charge_fitted_on_both_mean_strokes(independent_records):
    truth, params = _truth(independent_records, "d09_gas_charge")
    recs = [read_record(independent_records / f"d09_gas_charge_{r}.csv") for r in ("cal", "val")]
    assert [r.offset for r in recs] == pytest.approx([-0.031, -0.012], abs=2e-4)
    sim = truth["simulator_settings"]
    p_c = sim["p_g0"] - truth["parameters"]["atmospheric pressure"]["value"]  # gauge 689 kPa
    start = GasCharge(sim["A_r"], 4e5, 4e-6, sim["n_g"])
    # the rod area known (the catalogue's default fit keys free it too)
    spec = FitSpec.default().with_effect(start, keys=("charge_pressure_Pa", "gas_volume_m3"))
    res = calibrate(recs, params=params, effects=(start,), spec=spec, sizing="preset",
                    max_nfev=60)
    g = res.device_model.effect("gas_charge")
    assert g.charge_pressure_Pa == pytest.approx(p_c, rel=0.10)
    assert g.gas_volume_m3 == pytest.approx(sim["V_g0"], rel=0.30)
    assert res.nrmse_calibration < 0.03
    # the preload at y = 0: 31.0 N in the truth
    assert g.force(0.0) == pytest.approx(31.0, abs=3.0)


def test_d02_relief_valve_recovered_per_direction(independent_records):
    truth, params = _truth(independent_records, "d02_relief_valve")
    recs = [read_record(independent_records / f"d02_relief_valve_{r}.csv") for r in ("cal", "val")]
    start = DigressiveValve(6e5, 1e-11, 6e5, 1e-11)
    res = calibrate(recs[:1], params=params, effects=(start,), validate=recs[1:],
                    sizing="preset", max_nfev=80)
    d = res.device_model.effect("digressive_valve")
    p_r, G = truth["simulator_settings"]["p_relief"], truth["simulator_settings"]["G_relief"]
    assert d.compression_cracking_Pa == pytest.approx(p_r, rel=0.05)
    assert d.rebound_cracking_Pa == pytest.approx(p_r, rel=0.05)
    assert d.compression_conductance_m3_per_s_Pa == pytest.approx(G, rel=0.15)
    assert d.rebound_conductance_m3_per_s_Pa == pytest.approx(G, rel=0.15)
    # raw records (the command line averages them first: 0.0013 / 0.0017 there); the 5 Hz
    # record's 21-point Savitzky-Golay velocity is 1.3 % low
    assert res.nrmse_calibration < 0.01 and res.nrmse_validation < 0.05


def test_d09_default_diagnosis_finds_the_gas_charge(independent_records):
    """Issue #20 must-show: the DEFAULT diagnosis adds gas_charge first, its identifiable
    numbers -- the gas force and rate at the calibration record's mean stroke (15.5 N and
    0.30 N/mm in truth.json's closed forms) and the preload at the datum A_r p_c (31.0 N)
    -- within 30 %, the held-out NRMSE at least halved.  The baseline's chambers are freed
    to their pressure level first (``pressure_level``, a device step, p0 about 4 bar on the
    sized piston), then the gas adds the rod at that level.  Opt-in (1-3 min, measured
    128 s under load): LIQUIDAMP_INDEPENDENT=all."""
    import os

    from liquidamp.analysis.measured.diagnosis import diagnose
    from liquidamp.analysis.reports.damper_characteristics import gas_charge_characteristics

    if os.environ.get("LIQUIDAMP_INDEPENDENT") != "all":
        pytest.skip("long held-out check: set LIQUIDAMP_INDEPENDENT=all to run it")
    truth = json.loads((independent_records / "truth.json").read_text())["d09_gas_charge"]
    closed = truth["closed_form"]
    d = diagnose([read_record(independent_records / "d09_gas_charge_cal.csv")],
                 [read_record(independent_records / "d09_gas_charge_val.csv")])
    assert d.added[:1] == ("gas_charge",), d.summary()
    cal = gas_charge_characteristics(d.final)["records"][0]
    assert cal["gas_force [N]"] == pytest.approx(closed["gas force at y = -31 mm [N]"], rel=0.3)
    assert cal["gas_rate [N/m]"] / 1e3 == pytest.approx(
        closed["gas rate at y = -31 mm [N/mm]"], rel=0.3)
    assert "pressure_level" in [s.effect for s in d.device_steps]
    g = d.final.device_model.effect("gas_charge")
    assert g.rod_area_m2 * g.charge_pressure_Pa == pytest.approx(
        closed["gas force at y = 0 mm [N]"], rel=0.3)
    assert d.final.nrmse_validation < 0.5 * d.baseline.nrmse_validation
