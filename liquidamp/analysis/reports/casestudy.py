"""The paper's case study (Sec. IV.D, Figs. 7-11) as data, then as figures and a page.

:func:`run_case_study` computes every periodic steady state with the full
model (eq. 10) and its first-harmonic dynamic stiffness;
:func:`write_case_study` draws the three-panel figures and writes an
``index.html`` with the table of |K*| and phase for every case.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Table 3 and Figs. 7-11.
"""

from __future__ import annotations

import html
from dataclasses import dataclass
from pathlib import Path

from liquidamp.analysis.response.harmonics import DynamicStiffness, dynamic_stiffness
from liquidamp.atomic import save_figure, write_text
from liquidamp.coupled.testrig import DeviceResponse, steady_state
from liquidamp.device import preset
from liquidamp.options import SolverOptions, resolve_options
from liquidamp.structure.testmachine import HarmonicStroke

__all__ = ["FigureSpec", "FIGURES", "CaseResult", "CaseStudy", "run_case_study",
           "write_case_study"]


@dataclass(frozen=True)
class FigureSpec:
    """One figure of the case study.

    Attributes
    ----------
    key : str
        File stem of the figure.
    title : str
        Caption (the paper's).
    preset : str
        Device preset.
    cases : tuple of (float, float)
        (frequency [Hz], amplitude [m]) pairs.
    reference : bool
        Also draw the reference design at the same cases (grey).
    ideal : tuple of str
        Ideal characteristics overlaid (see :func:`liquidamp.analysis.reports.plots.plot_loops`).
    """

    key: str
    title: str
    preset: str
    cases: tuple[tuple[float, float], ...]
    reference: bool
    ideal: tuple[str, ...]


_SPEC_CASES = ((3.0, 1e-3), (3.0, 3e-3))
_GENERAL_CASES = ((1.0, 1.5e-3), (2.0, 1.5e-3), (4.0, 1.5e-3), (7.0, 1.5e-3))

#: Figures 7-11 of the paper.
FIGURES = (
    FigureSpec("fig07_spring", "Fig. 7: stiffness-dominated responses", "spring", _SPEC_CASES,
               True, ("spring",)),
    FigureSpec("fig08_damper", "Fig. 8: damping-dominated responses", "damper", _SPEC_CASES,
               True, ("damper",)),
    FigureSpec("fig09_inerter", "Fig. 9: inertia-dominated responses", "inerter", _SPEC_CASES,
               True, ("inerter",)),
    FigureSpec("fig10_device_a", "Fig. 10: Device A, increased flow inertia", "device_a",
               _GENERAL_CASES, False, ("spring", "damper", "inerter")),
    FigureSpec("fig11_device_b", "Fig. 11: Device B, reduced flow inertia", "device_b",
               _GENERAL_CASES, False, ("spring", "damper", "inerter")),
)


@dataclass(frozen=True, eq=False)
class CaseResult:
    """One steady state of the case study and its dynamic stiffness."""

    figure: str
    preset: str
    response: DeviceResponse
    stiffness: DynamicStiffness


@dataclass(frozen=True, eq=False)
class CaseStudy:
    """All cases of Figs. 7-11 (``reference`` holds the grey reference-design runs)."""

    cases: tuple[CaseResult, ...]
    reference: tuple[CaseResult, ...]

    def for_figure(self, key: str) -> tuple[CaseResult, ...]:
        """Cases of figure ``key``."""
        return tuple(c for c in self.cases if c.figure == key)


def _run(figure: str, name: str, f: float, Y: float, options) -> CaseResult:
    r = steady_state("full", preset(name), HarmonicStroke(Y, f), options=options)
    return CaseResult(figure, name, r, dynamic_stiffness(r))


