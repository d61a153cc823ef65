"""Standard wheel measures (flange height, flange thickness, qR)."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from ..core.errors import ProfileError
from .profile import Profile


def wheel_measures(profile: Profile, flange_back: float | None = None) -> dict:
    """Flange height Sh, flange thickness Sd and qR of a wheel profile [m].

    Heights are measured from the tape circle (y = 0).  Sd is the lateral distance
    from the flange back (default: the profile's inner end) to the flange-face point
    10 mm above the tape circle; qR is the lateral distance between the flange-face
    points 10 mm and 2 mm below the flange tip (for a 28 mm flange: 10 and 26 mm).

    Returns
    -------
    dict with keys ``flange_height``, ``flange_thickness``, ``qR``, ``flange_tip_y``.
    """
    if profile.kind != "wheel":
        raise ProfileError(f"profile {profile.name!r} is a rail profile; wheel measures need a "
                           "wheel profile")
    if not (profile.y_min < 0.0 < profile.y_max):
        raise ProfileError(f"wheel profile {profile.name!r} does not contain the tape circle y = 0")
    yy = np.linspace(profile.y_min, 0.0, 20000)
    F = profile.z_at(yy) - float(profile.z_at(0.0))
    i_tip = int(np.nanargmax(F))
    y_tip, h = yy[i_tip], float(F[i_tip])
    if h < 0.015:
        raise ProfileError(f"wheel profile {profile.name!r}: no flange found (max height "
                           f"{h * 1e3:.1f} mm above the tape circle)")

    def face_point(level):
        return brentq(lambda t: float(profile.z_at(t) - profile.z_at(0.0)) - level, y_tip, 0.0)

    y10 = face_point(0.010)
    y_low = face_point(h - 0.002)
    back = profile.y_min if flange_back is None else flange_back
    return {"flange_height": h, "flange_thickness": y10 - back, "qR": y10 - y_low,
            "flange_tip_y": y_tip}
