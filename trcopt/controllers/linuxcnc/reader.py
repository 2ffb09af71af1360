"""RS274NGC / LinuxCNC G-code front end: program text → canonical moves (absolute mm).

The language is LinuxCNC's: ``( )`` and ``;`` comments, block delete ``/``,
``N`` numbers, ``%`` lines; parameters, ``[ ]`` expressions, O-word subroutines and control flow
(:class:`~trcopt.controllers.linuxcnc.ngc_flow.NgcFlow`); each block is then decoded
(:mod:`~trcopt.controllers.linuxcnc.ngc_words`) and executed in LinuxCNC's order
(:mod:`~trcopt.controllers.linuxcnc.ngc_exec`): G0 G1 G2 G3 (I/J/K or R, P turns, helices), G4,
G17–G19, G20/G21, G40–G42 and G41.1/G42.1, G43/G43.1/G43.2/G49, G54–G59.3, G10 L1/L10/L2/L20,
G28/G30 and G28.1/G30.1, G52, G53, G92/G92.1/G92.2/G92.3, G61/G61.1/G64, G73 G74 G81–G87 G89 with
G98/G99 (:mod:`~trcopt.controllers.linuxcnc.ngc_cycles`), G80, G90/G91, G90.1/G91.1, G93/G94/G95
(:mod:`~trcopt.controllers.linuxcnc.ngc_feed`: inverse time, units per minute, per revolution); F, S,
T, M0 M1 M2 M3 M4 M5 M6 M7 M8 M9 M30 M48 M49 M60 M61; ``(MSG,…)``, ``(DEBUG,…)``, ``(PRINT,…)``
(kept as ``LCNC-MESSAGE`` notes), ``(ABORT,…)``. Codes LinuxCNC has and trcopt does not model
(G33, G38.x, G76, G96, M62…, M98/M99, …) stop the read with ``NC-UNSUPPORTED`` naming them.

Conventions: the program starts at (0, 0, 0) in G17, G90, G91.1 and mm (until G20); lengths are
converted to mm here, feeds to mm/s. The moves are in the G54 system as it stands at the start
(:mod:`~trcopt.controllers.linuxcnc.ngc_offsets`). The tool table is LinuxCNC's ``.tbl``
(:mod:`trcopt.controllers.linuxcnc.tooltable`) in the machine unit: the program's own unit unless
``tool_unit`` says inch or mm; parameters (``#5161``… reference points, work offsets) and the
G73/G83 peck clearances may be set in ``rs274ngc.toml`` beside the tool table or the program.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_comment import active_comment
from trcopt.controllers.linuxcnc.ngc_exec import execute_block
from trcopt.controllers.linuxcnc.ngc_expr import NgcError, Parameters, normalise
from trcopt.controllers.linuxcnc.ngc_flow import FlowError, NgcFlow, Step
from trcopt.controllers.linuxcnc.ngc_motion import NgcState, Stop, ToolEntry
from trcopt.controllers.linuxcnc.ngc_offsets import OffsetError, Offsets
from trcopt.controllers.linuxcnc.ngc_plain import execute_plain
from trcopt.controllers.linuxcnc.ngc_words import decode
from trcopt.controllers.linuxcnc.tooltable import LinuxCncToolTable, find_tbl, load_parameters, load_tbl
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.modes import Side, ToolUnit, parse_enum
from trcopt.nc.collector import collector_paused
from trcopt.nc.modal import ReadOptions
from trcopt.nc.model import Move, NcProgram
from trcopt.nc.stream import MoveStream, ReadSummary
from trcopt.textlines import iter_lines

__all__ = ["Rs274Reader", "read_rs274", "read_ngc", "stream_ngc"]

_PLANE_CODE = {Plane.G17: 170.0, Plane.G18: 180.0, Plane.G19: 190.0}
_SIDE_CODE = {Side.OFF: 400.0, Side.LEFT: 410.0, Side.RIGHT: 420.0}


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
        The machine unit: of a tool table read from a path and of the offset parameters —
        ``"program"`` (the default: the unit of the program's first G20/G21), ``"inch"``
        (LinuxCNC's standalone interpreter) or ``"mm"``.
    parameters:
        A ``rs274ngc.toml`` file (parameter values, peck clearances); default: beside the tool
        table, else beside the program.
    """

    name = "rs274"

    def __init__(
        self,
        file: str = "<program>",
        tools: LinuxCncToolTable | str | os.PathLike[str] | None = None,
        tool_unit: ToolUnit | str = ToolUnit.PROGRAM,
        arc_tolerance_mm: float = 0.005,
        parameters: str | os.PathLike[str] | None = None,
    ) -> None:
        self.file = file
        self.diags: list[Diagnostic] = []
        self.arc_tolerance_mm = arc_tolerance_mm
        self.unit = parse_enum(ToolUnit, tool_unit, "tool unit") if isinstance(tool_unit, str) else tool_unit
        table_path: str | os.PathLike[str] | None = None
        if tools is None:
            tools = find_tbl(file)
        if isinstance(tools, (str, os.PathLike)):
            table_path = tools
            table = load_tbl(tools, self.unit)
            self.diags.append(
                Diagnostic(
                    Severity.INFO,
                    Code.LCNC_TOOL_TABLE,
                    f"tool table {table.source} read in {_unit_name(table.unit)}",
                    SourceSpan(file, 0, 0),
                )
            )
            tools = table
        self.tools: LinuxCncToolTable = (
            tools if isinstance(tools, LinuxCncToolTable) else LinuxCncToolTable(unit=self.unit)
        )
        self.settings = load_parameters(parameters, table_path, file)

    # -- reading ----------------------------------------------------------------------------
    def read(self, text: str) -> NcProgram:
        with collector_paused():  # the moves are acyclic (trcopt.nc.collector)
            moves = tuple(self.iter_moves(text))
        return NcProgram(self.file, "rs274", moves, tuple(self.diags), self.blocks)

    def iter_moves(self, text: str) -> Iterator[Move]:
        """The moves of ``text`` as they are executed (one block at a time: the program's moves
        are never all held); when it ends, ``diags`` holds the diagnostics and ``blocks`` the
        number of blocks executed, as :meth:`read` returns them."""
        self.blocks = 0
        params = Parameters()
        for number, value in self.settings.parameters.items():
            params.numbered[number] = value
        unit = self.tools.unit
        k = unit.mm
        entries = {
            n: ToolEntry(t.diameter_mm / k, [t.x_offset_mm / k, t.y_offset_mm / k, t.z_offset_mm / k], t.orientation)
            for n, t in self.tools.tools.items()
        }
        holder: list[NgcState] = []
        offsets = Offsets(params, lambda: holder[0].machine_unit())
        st = NgcState(offsets, entries, program_unit(text) if unit is ToolUnit.PROGRAM else unit.mm)
        st.peck_clearance = dict(self.settings.peck_clearance)
        holder.append(st)
        params.readonly = lambda name: _readonly(name, st)
        try:  # the machine starts at its origin, as LinuxCNC's interpreter does
            st.pos = offsets.machine_end({0: 0.0, 1: 0.0, 2: 0.0}, st.pos)
        except OffsetError as exc:
            self.diags.append(Diagnostic(Severity.ERROR, exc.code, exc.message, SourceSpan(self.file, 0, 0)))
            return
        moves: list[Move] = []
        steps = NgcFlow(self.file, text, params).blocks()
        try:
            while True:
                try:
                    step = next(steps, None)
                except FlowError as err:
                    span = SourceSpan(err.file, err.line, err.column, err.block)
                    self.diags.append(Diagnostic(Severity.ERROR, err.code, err.message, span))
                    break
                if step is None:
                    break
                self.blocks += 1
                span = SourceSpan(step.file, step.line, 1, None if step.number is None else f"N{step.number}")
                try:
                    ended = self._block(step, span, st, moves, params)
                except Stop as stop:
                    first = step.block.words[0][2] if step.block.words else 1
                    span = SourceSpan(span.file, span.line, stop.column or first, span.block)
                    self.diags.append(Diagnostic(Severity.ERROR, stop.code, stop.message, span))
                    ended = True
                except NgcError as exc:
                    span = SourceSpan(span.file, span.line, exc.column or 1, span.block)
                    self.diags.append(Diagnostic(Severity.ERROR, exc.code, exc.message, span))
                    ended = True
                except (ArithmeticError, LookupError, TypeError, ValueError) as exc:  # a bug must not pass silently
                    message = f"internal error while reading this block: {exc!r}"
                    self.diags.append(Diagnostic(Severity.ERROR, Code.NC_INTERNAL, message, span))
                    ended = True
                if moves:  # the block's moves (those before an error in it too, as read() keeps them)
                    yield from moves
                    moves.clear()
                if ended:
                    break
        finally:
            steps.close()

    def _block(self, step: Step, span: SourceSpan, st: NgcState, moves: list[Move], params: Parameters) -> bool:
        if step.plain is not None:
            if execute_plain(step.plain, span, st, moves.append, params):
                return False
            step.read_block(params)  # read and run as any other line
        words = decode(step.block.words, st)
        action = None
        if step.block.comment is not None:  # a line without a comment has no message
            settings = dict(step.block.settings)

            def numbered(k: int) -> float | None:
                v = settings.get(k)
                return params.numbered[k] if v is None else v

            def named(name: str) -> float | None:
                v = settings.get(name)
                return params.get_named(name) if v is None else v

            message = active_comment(step.block.comment, numbered, named)
            if message is not None:
                kind, text = message
                action = f'MSG("{text}")'
                self.diags.append(Diagnostic(Severity.INFO, Code.LCNC_MESSAGE, f"{kind}: {text}", span))
        ended = execute_block(words, span, st, moves.append, self.arc_tolerance_mm, action)
        pos, unit, numbered_params = st.pos, st.unit, params.numbered
        numbered_params[5420] = pos[0] / unit
        numbered_params[5421] = pos[1] / unit
        numbered_params[5422] = pos[2] / unit
        params.comp_on = st.side is not Side.OFF
        return ended