def run_case_study(figures=FIGURES, options: SolverOptions | None = None,
                   progress=None) -> CaseStudy:
    """Compute every steady state of ``figures`` with the full model (eq. 10).

    Parameters
    ----------
    figures : sequence of FigureSpec
        Default: Figs. 7-11.
    options : SolverOptions, optional
        Tolerances and engine; default the ``"casestudy"`` preset of
        :data:`liquidamp.options.PRESETS` (the default tolerances on the
        compiled engine).
    progress : callable, optional
        Called with a one-line message after each case.

    Returns
    -------
    CaseStudy
    """
    options = resolve_options(options, "casestudy")
    cases, ref = [], {}
    for spec in figures:
        for f, Y in spec.cases:
            cases.append(_run(spec.key, spec.preset, f, Y, options))
            if progress:
                c = cases[-1]
                progress(f"{spec.key}: {spec.preset} {Y * 1e3:g} mm {f:g} Hz "
                         f"|K*| = {c.stiffness.magnitude:.4g} N/m, "
                         f"phase {c.stiffness.phase_deg:.1f} deg")
            if spec.reference and (f, Y) not in ref:
                ref[(f, Y)] = _run("reference", "reference", f, Y, options)
    return CaseStudy(tuple(cases), tuple(ref.values()))


def write_case_study(study: CaseStudy, out_dir: str | Path, figures=FIGURES,
                     extra_html: str = "") -> Path:
    """Write one PNG per figure and ``index.html`` with the stiffness table.

    Parameters
    ----------
    study : CaseStudy
        Output of :func:`run_case_study`.
    out_dir : str or Path
        Directory (created if missing).
    figures : sequence of FigureSpec
        Figures to draw.
    extra_html : str
        HTML appended to the page (other parts of the demo).

    Returns
    -------
    Path
        Path of ``index.html``.
    """
    from liquidamp.analysis.reports.plots import plot_loops
    from liquidamp.analysis.reports.report_calibration import CSS, DPI

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    blocks = []
    for spec in figures:
        cases = study.for_figure(spec.key)
        reference = [c.response for c in study.reference
                     if (c.response.frequency, c.response.amplitude) in spec.cases]
        fig = plot_loops([c.response for c in cases], reference=reference, ideal=spec.ideal,
                         title=f"{spec.title} (preset {spec.preset})")
        save_figure(fig, out / f"{spec.key}.png", dpi=DPI)
        blocks.append(f'<h2>{html.escape(spec.title)}</h2>\n'
                      f'<img src="{spec.key}.png" alt="{html.escape(spec.title)}">')
    rows = []
    for c in list(study.cases) + list(study.reference):
        r, K = c.response, c.stiffness
        warn = "; ".join(r.warnings) or "none"
        rows.append(
            f"<tr><td>{c.figure}</td><td>{c.preset}</td><td>{r.frequency:g}</td>"
            f"<td>{r.amplitude * 1e3:g}</td><td>{K.magnitude:.4g}</td>"
            f"<td>{K.phase_deg:.1f}</td><td>{r.force.max():.4g}</td>"
            f"<td>{r.min_pressure / 1e3:.3g}</td><td>{r.cycles}</td>"
            f"<td>{html.escape(warn)}</td></tr>"
        )
    table = (
        "<table>\n"
        "<tr><th>figure</th><th>preset</th><th>f [Hz]</th><th>Y [mm]</th>"
        "<th>|K*| [N/m]</th><th>phase [deg]</th><th>peak force [N]</th>"
        "<th>lowest pressure [kPa]</th><th>cycles to steady state</th><th>warnings</th></tr>\n"
        + "\n".join(rows) + "\n</table>"
    )
    page = f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>liquidamp case study</title>
<style>{CSS}</style></head><body>
<h1>liquidamp: case study of Titurus (2018), Figs. 7-11</h1>
<p>Full 5-state model (eq. 10), periodic steady state under y = Y sin(2&pi;ft).
Dynamic stiffness K* = F<sub>1</sub>/Y (first harmonic, sine convention), phase in
(&minus;180&deg;, 180&deg;]: 0&deg; spring, 90&deg; damper, 180&deg; inerter
(python-control's <code>FrequencyResponseData</code> unwraps the phase instead; see
<code>StiffnessCurve.to_frd</code>). Red dashes: ideal spring (closed channel), damper
(incompressible, eq. 5) and inerter (eq. 20); grey: reference design; wide purple band: stretches
where a chamber pressure is below the vapour pressure (the liquid would cavitate, which the
full model without the cavitation effect does not represent).</p>
<h2>First-harmonic dynamic stiffness</h2>
{table}
{''.join(blocks)}
{extra_html}
</body></html>
"""
    index = out / "index.html"
    write_text(index, page)
    return index
