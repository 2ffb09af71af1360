"""The controllers and their registry — the only place that knows controllers by name.

Each controller lives in its own folder (``siemens/``, ``heidenhain/``, ``linuxcnc/``) and exposes
one :class:`~trcopt.controllers.base.Controller` record as ``CONTROLLER``. Adding a controller is
one folder plus one line in ``_BUILTIN`` below (or :func:`register` at run time).

* :func:`names` — the registered controller names, in registration order;
* :func:`get` — a controller by its name or its dialect name, rejecting unknown names with the
  valid options;
* :func:`detect` — the controller of a program, from its file suffix, else its text, else the
  first registered controller;
* :func:`read_program` — program text (or a path) → canonical moves, by the controller's reader;
* :func:`stream_program` — the same moves one at a time (bounded memory for large programs).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping
from pathlib import PurePath

from trcopt.config import Tolerances
from trcopt.controllers import heidenhain, linuxcnc, siemens
from trcopt.controllers.base import Controller
from trcopt.modes import ToolUnit, parse_enum
from trcopt.nc.limits import check_moves
from trcopt.nc.modal import ReadOptions
from trcopt.nc.model import NcProgram
from trcopt.nc.stream import MoveStream
from trcopt.nc.text import decode_program
from trcopt.nc.tools import ToolEdge

__all__ = [
    "Controller", "names", "dialects", "get", "detect", "register", "unregister", "read_program", "stream_program",
]

_BUILTIN = (siemens.CONTROLLER, heidenhain.CONTROLLER, linuxcnc.CONTROLLER)
_REGISTRY: dict[str, Controller] = {c.name: c for c in _BUILTIN}


def names() -> tuple[str, ...]:
    """Registered controller names, in registration order (the first is the fallback of :func:`detect`)."""
    return tuple(_REGISTRY)


def dialects() -> tuple[str, ...]:
    """The dialect names of the registered controllers, in registration order."""
    return tuple(c.dialect for c in _REGISTRY.values())


def get(name: str | Controller) -> Controller:
    """The controller called ``name`` (its registry name or its dialect name, case-insensitive)."""
    if isinstance(name, Controller):
        return name
    key = str(name).strip().lower()
    for c in _REGISTRY.values():
        if key in (c.name, c.dialect):
            return c
    valid = sorted({*names(), *dialects()})
    raise ValueError(f"unknown controller or dialect {name!r}; valid: {', '.join(valid)}")


def detect(path: str | os.PathLike[str] | None, text: str) -> Controller:
    """The controller of a program: by file suffix, else by the first signature found in the text
    (registration order), else the first registered controller."""
    suffix = PurePath(os.fspath(path)).suffix.lower() if path else ""
    for c in _REGISTRY.values():
        if suffix in c.extensions:
            return c
    for c in _REGISTRY.values():
        if c.claims(text):
            return c
    return next(iter(_REGISTRY.values()))


def register(controller: Controller) -> Controller:
    """Add a controller; its name and dialect must be new."""
    taken = {*names(), *dialects()}
    if controller.name in taken or controller.dialect in taken:
        raise ValueError(f"a controller called {controller.name!r} (dialect {controller.dialect!r}) is registered")
    _REGISTRY[controller.name] = controller
    return controller


def unregister(name: str) -> None:
    """Remove a controller added with :func:`register` (built-in controllers stay)."""
    c = get(name)
    if c in _BUILTIN:
        raise ValueError(f"{c.name!r} is a built-in controller")
    del _REGISTRY[c.name]


def read_program(
    source: str | os.PathLike[str],
    file: str | None = None,
    dialect: str = "auto",
    tools: Mapping[tuple[int, int], ToolEdge | Mapping[str, object]] | None = None,
    tolerances: Tolerances | None = None,
    max_disc: int = 50,
    tool_table: str | os.PathLike[str] | None = None,
    tool_unit: str | ToolUnit = ToolUnit.PROGRAM,
    appr_radius: str = "centre",
    zero_offsets: str | os.PathLike[str] | None = None,
) -> NcProgram:
    """Read a part program into canonical moves with its controller's reader.

    Never raises for a problem in the program: the returned :class:`~trcopt.nc.model.NcProgram`
    carries an error-severity diagnostic (with file, line, column and block number) and its moves
    stop before the offending block; warnings are collected and reading continues. A file that
    is not text raises :class:`~trcopt.errors.TrcoptError` (code ``NC-NOT-TEXT``).

    Parameters
    ----------
    source:
        Program text, or a path (``os.PathLike``) to read it from.
    file:
        Name used in the source spans (default: the path, or ``"<program>"``).
    dialect:
        A controller or dialect name (:func:`names`, :func:`dialects`), or ``"auto"`` (:func:`detect`).
    tools:
        Preset tool edges ``{(t, d): ToolEdge | {"type":…, "radius": mm, "wear": mm}}``; a
        SINUMERIK program's ``$TC_DP`` assignments update them.
    tolerances:
        Geometric tolerances (arc end radius check: ``arc_end_radius_mm``, default 0.002 mm).
    max_disc:
        Upper limit of DISC (MD20220, default 50).
    tool_table, tool_unit:
        A tool-table file in the controller's format (LinuxCNC ``.tbl`` in ``tool_unit``, by
        default the program's G20/G21 unit; Heidenhain TOML). SINUMERIK programs carry their
        tool data as ``$TC_DP`` assignments. An unreadable or invalid table raises
        :class:`~trcopt.errors.ConfigError`.
    appr_radius:
        Heidenhain APPR/DEP CT/LCT radius: ``"centre"`` (tool-centre arc, default) or ``"contour"``.
    zero_offsets:
        SINUMERIK settable zero offsets (TOML, G54…); default: ``<program>.offsets.toml`` beside it.
    """
    controller, text, options = _prepared(
        source, file, dialect, tools, tolerances, max_disc, tool_table, tool_unit, appr_radius, zero_offsets
    )
    program = controller.read(text, options)
    # every number a move carries is finite and within trcopt.nc.limits before any stage uses it
    moves, diagnostics = check_moves(program.moves, program.diagnostics)
    if len(moves) == len(program.moves):
        return program
    return dataclasses.replace(program, moves=moves, diagnostics=diagnostics)


def stream_program(
    source: str | os.PathLike[str],
    file: str | None = None,
    dialect: str = "auto",
    tools: Mapping[tuple[int, int], ToolEdge | Mapping[str, object]] | None = None,
    tolerances: Tolerances | None = None,
    max_disc: int = 50,
    tool_table: str | os.PathLike[str] | None = None,
    tool_unit: str | ToolUnit = ToolUnit.PROGRAM,
    appr_radius: str = "centre",
    zero_offsets: str | os.PathLike[str] | None = None,
) -> MoveStream:
    """:func:`read_program` as a stream of moves (same arguments, same moves and diagnostics):
    block by block where the controller's reader can run so (``Controller.stream``), else from
    the program read whole. The moves are range-checked as they pass (:mod:`trcopt.nc.stream`)."""
    controller, text, options = _prepared(
        source, file, dialect, tools, tolerances, max_disc, tool_table, tool_unit, appr_radius, zero_offsets
    )
    if controller.stream is None:
        return MoveStream.of(controller.read(text, options))
    return controller.stream(text, options)


def _prepared(
    source: str | os.PathLike[str],
    file: str | None,
    dialect: str,
    tools: Mapping[tuple[int, int], ToolEdge | Mapping[str, object]] | None,
    tolerances: Tolerances | None,
    max_disc: int,
    tool_table: str | os.PathLike[str] | None,
    tool_unit: str | ToolUnit,
    appr_radius: str,
    zero_offsets: str | os.PathLike[str] | None,
) -> tuple[Controller, str, ReadOptions]:
    """The controller, the program text and the reader's options of :func:`read_program`."""
    if isinstance(source, os.PathLike):
        path = os.fspath(source)
        with open(path, "rb") as fh:
            text = decode_program(fh.read(), path)
        file = file or path
    else:
        text = source
    file = file or "<program>"
    controller = detect(file, text) if str(dialect).strip().lower() == "auto" else get(dialect)
    options = ReadOptions(
        file=file,
        tolerances=tolerances or Tolerances(),
        max_disc=int(max_disc),
        tools=tools,
        tool_table=tool_table,
        tool_unit=parse_enum(ToolUnit, tool_unit, "tool unit"),
        appr_radius=appr_radius,
        zero_offsets=zero_offsets,
    )
    return controller, text, options
