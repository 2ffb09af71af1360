"""SINUMERIK tool data from a TOML tool table (``--tool-table``), beside the program's ``$TC_DP``.

One table per cutting edge, keyed ``T<n>.D<m>``; the keys are the tool parameters trcopt uses::

    [T1.D1]
    type = 120      # $TC_DP1: tool type (120 end mill; 2xx drills are refused under G41/G42)
    radius = 5.0    # $TC_DP6: geometry radius, mm
    wear = -0.02    # $TC_DP15: wear radius, mm

The program's ``$TC_DP…`` assignments override the table's values edge by edge as they run.
Without ``--tool-table`` the reader looks for ``<program>.tools.toml``, then ``tools.toml`` in the
program's folder.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

from trcopt.config import file_beside, read_toml
from trcopt.errors import ConfigError
from trcopt.nc.limits import MAX_COORDINATE_MM
from trcopt.nc.tools import ToolEdge

__all__ = ["load_tool_table", "tool_table_from_dict", "find_tool_table"]

_T = re.compile(r"T(\d+)\Z", re.I)
_D = re.compile(r"D(\d+)\Z", re.I)
_KEYS = {"type", "radius", "wear"}


def tool_table_from_dict(data: dict[str, object], source: str = "<tool table>") -> dict[tuple[int, int], ToolEdge]:
    """The edges of a parsed table (``{"T1": {"D1": {"radius": 5.0}}}``); unknown keys are errors."""
    edges: dict[tuple[int, int], ToolEdge] = {}
    for tkey, tool in data.items():
        tm = _T.match(tkey)
        if tm is None or not isinstance(tool, dict):
            raise ConfigError(f"{source}: {tkey!r} is not a tool: expected tables [T<number>.D<number>]")
        for dkey, edge in tool.items():
            dm = _D.match(dkey)
            if dm is None or not isinstance(edge, dict):
                raise ConfigError(f"{source}: {tkey}.{dkey} is not a cutting edge: expected [T<number>.D<number>]")
            bad = set(edge) - _KEYS
            if bad:
                raise ConfigError(
                    f"{source}: [{tkey}.{dkey}]: unknown key {sorted(bad)[0]!r}; valid: type, radius, wear"
                )
            for key in ("radius", "wear"):
                value = edge.get(key, 0.0)
                if (
                    isinstance(value, bool)
                    or not isinstance(value, int | float)
                    or not (math.isfinite(value) and abs(value) <= MAX_COORDINATE_MM)
                ):
                    raise ConfigError(f"{source}: [{tkey}.{dkey}].{key} = {value!r} is not a length in mm")
            kind = edge.get("type", 0)
            if isinstance(kind, bool) or not isinstance(kind, int) or kind < 0:
                raise ConfigError(f"{source}: [{tkey}.{dkey}].type = {kind!r} is not a tool type number")
            if float(edge.get("radius", 0.0)) < 0.0:
                raise ConfigError(f"{source}: [{tkey}.{dkey}].radius: a tool radius cannot be negative")
            edges[(int(tm.group(1)), int(dm.group(1)))] = ToolEdge.from_value(edge)
    return edges


def load_tool_table(path: str | os.PathLike[str]) -> dict[tuple[int, int], ToolEdge]:
    """Read a tool table TOML file (see the module docstring)."""
    return tool_table_from_dict(read_toml(Path(path), "tool table"), str(path))


def find_tool_table(program: str) -> Path | None:
    """``<stem>.tools.toml`` beside the program file, else ``tools.toml`` in its folder."""
    return file_beside(program, ".tools.toml", "tools.toml")
