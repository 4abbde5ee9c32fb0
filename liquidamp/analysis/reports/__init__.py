"""Plots and reports: figures in the paper's style and HTML pages.

Plotting only (matplotlib imported lazily, Agg canvas); results come from the other
subpackages.

* :mod:`.plots` -- device responses in the three-panel style of Titurus 2018, Figs. 5-11.
* :mod:`.stiffness_plots` -- Bode-style dynamic-stiffness figure.
* :mod:`.stability_plots` -- Coleman, V-g and V-f diagrams, limit cycles.
* :mod:`.report_calibration` -- HTML report of a calibration or a diagnosis.
* :mod:`.casestudy` -- the paper's case study (Sec. IV.D, Figs. 7-11) as data, figures, a page.
"""