_UNIT_WORD = re.compile(r"g0*2([01])(?![0-9.])")
# a line without a comment in which this is not found has no G20/G21 once normalised (blanks are
# the only characters normalise() drops from it)
_MAYBE_UNIT_WORD = re.compile("[gG][0 \t\r\n\f\v]*2[ \t\r\n\f\v]*[01]").search


def program_unit(text: str) -> float:
    """mm per unit of the program's first G20/G21 (mm when it has none): the machine unit of a
    tool table and parameters given in the program's unit."""
    for raw in iter_lines(text):  # up to the first unit word, not a list of every line
        if "(" not in raw and _MAYBE_UNIT_WORD(raw) is None:
            continue
        try:
            line = normalise(raw).text
        except NgcError:
            continue
        m = _UNIT_WORD.search(line)
        if m and not line.startswith("o"):
            return 25.4 if m.group(1) == "0" else 1.0
    return 1.0


def _unit_name(unit: ToolUnit) -> str:
    return "the program's unit" if unit is ToolUnit.PROGRAM else unit.value


def _readonly(name: str, st: NgcState) -> float | None:
    """LinuxCNC's predefined read-only parameters that trcopt models (program units)."""
    u = st.unit
    if name in ("_x", "_y", "_z", "_abs_x", "_abs_y", "_abs_z"):
        if st.side is not Side.OFF:
            raise NgcError(f"#<{name}> with cutter radius compensation on is not modelled", 0, Code.NC_UNSUPPORTED)
        p = st.offsets.machine(st.pos) if name.startswith("_abs") else st.pos
        return p["xyz".index(name[-1])] / u
    if name in ("_a", "_b", "_c", "_u", "_v", "_w", "_abs_a", "_abs_b", "_abs_c", "_abs_u", "_abs_v", "_abs_w"):
        return 0.0
    off = st.offsets
    values = {
        "_plane": lambda: _PLANE_CODE[st.plane],
        "_ccomp": lambda: _SIDE_CODE[st.side],
        "_metric": lambda: float(u == 1.0),
        "_imperial": lambda: float(u != 1.0),
        "_absolute": lambda: float(st.absolute),
        "_incremental": lambda: float(not st.absolute),
        "_inverse_time": lambda: float(st.feed_mode == 93.0),
        "_units_per_minute": lambda: float(st.feed_mode == 94.0),
        "_units_per_rev": lambda: float(st.feed_mode == 95.0),
        "_coord_system": lambda: 530.0 + 10 * off.index if off.index < 7 else 584.0 + off.index,
        "_tool_offset": lambda: float(any(off.tool)),
        "_retract_r_plane": lambda: float(not st.cycle.retract_old),
        "_retract_old_z": lambda: float(st.cycle.retract_old),
        "_spindle_rpm_mode": lambda: 1.0,
        "_spindle_css_mode": lambda: 0.0,
        "_ijk_absolute_mode": lambda: float(st.ijk_absolute),
        "_lathe_diameter_mode": lambda: 0.0,
        "_lathe_radius_mode": lambda: 1.0,
        "_spindle_on": lambda: float(st.spindle != 0),
        "_spindle_cw": lambda: float(st.spindle > 0),
        "_mist": lambda: float(st.mist),
        "_flood": lambda: float(st.flood),
        "_feed": lambda: st.feed,
        "_rpm": lambda: st.speed,
        "_current_tool": lambda: float(st.spindle_tool),
        "_selected_tool": lambda: float(-1 if st.selected_tool is None else st.selected_tool),
    }
    if name == "_motion_mode":
        return 800.0 if st.motion is None else st.motion * 10.0
    fn = values.get(name)
    if name in ("_x", "_y", "_z") or fn is None:
        return None
    if name in ("_absolute", "_coord_system"):
        off.start()
    return fn()


