"""Reading CONTACT's input files (``.inp``): the cases of modules 1 and 3.

The format is that of CONTACT's user guide (eve70a/CONTACT, ``doc/user-guide``,
appendix "Specification of the input file"):

* ``%`` starts a comment; empty lines are skipped;
* a group of values is read from one line, continuing on the next lines while
  values are missing; text after the last value of a group is ignored (the
  inputs name their variables there), text before it is an error;
* optional values (the guide's ``{...}``) are read only from the line of the
  group's last mandatory value, where they are numbers;
* reals may carry ``d`` (degrees) or ``r`` (radians); strings are in single quotes;
* a case starts with its module number (1 wheel-rail, 3 basic contact, 0 stop),
  then its control words, whose digits say which inputs follow and which are kept
  from the previous case of the same module.

This module only reads: :class:`InpCase` holds the control digits and every value
as CONTACT has them after the case was read (the kept ones included), in
CONTACT's units (mm, N, rad, s).  What railcontact supports and how it maps onto a
case file is :mod:`railcontact.contact_inp.mapping`.
"""

from __future__ import annotations

import copy
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..core.checks import shown
from ..core.errors import CaseFileError

#: control words: digit names from left to right (module 1; module 3 without C and V)
WORDS = {1: ("CPBTNFS", "VLDCMZE", "XHGIAOWR"), 3: ("PBTNFS", "LDCMZE", "XHGIAOWR")}

_REAL = re.compile(r"^([-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?)([dr]?)$")


class InpError(CaseFileError):
    """A CONTACT input file cannot be read, or asks for what railcontact does not
    support."""


def _real(tok: str):
    """A real number of CONTACT's input (``180d`` in degrees, ``3.1r`` in radians,
    Fortran's ``1.0D-3``), or None."""
    m = _REAL.match(tok)
    if not m:
        return None
    v = float(m.group(1).replace("D", "e").replace("d", "e") if m.group(3) else m.group(1))
    return math.radians(v) if m.group(4) == "d" else v


def _int(tok: str):
    return int(tok) if re.fullmatch(r"[-+]?\d+", tok) else None


class _Lines:
    """The input's lines (comments stripped, empty ones skipped) and a position."""

    def __init__(self, path: Path):
        self.path = path
        try:
            text = path.read_text(errors="replace")
        except OSError as exc:
            raise InpError(f"{path}: cannot read: {exc}") from None
        self.lines = []
        for ln, line in enumerate(text.splitlines(), 1):
            s = line.split("%", 1)[0].strip()
            if s:
                self.lines.append((ln, s))
        self.i = 0
        self.last_line = 0              # the line of the last value read

    @property
    def line_number(self) -> int:
        return self.lines[self.i][0] if self.i < len(self.lines) else (
            self.lines[-1][0] if self.lines else 0)

    def error(self, what: str, line: int | None = None) -> InpError:
        """The error at ``line``, else at the line of the value last read (or the next
        line, before any)."""
        return InpError(f"{self.path.name}, line {line or self.last_line or self.line_number}: "
                        f"{what}")

    @staticmethod
    def _tokens(s: str):
        return re.findall(r"'[^']*'|[^\s,]+", s)

    def group(self, kinds: str, names: str, optional: str = ""):
        """Read a group: ``kinds`` one letter per mandatory value (``i`` integer, ``d``
        real, ``s`` quoted string), ``optional`` the optional ones (read from the
        line of the last mandatory value where they are numbers).  ``names`` (comma
        separated) name the values in errors.  Returns the list of values (None for
        optional values not given)."""
        names_l = [n.strip() for n in names.split(",")]
        out = []
        toks, j = [], 0
        while len(out) < len(kinds):
            if j >= len(toks):
                if self.i >= len(self.lines):
                    raise self.error(f"unexpected end of file reading {names}")
                toks, j = self._tokens(self.lines[self.i][1]), 0
                self.i += 1
            kind, tok = kinds[len(out)], toks[j]
            val = _parse(kind, tok)
            self.last_line = self.lines[self.i - 1][0]
            if val is None:
                self.i -= 1
                raise self.error(f"{names_l[min(len(out), len(names_l) - 1)]} = {shown(tok)}: "
                                 f"expected {_KIND_NAMES[kind]}")
            out.append(val)
            j += 1
        for kind in optional:
            val = _parse(kind, toks[j]) if j < len(toks) else None
            if val is None:
                break
            out.append(val)
            j += 1
        out += [None] * (len(kinds) + len(optional) - len(out))
        return out

    def done(self) -> bool:
        return self.i >= len(self.lines)


