"""Subsurface stresses of CONTACT's input files (STRESS digit S = 1, 2, 3).

A case with S >= 1 asks for the stress tensor at blocks of points below its
contact (user guide, "Subsurface stresses"): element centres of the potential
contact area at given depths (ISUBS = 1-3: NZ, ZL, DZ; 5-7: listed depths; 1, 5
every element, 2, 6 a regular selection of columns and rows, 3, 7 listed ones) or
any points (ISUBS = 9: X, Y, Z listed).  The reader keeps the blocks (S = 3 reads
new ones, S = 1, 2 use those kept); this module evaluates them for a solved case:

* the loads are the case's surface tractions on body 1 (module 1: the rail,
  module 3: the upper body, z >= 0 into it), piecewise constant on the elements, in
  CONTACT's contact-local axes (x rolling, y lateral, z depth), mm and N/mm^2;
* element-centre blocks are taken from the FFT convolution of the whole grid per
  depth (:func:`railcontact.subsurface.stresses_on_grid`), ISUBS = 9 points from
  direct sums over the loaded elements
  (:func:`railcontact.subsurface.stresses_at_points`); the half-space stresses
  depend on body 1's Poisson ratio alone (POISS1);
* the points are sorted ascending and ordered as CONTACT writes them (x fastest,
  then y, then z); stresses are tension positive (CONTACT's sign in STRESS).

Each block gives the components SIGXX .. SIGZZ, the mean stress SIGHYD, von Mises'
SIGVM, the principal stresses SIGMA1 >= SIGMA2 >= SIGMA3 and Tresca's SIGTR =
SIGMA1 - SIGMA3 [N/mm^2], and the maxima that CONTACT prints per block
(:func:`block_maxima`).  CONTACT's displacements UX, UY, UZ are not computed.
:func:`to_csv` and :func:`to_netcdf` write them (``railcontact solve FILE.inp
--subsurface FILE.csv|.nc``; docs/subsurface.md).
"""

from __future__ import annotations

import csv
import io
import numpy as np

from ..subsurface import stresses_at_points, stresses_on_grid
from .reader import InpError

#: CONTACT's component order in its .subs files
SUBS_COMPONENTS = ("xx", "xy", "xz", "yy", "yz", "zz")
#: railcontact's (railcontact.subsurface.COMPONENTS) -> CONTACT's order
_ORDER = (0, 3, 4, 1, 5, 2)
#: the columns of one point in :func:`to_csv`
CSV_COLUMNS = ("case", "patch", "block", "x_mm", "y_mm", "z_mm", "sighyd", "sigvm", "sigtr",
               "sigma1", "sigma2", "sigma3") + tuple(f"sig{c}" for c in SUBS_COMPONENTS)
#: the maxima CONTACT prints per block: (name, quantity, kind)
MAXIMA = (("ABSMAX SIGHYD", "sighyd", "absmax"), ("MAX SIGVM", "sigvm", "max"),
          ("MAX SIGTR", "sigtr", "max"), ("MAX SIGMA1", "sigma1", "max"),
          ("MIN SIGMA3", "sigma3", "min"), ("ABSMAX SIGXX", "sigxx", "absmax"),
          ("ABSMAX SIGYY", "sigyy", "absmax"), ("ABSMAX SIGZZ", "sigzz", "absmax"))


def wanted(case) -> bool:
    """Whether a case asks for subsurface stresses (S = 1, 2, 3 with blocks kept)."""
    return case.digits.get("S", 0) in (1, 2, 3) and bool(case.values.get("SUBSURFACE_BLOCKS"))


def _axis(index, centres):
    """Element centres of 1-based column or row numbers (None: all; numbers outside
    the grid are ignored, as CONTACT ignores them)."""
    n = centres.size
    if index is None:
        return np.arange(n)
    k = np.array([i - 1 for i in index if 1 <= i <= n], dtype=int)
    return np.unique(k)