def read_rs274(
    text: str,
    file: str = "<program>",
    tools: LinuxCncToolTable | str | os.PathLike[str] | None = None,
    tool_unit: ToolUnit | str = ToolUnit.PROGRAM,
    parameters: str | os.PathLike[str] | None = None,
) -> NcProgram:
    """Read an RS274NGC program; never raises for a problem in the program (see the module
    docstring). ``tools``: a LinuxCNC tool table or a path to one (read in ``tool_unit``, the
    machine unit); default: ``<stem>.tbl``/``tools.tbl`` beside ``file``."""
    return Rs274Reader(file, tools, tool_unit, parameters=parameters).read(text)


def read_ngc(text: str, options: ReadOptions) -> NcProgram:
    """The controller's reader: ``options.tool_table`` is a LinuxCNC ``.tbl`` read in
    ``options.tool_unit`` (default: ``<stem>.tbl``/``tools.tbl`` beside the program)."""
    return _reader(options).read(text)


def stream_ngc(text: str, options: ReadOptions) -> MoveStream:
    """:func:`read_ngc` block by block (:meth:`Rs274Reader.iter_moves`)."""
    reader = _reader(options)
    return MoveStream(
        options.file, "rs274", reader.iter_moves(text), lambda: ReadSummary(list(reader.diags), reader.blocks)
    )


def _reader(options: ReadOptions) -> Rs274Reader:
    table: LinuxCncToolTable | str | os.PathLike[str] | None = options.tool_table
    if table is None and options.tools is not None:
        # preset edges are SINUMERIK tool data, not a LinuxCNC table: the program reads with an
        # empty table (and, as any table given, none is looked up beside the program)
        table = LinuxCncToolTable(unit=options.tool_unit)
    return Rs274Reader(options.file, table, options.tool_unit)
