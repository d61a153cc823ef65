"""Compiled creep-force laws for one elliptic patch, for use inside loops: vehicle
dynamics (evaluated at every step) and batches of patches (:mod:`railcontact.cases.batch`).

The laws are the registered tangential models that declare the ``"online"``
capability; their class attribute ``online_law`` is the code below
(:func:`online_law` looks it up in the registry):

* ``linear``: Kalker's linear theory, F_x = G c² C11 ξ, F_y = G c² C22 η + G c³ C23 φ
  (no saturation, no spin moment);
* ``fastsim``: :func:`railcontact.tangential.fastsim.fastsim_ellipse` (blended
  flexibilities, Hertzian traction bound), forces only;
* ``polach``: :func:`railcontact.tangential.polach.polach_kernel` with the
  slip-velocity dependent friction μ = μ0 ((1 − A) e^(−B w) + A) of the extended
  model, w = |(ξ, η)| V.
"""

from __future__ import annotations

import math

from numba import njit

from .base import tangential_model_class, tangential_supports
from .fastsim import fastsim_ellipse
from .kalker import Creepage, KalkerCoefficients, linear_forces
from .polach import polach_kernel


def online_law(name: str) -> int | None:
    """Code of the compiled law of the tangential model ``name`` for
    :func:`patch_forces`, or None where the model has none (it then runs through
    its Python ``solve``).  Unknown names raise
    :class:`~railcontact.core.errors.UnknownModelError`."""
    cls = tangential_model_class(name)
    return cls.online_law if tangential_supports(name, "online") else None


@njit(cache=True, nogil=True)
def patch_forces(law, tp, N, a, b, C11, C22, C23, xi, eta, phi, V):
    """(F_x, F_y, M_z) [N, N, N m] on the wheel of one Hertz patch.

    Parameters
    ----------
    law : int
        Code from :func:`online_law`.
    tp : ndarray
        (mu0, G [Pa], nx, ny (FASTSIM elements), kA, kS, A, B [s/m]) — Polach's
        reduction factors and falling-friction parameters (A = 1: constant friction).
    N, a, b : normal force [N] and semi-axes [m];  C11, C22, C23 : Kalker's coefficients
    xi, eta, phi : creepages [-, -, 1/m];  V : rolling velocity [m/s]
    """
    mu, G = tp[0], tp[1]
    if N <= 0.0 or a <= 0.0 or b <= 0.0:
        return 0.0, 0.0, 0.0
    if law == 0:
        fx, fy = linear_forces(G, a, b, C11, C22, C23, xi, eta, phi)
        return fx, fy, 0.0
    if law == 1:
        return fastsim_ellipse(a, b, N, mu, G, KalkerCoefficients(C11, C22, C23),
                               Creepage(xi, eta, phi), int(tp[2]), int(tp[3]))
    w = math.hypot(xi, eta) * V
    mu_eff = mu * ((1.0 - tp[6]) * math.exp(-tp[7] * w) + tp[6])
    fx, fy = polach_kernel(N, mu_eff, a, b, G, KalkerCoefficients(C11, C22, C23),
                           Creepage(xi, eta, phi), tp[4], tp[5])
    return fx, fy, 0.0