def block_stresses(x, y, size, loads, block, poisson: float) -> dict:
    """One block of subsurface points under piecewise constant loads.

    Parameters
    ----------
    x, y : ndarray
        Element centres [mm] of a uniform grid (x rolling, y lateral).
    size : (float, float)
        The element size (dx, dy) [mm].
    loads : tuple of 3 ndarrays (mx, my)
        Pressure and tangential tractions (p, q_x, q_y) [N/mm^2] on the body.
    block : dict
        The reader's block (``isubs``, ``ix``, ``iy``, ``x``, ``y``, ``z`` [mm]).
    poisson : float
        Poisson's ratio of the body [-].

    Returns
    -------
    dict with ``x``, ``y``, ``z`` [mm] per point (CONTACT's order: x fastest, then y,
    then z), ``sigma`` (n, 6) in CONTACT's order xx, xy, xz, yy, yz, zz and the
    derived ``sighyd``, ``sigvm``, ``sigtr``, ``sigma1``, ``sigma2``, ``sigma3``
    [N/mm^2], and ``shape`` (nx, ny, nz).
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    p, qx, qy = (np.asarray(a, float) for a in loads)
    z = np.array(sorted(float(v) for v in block["z"]))
    if np.any(z < 0):
        raise InpError(f"subsurface depths {block['z']}: expected z >= 0 mm")
    if block["isubs"] == 9:
        xs, ys = np.array(sorted(block["x"]), float), np.array(sorted(block["y"]), float)
        Z, Y, X = np.meshgrid(z, ys, xs, indexing="ij")
        pts = np.c_[X.ravel(), Y.ravel(), Z.ravel()]
        load = np.abs(p) + np.abs(qx) + np.abs(qy) > 0
        i, j = np.nonzero(load)
        hx, hy = 0.5 * float(size[0]), 0.5 * float(size[1])
        rect = np.c_[x[i] - hx, x[i] + hx, y[j] - hy, y[j] + hy]
        ld = np.c_[p[i, j], qx[i, j], qy[i, j]]
        s = stresses_at_points(pts, rect, ld, poisson) if i.size else np.zeros((len(pts), 6))
        shape = (xs.size, ys.size, z.size)
    else:
        ix, iy = _axis(block["ix"], x), _axis(block["iy"], y)
        if x.size < 2 or y.size < 2:
            raise InpError(f"subsurface block ISUBS = {block['isubs']} on a grid of {x.size} x "
                           f"{y.size} elements: expected at least 2 x 2 (or ISUBS = 9)")
        full = stresses_on_grid(x, y, p, qx, qy, z, poisson)        # (6, mx, my, nz)
        sel = full[:, ix][:, :, iy]                                   # (6, nx, ny, nz)
        # CONTACT's order: x fastest, then y, then z
        s = np.transpose(sel, (3, 2, 1, 0)).reshape(-1, 6)
        Z, Y, X = np.meshgrid(z, y[iy], x[ix], indexing="ij")
        shape = (ix.size, iy.size, z.size)
    out = derived(s[:, list(_ORDER)])
    out.update(x=X.ravel(), y=Y.ravel(), z=Z.ravel(), shape=shape)
    return out


def derived(sigma) -> dict:
    """The stress measures of CONTACT's STRESS subprogram from components (n, 6) in
    CONTACT's order xx, xy, xz, yy, yz, zz [N/mm^2]."""
    xx, xy, xz, yy, yz, zz = sigma.T
    T = np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1),
                  np.stack([xz, yz, zz], -1)], -2)
    ev = np.linalg.eigvalsh(T)                       # ascending
    vm = np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2)
                 + 3.0 * (xy ** 2 + xz ** 2 + yz ** 2))
    return {"sigma": sigma, "sighyd": (xx + yy + zz) / 3.0, "sigvm": vm,
            "sigma1": ev[:, 2], "sigma2": ev[:, 1], "sigma3": ev[:, 0],
            "sigtr": ev[:, 2] - ev[:, 0]}


def quantity(block: dict, name: str) -> np.ndarray:
    """A block's values of one CSV quantity (``sigvm``, ``sigxx`` ...)."""
    if name.startswith("sig") and name[3:] in SUBS_COMPONENTS:
        return block["sigma"][:, SUBS_COMPONENTS.index(name[3:])]
    return block[name]


def block_maxima(block: dict) -> list:
    """The maxima that CONTACT prints per block (O_s >= 1): ``(name, value, (x, y,
    z))`` for ABSMAX SIGHYD, MAX SIGVM, MAX SIGTR, MAX SIGMA1, MIN SIGMA3 and ABSMAX
    SIGXX, SIGYY, SIGZZ [N/mm^2, mm], the first point in CONTACT's order where
    several are equal."""
    out = []
    for name, q, kind in MAXIMA:
        v = quantity(block, q)
        k = int(np.argmax(np.abs(v) if kind == "absmax" else (v if kind == "max" else -v)))
        out.append((name, float(v[k]), (float(block["x"][k]), float(block["y"][k]),
                                         float(block["z"][k]))))
    return out


