"""Worked examples shipped with the package: stability-sweep scripts.

Run them from an installed copy with ``python -m``:

- ``python -m liquidamp.examples.ground_resonance_map --out DIR``: largest real
  part of the Hammond (1974) rotor against rotor speed for the viscous damper and
  the liquid devices (healthy and with one damper failed), and a map over rotor
  speed and channel inertance.
- ``python -m liquidamp.examples.flutter_map --out DIR``: flutter speed of the
  Hodges & Pierce typical section against device parameters.
- ``python -m liquidamp.examples.forward_flight_lag_damping --out DIR``: lag-mode
  damping of the Hammond blade against the 1/rev damper stroke (Floquet and the
  dual-frequency K_lag prediction) for liquid presets and a friction damper.

The first two run on local processes and accept ``--dask ADDRESS``; all write PNG and JSON.
"""