_KIND_NAMES = {"i": "an integer", "d": "a real number", "s": "a quoted file name"}


def _parse(kind, tok):
    if kind == "i":
        v = _int(tok)
        if v is None:
            # an integer written as a real ("0.0"), as CONTACT's reader takes it
            r = _real(tok)
            if r is not None and re.fullmatch(r"[-+]?\d+\.0*", tok) and math.isfinite(r) \
                    and r == int(r):
                v = int(r)
        return v
    if kind == "d":
        return _real(tok)
    if kind == "s":
        return tok[1:-1] if len(tok) >= 2 and tok[0] == tok[-1] == "'" else None
    raise ValueError(kind)


def _digits(word: str, value: int, line: _Lines) -> dict:
    """The digits of a control word, named by the letters of ``word`` (from the
    right: leading zeros may be left out; X of XHGIAOWR is 0 when the word has
    seven digits)."""
    if value < 0:
        raise line.error(f"control word {word} = {value}: expected a non-negative integer")
    s = str(value).rjust(len(word), "0")
    if len(s) > len(word):
        raise line.error(f"control word {word} = {value}: expected at most {len(word)} digits")
    return {c: int(d) for c, d in zip(word, s)}


@dataclass
class InpCase:
    """One case of a CONTACT input file, as CONTACT holds it after reading it.

    ``digits``: the control digits (module 1: C P B T N F S V L D C3 M Z E M2 X H G I
    A O W R; the influence-coefficient digit is ``C3``); ``values``: every input
    value in CONTACT's units (names of the user guide), kept ones included;
    ``read``: the names read in this case (not kept from an earlier one).
    """

    path: Path
    number: int
    module: int
    line: int
    digits: dict
    values: dict = field(default_factory=dict)
    read: set = field(default_factory=set)

    #: the line each value was read from (kept values: the line of an earlier case)
    value_lines: dict = field(default_factory=dict)

    def where(self, name: str | None = None) -> str:
        """File, case and line: the line of the value ``name`` where given and read,
        else the case's first line."""
        line = self.value_lines.get(name, self.line) if name else self.line
        return f"{self.path.name}, case {self.number} (line {line})"


def read_inp(path) -> list:
    """All cases of a CONTACT input file up to its ``0 MODULE`` (or its end), as
    :class:`InpCase`; cases with RETURN digit 2 or 3 (preprocessing only) are
    read and left out.  Raises :class:`InpError` (one line: file, line, what was
    expected) where the file does not follow the format."""
    path = Path(path)
    if not path.is_file():
        raise InpError(f"CONTACT input file {str(path)!r} does not exist")
    lines = _Lines(path)
    state = {1: {}, 3: {}}                      # per module: the values kept
    lines_of = {1: {}, 3: {}}                   # and the lines they were read from
    cases, number = [], 0
    while not lines.done():
        first = lines.line_number
        module, = lines.group("i", "MODULE")
        if module == 0:
            break
        if module not in (1, 3):
            raise lines.error(f"MODULE = {module}: expected 1 (wheel-rail), 3 (basic contact) "
                              "or 0 (stop)")
        number += 1
        case = InpCase(path, number, module, first, {}, copy.deepcopy(state[module]),
                       value_lines=dict(lines_of[module]))
        case._source = lines
        _read_case(lines, case)
        del case._source
        state[module] = copy.deepcopy(case.values)
        lines_of[module] = dict(case.value_lines)
        if case.digits["R"] in (0, 1):
            cases.append(case)
    if not cases:
        raise InpError(f"{path.name}: no case found; expected cases starting with '1 MODULE' "
                       "or '3 MODULE'")
    return cases


def _put(case, names: str, vals):
    for n, v in zip([n.strip() for n in names.split(",")], vals):
        if v is not None or n not in case.values:
            case.values[n] = v
        case.read.add(n)
        source = getattr(case, "_source", None)
        if source is not None:
            case.value_lines[n] = source.last_line


