"""Results in CONTACT's units and frames: one row per contact patch.

The columns are those of ``../shared/reference/README.md``: positions in mm in the
track frame (``_tr``), rail-profile (``_r``) and wheel-profile (``_w``)
coordinates of CONTACT (for a left-side case y points to the track centre, so
that y points to the right on both sides), the contact angle delta_tr, the
creepages (cphi per mm), and the forces and moment on the rail (body 1) in N and
N mm: F_n along the normal, F_x, F_s in the tangent plane, M_n about the normal;
``fric_power_W``, the patch's frictional power in W as CONTACT's ``FRIC.POWER``
(the power of the tractions on the rail on the rail's slip relative to the wheel:
negative, minus the dissipated :attr:`~railcontact.tangential.TangentialSolution.frictional_power`);
the approach and areas in mm and mm^2, p_max in MPa (N/mm^2); the element counts
of the grid.  ``fx_tr_N``, ``fy_tr_N``, ``fz_tr_N`` are a case's total forces on
the rail in the track frame: F_y = f_s cos(delta) - f_n sin(delta), F_z = f_s
sin(delta) + f_n cos(delta), summed over its patches.
"""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np

from ..geometry.track import rotation

#: the columns of a row, in order (module 3 rows leave the wheel-rail ones empty)
COLUMNS = ("case", "module", "side", "patch", "npatch", "y_ws_mm", "z_ws_mm", "roll_rad",
           "yaw_rad", "vpitch_rad_s", "xcp_tr_mm", "ycp_tr_mm", "zcp_tr_mm", "delta_tr_rad",
           "ycp_r_mm", "zcp_r_mm", "xcp_w_mm", "ycp_w_mm", "zcp_w_mm", "r_wheel_mm", "cksi",
           "ceta", "cphi_per_mm", "veloc_mm_s", "mu", "fn_N", "fx_N", "fs_N", "mn_Nmm",
           "fric_power_W", "approach_mm", "pmax_MPa", "area_mm2", "ncon", "nadh", "nslip", "mx", "my", "dx_mm",
           "ds_mm", "fx_tr_N", "fy_tr_N", "fz_tr_N", "tmax_C", "converged", "message")


def _patch_values(p) -> dict:
    """A patch's solution in CONTACT's units: forces on the rail (railcontact's
    are on the wheel: their negatives), element counts and grid."""
    n, t = p.normal, p.tangential
    ncon = int(np.count_nonzero(n.contact))
    # on the tangential model's grid (the normal one for the exact solvers)
    nadh = int(np.count_nonzero(t.contact & t.stick)) if t is not None else 0
    nslip = int(np.count_nonzero(t.contact & ~t.stick)) if t is not None else 0
    xs, ys = np.asarray(n.x), np.asarray(n.y)
    return {"cksi": float(p.creepage[0]), "ceta": float(p.creepage[1]),
            "cphi_per_mm": float(p.creepage[2]) * 1e-3,
            "mu": float(t.friction) if t is not None else None,
            "fn_N": float(n.normal_force), "fx_N": -t.fx if t is not None else 0.0,
            "fs_N": -t.fy if t is not None else 0.0,
            "mn_Nmm": -t.mz * 1e3 if t is not None else 0.0,
            "fric_power_W": -t.frictional_power if t is not None else 0.0,
            "approach_mm": float(n.penetration) * 1e3, "pmax_MPa": float(n.pmax) * 1e-6,
            "area_mm2": float(n.area) * 1e6, "ncon": ncon, "nadh": nadh,
            "nslip": nslip, "mx": int(xs.size), "my": int(ys.size),
            "dx_mm": float(xs[1] - xs[0]) * 1e3 if xs.size > 1 else None,
            "ds_mm": float(ys[1] - ys[0]) * 1e3 if ys.size > 1 else None}


def rail_coordinates(y, z, meta):
    """Rail-profile coordinates [mm] of CONTACT (the file's, before the cant) from
    railcontact's mounted rail profile's."""
    if "profile_deviation" in meta:
        # a roller's profile turned by roll and lowered by dz: back to the profile
        # as read
        dz, roll = meta["profile_deviation"]
        c, s = math.cos(roll), math.sin(roll)
        y, z = c * y + s * (z - dz), -s * y + c * (z - dz)
    y0, z0 = meta.get("origin_shift", (0.0, 0.0))
    cant = meta.get("cant", 0.0)
    y, z = y + y0, z + z0
    c, s = math.cos(cant), math.sin(cant)
    return (c * y - s * z) * 1e3, (s * y + c * z) * 1e3


