"""Tool-centre G-code of a whole plan: the path of :mod:`trcopt.io.gcode` with the program's
non-motion words, its units, its alarm and its omitted blocks.

:func:`plan_to_gcode` writes, in program order,

* every non-motion word the reader kept in a move's ``actions`` (tool call and change ``T``/``M6``,
  ``D``, spindle ``S``/``M3``/``M4``/``M5``, coolant ``M7``/``M8``/``M9``, work offsets
  ``G54``–``G59``/``G500``, ``MSG``, ``M0``/``M1``, dwell ``G4``, tool data) as a block of its
  own **before** the first motion of its source block — where the controller outputs them at the
  block start — except the words that act at the **block end** (``M0``, ``M1``, ``M5``, ``M9``),
  written after the last motion of the block; a block without motion (or whose motion was
  omitted) keeps its place between the motions around it. ``F`` is written with the motions; the
  program's path-control words (``G64``, ``G642``, ``CTOL=``, ``CYCLE832`` …) become a comment, as
  their rounding is already in the tool-centre path; the program end (``M30``/``M2``/``RET``) is
  the flavour's end word. Words another flavour cannot read (``$TC_DP…`` in LinuxCNC output) are
  kept as comments; ``MSG("…")`` becomes LinuxCNC's ``(MSG, …)`` and a dwell's time its ``P``.
  Of a LinuxCNC program also the words its reader resolves (:mod:`trcopt.io.ngc_source_words`:
  the tool length offset written, work systems and axis offsets as comments);
* the program's own comments at their lines (:mod:`trcopt.io.program_comments`), up to its last motion;
* no motion the program did not command: the first motion starts where the program's first
  motion starts, and an axis the program has not moved or named yet is not written;
* the program's units: a program in inch (SINUMERIK ``G70``/``G700``, RS274 ``G20``, Heidenhain
  ``BEGIN PGM … INCH``, in force at its first motion) is written in inch with one more decimal;
* a comment naming each omitted block (alarm 10763) and, for a program stopped by an alarm, a
  last comment naming it (code, message, file:line) instead of the end word.

Every motion block names its source (``; N60 L6 corner``, ``(N60 L6 corner)``), the pieces of one
segment on the first block, a word block its source block and line.
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from trcopt.codes import Code, family
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry.poly import Poly
from trcopt.geometry.primitives import Arc, Line
from trcopt.io.gcode import MAX_DECIMALS, GcodeFlavor, _round, open_writer, write_segment
from trcopt.io.ngc_source_words import resolved_lines, source_words
from trcopt.io.program_comments import program_comments
from trcopt.io.spill import SpilledSegments
from trcopt.path import Segment
from trcopt.textlines import TextLines

__all__ = ["plan_to_gcode", "plan_to_gcode_chunks", "program_units", "kept_words", "carries_words"]

INCH_MM = 25.4
_END = {"M2", "M02", "M30", "M17", "RET"}
_AT_BLOCK_END = {"M0", "M00", "M1", "M01", "M5", "M05", "M9", "M09"}
_PATH_CONTROL = re.compile(r"^(G0*9(?![\d.])|G6[01](\.1)?|G60[1-3]|G64[1-5]?|ADIS=|ADISPOS=|CTOL=|CYCLE832)", re.I)
_DROPPED = re.compile(f"{_PATH_CONTROL.pattern}|^G0*9[35]$", re.I)  # path control and feed mode: comments
_PORTABLE = re.compile(r"^(T\d+|M\d+|S\d+(\.\d*)?|G5[4-9])$", re.I)
_FEED = re.compile(r"^F[-+.\d]", re.I)
_FEED_MODE = re.compile(r"^G0*(9[35])$", re.I)  # G93, G95 a reader keeps: the output's feeds are per minute
_FEED_MODES = {"93": "inverse time", "95": "feed per revolution, F × S"}
_DWELL = re.compile(r"^G0*4$", re.I)
_MSG = re.compile(r'^MSG\s*\(\s*"(.*)"\s*\)$', re.I)
_COMMENTS = re.compile(r"\([^)]*\)|;.*$|\"[^\"]*\"")
_AXIS = re.compile(r"(?<![A-Z0-9_$\[.])([XYZ])(?=\s*[-+=.\d(])", re.I)
_UNIT_WORDS = {
    "siemens": re.compile(r"(?<![A-Z0-9_.])G0*(70|700|71|710)(?![\d.])", re.I),
    "rs274": re.compile(r"(?<![A-Z0-9_.])G\s*0*(20|21)(?![\d.])", re.I),
}
_INCH_PREAMBLE = {"G71": "G70", "G21": "G20"}
_FLAVOR_DIALECT = {"linuxcnc": "rs274"}  # an output-only flavour (grbl) is no program's dialect
#: how a flavour writes a block in machine coordinates (a segment whose span carries ``machine``)
_MACHINE_WORDS = {"siemens": ("SUPA",), "linuxcnc": ("G53",), "grbl": ("G53",)}


def program_units(source: str, dialect: str, first_motion_line: int | None) -> tuple[bool, bool]:
    """``(inch, feed_inch)``: whether the program's lengths are in inch at its first motion and
    whether its feeds are too (SINUMERIK ``G70`` keeps feeds in mm/min, ``G700`` does not)."""
    lines = itertools.islice(TextLines(source), first_motion_line)  # up to the first motion
    if dialect == "heidenhain":
        inch = any(re.match(r"\s*\d*\s*BEGIN\s+PGM\s+\S+\s+INCH\b", ln, re.I) for ln in lines)
        return inch, inch
    pattern = _UNIT_WORDS.get(dialect)
    last = None
    for ln in lines if pattern is not None else ():
        for m in pattern.finditer(_COMMENTS.sub(" ", ln)):
            last = m.group(1)
    if last in ("70", "700", "20"):
        return True, last != "70"
    return False, False


def _scaled(seg: Segment, k: float, feed_k: float) -> Segment:
    """The segment with lengths times ``k`` and the feed times ``feed_k``."""
    g = seg.geometry

    def p(q: tuple[float, float, float]) -> tuple[float, float, float]:
        return (q[0] * k, q[1] * k, q[2] * k)

    if isinstance(g, Line):
        geom: Line | Arc | Poly = Line(p(g.start), p(g.end))
    elif isinstance(g, Arc):
        geom = Arc((g.center[0] * k, g.center[1] * k), g.radius * k, g.a0, g.sweep, g.w0 * k, g.w1 * k)
    else:
        curv = None if g.curvatures is None else tuple((c[0] / k, c[1] / k, c[2] / k) for c in g.curvatures)
        geom = replace(g, points=tuple(p(q) for q in g.points), cum=tuple(c * k for c in g.cum), curvatures=curv)
    feed = None if seg.feed_mm_s is None else seg.feed_mm_s * feed_k
    return replace(seg, geometry=geom, feed_mm_s=feed)


class _Scaled(Sequence[Segment]):
    """The segments of a path scaled by ``k`` (feeds by ``feed_k``), each made when it is read."""

    def __init__(self, segs: Sequence[Segment], k: float, feed_k: float) -> None:
        self.segs, self.k, self.feed_k = segs, k, feed_k

    def __len__(self) -> int:
        return len(self.segs)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        return _scaled(self.segs[i], self.k, self.feed_k)

    def __iter__(self) -> Iterator[Segment]:
        for s in self.segs:
            yield _scaled(s, self.k, self.feed_k)


@dataclass
class _Group:
    """The non-motion words and notes of one source line."""

    line: int
    block: str | None
    before: list[str] = field(default_factory=list)
    after: list[str] = field(default_factory=list)
    comments: list[str] = field(default_factory=list)
    remarks: list[str] = field(default_factory=list)  # the program's own comments on the line

    @property
    def source(self) -> str:
        return " ".join(x for x in (self.block, f"L{self.line}") if x)


def carries_words(actions: tuple[str, ...] | list[str]) -> bool:
    """Whether the G-code writer writes something of a move's ``actions`` (its words, or a comment
    on its path-control words): the moves a plan keeps for the writer."""
    return bool(actions) and (bool(kept_words(actions)) or any(_DROPPED.match(a.strip()) for a in actions))


def kept_words(actions: tuple[str, ...] | list[str]) -> list[str]:
    """The words of a move's ``actions`` the writer keeps as words, in order (the feed and the
    path-control words and the program end are written otherwise; a dwell keeps its time)."""
    words: list[str] = []
    dwell = any(_DWELL.match(a) for a in actions)
    for a in actions:
        text = a.strip()
        if not text or text.endswith(":") or text.upper() in _END or _DROPPED.match(text):
            continue
        if _FEED.match(text) and not dwell:
            continue
        words.append(text)
    return words


def _feed_mode_note(actions: Any) -> list[str]:
    """The comment on a program's G93/G95 (a word of its own would change the meaning of every F written)."""
    modes = [m.group(1) for m in (_FEED_MODE.match(a.strip()) for a in actions) if m]
    return [f"G{g} ({_FEED_MODES[g]}) of the program: the feeds are written per minute (G94)" for g in modes]


