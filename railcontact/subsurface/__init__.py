"""Subsurface stresses: the stress tensor in the half-space below a solved patch.

:func:`subsurface_stresses` takes a patch's normal (and tangential) solution and
returns :class:`SubsurfaceStresses` (components, von Mises, Tresca, orthogonal
shears, their maxima and depths, ``to_xarray``, ``plot_sections``).  Below it,
:func:`stresses_on_grid` convolves loads on a uniform grid by FFT per depth and
:func:`stresses_at_points` sums uniform rectangular loads at any points.
``docs/subsurface.md`` describes the method and its verification.
"""

from .kernels import COMPONENTS, stresses_at_points
from .stresses import (MEASURES, SubsurfaceStresses, default_depths, stresses_on_grid,
                       subsurface_stresses)

__all__ = ["subsurface_stresses", "SubsurfaceStresses", "stresses_on_grid", "stresses_at_points",
           "default_depths", "COMPONENTS", "MEASURES"]