def _read_case(lines: _Lines, case: InpCase) -> None:
    """Read one case's control words and the inputs they call for (the user
    guide's input specification of modules 1 and 3)."""
    m1 = case.module == 1
    w1, w2, w3 = WORDS[case.module]
    d = {}
    d.update(_digits(w1, lines.group("i", w1)[0], lines))
    case.value_lines[w1] = lines.last_line
    word2, m2 = lines.group("i", w2, "i")
    case.value_lines[w2] = lines.last_line
    dd = _digits(w2, word2, lines)
    dd["C3"] = dd.pop("C")
    d.update(dd)
    d["M2"] = m2 if m2 is not None else 0
    d.update(_digits(w3, lines.group("i", w3)[0], lines))
    if not m1:
        d["C"], d["V"] = 1, 0
    case.digits = d
    put = lambda names, vals: _put(case, names, vals)   # noqa: E731
    if d["X"] == 1:
        put("PSFLCIN", lines.group("i", "PSFLCIN", "i"))
    if d["C3"] >= 2:
        # the influence coefficients in force (C = 0, 1 keep them for later cases)
        put("INFLCF", [d["C3"]])
    if d["G"] != 1:
        if m1:
            put("MAXGS, MAXIN, MAXNR, MAXOUT, EPS, NPOT_MAX",
                lines.group("iiiid", "MAXGS, MAXIN, MAXNR, MAXOUT, EPS", "i"))
        else:
            put("MAXGS, MAXIN, MAXNR, MAXOUT, EPS", lines.group("iiiid", "MAXGS, MAXIN, MAXNR, "
                                                                "MAXOUT, EPS"))
    if d["G"] in (2, 3):
        put("OMEGAH, OMEGAS, INISLP, OMGSLP",
            lines.group("ddid", "OMEGAH, OMEGAS, INISLP, OMGSLP"))
    elif d["G"] == 4:
        put("INISLP, OMGSLP", lines.group("id", "INISLP, OMGSLP"))
    elif d["G"] == 5:
        put("FDECAY, BETATH, KDOWFB, D_IFC, D_LIN, D_CNS, D_SLP, POW_S",
            lines.group("dddddddd", "FDECAY, BETATH, KDOWFB, D_IFC, D_LIN, D_CNS, D_SLP, POW_S"))
    if not m1:
        # the F digit says which of creepages and relative forces are given
        tang = {0: "CKSI, CETA", 1: "FXREL, CETA", 2: "FXREL, FYREL"}.get(d["F"], "CKSI, CETA")
        put(f"{'FN' if d['N'] == 1 else 'PEN'}, {tang}, CPHI, SPINXO, SPINYO",
            lines.group("dddd", "PEN/FN, CKSI/FXREL, CETA/FYREL, CPHI", "dd"))
    _read_friction(lines, case, d)
    if m1:
        _read_materials(lines, case, d)
        if d["D"] >= 2:
            # the contact search in force (D = 0, 1 keep it for later cases)
            put("DISCNS", [d["D"]])
            put("DX, DS, DQREL, A_SEP, D_SEP, D_COMB, D_TURN, G_MISS",
                lines.group("dddddd", "DX, DS, DQREL, A_SEP, D_SEP, D_COMB", "dd"))
        _read_track(lines, case, d)
        _read_wheelset(lines, case, d)
    else:
        _read_materials(lines, case, d)
        if d["D"] == 2:
            ipotcn, = lines.group("i", "IPOTCN")
            put("IPOTCN", [ipotcn])
            spec = {-1: "MX, MY, A1, B1, SCALE", -2: "MX, MY, A1, AOB, SCALE",
                    -3: "MX, MY, AA, BB, SCALE", -4: "MX, MY, A1, BB, SCALE",
                    -5: "MX, MY, AA, BB, SCALE", -6: "MX, MY, AA, BNEG, BPOS, SCALE",
                    1: "MX, MY, XL, YL, DX, DY", 2: "MX, MY, XL, YL, XH, YH",
                    3: "MX, MY, XC1, YC1, DX, DY", 4: "MX, MY, XC1, YC1, XCM, YCM"}.get(ipotcn)
            if spec is None:
                raise lines.error(f"IPOTCN = {ipotcn}: expected -6 .. -1 or 1 .. 4")
            kinds = "ii" + "d" * (spec.count(",") - 1)
            put(spec, lines.group(kinds, spec))
        if d["Z"] > 1 and case.values.get("IPOTCN", -1) > 0:
            _read_undeformed_distance(lines, case)
        _read_extra_slip(lines, case, d["E"])
    if not m1 and d["T"] <= 1:
        # no rolling: CONTACT sets CHI = 0, DQ = 1 mm, VELOC = 1 mm/s (user guide,
        # "Tangential quantities in case of a shift")
        case.values.update(CHI=0.0, DQ=1.0, VELOC=1.0)
    if d["S"] in (2, 3):
        _read_subsurface(lines, case, d["S"])
    if d["S"] in (1, 2) and not case.values.get("SUBSURFACE_BLOCKS"):
        raise InpError(f"{case.where(WORDS[case.module][0])}: STRESS = {d['S']} (subsurface "
                       "stresses at the points kept) without points read by an earlier case; "
                       "expected S = 3 (new points) first")


