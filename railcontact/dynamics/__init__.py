"""Dynamics layer: vehicle models running on the track with the contact models.

So far: a single wheelset on tangent track (:mod:`railcontact.dynamics.wheelset`).
"""

from .wheelset import WheelsetModel, critical_speed, linear_matrix, simulate, wavelength

__all__ = ["WheelsetModel", "simulate", "wavelength", "linear_matrix", "critical_speed"]
