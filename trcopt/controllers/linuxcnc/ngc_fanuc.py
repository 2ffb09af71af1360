"""Fanuc-style programs in LinuxCNC: ``O100`` … ``M99`` called by ``M98 P100 [L n]``.

As LinuxCNC runs them: ``M98`` searches forward for the program number (or jumps to it when it
was found before), runs the program ``L`` times and returns with ``M99``; the called program
shares ``#1``…``#30`` with its caller (an O-word call gets its own), has its own named locals, and
must end with ``M99``; an ``O100`` line reached in the program's flow is passed through; an ``M99``
in the main program ends it as ``M2`` does (LinuxCNC without its loop-on-M99 setting, as
``rs274`` runs it). Not modelled (an error naming it): ``M98 L0`` and ``M98``/``M99`` with other
words in their block.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_block import Block, OLine
from trcopt.controllers.linuxcnc.ngc_expr import NgcError

__all__ = ["CALL_LEVELS", "Frame", "m98_block", "program_number"]

CALL_LEVELS = 10  # LinuxCNC's INTERP_SUB_ROUTINE_LEVELS


@dataclass(slots=True)
class Frame:
    """A call level of :class:`~trcopt.controllers.linuxcnc.ngc_flow.NgcFlow`."""

    sub: str | None = None
    saved: list[float] = field(default_factory=list)  # the caller's #1…#30, kept by the caller's frame
    file: str = ""
    index: int = 0  # where the caller continues
    fanuc: bool = False  # called by M98 (returns with M99, shares #1…#30 with the caller)
    repeats: int = 0  # M98 L: runs still to go after this one


def program_number(self: Any, o: OLine) -> None:
    """``O100`` alone on a line (``self``: the flow): the start of a Fanuc-style program. Found
    while M98 searches for it, its place is kept; reached in the program's flow, the program runs
    on into it."""
    name = o.label
    if self.skipping_to_sub == name:
        if name not in self.offsets:
            self._save_offset(o, name)
        self.skipping = self.skipping_to_sub = None
        return
    if self.skipping is not None or self.skipping_to_sub is not None:
        return
    if len(self.frames) > 1 and not self.frames[-1].fanuc:
        raise NgcError("Fanuc 'O....' subroutine must be called with 'M98'", o.at, Code.LCNC_OWORD)

def m98_block(self: Any, block: Block) -> bool:
    """``M98 P… [L…]`` and ``M99`` in ``block``: call, repeat or return; True when the block
    was a call or a return (it has no other words). An ``M99`` in the main program ends it as
    ``M2`` does (LinuxCNC without its loop-on-M99 setting): the caller reads it as M2."""
    for k, v, _ in block.words:
        if k == "M" and v in (98.0, 99.0):
            break
    else:
        return False
    ms = [(i, v) for i, (k, v, _) in enumerate(block.words) if k == "M" and v in (98.0, 99.0)]
    i, code = ms[0]
    col = block.words[i][2]
    other = [k for k, _, _ in block.words if k not in ("M", "P", "L")]
    if other or block.settings or len([k for k, _, _ in block.words if k == "M"]) > 1:
        raise NgcError(f"M{int(code)} with other words in its block is not modelled", col - 1, Code.NC_UNSUPPORTED)
    if code == 99.0:
        frame = self.frames[-1]
        if len(self.frames) == 1:
            k, _, c = block.words[i]
            block.words[i] = (k, 2.0, c)  # the program end
            return False
        if not frame.fanuc:
            raise NgcError(
                "'O.... endsub' or 'O.... return' must follow 'O.... sub' subroutine definition",
                col - 1,
                Code.LCNC_OWORD,
            )
        if frame.repeats > 0:
            frame.repeats -= 1
            self.params.frames[-1] = {}
            self._back_to(frame.sub or "", OLine(frame.sub or "", "", 0, col - 1))
            self.index += 1  # on to the line after the program number
            return True
        self.frames.pop()
        self.params.frames.pop()
        caller = self.frames[-1]
        self.file, self.index = caller.file, caller.index
        return True
    values = {k: v for k, v, _ in block.words}
    if "P" not in values:
        raise NgcError("M98 requires a P word", col - 1, Code.LCNC_WORDS)
    runs = int(round(values.get("L", 1.0)))
    if runs < 1:
        raise NgcError("M98 L0 (no run) is not modelled", col - 1, Code.NC_UNSUPPORTED)
    name = str(int(round(values["P"])))
    if len(self.frames) >= CALL_LEVELS:
        raise NgcError("Too many subroutine levels", col - 1, Code.LCNC_OWORD)
    caller = self.frames[-1]
    caller.file, caller.index = self.file, self.index
    self.frames.append(Frame(name, fanuc=True, repeats=runs - 1))
    self.params.frames.append({})
    op = self.offsets.get(name)
    if op is not None:
        self.file, self.index = op.file, op.index + 1
        return True
    self.skipping = self.skipping_to_sub = name
    self.skip_start = self.index
    return True