def _read_subsurface(lines, case, s_digit):
    """The subsurface stress input (user guide, section 'Input for the subsurface
    stress calculation'): MATFIL, OUTPUT and, for S = 3, blocks of points until
    ISUBS = 0, kept in ``values["SUBSURFACE_BLOCKS"]`` as dicts with ``isubs`` and
    either explicit coordinates ``x``, ``y``, ``z`` [mm] (ISUBS = 9), or element
    columns/rows ``ix``, ``iy`` (1-based; None: all, ISUBS 1, 5) and depths ``z``
    [mm] (ISUBS 1-3 from NZ, ZL, DZ; 5-7 listed)."""
    _put(case, "MATFIL_SUBS, OUTPUT_SUBS", lines.group("ii", "MATFIL, OUTPUT"))
    if s_digit != 3:
        return
    blocks = []
    while True:
        isubs, = lines.group("i", "ISUBS")
        if isubs == 0:
            break
        if isubs not in (1, 2, 3, 5, 6, 7, 9):
            raise lines.error(f"ISUBS = {isubs}: expected 1, 2, 3, 5, 6, 7, 9 or 0 (end)")
        b = {"isubs": isubs, "ix": None, "iy": None}
        if isubs == 9:
            nx, ny, nz = lines.group("iii", "NX, NY, NZ")
            if min(nx, ny, nz) < 1:
                raise lines.error(f"NX, NY, NZ = {nx}, {ny}, {nz}: expected at least 1 each")
            b["x"] = lines.group("d" * nx, ", ".join(["X"] * nx))
            b["y"] = lines.group("d" * ny, ", ".join(["Y"] * ny))
            b["z"] = lines.group("d" * nz, ", ".join(["Z"] * nz))
        else:
            if isubs in (2, 6):
                if _leading_integers(lines) >= 6:
                    xl, xinc, xh, yl, yinc, yh = lines.group("iiiiii", "IXL, IXINC, IXH, "
                                                             "IYL, IYINC, IYH")
                else:       # a line each (CONTACT's examples: each with its comment)
                    xl, xinc, xh = lines.group("iii", "IXL, IXINC, IXH")
                    yl, yinc, yh = lines.group("iii", "IYL, IYINC, IYH")
                if xinc < 1 or yinc < 1:
                    raise lines.error(f"IXINC, IYINC = {xinc}, {yinc}: expected >= 1")
                b["ix"], b["iy"] = list(range(xl, xh + 1, xinc)), list(range(yl, yh + 1, yinc))
            elif isubs in (3, 7):
                nx, ny = lines.group("ii", "NX, NY")
                b["ix"] = lines.group("i" * nx, ", ".join(["IX"] * nx))
                b["iy"] = lines.group("i" * ny, ", ".join(["IY"] * ny))
            if isubs in (1, 2, 3):
                nz, zl, dz = lines.group("idd", "NZ, ZL, DZ")
                b["z"] = [zl + k * dz for k in range(nz)]
            else:
                nz, = lines.group("i", "NZ")
                b["z"] = lines.group("d" * nz, ", ".join(["Z"] * nz))
        blocks.append(b)
    case.values["SUBSURFACE_BLOCKS"] = blocks
    case.read.add("SUBSURFACE_BLOCKS")


