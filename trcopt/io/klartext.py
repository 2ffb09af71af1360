"""Tool-centre Heidenhain Klartext (conversational) of a Heidenhain plan.

A TNC runs ISO programs only with the DIN/ISO option, and reads the circle centre ``I, J`` there
as an absolute position (``CC``); the conversational form is what every TNC runs.
:func:`plan_to_klartext` writes the plan of a Heidenhain program as such a program, from the ISO
tool-centre program of :func:`~trcopt.io.gcode_program.plan_to_gcode` (so the arcs keep that
writer's after-rounding consistency and the program's words their places):

* ``BEGIN PGM name MM|INCH`` … ``END PGM``; the program's ``TOOL DEF`` blocks first, its
  ``TOOL CALL`` and ``STOP`` blocks as written, at their place;
* a straight move ``L X… Y… Z… R0 F…`` (``FMAX`` for a rapid); an arc ``CC`` (its centre, absolute)
  and ``C X… Y… DR± R0``; a helix ``CC`` and ``CP IPA± IZ± DR± R0`` (Klartext has no Cartesian
  helix); every move with ``R0`` — the coordinates are the tool centre;
* M functions on the motion blocks: those that act at the block start (``M3``, ``M8`` …) on the next
  move, those that act at its end (``M0``, ``M1``, ``M5``, ``M9``) on the previous one;
* the program's flow (``LBL``, ``CALL LBL``, ``FN``, Q parameters), its coordinate transformations
  (``CYCL DEF 7/8/10/11/26``) and its path-control tolerance (``CYCL DEF 32``) are already in the
  path: not written again;
* every move that starts a source element names it in a comment at the block end
  (``L X+10 R0 F800 ; 24 L25 approach``: the source block number, its line and the element's role),
  as the ISO writer does; the further pieces of one element follow it without one;
* a program stopped by an alarm ends with a comment naming it and a ``STOP`` block.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

from trcopt.io.gcode import GcodeError, GcodeFlavor
from trcopt.io.gcode_program import plan_to_gcode

__all__ = ["plan_to_klartext"]

_AT_END = {"M0", "M1", "M2", "M5", "M9", "M30"}
_NUMBERED = re.compile(r"^\s*N\d+\s+")
_SOURCE = re.compile(r"\bL(\d+)\b")
_WORD = re.compile(r"([A-Z]+)([-+]?\d*\.?\d+(?:[eE][-+]?\d+)?)?")
_STATEMENT = re.compile(r"^\s*\d+\s+(TOOL DEF|TOOL CALL|STOP)\b", re.I)
_ISO = GcodeFlavor(
    name="heidenhain", paren_comments=False, block_numbers=True, decimal_point=False,
    preamble=("G71", "G90", "G94", "G40"), end="M30",
)  # fmt: skip
_PLANE_AXES = {"G17": ("X", "Y", "Z"), "G18": ("Z", "X", "Y"), "G19": ("Y", "Z", "X")}
_CENTRE = {"X": "I", "Y": "J", "Z": "K"}
_MODAL = {"G70", "G71", "G90", "G94", "G40", "G17", "G18", "G19"}


def _num(axis: str, value: float, decimals: int) -> str:
    text = f"{abs(value):.{decimals}f}".rstrip("0").rstrip(".") or "0"
    return f"{axis}{'-' if value < 0 and text != '0' else '+'}{text}"


class _Out:
    def __init__(self, decimals: int) -> None:
        self.blocks: list[str] = []
        self.notes: dict[int, str] = {}  # block index → the comment at its end (the source it comes from)
        self.decimals = decimals
        self.pending: list[str] = []  # M functions for the next move
        self.last_move: int | None = None  # index of the last move block

    def add(self, text: str, move: bool = False, note: str = "") -> None:
        if move and self.pending:
            text = f"{text} {' '.join(self.pending)}"
            self.pending = []
        self.blocks.append(text)
        if note:
            self.notes[len(self.blocks) - 1] = note
        if move:
            self.last_move = len(self.blocks) - 1

    def text(self) -> str:
        """The numbered blocks, each with its comment at the end."""
        lines = []
        for i, block in enumerate(self.blocks):
            note = self.notes.get(i)
            lines.append(f"{i} {block}" + (f" ; {note}" if note else ""))
        return "\n".join(lines) + "\n"

    def m_word(self, word: str) -> None:
        if word.upper() in _AT_END and self.last_move is not None:
            self.blocks[self.last_move] += f" {word}"
        else:
            self.pending.append(word)


def plan_to_klartext(result: Any, *, decimals: int = 4, program_name: str = "PGM") -> str:
    """The Klartext program of ``result`` (a plan of a Heidenhain program), see the module
    description. Raises :class:`~trcopt.io.gcode.GcodeError` for a plan of another dialect."""
    if getattr(result, "dialect", None) != "heidenhain":
        raise GcodeError("Klartext output is written for Heidenhain programs only (use --gcode-flavor grbl or ISO)")
    source = (result.source or "").splitlines()
    iso = plan_to_gcode(result, flavor=_ISO, dialect="heidenhain", decimals=decimals, program_name=program_name)
    name = re.sub(r"[^A-Za-z0-9_]", "_", Path(program_name).stem).upper() or "PGM"
    inch = any(re.match(r"\s*\d*\s*BEGIN\s+PGM\s+\S+\s+INCH\b", ln, re.I) for ln in source[:5])
    unit = "INCH" if inch else "MM"
    out = _Out(decimals)
    out.add(f"BEGIN PGM {name} {unit}")
    out.add(f"; trcopt tool-centre path of {program_name}: coordinates are the tool centre (R0)")
    for ln in source:
        m = _STATEMENT.match(ln)
        if m and m.group(1).upper() == "TOOL DEF":
            out.add(_body(ln))
    pos: dict[str, float] = {}
    plane = "G17"
    copied: set[int] = set()
    ended = False
    for raw in iso.splitlines():
        code, _, note = _NUMBERED.sub("", raw).partition(";")
        code, note = code.strip(), note.strip()
        if not code:
            if note and not note.startswith(("trcopt tool-centre", "G40 only", "units:")):
                out.add(f"; {note}")
            continue
        words = [(m.group(1).upper(), m.group(2)) for m in _WORD.finditer(code.upper())]
        letters = {k: v for k, v in words}
        gs = [f"G{int(float(v))}" for k, v in words if k == "G" and v is not None]
        if any(g in _PLANE_AXES for g in gs):
            plane = next(g for g in gs if g in _PLANE_AXES)
        motion = next((g for g in gs if g in ("G0", "G1", "G2", "G3")), None)
        if motion is None and len(gs) == len(words) and set(gs) <= _MODAL:
            continue  # the ISO preamble: units, absolute, feed per minute, no compensation, plane
        if motion is None:
            _words_block(out, words, note, source, copied)
            if any(k == "M" and v is not None and int(float(v)) in (2, 30) for k, v in words):
                ended = True
            continue
        # the ISO writer may give an arc more digits, so that it reads back consistently: keep them
        digits = max([decimals] + [len(v.partition(".")[2]) for _, v in words if v is not None and "." in v])
        _move(out, motion, letters, pos, plane, digits, note)
    if not ended and out.pending:
        out.add("STOP " + " ".join(out.pending))
        out.pending = []
    if not ended:
        out.add("STOP")
    out.add(f"END PGM {name} {unit}")
    return out.text()


def _body(line: str) -> str:
    """A source block without its block number."""
    return re.sub(r"^\s*\d+\s+", "", line).strip()


def _words_block(
    out: _Out, words: list[tuple[str, str | None]], note: str, source: list[str], copied: set[int]
) -> None:
    """A block of the ISO program without motion: the source's TOOL CALL or STOP block, the M
    functions on the moves, the program end, anything else as a comment."""
    m = _SOURCE.search(note)
    line = int(m.group(1)) if m else 0
    text = source[line - 1] if 0 < line <= len(source) else ""
    st = _STATEMENT.match(text)
    rest: list[str] = []
    for k, v in words:
        if k == "T" or (k == "S" and st is not None):
            continue
        if k == "M" and v is not None:
            word = f"M{int(float(v))}"
            if word in ("M2", "M30"):
                if out.pending:
                    out.add("STOP " + " ".join(out.pending))
                    out.pending = []
                if out.last_move is not None:
                    out.m_word(word)
                else:
                    out.add(f"STOP {word}")
                continue
            if word == "M0" and st is not None and st.group(1).upper() == "STOP":
                continue
            out.m_word(word)
            continue
        rest.append(f"{k}{v or ''}")
    if st is not None and line not in copied:
        copied.add(line)
        out.add(_body(text), note=note)
    if rest:
        out.add(f"; not written in Klartext: {' '.join(rest)} ({note})")


def _move(
    out: _Out, motion: str, w: dict[str, str | None], pos: dict[str, float], plane: str, d: int, note: str = ""
) -> None:
    feed = "FMAX" if motion == "G0" else (f"F{float(w['F']):g}" if w.get("F") else "")
    end = {a: float(w[a]) for a in "XYZ" if w.get(a) is not None}
    if motion in ("G0", "G1"):
        coords = " ".join(_num(a, end[a], d) for a in "XYZ" if a in end)
        out.add(" ".join(x for x in ("L", coords, "R0", feed) if x), move=True, note=note)
        pos.update(end)
        return
    u, v, axis = _PLANE_AXES[plane]
    if u not in pos or v not in pos:
        raise GcodeError("an arc before the position in its plane is known cannot be written in Klartext")
    cu = pos[u] + float(w.get(_CENTRE[u]) or 0.0)
    cv = pos[v] + float(w.get(_CENTRE[v]) or 0.0)
    eu, ev = end.get(u, pos[u]), end.get(v, pos[v])
    sense = "DR+" if motion == "G3" else "DR-"
    centre = {u: cu, v: cv}
    out.add("CC " + " ".join(_num(a, centre[a], d) for a in "XYZ" if a in centre))
    dz = end.get(axis, pos.get(axis, 0.0)) - pos.get(axis, 0.0) if axis in end else 0.0
    if abs(dz) > 0.5 * 10.0**-d:
        a0 = math.atan2(pos[v] - cv, pos[u] - cu)
        a1 = math.atan2(ev - cv, eu - cu)
        sweep = math.degrees(a1 - a0)
        if motion == "G3":
            sweep = sweep % 360.0 or 360.0
        else:
            sweep = -((-sweep) % 360.0 or 360.0)
        ipa = f"IPA{'+' if sweep >= 0 else '-'}{abs(sweep):.{max(d, 4)}f}".rstrip("0").rstrip(".")
        out.add(" ".join(x for x in ("CP", ipa, "I" + _num(axis, dz, d), sense, "R0", feed) if x), move=True, note=note)
    else:
        target = {u: eu, v: ev}
        coords = " ".join(_num(a, target[a], d) for a in "XYZ" if a in target)
        out.add(" ".join(x for x in ("C", coords, sense, "R0", feed) if x), move=True, note=note)
    pos.update(end)
