"""Profiles layer: wheel and rail cross-sections in SI units.

See :class:`~railcontact.profiles.profile.Profile` for the conventions.
"""

from .io import process_points, read_profile, write_profile
from .library import builtin_names, get_profile
from .measures import wheel_measures
from .processing import ProfileOptions, Smoothing
from .profile import Profile
from .rails import rail_profile
from .en13715 import s1002

__all__ = ["Profile", "ProfileOptions", "Smoothing", "process_points", "read_profile",
           "write_profile", "get_profile", "builtin_names", "rail_profile", "s1002",
           "wheel_measures"]
