"""Stability and limit cycles of structures with devices.

* :mod:`.floquet` -- Floquet analysis of linear periodic systems (monodromy, multipliers).
* :mod:`.ground_resonance` -- rotor ground resonance against rotor speed (Coleman, Floquet;
  Coleman & Feingold 1958, Hammond 1974).
* :mod:`.flutter` -- flutter and divergence of the typical section (p-k, k and p methods).
* :mod:`.modes` -- modal properties and mode tracking across a sweep (MAC).
* :mod:`.damped_stability` -- the same analyses with devices as linear or equivalent systems.
* :mod:`.sizing` -- sizing a lag or flutter damper for a stability margin.
* :mod:`.lco` -- limit cycles: describing function against the time domain.
* :mod:`.parallel` -- batched map of independent runs over processes or any executor.
* :mod:`.lag_sweep` -- lag damping against the 1/rev stroke: Floquet and the K_lag prediction.
"""
