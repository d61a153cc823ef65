"""Reading and writing profile files.

Supported formats
-----------------
* SIMPACK ``.prr`` (rail) / ``.prw`` (wheel): the header options ``mirror.y``,
  ``mirror.z``, ``inversion`` and ``units.len.f`` are applied.
* MiniProf ``.ban`` (rail) / ``.whl`` (wheel): header lines (``Key=Value`` or
  old-style free text) up to the first empty line, then columns as named by
  ``ColumnDef`` (X lateral, Y vertical; default X, Y), shifted by ``XOffset`` and
  ``YOffset``; values in mm.  ``!``, ``"``, ``%`` and ``#`` start comments.
* Plain text / CSV: two columns y, z; ``#``, ``%``, ``"`` and ``!`` start comments.

Units are detected from the profile width unless given (``units="mm"`` or ``"m"``);
the assumption is logged.  The vertical orientation is detected as CONTACT
detects it (:func:`~railcontact.profiles.processing.z_points_down`) unless
``z_down`` or ``options.mirror_z`` is given; a wheel whose flange lies at positive
y is mirrored so that the flange is at negative y (right-wheel convention) unless
mirroring is given.  The points are then processed along their arc length
(:func:`process_points`: zig-zag repair, the
options' scale and smoothing, the visible surface of a folded face).
"""

from __future__ import annotations

import logging
import re
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..core.checks import shown
from ..core.errors import ProfileError
from ..core.files import write_text
from .processing import (ProfileOptions, find_kinks, remove_close_points, remove_zigzags,
                         smooth_points, z_points_down)
from .profile import MAX_WIDTH, MIN_WIDTH, Profile

log = logging.getLogger(__name__)

