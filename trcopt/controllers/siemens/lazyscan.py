"""A SINUMERIK program scanned for running block by block: :func:`scan_lazy`.

:func:`~trcopt.controllers.siemens.flow.scan` makes one :class:`~trcopt.controllers.siemens.flow.Statement`
per line before the program runs; a million-block program is then a million statements held at
once. :func:`scan_lazy` gives the same :class:`~trcopt.controllers.siemens.flow.Program` with
statements made when the runner asks for them (:class:`LazyStatements`): what it holds for the
whole program is the text, where each line starts (:class:`~trcopt.textlines.TextLines`, 5 bytes a
line), the labels and the partners of the structure keywords. Only the lines that can carry a label
or a structure keyword (a ``:`` or one of ``IF ELSE WHILE FOR REPEAT UNTIL LOOP`` in any letter
case, found in the text as a whole) are scanned before the run, so that a structure that does not
close is alarm 12640 before the first block runs, as with ``scan``. The statements of the block
numbers a jump looks for (``GOTOF N100``) are found when the jump asks (:class:`LazyNumbers`).
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping

from trcopt.controllers.siemens.flow import Program, Statement, _statement, match_structures
from trcopt.nc.ondemand import OnDemand, lines_matching
from trcopt.textlines import TextLines

__all__ = ["scan_lazy", "LazyStatements", "LazyNumbers"]

#: a line with one of these (its ASCII letters in upper case) may carry a label or a structure keyword
_STRUCTURE = re.compile(rb"IF|ELSE|WHILE|FOR|REPEAT|UNTIL|LOOP|:")


def scan_lazy(text: str, file: str, name: str, known: frozenset[str]) -> Program:
    """:func:`~trcopt.controllers.siemens.flow.scan` with statements made on demand (module
    docstring); the same labels, partners and alarm 12640."""
    lines = TextLines(text)
    candidates = (_statement(i, i + 1, lines[i], known) for i in lines_matching(lines, _STRUCTURE))
    labels, partners = match_structures(candidates, file)
    statements = LazyStatements(lines, known, partners)
    return Program(file, name, statements, labels, LazyNumbers(statements))


class LazyStatements(OnDemand[Statement]):
    """The statements of a program's lines, each made when asked for (the last few kept):
    ``statements[i]`` equals what :func:`~trcopt.controllers.siemens.flow.scan` makes."""

    def __init__(self, lines: TextLines, known: frozenset[str], partners: dict[int, int]) -> None:
        super().__init__(len(lines), self.statement)
        self.lines, self.known, self.partners = lines, known, partners

    def statement(self, i: int) -> Statement:
        """The statement of line ``i`` (0-based), made anew."""
        st = _statement(i, i + 1, self.lines[i], self.known)
        partner = self.partners.get(i)
        if partner is not None:
            st.partner = partner
        return st


class LazyNumbers(Mapping[str, list[int]]):
    """Block number (``"N100"``) → the indices of its statements, found in the text when a
    number is first asked for (a line with ``N`` or ``:`` and the number, then checked as
    :func:`~trcopt.controllers.siemens.flow.scan` reads the line)."""

    def __init__(self, statements: LazyStatements) -> None:
        self.statements = statements
        self._found: dict[str, list[int]] = {}

    def __getitem__(self, key: str) -> list[int]:
        found = self._found.get(key)
        if found is None:
            found = []
            if re.fullmatch(r"N\d+", key):
                pattern = re.compile(rb"[N:]0*" + str(int(key[1:])).encode() + rb"(?![0-9])")
                make = self.statements.statement
                found = [i for i in lines_matching(self.statements.lines, pattern) if make(i).number == key]
            self._found[key] = found
        if not found:
            raise KeyError(key)
        return found

    def __iter__(self) -> Iterator[str]:  # the numbers asked for so far
        return (k for k, v in self._found.items() if v)

    def __len__(self) -> int:
        return sum(1 for v in self._found.values() if v)