def _leading_integers(lines) -> int:
    """How many integers open the next line of input (before any comment text)."""
    if lines.i >= len(lines.lines):
        return 0
    n = 0
    for tok in lines._tokens(lines.lines[lines.i][1]):
        if _parse("i", tok) is None:
            break
        n += 1
    return n


def _read_undeformed_distance(lines, case):
    """``IBASE IPLAN`` and their parameters (module 3 with IPOTCN > 0): the quadratic
    undeformed distance (IBASE = 1: B1 .. B6) on an unrestricted planform (IPLAN =
    1) is read; the other forms stop with the line naming them."""
    ibase, iplan = lines.group("ii", "IBASE, IPLAN")
    if ibase not in (1, 2, 3, 9):
        raise lines.error(f"IBASE = {ibase}: expected 1 (quadratic), 2 (circular in x, a "
                          "profile in y), 3 (quadratic and two sines) or 9 (a value per "
                          "element)")
    if iplan != 1:
        raise lines.error(f"IPLAN = {iplan}: only the unrestricted planform (IPLAN = 1) is "
                          "supported")
    _put(case, "IBASE, IPLAN", [ibase, iplan])
    if ibase == 1:
        case.values["B"] = lines.group("dddddd", "B1, B2, B3, B4, B5, B6")
    elif ibase == 3:
        case.values["B"] = lines.group("dddddddd", "B1, B2, B3, B4, B5, B6, B7, B8")
    elif ibase == 9:
        # H(I) [mm] at every element's centre, I = ix + (iy - 1) MX (x fastest)
        case.values["B"] = lines.group("d" * _elements(lines, case), "H(I)")
    else:
        nn, xm, rm, y1, dy1 = lines.group("idddd", "NN, XM, RM, Y1, DY1")
        if nn < 1:
            raise lines.error(f"NN = {nn}: expected at least one profile point")
        heights = lines.group("d" * nn, ", ".join(f"B({k + 1})" for k in range(nn)))
        case.values["B"] = [nn, xm, rm, y1, dy1, heights]
    case.read.add("B")


def _elements(lines, case) -> int:
    """MX MY, the number of elements of the potential contact area (module 3)."""
    mx, my = case.values.get("MX"), case.values.get("MY")
    if not (isinstance(mx, int) and isinstance(my, int) and mx >= 1 and my >= 1):
        raise lines.error(f"MX, MY = {mx}, {my}: a value per element needs the potential "
                          "contact area (D = 2) first")
    return mx * my


def _read_extra_slip(lines, case, e):
    """The EXRHS digit of module 3 (user guide, "E3 - EXRHS"): 9 reads the extra term
    of the rigid slip, (x, y) per element in CONTACT's element order (x fastest),
    kept in ``values["EXRHS"]`` as the flat list of the 2 MX MY values read; 0 clears
    it; 1 keeps it.  The spin-discarding options 2 and 3 are left to the digit (the
    solvers refuse them)."""
    if e == 0:
        case.values["EXRHS"] = None
    elif e == 9:
        n = _elements(lines, case)
        vals = lines.group("d" * (2 * n), "EXRHS(I,:)")
        case.values["EXRHS"] = vals
        case.read.add("EXRHS")
        source = getattr(case, "_source", None)
        if source is not None:
            case.value_lines["EXRHS"] = source.last_line


