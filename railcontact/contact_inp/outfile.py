"""Reading CONTACT's printed output (``.out``, the testbank's ``.ref_out``) of
module 3 cases, to compare railcontact's rows with CONTACT's.

Per case CONTACT prints its totals in two blocks (user guide, "Output in rolling
problems" and "Output in case of shifts")::

     FN          FX          FY          MZ         ELAST.EN.   FRIC.WORK
        9.195      -3.218       0.000       0.000   8.525E-05  -2.750E-06
     FN/G       SHIFT X      SHIFT Y     APPROACH     PMAX
     4.598E-02   8.155E-03       0.000   1.998E-02       4.393

(the labels of the second block's middle columns name what they hold: ``CKSI``,
``CREEP X``, ``SHIFT X``, ``FX/FSTAT/FN`` ...), and, at higher output levels, the
element counts ``NPOT NCON NADH NSLIP``.  Forces in N, moment in N mm, approach
in mm, PMAX in N/mm^2; creepages as CONTACT has them (shifts in mm).
"""

from __future__ import annotations

import re
from pathlib import Path

from .reader import InpError

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"


def _nums(line: str) -> list:
    return [float(t.replace("D", "E").replace("d", "e")) for t in re.findall(_NUM, line)]


def read_out(path) -> dict:
    """CONTACT's totals per case number of a module 3 output file: ``fn_N``, ``fx_N``,
    ``fy_N``, ``mz_Nmm``, ``approach_mm``, ``pmax_MPa``, the second block's middle
    columns by their labels (``x_label``, ``x_value``, ``y_label``, ``y_value``),
    and where printed ``npot``, ``ncon``, ``nadh``, ``nslip`` and the largest
    surface temperature ``tmax_C`` (MAX(T1,T2), deg C).  Cases without
    totals (a module 1 case) are left out."""
    path = Path(path)
    try:
        text = path.read_text(errors="replace")
    except OSError as exc:
        raise InpError(f"{path}: cannot read: {exc}") from None
    parts = re.split(r"\n Case +(\d+)\s*\n", "\n" + text)
    out = {}
    for num, body in zip(parts[1::2], parts[2::2]):
        lines = body.splitlines()
        case = {}
        for k, line in enumerate(lines):
            head = line.split()
            if head[:4] == ["FN", "FX", "FY", "MZ"] and k + 1 < len(lines):
                v = _nums(lines[k + 1])
                if len(v) >= 4:
                    case.update(fn_N=v[0], fx_N=v[1], fy_N=v[2], mz_Nmm=v[3])
            elif head[:1] == ["FN/G"] and "APPROACH" in head and k + 1 < len(lines):
                v = _nums(lines[k + 1])
                labels = re.split(r"\s{2,}", line.strip())
                if len(v) >= 5 and len(labels) >= 5:
                    case.update(x_label=labels[1], x_value=v[1], y_label=labels[2],
                                y_value=v[2], approach_mm=v[3], pmax_MPa=v[4])
                if len(v) >= 6 and "MAX(T1,T2)" in labels:
                    case["tmax_C"] = v[5]
            elif head[:4] == ["NPOT", "NCON", "NADH", "NSLIP"] and k + 1 < len(lines):
                v = _nums(lines[k + 1])
                if len(v) >= 4:
                    case.update(npot=int(v[0]), ncon=int(v[1]), nadh=int(v[2]),
                                nslip=int(v[3]))
        if "fn_N" in case:
            out[int(num)] = case
    return out
