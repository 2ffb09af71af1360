"""RS274NGC / LinuxCNC G-code front end: program text → canonical moves (absolute mm).

The supported subset (issue 3): ``( )`` and ``;`` comments, block delete ``/``, ``N`` numbers,
``%`` lines; G0 G1 G2 G3 (centre I/J/K incremental — G91.1, the default — or absolute with G90.1,
or ``R``; ``P`` full turns; a change of the applicate makes a helix), G4, G17 G18 G19, G20 G21,
G40 G41 G42 (``D`` = tool number in the tool table, none = the tool in the spindle), G41.1 G42.1
(``D`` = diameter in program units), G43/G49, G54, G61/G61.1/G64, G80, G90 G91, G94; F (units per
minute), S, T, M0 M1 M3 M4 M5 M6 M7 M8 M9, M2/M30 (end). The language around the words —
parameters, ``[ ]`` expressions, O-word subroutines and control flow (issue 16) — is LinuxCNC's,
run by :class:`~trcopt.controllers.linuxcnc.ngc_flow.NgcFlow`; this module executes the blocks it
yields. Anything else — G10/G28/G30/G53/G92, G93/G95, other work offsets — stops the read with an
``NC-UNSUPPORTED`` error that names it.

Conventions: the program starts at (0, 0, 0) in G17, G90, G91.1 and mm (until G20); lengths are
converted to mm here, feeds to mm/s. The tool table is LinuxCNC's ``.tbl``
(:mod:`trcopt.controllers.linuxcnc.tooltable`), read with an explicit unit.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_flow import FlowError, NgcFlow
from trcopt.controllers.linuxcnc.tooltable import LinuxCncToolTable, find_tbl, load_tbl
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec3
from trcopt.modes import PathMode, Side, ToleranceKind, ToolUnit
from trcopt.nc.modal import ReadOptions, arc_centre_from_radius
from trcopt.nc.model import EXACT_PATH, CompState, Move, MoveKind, NcProgram, PathControl

__all__ = ["Rs274Reader", "read_rs274", "read_ngc"]

INCH = 25.4
_PLANES = {17.0: Plane.G17, 18.0: Plane.G18, 19.0: Plane.G19}
_CENTRE_LETTER = "IJK"  # centre word of x, y, z
_IGNORED_G = {4.0, 43.0, 49.0, 54.0, 80.0, 94.0}
_CONTROL_G = (61.0, 61.1, 64.0)
LCNC_BLEND_SHARE = 0.25  # a G64 blend passes at most this share of the shorter move from the corner
_IGNORED_M = {0, 1, 3, 4, 5, 7, 8, 9}
_ALLOWED_LETTERS = set("GMXYZIJKRFSTDNPHQL")


class _Stop(Exception):
    def __init__(self, code: Code, message: str, column: int = 1) -> None:
        super().__init__(message)
        self.code, self.message, self.column = code, message, column


@dataclass(slots=True)
class _State:
    pos: Vec3 = (0.0, 0.0, 0.0)
    plane: Plane = Plane.G17
    unit: float = 1.0  # mm per program unit
    absolute: bool = True
    ijk_absolute: bool = False
    motion: MoveKind | None = None
    ccw: bool = False  # sense of the modal arc motion (G3)
    feed_mm_s: float | None = None
    side: Side = Side.OFF
    radius_mm: float = 0.0  # signed
    selected_tool: int | None = None
    spindle_tool: int | None = None
    control: PathControl = EXACT_PATH  # G61 (and no mode programmed); G61.1; G64 [P]


class Rs274Reader:
    """Reads one RS274NGC program (``read(text) -> NcProgram``); see the module docstring.

    Parameters
    ----------
    file:
        Name used in source spans; when it is a real file, ``<stem>.tbl`` or ``tools.tbl`` beside
        it is the tool table if ``tools`` is not given.
    tools:
        A :class:`~trcopt.controllers.linuxcnc.tooltable.LinuxCncToolTable`, or a path to a ``.tbl`` file (read in
        ``tool_unit``).
    tool_unit:
        Unit of a tool table read from a path: ``"inch"`` (LinuxCNC's default machine unit) or
        ``"mm"``.
    """

    name = "rs274"

    def __init__(
        self,
        file: str = "<program>",
        tools: LinuxCncToolTable | str | os.PathLike[str] | None = None,
        tool_unit: ToolUnit | str = ToolUnit.INCH,
        arc_tolerance_mm: float = 0.005,
    ) -> None:
        self.file = file
        self.diags: list[Diagnostic] = []
        self.arc_tolerance_mm = arc_tolerance_mm
        if tools is None:
            found = find_tbl(file)
            if found is not None:
                tools = found
        if isinstance(tools, (str, os.PathLike)):
            table = load_tbl(tools, tool_unit)
            self.diags.append(
                Diagnostic(
                    Severity.INFO,
                    Code.LCNC_TOOL_TABLE,
                    f"tool table {table.source} read in {table.unit.value}",
                    SourceSpan(file, 0, 0),
                )
            )
            tools = table
        self.tools: LinuxCncToolTable = (
            tools if isinstance(tools, LinuxCncToolTable) else LinuxCncToolTable()
        )

    # -- reading ----------------------------------------------------------------------------
    def read(self, text: str) -> NcProgram:
        st = _State()
        moves: list[Move] = []
        blocks = 0
        steps = NgcFlow(self.file, text).blocks()
        while True:
            try:
                step = next(steps, None)
            except FlowError as err:
                span = SourceSpan(err.file, err.line, err.column, err.block)
                self.diags.append(Diagnostic(Severity.ERROR, err.code, err.message, span))
                break
            if step is None:
                break
            blocks += 1
            span = SourceSpan(step.file, step.line, 1, None if step.number is None else f"N{step.number}")
            try:
                ended = self._block(step.block.words, span, st, moves)
            except _Stop as stop:
                span = SourceSpan(span.file, span.line, stop.column, span.block)
                self.diags.append(Diagnostic(Severity.ERROR, stop.code, stop.message, span))
                break
            except (ArithmeticError, LookupError, TypeError, ValueError) as exc:  # a bug must not pass silently
                message = f"internal error while reading this block: {exc!r}"
                self.diags.append(Diagnostic(Severity.ERROR, Code.NC_INTERNAL, message, span))
                break
            if ended:
                break
        steps.close()
        return NcProgram(self.file, "rs274", tuple(moves), tuple(self.diags), blocks)

    def _block(self, words: list[tuple[str, float, int]], span: SourceSpan, st: _State, moves: list[Move]) -> bool:
        for letter, _, col in words:
            if letter not in _ALLOWED_LETTERS:
                raise _Stop(Code.NC_UNSUPPORTED, f"word {letter} is not supported", col)
        values: dict[str, float] = {}
        gcodes: list[tuple[float, int]] = []
        mcodes: list[tuple[int, int]] = []
        for letter, value, col in words:
            if letter == "G":
                gcodes.append((round(value, 1), col))
            elif letter == "M":
                mcodes.append((int(value), col))
            elif letter == "N":
                raise _Stop(Code.NC_SYNTAX, "N word must start the block", col)
            elif letter in values:
                raise _Stop(Code.NC_SYNTAX, f"word {letter} given twice in one block", col)
            else:
                values[letter] = value
        actions: list[str] = []
        motion: MoveKind | None = None
        arc_ccw: bool | None = None
        comp_g: float | None = None
        ended = False
        for g, col in gcodes:
            if g in (0.0, 1.0, 2.0, 3.0):
                motion = {0.0: MoveKind.RAPID, 1.0: MoveKind.LINE}.get(g, MoveKind.ARC)
                arc_ccw = g == 3.0 if g in (2.0, 3.0) else None
            elif g in _PLANES:
                st.plane = _PLANES[g]
            elif g == 20.0:
                st.unit = INCH
            elif g == 21.0:
                st.unit = 1.0
            elif g in (40.0, 41.0, 42.0, 41.1, 42.1):
                comp_g = g
            elif g == 90.0:
                st.absolute = True
            elif g == 91.0:
                st.absolute = False
            elif g == 90.1:
                st.ijk_absolute = True
            elif g == 91.1:
                st.ijk_absolute = False
            elif g in _CONTROL_G:
                self._path_control(g, col, values, st)
            elif g in _IGNORED_G:
                actions.append(f"G{g:g}")
            else:
                raise _Stop(Code.NC_UNSUPPORTED, f"G{g:g} is not supported by the rs274 reader", col)
        if "F" in values:
            st.feed_mm_s = values["F"] * st.unit / 60.0
            actions.append(f"F{values['F']:g}")
        if "S" in values:
            actions.append(f"S{values['S']:g}")
        if "T" in values:
            st.selected_tool = int(values["T"])
            actions.append(f"T{int(values['T'])}")
        for mc, col in mcodes:
            if mc == 6:
                st.spindle_tool = st.selected_tool
                actions.append("M6")
            elif mc in (2, 30):
                ended = True
                actions.append(f"M{mc}")
            elif mc in _IGNORED_M:
                actions.append(f"M{mc}")
            else:
                raise _Stop(Code.NC_UNSUPPORTED, f"M{mc} is not supported by the rs274 reader", col)
        side_programmed = comp_g is not None
        if comp_g is not None:
            self._compensation(comp_g, values, st)
        elif "D" in values:
            raise _Stop(Code.NC_SYNTAX, "D word without G41/G42/G41.1/G42.1")
        if motion is not None:
            st.motion = motion
            if arc_ccw is not None:
                st.ccw = arc_ccw
        comp = CompState(
            side=st.side, radius=st.radius_mm, tool_active=True, side_programmed=side_programmed
        )
        axes = [letter for letter in "XYZ" if letter in values]
        full_circle = motion is MoveKind.ARC and any(k in values for k in "IJKR")
        if not axes and not full_circle:
            if motion is MoveKind.ARC:
                raise _Stop(Code.NC_SYNTAX, "G2/G3 without end point or centre")
            moves.append(
                Move(
                    MoveKind.NONE,
                    st.pos,
                    st.pos,
                    st.plane,
                    span,
                    comp,
                    st.feed_mm_s,
                    actions=tuple(actions),
                    control=st.control,
                )
            )
            return ended
        if st.motion is None:
            raise _Stop(Code.NC_SYNTAX, "axis words without a motion mode (G0/G1/G2/G3)")
        end = list(st.pos)
        for i, letter in enumerate("XYZ"):
            if letter in values:
                v = values[letter] * st.unit
                end[i] = v if st.absolute else st.pos[i] + v
        end_t: Vec3 = (end[0], end[1], end[2])
        iu, iv, _ = st.plane.axes
        plane_programmed = "XYZ"[iu] in values or "XYZ"[iv] in values
        kind = st.motion
        feed = None if kind is MoveKind.RAPID else st.feed_mm_s
        if kind is not MoveKind.RAPID and feed is None:
            raise _Stop(Code.NC_SYNTAX, "feed move with no feed rate (F) programmed")
        if kind is MoveKind.ARC:
            move = self._arc(st, values, end_t, span, comp, feed, tuple(actions), plane_programmed)
        else:
            move = Move(
                kind,
                st.pos,
                end_t,
                st.plane,
                span,
                comp,
                feed,
                actions=tuple(actions),
                plane_programmed=plane_programmed,
                control=st.control,
            )
        moves.append(move)
        st.pos = end_t
        return ended

    def _path_control(self, g: float, col: int, values: Mapping[str, float], st: _State) -> None:
        """G61 exact path, G61.1 exact stop, G64 blending: the blend arc passes at most ``P`` from
        the programmed corner point and at most a quarter of the shorter move (no ``P``, or
        ``P0``: the quarter alone) — LinuxCNC's trajectory planner (docs/continuous_path.md)."""
        if st.side is not Side.OFF:
            raise _Stop(Code.LCNC_CONTROL_MODE, "Cannot change control mode with cutter radius compensation on", col)
        if g == 61.0:
            st.control = PathControl(PathMode.EXACT_PATH, word="G61")
        elif g == 61.1:
            st.control = PathControl(PathMode.EXACT_STOP, word="G61.1")
        else:
            p = values.get("P")
            q = values.get("Q", p)
            if p is not None and p < 0:
                raise _Stop(Code.NC_SYNTAX, "G64 P must not be negative", col)
            if q is not None and q < 0:
                raise _Stop(Code.NC_SYNTAX, "G64 Q must not be negative", col)
            tol = p * st.unit if p else None
            merge = q * st.unit if q else None  # the naive-CAM detector: Q defaults to P, Q0 is off
            word = "G64" if p is None else f"G64 P{p:g}" + ("" if "Q" not in values else f" Q{q:g}")
            st.control = PathControl(PathMode.BLEND, tol, ToleranceKind.VERTEX, word, LCNC_BLEND_SHARE, merge)

    def _compensation(self, g: float, values: Mapping[str, float], st: _State) -> None:
        if g == 40.0:
            st.side, st.radius_mm = Side.OFF, 0.0
            return
        st.side = Side.LEFT if g in (41.0, 41.1) else Side.RIGHT
        if g in (41.1, 42.1):
            if "D" not in values:
                raise _Stop(Code.NC_SYNTAX, f"G{g:g} with no D word")
            if "L" in values:
                raise _Stop(Code.NC_UNSUPPORTED, "lathe tool orientation (L word) is not supported")
            st.radius_mm = values["D"] * st.unit / 2.0
            return
        if "D" in values:
            d = values["D"]
            if d != int(d):
                raise _Stop(Code.NC_SYNTAX, f"G{g:g} requires D word to be a whole number")
            if d < 0:
                raise _Stop(Code.NC_SYNTAX, "Negative D word tool radius index used")
            number: int | None = int(d)
        else:
            number = st.spindle_tool
        if number is None or number == 0 and number not in self.tools:
            st.radius_mm = 0.0
            return
        tool = self.tools.get(number)
        if tool is None:
            raise _Stop(
                Code.LCNC_TOOL_NOT_FOUND, f"Requested tool {number} not found in the tool table"
            )
        if tool.orientation not in (0, 9):
            raise _Stop(
                Code.NC_UNSUPPORTED,
                f"lathe tool T{number} (orientation {tool.orientation}) is not supported",
            )
        st.radius_mm = tool.radius_mm

    def _arc(
        self,
        st: _State,
        values: Mapping[str, float],
        end: Vec3,
        span: SourceSpan,
        comp: CompState,
        feed: float | None,
        actions: tuple[str, ...],
        plane_programmed: bool,
    ) -> Move:
        plane = st.plane
        iu, iv, iw = plane.axes
        ccw = st.ccw
        s_uvw, e_uvw = plane.to_uvw(st.pos), plane.to_uvw(end)
        s2, e2 = (s_uvw[0], s_uvw[1]), (e_uvw[0], e_uvw[1])
        turns = 0
        if "P" in values:
            p = values["P"]
            if p != int(p) or p < 1:
                raise _Stop(
                    Code.NC_SYNTAX, "P word of an arc must be a positive whole number of turns"
                )
            turns = int(p) - 1
        if "R" in values:
            try:
                c2 = arc_centre_from_radius(
                    s2, e2, values["R"] * st.unit, ccw, self.arc_tolerance_mm, 1e-9
                )
            except ValueError as exc:
                raise _Stop(Code.LCNC_ARC_RADIUS, f"R-format arc: {exc}") from None
        else:
            cu_l, cv_l = _CENTRE_LETTER[iu], _CENTRE_LETTER[iv]
            if cu_l not in values and cv_l not in values:
                raise _Stop(Code.NC_SYNTAX, f"arc in {plane.value} needs {cu_l} or {cv_l} (or R)")
            for letter in _CENTRE_LETTER[iw]:
                if letter in values:
                    raise _Stop(Code.NC_SYNTAX, f"{letter} word is not a centre word in {plane.value}")
            du = values.get(cu_l, 0.0) * st.unit
            dv = values.get(cv_l, 0.0) * st.unit
            if st.ijk_absolute:
                c2 = (du if cu_l in values else s2[0], dv if cv_l in values else s2[1])
            else:
                c2 = (s2[0] + du, s2[1] + dv)
            r0 = math.hypot(s2[0] - c2[0], s2[1] - c2[1])
            r1 = math.hypot(e2[0] - c2[0], e2[1] - c2[1])
            diff = abs(r1 - r0)
            # LinuxCNC: 0.05 in / 0.5 mm always, 0.0005 in / 0.005 mm when also > 0.1 % of r
            big, small = (0.05 * INCH, 0.0005 * INCH) if st.unit != 1.0 else (0.5, 0.005)
            if diff > big or (diff > small and diff > 0.001 * r0):
                raise _Stop(
                    Code.LCNC_ARC_RADIUS,
                    f"Radius to end of arc differs from radius to start: r1={r0 / st.unit:.4f} r2={r1 / st.unit:.4f}",
                )
            if r0 == 0.0:
                raise _Stop(Code.LCNC_ARC_RADIUS, "Zero-radius arc")
        centre = plane.to_xyz((c2[0], c2[1], s_uvw[2]))
        return Move(
            MoveKind.ARC,
            st.pos,
            end,
            plane,
            span,
            comp,
            feed,
            center=centre,
            ccw=ccw,
            turns=turns,
            actions=actions,
            plane_programmed=plane_programmed,
            control=st.control,
        )


def read_rs274(
    text: str,
    file: str = "<program>",
    tools: LinuxCncToolTable | str | os.PathLike[str] | None = None,
    tool_unit: ToolUnit | str = ToolUnit.INCH,
) -> NcProgram:
    """Read an RS274NGC program; never raises for a problem in the program (see the module
    docstring). ``tools``: a LinuxCNC tool table or a path to one (read in ``tool_unit``);
    default: ``<stem>.tbl``/``tools.tbl`` beside ``file``."""
    return Rs274Reader(file, tools, tool_unit).read(text)


def read_ngc(text: str, options: ReadOptions) -> NcProgram:
    """The controller's reader: ``options.tool_table`` is a LinuxCNC ``.tbl`` read in
    ``options.tool_unit`` (default: ``<stem>.tbl``/``tools.tbl`` beside the program)."""
    table: LinuxCncToolTable | str | os.PathLike[str] | None = options.tool_table
    if table is None and options.tools is not None:
        # preset edges are SINUMERIK tool data, not a LinuxCNC table: the program reads with an
        # empty table (and, as any table given, none is looked up beside the program)
        table = LinuxCncToolTable()
    return read_rs274(text, file=options.file, tools=table, tool_unit=options.tool_unit)
