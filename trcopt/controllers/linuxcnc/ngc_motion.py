"""The state an RS274NGC program runs in, and the moves of its motion blocks.

:class:`NgcState` is LinuxCNC's ``setup`` as far as trcopt models it (positions in mm, program
coordinates); :func:`arc_move` builds a G2/G3 move, :func:`compensation_on` reads LinuxCNC's
G40/G41/G42/G41.1/G42.1 rules, :func:`path_control` G61/G61.1/G64. The block itself is executed
by :mod:`trcopt.controllers.linuxcnc.ngc_exec`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_cycles import CycleState
from trcopt.controllers.linuxcnc.ngc_offsets import Offsets
from trcopt.errors import SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec3
from trcopt.modes import PathMode, Side, ToleranceKind
from trcopt.nc.model import EXACT_PATH, CompState, Move, MoveKind, PathControl

__all__ = ["INCH", "NgcState", "Stop", "ToolEntry", "arc_move", "compensation_on", "path_control"]

INCH = 25.4
_CENTRE_LETTER = "IJK"  # centre word of x, y, z
LCNC_BLEND_SHARE = 0.25  # a G64 blend passes at most this share of the shorter move from the corner


class Stop(Exception):
    """An error that stops the read at this block (``column`` 0: the block's first word)."""

    def __init__(self, code: Code, message: str, column: int = 0) -> None:
        super().__init__(message)
        self.code, self.message, self.column = code, message, column


@dataclass(slots=True)
class ToolEntry:
    """A tool-table entry as the interpreter holds it: lengths in the machine unit."""

    diameter: float = 0.0
    offset: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    orientation: int = 0


@dataclass(slots=True)
class NgcState:
    offsets: Offsets
    tools: dict[int, ToolEntry]
    machine_mm: float | None  # mm per machine unit (None: the program's, decided at its first G20/G21)
    pos: Vec3 = (0.0, 0.0, 0.0)
    plane: Plane = Plane.G17
    unit: float = 1.0  # mm per program unit
    absolute: bool = True
    ijk_absolute: bool = False
    motion: float | None = None  # the G code of the motion mode (None: G80 / none yet)
    feed: float = 0.0  # LinuxCNC's feed rate: program units per minute (G94, G93), per revolution (G95)
    speed: float = 0.0  # the spindle speed S, rev/min
    feed_mode: float = 94.0  # G93 inverse time, G94 units per minute, G95 units per revolution
    side: Side = Side.OFF
    radius_mm: float = 0.0  # signed
    orientation: int = 0  # lathe tool orientation of the compensation (0: a mill tool)
    selected_tool: int | None = None
    spindle_tool: int = 0  # the tool in the spindle (0: none)
    spindle: int = 0  # 1 clockwise, -1 counter-clockwise, 0 stopped
    mist: bool = False
    flood: bool = False
    control: PathControl = EXACT_PATH  # G61 (and no mode programmed); G61.1; G64 [P]
    cycle: CycleState = field(default_factory=CycleState)
    peck_clearance: dict[float, float] = field(default_factory=dict)  # G73/G83 back-off, program units

    @property
    def feed_mm_s(self) -> float | None:
        """The path feed (mm/s; None: none): under G95 the feed per revolution times the speed."""
        if self.feed_mode == 95.0:
            return self.feed * self.speed * self.unit / 60.0 if self.feed and self.speed else None
        return self.feed * self.unit / 60.0 if self.feed else None

    def machine_unit(self) -> float:
        if self.machine_mm is None:
            self.machine_mm = self.unit
        return self.machine_mm

    def user_mm(self, value: float) -> float:
        """A length in the machine unit, in mm (a zero decides no unit)."""
        return value * self.machine_unit() if value else 0.0

    def spindle_entry(self) -> ToolEntry:
        """LinuxCNC's tool slot 0: the tool in the spindle (an empty tool when none)."""
        return self.tools.get(self.spindle_tool, ToolEntry()) if self.spindle_tool else ToolEntry()


def path_control(g: float, values: Mapping[str, float], st: NgcState, col: int) -> None:
    """G61 exact path, G61.1 exact stop, G64 blending: the blend arc passes at most ``P`` from
    the programmed corner point and at most a quarter of the shorter move (no ``P``, or
    ``P0``: the quarter alone) — LinuxCNC's trajectory planner (docs/continuous_path.md)."""
    if st.side is not Side.OFF:
        raise Stop(Code.LCNC_CONTROL_MODE, "Cannot change control mode with cutter radius compensation on", col)
    if g == 61.0:
        st.control = PathControl(PathMode.EXACT_PATH, word="G61")
    elif g == 61.1:
        st.control = PathControl(PathMode.EXACT_STOP, word="G61.1")
    else:
        p = values.get("P")
        q = values.get("Q", p)
        if p is not None and p < 0:
            raise Stop(Code.NC_SYNTAX, "G64 P must not be negative", col)
        if q is not None and q < 0:
            raise Stop(Code.NC_SYNTAX, "G64 Q must not be negative", col)
        tol = p * st.unit if p else None
        merge = q * st.unit if q else None  # the naive-CAM detector: Q defaults to P, Q0 is off
        word = "G64" if p is None else f"G64 P{p:g}" + ("" if "Q" not in values else f" Q{q:g}")
        st.control = PathControl(PathMode.BLEND, tol, ToleranceKind.VERTEX, word, LCNC_BLEND_SHARE, merge)


def compensation_on(g: float, values: Mapping[str, float], st: NgcState, tools: Mapping[int, ToolEntry]) -> None:
    """G40 off; G41/G42 with the tool ``D`` (none or D0: the tool in the spindle); G41.1/G42.1
    with the diameter ``D`` in program units (LinuxCNC's ``convert_cutter_compensation``)."""
    if g == 40.0:
        st.side, st.radius_mm, st.orientation = Side.OFF, 0.0, 0
        return
    side = Side.LEFT if g in (41.0, 41.1) else Side.RIGHT
    if g in (41.1, 42.1):
        if "D" not in values:
            raise Stop(Code.NC_SYNTAX, f"G{g:g} with no D word")
        orientation = 0
        if "L" in values:  # a lathe tool's orientation (LinuxCNC reads L as a whole number)
            if st.plane is not Plane.G18:
                raise Stop(Code.LCNC_WORDS, f"G{g:g} with L word, but plane is not G18")
            orientation = int(values["L"])
        st.side, st.radius_mm, st.orientation = side, values["D"] * st.unit / 2.0, orientation
        return
    if "D" in values:
        d = values["D"]
        if abs(d - round(d)) > 0.0001:
            raise Stop(Code.NC_SYNTAX, f"G{g:g} requires D word to be a whole number")
        if d < 0:
            raise Stop(Code.NC_SYNTAX, "Negative D word tool radius index used")
        number = int(round(d))
    else:
        number = 0
    if number == 0:
        entry = st.spindle_entry()
    else:
        found = tools.get(number)
        if found is None:
            raise Stop(Code.LCNC_TOOL_NOT_FOUND, f"Requested tool {number} not found in the tool table")
        entry = found
    if entry.orientation not in (0, 9) and st.plane is not Plane.G18:
        raise Stop(Code.LCNC_WORDS, f"G{g:g} with lathe tool, but plane is not G18")
    st.side, st.radius_mm, st.orientation = side, st.user_mm(entry.diameter) / 2.0, entry.orientation


def _r_centre(s2: tuple[float, float], e2: tuple[float, float], radius: float, ccw: bool) -> tuple[float, float]:
    """LinuxCNC's ``arc_data_r``: the centre of an R-format arc (R < 0: more than a half turn)."""
    if s2 == e2:
        raise Stop(Code.LCNC_ARC_RADIUS, "Current point same as end point of arc")
    r = abs(radius)
    mid = ((s2[0] + e2[0]) / 2.0, (s2[1] + e2[1]) / 2.0)
    half = math.hypot(mid[0] - e2[0], mid[1] - e2[1])
    if half - r > 0.00005 * INCH:  # LinuxCNC's radius tolerance: 0.00005 in, 0.00127 mm
        raise Stop(Code.LCNC_ARC_RADIUS, "Arc radius too small to reach end point")
    if r == 0.0 or half / r > 1.0 - 1e-12:
        half = r  # a half circle, within the tolerance
    chord = math.atan2(e2[1] - s2[1], e2[0] - s2[0])
    theta = chord - math.pi / 2 if (not ccw) == (radius > 0) else chord + math.pi / 2
    offset = r * math.cos(math.asin(half / r)) if r else 0.0
    return (mid[0] + offset * math.cos(theta), mid[1] + offset * math.sin(theta))


def _g4(value: float) -> str:
    return "%.4g" % value  # noqa: UP031 - C's %g, as LinuxCNC prints it


def arc_move(
    st: NgcState,
    values: Mapping[str, float],
    start: Vec3,
    end: Vec3,
    span: SourceSpan,
    comp: CompState,
    actions: tuple[str, ...],
    plane_programmed: bool,
    ccw: bool,
    arc_tolerance_mm: float,
) -> Move:
    """A G2/G3 move from ``start`` to ``end`` (program coordinates, mm)."""
    plane = st.plane
    iu, iv, iw = plane.axes
    s_uvw, e_uvw = plane.to_uvw(start), plane.to_uvw(end)
    s2, e2 = (s_uvw[0], s_uvw[1]), (e_uvw[0], e_uvw[1])
    turns = 0
    if "P" in values:
        p = values["P"]
        if abs(p - round(p)) > 0.001:
            raise Stop(Code.LCNC_WORDS, "P value not an integer with M19 G2 or G3")
        if round(p) < 1:
            raise Stop(Code.LCNC_WORDS, "P value should be 1 or greater with G2 or G3")
        turns = int(round(p)) - 1
    if "R" in values:
        c2 = _r_centre(s2, e2, values["R"] * st.unit, ccw)
    else:
        cu_l, cv_l = _CENTRE_LETTER[iu], _CENTRE_LETTER[iv]
        if cu_l not in values and cv_l not in values:
            raise Stop(Code.NC_SYNTAX, f"arc in {plane.value} needs {cu_l} or {cv_l} (or R)")
        for letter in _CENTRE_LETTER[iw]:
            if letter in values:
                raise Stop(Code.NC_SYNTAX, f"{letter} word is not a centre word in {plane.value}")
        du = values.get(cu_l, 0.0) * st.unit
        dv = values.get(cv_l, 0.0) * st.unit
        if st.ijk_absolute:
            c2 = (du if cu_l in values else s2[0], dv if cv_l in values else s2[1])
        else:
            c2 = (s2[0] + du, s2[1] + dv)
        r0 = math.hypot(s2[0] - c2[0], s2[1] - c2[1])
        r1 = math.hypot(e2[0] - c2[0], e2[1] - c2[1])
        u = st.unit
        a, b = "XYZ"[iu], "XYZ"[iv]
        where = (
            f"start=({a}{s2[0] / u:.4f},{b}{s2[1] / u:.4f}) center=({a}{c2[0] / u:.4f},{b}{c2[1] / u:.4f}) "
            f"end=({a}{e2[0] / u:.4f},{b}{e2[1] / u:.4f}) r1={r0 / u:.4f} r2={r1 / u:.4f}"
        )
        # LinuxCNC: zero below 0.00005 in (0.00127 mm); the end radius may differ by 0.05 in /
        # 0.5 mm, or by 0.0005 in / 0.005 mm and 0.1 % of the larger radius
        zero, small = 0.00005 * INCH, (0.0005 * INCH if u != 1.0 else 0.005)
        if r0 < zero or r1 < zero:
            raise Stop(Code.LCNC_ARC_RADIUS, f"Zero-radius arc: {where}")
        diff = abs(r1 - r0)
        rel = diff / max(r0, r1)
        if diff > 100.0 * small or (rel > 0.001 and diff > small):
            raise Stop(
                Code.LCNC_ARC_RADIUS,
                "Radius to end of arc differs from radius to start: "
                f"{where} abs_err={_g4(diff / u)} rel_err={rel * 100:.4f}%",
            )
    centre = plane.to_xyz((c2[0], c2[1], s_uvw[2]))
    return Move(
        MoveKind.ARC, start, end, plane, span, comp, st.feed_mm_s, center=centre, ccw=ccw, turns=turns,
        actions=actions, plane_programmed=plane_programmed, control=st.control,
    )  # fmt: skip
