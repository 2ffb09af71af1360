"""Progress of long stages: a small interface the stages call, a terminal display the CLI installs.

The stages of a plan (:mod:`trcopt.pipeline`, the corner optimisation) announce what they do with
:func:`stage` (a context manager giving an ``advance(n)`` callable) or :func:`iterate` (a loop
over items); nothing is shown unless a :class:`Reporter` is installed with :func:`reporting`, so
the library stays silent by default and pays one context-variable look-up per stage.

The command line installs :func:`terminal_reporter`: one status line on standard error, only when
it is a terminal, naming the stages running now (``planning › corners (optimal) › corner problems
3/12``, with tqdm's bar and estimate), shown only once the outermost stage has run for
:data:`DELAY_S` seconds (quick plans print nothing) and cleared when it ends. Worker processes
report nothing; their results are counted as they come back.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from typing import IO, Any, Protocol, TypeVar

__all__ = ["DELAY_S", "Reporter", "Task", "iterate", "reporting", "stage", "terminal_reporter"]

DELAY_S = 2.0  # a stage is shown once it has run this long
REFRESH_S = 0.5  # the elapsed time of a shown stage is refreshed this often, ticks or not

T = TypeVar("T")


class Task(Protocol):
    """One running stage: ``advance(n)`` counts work done, ``close()`` ends it."""

    def advance(self, n: int = 1) -> None: ...

    def close(self) -> None: ...


class Reporter(Protocol):
    """Shows stages: ``start(what, total)`` returns the :class:`Task` of a new stage (``total``
    None when the amount of work is not known)."""

    def start(self, what: str, total: int | None = None) -> Task: ...


_CURRENT: contextvars.ContextVar[Reporter | None] = contextvars.ContextVar("trcopt_progress", default=None)


def _nothing(n: int = 1) -> None:
    return None


@contextlib.contextmanager
def reporting(reporter: Reporter | None) -> Iterator[Reporter | None]:
    """Install ``reporter`` for the stages run inside the block (None: report nothing)."""
    token = _CURRENT.set(reporter)
    try:
        yield reporter
    finally:
        _CURRENT.reset(token)


@contextlib.contextmanager
def stage(what: str, total: int | None = None) -> Iterator[Callable[[int], None]]:
    """A stage of work called ``what``; yields ``advance(n)`` (a no-op without a reporter)."""
    reporter = _CURRENT.get()
    if reporter is None:
        yield _nothing
        return
    task = reporter.start(what, total)
    try:
        yield task.advance
    finally:
        task.close()


def iterate(items: Iterable[T], what: str, total: int | None = None) -> Iterator[T]:
    """The items of ``items``, counted as a stage ``what`` (``total`` defaults to ``len(items)``)."""
    if total is None and hasattr(items, "__len__"):
        total = len(items)  # type: ignore[arg-type]
    with stage(what, total) as advance:
        for item in items:
            yield item
            advance(1)


class _Line:
    """A stage on the terminal line: its name, its count and its total."""

    def __init__(self, owner: TerminalReporter, what: str, total: int | None) -> None:
        self.owner, self.what, self.total, self.n = owner, what, total, 0
        self.start = time.monotonic()

    def advance(self, n: int = 1) -> None:
        self.n += n
        self.owner._draw(throttle=True)

    def close(self) -> None:
        self.owner._end(self)


class _Silent:
    def advance(self, n: int = 1) -> None:
        return None

    def close(self) -> None:
        return None


class TerminalReporter:
    """One status line on ``stream`` for the stages running now (outermost first, the innermost
    with its count, bar and estimate by :func:`tqdm.tqdm.format_meter`), shown once the outermost
    has run ``delay`` seconds, refreshed by a background thread and cleared when it ends."""

    def __init__(self, stream: IO[str], delay: float = DELAY_S) -> None:
        self.stream = stream
        self.delay = delay
        self.pid = os.getpid()
        self._stack: list[_Line] = []
        self._lock = threading.RLock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._t0 = self._drawn_at = 0.0
        self._shown = False

    def start(self, what: str, total: int | None = None) -> Task:
        if os.getpid() != self.pid:  # a forked worker inherited the reporter: it shows nothing
            return _Silent()
        task = _Line(self, what, total)
        with self._lock:
            if not self._stack:
                self._t0 = task.start
                self._stop.clear()
                self._thread = threading.Thread(target=self._run, name="trcopt-progress", daemon=True)
                self._thread.start()
            self._stack.append(task)
        self._draw()
        return task

    def _end(self, task: _Line) -> None:
        with self._lock:
            if task in self._stack:
                self._stack.remove(task)
            last = not self._stack
            thread = self._thread
        if last and thread is not None:
            self._stop.set()
            if thread is not threading.current_thread():
                thread.join()
            with self._lock:
                if self._shown:
                    self._write("\r\x1b[K")
                    self._shown = False

    def _run(self) -> None:
        while not self._stop.wait(REFRESH_S):
            self._draw()

    def _draw(self, throttle: bool = False) -> None:
        from shutil import get_terminal_size

        from tqdm import tqdm

        with self._lock:
            now = time.monotonic()
            if not self._stack or now - self._t0 < self.delay or (throttle and now - self._drawn_at < 0.1):
                return
            top = self._stack[-1]
            width = max(40, get_terminal_size().columns - 1)
            names = _fit([t.what for t in self._stack], max(24, width - (45 if top.total else 10)))
            if top.total:
                line = tqdm.format_meter(min(top.n, top.total), top.total, now - top.start, ncols=width, prefix=names)
            else:
                line = f"{names} [{tqdm.format_interval(now - self._t0)}]"
            self._write("\r" + line[:width] + "\x1b[K")
            self._shown, self._drawn_at = True, now

    def _write(self, text: str) -> None:
        try:
            self.stream.write(text)
            self.stream.flush()
        except (OSError, ValueError):  # the terminal went away: show nothing more
            self._stack.clear()


def _fit(names: list[str], room: int) -> str:
    """The stage names joined outermost first; when they do not fit in ``room`` characters the
    outer ones give way first (``… › corners (optimal) › corner problems``), so the stage running
    now is always shown."""
    joined = " › ".join(names)
    while len(joined) > room and len(names) > 1:
        names = names[1:]
        joined = "… › " + " › ".join(names)
    return joined


def terminal_reporter(stream: Any = None, *, quiet: bool = False, delay: float | None = None) -> Reporter | None:
    """Progress bars on ``stream`` (standard error by default) when it is a terminal and not
    ``quiet`` and tqdm is installed, each shown after ``delay`` s (default :data:`DELAY_S`);
    None (report nothing) otherwise."""
    import sys

    delay = DELAY_S if delay is None else delay

    stream = sys.stderr if stream is None else stream
    if quiet:
        return None
    try:
        if not stream.isatty():
            return None
        import tqdm  # noqa: F401
    except (AttributeError, ValueError, ImportError):  # no isatty, a closed stream, no tqdm
        return None
    return TerminalReporter(stream, delay)

