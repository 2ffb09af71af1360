"""The :class:`Controller` record: everything the pipeline needs from one controller.

A controller owns its language (the reader), its lead handling where the language has one as a
separate pass (SINUMERIK SAR), its tool-table format (read inside the reader), its compensation
semantics and its output flavour. The registry in :mod:`trcopt.controllers` is the only place
that knows the controllers by name.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import Any

from trcopt.config import TrcSettings
from trcopt.errors import Diagnostic
from trcopt.io.gcode import GcodeFlavor
from trcopt.nc.modal import ReadOptions
from trcopt.nc.model import Move, NcProgram
from trcopt.nc.stream import MoveStream
from trcopt.path import Segment

__all__ = ["Controller", "ReadFn", "StreamFn", "LeadPassFn", "CompensateFn", "deferred"]

ReadFn = Callable[[str, ReadOptions], NcProgram]
"""Program text → canonical moves; never raises for a problem in the program (diagnostics)."""

StreamFn = Callable[[str, ReadOptions], MoveStream]
"""Program text → its moves as they are read (:class:`~trcopt.nc.stream.MoveStream`)."""

LeadPassFn = Callable[[Iterable[Move], TrcSettings, list[Diagnostic]], Iterator[Move]]
"""Canonical moves with lead blocks → canonical moves the compensation engine runs as programmed."""

CompensateFn = Callable[[Iterable[Move], TrcSettings, list[Diagnostic], bool], Iterator[Segment]]
"""``(moves, settings, diagnostics, complete)`` → tool-centre segments; an alarm stops the stream."""


class deferred:  # noqa: N801 - used as a function
    """The function ``name`` of ``module``, imported when it is first called: a controller's
    reader and compensation load with the first program of that controller, not with the
    registry (a short run's start-up is mostly imports). Picklable, like the function itself."""

    __slots__ = ("module", "name")

    def __init__(self, module: str, name: str) -> None:
        self.module, self.name = module, name

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return getattr(importlib.import_module(self.module), self.name)(*args, **kwargs)

    def __repr__(self) -> str:
        return f"deferred({self.module!r}, {self.name!r})"


@dataclass(frozen=True, slots=True)
class Controller:
    """One controller: its names, how to recognise its programs, and its stages.

    Parameters
    ----------
    name:
        Registry name (``--profile``, ``--gcode-flavor``), lower case.
    dialect:
        Name of its program language (``--dialect``, the plan JSON's ``dialect``).
    title:
        Human-readable name for messages and documentation.
    extensions:
        File suffixes of its programs, lower case with the dot (``.mpf``).
    read:
        The program reader.
    compensate:
        Its tool radius compensation.
    gcode:
        Its flavour of plain tool-centre G-code.
    leads:
        A pass that expands lead blocks into ordinary moves before compensation (``None``: the
        reader already produced ordinary moves).
    recognise:
        Recognises its programs by their text when the file suffix says nothing (``None``: never
        claims a program by its text).
    stream:
        The reader run block by block (``None``: the reader cannot stream; the program is read
        whole and its moves are streamed from the list).
    near_tangent_rad:
        Its compensation leaves joints whose programmed turn is at most this (rad) as they are: the
        next line starts where the tool is (LinuxCNC 0.05; 0: every joint is compensated). The
        verification measures those lines against that construction.
    verified_path:
        ``(tool path, moves)`` → the path the verification measures against the programmed
        contour, where the controlled point is not the tool centre (LinuxCNC lathe tools: their
        tip); ``None``: the tool path itself.
    """

    name: str
    dialect: str
    title: str
    extensions: tuple[str, ...]
    read: ReadFn
    compensate: CompensateFn
    gcode: GcodeFlavor
    leads: LeadPassFn | None = None
    recognise: Callable[[str], bool] | None = None
    near_tangent_rad: float = 0.0
    stream: StreamFn | None = None
    verified_path: Callable[[list[Segment], list[Move]], list[Segment]] | None = None

    def claims(self, text: str) -> bool:
        """True if ``text`` looks like a program of this controller."""
        return self.recognise is not None and self.recognise(text)
