"""The state :class:`~trcopt.verify.stream.StreamVerifier` keeps between windows: the largest
residual of a family (:class:`Best`), the no-reversal runs (:class:`Reversal`), the notes of the
clearance limits (:class:`Notes`) and the clearance measurements (:class:`Clearance`), the ones
that wait for a later window included."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from trcopt.path import Role, Segment
from trcopt.verify.batch import KINDS
from trcopt.verify.families import COMPENSATED_ROLES, LEADS
from trcopt.verify.joints import SAME_POINT_MM
from trcopt.verify.model import points_distance, reversal_residual
from trcopt.verify.report import FamilyResidual
from trcopt.verify.table import ROLE, fmap, py_max

__all__ = ["Best", "Clearance", "Notes", "Reversal"]

_KEY = 1 << 31  # key of a pair: segment · _KEY + programmed row


class Best:
    """The largest residual of a family and its first segment (:meth:`FamilyResidual.add` in
    path order), from values offered in any order."""

    __slots__ = ("value", "k", "span", "checks")

    def __init__(self) -> None:
        self.value, self.k, self.span, self.checks = 0.0, None, None, 0

    def offer(self, values: np.ndarray, ks: np.ndarray, segs: Any, base: int) -> None:
        """Values at segments ``ks`` (ascending; ``segs[k - base]`` is segment k)."""
        m = len(values)
        if m == 0:
            return
        self.checks += m
        ok = np.nonzero(values >= 0.0)[0]
        if ok.size == 0:
            return
        top = values[ok].max()
        j = int(ok[np.argmax(values[ok] == top)])
        v, k = float(values[j]), int(ks[j])
        if self.k is None or v > self.value or (v == self.value and k < self.k):
            self.value, self.k, self.span = v, k, segs[k - base].span

    @staticmethod
    def then(a: Best, b: Best) -> Best:
        """``a``'s values added before ``b``'s."""
        out = b if a.k is None or (b.k is not None and b.value > a.value) else a
        res = Best()
        res.value, res.k, res.span, res.checks = out.value, out.k, out.span, a.checks + b.checks
        return res

    def into(self, f: FamilyResidual) -> None:
        f.checks = self.checks
        if self.k is not None:
            f.max_residual, f.segment = self.value, self.k
            f.block, f.line, f.span = self.span.block, self.span.line, self.span


class Notes:
    """Per limit kind: the first pair where a limit lets the tool nearer than R, and the largest
    such amount with its segment (the notes of ``verify_plan``'s clearance)."""

    def __init__(self) -> None:
        self.first: dict[int, int] = {}
        self.best: dict[int, tuple[float, int, Any]] = {}

    def offer(self, kind: np.ndarray, e: np.ndarray, key: np.ndarray, span_of: Any) -> None:
        for code in np.flatnonzero(np.bincount(kind, minlength=len(KINDS))).tolist():  # the kinds present
            sel = (kind == code) & (e > 0.0)
            if not sel.any():
                continue
            ek, kk = e[sel], key[sel]
            self.first[code] = min(self.first.get(code, int(kk.min())), int(kk.min()))
            top = ek.max()
            at = int(kk[ek == top].min())
            old = self.best.get(code)
            if old is None or top > old[0] or (top == old[0] and at < old[1]):
                self.best[code] = (float(top), at, span_of(at // _KEY))

    def ordered(self) -> list[tuple[int, float, Any]]:
        return [(code, self.best[code][0], self.best[code][2]) for code in sorted(self.first, key=self.first.get)]


class Reversal:
    """The ``no_reversal`` values: the SAR blocks (in the order of the moves) and the runs of
    approach or retraction segments (in path order)."""

    def __init__(self) -> None:
        self.runs = Best()
        self.sar: dict[int, list[Any]] = {}  # line → [first k, span, start w, end ws]
        self.open: list[Any] | None = None  # run: [k, role, span, ws]
        self.ext: set[int] = set()  # SAR approach lines whose lead contour goes on
        self.result_best: Best | None = None

    def take(self, segs: list[Segment], tool: Any, c0: int, count: int, done: int, specs: dict[int, Any]) -> None:
        lines = tool.line
        spec_lines = np.fromiter(specs, np.int64, len(specs))
        mask = np.isin(tool.role, [ROLE[r] for r in LEADS]) | np.isin(lines, spec_lines)
        look = mask.copy()
        look[1:] |= mask[:-1]
        look[c0] = True
        for j in np.nonzero(look[c0 : c0 + count])[0].tolist():
            j += c0
            seg, k = segs[j], done + j - c0
            line, role = int(lines[j]), seg.role
            prev = int(lines[j - 1]) if j > 0 else None
            if prev is not None and prev != line and prev in specs and specs[prev].contour.is_approach:
                self.ext.add(prev)
            used = line in specs
            if role is Role.APPROACH:
                for s in self.ext:
                    self.sar[s][3].append(float(tool.ez[j]))
                used = used or bool(self.ext)
            else:
                self.ext.clear()
            if line in specs:
                rec = self.sar.setdefault(line, [k, seg.span, float(tool.sz[j]), []])
                rec[3].append(float(tool.ez[j]))
            run = self.open
            if run is not None and run[1] is role and not used:
                run[3].append(float(tool.ez[j]))
                continue
            if run is not None:
                self._close()
            if role in LEADS and not used:
                self.open = [k, role, seg.span, [float(tool.sz[j]), float(tool.ez[j])]]

    def _close(self) -> None:
        k, _, span, ws = self.open  # type: ignore[misc]
        self.runs.offer(np.array([reversal_residual(ws)]), np.array([k]), [SpanOnly(span)], k)
        self.open = None

    def close(self, specs: dict[int, Any]) -> None:
        if self.open is not None:
            self._close()
        sar = Best()
        for line, spec in specs.items():
            rec = self.sar.get(line)
            if rec is None:
                continue
            k, span, w0, ends = rec
            ws = ends if spec.contour.is_approach else [w0, *ends[:-1]]
            value = reversal_residual(ws)
            one = Best()
            one.offer(np.array([value]), np.array([k]), [SpanOnly(span)], k)
            sar = Best.then(sar, one)
        self.result_best = Best.then(sar, self.runs)

    def result(self) -> Best:
        assert self.result_best is not None
        return self.result_best


@dataclass(slots=True)
class SpanOnly:
    span: Any


@dataclass(slots=True)
class _Waiting:
    """A measured segment whose clearance waits: its pairs nearer than R (row, distance), their
    near-tangent limits so far, the continuation at it whose following element is not known."""

    k: int
    span: Any
    radius: float
    line: int
    lead_fixed: bool
    rows: np.ndarray
    dist: np.ndarray
    near: np.ndarray
    cont: tuple[float, int, int] | None  # (limit, programmed row, next row by line)


class Clearance:
    """``clearance`` and ``lead_clearance`` of the windows, and the notes of the limits."""

    def __init__(self, owner: Any) -> None:  # the StreamVerifier
        self.v = owner
        self.best = {"clearance": Best(), "lead_clearance": Best()}
        self.notes = Notes()
        self.waiting: list[_Waiting] = []
        self.kept: dict[int, Segment] = {}  # segments around the edges of the open run
        self.lead_fixed: dict[int, bool] = {}
        self.runs: list[Any] = []  # ended runs whose closing limits are not computed yet
        self.limits: dict[tuple[int, int], float] = {}
        self.last: Segment | None = None

    def keep(self, segs: Any, k0: int, ended: list[Any]) -> None:
        """Keep the segments the closing limits may read (around the blocks at a run's ends)."""
        facts = self.v.facts
        if self.last is not None:
            self.kept.setdefault(k0 - 1, self.last)
        for j, s in enumerate(segs):
            self.kept[k0 + j] = s
        if segs:
            self.last = segs[-1]
        for r in ended:
            if r.closing is not None:
                r.segments = {k: s for k, s in self.kept.items() if r.start - 1 <= k <= r.end}
                self.runs.append(r)
        if facts.run_start < 0 or not facts.head:
            self.kept.clear()
        else:
            start, head, tail = facts.run_start - 1, facts.head[-1], facts.tail[0]
            for k in [k for k, s in self.kept.items() if k < start or head < s.span.line < tail]:
                del self.kept[k]
        need = set(self.kept).union(*(r.segments for r in self.runs))
        for k in [k for k in self.lead_fixed if k not in need]:
            del self.lead_fixed[k]

    def wait_lines(self) -> set[int]:
        return self.v.facts.open_lines().union(*(r.lines for r in self.runs))

    def window(self, segs: list[Segment], tool: Any, c0: int, count: int, prog: Any, rows: np.ndarray, conts: Any,
               lead_fixed: np.ndarray) -> None:  # fmt: skip
        v, facts, store = self.v, self.v.facts, self.v.store
        done = v.done
        need = set(self.kept).union(*(r.segments for r in self.runs))
        for j in range(count):
            if done + j in need:
                self.lead_fixed[done + j] = bool(lead_fixed[j])
        local = np.arange(c0, c0 + count)
        meas = local[(tool.radius[local] > 0.0) & (tool.plen[local] > 0.0) & tool.roles(*COMPENSATED_ROLES)[local]]
        if meas.size == 0:
            return
        R = tool.radius
        grid = v._grid(float(R[meas].max()))
        q, pj = grid.near_many(tool.bboxes(meas), R[meas])
        pk = meas[q]
        urows, inv = np.unique(pj, return_inverse=True)
        part = store.table(urows)
        d = pair_distances_of(tool, part, pk, inv, segs, store, urows)
        near_r = d < R[pk]
        pk, pj, d = pk[near_r], pj[near_r], d[near_r]
        pv, pd = facts.part(store.line[pj])
        # near-tangent limits (batch.pair_limits): the continuations at k and k + 1
        row = np.full(len(tool) + 1, -1)
        row[conts.k] = np.arange(len(conts))
        lim = R[conts.k] * fmap(math.cos, conts.turn)
        prev_g, prog_g = rows[conts.previous], rows[conts.programmed]
        fol_g = np.where(conts.following >= 0, rows[np.maximum(conts.following, 0)], -1)
        wait = self.wait_lines()
        unsure_line = np.isin(tool.line, np.fromiter(wait, np.int64, len(wait)))
        near = np.full(len(pk), np.inf)
        for r, ends in ((row[pk], True), (row[pk + 1], False)) if len(conts) else ():
            c = np.maximum(r, 0)
            hit = (pj == prev_g[c]) | (pj == prog_g[c])
            if ends:
                hit |= (pj == fol_g[c]) & ~unsure_line[pk]
            ok = (r >= 0) & hit & ~(lim[c] >= R[pk]) & (lim[c] < near)
            near = np.where(ok, lim[c], near)
        lv, ld = facts.lead(tool.line[meas])
        slot = np.searchsorted(meas, pk)
        has_pair = np.zeros(len(meas), bool)
        has_pair[slot] = True
        unsure = np.zeros(len(meas), bool)
        np.logical_or.at(unsure, slot, ~pd)
        waits = ~ld | (has_pair & (unsure | unsure_line[meas]))
        ks = done + meas - c0
        # the final ones, all at once
        fin = ~waits[slot]
        take = fin & pv
        worst = np.zeros(len(meas))
        np.fmax.at(worst, slot[take], np.where(near[take] < np.inf, near[take], R[pk[take]]) - d[take])
        worst = py_max(np.zeros(len(meas)), worst)
        lead = lead_fixed[meas - c0] | lv
        for name, sel in (("lead_clearance", lead & ~waits), ("clearance", ~lead & ~waits)):
            self.best[name].offer(worst[sel], ks[sel], segs, done - c0)
        lt = take & (near < np.inf)
        if lt.any():
            e = R[pk[lt]] - py_max(d[lt], near[lt])
            key = (done + pk[lt] - c0).astype(np.int64) * _KEY + pj[lt]
            self.notes.offer(np.zeros(int(lt.sum()), np.int64), e, key, lambda k: segs[k - done + c0].span)
        for i in np.nonzero(waits)[0].tolist():
            j = int(meas[i])
            sel = slot == i
            cont = None
            if unsure_line[j] and row[j] >= 0:
                c = int(row[j])
                cont = (float(lim[c]), int(prog_g[c]), int(store.first_row_after(int(tool.line[j]))))
            self.waiting.append(_Waiting(done + j - c0, segs[j].span, float(R[j]), int(tool.line[j]),
                                         bool(lead_fixed[j - c0]), pj[sel], d[sel], near[sel], cont))  # fmt: skip

    def settle(self) -> None:
        """Compute the closing limits of the ended runs now evaluated, then every waiting
        measurement that is known now."""
        v = self.v
        left = []
        for run in self.runs:
            if v.done > run.end or v.facts.finished and v.done >= v.n:
                self._closing(run)
            else:
                left.append(run)
        self.runs = left
        if not self.waiting:
            return
        wait = self.wait_lines()
        still = []
        for w in self.waiting:
            if w.line in wait or not self._known(w):
                still.append(w)
            else:
                self._put(w)
        self.waiting = still

    def _known(self, w: _Waiting) -> bool:
        facts = self.v.facts
        _, ld = facts.lead(np.array([w.line]))
        if not ld[0]:
            return False
        _, pd = facts.part(self.v.store.line[w.rows])
        return bool(pd.all())

    def _put(self, w: _Waiting) -> None:
        facts, store = self.v.facts, self.v.store
        near = w.near.copy()
        if w.cont is not None:
            limit, b, nxt = w.cont
            first = facts.closings.get(w.line)
            if first is not None and store.first_row(first, store.sel) >= 0:
                nxt = store.first_row(first, store.sel)
            if nxt >= 0 and math.hypot(store.sx[nxt] - store.ex[b], store.sy[nxt] - store.ey[b]) <= SAME_POINT_MM:
                ok = (w.rows == nxt) & ~(limit >= w.radius) & (limit < near)
                near = np.where(ok, limit, near)
        closing = np.array([self.limits.get((w.k, int(j)), np.inf) for j in w.rows.tolist()], float)
        pv, _ = facts.part(store.line[w.rows])
        first = ~(closing < near)
        lim = np.where(first, near, closing)
        limited = (near < np.inf) | (closing < np.inf)
        vals = (np.where(limited, lim, w.radius) - w.dist)[pv]
        worst = max(0.0, float(np.fmax.reduce(vals))) if vals.size else 0.0
        worst = 0.0 if math.isnan(worst) else worst
        lv, _ = facts.lead(np.array([w.line]))
        name = "lead_clearance" if w.lead_fixed or lv[0] else "clearance"
        self.best[name].offer(np.array([worst]), np.array([w.k]), [SpanOnly(w.span)], w.k)
        sel = pv & limited
        if sel.any():
            e = w.radius - py_max(w.dist[sel], lim[sel])
            key = np.int64(w.k) * _KEY + w.rows[sel]
            self.notes.offer(np.where(first[sel], 0, 1), e, key, lambda k: w.span)

    def _closing(self, run: Any) -> None:
        """``batch._closing_limits`` of one closing joint."""
        facts, store = self.v.facts, self.v.store
        f_line, l_line = run.closing
        segs = run.segments

        def lead(k: int) -> bool:
            return self.lead_fixed.get(k, False) or segs[k].span.line in facts.lead_lines

        def usable(k: int) -> bool:
            s = segs[k]
            return s.radius > 0.0 and s.role in (Role.CONTOUR, Role.CORNER) and not lead(k)

        order = sorted(segs)
        first = [k for k in order if segs[k].span.line == f_line and usable(k)]
        last = [k for k in order if segs[k].span.line == l_line and usable(k)]
        if not first or not last:
            return
        n = self.v.n if self.v.facts.finished else run.end + 1
        if first[0] > 0 and not lead(first[0] - 1) or last[-1] + 1 < n and not lead(last[-1] + 1):
            return
        entry, exit_ = segs[first[0]].geometry.point2(0.0), segs[last[-1]].geometry.point2(1.0)
        for group, point, across in ((first, entry, l_line), (last, exit_, f_line)):
            a, b = store.rows_of(across, across)
            rows = np.arange(a, b)[store.star[a:b]]
            pv, _ = facts.part(store.line[rows])
            for i in rows[pv].tolist():
                limit = float(points_distance(store.geometry(i), np.array([point], float))[0])
                for k in group:
                    key = (k, i)
                    if not limit >= segs[k].radius and (key not in self.limits or limit < self.limits[key]):
                        self.limits[key] = limit

    def any_part(self) -> bool:
        store, facts = self.v.store, self.v.facts
        rows = np.nonzero(store.star)[0]
        for a in range(0, len(rows), 1 << 16):
            if facts.part(store.line[rows[a : a + (1 << 16)]])[0].any():
                return True
        return False


def pair_distances_of(tool: Any, part: Any, pk: np.ndarray, pi: np.ndarray, segs: list[Segment], store: Any,
                      urows: np.ndarray) -> np.ndarray:  # fmt: skip
    from trcopt.verify.clearance import pair_distances

    return pair_distances(tool, part, pk, pi, lambda k: segs[k].geometry, lambda i: store.geometry(int(urows[i])))
