"""The demo's end-to-end loop on the bundled records (``liquidamp demo``): calibrate,
diagnose, write the JSON and the HTML report.

The records (``liquidamp/analysis/measured/data/``, synthetic: the paper's calibrated device
with smooth friction) are described in that folder's README.
"""

from __future__ import annotations

from liquidamp.analysis.measured.diagnosis import bundled_records, diagnose

__all__ = ["demo_loop"]


def demo_loop(out_dir, *, cycles: float = 3.0, top: int = 1) -> dict:
    """Calibrate and diagnose the bundled records end to end; write JSON and an HTML report.

    Calibrates on ``demo_3Hz_3mm`` and validates on ``demo_4Hz_2mm``
    (synthetic: the paper's calibrated device with smooth friction, see
    ``liquidamp/analysis/measured/data/README.md``), each trimmed to its first
    ``cycles`` cycles to keep the run short.

    Returns
    -------
    dict
        ``added`` (effects), ``nrmse`` before/after on both sets, the truth's
        effects, ``report`` (index.html path), ``json`` path, ``seconds``.
    """
    import json
    import time
    from pathlib import Path

    from liquidamp.analysis.measured.records import read_record
    from liquidamp.analysis.reports.report_calibration import write_report

    t0 = time.perf_counter()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = bundled_records()
    cal = read_record(files["demo_3Hz_3mm"]).trimmed(cycles)
    val = read_record(files["demo_4Hz_2mm"]).trimmed(cycles)
    d = diagnose([cal], [val], top=top, max_nfev=40)
    (out / "diagnosis.json").write_text(json.dumps(d.as_dict(), indent=2, default=float))
    report = write_report(out / "report", diagnosis=d, title="liquidamp demo: calibrate and "
                          "diagnose the bundled records")
    truth = json.loads(files["demo_3Hz_3mm"].with_suffix(".json").read_text())["effects"]
    return {
        "added": list(d.added),
        "parameters": [s.parameters for s in d.steps],
        "truth_effects": truth,
        "nrmse": {"baseline": {"calibration": d.baseline.nrmse_calibration,
                               "validation": d.baseline.nrmse_validation},
                  "final": {"calibration": d.final.nrmse_calibration,
                            "validation": d.final.nrmse_validation}},
        "stop_reason": d.stop_reason,
        "warnings": list(d.warnings),
        "report": str(report),
        "json": str(out / "diagnosis.json"),
        "seconds": time.perf_counter() - t0,
    }
