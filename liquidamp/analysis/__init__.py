"""What the models are used for, one subpackage per purpose.

* :mod:`~liquidamp.analysis.measured` -- measured test-machine records, calibration against
  them, residual diagnosis, synthetic records (Sec. IV.C).
* :mod:`~liquidamp.analysis.response` -- linear and equivalent models and the periodic response:
  transfer functions (eqs. 16, 18, 19), linearization, python-control I/O systems, first
  harmonic and dynamic stiffness K* = F1/Y, describing functions, shooting.
* :mod:`~liquidamp.analysis.stability` -- stability and limit cycles of hosts with devices:
  Floquet, ground resonance, flutter, mode tracking, damper sizing, limit cycles.
* :mod:`~liquidamp.analysis.reports` -- figures and HTML pages (Figs. 5-11, case study).
* :mod:`~liquidamp.analysis.bench` -- performance benchmarks of the above.

Dependencies point one way: ``reports`` draws results of the others (importing them only for
types), ``stability`` and ``measured`` use ``response``; ``response`` uses none of them.
"""