def _translate(words: list[str], same: bool, flavor: GcodeFlavor, source_line: str) -> tuple[list[str], list[str]]:
    """``(words, comments)`` for the output flavour: everything as is in the program's own
    dialect; elsewhere the portable words, the dwell and the message, the rest as comments."""
    if any(_DWELL.match(w) for w in words):
        time = next((w[1:] for w in words if w[:1].upper() in "FP" and w[1:2] in "0123456789.+"), None)
        if time is None:
            m = re.search(r"(?<![A-Z])P\s*([\d.]+)", _COMMENTS.sub(" ", source_line), re.I)
            time = m.group(1) if m else None
        words = [w for w in words if not (w[:1].upper() in "FP" and w[1:2] in "0123456789.+")]
        letter = "P" if flavor.paren_comments else "F"
        words = [f"G4 {letter}{time}" if _DWELL.match(w) and time is not None else w for w in words]
    if same and not (flavor.paren_comments and any(_MSG.match(w) for w in words)):
        return words, []
    if same:
        # a LinuxCNC message is a comment, (MSG, …), not a word
        msgs = [f"MSG,{m.group(1)}" for m in map(_MSG.match, words) if m]
        return [w for w in words if not _MSG.match(w)], msgs
    kept: list[str] = []
    comments: list[str] = []
    portable = _PORTABLE if flavor.portable_words is None else re.compile(flavor.portable_words, re.I)
    tools = [w for w in words if re.match(r"^T\d+$", w, re.I)]
    for w in words:
        msg = _MSG.match(w)
        if flavor.manual_tool_change and re.match(r"^M0*6$", w, re.I):
            # no tool changer: the program stops for the operator to change the tool by hand
            kept.append(flavor.manual_tool_change)
            comments.append(" ".join(["tool change", *tools, f"{w}: change the tool by hand, then resume"]))
        elif msg and flavor.paren_comments:
            comments.append(f"MSG, {msg.group(1)}")
        elif portable.match(w) or w.upper().startswith("G4 "):
            kept.append(w)
        else:
            comments.append(f"not written in {flavor.name} G-code: {w}")
    return kept, comments


