"""The words of one RS274NGC block sorted as LinuxCNC's interpreter sorts them.

:func:`decode` puts every G and M code in its modal group (two of one group in a block are
LinuxCNC's "Two g codes used from same modal group"), finds the motion the block runs (its
group-1 code, or the modal motion when axis words stand alone — LinuxCNC's ``enhance_block``)
and runs the checks of LinuxCNC's ``check_items`` on the other words (a D, H, I, J, K, L, P, Q or
R word no code of the block uses), with LinuxCNC's messages. Codes LinuxCNC knows but trcopt
does not model are ``NC-UNSUPPORTED`` errors that name them; codes LinuxCNC does not know are
its "Unknown g code used" / "Unknown m code used".
"""

from __future__ import annotations

from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_motion import NgcState, Stop

__all__ = ["Words", "decode"]

_G_GROUP: dict[float, int] = {
    0.0: 1, 1.0: 1, 2.0: 1, 3.0: 1, 73.0: 1, 74.0: 1, 80.0: 1, 81.0: 1, 82.0: 1, 83.0: 1, 84.0: 1,
    85.0: 1, 86.0: 1, 87.0: 1, 88.0: 1, 89.0: 1,
    4.0: 0, 10.0: 0, 28.0: 0, 28.1: 0, 30.0: 0, 30.1: 0, 52.0: 0, 53.0: 0, 92.0: 0, 92.1: 0, 92.2: 0, 92.3: 0,
    17.0: 2, 18.0: 2, 19.0: 2, 90.0: 3, 91.0: 3, 90.1: 4, 91.1: 4, 93.0: 5, 94.0: 5, 95.0: 5, 20.0: 6, 21.0: 6,
    40.0: 7, 41.0: 7, 42.0: 7, 41.1: 7, 42.1: 7, 43.0: 8, 43.1: 8, 43.2: 8, 49.0: 8, 98.0: 10, 99.0: 10,
    54.0: 12, 55.0: 12, 56.0: 12, 57.0: 12, 58.0: 12, 59.0: 12, 59.1: 12, 59.2: 12, 59.3: 12,
    61.0: 13, 61.1: 13, 64.0: 13, 97.0: 14, 8.0: 15,
}  # fmt: skip
# LinuxCNC codes trcopt does not model
_G_UNMODELLED = {
    5.0, 5.1, 5.2, 5.3, 7.0, 17.1, 18.1, 19.1, 33.0, 33.1, 38.2, 38.3, 38.4, 38.5, 70.0, 71.0, 71.1,
    71.2, 72.0, 72.1, 72.2, 76.0, 96.0,
}  # fmt: skip
_M_GROUP = {0: 4, 1: 4, 2: 4, 30: 4, 60: 4, 6: 6, 61: 6, 3: 7, 4: 7, 5: 7, 7: 8, 8: 8, 9: 8, 48: 9, 49: 9}
_M_UNMODELLED = {19, 50, 51, 52, 53, 62, 63, 64, 65, 66, 67, 68, 70, 71, 72, 73}
_COVETS_AXES = {10.0, 28.0, 30.0, 52.0, 92.0}
_ALLOWED_LETTERS = set("GMXYZIJKRFSTDNPHQL")
_ARC = (2.0, 3.0)
_G_KEY = {group: f"G{group}" for group in set(_G_GROUP.values())}  # Words.cols keys
_M_KEY = {group: f"M{group}" for group in set(_M_GROUP.values())}
_CYCLE = {73.0, 74.0, 81.0, 82.0, 83.0, 84.0, 85.0, 86.0, 87.0, 88.0, 89.0}


@dataclass(slots=True)
class Words:
    """A decoded block: G codes and M codes by modal group, the other words' values (program
    units), every word's column, and the motion the block runs (None: none)."""

    g: dict[int, float] = field(default_factory=dict)
    m: dict[int, int] = field(default_factory=dict)
    values: dict[str, float] = field(default_factory=dict)
    cols: dict[str, int] = field(default_factory=dict)
    motion: float | None = None

    def col(self, letter: str) -> int:
        return self.cols.get(letter, 0)

    def gcol(self, group: int) -> int:
        return self.cols.get(f"G{group}", 0)

    def mcol(self, group: int) -> int:
        return self.cols.get(f"M{group}", 0)


def decode(words: list[tuple[str, float, int]], st: NgcState) -> Words:
    """Sort and check the words of a block (see the module docstring)."""
    w = Words()
    for letter, _, col in words:
        if letter not in _ALLOWED_LETTERS:
            raise Stop(Code.NC_UNSUPPORTED, f"word {letter} is not supported", col)
    for letter, value, col in words:
        if letter == "G":
            code = round(value, 1)
            group = _G_GROUP.get(code)
            if group is None:
                if code in _G_UNMODELLED:
                    raise Stop(Code.NC_UNSUPPORTED, f"G{code:g} is not supported by the rs274 reader", col)
                raise Stop(Code.LCNC_WORDS, "Unknown g code used", col)
            if group in w.g:
                raise Stop(Code.LCNC_WORDS, "Two g codes used from same modal group", col)
            w.g[group] = code
            w.cols[_G_KEY[group]] = col
        elif letter == "M":
            mc = int(round(value))
            if mc in _M_UNMODELLED or 100 <= mc <= 199:
                raise Stop(Code.NC_UNSUPPORTED, f"M{mc} is not supported by the rs274 reader", col)
            mgroup = _M_GROUP.get(mc)
            if mgroup is None:
                raise Stop(Code.LCNC_WORDS, f"Unknown m code used: M{mc}", col)
            if mgroup in w.m:
                raise Stop(Code.LCNC_WORDS, "Two m codes used from same modal group", col)
            w.m[mgroup] = mc
            w.cols[_M_KEY[mgroup]] = col
        elif letter == "N":
            raise Stop(Code.NC_SYNTAX, "N word must start the block", col)
        elif letter in w.values:
            raise Stop(Code.LCNC_WORDS, f"Multiple {letter.lower()} words on one line", col)
        else:
            w.values[letter] = value
            w.cols[letter] = col
    _enhance(w, st)
    _check(w)
    return w