_NUM = re.compile(r"^[\s,;]*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def _kind_from_suffix(path: Path) -> str | None:
    return {".prr": "rail", ".ban": "rail", ".prw": "wheel", ".whl": "wheel"}.get(
        path.suffix.lower())


_COMMENT = re.compile(r'[!"%#]')


def _strip_comment(line: str) -> str:
    """The line up to its first comment character (``!``, ``"``, ``%``, ``#``)."""
    m = _COMMENT.search(line)
    return (line[:m.start()] if m else line).strip()


def _parse_numbers(lines, path, ncol_min=2):
    rows = []
    for ln, line in lines:
        s = _strip_comment(line)
        if not s:
            continue
        parts = [p for p in re.split(r"[\s,;]+", s) if p]
        vals = []
        for p in parts:             # the leading numbers; text after them is ignored
            try:
                vals.append(float(p))
            except ValueError:
                break
        if not vals:
            if rows:
                raise ProfileError(f"{path}: line {ln}: {shown(line.strip())} is not numeric; "
                                   "expected columns of numbers y z")
            continue  # header line before the data
        if len(vals) < ncol_min:
            raise ProfileError(f"{path}: line {ln}: expected at least {ncol_min} columns, "
                               f"got {len(vals)}")
        rows.append(vals[:max(ncol_min, len(vals))])
    if not rows:
        raise ProfileError(f"{path}: no profile points found; expected columns y z")
    width = min(len(r) for r in rows)
    return np.array([r[:width] for r in rows], dtype=float)


def _read_simpack(path: Path):
    text = path.read_text(errors="replace").splitlines()
    opts = {}
    pts, inside, block = [], False, ""
    for ln, line in enumerate(text, 1):
        s = line.strip()
        if s.endswith(".begin") and not s.startswith("point"):
            block = s[:-len(".begin")]
            continue
        if s.startswith("point.begin"):
            inside = True
            continue
        if s.startswith("point.end"):
            inside = False
            continue
        if inside:
            pts.append((ln, line))
            continue
        m = re.match(r"^([A-Za-z][\w.]*)\s*=\s*([^!]*)", s)
        if m:
            key = m.group(1).lower()
            opts[f"{block}.{key}" if block == "header" else key] = m.group(2).strip().strip("'")
    if not pts:
        raise ProfileError(f"{path}: no 'point.begin' ... 'point.end' block; "
                           "expected a SIMPACK profile file")
    data = _parse_numbers(pts, path)
    y, z = data[:, 0], data[:, 1]
    if int(float(opts.get("mirror.y", 0))):
        y = -y
    if int(float(opts.get("mirror.z", 0))):
        z = -z
    factor = float(opts.get("units.len.f", 1.0))
    if not factor > 0:
        raise ProfileError(f"{path}: units.len.f = {factor}; expected a positive factor")
    kind = {"0": "rail", "1": "wheel"}.get(str(opts.get("header.type", "")).strip())
    return y / factor, z / factor, kind, "m", True


def _read_miniprof(path: Path):
    text = path.read_text(errors="replace").splitlines()
    header, data_lines, in_header = {}, [], None
    for ln, line in enumerate(text, 1):
        s = _strip_comment(line)
        if in_header is None:                  # before the first line that counts
            if not s:
                continue
            in_header = not _NUM.match(s) or "=" in s
        if in_header:
            if not line.strip():               # the data follow the first empty line
                in_header = False
                continue
            m = re.match(r"^\s*([A-Za-z_][\w.]*)\s*=\s*(.*)$", s)
            if m:
                header[m.group(1).lower()] = m.group(2).strip()
            continue
        data_lines.append((ln, line))
    cols = [c.strip().upper() for c in header.get("columndef", "X,Y").split(",")]
    if "X" not in cols or "Y" not in cols:
        raise ProfileError(f"{path}: ColumnDef={shown(header.get('columndef'))}; expected X and Y")
    data = _parse_numbers(data_lines, path, ncol_min=max(cols.index("X"), cols.index("Y")) + 1)

    def offset(key):
        try:
            return float(header.get(key) or 0.0)
        except ValueError:
            raise ProfileError(f"{path}: {key} = {shown(header.get(key))}; expected a number "
                               "(mm)") from None

    return (data[:, cols.index("X")] + offset("xoffset"),
            data[:, cols.index("Y")] + offset("yoffset"), None, "mm", None)


def _read_text(path: Path):
    text = path.read_text(errors="replace").splitlines()
    units = None
    for line in text[:5]:
        m = re.search(r"units?\s*[:=]\s*(mm|m)\b", line)
        if line.lstrip().startswith("#") and m:
            units = m.group(1)
    data = _parse_numbers(list(enumerate(text, 1)), path)
    return data[:, 0], data[:, 1], None, units, None


def read_profile(path, kind: str | None = None, units: str = "auto",
                 z_down: bool | None = None, mirror_y: bool | None = None,
                 name: str | None = None, options: ProfileOptions | None = None) -> Profile:
    """Read a profile file into a :class:`Profile` in SI units.

    Parameters
    ----------
    path : str or Path
        ``.prr``, ``.prw``, ``.ban``, ``.whl``, ``.csv`` or ``.txt`` file.
    kind : {"wheel", "rail"}
        Body; taken from the file type or extension when not given.
    units : {"auto", "mm", "m"}
        Length unit of the file.  ``"auto"`` detects it from the profile width.
    z_down : bool, optional
        Whether the file's vertical axis already points down (into the rail, away
        from the wheel axle).  Detected when not given (``options.mirror_z``, where
        given, is its negation).
    mirror_y : bool, optional
        Mirror the lateral axis (e.g. a left-side measurement); overrides
        ``options.mirror_y``.  None: a wheel whose flange lies at positive y is
        mirrored (except SIMPACK files, whose header says).
    name : str, optional
        Label; the file name by default.
    options : ProfileOptions, optional
        CONTACT's profile options: mirroring, scale, zig-zag repair, kinks and
        smoothing along the arc length (:mod:`railcontact.profiles.processing`).
    """
    path = Path(path)
    if not path.is_file():
        raise ProfileError(f"profile file {str(path)!r} does not exist")
    suffix = path.suffix.lower()
    if units not in ("auto", "mm", "m"):
        raise ProfileError(f"units={shown(units)}: expected 'auto', 'mm' or 'm'")
    try:
        if suffix in (".prr", ".prw"):
            y, z, fkind, funits, fz_down = _read_simpack(path)
        elif suffix in (".ban", ".whl"):
            y, z, fkind, funits, fz_down = _read_miniprof(path)
        else:
            y, z, fkind, funits, fz_down = _read_text(path)
    except UnicodeError as exc:
        raise ProfileError(f"{path}: cannot decode the file: {exc}") from None
    kind = kind or fkind or _kind_from_suffix(path)
    if kind not in ("wheel", "rail"):
        raise ProfileError(f"{path}: cannot tell whether this is a wheel or a rail profile; "
                           "pass kind='wheel' or kind='rail'")
    if y.size < 2:
        raise ProfileError(f"{path}: {y.size} profile point(s); expected at least 8")
    opts = options or ProfileOptions()
    if units == "auto":
        units = funits
    if units is None:
        width = np.ptp(y) * opts.scale
        if MIN_WIDTH <= width <= MAX_WIDTH:
            units = "m"
        elif MIN_WIDTH * 1e3 <= width <= MAX_WIDTH * 1e3:
            units = "mm"
        else:
            raise ProfileError(f"{path}: profile width {width:g} is implausible in both m and "
                               f"mm; expected {MIN_WIDTH * 1e3:.0f}-{MAX_WIDTH * 1e3:.0f} mm")
        log.info("%s: lengths assumed in %s (profile width %g)", path.name, units, width)
    if units == "mm" and funits != "m":
        y, z = y * 1e-3, z * 1e-3
    if mirror_y is None:
        mirror_y = opts.mirror_y
    if mirror_y:
        y = -y
    if z_down is None and opts.mirror_z is not None:
        z_down = not opts.mirror_z
    if z_down is None:
        z_down = fz_down
    if z_down is None:
        z_down = z_points_down(y, z, kind)
        if not z_down:
            log.info("%s: vertical axis points up; flipped to z down", path.name)
    if not z_down:
        z = -z
    if kind == "wheel" and fz_down is None and mirror_y is None:
        order = np.argsort(y)
        ys, zs = y[order], z[order]
        if ys[np.argmax(zs)] > 0.5 * (ys[0] + ys[-1]):
            log.info("%s: flange at positive y; mirrored to the right-wheel convention",
                     path.name)
            y = -y
    return process_points(y, z, kind, replace(opts, mirror_y=False, mirror_z=False),
                          name=name or path.stem)


def write_profile(profile: Profile, path, units: str = "mm") -> Path:
    """Write a profile as CSV/text (``.csv``, ``.txt``) or SIMPACK (``.prr``, ``.prw``).

    The file is written completely or not at all (temporary file, then rename).
    """
    path = Path(path)
    if units not in ("mm", "m"):
        raise ProfileError(f"units={shown(units)}: expected 'mm' or 'm'")
    f = 1e3 if units == "mm" else 1.0
    suffix = path.suffix.lower()
    if suffix in (".prr", ".prw"):
        kind_code = 0 if profile.kind == "rail" else 1
        lines = ["! SIMPACK Rail-Wheel Profile written by railcontact",
                 "  header.begin", "    version = 1",
                 f"    type = {kind_code}   ! 0=rail profile, 1=wheel profile", "  header.end",
                 "  spline.begin", "    approx.smooth = 0.0",
                 f"    comment = '{profile.name}'",
                 "    mirror.y = 0", "    mirror.z = 0", "    inversion = 0",
                 f"    units.len.f = {f:.6e}   ! length unit factor (l[User] / l[m])",
                 "    units.ang.f = 1.0", "    point.begin"]
        lines += [f"{a:.9e}  {b:.9e}" for a, b in zip(profile.y * f, profile.z * f)]
        lines += ["    point.end", "  spline.end"]
    elif suffix in (".csv", ".txt", ".dat", ""):
        sep = "," if suffix == ".csv" else " "
        lines = [f"# railcontact profile {profile.name!r}, kind: {profile.kind}, units: {units}",
                 "# y positive to the field side of a right body, z positive downwards",
                 f"y_{units}{sep}z_{units}"]
        lines += [f"{a:.9e}{sep}{b:.9e}" for a, b in zip(profile.y * f, profile.z * f)]
    else:
        raise ProfileError(f"cannot write profile format {shown(suffix)}; expected .csv, .txt, "
                           ".prr or .prw")
    return write_text(path, "\n".join(lines) + "\n")


def process_points(y, z, kind: str, options: ProfileOptions | None = None,
                   name: str = "profile", z_down: bool | None = None):
    """A :class:`~railcontact.profiles.profile.Profile` from measured points [m],
    processed as CONTACT processes a profile: close points dropped, zig-zags
    repaired, mirrored and scaled by ``options``, kinks found, smoothed along the
    arc length where asked, and the visible surface of a curve that folds back.

    ``z_down``: the reader's knowledge of the vertical axis (a SIMPACK file's is
    down), used where ``options.mirror_z`` is None; None: detected.
    """
    opt = options or ProfileOptions()
    y = np.asarray(y, dtype=float) * opt.scale
    z = np.asarray(z, dtype=float) * opt.scale
    if y.size < 8 or not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
        return Profile(y, z, kind=kind, name=name)       # its own error messages
    y, z = remove_close_points(y, z)
    y, z, nzig = remove_zigzags(y, z, opt.zigzag)
    if nzig:
        log.info("profile %s: %d zig-zag pattern(s) replaced by their mean point", name, nzig)
    if opt.mirror_y:
        y = -y
    if opt.mirror_z is not None:
        flip = opt.mirror_z
    else:
        flip = not (z_down if z_down is not None else z_points_down(y, z, kind))
        if flip:
            log.info("profile %s: vertical axis points up; mirrored to z down", name)
    if flip:
        z = -z
    if y[-1] < y[0]:
        y, z = y[::-1], z[::-1]
    if opt.smoothing is not None and opt.smoothing.active:
        kinks = find_kinks(y, z, opt.kink_high, opt.low, opt.kink_width)
        if kinks.size > 2:
            log.info("profile %s: kinks at y = %s mm", name,
                     ", ".join(f"{v * 1e3:.2f}" for v in y[kinks[1:-1]]))
        y, z = smooth_points(y, z, opt.smoothing, kinks)
    return Profile(y, z, kind=kind, name=name)