def _groups(result: Any, flavor: GcodeFlavor, same: bool, lines: Sequence[str]) -> list[_Group]:
    by_line: dict[int, _Group] = {}

    def group(line: int, block: str | None) -> _Group:
        if line not in by_line:
            by_line[line] = _Group(line, block)
        return by_line[line]

    # the moves' actions and the words of blocks a reader keeps without a move (Heidenhain TOOL CALL)
    blocks = [(m.span, m.actions) for m in result.nc.moves]
    blocks += list(result.nc.extras.get("words", ()))  # type: ignore[call-overload]
    if result.dialect == "rs274":
        # the blocks with words the reader resolves, found in the text as well (a program without
        # o-word flow runs every line up to its end or alarm): a plan made window by window keeps
        # only the moves with words, and a block that raised the alarm has none
        alarm = _stop(result)
        last = alarm.span.line if alarm is not None and alarm.span.file == result.nc.file else None
        have = {span.line for span, _ in blocks}
        blocks += [(SourceSpan(result.nc.file, n), ()) for n in resolved_lines(lines, last) if n not in have]
    read: set[int] = set()  # the lines whose text was read for the words the reader resolves
    for span, actions in sorted(blocks, key=lambda b: b[0].line):
        notes: list[str] = []
        if result.dialect == "rs274" and span.line not in read and span.file == result.nc.file:
            read.add(span.line)
            actions, notes = _with_source_words(actions, span.line, lines)
        words = kept_words(actions)
        dropped = [a for a in actions if _PATH_CONTROL.match(a.strip())]
        notes += _feed_mode_note(actions)
        if not words and not dropped and not notes:
            continue
        g = group(span.line, span.block)
        source_line = lines[span.line - 1] if 0 < span.line <= len(lines) else ""
        kept, comments = _translate(words, same, flavor, source_line)
        g.before += [w for w in kept if w.upper() not in _AT_BLOCK_END]
        g.after += [w for w in kept if w.upper() in _AT_BLOCK_END]
        g.comments += notes + comments
        if dropped:
            g.comments.append("path control " + " ".join(dropped) + ": its rounding is in the tool-centre path")
    for d in result.diagnostics:
        if d.code == Code.ALARM_10763 and d.span.line:
            group(d.span.line, d.span.block).comments.append(f"omitted block, {d.format()}")
    for n, text in enumerate(lines, 1):  # the program's comments, at their lines
        remarks = program_comments(text, result.dialect)
        if remarks:
            group(n, by_line[n].block if n in by_line else None).remarks += remarks
    return sorted(by_line.values(), key=lambda g: g.line)