def _read_friction(lines, case, d):
    put = lambda names, vals: _put(case, names, vals)   # noqa: E731
    law = d["L"]
    if law == 1:
        return
    params = {0: ("FSTAT, FKIN", "dd"), 2: ("FKIN, FLIN1, SABSH1, FLIN2, SABSH2", "ddddd"),
              3: ("FKIN, FRAT1, SABSH1, FRAT2, SABSH2", "ddddd"),
              4: ("FKIN, FEXP1, SABSH1, FEXP2, SABSH2", "ddddd"),
              5: ("FKIN, FEXP1, SABSH1, FEXP2, SABSH2", "ddddd"),
              6: ("FREF, TREF, DFHEAT, DTHEAT", "dddd")}.get(law)
    if params is None:
        raise lines.error(f"FRCLAW = {law}: expected 0 .. 6", case.value_lines.get(WORDS[
            case.module][1]))
    names, kinds = params
    case.values["FRICTION_LAW"] = law
    if d["V"] == 0:
        put(names, lines.group(kinds, names))
        case.values["NVF"] = 0
    else:
        nvf, = lines.group("i", "NVF")
        if nvf < 1:
            raise lines.error(f"NVF = {nvf}: expected at least one friction control point")
        rows = [lines.group("d" + kinds, "ALPHA/SVF, " + names) for _ in range(nvf)]
        case.values["NVF"] = nvf
        case.values["VARFRC_ROWS"] = rows
        case.read.update(("NVF", "VARFRC_ROWS"))
    if law in (2, 3, 4, 5, 6):
        put("MEMDST, MEM_S0", lines.group("dd", "MEMDST, MEM_S0"))


def _read_materials(lines, case, d):
    put = lambda names, vals: _put(case, names, vals)   # noqa: E731
    c3, m = d["C3"], d["M"]
    if c3 >= 2:
        case.values["INFLCF"] = c3              # in force until a case sets another
        _read_elastic(lines, case, d, put)
    if d["M2"] == 2:
        put("CDAMPN, CDAMPT, DFNMAX, DFTMAX", lines.group("dddd", "CDAMPN, CDAMPT, DFNMAX, "
                                                          "DFTMAX"))
    if d["H"] == 3:
        # one line per body, as CONTACT reads them
        put("BKTEMP1, HEATCP1, LAMBDA1, DENS1",
            lines.group("dddd", "BKTEMP1, HEATCP1, LAMBDA1, DENS1"))
        put("BKTEMP2, HEATCP2, LAMBDA2, DENS2",
            lines.group("dddd", "BKTEMP2, HEATCP2, LAMBDA2, DENS2"))
        if m == 4:
            put("BETAPL", lines.group("d", "BETAPL"))


def _read_elastic(lines, case, d, put):
    """The inputs of INFLCF >= 2: rolling step (module 3), materials, model
    parameters."""
    c3, m = d["C3"], d["M"]
    if case.module == 3:
        if d["T"] <= 1 and m == 5:
            put("DT", lines.group("d", "DT"))
        if d["T"] > 1:
            put("CHI, DQ, VELOC", lines.group("ddd", "CHI, DQ, VELOC"))
        if c3 == 4:
            raise lines.error("conformal influence coefficients (INFLCF = 4) are not supported")
        if c3 == 9:
            put("CFNAME", lines.group("s", "CFNAME"))
    elif c3 == 4:
        put("IF_METH, VARIANT", lines.group("ii", "IF_METH, VARIANT"))
    put("POISS1, POISS2, GG1, GG2", lines.group("dddd", "POISS1, POISS2, GG1, GG2"))
    if d["B"] == 1:
        put("FLXZ", lines.group("d", "FLXZ"))
    if m == 1:
        put("FG1, FG2, VT1, VT2", lines.group("dddd", "FG1, FG2, VT1, VT2"))
    elif m == 2:
        put("FLX, K0_MF, ALFAMF, BETAMF", lines.group("dddd", "FLX, K0_MF, ALFAMF, BETAMF"))
    elif m in (3, 5):
        put("K0_MF, ALFAMF, BETAMF", lines.group("ddd", "K0_MF, ALFAMF, BETAMF"))
    elif m == 4:
        put("GG3, LAYTHK, TAU_C0, K_TAU", lines.group("dddd", "GG3, LAYTHK, TAU_C0, K_TAU"))


