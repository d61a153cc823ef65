"""Wear layer: wear laws, wear along the profiles, profile evolution."""

from .driver import WearDriver
from .laws import get_wear_law, wear_laws
from .mapping import profile_depth, removed_area, strip_depth, wear_profile
from .simulation import WearScenario, WearSimulation

__all__ = ["WearDriver", "get_wear_law", "wear_laws", "profile_depth", "removed_area",
           "strip_depth", "wear_profile", "WearScenario", "WearSimulation"]
