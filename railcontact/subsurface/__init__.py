"""Subsurface stresses: the stress tensor in the half-space below a solved patch.

:func:`subsurface_stresses` takes a patch's normal (and tangential) solution and
returns :class:`SubsurfaceStresses` (components, von Mises, Tresca, orthogonal
shears, their maxima and depths, ``to_xarray``, ``plot_sections``).  Below it,
:func:`stresses_on_grid` convolves loads on a uniform grid by FFT per depth and
:func:`stresses_at_points` sums uniform rectangular loads at any points.
Below a patch loaded beyond yield, :func:`solve_elastic_plastic` (and
:class:`ElasticPlasticContact` for load histories and repeated passes) solves the
elastic-plastic contact with isotropic hardening (Jacq et al. 2002), on the
eigenstrain influence of :mod:`railcontact.subsurface.eigenstrain`.
``docs/subsurface.md`` describes the methods and their verification.
"""

from .elastoplastic import (MN13, ElasticPlasticContact, ElasticPlasticOptions,
                            ElasticPlasticResult, Hardening, solve_elastic_plastic)
from .kernels import COMPONENTS, stresses_at_points
from .stresses import (MEASURES, SubsurfaceStresses, default_depths, stresses_on_grid,
                       subsurface_stresses)

__all__ = ["subsurface_stresses", "SubsurfaceStresses", "stresses_on_grid", "stresses_at_points",
           "default_depths", "COMPONENTS", "MEASURES", "solve_elastic_plastic",
           "ElasticPlasticContact", "ElasticPlasticOptions", "ElasticPlasticResult",
           "Hardening", "MN13"]
