"""Hosts the device is attached to: test machine, blade, rotor, wing section."""