def _with_source_words(actions: Any, line: int, lines: Sequence[str]) -> tuple[tuple[str, ...], list[str]]:
    """The actions of the first move of an RS274NGC ``line`` with the words its reader resolves
    (:func:`trcopt.io.ngc_source_words.source_words`), and the comments on the others."""
    if not 0 < line <= len(lines):
        return tuple(actions), []
    add, notes = source_words(lines[line - 1], actions)
    return (*add, *actions), notes


def _write_machine(w: Any, seg: Segment, flavor: GcodeFlavor, k: float) -> None:
    """A block in machine coordinates (SINUMERIK G53/G153/SUPA): its programmed machine positions,
    with the flavour's word for it (``SUPA``, LinuxCNC ``G53``); the modal position is the path's."""
    assert seg.span.machine is not None
    words = ["G0" if seg.is_rapid else "G1", *_MACHINE_WORDS[flavor.name]]
    words += [f"{name}{w.num(v * k)}" for name, v in zip("XYZ", seg.span.machine, strict=True) if v is not None]
    if not seg.is_rapid:
        words += w.feed_word(seg.feed_mm_s)
    w.emit(words, " ".join(x for x in (seg.span.block, f"L{seg.span.line}", "machine coordinates") if x))
    w.started = True
    for i in range(3):
        w.pos[i] = _round(seg.end_xyz[i], w.decimals)


def _in_run_order(result: Any) -> bool:
    """Whether the program runs its blocks out of line order (jumps, loops, repetitions) or in other
    files (subprograms): its words are then written move by move as they run."""
    moves = result.nc.moves
    if result.nc.extras.get("words"):
        return False
    return any(m.span.file != result.nc.file for m in moves) or any(
        b.span.line < a.span.line for a, b in zip(moves, moves[1:], strict=False)
    )


def _move_groups(result: Any, flavor: GcodeFlavor, same: bool, lines: Sequence[str]) -> list[tuple[Any, _Group]]:
    """The words of every move in the order the moves run (one group per move)."""
    out = []
    previous = None
    for m in result.nc.moves:
        g = _Group(m.span.line, m.span.block)
        actions, notes = m.actions, []
        here = m.span.file == result.nc.file and 0 < m.span.line <= len(lines)
        if result.dialect == "rs274" and here and m.span != previous:  # the first move of a block run
            actions, notes = _with_source_words(actions, m.span.line, lines)
        if here and m.span != previous:
            g.remarks += program_comments(lines[m.span.line - 1], result.dialect)
        previous = m.span
        words = kept_words(actions)
        dropped = [a for a in actions if _PATH_CONTROL.match(a.strip())]
        g.comments += notes + _feed_mode_note(actions)
        if words or dropped:
            kept, comments = _translate(words, same, flavor, lines[m.span.line - 1] if here else "")
            g.before += [w for w in kept if w.upper() not in _AT_BLOCK_END]
            g.after += [w for w in kept if w.upper() in _AT_BLOCK_END]
            g.comments += comments
            if dropped:
                g.comments.append("path control " + " ".join(dropped) + ": its rounding is in the tool-centre path")
        if m.span.file != result.nc.file:
            g.block = " ".join(x for x in (m.span.file, g.block) if x)
        out.append((m.span, g))
    for d in result.diagnostics:
        if d.code == Code.ALARM_10763 and d.span.line:
            match = next((g for span, g in out if span.line == d.span.line and span.file == d.span.file), None)
            if match is not None:
                match.comments.append(f"omitted block, {d.format()}")
    return out


