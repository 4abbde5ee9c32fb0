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

The main verbs are importable from the top (lazily: ``import liquidamp``
imports no numerical library until one is used)::

    from liquidamp import preset, get_model, with_effects, steady_state, dynamic_stiffness

Reference
---------
B. Titurus, "Generalized Liquid-Based Damping Device for Passive Vibration
Control", AIAA Journal 56(10), 4134-4145, 2018. doi:10.2514/1.J056636
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

#: The main verbs and types, imported on first use (``import liquidamp`` imports no numerical
#: library): name -> the module that defines it.
_EXPORTS = {
    # the device
    "DeviceParams": "liquidamp.device.params",
    "preset": "liquidamp.device.presets",
    "preset_names": "liquidamp.device.presets",
    "load_device": "liquidamp.device.presets",
    "get_model": "liquidamp.device.models",
    "model_names": "liquidamp.device.models",
    "with_effects": "liquidamp.device.effects",
    "make_effect": "liquidamp.device.effects",
    "effect_names": "liquidamp.device.effects",
    # strokes, options, errors
    "HarmonicStroke": "liquidamp.structure.testmachine",
    "TwoFrequencyStroke": "liquidamp.structure.testmachine",
    "RecordedStroke": "liquidamp.structure.testmachine",
    "SolverOptions": "liquidamp.options",
    "LiquidampError": "liquidamp.errors",
    "ParameterError": "liquidamp.errors",
    "ConvergenceError": "liquidamp.errors",
    # the device on the test machine
    "simulate": "liquidamp.coupled.testrig",
    "steady_state": "liquidamp.coupled.testrig",
    "first_harmonic": "liquidamp.analysis.response.harmonics",
    "dynamic_stiffness": "liquidamp.analysis.response.harmonics",
    "nonlinear_stiffness": "liquidamp.analysis.response.stiffness",
    "dual_frequency_stiffness": "liquidamp.analysis.response.dual_frequency",
    "equivalent_stiffness": "liquidamp.analysis.response.equivalent",
    "device_lti": "liquidamp.analysis.stability.damped_stability",
    # the device in a structure
    "Device": "liquidamp.coupled.assembly",
    "viscous": "liquidamp.coupled.assembly",
    "couple": "liquidamp.coupled.assembly",
    "rotor_system": "liquidamp.coupled.assembly",
    "blade_system": "liquidamp.coupled.assembly",
    "simulate_coupled": "liquidamp.coupled.assembly",
    "load_rotor": "liquidamp.structure.hostio",
    "load_blade": "liquidamp.structure.hostio",
    "load_section": "liquidamp.structure.hostio",
    # measured data
    "read_record": "liquidamp.analysis.measured.records",
    "synthetic_record": "liquidamp.analysis.measured.synthetic",
    "simulate_record": "liquidamp.analysis.measured.record_model",
    "calibrate": "liquidamp.analysis.measured.calibration",
    "diagnose": "liquidamp.analysis.measured.diagnosis",
}

__all__ = ["__version__", *_EXPORTS]


def __getattr__(name: str):
    """Import a main verb on first use (PEP 562), then keep it in the module."""
    where = _EXPORTS.get(name)
    if where is None:
        raise AttributeError(f"module 'liquidamp' has no attribute {name!r}")
    value = getattr(importlib.import_module(where), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