def _enhance(w: Words, st: NgcState) -> None:
    """LinuxCNC's ``enhance_block``: which motion runs, and which words the axes belong to."""
    values = w.values
    axis = "X" in values or "Y" in values or "Z" in values
    mode0, mode1 = w.g.get(0), w.g.get(1)
    covets = mode0 in _COVETS_AXES
    if mode1 is not None:
        if mode1 == 80.0:
            if axis and not covets:
                raise Stop(Code.LCNC_WORDS, "Cannot use axis values with g80", w.gcol(1))
            if not axis and mode0 in (52.0, 92.0):
                raise Stop(Code.LCNC_OFFSET, "All axes missing with g52 or g92", w.gcol(0))
        else:
            if covets:
                raise Stop(Code.LCNC_WORDS, "Cannot use two g codes that both use axis values", w.gcol(0))
            if not axis and mode1 not in (0.0, 1.0, 2.0, 3.0):
                raise Stop(Code.LCNC_WORDS, "All axes missing with motion code", w.gcol(1))
        w.motion = mode1
    elif covets:
        if not axis and mode0 in (52.0, 92.0):
            raise Stop(Code.LCNC_OFFSET, "All axes missing with g52 or g92", w.gcol(0))
    elif axis:
        tlo = w.g.get(8)
        if st.motion is None and tlo not in (43.1, 43.2):
            raise Stop(Code.LCNC_WORDS, "Cannot use axis values without a g code that uses them")
        if tlo != 43.1:
            w.motion = st.motion
    elif ("I" in values or "J" in values or "K" in values) and st.motion in _ARC:
        w.motion = st.motion
    if mode0 == 53.0 and w.motion not in (0.0, 1.0):
        raise Stop(Code.LCNC_OFFSET, "Must use g0 or g1 with g53", w.gcol(0))
    if mode0 == 53.0 and (w.g.get(3) == 91.0 or (w.g.get(3) is None and not st.absolute)):
        raise Stop(Code.LCNC_OFFSET, "Cannot use g53 incremental", w.gcol(0))
    if mode0 == 4.0 and "P" not in w.values:
        raise Stop(Code.LCNC_WORDS, "Dwell time missing with g4", w.gcol(0))
    if mode0 == 4.0 and w.motion in _ARC and mode1 is not None:
        raise Stop(Code.LCNC_WORDS, "G4 not allowed with G2 or G3 because they both use P", w.gcol(0))


def _check(w: Words) -> None:
    """LinuxCNC's ``check_other_codes`` for the words trcopt reads."""
    motion, mode0, comp, tlo, ctrl = w.motion, w.g.get(0), w.g.get(7), w.g.get(8), w.g.get(13)
    v, m = w.values, w.m

    def fail(letter: str, message: str) -> None:
        raise Stop(Code.LCNC_WORDS, message, w.col(letter))

    if "D" in v and comp not in (41.0, 42.0, 41.1, 42.1) and motion not in (73.0, 83.0):
        fail("D", "D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 G73, G83 or G96 to use it")
    if "H" in v and tlo not in (43.0, 43.2):
        fail("H", "H word with no G43 or G76 to use it")
    if "I" in v and motion not in (2.0, 3.0, 87.0) and mode0 != 10.0:
        fail("I", "I word with no G2, G3, G5, G5.1, G6, G6.1, G10, G33.1, G76, or G87 to use it")
    if "J" in v and motion not in (2.0, 3.0, 87.0) and mode0 != 10.0:
        fail("J", "J word with no G2, G3, G5, G5.1, G6, G6.1, G10, G76 or G87 to use it")
    if "K" in v and motion not in (2.0, 3.0, 87.0):
        fail("K", "K word with no G2, G3, G6.2, G33, G33.1, G76, or G87 to use it")
    if "L" in v and motion not in _CYCLE and mode0 != 10.0 and comp not in (41.0, 42.0, 41.1, 42.1):
        fail("L", "L word with no G10, cutter compensation, canned cycle, digital/analog input, M98 or NURBS code")
    p_users = (2.0, 3.0, 74.0, 82.0, 84.0, 86.0, 88.0, 89.0)
    if "P" in v and mode0 not in (10.0, 4.0) and ctrl != 64.0 and motion not in p_users:
        fail(
            "P",
            "P word with no G2 G3 G4 G10 G64 G5 G5.2 G6, G6.2, G76 G82 G86 G88 G89 or M50 M51 M52 M53 M62 M63 "
            "M64 M65 M66 M98 or user M code to use it",
        )
    if "Q" in v and motion not in (73.0, 83.0) and mode0 != 10.0 and m.get(6) != 61 and ctrl != 64.0:
        fail("Q", "Q word with no G5, G6, G10, G64, G73, G76, G83, M19, M66, M67, M68 or user M code that uses it")
    if "R" in v and motion not in (2.0, 3.0, 73.0, 74.0) and motion not in _CYCLE and comp not in (41.1, 42.1):
        if mode0 != 10.0 and ctrl != 64.0:
            fail("R", "R word with no g code that uses it")