def _write_in_run_order(
    w: Any, result: Any, segs: list[Segment], groups: list[tuple[Any, _Group]], flush: Any, lines: Sequence[str],
    inch: bool,
) -> None:
    """Write the segments with the words of the moves they come from, in the order the moves run."""
    done = 0  # the moves before this index are written
    current = -1  # the move whose segments are being written
    for seg in segs:
        if current < 0 or groups[current][0] != seg.span:
            k = next((i for i in range(done, min(len(groups), done + 10_000)) if groups[i][0] == seg.span), None)
            if k is not None:
                if current >= 0:
                    flush(groups[current][1], False, True)
                for i in range(done, k):
                    flush(groups[i][1], True, True)
                flush(groups[k][1], True, False)
                current, done = k, k + 1
                span = seg.span
                here = span.file == result.nc.file and 0 < span.line <= len(lines)
                text = _COMMENTS.sub(" ", lines[span.line - 1]) if here else ""
                w.programmed = frozenset("XYZ".index(m.group(1).upper()) for m in _AXIS.finditer(text))
        if seg.span.machine is not None and isinstance(seg.geometry, Line) and w.flavor.name in _MACHINE_WORDS:
            _write_machine(w, seg, w.flavor, 1.0 / INCH_MM if inch else 1.0)
            continue
        write_segment(w, seg)
    w.programmed = frozenset()
    if current >= 0:
        flush(groups[current][1], False, True)
    for i in range(done, len(groups)):
        flush(groups[i][1], True, True)


def _stop(result: Any) -> Diagnostic | None:
    """The alarm that stopped the program (not a failed verification under strict)."""
    return next(
        (d for d in result.diagnostics if d.severity is Severity.ERROR and family(d.code) != "verification"), None
    )


def plan_to_gcode(
    result: Any,
    *,
    flavor: GcodeFlavor,
    dialect: str | None = None,
    decimals: int = 4,
    arc_tolerance_mm: float = 0.002,
    fit_tolerance_mm: float = 0.001,
    poly_output: str = "arcs",
    program_name: str | None = None,
) -> str:
    """Safe tool-centre G-code of a :class:`trcopt.pipeline.PlanResult` (see the module docstring).

    ``flavor``: the output controller's (``trcopt.controllers.get(name).gcode``); ``dialect``: the
    dialect that controller reads (``controllers.get(name).dialect``; by default the flavour's
    name, ``rs274`` for ``linuxcnc``) — the program's words are written as they are when it is the
    program's, else only the portable ones; ``decimals``: decimals of coordinates in mm (one more
    in inch); the tolerances are in mm whatever the output unit; the other parameters as
    :func:`trcopt.io.gcode.toolpath_to_gcode`'s. The text of :func:`plan_to_gcode_chunks` joined.
    """
    return "".join(
        plan_to_gcode_chunks(
            result, flavor=flavor, dialect=dialect, decimals=decimals, arc_tolerance_mm=arc_tolerance_mm,
            fit_tolerance_mm=fit_tolerance_mm, poly_output=poly_output, program_name=program_name,
        )
    )


GCODE_CHUNK_SEGMENTS = 4096  # segments written between two pieces of :func:`plan_to_gcode_chunks`


