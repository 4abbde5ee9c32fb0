"""Linearization, dynamic stiffness, stability, limit cycles, calibration, plots."""
