"""Plain tool-centre G-code (G40 only) for controllers without radius compensation.

One output block per segment: ``G0`` for rapids, ``G1`` for lines, ``G2``/``G3`` for arcs and
helices (centre words I/J/K incremental from the start point). A smooth curve (:class:`Poly`:
corner transitions, splines, lead curves) is written as a tangent-continuous chain of arcs and
lines within ``fit_tolerance_mm`` of it (:func:`trcopt.geometry.arcfit.fit_arcs`), preceded once
by the flavour's continuous-path words (LinuxCNC ``G64 P…``, SINUMERIK ``CTOL=…`` and ``G642``)
so that the controller does not stop between the pieces; ``poly_output="chords"`` writes the
curve as ``G1`` chords through its samples instead. Every block names its source in a comment
(``; N60 L6 corner`` for Siemens, ``(N60 L6 corner)`` for RS274/LinuxCNC); the pieces of one
segment name it on the first block only.

Arcs are re-checked **after rounding**, with the numbers the controller will read: the start is
the position last written, the end the rounded end, the centre the start plus the rounded
centre offset. If the two radii differ by more than ``arc_tolerance_mm / 2`` the centre is moved
onto the perpendicular bisector of the rounded chord (the point of the bisector nearest the exact
centre, so sense and side are kept), rounded and checked again; if that still fails the block is
written with more decimals (up to 6); an arc that cannot be made consistent even then (too
short/flat) is written as ``G1``. :func:`check_gcode_arcs` is an independent re-reader of the
programs this module writes.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from trcopt.codes import Code
from trcopt.errors import TrcoptError
from trcopt.geometry import vec
from trcopt.geometry.plane import Plane
from trcopt.geometry.poly import Poly
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec3
from trcopt.io.gcode_check import check_gcode_arcs
from trcopt.path import Role, Segment
from trcopt.units import mm_s_to_mm_min

__all__ = ["GcodeError", "GcodeFlavor", "toolpath_to_gcode", "check_gcode_arcs", "open_writer", "write_segment"]

MAX_DECIMALS = 6
POLY_OUTPUTS = ("arcs", "chords")


# centre word letter for each workpiece axis (x, y, z)
_CENTRE_WORDS = ("I", "J", "K")
# an arc is written with more decimals (up to MAX_DECIMALS) until its start and end radius as read
# back agree within this, mm: re-reading the output then gives a path without gaps
ARC_CONSISTENT_MM = 5e-7


class GcodeError(TrcoptError, ValueError):
    """Invalid writer option or a segment that cannot be written."""

    def __init__(self, message: str, code: str = Code.GCODE) -> None:
        super().__init__(message, None, code)


@dataclass(frozen=True, slots=True)
class GcodeFlavor:
    """How one controller family writes plain G-code; each controller defines its own.

    Parameters
    ----------
    name:
        Name shown in messages (the controller's).
    paren_comments:
        Comments as ``( … )`` (RS274NGC; parentheses inside become brackets) instead of ``; …``.
    block_numbers:
        Number the blocks N10, N20, ….
    decimal_point:
        Every number keeps a decimal point (``5.0``; RS274NGC reads ``5`` as ``5.0`` too, but
        the written form is unambiguous for every ISO reader).
    preamble:
        Modal words of the first block, before the plane word (units, absolute, feed per minute,
        incremental arc centres, compensation off).
    end:
        The program end word.
    continuous_path:
        Blocks that switch to continuous-path mode with a contour tolerance, written once after
        the preamble block when a smooth curve is written as arcs; ``{tol}`` in a block is
        replaced by the fit tolerance (mm). Empty: no such words are written.
    """

    name: str
    paren_comments: bool
    block_numbers: bool
    decimal_point: bool
    preamble: tuple[str, ...]
    end: str
    continuous_path: tuple[str, ...] = ()
    #: the non-motion words (regular expression, whole word) this flavour reads when the program is
    #: in another dialect; the others become comments. None: tool call and change, M functions,
    #: spindle speed and the work offsets G54–G59
    portable_words: str | None = None
    #: the words written for a tool change (``M6``) on a controller without a tool changer (spindle
    #: stop and program stop, so that the operator changes the tool by hand), None: none
    manual_tool_change: str | None = None

    def comment(self, text: str) -> str:
        """``text`` as one comment of this flavour."""
        if self.paren_comments:
            return f"({_rs274_comment_text(text)})"
        return "; " + text.replace("\n", " ").replace("\r", " ")


def _fmt(value: float, decimals: int, flavor: GcodeFlavor) -> str:
    """Fixed-point number without trailing zeros; RS274 keeps a decimal point (``5.0``)."""
    text = f"{value:.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    if text in ("-0", ""):
        text = "0"
    if flavor.decimal_point and "." not in text:
        text += ".0"
    return text


def _round(value: float, decimals: int) -> float:
    """The value the controller reads from the written word."""
    return float(f"{value:.{decimals}f}") + 0.0


def _rs274_comment_text(text: str) -> str:
    # RS274NGC comments cannot contain parentheses; keep them on one line
    return text.replace("(", "[").replace(")", "]").replace("\n", " ").replace("\r", " ")


@dataclass
class _Writer:
    flavor: GcodeFlavor
    decimals: int
    tolerance: float
    lines: list[str]
    pos: list[float | None]  # modal position as written (rounded), x y z
    feed: float | None = None  # last written feed, mm/min
    plane: Plane | None = None
    number: int = 0
    fit_tolerance: float = 0.001  # largest distance of the written arcs from a Poly, mm
    poly_output: str = "arcs"
    # where a program starts (the readers' start point): an axis the program has not moved yet
    # stays unwritten (None) until it moves or its source block names it
    assumed: tuple[float, float, float] = (0.0, 0.0, 0.0)
    programmed: frozenset[int] = frozenset()  # axes (0 1 2) the current source block writes
    started: bool = False

    # -- block assembly -------------------------------------------------------------------------
    def comment(self, text: str) -> str:
        return self.flavor.comment(text)

    def emit(self, words: list[str], note: str | None = None) -> None:
        parts = list(words)
        if self.flavor.block_numbers:
            self.number += 10
            parts.insert(0, f"N{self.number}")
        line = " ".join(parts)
        if note:
            line += " " + self.comment(note)
        self.lines.append(line)

    def num(self, value: float, decimals: int | None = None) -> str:
        return _fmt(value, self.decimals if decimals is None else decimals, self.flavor)

    def feed_word(self, feed_mm_s: float | None) -> list[str]:
        if feed_mm_s is None:
            return []
        f = _round(mm_s_to_mm_min(feed_mm_s), 3)
        if self.feed is not None and f == self.feed:
            return []
        self.feed = f
        return [f"F{_fmt(f, 3, self.flavor)}"]

    def axis_words(self, xyz: Vec3, decimals: int, force: Sequence[int] = ()) -> list[str]:
        """Words for the axes whose rounded value differs from the modal position (or forced)."""
        words = []
        for i, name in enumerate("XYZ"):
            r = _round(xyz[i], decimals)
            if self.pos[i] is None and i not in force and i not in self.programmed:
                if r == _round(self.assumed[i], decimals):
                    continue  # not moved by the program yet: the machine's position is kept
            if self.pos[i] is None or r != self.pos[i] or i in force:
                words.append(f"{name}{self.num(xyz[i], decimals)}")
                self.pos[i] = r
        return words

    def plane_words(self, plane: Plane) -> list[str]:
        if plane is self.plane:
            return []
        self.plane = plane
        return [plane.value]

    # -- motions --------------------------------------------------------------------------------
    def here(self) -> list[float]:
        """The written position, the start point for axes not written yet."""
        return [self.assumed[i] if c is None else float(c) for i, c in enumerate(self.pos)]

    def straight(self, g: str, end: Vec3, feed_mm_s: float | None, note: str | None) -> bool:
        digits = self.decimals
        if g != "G0":
            here = self.here()
            length = math.dist(here, end)
            if length < 0.5 * 10.0**-self.decimals:
                # shorter than the output resolution (a sliver between two transitions): the
                # written position is the end point to the digits written
                return False
            if length < 100.0 * 10.0**-self.decimals:
                # a short line between transitions keeps its direction: written to more digits
                digits = MAX_DECIMALS
        axes = self.axis_words(end, digits)
        if not axes:
            return False
        words = [g, *axes]
        if g != "G0":
            words += self.feed_word(feed_mm_s)
        self.emit(words, note)
        return True


def _source_note(seg: Segment) -> str:
    parts = []
    if seg.span.block:
        parts.append(str(seg.span.block))
    if seg.span.line:
        parts.append(f"L{seg.span.line}")
    parts.append(seg.role.value)
    return " ".join(parts)


def _split_arc(arc: Arc, pieces: int) -> list[Arc]:
    return [arc.sub(k / pieces, (k + 1) / pieces) for k in range(pieces)]


def _arc_block(
    w: _Writer, plane: Plane, arc: Arc, feed_mm_s: float | None, note: str | None, depth: int = 0
) -> bool:
    """Write one arc piece (|sweep| < 360°) with the after-rounding check; True if written."""
    ui, vi, wi = plane.axes
    end_xyz = plane.to_xyz(arc.end)
    start_xyz = plane.to_xyz(arc.start)
    # the controller starts where the last block ended (as written)
    s_xyz = [known if known is not None else _round(start_xyz[i], w.decimals) for i, known in enumerate(w.pos)]
    s_u, s_v = s_xyz[ui], s_xyz[vi]
    cu, cv = arc.center
    sense = 1 if arc.sweep > 0 else -1
    tol_half = w.tolerance / 2.0

    if arc.plane_length < 10.0**-w.decimals:
        # shorter than the output resolution: a straight move is exact to the written digits
        return w.straight("G1", end_xyz, feed_mm_s, note)
    for d in range(w.decimals, MAX_DECIMALS + 1):
        e_u, e_v = _round(end_xyz[ui], d), _round(end_xyz[vi], d)
        chord = math.hypot(e_u - s_u, e_v - s_v)
        if chord == 0.0:
            continue
        # and the nearest point of the perpendicular bisector of the rounded chord to the exact centre
        candidates = [(cu, cv), vec.bisector_foot((s_u, s_v), (e_u, e_v), (cu, cv))]
        unit = 10.0**-d
        tries: list[tuple[int, float, float, float, float, float]] = []  # (mismatch/nm, shift, I, J, r0, mismatch)
        for c_u, c_v in candidates:
            # the written centres around the rounded one: the one nearest the bisector makes the
            # start and end radius of the arc as read back agree as well as the digits allow
            i0, j0 = _round(c_u - s_u, d), _round(c_v - s_v, d)
            for di in (-2, -1, 0, 1, 2):
                for dj in (-2, -1, 0, 1, 2):
                    i_try, j_try = _round(i0 + di * unit, d), _round(j0 + dj * unit, d)
                    r0 = math.hypot(i_try, j_try)
                    if r0 > 0.0:
                        r1 = math.hypot(e_u - s_u - i_try, e_v - s_v - j_try)
                        mismatch = abs(r0 - r1)
                        # equal mismatches (to a nanometre): the centre nearest the exact one
                        shift = math.hypot(s_u + i_try - cu, s_v + j_try - cv)
                        tries.append((math.floor(mismatch * 1e9), shift, i_try, j_try, r0, mismatch))
        tries.sort()
        found = next(
            (t for t in tries if _intended(arc, s_u + t[2], s_v + t[3], t[4], s_u, s_v, e_u, e_v, sense, w)), None
        )
        chosen = None if found is None else (found[5], found[2], found[3], found[4])
        limit = tol_half if d == MAX_DECIMALS else min(tol_half, ARC_CONSISTENT_MM)
        if chosen is not None and chosen[0] <= limit:
            i_off, j_off = chosen[1], chosen[2]
            words = w.plane_words(plane)
            words.append("G3" if sense > 0 else "G2")
            force = (ui, vi)
            words += w.axis_words(end_xyz, d, force=force)
            offs = {ui: i_off, vi: j_off}
            words += [f"{_CENTRE_WORDS[k]}{w.num(offs[k], d)}" for k in sorted(offs)]
            words += w.feed_word(feed_mm_s)
            w.emit(words, note)
            return True
    # cannot be written consistently: a nearly closed arc is split, a short/flat one becomes G1
    if abs(arc.sweep) > math.pi / 2 and depth < 4:
        first, second = _split_arc(arc, 2)
        done = _arc_block(w, plane, first, feed_mm_s, note, depth + 1)
        return _arc_block(w, plane, second, feed_mm_s, None if done else note, depth + 1) or done
    return w.straight("G1", end_xyz, feed_mm_s, note)


def _intended(
    arc: Arc, rc_u: float, rc_v: float, r0: float, s_u: float, s_v: float, e_u: float, e_v: float, sense: int,
    w: _Writer,
) -> bool:
    """Whether the arc the controller reads (centre ``rc``, radius ``r0``, from the written start to
    the written end in the sense of ``arc``) is the intended one: its points stay within the position
    rounding (plus the tolerance) of ``arc``, and a nearly closed arc does not wrap."""
    a0 = math.atan2(s_v - rc_v, s_u - rc_u)
    a1 = math.atan2(e_v - rc_v, e_u - rc_u)
    sweep = (a1 - a0) % (2 * math.pi) if sense > 0 else -((a0 - a1) % (2 * math.pi))
    if sweep == 0.0:
        return False
    slack = w.tolerance + 10.0**-w.decimals
    return all(
        arc.distance2((rc_u + r0 * math.cos(a0 + f * sweep), rc_v + r0 * math.sin(a0 + f * sweep))) <= slack
        for f in (0.25, 0.5, 0.75)
    )


def _close_gap(w: _Writer, seg: Segment, note: str) -> None:
    """A straight move to the segment's start when the path has a gap there, so that an arc
    starts where it was planned."""
    start = seg.start_xyz
    if math.dist(w.here(), start) > max(w.tolerance, 10.0**-w.decimals):
        w.straight("G1", start, seg.feed_mm_s, f"gap before {note}")


def _write_poly_arcs(w: _Writer, seg: Segment, g: Poly, note: str | None) -> None:
    """A smooth curve as its arc fit: G2/G3 for the arcs, G1 for the lines."""
    from trcopt.geometry.arcfit import fit_arcs  # numpy: loaded only when a curve is written

    if note is not None:
        _close_gap(w, seg, note)
    for piece in fit_arcs(g, w.fit_tolerance):
        if isinstance(piece, Arc):
            written = _arc_block(w, seg.plane, piece, seg.feed_mm_s, note)
        else:
            written = w.straight("G1", seg.plane.to_xyz(piece.end), seg.feed_mm_s, note)
        if written:
            note = None  # name the source once, on the first piece


def write_segment(w: _Writer, seg: Segment) -> None:
    """Write one segment of the tool-centre path."""
    g = seg.geometry
    note: str | None = _source_note(seg)
    plane = seg.plane
    if not w.started:
        w.started = True
        if math.dist(seg.start_xyz, w.assumed) > 1e-9:
            # a path that does not start where a program starts (a hand-built or cut-out path):
            # a rapid to its start point
            programmed, w.programmed = w.programmed, frozenset((0, 1, 2))
            w.straight("G0", seg.start_xyz, None, f"start of path, {note}")
            w.programmed = programmed
    if isinstance(g, Line):
        w.straight("G0" if seg.is_rapid else "G1", seg.end_xyz, seg.feed_mm_s, note)
        return
    if isinstance(g, Poly):
        if w.poly_output == "arcs" and not seg.is_rapid:
            _write_poly_arcs(w, seg, g, note)
            return
        for p in g.points[1:]:
            if w.straight("G0" if seg.is_rapid else "G1", plane.to_xyz(p), seg.feed_mm_s, note):
                note = None  # name the source once, on the first chord
        return
    if isinstance(g, Arc):
        if note is not None:
            _close_gap(w, seg, note)
        span = abs(g.sweep)
        pieces = 1 if span < 2 * math.pi - 1e-12 else max(2, math.ceil(span / math.pi - 1e-9))
        for piece in _split_arc(g, pieces) if pieces > 1 else [g]:
            if _arc_block(w, plane, piece, seg.feed_mm_s, note):
                note = None
        return
    raise GcodeError(f"cannot write segment geometry {type(g).__name__}")


def toolpath_to_gcode(
    segments: Iterable[Segment],
    *,
    flavor: GcodeFlavor,
    decimals: int = 4,
    arc_tolerance_mm: float = 0.002,
    program_name: str = "trcopt",
    fit_tolerance_mm: float = 0.001,
    poly_output: str = "arcs",
) -> str:
    """Plain tool-centre G-code (G40 only) for the tool-centre path ``segments``.

    Parameters
    ----------
    segments:
        Tool-centre path in execution order (absolute workpiece coordinates, mm).
    flavor:
        The controller's flavour (``trcopt.controllers.get(name).gcode``): SINUMERIK writes ``;``
        comments, N10/N20… block numbers, G71 and M30; LinuxCNC parenthesised comments, G21,
        G91.1 incremental centres and M2.
    decimals:
        Decimals of coordinates (mm); arcs may get more (up to 6) when the rounded numbers would
        not describe a consistent arc.
    arc_tolerance_mm:
        Largest difference between start and end radius the controller will accept, mm; the
        writer keeps its own arcs within half of it.
    program_name:
        Name of the source program, written in the header comment.
    fit_tolerance_mm:
        Largest distance (mm) between a smooth curve and the arcs written for it (both ways,
        before rounding to ``decimals``); also the contour tolerance of the continuous-path words.
    poly_output:
        ``"arcs"``: a smooth curve as a tangent-continuous chain of G2/G3 arcs and G1 lines, with
        the flavour's continuous-path words once after the preamble; ``"chords"``: as G1 chords
        through its samples (≤ 1 µm chord error), without those words.

    Returns
    -------
    str
        The program text, one block per line, ending with a newline.
    """
    segs = list(segments)
    w = open_writer(
        segs,
        flavor=flavor,
        decimals=decimals,
        arc_tolerance_mm=arc_tolerance_mm,
        program_name=program_name,
        fit_tolerance_mm=fit_tolerance_mm,
        poly_output=poly_output,
    )
    for seg in segs:
        write_segment(w, seg)
    w.emit([flavor.end])
    return "\n".join(w.lines) + "\n"


def open_writer(
    segs: Sequence[Segment],
    *,
    flavor: GcodeFlavor,
    decimals: int,
    arc_tolerance_mm: float,
    program_name: str,
    fit_tolerance_mm: float,
    poly_output: str,
    preamble: Sequence[str] = (),
    header: Sequence[str] = (),
) -> _Writer:
    """A writer with the header comments, the preamble block (``preamble`` instead of the
    flavour's when given) and the continuous-path words written; ``header``: more comment lines."""
    if not isinstance(flavor, GcodeFlavor):
        raise GcodeError(f"invalid G-code flavor {flavor!r}: a GcodeFlavor (trcopt.controllers.get(name).gcode)")
    if not 0 <= int(decimals) <= MAX_DECIMALS:
        raise GcodeError(f"decimals must be in 0..{MAX_DECIMALS}, got {decimals}")
    if not arc_tolerance_mm > 0.0:
        raise GcodeError(f"arc_tolerance_mm must be > 0, got {arc_tolerance_mm}")
    fit_tol = _fit_tolerance(fit_tolerance_mm)
    if poly_output not in POLY_OUTPUTS:
        raise GcodeError(f"invalid poly_output {poly_output!r}; valid: {', '.join(POLY_OUTPUTS)}")
    w = _Writer(flavor, int(decimals), float(arc_tolerance_mm), [], [None, None, None])
    w.fit_tolerance, w.poly_output = fit_tol, poly_output
    w.lines.append(w.comment(f"trcopt tool-centre path of {program_name}"))
    w.lines.append(w.comment("G40 only: coordinates are the tool centre, no radius compensation"))
    w.lines.extend(w.comment(text) for text in header)

    def curve_as_arcs(s: Segment) -> bool:
        return poly_output == "arcs" and isinstance(s.geometry, Poly) and not s.is_rapid

    def transition(s: Segment) -> bool:
        return curve_as_arcs(s) or (s.role is Role.CORNER and isinstance(s.geometry, Arc) and not s.is_rapid)

    # a path with transitions (curves as arc chains, circular blends) is tangent-continuous where
    # the digits written leave kinks: the controller must not stop there
    curves = any(transition(s) for s in segs)
    # the plane of the first arc (a curve written as arcs counts) goes into the preamble
    first = next((s for s in segs if isinstance(s.geometry, Arc) or curve_as_arcs(s)), segs[0] if segs else None)
    w.plane = first.plane if first is not None else Plane.G17
    w.emit([*(preamble or flavor.preamble), w.plane.value])
    if curves:
        # the curves become chains of short tangent-continuous pieces: no stop between them
        tol_text = _fmt(fit_tol, min(15, max(MAX_DECIMALS, 2 - math.floor(math.log10(fit_tol)))), flavor)
        for block in flavor.continuous_path:
            w.emit([block.format(tol=tol_text)])
    return w


def _fit_tolerance(value: object) -> float:
    try:
        tol = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise GcodeError(f"fit_tolerance_mm must be a positive finite length in mm, got {value!r}") from None
    if isinstance(value, bool) or not (tol > 0.0 and math.isfinite(tol)):
        raise GcodeError(f"fit_tolerance_mm must be a positive finite length in mm, got {value!r}")
    return tol

