"""LinuxCNC tool tables (``.tbl``): one tool per line, ``T<n> P<pocket> D<diameter> ... ;comment``.

Words (any order, case-insensitive): ``T`` tool number (required), ``P`` pocket, ``X Y Z A B C U V
W`` offsets, ``D`` diameter, ``I``/``J`` front/back angle, ``Q`` orientation (lathe tools 1-9).
Everything after ``;`` is a comment. The file itself does not say its unit: LinuxCNC reads it in
the machine units, which for the standalone interpreter are **inches**; :func:`load_tbl` therefore
takes the unit explicitly (``"inch"`` or ``"mm"``) and stores every length in mm.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from trcopt.codes import Code
from trcopt.errors import ConfigError, SourceSpan
from trcopt.modes import ToolUnit, parse_enum

__all__ = ["LinuxCncTool", "LinuxCncToolTable", "NgcSettings", "load_parameters", "load_tbl", "parse_tbl", "find_tbl"]
_WORD = re.compile(r"([A-Za-z])\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")
_KNOWN = set("TPXYZABCUVWDIJQ")


@dataclass(frozen=True, slots=True)
class LinuxCncTool:
    """One tool-table entry; lengths in mm."""

    number: int
    pocket: int = 0
    diameter_mm: float = 0.0
    orientation: int = 0
    z_offset_mm: float = 0.0
    comment: str = ""
    x_offset_mm: float = 0.0
    y_offset_mm: float = 0.0

    @property
    def radius_mm(self) -> float:
        """Compensation radius (half the diameter; negative swaps the side), mm."""
        return self.diameter_mm / 2.0


@dataclass(frozen=True, slots=True)
class LinuxCncToolTable:
    """Tools by number, with the unit the file was read in."""

    tools: dict[int, LinuxCncTool] = field(default_factory=dict)
    unit: ToolUnit = ToolUnit.INCH
    source: str = "<table>"

    def get(self, number: int) -> LinuxCncTool | None:
        return self.tools.get(int(number))

    def __contains__(self, number: object) -> bool:
        return number in self.tools

    def __len__(self) -> int:
        return len(self.tools)


def _unit(unit: ToolUnit | str) -> ToolUnit:
    """The table's unit; ``in``/``inches`` are read as inch, anything unknown is a ConfigError
    (``program``: the lengths are kept as written, the reader scales them by the program's unit)."""
    key = unit if isinstance(unit, ToolUnit) else {"in": "inch", "inches": "inch"}.get(str(unit).strip().lower(), unit)
    try:
        return parse_enum(ToolUnit, key, "tool table unit")
    except ValueError as exc:
        raise ConfigError(str(exc), code=Code.CONFIG) from None


def parse_tbl(text: str, unit: ToolUnit | str = ToolUnit.INCH, source: str = "<table>") -> LinuxCncToolTable:
    """Parse the text of a LinuxCNC tool table whose lengths are in ``unit``.

    Raises :class:`~trcopt.errors.ConfigError` (naming file and line) for a line without ``T``,
    an unknown word, a word given twice or a repeated tool number.
    """
    table_unit = _unit(unit)
    k = table_unit.mm
    tools: dict[int, LinuxCncTool] = {}
    for lineno, raw in enumerate(text.splitlines(), start=1):
        body, _, comment = raw.partition(";")
        if not body.strip():
            continue
        span = SourceSpan(source, lineno, 1)
        leftover = _WORD.sub("", body).strip()
        if leftover:
            raise ConfigError(f"tool table: cannot read {leftover!r}", span)
        words: dict[str, float] = {}
        for letter, value in _WORD.findall(body):
            letter = letter.upper()
            if letter not in _KNOWN:
                raise ConfigError(
                    f"tool table: unknown word {letter!r}; valid: {' '.join(sorted(_KNOWN))}", span
                )
            if letter in words:
                raise ConfigError(f"tool table: word {letter} given twice", span)
            words[letter] = float(value)
        if "T" not in words:
            raise ConfigError("tool table: line without tool number T", span)
        number = int(words["T"])
        if number in tools:
            raise ConfigError(f"tool table: tool T{number} defined twice", span)
        tools[number] = LinuxCncTool(
            number=number,
            pocket=int(words.get("P", 0)),
            diameter_mm=words.get("D", 0.0) * k,
            orientation=int(words.get("Q", 0)),
            z_offset_mm=words.get("Z", 0.0) * k,
            comment=comment.strip(),
            x_offset_mm=words.get("X", 0.0) * k,
            y_offset_mm=words.get("Y", 0.0) * k,
        )
    return LinuxCncToolTable(tools, table_unit, source)


def load_tbl(path: str | os.PathLike[str], unit: ToolUnit | str = ToolUnit.INCH) -> LinuxCncToolTable:
    """Read a LinuxCNC ``.tbl`` file whose lengths are in ``unit`` (``"inch"``, LinuxCNC's default
    machine unit, or ``"mm"``). An unreadable file raises ConfigError (code ``IO``)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ConfigError(f"cannot read tool table {p}: {exc.strerror}", code=Code.IO) from None
    return parse_tbl(text, unit, str(p))


def find_tbl(program: str) -> Path | None:
    """The tool table beside a program file: ``<stem>.tbl``, else ``tools.tbl``; None if none."""
    p = Path(program)
    if not p.name or not os.path.isfile(p):  # os.path: False for a name the system refuses
        return None
    for cand in (p.with_suffix(".tbl"), p.with_name("tools.tbl")):
        if os.path.isfile(cand):
            return cand
    return None


@dataclass(frozen=True, slots=True)
class NgcSettings:
    """What ``rs274ngc.toml`` sets: parameter values (the machine unit, as LinuxCNC's parameter
    file) and the G73/G83 peck clearances (program units, LinuxCNC's ``G73_PECK_CLEARANCE``)."""

    parameters: dict[int, float] = field(default_factory=dict)
    peck_clearance: dict[float, float] = field(default_factory=dict)
    source: str = ""


PARAMS_FILE = "rs274ngc.toml"


def load_parameters(
    path: str | os.PathLike[str] | None, table: str | os.PathLike[str] | None, program: str
) -> NgcSettings:
    """Read ``path``, else ``rs274ngc.toml`` beside the tool table ``table``, else beside
    ``program`` (none found: no settings)::

        [parameters]          # numbered parameters, e.g. the G28 reference point
        5161 = 0.0
        5163 = 50.0
        [rs274ngc]
        g73_peck_clearance = 1.0
        g83_peck_clearance = 1.0
    """
    if path is None:
        for base in (table, program):
            if base is None:
                continue
            cand = Path(base).with_name(PARAMS_FILE)
            if Path(base).name and os.path.isfile(cand):
                path = cand
                break
    if path is None:
        return NgcSettings()
    import tomllib

    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ConfigError(f"cannot read {p}: {exc.strerror}", code=Code.IO) from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{p}: {exc}") from None
    unknown = set(data) - {"parameters", "rs274ngc"}
    if unknown:
        raise ConfigError(f"{p}: unknown table(s) {sorted(unknown)}; valid: [parameters], [rs274ngc]")
    params: dict[int, float] = {}
    for key, value in dict(data.get("parameters", {})).items():
        if not str(key).isdigit() or not 1 <= int(key) <= 5601 or not isinstance(value, (int, float)):
            raise ConfigError(f"{p}: [parameters] {key} = {value!r}: a parameter number 1…5601 and a number")
        params[int(key)] = float(value)
    peck: dict[float, float] = {}
    for key, value in dict(data.get("rs274ngc", {})).items():
        if key not in ("g73_peck_clearance", "g83_peck_clearance") or not isinstance(value, (int, float)):
            raise ConfigError(f"{p}: [rs274ngc] {key} = {value!r}: g73_peck_clearance or g83_peck_clearance, a number")
        peck[73.0 if key.startswith("g73") else 83.0] = float(value)
    return NgcSettings(params, peck, str(p))
