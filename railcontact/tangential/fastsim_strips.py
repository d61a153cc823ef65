"""FASTSIM with a local ellipse per strip: ``tangential="fastsim-strips"``.

The flexibilities of each strip come from the Hertz ellipse of the gap's relative
curvatures at the strip's centre line (Ayasse & Chollet, VSD 43, 2005), and the
spin from the local contact angle (Tao et al., CM2015); the strips march as in
:class:`~railcontact.tangential.fastsim.FastsimModel`.
"""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from ..geometry.gap import sample_strip_spin
from ..core.hertz_theory import hertz_ellipses
from ..normal.semi_hertzian import strip_minima
from .base import register
from .fastsim import FastsimModel, batch_flexibilities


def local_curvatures(normal, geometry):
    """Relative curvatures (A(y), B(y)) [1/m] of the gap at each strip's minimum.

    :func:`~railcontact.normal.semi_hertzian.strip_minima` of h(x, y) on the
    normal solution's grid, reusing the normal solution's gap where it holds one.
    """
    x, y = normal.x, normal.y
    if x.size < 3 or y.size < 3:
        raise InputError("fastsim-strips needs a grid of at least 3 x 3 elements")
    h = normal.gap if normal.gap is not None else geometry.gap(x[:, None], y[None, :])
    _, _, A, B = strip_minima(h, x, normal.dx, normal.dy)
    return A, B


@register("fastsim-strips")
class FastsimStripsModel(FastsimModel):
    """FASTSIM with a local ellipse per strip (Ayasse & Chollet's STRIPES approach).

    Each strip (fixed lateral position y) gets its own flexibilities L1, L2, L3,
    computed from a *local ellipse*: the Hertz ellipse of the gap's relative
    curvatures A(y), B(y) at the strip's centre line, for the patch's approach
    (Ayasse & Chollet, VSD 43, 2005; described as used with STRIPES and ANALYN in
    Tao et al., CM2015).  On a Hertzian (quadratic) gap every local ellipse is the
    Hertz ellipse, so the model reduces to :class:`FastsimModel` and Kalker's linear
    theory.  Where the lateral curvature varies across the patch (worn profiles,
    gauge corner, the tread-flange transition) the flexibilities vary with it.

    The spin varies per strip with the local contact angle delta(y) of the rail
    surface under the strip (as in STRIPES and ANALYN, Tao et al. CM2015):
    phi(y) = phi cos(D) + (omega . s / V) sin(D), D = delta(y) - delta, from the
    wheelset's angular velocity (:meth:`ContactGeometry.spin_at`).  Patches without
    profile geometry (bodies cases) keep the constant spin.

    Needs the patch geometry (``solve(normal, geometry, ...)``) unless the normal
    solution is an ellipse (Hertz), in which case it equals ``fastsim``.
    Options as :class:`FastsimModel`.
    """

    capabilities = frozenset({"strip-march"})
    online_law = None

    @staticmethod
    def _batch_flexibilities(strips, patches, a, b, ok, creepage, material, friction):
        """A local ellipse per strip, from the gap's curvatures along the strip
        (:func:`~railcontact.tangential.fastsim.strip_flexibilities`; a patch without
        an approach, e.g. a light secondary patch of a strip model, has no local
        ellipse: its strips keep the patch's flexibilities), and the spin of the
        local contact angle (as :meth:`_strip_parameters`)."""
        L = batch_flexibilities(strips, a, b, ok, creepage, material, friction, True)
        return L, np.ascontiguousarray(sample_strip_spin(patches, strips.y))

    def _reported_flexibilities(self, L1, L2, L3):
        """Flexibilities per strip (arrays over y)."""
        return (L1, L2, L3)

    def _strip_parameters(self, normal, geometry, material, a, b, creepage, friction):
        my = normal.y.size
        if geometry is None:
            if normal.semi_axes is None:
                raise InputError("fastsim-strips: the patch geometry is needed for the local "
                                 "curvatures of a non-elliptic patch (solve(normal, geometry, ...))")
            return super()._strip_parameters(normal, geometry, material, a, b, creepage,
                                             friction)
        G, nu = material.shear_modulus, material.nu
        A, B = local_curvatures(normal, geometry)
        x_lead, x_trail = normal.strips
        active = np.flatnonzero(np.asarray(x_lead) > np.asarray(x_trail))
        L = np.empty((3, my))
        L[:] = np.asarray(self._flexibilities(a, b, G, nu, creepage, friction,
                                                normal.normal_force))[:, None]
        la, lb, _ = hertz_ellipses(A[active], B[active], material.contact_modulus,
                                   normal.penetration)      # one local ellipse per strip
        # no local ellipse where the approach is not positive (a light patch of a strip
        # model): those strips keep the patch's flexibilities
        good = np.isfinite(la) & np.isfinite(lb) & (la > 0) & (lb > 0)
        active, la, lb = active[good], la[good], lb[good]
        if active.size:
            L[:, active] = np.asarray(self._flexibilities(la, lb, G, nu, creepage, friction,
                                                          normal.normal_force))
        phi = np.ascontiguousarray(geometry.spin_at(normal.y, creepage[2]), dtype=float)
        return (np.ascontiguousarray(L[0]), np.ascontiguousarray(L[1]),
                np.ascontiguousarray(L[2]), phi)
