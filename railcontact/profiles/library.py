"""Built-in profiles by name, and resolution of a name-or-path to a profile."""

from __future__ import annotations

import math
from dataclasses import is_dataclass, replace
from functools import lru_cache
from pathlib import Path

from ..core.errors import ProfileError
from .io import read_profile
from .profile import Profile
from .rails import ALIASES, HEADS, rail_profile
from .en13715 import s1002

WHEEL_PROFILES = ("S1002",)
RAIL_PROFILES = tuple(sorted(HEADS)) + tuple(sorted(ALIASES))
#: default rail inclination of built-in rails [rad]
DEFAULT_INCLINATION = math.atan(1 / 40)


def builtin_names() -> dict:
    """Names of the built-in profiles, by body."""
    return {"wheel": WHEEL_PROFILES, "rail": RAIL_PROFILES}


def get_profile(spec, kind: str, inclination: float | None = None,
                base_dir: Path | None = None, **read_kw) -> Profile:
    """Resolve a built-in name or a file path to a :class:`Profile`.

    Parameters
    ----------
    spec : str, Path or Profile
        Built-in name (``"S1002"``, ``"60E1"``, ``"54E1"``, ``"60E2"``, ``"UIC60"``)
        or a profile file.
    kind : {"wheel", "rail"}
    inclination : float, optional
        Rail inclination [rad].  For built-in rails the default is 1:40; for rail
        files it is 0, since a file usually holds the rail as mounted (canted).
    base_dir : Path, optional
        Directory relative to which file paths are resolved (the case file's).
    **read_kw
        Passed to :func:`read_profile` for files: ``units``, ``options``
        (:class:`~railcontact.profiles.ProfileOptions`), ...
    """
    if isinstance(spec, Profile):
        prof = spec
    else:
        name = str(spec)
        upper = name.upper()
        builtin = (kind == "wheel" and upper in WHEEL_PROFILES) or \
            (kind == "rail" and upper in RAIL_PROFILES)
        opts = read_kw.get("options")
        scale = 1.0
        if builtin and opts is not None:
            # a built-in profile may be scaled (a scaled model on a roller rig), no more
            if not is_dataclass(opts) or replace(opts, scale=1.0) != type(opts)():
                raise ProfileError(f"{kind} profile {name!r} is built in: the profile-file "
                                   "options (mirroring, smoothing, kinks) apply to files; "
                                   "only scale applies to it")
            scale = float(opts.scale)
        if kind == "wheel" and upper in WHEEL_PROFILES:
            return _scaled(s1002(), scale)
        if kind == "rail" and upper in RAIL_PROFILES:
            return _scaled(rail_profile(upper, DEFAULT_INCLINATION if inclination is None
                                        else inclination), scale)
        path = Path(name)
        if base_dir is not None and not path.is_absolute():
            path = Path(base_dir) / path
        if not path.is_file():
            builtins = WHEEL_PROFILES if kind == "wheel" else RAIL_PROFILES
            raise ProfileError(f"{kind} profile {name!r}: neither a built-in name "
                               f"({', '.join(builtins)}) nor an existing file")
        stat = path.stat()
        prof = _read_file(str(path.resolve()), stat.st_mtime_ns, stat.st_size, kind,
                          tuple(sorted(read_kw.items())))
    if prof.kind != kind:
        raise ProfileError(f"profile {prof.name!r} is a {prof.kind} profile; expected a {kind} "
                           "profile")
    if kind == "rail" and inclination:
        prof = _inclined(prof, float(inclination))
    return prof


def _scaled(prof: Profile, scale: float) -> Profile:
    """A built-in profile with its coordinates multiplied by ``scale`` (a 1:5 model:
    0.2); the same profile for 1."""
    if scale == 1.0:
        return prof
    return Profile(prof.y * scale, prof.z * scale, kind=prof.kind,
                   name=f"{prof.name} x{scale:g}")


@lru_cache(maxsize=32)
def _read_file(path: str, mtime_ns: int, size: int, kind: str, read_kw: tuple) -> Profile:
    """A profile file read once per version (path, modification time and size): a
    sweep or a time history that names a profile file solves every case with the
    same profile, which takes longer to parse than an exact case to solve."""
    return read_profile(Path(path), kind=kind, **dict(read_kw))


@lru_cache(maxsize=32)
def _inclined(prof: Profile, inclination: float) -> Profile:
    """A rail profile turned by its inclination, its origin at the top (once per
    profile and inclination)."""
    return prof.rotated(inclination).with_origin_at_top()
