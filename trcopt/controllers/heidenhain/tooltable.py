"""Heidenhain tool data: TOOL DEF rows, the tool table (TOML) and the compensation value.

Compensation value used for RL/RR/R+/R− (spec §4, REQ-HT-03)::

    r = R + DR_TAB + DR_CALL

R from ``TOOL DEF`` or the table, DR_TAB the table's wear/oversize column, DR_CALL the
``TOOL CALL … DR`` allowance. Tool 0 is the zero tool (R = 0). A ``TOOL DEF`` row replaces the
table's row of the same number for the program (program-defined tools carry no table delta).

Tool table file (TOML, one table per tool number; keys as the TNC columns)::

    [tool.3]
    NAME = "MILL_D12"   # optional, for TOOL CALL "MILL_D12"
    L = 50.0            # mm
    R = 6.0             # mm
    DL = 0.0            # mm
    DR = -0.05          # mm (DR_TAB)
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from trcopt.config import file_beside, read_toml
from trcopt.errors import ConfigError
from trcopt.nc.limits import MAX_COORDINATE_MM

__all__ = [
    "HhTool",
    "load_tool_table",
    "tool_table_from_dict",
    "find_tool_table",
    "compensation_value",
]

_KEYS = {"NAME", "L", "R", "DL", "DR", "R2", "DR2"}


@dataclass(frozen=True, slots=True)
class HhTool:
    """One tool: length L, radius R and the table deltas DL, DR (mm)."""

    number: int
    name: str = ""
    length: float = 0.0
    radius: float = 0.0
    dl: float = 0.0
    dr: float = 0.0


def compensation_value(radius: float, dr_tab: float, dr_call: float) -> float:
    """``r = R + DR_TAB + DR_CALL`` (mm)."""
    return radius + dr_tab + dr_call


def tool_table_from_dict(
    data: Mapping[str, object], source: str = "<tool table>"
) -> dict[int, HhTool]:
    """Tools from the parsed TOML (``{"tool": {"3": {"R": 6.0, …}}}``); unknown keys are errors."""
    unknown = set(data) - {"tool"}
    if unknown:
        raise ConfigError(f"{source}: unknown key {sorted(unknown)[0]!r}; valid: tool")
    table: dict[int, HhTool] = {}
    tools = data.get("tool", {})
    if not isinstance(tools, Mapping):
        raise ConfigError(f"{source}: 'tool' must be a table of tool numbers")
    for key, row in tools.items():
        try:
            number = int(key)
        except ValueError:
            raise ConfigError(f"{source}: tool number {key!r} is not an integer") from None
        if not isinstance(row, Mapping):
            raise ConfigError(f"{source}: tool.{key} must be a table")
        bad = set(row) - _KEYS
        if bad:
            raise ConfigError(
                f"{source}: tool.{key}: unknown key {sorted(bad)[0]!r}; valid: {', '.join(sorted(_KEYS))}"
            )
        try:
            table[number] = HhTool(
                number,
                str(row.get("NAME", "")),
                float(row.get("L", 0.0)),
                float(row.get("R", 0.0)),
                float(row.get("DL", 0.0)),
                float(row.get("DR", 0.0)),
            )
        except (TypeError, ValueError):
            raise ConfigError(f"{source}: tool.{key}: values must be numbers") from None
        tool = table[number]
        for name, value in (("L", tool.length), ("R", tool.radius), ("DL", tool.dl), ("DR", tool.dr)):
            if not (math.isfinite(value) and abs(value) <= MAX_COORDINATE_MM):
                raise ConfigError(
                    f"{source}: tool.{key}.{name} = {value!r} is not a finite length within ±{MAX_COORDINATE_MM:g} mm"
                )
        if tool.radius < 0.0:
            raise ConfigError(f"{source}: tool.{key}.R = {tool.radius:g} mm: a tool radius cannot be negative")
    return table


def load_tool_table(path: str | os.PathLike[str]) -> dict[int, HhTool]:
    """Read a tool table TOML file (see the module docstring)."""
    return tool_table_from_dict(read_toml(Path(path), "tool table"), str(path))


def find_tool_table(program: str) -> Path | None:
    """The tool table that belongs to a program file: ``<stem>.tools.toml`` beside it, else
    ``tools.toml`` in its folder (the TNC's TOOL.T); None when there is none."""
    return file_beside(program, ".tools.toml", "tools.toml")
