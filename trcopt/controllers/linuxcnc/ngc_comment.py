"""LinuxCNC's active comments: ``(MSG,…)``, ``(DEBUG,…)``, ``(PRINT,…)``, ``(ABORT,…)``.

Only the last comment of a line counts (LinuxCNC keeps one per block). ``MSG`` shows its text as
written; ``DEBUG``, ``PRINT`` and ``ABORT`` substitute parameters first (``#1``, ``#<name>``;
``%d``, ``%f``, ``%.Nf`` choose the format of the following ones, ``%lf`` by default; an unknown
parameter prints ``######``) — LinuxCNC's ``convert_param_comment``. ``LOG``/``LOGOPEN``/… write
a log file and are plain comments here; ``PY``/``PYRUN`` (embedded Python) are not modelled.
"""

from __future__ import annotations

from collections.abc import Callable

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_motion import Stop

__all__ = ["active_comment"]

_MAX_PARAMETERS = 5602


def _expand(text: str, numbered: Callable[[int], float | None], named: Callable[[str], float | None]) -> str:
    out: list[str] = []
    fmt = "%f"
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "%":
            i += 1
            nxt = text[i] if i < n else ""
            if nxt == "d":
                fmt, i = "%.0f", i + 1
            elif nxt == "f":
                fmt, i = "%.4f", i + 1
            elif nxt == "." and i + 2 < n and text[i + 1].isdigit() and text[i + 2] == "f":
                fmt, i = f"%.{text[i + 1]}f", i + 3
            elif nxt == ".":
                out.append(".")
                i += 1
            else:
                out.append("%")
        elif c == "#":
            i += 1
            value: float | None = None
            if i < n and text[i].isdigit():
                j = i
                while j < n and text[j].isdigit():
                    j += 1
                number = int(text[i:j])
                i = j
                value = numbered(number) if 0 <= number < _MAX_PARAMETERS else None
            elif i < n and text[i] == "<":
                close = text.find(">", i)
                if close < 0:
                    raise Stop(Code.NC_SYNTAX, "Named parameter not terminated")
                name = "".join(text[i + 1 : close].split()).lower()
                i = close + 1
                value = named(name)
            else:
                out.append("#")
                continue
            if value is None:
                out.append("######")
            else:
                value = 0.0 if abs(value) < 1e-6 else value
                out.append(fmt % value)
        else:
            out.append(c)
            i += 1
    return "".join(out)


def active_comment(
    comment: str | None, numbered: Callable[[int], float | None], named: Callable[[str], float | None]
) -> tuple[str, str] | None:
    """``(kind, text)`` of a message comment (kind ``MSG``, ``DEBUG`` or ``PRINT``), None for a
    plain comment; raises :class:`Stop` for ``ABORT`` (``LCNC-ABORT``) and embedded Python."""
    if comment is None:
        return None
    body = comment.lstrip()
    low = body.lower()
    for kind in ("msg,", "debug,", "print,", "abort,"):
        if low.startswith(kind):
            rest = body[len(kind) :]
            if kind == "msg,":
                return "MSG", rest
            text = _expand(rest, numbered, named)
            if kind == "abort,":
                raise Stop(Code.LCNC_ABORT, text)
            return kind[:-1].upper(), text
    if low.startswith(("py,", "pyrun,", "pyreload")):
        raise Stop(Code.NC_UNSUPPORTED, "embedded Python comments (PY, PYRUN, PYRELOAD) are not supported")
    return None
