"""The comments of a part program's line, as the tool-centre G-code keeps them.

* SINUMERIK: the text after the first ``;`` that is not inside a string (``MSG("a;b")``);
* RS274NGC (LinuxCNC): every ``( … )`` and the text after a ``;`` outside them — except the
  active comments (``(MSG, …)``, ``(DEBUG, …)``, ``(PRINT, …)``, ``(LOG…)``, ``(PROBE…)``,
  ``(ABORT, …)``), which the reader executes and the writer writes as what they are;
* Heidenhain Klartext: a comment block (``3 * - CONTOUR 80 X 50``) and the text after a ``;`` at
  a block's end (``12 Q1 = 80 ; width``).
"""

from __future__ import annotations

import re

__all__ = ["program_comments"]

_ACTIVE = re.compile(r"^\s*(MSG|DEBUG|PRINT|LOG\w*|PROBE\w*|ABORT)\b", re.I)
_HEIDENHAIN_STAR = re.compile(r"^\s*\d*\s*\*\s*-?\s*(.*)$")
_MARKERS = {"siemens": ";", "rs274": ";(", "heidenhain": ";*"}


def program_comments(text: str, dialect: str) -> list[str]:
    """The comments of the program line ``text`` in ``dialect`` (``siemens``, ``rs274``,
    ``heidenhain``; none for another dialect), stripped, empty ones left out."""
    markers = _MARKERS.get(dialect)
    if markers is None or not any(c in text for c in markers):
        return []
    if dialect == "heidenhain":
        star = _HEIDENHAIN_STAR.match(text)
        if star:
            return [star.group(1).strip()] if star.group(1).strip() else []
        return _after_semicolon(text)
    if dialect == "siemens":
        return _after_semicolon(text)
    out: list[str] = []
    depth_start = None
    for i, ch in enumerate(text):
        if depth_start is None and ch == ";":
            out.append(text[i + 1 :])
            break
        if ch == "(" and depth_start is None:
            depth_start = i + 1
        elif ch == ")" and depth_start is not None:
            body = text[depth_start:i]
            depth_start = None
            if not _ACTIVE.match(body):
                out.append(body)
    return [c.strip() for c in out if c.strip()]


def _after_semicolon(text: str) -> list[str]:
    """The text after the first ``;`` outside a string."""
    quoted = False
    for i, ch in enumerate(text):
        if ch == '"':
            quoted = not quoted
        elif ch == ";" and not quoted:
            rest = text[i + 1 :].strip()
            return [rest] if rest else []
    return []
