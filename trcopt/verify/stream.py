"""The verification of a plan read in windows, with bounded memory: :class:`StreamVerifier`.

    v = StreamVerifier(settings, tolerance=1e-6, near_tangent_rad=..., part=programmed_segments)
    for programmed_chunk, toolpath_chunk, moves_chunk in windows:   # consecutive pieces
        v.add(programmed_chunk, toolpath_chunk, moves_chunk)
    report = v.finish()

``report`` equals :func:`~trcopt.verify.plan.verify_plan` of the whole lists, for any cut points.

**Clearance is exact by knowing the part in advance.** ``part`` is every programmed segment of
the plan, in order, or their :class:`~trcopt.verify.store.ProgramStore` (read before the windows
are verified; the programmed chunks must add up to the same list): it is kept as those compact
columns and a ``float32`` grid over the part candidates (:class:`~trcopt.verify.cellgrid.CompactGrid`, built
at the first window that needs it), so each tool-path window is measured against the
whole part when it arrives — elements of later blocks included — and no tool-path segment is
kept. Whether an element is part contour (its block compensated, not a lead block) is known from
the tool path read so far (:class:`~trcopt.verify.runs.LineFacts`); the few measurements that
depend on what comes later (the blocks ahead, the first and last blocks of a run whose leads and
closing are known when it ends) wait, with their segments, until it is known.

The other families are local: each window is evaluated with the two segments before it and the
one after it (a window's last segments, up to its last one that is not a corner, wait for the
next window), by the whole-array functions of :mod:`trcopt.verify.families`. Every family keeps
its largest residual and its first segment, which does not depend on the order the windows
come in.

Without ``part``, or for a program whose source lines decrease (subprograms, repetitions, loops),
the windows are kept and verified at :meth:`StreamVerifier.finish` by ``verify_plan`` itself (the
same report, memory as before).
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Sequence
from types import SimpleNamespace
from typing import Any

import numpy as np

from trcopt.path import Role, Segment
from trcopt.verify.batch import KINDS, continuation_table
from trcopt.verify.cellgrid import CompactGrid
from trcopt.verify.contour import Closing
from trcopt.verify.families import LEADS, arc_radius, contact_arrays, joint_arrays, sar_for
from trcopt.verify.plan import verify_plan
from trcopt.verify.report import FAMILIES, FamilyResidual, VerificationReport
from trcopt.verify.runs import LineFacts
from trcopt.verify.store import ProgramStore
from trcopt.verify.streamparts import Best, Clearance, Notes, Reversal

__all__ = ["StreamVerifier"]

_CONTEXT = 2  # segments before a window that its joints and continuations read


class StreamVerifier:
    """Incremental :func:`~trcopt.verify.plan.verify_plan` (see the module docstring)."""

    def __init__(self, settings: Any = None, tolerance: float = 1e-6, near_tangent_rad: float = 0.0,
                 part: Iterable[Segment] | ProgramStore | None = None) -> None:  # fmt: skip
        t0 = time.perf_counter()
        self.settings, self.tolerance, self.near = settings, tolerance, near_tangent_rad
        self.store = part if isinstance(part, ProgramStore) or part is None else ProgramStore(part)
        self._buffer: tuple[list, list, list] | None = None
        if self.store is None or not self.store.monotone:
            self.store, self._buffer = None, ([], [], [])
            self._seconds = time.perf_counter() - t0
            return
        self.facts = LineFacts(self.store)
        self.specs: dict[int, Any] = {}
        self.n = 0  # tool-path segments read
        self.done = 0  # tool-path segments evaluated
        self.n_programmed = 0
        self.waiting: list[Segment] = []  # read, not evaluated (from index self.done)
        self.context: list[Segment] = []  # the last evaluated ones
        self.best = {name: Best() for name in ("radius", "contact_tangency", "joint_tangency", "continuity")}
        self.reversal = Reversal()
        self.clear = Clearance(self)
        self.notes = Notes()
        self.held_arcs: list[tuple[int, Segment]] = []
        self.grid: CompactGrid | None = None
        self.after_approach = False  # the last evaluated segment is an approach or a corner after one
        self._seconds = time.perf_counter() - t0

    # ---- input ------------------------------------------------------------------------------

    @property
    def streaming(self) -> bool:
        """Whether the windows are evaluated as they come (with ``part``): the programmed pieces
        may then be given as their numbers of segments (the part is known)."""
        return self._buffer is None

    def add(self, programmed: Sequence[Segment] | int, toolpath: Sequence[Segment],
            moves: Sequence[Any] | None = None) -> None:  # fmt: skip
        """The next piece of each list (programmed segments, or their number when
        :attr:`streaming`; tool-centre segments; moves)."""
        t0 = time.perf_counter()
        if self._buffer is not None:
            if isinstance(programmed, int):
                raise TypeError("programmed segments are needed without the part")
            for out, piece in zip(self._buffer, (programmed, toolpath, moves or ()), strict=True):
                out.extend(piece)
        else:
            self._read(programmed, toolpath, moves)
            self._evaluate(final=False)
        self._seconds += time.perf_counter() - t0

    def _read(self, programmed: Sequence[Segment] | int, toolpath: Sequence[Segment],
              moves: Sequence[Any] | None) -> None:  # fmt: skip
        self.n_programmed += programmed if isinstance(programmed, int) else len(programmed)
        for m in moves or ():
            sar = getattr(m, "sar", None)
            if sar is not None:
                self.specs[m.span.line] = sar
        if not toolpath:
            return
        lines = np.fromiter((s.span.line for s in toolpath), np.int64, len(toolpath))
        on = np.fromiter((s.radius > 0.0 and s.role in (Role.CONTOUR, Role.CORNER) for s in toolpath), bool,
                         len(toolpath))  # fmt: skip
        before = len(self.facts.ended)
        self.facts.read(on, lines, self.n)
        self.clear.keep(toolpath, self.n, self.facts.ended[before:])
        self.waiting.extend(toolpath)
        self.n += len(toolpath)

    # ---- evaluation -------------------------------------------------------------------------

    def _evaluate(self, final: bool) -> None:
        """Evaluate the waiting segments up to the last one that is not a corner (all when
        ``final``), with the one after them as context."""
        w = self.waiting
        if final:
            upto = len(w)
        else:
            upto = next((j for j in range(len(w) - 1, -1, -1) if w[j].role is not Role.CORNER), 0)
        if upto > 0:
            self._window(self.context + w[: upto + 1], len(self.context), upto)
            self.context = (self.context + w[:upto])[-_CONTEXT:]
            self.done += upto
            del w[:upto]
        self.clear.settle()
        self._settle_arcs()

    def _window(self, segs: list[Segment], c0: int, count: int) -> None:
        """Evaluate ``segs[c0 : c0 + count]`` (global indices from ``self.done``)."""
        from trcopt.verify.table import SegmentTable

        store, facts = self.store, self.facts
        assert store is not None
        tool = SegmentTable(segs)
        local = np.arange(c0, c0 + count)
        ks = self.done + local - c0
        lines = tool.line
        # the programmed rows the window reads: its lines, the next line with elements, closings
        top = int(lines.max())
        nxt = store.next_line(top)
        a, b = store.rows_of(int(lines.min()), int(max(top, nxt)))
        rows = np.arange(a, b)
        firsts = [facts.closings[ln] for ln in set(lines.tolist()) if ln in facts.closings]
        if firsts:
            extra = np.concatenate([np.arange(*store.rows_of(f, f)) for f in firsts])
            rows = np.unique(np.concatenate((rows, extra)))
        prog = store.table(rows)
        comp_rows = np.nonzero(store.star[rows])[0]
        comp = store.table(rows[comp_rows])
        closings = [Closing(f, last) for last, f in facts.closings.items() if last in set(lines.tolist())]
        conts = continuation_table(tool, prog, self.near, closings)
        compensated = _Lazy(store, rows[comp_rows])

        held_local: list[int] = []

        def nearest(centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            dv, held = self._nearest(centres)
            return dv, held

        radius, tangent, has_r, has_t, held = contact_arrays(tool, prog, comp, conts, nearest, segs, compensated,
                                                             self.specs)  # fmt: skip
        sel = slice(c0, c0 + count)
        self.best["radius"].offer(radius[sel][has_r[sel]], ks[has_r[sel]], segs, self.done - c0)
        self.best["contact_tangency"].offer(tangent[sel][has_t[sel]], ks[has_t[sel]], segs, self.done - c0)
        held_local = local[held[sel]].tolist()
        self.held_arcs += [(self.done + j - c0, segs[j]) for j in held_local]
        gap, jrows, jvals = joint_arrays(tool, prog, comp, conts, segs, self.specs)
        if len(gap):
            b_all = np.arange(1, len(segs))
            inside = (b_all >= c0) & (b_all < c0 + count)
            self.best["continuity"].offer(gap[inside], self.done + b_all[inside] - c0, segs, self.done - c0)
            inside = (jrows >= c0) & (jrows < c0 + count)
            self.best["joint_tangency"].offer(jvals[inside], self.done + jrows[inside] - c0, segs, self.done - c0)
        lead_fixed = self._lead_fixed(segs, tool, c0, count)
        self.reversal.take(segs, tool, c0, count, self.done, self.specs)
        self.clear.window(segs, tool, c0, count, prog, rows, conts, lead_fixed)

    def _lead_fixed(self, segs: list[Segment], tool: Any, c0: int, count: int) -> np.ndarray:
        """Which segments of the window are lead moves whatever the lead blocks: approach and
        retraction without SAR, the corners after an approach and before a retraction."""
        out = np.zeros(count, bool)
        n = len(segs)
        for j in range(c0, c0 + count):
            seg = segs[j]
            role = seg.role
            if role is Role.CORNER:
                out[j - c0] = self.after_approach
                if not self.after_approach:
                    i = j + 1
                    while i < n and segs[i].role is Role.CORNER:
                        i += 1
                    out[j - c0] = i < n and segs[i].role is Role.RETRACT
            else:
                self.after_approach = role is Role.APPROACH
                if role in LEADS:
                    out[j - c0] = sar_for(seg.span.line, self.specs, role) is None
        return out

    def _nearest(self, centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The distance of each point (m×2) to the nearest vertex of a compensated programmed
        element, and which are not final (a nearer vertex of a block not settled yet)."""
        m = len(centres)
        out, held = np.full(m, np.inf), np.zeros(m, bool)
        grid = self._grid(0.0)
        if m == 0 or len(grid.boxes) == 0:
            return out, held
        store = self.store
        assert store is not None
        todo = np.arange(m)
        r = grid.cell
        far = np.hypot(centres[:, 0] - grid.origin[0], centres[:, 1] - grid.origin[1]) + grid.extent()
        while todo.size:
            c = centres[todo]
            q, j = grid.near_many(np.column_stack((c, c)), np.full(len(todo), r))
            value, final = self.facts.compensated(store.line[j])
            d = np.hypot(store.sx[j] - c[q, 0], store.sy[j] - c[q, 1])
            best, unsure = np.full(len(todo), np.inf), np.full(len(todo), np.inf)
            sure = value & final
            np.minimum.at(best, q[sure], d[sure])
            np.minimum.at(unsure, q[~final], d[~final])
            done = (best <= r) | (r >= far[todo])
            i = todo[done]
            out[i], held[i] = best[done], unsure[done] < best[done]
            todo = todo[~done]
            r *= 2.0
        return out, held

    def _grid(self, margin: float) -> CompactGrid:
        if self.grid is None:
            store = self.store
            assert store is not None
            self.grid = CompactGrid(store.boxes, store.part_rows(), margin)
        return self.grid

    def _settle_arcs(self) -> None:
        if not self.held_arcs:
            return
        centres = np.array([(s.geometry.center[0], s.geometry.center[1]) for _, s in self.held_arcs], float)
        dv, held = self._nearest(centres)
        keep = []
        for (k, seg), d, h in zip(self.held_arcs, dv.tolist(), held.tolist(), strict=True):
            if h:
                keep.append((k, seg))
                continue
            value = arc_radius(seg, d, self.specs)
            if value is not None:
                self.best["radius"].offer(np.array([value]), np.array([k]), [seg], k)
        self.held_arcs = keep

    # ---- the report -------------------------------------------------------------------------

    def finish(self) -> VerificationReport:
        """The report of the whole plan (:func:`~trcopt.verify.plan.verify_plan`'s)."""
        t0 = time.perf_counter()
        if self._buffer is not None:
            programmed, toolpath, moves = self._buffer
            report = verify_plan(programmed, toolpath, moves, self.settings, tolerance=self.tolerance,
                                 near_tangent_rad=self.near)  # fmt: skip
            report.seconds += self._seconds
            return report
        store = self.store
        assert store is not None
        if self.n_programmed != store.n:
            raise ValueError(f"the programmed pieces ({self.n_programmed}) are not the part ({store.n} segments)")
        self._evaluate(final=True)
        before = len(self.facts.ended)
        self.facts.finish(self.n)
        self.clear.keep([], self.n, self.facts.ended[before:])
        self.clear.settle()
        self._settle_arcs()
        self.reversal.close(self.specs)
        fam = {name: FamilyResidual(name) for name in FAMILIES}
        self.best["radius"].into(fam["radius"])
        self.best["continuity"].into(fam["continuity"])
        Best.then(self.best["contact_tangency"], self.best["joint_tangency"]).into(fam["tangency"])
        self.reversal.result().into(fam["no_reversal"])
        notes: list[str] = []
        if self.clear.any_part():
            self.clear.best["clearance"].into(fam["clearance"])
            self.clear.best["lead_clearance"].into(fam["lead_clearance"])
            for kind, amount, span in self.clear.notes.ordered():
                if amount > self.tolerance:
                    notes.append(_note(KINDS[kind], amount, span, self.near))
        if self.settings is not None and getattr(self.settings, "wab_clearance_tolerance_mm", None) is not None:
            if fam["no_reversal"].max_residual > 0.0:
                notes.append(
                    f"no_reversal {fam['no_reversal'].max_residual:.6g} mm "
                    f"(controller snap tolerance MD20204 = {self.settings.wab_clearance_tolerance_mm} mm)"
                )
        return VerificationReport(fam, self.tolerance, self._seconds + time.perf_counter() - t0, notes)


def _note(kind: str, amount: float, span: Any, near_tangent_rad: float) -> str:
    from trcopt.verify.families import _allowed_note

    return _allowed_note(kind, amount, SimpleNamespace(span=span), near_tangent_rad)  # type: ignore[arg-type]


class _Lazy:
    """The compensated programmed segments of some rows, made only when iterated."""

    def __init__(self, store: ProgramStore, rows: np.ndarray) -> None:
        self.store, self.rows = store, rows

    def __iter__(self) -> Any:
        return (self.store.segment(int(r)) for r in self.rows.tolist())

    def __len__(self) -> int:
        return len(self.rows)

    def of_lines(self, lines: set[int]) -> Any:
        rows = self.rows[np.isin(self.store.line[self.rows], np.fromiter(lines, np.int64, len(lines)))]
        return (self.store.segment(int(r)) for r in rows.tolist())

