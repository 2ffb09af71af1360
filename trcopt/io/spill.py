"""A sequence of segments kept in a temporary file: :class:`SpilledSegments`.

A plan computed window by window (:mod:`trcopt.pipeline.stream`) appends each window's segments
here (one chunk per window, as the columns of :mod:`trcopt.io.segcodec`, or pickled when a chunk
holds a number that is not a float) and the later stages read them back chunk by chunk (the
verification, timing and writers of each window; the G-code writer reads the path twice: to
choose its preamble, then to write it): the memory held is one chunk, whatever the length of the
path.
"""

from __future__ import annotations

import copyreg
import dataclasses
import pickle
import tempfile
from collections.abc import Iterator, Sequence
from typing import IO, Any, overload

from trcopt.errors import SourceSpan
from trcopt.geometry.primitives import Line
from trcopt.path import Segment

__all__ = ["SpilledSegments"]

_SEGMENT = tuple(f.name for f in dataclasses.fields(Segment))
_SPAN = tuple(f.name for f in dataclasses.fields(SourceSpan))


def _made(cls: type, names: tuple[str, ...], values: tuple[Any, ...]) -> Any:
    """An instance of the frozen dataclass ``cls`` with its fields set as pickled (no checks: they
    were checked when it was first made)."""
    obj = object.__new__(cls)
    for name, value in zip(names, values, strict=True):
        object.__setattr__(obj, name, value)
    return obj


def _segment(*values: Any) -> Segment:
    return _made(Segment, _SEGMENT, values)  # type: ignore[no-any-return]


def _span(*values: Any) -> SourceSpan:
    return _made(SourceSpan, _SPAN, values)  # type: ignore[no-any-return]


# the segments, spans and lines as tuples of their fields: the dataclasses' own pickling reads
# their field lists for every object, twice as slow
_DISPATCH = copyreg.dispatch_table.copy()
_DISPATCH.update({
    Segment: lambda s: (_segment, tuple(getattr(s, k) for k in _SEGMENT)),
    SourceSpan: lambda s: (_span, tuple(getattr(s, k) for k in _SPAN)),
    Line: lambda g: (Line, (g.start, g.end)),
})  # fmt: skip


class SpilledSegments(Sequence[Segment]):
    """Segments appended in chunks to a temporary file; iterated (and indexed) from it."""

    def __init__(self) -> None:
        self._file: IO[bytes] = tempfile.TemporaryFile()  # noqa: SIM115 (closed by close())
        self._starts: list[int] = []  # first index of every chunk
        self._offsets: list[int] = []  # file offset of every chunk
        self._n = 0
        self._cache: tuple[int, list[Segment]] | None = None

    def append(self, segments: Sequence[Segment]) -> None:
        if not segments:
            return
        self._file.seek(0, 2)
        self._starts.append(self._n)
        self._offsets.append(self._file.tell())
        from trcopt.io.segcodec import encode

        chunk = list(segments)
        columns = encode(chunk)
        pickler = pickle.Pickler(self._file, protocol=pickle.HIGHEST_PROTOCOL)
        pickler.dispatch_table = _DISPATCH
        pickler.dump(chunk if columns is None else columns)
        self._n += len(chunk)

    def __len__(self) -> int:
        return self._n

    def _chunk(self, k: int) -> list[Segment]:
        if self._cache is not None and self._cache[0] == k:
            return self._cache[1]
        self._file.seek(self._offsets[k])
        chunk: Any = pickle.load(self._file)
        if isinstance(chunk, tuple):
            from trcopt.io.segcodec import decode

            chunk = decode(*chunk)
        self._cache = (k, chunk)
        return chunk

    def __iter__(self) -> Iterator[Segment]:
        for k in range(len(self._offsets)):
            yield from self._chunk(k)

    def chunks(self) -> Iterator[list[Segment]]:
        """The chunks as they were appended (each read from the file as it is reached)."""
        for k in range(len(self._offsets)):
            yield self._chunk(k)

    @overload
    def __getitem__(self, i: int) -> Segment: ...
    @overload
    def __getitem__(self, i: slice) -> list[Segment]: ...
    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(self._n))]
        if i < 0:
            i += self._n
        if not 0 <= i < self._n:
            raise IndexError(i)
        import bisect

        k = bisect.bisect_right(self._starts, i) - 1
        return self._chunk(k)[i - self._starts[k]]

    def close(self) -> None:
        self._cache = None
        self._file.close()