def rows(result, mapped) -> list:
    """The rows of one solved case (``result``: :class:`railcontact.SolveResult`,
    ``mapped``: its :class:`~railcontact.contact_inp.mapping.MappedCase`)."""
    meta, raw = mapped.meta, mapped.raw
    status = result.status
    common = {"case": mapped.number, "module": mapped.module, "converged": status.converged,
              "message": status.message}
    if mapped.module == 3:
        p = result.patches[0]
        return [{**common, "patch": 1, "npatch": 1, **_patch_values(p),
                 "tmax_C": p.max_temperature if meta.get("heat") else None}]
    side, ws = meta["side"], raw["wheelset"]
    sgn = 1.0 if side == "right" else -1.0
    pose = result.pose
    z_top = meta["z_top"]
    r0 = meta["nominal_radius"]
    # a wheel-rail case's WheelsetPose or a surface case's SurfacePose
    lateral = pose.lateral_shift if hasattr(pose, "lateral_shift") else pose.lateral
    common.update(side=side, npatch=len(result.patches), y_ws_mm=lateral * 1e3,
                  z_ws_mm=(pose.vertical - z_top) * 1e3, roll_rad=pose.roll, yaw_rad=pose.yaw,
                  vpitch_rad_s=ws["pitch_velocity"])
    # the wheelset's axes and centre in the side frame: wheel-profile x of a point
    R = rotation(sgn * pose.yaw, sgn * pose.roll)
    O = np.array([0.0, sgn * lateral, pose.vertical - r0])
    out, tot = [], np.zeros(3)
    for k, p in enumerate(result.patches, 1):
        g = p.geometry
        x, y, z = (float(v) for v in g.position)
        L = R.T @ (np.array([x, sgn * y, z]) - O)
        yr, zr = rail_coordinates(g.y_rail, g.z_rail, meta)
        # the reference point (on the rail surface) in wheel-profile coordinates
        xw, yw, zw = float(L[0]), float(L[1]) - meta["wheel_offset"], float(L[2]) - r0
        row = {**common, "patch": k, "xcp_tr_mm": x * 1e3,
               "ycp_tr_mm": (y - meta.get("translation", 0.0)) * 1e3,
               "zcp_tr_mm": (z - z_top) * 1e3, "delta_tr_rad": float(g.contact_angle),
               "ycp_r_mm": sgn * yr, "zcp_r_mm": zr, "xcp_w_mm": xw * 1e3,
               "ycp_w_mm": sgn * yw * 1e3, "zcp_w_mm": zw * 1e3, "r_wheel_mm": (r0 + zw) * 1e3,
               "veloc_mm_s": g.velocity * 1e3, **_patch_values(p),
               "tmax_C": p.max_temperature if meta.get("heat") else None}
        d = row["delta_tr_rad"]
        tot += (row["fx_N"], row["fs_N"] * math.cos(d) - row["fn_N"] * math.sin(d),
                row["fs_N"] * math.sin(d) + row["fn_N"] * math.cos(d))
        out.append(row)
    for row in out:
        row.update(fx_tr_N=tot[0], fy_tr_N=tot[1], fz_tr_N=tot[2])
    if not out:                      # no contact: one row with the case's totals
        out.append({**common, "patch": 0, "npatch": 0, "fx_tr_N": 0.0, "fy_tr_N": 0.0,
                    "fz_tr_N": 0.0})
    return out


def to_csv(table: list) -> str:
    """The rows as CSV with the columns of :data:`COLUMNS` (empty where a row has
    no value)."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=COLUMNS, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for r in table:
        w.writerow({k: ("" if r.get(k) is None else _fmt(r[k])) for k in COLUMNS})
    return buf.getvalue()


def _fmt(v):
    if isinstance(v, float):
        return f"{v:.10g}"
    return v


def to_json(table: list, source: str = "") -> str:
    """The rows as JSON: ``{"source": file, "units": "CONTACT (mm, N, rad, s)",
    "rows": [...]}``."""
    clean = [{k: (None if isinstance(v, float) and not math.isfinite(v) else v)
              for k, v in r.items()} for r in table]
    return json.dumps({"source": source, "units": "CONTACT: mm, N, N/mm^2, rad, s",
                       "rows": clean}, allow_nan=False)


def to_text(table: list) -> str:
    """A short table for the terminal."""
    head = (f"{'case':>4} {'side':>5} {'cp':>2} {'ycp_tr':>10} {'delta':>8} {'fn':>10} "
            f"{'fx':>10} {'fs':>10} {'pmax':>8} {'area':>8} {'cksi':>11}")
    lines = [head]
    for r in table:
        if not r.get("npatch", 1):
            lines.append(f"{r['case']:>4} {str(r.get('side', '')):>5}  -  no contact")
            continue
        f = lambda k, w, p: (f"{r[k]:{w}.{p}f}" if r.get(k) is not None   # noqa: E731
                             else " " * w)
        lines.append(f"{r['case']:>4} {str(r.get('side') or ''):>5} {r['patch']:>2} "
                     f"{f('ycp_tr_mm', 10, 4)} {f('delta_tr_rad', 8, 4)} {f('fn_N', 10, 1)} "
                     f"{f('fx_N', 10, 1)} {f('fs_N', 10, 1)} {f('pmax_MPa', 8, 1)} "
                     f"{f('area_mm2', 8, 2)} {r.get('cksi', 0.0):11.4e}")
    return "\n".join(lines)
