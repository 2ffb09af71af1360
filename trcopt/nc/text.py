"""Program files as text: the one decoding every reader's input goes through.

A part program is text: UTF-8 (with or without a byte-order mark), UTF-16 with its byte-order
mark, or a single-byte code page (read as Latin-1, so that every byte is a character and a column
is a byte). A file with NUL bytes (and no UTF-16 mark), or whose bytes are mostly control
characters, is not a program: :func:`decode_program` raises :class:`~trcopt.errors.TrcoptError`
with code ``NC-NOT-TEXT`` naming the file, instead of letting a reader report a syntax error at
some arbitrary byte.
"""

from __future__ import annotations

import codecs
import re

from trcopt.codes import Code
from trcopt.errors import SourceSpan, TrcoptError

__all__ = ["decode_program", "program_lines", "MAX_CONTROL_FRACTION"]

# share of control characters (other than tab, line feed, carriage return, form feed, Ctrl-Z) above
# which undecodable bytes are taken for a binary file rather than a code-page text
MAX_CONTROL_FRACTION = 0.05
_TEXT_CONTROLS = frozenset(b"\t\n\r\f\x1a")
_LINE_END = re.compile(r"\r\n|\r|\n")


def program_lines(text: str) -> list[str]:
    """The lines of a program as an editor numbers them: split at LF, CR LF and CR only.

    ``str.splitlines`` also splits at form feed, vertical tab, the file/group/record separators,
    NEL (U+0085, a byte 0x85 read as Latin-1) and U+2028/2029, which would shift every later line
    number away from what the user sees. A final line end does not start another line.
    """
    lines = _LINE_END.split(text)
    if lines and lines[-1] == "":
        lines.pop()
    return lines


_BLOCK_NUMBER = re.compile(rb"[ \t\f\v]*(N[0-9]+|[0-9]+)(?=[ \t\f\v]|$)", re.IGNORECASE)


def _byte_place(raw: bytes, offset: int, file: str) -> SourceSpan:
    """The place of byte ``offset`` as an editor shows it: line (LF, CR LF or CR ends a line),
    column (bytes from the line start, 1-based) and the line's block number (``N…`` or a
    Heidenhain number) when it starts with one."""
    head = raw[:offset]
    ends = [m.end() for m in re.finditer(rb"\r\n|\r(?!\n)|\n", head)]
    start = ends[-1] if ends else 0
    line_end = re.search(rb"\r|\n", raw[start:])
    text = raw[start : start + line_end.start()] if line_end else raw[start:]
    m = _BLOCK_NUMBER.match(text)
    block = m.group(1).decode("latin-1").upper() if m and m.end(1) <= offset - start else None
    return SourceSpan(file, len(ends) + 1, offset - start + 1, block)


def decode_program(raw: bytes, file: str) -> str:
    """The text of a program file's bytes ``raw``.

    Parameters
    ----------
    raw:
        The file's content.
    file:
        Its name, for the error message.

    Raises
    ------
    TrcoptError
        Code ``NC-NOT-TEXT``: the bytes are not text (NUL bytes, or more than
        :data:`MAX_CONTROL_FRACTION` control characters in a file that is not UTF-8).
    """
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError:
            raise TrcoptError(
                "not a text file (invalid UTF-16)", code=Code.NC_NOT_TEXT, span=SourceSpan(file)
            ) from None
    nul = raw.find(b"\x00")
    if nul >= 0:
        raise TrcoptError(
            f"not a text file (NUL byte at offset {nul})", code=Code.NC_NOT_TEXT, span=_byte_place(raw, nul, file)
        )
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        pass
    controls = sum(1 for b in raw if (b < 32 or b == 127) and b not in _TEXT_CONTROLS)
    if raw and controls / len(raw) > MAX_CONTROL_FRACTION:
        first = next(i for i, b in enumerate(raw) if (b < 32 or b == 127) and b not in _TEXT_CONTROLS)
        raise TrcoptError(
            f"not a text file ({controls} of {len(raw)} bytes are control characters, the first at offset {first})",
            code=Code.NC_NOT_TEXT,
            span=_byte_place(raw, first, file),
        )
    return raw.decode("latin-1")
