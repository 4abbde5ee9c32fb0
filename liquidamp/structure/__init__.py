"""Hosts the device is attached to: test machine, blade, rotor, wing section.

Every host is a linear structure with named signals and device ports
(:mod:`liquidamp.structure.port`):

- :class:`ArticulatedBlade` -- a blade in lead-lag (rotating frame);
- :class:`GroundResonanceRotor` -- N blades on a flexible hub (ground
  resonance), periodic in rotating coordinates, constant in multiblade
  coordinates when all blades are alike;
- :class:`TypicalSection` -- the pitch-plunge wing section (flutter).

Presets (``hammond1974``, ``hodges-pierce``) and host files are read by
:mod:`liquidamp.structure.hostio`.
"""

from liquidamp.structure.blade import ArticulatedBlade
from liquidamp.structure.hostio import (
    load_blade,
    load_rotor,
    load_section,
    preset_description,
    preset_names,
)
from liquidamp.structure.port import DevicePort, Host, PeriodicStateSpace, find_port
from liquidamp.structure.rotor import GroundResonanceRotor, multiblade_names
from liquidamp.structure.section import TypicalSection

# testmachine: re-exported by its own author (nothing imported from it here).

__all__ = [
    "ArticulatedBlade",
    "DevicePort",
    "GroundResonanceRotor",
    "Host",
    "PeriodicStateSpace",
    "TypicalSection",
    "find_port",
    "load_blade",
    "load_rotor",
    "load_section",
    "multiblade_names",
    "preset_description",
    "preset_names",
]