def plan_to_gcode_chunks(
    result: Any,
    *,
    flavor: GcodeFlavor,
    dialect: str | None = None,
    decimals: int = 4,
    arc_tolerance_mm: float = 0.002,
    fit_tolerance_mm: float = 0.001,
    poly_output: str = "arcs",
    program_name: str | None = None,
) -> Iterator[str]:
    """:func:`plan_to_gcode` in pieces of text (for a streamed, atomic write:
    :func:`trcopt.io.atomic.write_chunks_atomic`); the pieces joined are its text.

    ``flavor``: the output controller's (``trcopt.controllers.get(name).gcode``); ``dialect``: the
    dialect that controller reads (``controllers.get(name).dialect``; by default the flavour's
    name, ``rs274`` for ``linuxcnc``) — the program's words are written as they are when it is the
    program's, else only the portable ones; ``decimals``: decimals of coordinates in mm (one more
    in inch); the tolerances are in mm whatever the output unit; the other parameters as
    :func:`trcopt.io.gcode.toolpath_to_gcode`'s.
    """
    same = (dialect or _FLAVOR_DIALECT.get(flavor.name, flavor.name)) == result.dialect
    lines = TextLines(result.source)  # type: ignore[assignment]
    # a path kept in a file (a plan made window by window) is read from it, never held whole
    segs: Sequence[Segment] = result.toolpath if isinstance(result.toolpath, SpilledSegments) else list(result.toolpath)
    inch, feed_inch = program_units(result.source, result.dialect, segs[0].span.line if segs else None)
    preamble = list(flavor.preamble)
    if inch:
        k = 1.0 / INCH_MM
        segs = _Scaled(segs, k, k if feed_inch else 1.0)
        siemens_word = "G700" if feed_inch else "G70"  # G70: feeds stay in mm/min
        preamble = [
            p if p not in _INCH_PREAMBLE else siemens_word if flavor.name == "siemens" else _INCH_PREAMBLE[p]
            for p in preamble
        ]
        decimals = min(MAX_DECIMALS, int(decimals) + 1)
        arc_tolerance_mm, fit_tolerance_mm = arc_tolerance_mm * k, fit_tolerance_mm * k
    w = open_writer(
        segs,
        flavor=flavor,
        decimals=decimals,
        arc_tolerance_mm=arc_tolerance_mm,
        program_name=program_name or result.program,
        fit_tolerance_mm=fit_tolerance_mm,
        poly_output=poly_output,
        preamble=preamble,
        header=[f"units: {'inch' if inch else 'mm'}, the program's words in order, each block names its source"],
    )
    if segs:
        # the path starts where the reader started the program (the machine origin of a LinuxCNC
        # program with work offsets, say): no move is written to get there
        w.assumed = segs[0].start_xyz
    pending = _groups(result, flavor, same, lines)
    current: _Group | None = None  # the group of the source line whose motions are being written
    line = 0
    written, yielded = 0, False

    def flush(g: _Group, before: bool, after: bool) -> None:
        for text in g.remarks if before else ():
            w.lines.append(w.comment(f"{g.source}: {text}"))
        for text in g.comments if before else ():
            # a LinuxCNC message is a comment starting with "MSG,"
            w.lines.append(w.comment(text if text.startswith("MSG,") else f"{g.source} {text}"))
        words = (g.before if before else []) + (g.after if after else [])
        if words:
            w.emit(words, g.source)

    if _in_run_order(result):
        _write_in_run_order(w, result, segs, _move_groups(result, flavor, same, lines), flush, lines, inch)
        pending = []
        segs = []
    for seg in segs:
        if seg.span.line > line:
            line = seg.span.line
            if current is not None:
                flush(current, False, True)
                current = None
            while pending and pending[0].line < line:
                flush(pending.pop(0), True, True)
            if pending and pending[0].line == line:
                current = pending.pop(0)
                flush(current, True, False)
            text = _COMMENTS.sub(" ", lines[line - 1]) if 0 < line <= len(lines) else ""
            w.programmed = frozenset("XYZ".index(m.group(1).upper()) for m in _AXIS.finditer(text))
        if seg.span.machine is not None and isinstance(seg.geometry, Line) and flavor.name in _MACHINE_WORDS:
            _write_machine(w, seg, flavor, 1.0 / INCH_MM if inch else 1.0)
        else:
            write_segment(w, seg)
        written += 1
        if written % GCODE_CHUNK_SEGMENTS == 0 and w.lines:
            yield "\n".join(w.lines) + "\n"
            del w.lines[:]
            yielded = True
    w.programmed = frozenset()
    if current is not None:
        flush(current, False, True)
    for g in pending:  # the lines after the last motion: their words, not their comments
        g.remarks = []
        flush(g, True, True)
    alarm = _stop(result)
    if alarm is None:
        w.emit([flavor.end])
    else:
        w.lines.append(w.comment(f"stopped by {alarm.format()}"))
        w.lines.append(w.comment(f"no {flavor.end}: the program did not end"))
    if w.lines or not yielded:
        yield "\n".join(w.lines) + "\n"
