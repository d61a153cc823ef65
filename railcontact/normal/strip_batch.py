"""The strip models for many patches at once: forces, area and p_max only.

The per-patch models of :mod:`railcontact.normal.semi_hertzian` lay their strips
on a full grid and build a :class:`~railcontact.normal.base.NormalSolution` for
every patch.  For sweeps, wear loops and dynamics, where only the patch results
are needed, this module runs the same models (``kik-piotrowski``, ``kpec``,
``stripes``, ``analyn``; the one implementation of their equations,
:func:`railcontact.normal.strip_theory.strip_pressures`) on all patches together;
only the sampling of the gap differs:

* the gap of every patch is sampled at three points along x on each of ``strips``
  strips, in one compiled loop per profile pair
  (:func:`railcontact.geometry.gap.sample_gap_lines`); a parabola through the three
  samples gives each strip's minimum g(y), its position x_m(y) and the longitudinal
  curvature A(y); the lateral curvature B(y) is the second difference across the
  strips at x_m(y);
* the semi-elliptic pressure of strip j has half-length l_j around x_m(y_j) and
  maximum p_j, so that F_n = sum (pi/2) p_j l_j dy and the area is sum 2 l_j dy.

The results agree with the per-patch models within their grid resolution (tested in
``tests/normal/test_strip_batch.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..geometry.gap import sample_gap_lines
from ..core.hertz_theory import hertz_ellipses
from .strip_theory import MIN_CURVATURE, STRIP_MODELS, parabolic_minima, strip_pressures



@dataclass
class StripSolution:
    """Strip-wise semi-elliptic pressures of many patches (SI units).

    Arrays of shape (patches, strips): ``y`` strip centres, ``x_mid`` strip centres
    along x, ``half`` half-lengths (0: no contact), ``p_strip`` maximum pressure
    per strip and ``A``, ``B`` the gap's local relative curvatures [1/m] (along x at
    the strip's minimum, and across the strips); per patch: ``dy`` strip width,
    ``normal_force``, ``area``, ``pmax``, ``penetration``.
    """

    y: np.ndarray
    dy: np.ndarray
    x_mid: np.ndarray
    half: np.ndarray
    p_strip: np.ndarray
    penetration: np.ndarray
    A: np.ndarray
    B: np.ndarray
    #: (a, b) [m] per patch where the patches are ellipses cut in strips
    #: (:func:`hertz_ellipse_strips`): area, p_max and the equivalent ellipse are then
    #: the ellipse's own
    semi_axes: tuple | None = None

    @property
    def normal_force(self) -> np.ndarray:
        return 0.5 * math.pi * np.sum(self.p_strip * self.half, axis=1) * self.dy

    @property
    def area(self) -> np.ndarray:
        if self.semi_axes is not None:
            return math.pi * self.semi_axes[0] * self.semi_axes[1]
        return 2.0 * np.sum(self.half, axis=1) * self.dy

    @property
    def pmax(self) -> np.ndarray:
        if self.semi_axes is not None:
            area = self.area
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.where(area > 0, 1.5 * self.normal_force / area, 0.0)
        return self.p_strip.max(axis=1, initial=0.0)

    def equivalent_ellipses(self):
        """Semi-axes (a, b) [m] of the equivalent ellipse of every patch (area and
        length/width ratio of the contact, as :func:`~railcontact.tangential.fastsim.
        equivalent_ellipse`); zero where there is no contact."""
        if self.semi_axes is not None:
            return self.semi_axes
        on = self.half > 0
        anyc = on.any(axis=1)
        lead = np.where(on, self.x_mid + self.half, -np.inf).max(axis=1)
        trail = np.where(on, self.x_mid - self.half, np.inf).min(axis=1)
        my = on.shape[1]
        first = np.argmax(on, axis=1)
        last = my - 1 - np.argmax(on[:, ::-1], axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            L = np.where(anyc, lead - trail, 1.0)
            W = np.where(anyc, (last - first + 1) * self.dy, 1.0)
            r = np.sqrt(self.area / math.pi)
            return (np.where(anyc, r * np.sqrt(L / W), 0.0),
                    np.where(anyc, r * np.sqrt(W / L), 0.0))


def strip_geometry(patches, strips: int = 40, penetration=None, margin: float = 0.15,
                   widen: int = 4):
    """Strip quantities of many patches from their exact gaps.

    Returns ``y`` (patches, strips) [m], ``dy`` (patches,), ``x_m``, ``g`` (the
    smallest gap + approach per strip, ~0 at the deepest point), ``A``, ``B``
    [1/m].  The lateral window covers the interpenetration region of each patch
    at ``penetration`` [m] (default: the geometry's approach), from the geometry's
    extent, widened until the outer strips are free.  The patch is the run of
    interpenetrating strips through the deepest strip within the extent; strips
    outside it get g = penetration + 1 m (no contact).
    """
    n = len(patches)
    if strips < 5:
        raise InputError(f"strips {strips!r}: expected at least 5")
    app = np.array([p.approach for p in patches], float)
    pen = app if penetration is None else np.asarray(penetration, float)
    A0 = np.array([max(p.curvatures[0], MIN_CURVATURE) for p in patches], float)
    B0 = np.array([max(p.curvatures[1], MIN_CURVATURE) for p in patches], float)
    ext = np.array([p.extent if p.extent is not None else (0.0, 0.0, 0.0, 0.0)
                    for p in patches], float).reshape(n, 4)
    dpos = np.maximum(pen, 1e-9)
    xc = 0.5 * (ext[:, 0] + ext[:, 1])
    dx = np.maximum(0.5 * (ext[:, 1] - ext[:, 0]), np.sqrt(dpos / A0))
    yc = 0.5 * (ext[:, 2] + ext[:, 3])
    hy = np.maximum(0.5 * (ext[:, 3] - ext[:, 2]), np.sqrt(dpos / B0)) * (1.0 + margin)
    u = -1.0 + (2.0 * np.arange(strips) + 1.0) / strips
    core = hy / (1.0 + margin)                  # the geometry's extent: the deepest strip lies in it
    idx = np.arange(strips)
    todo = np.arange(n)
    out = [np.empty((n, strips)) for _ in range(5)]
    for _ in range(widen + 1):
        y = yc[todo, None] + hy[todo, None] * u[None, :]
        d = dx[todo, None]
        xs = xc[todo, None] + d * np.array([0.0, -1.0, 1.0])[None, :]
        h = sample_gap_lines([patches[k] for k in todo], xs, y) + app[todo, None, None]
        h0 = h[:, 0]
        t, c1, c2, g = parabolic_minima(h[:, 1], h0, h[:, 2], d, 2.0 * d)
        A = np.maximum(c2, MIN_CURVATURE)
        # lateral curvature at fixed x = x_m(y), across the neighbouring strips
        dy = 2.0 * hy[todo, None] / strips
        jc = np.clip(np.arange(strips), 1, strips - 2)

        def at(j):
            return h0[:, j] + c1[:, j] * t + c2[:, j] * t * t
        B = np.maximum(0.5 * (at(jc + 1) - 2.0 * at(jc) + at(jc - 1)) / (dy * dy),
                       MIN_CURVATURE)
        # the patch is the run of interpenetrating strips through the deepest strip of
        # the extent; other regions of the tangent plane (another patch, the flange
        # seen from the tread's plane) are not part of it
        inter = g < pen[todo, None]
        inside = np.abs(y - yc[todo, None]) <= core[todo, None]
        jd = np.argmin(np.where(inside, g, np.inf), axis=1)
        lo = np.where(~inter & (idx < jd[:, None]), idx, -1).max(axis=1) + 1
        hi = np.where(~inter & (idx > jd[:, None]), idx, strips).min(axis=1) - 1
        run = (idx >= lo[:, None]) & (idx <= hi[:, None]) & inter[np.arange(todo.size), jd][:, None]
        g = np.where(run, g, pen[todo, None] + 1.0)     # outside the run: no contact (1 m)
        for arr, val in zip(out, (y, xc[todo, None] + t, g, A, B)):
            arr[todo] = val
        edge = run[:, 0] | run[:, -1]
        if not edge.any():
            break
        todo = todo[edge]
        hy[todo] *= 1.6
    y, xm, g, A, B = out
    return y, 2.0 * hy / strips, xm, g, A, B


def patch_hertz_ellipses(patches, contact_modulus: float, penetration):
    """Hertz's semi-axes a, b [m] and forces [N] of many patches at the
    penetrations [m]: the force with each patch's ``force_curvature`` where it has
    one (:mod:`railcontact.geometry.patch_curvature`), the ellipse with its
    curvatures scaled to that force (a, b ~ F^(1/3)), as
    :func:`railcontact.cases.compiled_case.patch_hertz` and
    :class:`railcontact.normal.hertz.Hertz` have it."""
    n = len(patches)
    A = np.fromiter((p.curvatures[0] for p in patches), float, n)
    B = np.fromiter((p.curvatures[1] for p in patches), float, n)
    a, b, F = hertz_ellipses(A, B, contact_modulus, penetration)
    Bf = np.fromiter((getattr(p, "force_curvature", None) or B[i] for i, p in
                      enumerate(patches)), float, n)
    Bf = np.where(Bf > 0.0, Bf, B)
    if np.any(Bf != B):
        _, _, Fs = hertz_ellipses(A, Bf, contact_modulus, penetration)
        both = (F > 0) & (Fs > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where(both, np.cbrt(Fs / F), 1.0)
        a, b, F = a * scale, b * scale, np.where(both, Fs, F)
    return a, b, F


def hertz_ellipse_strips(patches, contact_modulus: float, strips: int = 40) -> StripSolution:
    """Hertz's ellipses of many patches (at the geometry's approach) cut in
    ``strips`` strips across: strip j at y_j has half-length a sqrt(1 - (y_j/b)^2)
    and peak pressure p0 sqrt(1 - (y_j/b)^2), scaled so that the strips carry the
    Hertz force exactly; for the strip creep laws (``fastrip``) on Hertz patches."""
    patches = list(patches)
    n = len(patches)
    A = np.fromiter((p.curvatures[0] for p in patches), float, n)
    B = np.fromiter((p.curvatures[1] for p in patches), float, n)
    pen = np.maximum(np.fromiter((p.approach for p in patches), float, n), 0.0)
    a, b, F = patch_hertz_ellipses(patches, contact_modulus, pen)
    u = -1.0 + (2.0 * np.arange(strips) + 1.0) / strips
    r = np.sqrt(1.0 - u * u)[None, :]
    y = b[:, None] * u[None, :]
    dy = 2.0 * b / strips
    half = a[:, None] * r
    with np.errstate(divide="ignore", invalid="ignore"):
        p0 = np.where(F > 0, F / (0.5 * math.pi * a * dy * np.sum(r * r)), 0.0)
    return StripSolution(y, dy, np.zeros_like(y), half, p0[:, None] * r, pen,
                         np.broadcast_to(A[:, None], y.shape),
                         np.broadcast_to(B[:, None], y.shape), semi_axes=(a, b))


def solve_strips(model: str, patches, contact_modulus: float, penetration=None,
                 strips: int = 40, elements: int = 20, eps: float = 0.55) -> StripSolution:
    """One strip model on many patches at given approaches.

    Parameters
    ----------
    model : {"kik-piotrowski", "kpec", "stripes", "analyn"}
    patches : sequence of ContactGeometry
    contact_modulus : float
        E* [Pa].
    penetration : array_like, optional
        Approach per patch [m]; default the geometry's approach.
    strips : int
        Strips across each patch's interpenetration region.
    elements : int
        Elements per strip for Kik-Piotrowski's displacement sum.
    eps : float
        Kik-Piotrowski's scaling factor.
    """
    if model not in STRIP_MODELS:
        raise InputError(f"batch strip model {model!r}: expected one of {', '.join(STRIP_MODELS)}")
    patches = list(patches)
    if not patches:
        raise InputError("solve_strips: no patches given")
    pen = (np.array([p.approach for p in patches], float) if penetration is None
           else np.broadcast_to(np.asarray(penetration, float), (len(patches),)).copy())
    if not np.all(np.isfinite(pen)) or np.any(pen < 0):
        raise InputError("penetration: expected finite values >= 0 m")
    y, dy, xm, g, A, B = strip_geometry(patches, strips, pen)
    half, pm = strip_pressures(model, y, dy, xm, g - pen[:, None], A, B, contact_modulus,
                               eps=eps, elements=elements)
    return StripSolution(y, dy, xm, half, pm, pen, A, B)