def grid_loads(result) -> tuple:
    """``(x, y, (dx, dy), (p, q_x, q_y))`` [mm, N/mm^2] of a module 3 case solved on
    its own grid (:class:`~railcontact.contact_inp.module3.CaseResult`: tractions on
    body 1)."""
    g = result.grid
    return (g.x * 1e3, g.y * 1e3, (g.dx * 1e3, g.dy * 1e3),
            (result.pressure * 1e-6, result.px * 1e-6, result.py * 1e-6))


def patch_loads(patch) -> tuple:
    """``(x, y, (dx, dy), (p, q_x, q_y))`` [mm, N/mm^2] of a solved patch
    (:class:`~railcontact.cases.results.PatchResult`) on body 1, the rail: the
    pressure and minus the tangential solution's tractions (those on the wheel),
    on the patch's grid about its reference point (CONTACT's x, s)."""
    n, t = patch.normal, patch.tangential
    p = np.asarray(n.pressure, float)
    qx = qy = np.zeros_like(p)
    if t is not None:
        if np.shape(t.traction_x) != p.shape:
            raise InpError(f"subsurface stresses: the tangential solution's grid "
                           f"{np.shape(t.traction_x)} is not the normal one's {p.shape}")
        qx, qy = -np.asarray(t.traction_x, float), -np.asarray(t.traction_y, float)
    x, y = np.asarray(n.x, float), np.asarray(n.y, float)
    size = (float(x[1] - x[0]) * 1e3, float(y[1] - y[0]) * 1e3)
    return x * 1e3, y * 1e3, size, (p * 1e-6, qx * 1e-6, qy * 1e-6)


def case_blocks(case, patches) -> list:
    """Every block of a solved case's subsurface points, for each of its patches.

    ``patches``: per patch ``(x, y, (dx, dy), (p, q_x, q_y))`` on body 1, mm and
    N/mm^2.
    Returns dicts of :func:`block_stresses` with ``case``, ``patch`` (1-based),
    ``block`` (1-based) and ``maxima`` (:func:`block_maxima`)."""
    nu = float(case.values["POISS1"])
    out = []
    for k, (x, y, size, loads) in enumerate(patches, 1):
        for b, block in enumerate(case.values["SUBSURFACE_BLOCKS"], 1):
            r = block_stresses(x, y, size, loads, block, nu)
            r.update(case=case.number, patch=k, block=b, maxima=block_maxima(r))
            out.append(r)
    return out


def to_csv(blocks: list) -> str:
    """The points of every block, one per line (:data:`CSV_COLUMNS`; CONTACT's
    units: mm and N/mm^2, tension positive)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for b in blocks:
        cols = [quantity(b, c) for c in CSV_COLUMNS[6:]]
        for i in range(b["x"].size):
            w.writerow([b["case"], b["patch"], b["block"], f"{b['x'][i]:.10g}",
                        f"{b['y'][i]:.10g}", f"{b['z'][i]:.10g}"]
                       + [f"{c[i]:.10g}" for c in cols])
    return buf.getvalue()


def to_dataset(blocks: list):
    """The points of every block as one :class:`xarray.Dataset` along ``point``
    (``case``, ``patch``, ``block`` per point; mm, N/mm^2)."""
    import xarray as xr
    n = sum(b["x"].size for b in blocks)
    cat = (lambda f: np.concatenate([f(b) for b in blocks]) if blocks   # noqa: E731
           else np.zeros(0))
    data = {name: ("point", cat(lambda b, nm=name: np.full(b["x"].size, b[nm], dtype=int)))
            for name in ("case", "patch", "block")}
    for c, unit in (("x", "mm"), ("y", "mm"), ("z", "mm")):
        data[f"{c}_mm"] = ("point", cat(lambda b, c=c: b[c]), {"units": unit})
    for q in CSV_COLUMNS[6:]:
        data[q] = ("point", cat(lambda b, q=q: quantity(b, q)),
                   {"units": "N/mm^2", "long_name": f"CONTACT's {q.upper()}, tension positive"})
    ds = xr.Dataset(data, coords={"point": np.arange(n)})
    ds.attrs.update(frame="CONTACT's contact-local axes: x rolling, y lateral, z depth into "
                          "body 1 (module 1: the rail)", units="mm, N/mm^2")
    return ds


def maxima_text(blocks: list) -> str:
    """CONTACT's printed maxima per block, for the terminal."""
    lines = []
    for b in blocks:
        lines.append(f" case {b['case']}, patch {b['patch']}: SUBSURFACE STRESSES BLOCK "
                     f"{b['block']:2d}:")
        for name, v, (x, y, z) in b["maxima"]:
            lines.append(f" {name:>13} = {v:9.3f} AT (X,Y,Z) = ({x:8.3f},{y:8.3f},{z:8.3f})")
    return "\n".join(lines)
