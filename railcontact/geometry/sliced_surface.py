"""The surface of a rail that varies along the track, given by slices
(:class:`railcontact.profiles.slices.RailSlices`), interpolated as CONTACT does (its
user guide, "3D surface building"): each slice is resampled uniformly in its summed
chord length, part by part between its features, with as many points per part in
every slice (1 + int(longest part / ``spacing``) segments; CONTACT's spacing
0.5 mm); the points of equal index form 'interpolation paths' y_j(s), z_j(s) along
the track, interpolated by cubic splines through the slices (not-a-knot); the
cross-section at s is the curve through (y_j(s), z_j(s)), a parametric natural
cubic spline in its summed chord length (CONTACT's ``varprof_get_loc_z_at_xy``; why
not a spline in the point index: docs/tuning.md, section "Geometry search").  An
interrupted rail (features missing from some slices) is made of the parts that
exist at s, with gaps between them (see :class:`SlicedSurface`).

Heights and slopes as every surface of :mod:`railcontact.geometry.surfaces` gives
them: z(s, y) [m] down, NaN where there is no surface.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np
from numba import njit
from scipy.interpolate import CubicSpline, make_interp_spline

from ..core.errors import InputError, ProfileError
from ..profiles.profile import Profile
from ..profiles.slices import RailSlices


#: CONTACT's largest spacing [m] of the resampled slices (``ds_max2d`` = 0.5 mm)
SLICE_SPACING = 5e-4


@njit(cache=True, nogil=True)
def _interval(Y, r, m, yk):
    """The interval i of row r's samples Y[r, :m] (increasing) with Y[r, i] <= yk <=
    Y[r, i + 1], by bisection."""
    lo, hi = 0, m - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if Y[r, mid] <= yk:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True, nogil=True)
def _hermite(Y, Z, B, G, n, row, y, z, dz):
    """z(y) and dz/dy on the rows of cross-sections (points Y[r, :n[r]], Z[r, :n[r]],
    Y increasing): cubic Hermite interpolation with the three-point slopes of the
    samples, one-sided at the break points B (the features: a kink may lie there)
    and at the ends of the gaps G (intervals where the rail is interrupted, NaN
    there); NaN outside a row."""
    for k in range(y.size):
        r = row[k]
        m = n[r]
        yk = y[k]
        if m < 2 or not (Y[r, 0] <= yk <= Y[r, m - 1]):
            z[k] = np.nan
            dz[k] = np.nan
            continue
        i = _interval(Y, r, m, yk)
        if G[r, i]:
            z[k] = np.nan
            dz[k] = np.nan
            continue
        h = Y[r, i + 1] - Y[r, i]
        # three-point slopes at i and i+1 (one-sided at the ends)
        d0 = (Z[r, i + 1] - Z[r, i]) / h
        if i > 0 and not B[r, i] and not G[r, i - 1]:
            h0 = Y[r, i] - Y[r, i - 1]
            s0 = (Z[r, i] - Z[r, i - 1]) / h0
            m0 = (h * s0 + h0 * d0) / (h0 + h)
        else:
            m0 = d0
        if i + 2 < m and not B[r, i + 1] and not G[r, i + 1]:
            h2 = Y[r, i + 2] - Y[r, i + 1]
            s2 = (Z[r, i + 2] - Z[r, i + 1]) / h2
            m1 = (h2 * d0 + h * s2) / (h + h2)
        else:
            m1 = d0
        t = (yk - Y[r, i]) / h
        t2 = t * t
        t3 = t2 * t
        z[k] = ((2 * t3 - 3 * t2 + 1) * Z[r, i] + (t3 - 2 * t2 + t) * h * m0
                + (-2 * t3 + 3 * t2) * Z[r, i + 1] + (t3 - t2) * h * m1)
        dz[k] = ((6 * t2 - 6 * t) * Z[r, i] / h + (3 * t2 - 4 * t + 1) * m0
                 + (-6 * t2 + 6 * t) * Z[r, i + 1] / h + (3 * t2 - 2 * t) * m1)


@njit(cache=True, nogil=True)
def _tensor(CY, CZ, Y, G, n, mono, row, y, z, dz):
    """z(y) and dz/dy on cross-sections given as parametric cubic splines (the
    coefficients CY, CZ (4, nv - 1, rows) of each interval in its local parameter,
    highest power first; the samples Y[r, :n[r]]): the interval holding y by
    bisection, its parameter by Newton's method on Y(t) = y.  Rows whose Y is not
    increasing (``mono`` False), points outside a row and in a gap G (an interval
    where the rail is interrupted) give NaN (the caller uses the samples for the
    rows that are not increasing)."""
    for k in range(y.size):
        r = row[k]
        m = n[r]
        yk = y[k]
        if not mono[r] or m < 2 or not (Y[r, 0] <= yk <= Y[r, m - 1]):
            z[k] = np.nan
            dz[k] = np.nan
            continue
        j = _interval(Y, r, m, yk)
        if G[r, j]:
            z[k] = np.nan
            dz[k] = np.nan
            continue
        a0, a1, a2, a3 = CY[0, j, r], CY[1, j, r], CY[2, j, r], CY[3, j, r] - yk
        t = (yk - Y[r, j]) / (Y[r, j + 1] - Y[r, j])
        for _ in range(20):
            f = ((a0 * t + a1) * t + a2) * t + a3
            d = (3.0 * a0 * t + 2.0 * a1) * t + a2
            if d == 0.0:
                break
            step = f / d
            t = min(max(t - step, 0.0), 1.0)
            if abs(step) < 1e-14:
                break
        b0, b1, b2, b3 = CZ[0, j, r], CZ[1, j, r], CZ[2, j, r], CZ[3, j, r]
        z[k] = ((b0 * t + b1) * t + b2) * t + b3
        dzt = (3.0 * b0 * t + 2.0 * b1) * t + b2
        dyt = (3.0 * a0 * t + 2.0 * a1) * t + a2
        dz[k] = dzt / dyt if dyt != 0.0 else np.nan


@njit(cache=True, nogil=True)
def _chord_splines(Ys, Zs, n, G, cy, cz):
    """Natural cubic splines y(c), z(c) of each row of points (Ys[r, :n[r]],
    Zs[r, :n[r]]) in its summed chord length c, one spline per piece between the
    gaps G[r, :n[r] - 1] (CONTACT's cross-sections: ``varprof_get_loc_z_at_xy`` fits
    a spline in arc length through the resampled points), as coefficients in the
    local parameter t in [0, 1] of each interval (highest power first), written
    into cy, cz of shape (4, nv - 1, rows); zero on the gaps."""
    rows, nv = Ys.shape
    h = np.empty(nv)
    diag = np.empty(nv)
    rhs = np.empty(nv)
    M = np.empty(nv)
    cp = np.empty(nv)
    for r in range(rows):
        for i in range(n[r] - 1):
            h[i] = max(math.hypot(Ys[r, i + 1] - Ys[r, i], Zs[r, i + 1] - Zs[r, i]), 1e-15)
            if G[r, i]:
                for q in range(4):
                    cy[q, i, r] = 0.0
                    cz[q, i, r] = 0.0
        a = 0
        while a < n[r] - 1:
            if G[r, a]:
                a += 1
                continue
            b = a + 1                          # the piece: points a .. b
            while b < n[r] - 1 and not G[r, b]:
                b += 1
            _natural_spline(Ys, r, a, b, h, diag, rhs, M, cp, cy)
            _natural_spline(Zs, r, a, b, h, diag, rhs, M, cp, cz)
            a = b


@njit(cache=True, nogil=True)
def _natural_spline(arr, r, a, b, h, diag, rhs, M, cp, out):
    """The natural cubic spline through arr[r, a:b + 1] at the chord steps h[a:b]:
    its second derivatives M by the Thomas algorithm, then each interval's
    coefficients in its local parameter into out[:, a:b, r]."""
    M[a] = 0.0
    M[b] = 0.0
    if b - a > 1:
        for i in range(a + 1, b):
            diag[i] = 2.0 * (h[i - 1] + h[i])
            rhs[i] = 6.0 * ((arr[r, i + 1] - arr[r, i]) / h[i]
                            - (arr[r, i] - arr[r, i - 1]) / h[i - 1])
        cp[a + 1] = h[a + 1] / diag[a + 1] if b - a > 2 else 0.0
        rhs[a + 1] = rhs[a + 1] / diag[a + 1]
        for i in range(a + 2, b):
            den = diag[i] - h[i - 1] * cp[i - 1]
            cp[i] = h[i] / den if i < b - 1 else 0.0
            rhs[i] = (rhs[i] - h[i - 1] * rhs[i - 1]) / den
        M[b - 1] = rhs[b - 1]
        for i in range(b - 2, a, -1):
            M[i] = rhs[i] - cp[i] * M[i + 1]
    for i in range(a, b):
        hi = h[i]
        out[0, i, r] = (M[i + 1] - M[i]) / (6.0 * hi) * hi ** 3
        out[1, i, r] = 0.5 * M[i] * hi * hi
        out[2, i, r] = (arr[r, i + 1] - arr[r, i]) - hi * hi * (2.0 * M[i] + M[i + 1]) / 6.0
        out[3, i, r] = arr[r, i]


class SlicedSurface:
    """A rail that varies along the track, interpolated between its slices (see
    the module notes).

    Parameters
    ----------
    slices : RailSlices
    spacing : float
        Largest spacing [m] of the resampled slices (default CONTACT's 0.5 mm).

    Notes
    -----
    An interrupted rail (CONTACT's 'interruptions': a feature missing from a slice)
    is made of the parts that exist at s.  A part (the profile between two
    successive features) exists in the slices that hold both its features, and
    along the track from the first to the last slice of each run of successive
    slices that hold it: the interpolation paths of its points are splines through
    those slices only.  A crossing nose that appears between two slices begins at
    the first slice that holds it, with a vertical face.  The cross-section at s is
    made of pieces, one natural spline in chord length each, with no surface (NaN)
    in the gaps between them.
    """

    #: cross-sections kept (by position), each a row of ~n_paths points
    CACHE = 4096

    def __init__(self, slices: RailSlices, spacing: float = SLICE_SPACING):
        if not (isinstance(spacing, (int, float)) and 1e-5 <= spacing <= 5e-3):
            raise InputError(f"slice spacing {spacing!r} m: expected a value in [1e-5, 5e-3]")
        self.slices = slices
        self.name = slices.name
        self.spacing = float(spacing)
        Y, Z, self._breaks, self._part, present = self._resample(slices, self.spacing)
        self.paths = (Y, Z)
        s = slices.s
        # the paths' splines along s: one per set of paths that exist in the same
        # slices, and per run of successive slices of that set
        self._splines = []
        exists = np.isfinite(Y)
        packed = np.ascontiguousarray(np.packbits(exists, axis=0).T)     # a key per path
        _, first, which = np.unique(packed.view(f"V{packed.shape[1]}").ravel(),
                                    return_index=True, return_inverse=True)
        for g, j in enumerate(first):
            cols = np.flatnonzero(which.ravel() == g)
            for a, b in _runs(exists[:, j]):
                self._splines.append((cols, s[a], s[b], CubicSpline(
                    s[a:b + 1], np.hstack((Y[a:b + 1, cols], Z[a:b + 1, cols])), axis=0,
                    bc_type="not-a-knot")))
        # each part's stretches along s
        self._spans = [[(s[a], s[b]) for a, b in _runs(present[:, p])]
                       for p in range(present.shape[1])]
        self._cache: OrderedDict = OrderedDict()

    @staticmethod
    def _resample(slices: RailSlices, spacing: float):
        """Each slice at the same number of points per part, uniformly in its summed
        chord length (CONTACT's varprof_make_vj / make_2dspline); the points of a
        part that a slice lacks are NaN.  Returns the points Y, Z (slices, paths),
        the paths at inner features, the part of each interval between paths and
        the parts present in each slice (slices, parts)."""
        n = len(slices)
        chords, splines = [], []
        for p in slices.profiles:
            c = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(p.y), np.diff(p.z)))))
            chords.append(c)
            splines.append((make_interp_spline(c, p.y, k=3), make_interp_spline(c, p.z, k=3)))
        ends = np.array([c[-1] for c in chords])
        if slices.features is None:
            feats = np.column_stack((np.zeros(n), ends))
        else:
            feats = np.array(slices.features, dtype=float)
            feats = np.where(feats < 0, np.nan, np.minimum(feats, ends[:, None]))
        present = np.isfinite(feats[:, :-1]) & np.isfinite(feats[:, 1:])
        lengths = np.where(present, np.diff(feats, axis=1), np.nan)
        bad = present & ~(lengths > 1e-9)
        if bad.any():
            k = int(np.flatnonzero(bad.any(axis=1))[0])
            raise ProfileError(f"rail slices {slices.name!r}: the features of slice {k + 1} "
                               f"(s = {slices.s[k]:.6g} m) are not increasing within the "
                               "profile")
        longest = np.max(np.where(present, lengths, 0.0), axis=0)
        nseg = 1 + ((longest + 1e-9) / spacing).astype(int)
        first = np.concatenate(([0], np.cumsum(nseg)))      # path index of each feature
        nv = int(first[-1]) + 1
        breaks = np.zeros(nv, dtype=bool)
        breaks[first[1:-1]] = True                          # the inner features
        part = np.repeat(np.arange(nseg.size), nseg)
        Y = np.full((n, nv), np.nan)
        Z = np.full((n, nv), np.nan)
        for k in range(n):
            idx, sj = [], []
            for p in np.flatnonzero(present[k]):
                t = np.arange(nseg[p] + 1) / nseg[p]
                idx.append(first[p] + np.arange(nseg[p] + 1))
                sj.append(feats[k, p] + lengths[k, p] * t)
            idx = np.concatenate(idx)
            sj = np.clip(np.concatenate(sj), 0.0, ends[k])
            Y[k, idx] = splines[k][0](sj)
            Z[k, idx] = splines[k][1](sj)
        return Y, Z, breaks, part, present

    def _sections(self, m):
        """The cross-sections at the positions m: for each, the points of the paths
        that exist there (compacted, padded with NaN), their number and the gaps
        between them (intervals of a part that does not exist there)."""
        nv = self.paths[0].shape[1]
        Ys = np.full((m.size, nv), np.nan)
        Zs = np.full((m.size, nv), np.nan)
        for cols, lo, hi, spline in self._splines:
            sel = (m >= lo) & (m <= hi)
            if sel.any():
                v = spline(m[sel])
                Ys[np.ix_(sel, cols)] = v[:, :cols.size]
                Zs[np.ix_(sel, cols)] = v[:, cols.size:]
        parts = np.zeros((m.size, len(self._spans)), dtype=bool)
        for p, spans in enumerate(self._spans):
            for lo, hi in spans:
                parts[:, p] |= (m >= lo) & (m <= hi)
        inside = parts[:, self._part]                       # (rows, nv - 1)
        Yc = np.full((m.size, nv), np.nan)
        Zc = np.full((m.size, nv), np.nan)
        Gc = np.zeros((m.size, nv - 1), dtype=np.bool_)
        count = np.zeros(m.size, dtype=np.int64)
        index = []
        for i in range(m.size):
            idx = np.flatnonzero(np.isfinite(Ys[i]))
            k = idx.size
            Yc[i, :k], Zc[i, :k], count[i] = Ys[i, idx], Zs[i, idx], k
            if k > 1:
                Gc[i, :k - 1] = ~((np.diff(idx) == 1) & inside[i, idx[:-1]])
            index.append(idx)
        return Yc, Zc, count, Gc, index

    def _rows(self, s_unique):
        """Cross-sections at the positions ``s_unique`` (cached by position): their
        samples (y_j, z_j), gaps and parametric cubic splines in chord length; rows
        whose y is not increasing (a fold-back, seen from above) also as the samples
        that keep y increasing (points behind the running maximum dropped).  Returns
        the arrays of :func:`_tensor` and :func:`_hermite`."""
        keys = [round(float(v), 12) for v in s_unique]
        missing = sorted({k for k in keys if k not in self._cache})
        if missing:
            Ys, Zs, count, G, index = self._sections(np.asarray(missing, float))
            cy = np.zeros((4, Ys.shape[1] - 1, Ys.shape[0]))
            cz = np.zeros_like(cy)
            _chord_splines(Ys, Zs, count, G, cy, cz)
            for i, key in enumerate(missing):
                k = count[i]
                if k < 2:
                    entry = None
                else:
                    yr, zr, gr = Ys[i, :k], Zs[i, :k], G[i, :k - 1]
                    mono = bool(np.all(np.diff(yr) > 0))
                    keep = np.concatenate(([True], yr[1:] > np.maximum.accumulate(yr)[:-1]))
                    kk = np.flatnonzero(keep)
                    cg = np.concatenate(([0], np.cumsum(gr)))
                    entry = (yr, zr, cy[:, :k - 1, i], cz[:, :k - 1, i], gr, mono, yr[keep],
                             zr[keep], self._breaks[index[i]][keep],
                             cg[kk[1:]] - cg[kk[:-1]] > 0)
                self._cache[key] = entry
                if len(self._cache) > self.CACHE:
                    self._cache.popitem(last=False)
        rows = [self._cache.get(k) for k in keys]
        nr = len(rows)
        nv = self.paths[0].shape[1]
        width = max([2] + [r[6].size for r in rows if r is not None])
        Y = np.full((nr, nv), np.nan)
        CY = np.zeros((4, nv - 1, nr))
        CZ = np.zeros((4, nv - 1, nr))
        G = np.zeros((nr, nv - 1), dtype=np.bool_)
        n = np.zeros(nr, dtype=np.int64)
        mono = np.zeros(nr, dtype=np.bool_)
        Yf = np.full((nr, width), np.nan)
        Zf = np.full((nr, width), np.nan)
        Bf = np.zeros((nr, width), dtype=np.bool_)
        Gf = np.zeros((nr, width - 1), dtype=np.bool_)
        nf = np.zeros(nr, dtype=np.int64)
        for i, r in enumerate(rows):
            if r is None:
                continue
            yr, zr, cyr, czr, gr, mo, yk, zk, bk, gk = r
            k = yr.size
            Y[i, :k] = yr
            CY[:, :k - 1, i] = cyr
            CZ[:, :k - 1, i] = czr
            G[i, :k - 1] = gr
            n[i] = k
            mono[i] = mo
            Yf[i, :yk.size] = yk
            Zf[i, :zk.size] = zk
            Bf[i, :bk.size] = bk
            Gf[i, :gk.size] = gk
            nf[i] = yk.size
        return (CY, CZ, Y, G, n, mono), (Yf, Zf, Bf, Gf, nf)

    def height(self, s, y):
        """Height z [m] and slope dz/dy [-] at (s, y) (arrays of one shape); NaN
        outside the slices' range of s, beyond a cross-section's ends and where the
        rail is interrupted."""
        s, y = np.broadcast_arrays(np.asarray(s, float), np.asarray(y, float))
        shape = s.shape
        su, inv = np.unique(s.ravel(), return_inverse=True)
        tensor, samples = self._rows(su)
        row = inv.astype(np.int64).ravel()
        yy = np.ascontiguousarray(y.ravel())
        z = np.empty(y.size)
        dz = np.empty(y.size)
        _tensor(*tensor, row, yy, z, dz)
        fold = ~tensor[5][row]
        if fold.any():                      # rows with a fold-back: the samples seen from above
            zf = np.empty(int(fold.sum()))
            dzf = np.empty(zf.size)
            _hermite(*samples, row[fold], yy[fold], zf, dzf)
            z[fold], dz[fold] = zf, dzf
        return z.reshape(shape), dz.reshape(shape)

    def section(self, s: float) -> Profile:
        """The cross-section at s as a :class:`Profile` (for curvatures; the gaps of
        an interrupted rail bridged by straight lines)."""
        _, (Y, Z, _, _, n) = self._rows(np.array([float(s)]))
        if n[0] < 8:
            raise ProfileError(f"rail {self.name!r}: no cross-section at s = {s:.6g} m (slices "
                               f"cover [{self.slices.s[0]:.6g}, {self.slices.s[-1]:.6g}] m)")
        return Profile(Y[0, :n[0]], Z[0, :n[0]], kind="rail", name=f"{self.name}@{s:.4f}")

    def s_range(self) -> tuple:
        return (float(self.slices.s[0]), float(self.slices.s[-1]))


def _runs(mask) -> list:
    """(first, last) indices of the runs of at least two successive True in mask."""
    m = np.concatenate(([False], np.asarray(mask, bool), [False]))
    edges = np.flatnonzero(np.diff(m.astype(np.int8)))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2]) if b - a > 1]
