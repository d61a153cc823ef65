"""Blanco's influence coefficients for conformal contact (CONTACT's INFLCF = 4).

On a conformal patch (:mod:`railcontact.geometry.conformal`) the boundary-element
grid lies on the developed surface (x, s), s the arc length along the curved
reference surface.  The half-space coefficients A(I - J) of that flat grid
(:mod:`railcontact.normal.influence`) give the displacement difference at element
I of a unit traction at element J as if both lay in one plane.  Blanco-Lorenzo,
Santamaria, Vadillo & Oyarzabal (Tribology International 2016, "On the influence
of conformity on wheel-rail rolling contact mechanics") correct them to first
order for the turning of the surface between J and I: the half-space is taken
tangent at J, so its displacement at I is expressed in J's frame (x, t_J, N_J)
(t the curve's tangent, N its normal pointing into the rail) and is turned into
I's frame.  With alpha the inclination of each grid column (its rotation about x;
CONTACT's surface inclination, here the curve's angle D of
:class:`~railcontact.geometry.conformal.ReferenceCurve`), Delta = alpha_J - alpha_I,
c = cos Delta, s = sin Delta, and the components (x, s, n) of the tractions on
the rail (n: the pressure) and of the displacement difference (n: the gap's
opening), variant 3 of CONTACT's user guide (Vollebregt's proposal, "the
displacements transformed") reads

    B_xk(I, J) = A_xk(I - J),
    B_sk(I, J) = c A_sk(I - J) - s A_nk(I - J),
    B_nk(I, J) = s A_sk(I - J) + c A_nk(I - J),      k = x, s, n

(:func:`blanco_coefficients`; t_J.t_I = c, N_J.t_I = -s, t_J.N_I = s, N_J.N_I = c).
A flat surface (alpha constant) gives the half-space coefficients.

B is no longer a convolution in s, but each entry is a sum of separable terms,
cos(a_J - a_I) = cos a_J cos a_I + sin a_J sin a_I and likewise the sine, so every
product B p is a few FFT convolutions of the half-space kernels with the tractions
weighted by cos alpha or sin alpha per column, weighted again per column of the
result.  For bodies of one material (A_xn = A_sn = 0):

* normal: u_n = sum_m w_m * A_nn (w_m * p), w = (cos alpha, sin alpha) per column
  (:class:`ModulatedConvolution`; symmetric and positive definite, as the
  constrained conjugate gradients of :mod:`railcontact.normal.polonsky_keer` need);
* tangential: u_x = A_xx t_x + A_xs t_s as on the half-space, and
  u_s = cos a_I [A_sx (cos a t_x) + A_ss (cos a t_s)] + sin a_I [A_sx (sin a t_x)
  + A_ss (sin a t_s)] (the modulated operator of
  :class:`~railcontact.tangential.semi_smooth_newton.SlipOperator`);
* the coupling of the two problems (:class:`BlancoCoupling`): the gap's opening
  from the tangential tractions, sum_J s A_s.(I - J) t_J, and the lateral
  displacement of the pressure, -sum_J s A_nn(I - J) p_J, solved by alternation
  as CONTACT's Panagiotopoulos process does (:mod:`railcontact.cases.coupling`).

Units: SI (m, Pa, rad).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..core.errors import InputError
from .influence import (Convolution, ShiftedConvolution, normal_kernel, rigid_slip_of,
                        tangential_kernels)

__all__ = ["blanco_coefficients", "column_weights", "ModulatedConvolution",
           "blanco_normal_operator", "BlancoCoupling"]


def blanco_coefficients(A, delta) -> np.ndarray:
    """Blanco's coefficients B (..., 3, 3) from the half-space's A (..., 3, 3)
    [m/Pa] (components x, s, n: row the displacement, column the traction) and the
    inclination differences ``delta`` = alpha_J - alpha_I [rad] (broadcast to A's
    leading shape); variant 3 (module docstring; the one
    :class:`~railcontact.geometry.conformal.ConformalInfluence` accepts)."""
    A = np.asarray(A, dtype=float)
    d = np.asarray(delta, dtype=float)[..., None]
    c, s = np.cos(d), np.sin(d)
    B = A.copy()
    B[..., 1, :] = c * A[..., 1, :] - s * A[..., 2, :]
    B[..., 2, :] = s * A[..., 1, :] + c * A[..., 2, :]
    return B


def column_weights(angles) -> np.ndarray:
    """(2, my) the weights (cos alpha, sin alpha) of the grid columns' inclinations
    ``angles`` [rad]."""
    a = np.asarray(angles, dtype=float)
    return np.ascontiguousarray(np.stack([np.cos(a), np.sin(a)]))


class ModulatedConvolution:
    """The normal operator of Blanco's coefficients on a block of the grid:
    u = sum_m w_m * A (w_m * p) with A the half-space :class:`Convolution`
    ``base`` and ``modulation`` (2, ny) the column weights (cos alpha, sin alpha)
    of the block's columns.  Its diagonal is A's (cos^2 + sin^2 = 1)."""

    def __init__(self, base: Convolution, modulation: np.ndarray):
        self.base = base
        self.modulation = np.ascontiguousarray(modulation, dtype=float)
        self.khat, self.shape, self.kernel, self.diag = base.khat, base.shape, base.kernel, \
            base.diag
        self.mx, self.my = base.mx, base.my

    def __call__(self, p: np.ndarray) -> np.ndarray:
        """B p for p on the block (its columns those of ``modulation``)."""
        if p.shape[1] != self.modulation.shape[1]:
            raise InputError(f"pressure with {p.shape[1]} columns: expected the operator's "
                             f"{self.modulation.shape[1]}")
        u = np.zeros(p.shape)
        for w in self.modulation:
            u += w[None, :] * self.base(w[None, :] * p)
        return u


def blanco_normal_operator(base: Convolution, angles) -> ModulatedConvolution:
    """The normal operator B_nn of Blanco's coefficients: the half-space operator
    ``base`` of a block with the inclinations ``angles`` [rad] of its columns."""
    return ModulatedConvolution(base, column_weights(angles))


@lru_cache(maxsize=16)
def _normal_rows(mx, my, dx, dy, contact_modulus):
    """The half-space normal kernel with one extra row of offsets in x (the rolling
    difference), as a :class:`ShiftedConvolution`."""
    return ShiftedConvolution(normal_kernel(mx, my, dx, dy, contact_modulus, extra_rows=1),
                              mx, my, 1)


@lru_cache(maxsize=16)
def _lateral_rows(mx, my, dx, dy, G, nu):
    """The kernels (A_sx, A_ss) of the lateral displacement, on the grid itself."""
    _, kxy, kyy = tangential_kernels(mx, my, dx, dy, G, nu)
    return Convolution(kxy, mx, my), Convolution(kyy, mx, my)


class BlancoCoupling:
    """The coupling of the normal and tangential problems that Blanco's coefficients
    bring, for bodies of one ``material`` (its shear modulus G, Poisson's ratio nu
    and contact modulus E*): ``angles(y)`` the inclinations [rad] of the grid
    columns at arc lengths ``y`` [m].  One implementation of the coupling protocol
    of :func:`railcontact.cases.coupling.solve_coupled` (``gap_from_tractions``,
    ``slip_from_pressure`` on a grid (x, y) [m]; the other: dissimilar materials)."""

    #: what couples the problems (for the messages)
    name = "Blanco's conformal influence coefficients"

    def __init__(self, angles, material):
        self.angles = angles
        #: whether the problems are coupled (always) and what the result records
        self.couples, self.options = True, {}
        self.G, self.nu = float(material.shear_modulus), float(material.nu)
        self.contact_modulus = float(material.contact_modulus)

    def _grid(self, x, y):
        """The column weights (cos, sin) (1, my), the step dx and the kernels of
        the grid (x, y)."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        if x.size < 2 or y.size < 2:
            raise InputError("Blanco coupling needs a grid of at least 2 x 2 elements")
        a = np.asarray(self.angles(y), dtype=float)
        if a.shape != y.shape:
            raise InputError(f"Blanco coupling: {a.size} column angles, expected one per grid "
                             f"column ({y.size})")
        dx = float(x[1] - x[0])
        key = (x.size, y.size, dx, float(y[1] - y[0]))
        return (np.cos(a)[None, :], np.sin(a)[None, :], dx,
                _normal_rows(*key, self.contact_modulus), _lateral_rows(*key, self.G, self.nu))

    def gap_from_tractions(self, x, y, tx_rail, ty_rail) -> np.ndarray:
        """The gap's opening [m] on the grid (x, y) from the tangential tractions on
        the rail [Pa]: sum_J sin(a_J - a_I) (A_sx t_x + A_ss t_s)(I - J)."""
        c, s, _, _, (ksx, kss) = self._grid(x, y)
        lat = lambda w: ksx(w * tx_rail) + kss(w * ty_rail)   # noqa: E731
        return c * lat(s) - s * lat(c)

    def lateral_displacement(self, x, y, p) -> np.ndarray:
        """The lateral displacement difference [m] of the pressure p [Pa] on the
        grid (x, y) and one row beyond it (the rolling difference):
        -sum_J sin(a_J - a_I) A_nn(I - J) p_J."""
        c, s, _, kn, _ = self._grid(x, y)
        return -(c * kn(s * p) - s * kn(c * p))

    def slip_from_pressure(self, x, y, p, mode: str = "rolling"):
        """The rigid slip (s_x, s_y) that the pressure p [Pa] on the grid (x, y)
        adds (:func:`~railcontact.normal.influence.rigid_slip_of`; s_x zero)."""
        u = self.lateral_displacement(x, y, p)
        return rigid_slip_of(np.zeros(u.shape), u, float(x[1] - x[0]), mode)
