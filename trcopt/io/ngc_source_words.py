"""The words of an RS274NGC (LinuxCNC) block that the tool-centre G-code takes from the program text.

The LinuxCNC reader resolves some words into the path and keeps no trace of them in a move's
actions: the tool length offset (``G43 H…``, ``G43.1``, ``G43.2``, ``G49``), the work systems
(``G54`` … ``G59.3``), the axis offsets (``G92`` family, ``G52``) and the path-control mode
(``G61``, ``G61.1``, ``G64 P… Q…``). :func:`source_words` reads them from a block's text for the
writer (:mod:`trcopt.io.gcode_program`):

* the tool length offset is **written** as it is, where it acts: the tool-centre coordinates are
  those of the controlled point (the tool tip), so the controller must apply the same tool length
  — without it a tool would run its length too deep;
* a work system or an axis offset becomes a **comment**: the coordinates written are already in the
  work system in force at the program start (the reader adds the offsets into them), so the word
  written again would shift the path a second time;
* a path-control word goes with the program's others (a comment: its rounding is in the path).

LinuxCNC ignores spaces and case outside comments (``g 4 3 h 2`` is ``G43 H2``); a word whose
value is an expression or a parameter (``H#1``, ``H[#1+1]``) is not evaluated here: it is named in
a comment instead.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

__all__ = ["source_words", "resolved_lines"]

_COMMENT = re.compile(r"\([^)]*\)|;.*$")
_WORD = re.compile(r"([A-Z])([-+]?(?:\d+\.?\d*|\.\d+)|\[|#)")
_AXES = "XYZABCUVW"
_TOOL_LENGTH = {"43", "43.1", "43.2", "49"}
_SYSTEMS = {"54", "55", "56", "57", "58", "59", "59.1", "59.2", "59.3"}
_OFFSETS = {"92", "92.1", "92.2", "92.3", "52"}
_PATH_CONTROL = {"61", "61.1", "64"}


_CANDIDATE = re.compile(r"G\s*0*(?:4[39]|5[2-9]|92|6[14])(?![0-9])", re.I)  # before the exact look
_END = re.compile(r"(?<![A-Z_<#])M\s*0*(?:2|30)(?![\d.])", re.I)
_FLOW = re.compile(r"^\s*/?\s*(?:N\s*\d+\s*)?O\s*[\d<]", re.I)


def resolved_lines(lines: Iterable[str], last: int | None = None) -> list[int]:
    """The lines (1-based, up to ``last`` and the program end ``M2``/``M30``) with a word
    :func:`source_words` reads, in a program that runs every line in order: none when the program
    has o-word flow (``o100 if``, ``sub``, ``while`` …), whose blocks a scan of the text cannot tell
    run from skipped."""
    found: list[int] = []
    for n, text in enumerate(lines, 1):
        if last is not None and n > last:
            break
        if _FLOW.match(text):
            return []
        code = _COMMENT.sub("", text)
        if _CANDIDATE.search(code) and any(source_words(text)):
            found.append(n)
        if _END.search(code):
            break
    return found


def _number(text: str) -> str:
    """``43.10`` → ``43.1``, ``049`` → ``49``: a G number as LinuxCNC reads it."""
    value = float(text)
    return f"{value:g}"


def _words(text: str) -> list[tuple[str, str]]:
    """``(letter, value)`` of a block without comments and spaces, upper case; an expression or a
    parameter as value is ``"?"``."""
    code = re.sub(r"\s+", "", _COMMENT.sub("", text)).upper()
    if code.startswith("/"):
        code = code[1:]
    if code.startswith("O"):
        return []  # an o-word block (sub, call, if, while …) carries no G code of these
    out: list[tuple[str, str]] = []
    for m in _WORD.finditer(code):
        value = m.group(2)
        out.append((m.group(1), "?" if value in ("[", "#") else value))
    return out


def source_words(text: str, actions: tuple[str, ...] | list[str] = ()) -> tuple[list[str], list[str]]:
    """``(actions, comments)`` of the RS274NGC block ``text`` the reader does not keep itself.

    ``actions``: words to add to the block's actions (the tool length offset, written as it is,
    and the path-control word, which the writer turns into its comment); ``comments``: the work
    systems and axis offsets the coordinates already hold, and a tool length word whose value is
    not a number. Words already among the move's ``actions`` are left out.
    """
    words = _words(text)
    gs = [v for k, v in words if k == "G" and v != "?"]
    gs = [_number(v) for v in gs]
    kept = {a.split()[0].upper() for a in actions if a.strip()}
    add: list[str] = []
    notes: list[str] = []
    values = {k: v for k, v in words if k != "G"}
    for g in gs:
        word = f"G{g}"
        if word in kept:
            continue
        if g in _TOOL_LENGTH:
            extra: list[str] = []
            if g in ("43", "43.2") and "H" in values:
                extra.append(f"H{values['H']}")
            if g in ("43.1", "43.2"):
                extra += [f"{k}{v}" for k, v in words if k in _AXES]
            block = " ".join([word, *extra])
            if "?" in block:
                notes.append(f"tool length offset {word} with a computed value: not written, set it by hand")
            else:
                add.append(block)
        elif g in _SYSTEMS:
            notes.append(f"work system {word}: its offset is in the coordinates (those of the start's work system)")
        elif g in _OFFSETS:
            notes.append(f"axis offset {word}: its offset is in the coordinates")
        elif g in _PATH_CONTROL:
            extra = [f"{k}{v}" for k, v in words if k in "PQ" and v != "?"] if g == "64" else []
            add.append(" ".join([word, *extra]))
    return add, notes
