"""liquidamp: the generalized liquid-based damping device of Titurus (2018).

Sub-packages (imports flow one way: ``device`` and ``structure`` know nothing
of each other, ``coupled`` uses both, ``analysis`` uses all three):

``liquidamp.device``
    Parameters and presets (Tables 1-3), fluid laws (eqs. 2-6), the model
    family (eq. 10 and its reductions, eqs. 11-20) and add-on effects.
``liquidamp.structure``
    Hosts: test machine, blade in lead-lag, rotor on its landing gear,
    typical wing section.
``liquidamp.coupled``
    Host plus device(s): nonlinear time domain and linear interconnection.
``liquidamp.analysis``
    Transfer functions, dynamic stiffness, stability, limit cycles,
    calibration and residual diagnosis, plots and reports.

Reference
---------
B. Titurus, "Generalized Liquid-Based Damping Device for Passive Vibration
Control", AIAA Journal 56(10), 4134-4145, 2018. doi:10.2514/1.J056636
"""

__version__ = "0.1.0"
