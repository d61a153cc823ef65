"""``[viscoelastic]`` of a ``[bodies]`` case: steady rolling of viscoelastic bodies
(the standard linear solid; CONTACT's M = 1), an option of the exact models.

Keys: ``spring_ratio`` f_g = (E_g - E_r)/E_r >= 0 (CONTACT's FG) and
``relaxation_time`` tau_c >= 0 [s] (TC) of the rail and, unless
``wheel_spring_ratio`` / ``wheel_relaxation_time`` are given, of the wheel; the
moduli of ``[material]`` are the initial (glassy) ones and the rolling speed is
``bodies.velocity``.  They become the ``viscoelastic`` option of the exact normal
and tangential models (:class:`~railcontact.normal.viscoelastic.ViscoelasticOption`).
"""

from __future__ import annotations

from .keys import CaseKeys
from ..core.errors import CaseFileError

#: the keys of the section
VISCOELASTIC_KEYS = {"spring_ratio", "relaxation_time", "wheel_spring_ratio",
                     "wheel_relaxation_time"}


def viscoelastic_option(keys: CaseKeys, normal: str, tangential: str) -> dict:
    """The ``viscoelastic`` option (a table) of the case's exact models, checked."""
    if "bodies" not in keys.raw:
        raise CaseFileError("[viscoelastic] needs a [bodies] case (steady rolling of two "
                            "bodies given by their curvatures and velocity)")
    if normal != "exact" or tangential not in ("exact", "none"):
        raise CaseFileError(f"[viscoelastic] is an option of the exact models; solver.normal "
                            f"= {normal!r}, solver.tangential = {tangential!r} (expected "
                            "'exact' and 'exact' or 'none')")
    f = keys.number("viscoelastic.spring_ratio", None, 0.0, 1e6)
    t = keys.number("viscoelastic.relaxation_time", None, 0.0, 1e9, "s")
    fw = keys.number("viscoelastic.wheel_spring_ratio", f, 0.0, 1e6)
    tw = keys.number("viscoelastic.wheel_relaxation_time", t, 0.0, 1e9, "s")
    return {"spring_ratio": [f, fw], "relaxation_time": [t, tw],
            "velocity": keys.number("bodies.velocity", 1.0, 1e-6, 1e3, "m/s")}