def _read_profile_line(lines, case, prefix: str):
    """``'FNAME' MIRRORY SCALE SMOOTH {MIRRORZ} {PRFOPT}`` and the lines PRFOPT
    calls for, stored as ``<prefix>FNAME`` etc. (prefix R_ or W_)."""
    fname, mir_y, scale, smooth, mir_z, prfopt = lines.group(
        "sidd", f"{prefix}FNAME, MIRRORY, SCALE, SMOOTH", "ii")
    vals = {"FNAME": fname, "MIRRORY": mir_y, "SCALE": scale, "SMOOTH": smooth,
            "MIRRORZ": mir_z or 0, "PRFOPT": prfopt or 0, "ISMOOTH": 0,
            "ZIGTHRS": None, "KINKHIGH": None, "KINKLOW": None, "KINKWID": None}
    if vals["PRFOPT"] >= 1:
        vals.update(zip(("ISMOOTH", "ZIGTHRS", "KINKHIGH", "KINKLOW", "KINKWID"),
                        lines.group("idddd", "ISMOOTH, ZIGTHRS, KINKHIGH, KINKLOW, KINKWID")))
    if vals["PRFOPT"] >= 2:
        vals.update(zip(("ERRHND", "MAXOMIT"), lines.group("id", "ERRHND, MAXOMIT")))
    for k, v in vals.items():
        case.values[prefix + k] = v
        case.read.add(prefix + k)
        case.value_lines[prefix + k] = lines.last_line


def _read_track(lines, case, d):
    put = lambda names, vals: _put(case, names, vals)   # noqa: E731
    z = d["Z"]
    if z in (1, 3):
        gaught, a, b, c, curv = lines.group("dddd", "GAUGHT, GAUGSQ/RAILY0, GAUGWD/RAILZ0, CANT",
                                            "d")
        if gaught > 0:
            put("GAUGHT, GAUGSQ, GAUGWD, CANT, CURV", [gaught, a, b, c, curv or 0.0])
        else:
            put("GAUGHT, RAILY0, RAILZ0, CANT, CURV", [gaught, a, b, c, curv or 0.0])
    if z == 3:
        _read_profile_line(lines, case, "R_")
    if z in (2, 3):
        put("DYRAIL, DZRAIL, DROLLR, VYRAIL, VZRAIL, VROLLR",
            lines.group("dddddd", "DYRAIL, DZRAIL, DROLLR, VYRAIL, VZRAIL, VROLLR"))
        if d["F"] == 3:
            put("KYRAIL, FYRAIL, KZRAIL, FZRAIL, DYSTEP0",
                lines.group("dddd", "KYRAIL, FYRAIL, KZRAIL, FZRAIL", "d"))


def _read_wheelset(lines, case, d):
    put = lambda names, vals: _put(case, names, vals)   # noqa: E731
    e = d["E"]
    if e in (3, 5):
        put("FBDIST, FBPOS, NOMRADW, YTAPE", lines.group("ddd", "FBDIST, FBPOS, NOMRADW", "d"))
        _read_profile_line(lines, case, "W_")
    if e >= 1:
        put(f"S_WS, Y_WS, {'FZ_WS' if d['N'] == 1 else 'Z_WS'}, ROLL, YAW, PITCH",
            lines.group("dddddd", "S_WS, Y_WS, Z_WS/FZ_WS, ROLL, YAW, PITCH"))
    if e >= 2:
        if d["T"] == 1:
            put("SHFT_SWS, SHFT_YWS, SHFT_ZWS, SHFT_ROL, SHFT_YAW, SHFT_WPIT",
                lines.group("dddddd", "SHFT_SWS, SHFT_YWS, SHFT_ZWS, SHFT_ROL, SHFT_YAW, "
                                      "SHFT_WPIT"))
        else:
            last = {0: "VPITCH", 1: "FX_WS", 2: "MY_WS"}.get(d["F"], "VPITCH")
            put(f"VS_WS, VY_WS, VZ_WS, VROLL, VYAW, {last}",
                lines.group("dddddd", f"VS_WS, VY_WS, VZ_WS, VROLL, VYAW, {last}"))
    if e >= 4:               # on two lines (positions, velocities), as CONTACT reads them
        put("DXWHL, DYWHL, DZWHL, DROLLW, DYAWW, DPITCHW",
            lines.group("dddddd", "DXWHL, DYWHL, DZWHL, DROLLW, DYAWW, DPITCHW"))
        put("VXWHL, VYWHL, VZWHL, VROLLW, VYAWW, VPITCHW",
            lines.group("dddddd", "VXWHL, VYWHL, VZWHL, VROLLW, VYAWW, VPITCHW"))
