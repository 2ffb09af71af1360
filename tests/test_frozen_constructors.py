"""The quick constructors of the frozen records made once per block — ``SourceSpan(...)``,
:func:`trcopt.nc.model.new_move`, :func:`trcopt.path.new_segment` — give the very objects the
dataclass constructor gives: equal, of the same class and hash, frozen, printed, copied, pickled
and replaced alike. ``Line(...)`` is made the same way."""

from __future__ import annotations

import copy
import dataclasses
import pickle

import pytest

from trcopt.errors import SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.primitives import Arc, Line
from trcopt.modes import PathMode, Side
from trcopt.nc.model import CompState, Move, MoveKind, PathControl, new_move
from trcopt.path import Role, Segment, new_segment


def _alike(a: object, b: object) -> None:
    assert type(a) is type(b)
    assert a == b and hash(a) == hash(b) and repr(a) == repr(b)
    assert dataclasses.astuple(a) == dataclasses.astuple(b)  # type: ignore[call-overload]
    assert pickle.loads(pickle.dumps(a)) == b
    assert copy.copy(a) == b and copy.deepcopy(a) == b
    field = dataclasses.fields(a)[0].name  # type: ignore[arg-type]
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(a, field, None)


def _dataclass_made(cls: type, *args: object, **kwargs: object) -> object:
    """What the generated dataclass constructor makes: every field set one by one."""
    obj = object.__new__(cls)
    names = [f.name for f in dataclasses.fields(cls)]
    values = dict(zip(names, args, strict=False))
    values.update(kwargs)
    for f in dataclasses.fields(cls):
        if f.name in values:
            value = values[f.name]
        elif f.default is not dataclasses.MISSING:
            value = f.default
        else:
            value = f.default_factory()  # type: ignore[misc]
        object.__setattr__(obj, f.name, value)
    return obj


def test_source_spans() -> None:
    cases = [
        ((), {}),
        (("p.ngc", 12, 3, "N40"), {}),
        (("p.ngc",), {"line": 4, "machine": (1.0, None, 2.0), "run": 2, "end_column": 9}),
    ]
    for args, kwargs in cases:
        span = SourceSpan(*args, **kwargs)  # type: ignore[arg-type]
        _alike(span, _dataclass_made(SourceSpan, *args, **kwargs))
    span = SourceSpan("p.ngc", 5, 1, "N5")
    assert dataclasses.replace(span, column=7) == SourceSpan("p.ngc", 5, 7, "N5")
    assert span != SourceSpan("p.ngc", 5, 1, None) and span in {SourceSpan("p.ngc", 5, 1, "N5")}


def test_moves() -> None:
    span = SourceSpan("p.ngc", 3, 1)
    comp = CompState(Side.LEFT, 2.5, True)
    control = PathControl(PathMode.BLEND, 0.01, word="G64 P0.01")
    cases = [
        (MoveKind.LINE, (0.0, 1.0, 2.0), (3.0, 4.0, -0.0), Plane.G17, span, comp, 10.0),
        (MoveKind.RAPID, (0.0, 1.0, 2.0), (3.0, 4.0, 5.0), Plane.G18, span, CompState(), None, None, None, 0,
         ("F600", "M3"), None, False, "approach", control),
        (MoveKind.ARC, (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), Plane.G17, span, comp, 5.0, (0.0, 0.0, 0.0), True, 2),
    ]  # fmt: skip
    for args in cases:
        move = new_move(*args)  # type: ignore[arg-type]
        _alike(move, _dataclass_made(Move, *args))
        _alike(move, Move(*args))  # type: ignore[arg-type]
    move = new_move(*cases[0])  # type: ignore[arg-type]
    assert dataclasses.replace(move, turns=1) == Move(*cases[0], turns=1)  # type: ignore[arg-type, misc]


def test_segments() -> None:
    span = SourceSpan("p.ngc", 3, 1)
    line = Line((0.0, 0.0, 0.0), (1.0, 2.0, 3.0))
    arc = Arc((0.0, 0.0), 2.0, 0.5, -1.0, 0.0, 1.0)
    cases = [
        (line, Plane.G17, Role.CONTOUR, span, 10.0),
        (line, Plane.G19, Role.RAPID, span, None, Side.OFF, 0.0),
        (arc, Plane.G17, Role.CORNER, span, 2.0, Side.RIGHT, 1.5),
    ]
    for args in cases:
        seg = new_segment(*args)  # type: ignore[arg-type]
        _alike(seg, _dataclass_made(Segment, *args))
        _alike(seg, Segment(*args))  # type: ignore[arg-type]
        assert seg.with_times(1.0, 2.0) == Segment(*args, t_start_s=1.0, t_end_s=2.0)  # type: ignore[arg-type, misc]


def test_lines() -> None:
    for start, end in [((0.0, 0.0, 0.0), (1.0, 2.0, 3.0)), ((-1.5, 2.0, 0.0), (-1.5, 2.0, 0.0))]:
        line = Line(start, end)
        _alike(line, _dataclass_made(Line, start, end))
        assert line.start is start and line.end is end
        assert dataclasses.replace(line, end=start) == Line(start, start)
        assert Line(end=end, start=start) == line
