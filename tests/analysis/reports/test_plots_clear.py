"""Issue #14: figures a user can read (legends, failed blade named, distinct colours,
cavitation marked, SI units, envelopes) and styled reports."""

import numpy as np
import pytest
from matplotlib.colors import to_hex

from liquidamp.analysis.reports.plots import PALETTE, plot_loops
from liquidamp.analysis.reports.stability_plots import plot_ground_resonance, plot_limit_cycle
from liquidamp.analysis.reports.stiffness_plots import plot_dynamic_stiffness
from liquidamp.analysis.response.stiffness import StiffnessCurve
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

FAST = SolverOptions(engine="compiled")


def test_loops_use_distinct_colours_and_mark_cavitation():
    p = preset("inerter")
    rs = [steady_state("full", p, HarmonicStroke(Y, 3.0), options=FAST) for Y in (1e-3, 3e-3)]
    assert rs[1].min_pressure < 2339.0 < rs[0].min_pressure  # 3 mm cavitates, 1 mm does not
    fig = plot_loops(rs, ideal=["inerter"])
    ax = fig.axes[0]
    labels = [line.get_label() for line in ax.lines]
    assert any("cavitation" in lab for lab in labels)
    loops = [line for line in ax.lines if "Hz" in line.get_label()]
    assert [to_hex(line.get_color()) for line in loops] == [to_hex(c) for c in PALETTE[:2]]
    band = next(line for line in ax.lines if "cavitation" in line.get_label())
    y = np.asarray(band.get_ydata(), float)
    assert 0 < np.isfinite(y).sum() < y.size  # only the low-pressure stretch is marked


def test_coleman_diagram_names_modes_and_failed_blade():
    from liquidamp.analysis.stability.ground_resonance import ground_resonance_sweep, rpm_to_rad_s
    from liquidamp.structure.hostio import load_rotor

    rotor = load_rotor("hammond1974").with_inoperative_damper(2)
    sweep = ground_resonance_sweep(rotor, rpm_to_rad_s(np.linspace(150, 350, 9)))
    fig = plot_ground_resonance(sweep)
    title = fig.axes[0].get_title()
    assert "blade 2 inoperative" in title and "Floquet" in title
    leg = [t.get_text() for t in fig.axes[1].get_legend().get_texts()]
    assert len(leg) >= 4 and all(t.startswith("mode ") for t in leg)
    healthy = ground_resonance_sweep(load_rotor("hammond1974"),
                                     rpm_to_rad_s(np.linspace(150, 350, 5)))
    assert "all lag dampers working" in plot_ground_resonance(healthy).axes[0].get_title()


def test_stiffness_plot_in_newton_per_metre_with_failed_points_marked():
    f = np.array([1.0, 2.0, 4.0])
    lin = StiffnessCurve("spring", f, np.full(3, 2e5 + 0j))

    class NL:  # the attributes plot_dynamic_stiffness reads
        model = "full"
        frequency = f
        amplitude = np.array([1e-3])
        value = np.array([[2e5 + 1e4j, np.nan + 1j * np.nan, 2.2e5 + 2e4j]])
        magnitude = np.abs(value)
        phase_deg = np.degrees(np.angle(value))

    fig = plot_dynamic_stiffness([lin], NL())
    ax_m, ax_p = fig.axes
    assert ax_m.get_ylabel() == "|K*| [N/m]"
    assert ax_m.lines[0].get_ydata()[0] == pytest.approx(2e5)  # N/m, not N/mm
    failed = [ln for ln in ax_p.lines if ln.get_label().startswith("failed")]
    assert len(failed) == 1 and list(failed[0].get_xdata()) == [2.0]


def test_limit_cycle_plot_shows_envelope_and_zoom():
    class Resp:
        time = np.linspace(0.0, 60.0, 12001)
        w = 2 * np.pi * 0.86
        amp = 0.0027 * (1 - np.exp(-time / 5.0))
        host_state_names = ("zeta_1", "zeta_2", "zeta_1_dot", "zeta_2_dot")
        host_states = np.vstack([amp * np.sin(w * time), amp * np.sin(w * time - np.pi / 2),
                                 0 * time, 0 * time])
        strokes = 0.25 * host_states[:2]
        port_names = ("blade_1", "blade_2")

    fig = plot_limit_cycle(Resp(), predicted_amplitude=0.0027, zoom_cycles=3)
    env, zoom, env_s, _ = fig.axes
    x, y = env.lines[0].get_xdata(), env.lines[0].get_ydata()
    assert x.size < 200  # an envelope of peaks, not 12001 samples of oscillation
    assert y[-1] == pytest.approx(np.degrees(0.0027), rel=1e-3)
    zx = zoom.lines[0].get_xdata()
    assert zx[0] == pytest.approx(60.0 - 3 / 0.86, abs=0.05) and zx[-1] == 60.0
    assert "last 3 cycles" in zoom.get_title()


def test_reports_are_styled_and_sharp(tmp_path):
    from liquidamp.analysis.reports.casestudy import FIGURES, run_case_study, write_case_study
    from liquidamp.analysis.reports.report_calibration import CSS, DPI

    figs = [f for f in FIGURES if f.key == "fig09_inerter"]
    study = run_case_study(figs, options=FAST)
    index = write_case_study(study, tmp_path, figures=figs)
    page = index.read_text()
    assert CSS.strip()[:40] in page and "(&minus;180&deg;, 180&deg;]" in page
    assert "<ul></ul>" not in page
    from matplotlib.image import imread

    img = imread(tmp_path / "fig09_inerter.png")
    assert DPI >= 150 and img.shape[1] >= 1800  # 12.6 in wide at 150 dpi
