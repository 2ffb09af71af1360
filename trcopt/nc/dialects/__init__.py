"""NC dialects: each turns program text into an :class:`~trcopt.nc.model.NcProgram`.

A dialect is anything with ``name`` and ``read(text) -> NcProgram`` built from
:class:`~trcopt.nc.interpret.ReadOptions` (see :class:`DialectReader`). :func:`detect_dialect`
guesses the dialect from the file name and the text.
"""

from __future__ import annotations

import re
from pathlib import PurePath
from typing import Protocol

from ..model import NcProgram

__all__ = ["DialectReader", "detect_dialect", "DIALECTS"]

DIALECTS = ("siemens", "heidenhain", "rs274")


class DialectReader(Protocol):
    """What ``read_program`` needs from a dialect: a name and ``read(text)``."""

    name: str

    def read(self, text: str) -> NcProgram: ...


_SIEMENS_EXT = {".mpf", ".spf"}
_HEIDENHAIN_EXT = {".h"}
_RS274_EXT = {".ngc"}
_BEGIN_PGM = re.compile(r"^\s*\d*\s*BEGIN\s+PGM\b", re.I | re.M)
# an RS274 comment: "(" at line start, after blank or after a number (Siemens writes AC(..),
# MSG(..), X=(..): always after a letter, '=' or an operator)
_PAREN_COMMENT = re.compile(r"(?:^|[\s0-9.])\([^)\n]*\)", re.M)
_STRING = re.compile(r'"[^"\n]*"')
_SEMICOLON_COMMENT = re.compile(r";[^\n]*")


def detect_dialect(text: str, filename: str | None = None) -> str:
    """Guess the dialect of a program.

    ``.mpf``/``.spf`` → ``"siemens"``; ``.h`` or a ``BEGIN PGM`` line → ``"heidenhain"``;
    ``.ngc`` or parenthesised comments → ``"rs274"``; otherwise ``"siemens"``. The file
    extension wins over the text.
    """
    ext = PurePath(filename).suffix.lower() if filename else ""
    if ext in _SIEMENS_EXT:
        return "siemens"
    if ext in _HEIDENHAIN_EXT:
        return "heidenhain"
    if ext in _RS274_EXT:
        return "rs274"
    if _BEGIN_PGM.search(text):
        return "heidenhain"
    # parentheses inside strings (MSG("…")) or ';' comments say nothing about the dialect
    code = _SEMICOLON_COMMENT.sub("", _STRING.sub('""', text))
    if _PAREN_COMMENT.search(code):
        return "rs274"
    return "siemens"
