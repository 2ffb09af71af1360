"""The ``program`` corner strategy: what the program's path-control mode makes the controller do.

The readers attach to every move the :class:`~trcopt.nc.model.PathControl` in force at its end
(LinuxCNC ``G61``/``G61.1``/``G64 P``, SINUMERIK ``G60``/``G9``/``G641``/``G642``/``CYCLE832``,
Heidenhain ``CYCL DEF 32``). :func:`path_control_plan` turns them into what the corners of a tool
path get:

* a **blend** where the block ending at the corner is in a blending mode: the controller rounds
  its own (tool-centre) path, so the tolerance bounds the distance of the tool-centre path from
  the exact one, measured as the mode says (LinuxCNC ``P``: from the corner point; SINUMERIK
  ``CTOL`` and Heidenhain ``T``: from the path; SINUMERIK ``ADIS``: where the rounding starts);
* an **exact stop** at the end of a block in an exact-stop mode (``G61.1``, ``G60``, ``G9``) even
  where the path is tangent;
* otherwise the exact path, which stops at every tangent discontinuity (no mode programmed,
  LinuxCNC ``G61``).

:func:`program_transitions` is the strategy: the circular blends of
:mod:`~trcopt.optimize.corners.fillet` at the blended joints.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace

from trcopt.geometry import Arc, Line, Poly
from trcopt.modes import PathMode, ToleranceKind
from trcopt.nc.model import EXACT_PATH, Move, PathControl
from trcopt.optimize.corners.fillet import FilletSpec, element_joint, fillet_path
from trcopt.optimize.corners.records import CornerResult
from trcopt.optimize.corners.strategies import CornerJob
from trcopt.path import Segment

__all__ = [
    "MERGE_MAX_MOVES", "PathControlPlan", "merge_collinear", "path_control_plan", "program_transitions", "with_stops",
]  # fmt: skip

MERGE_MAX_MOVES = 100  # the naive-CAM detector merges at most this many moves into one


@dataclass(frozen=True)
class PathControlPlan:
    """The program's path control on one tool path.

    Attributes
    ----------
    blends:
        The blend of each joint in a blending mode, by joint index (between ``toolpath[k]`` and
        ``[k + 1]``).
    stops:
        Indices of the segments that end in an exact stop.
    smooth:
        Indices of the segments whose end is a kink the mode rounds within its tolerance no
        tighter than the elements themselves curve (between arcs, or an arc and a line, e.g. the
        digits of a written arc spline): passed as a tangent joint.
    words:
        The distinct path-control words of the program's moves, in order (for the report).
    """

    blends: dict[int, FilletSpec]
    stops: frozenset[int]
    words: tuple[str, ...]
    smooth: frozenset[int] = frozenset()

    @property
    def tolerances(self) -> dict[int, float]:
        """The blends' tolerances by joint (the blends without a bound are left out)."""
        return {k: s.tolerance_mm for k, s in self.blends.items() if s.tolerance_mm is not None}


def _controls_by_line(moves: Iterable[Move]) -> dict[int, PathControl]:
    """The path-control mode of each line's last move; lines only ever in the default exact path
    (:data:`EXACT_PATH`) are left out (empty: the program sets no mode)."""
    out: dict[int, PathControl] = {}
    for m in moves:
        control = m.control
        if control is not EXACT_PATH or m.span.line in out:
            out[m.span.line] = control
    return out


def path_control_plan(
    toolpath: Sequence[Segment], moves: Iterable[Move], kind: ToleranceKind | None = None
) -> PathControlPlan:
    """What the program's path-control modes do at the corners of ``toolpath``; ``kind`` replaces
    the modes' own contour/vertex measure (not SINUMERIK's rounding distance)."""
    controls = _controls_by_line(moves)
    blends: dict[int, FilletSpec] = {}
    stops: set[int] = set()
    smooth: set[int] = set()
    words: dict[str, None] = {}
    if not controls:  # the exact path everywhere: no word, no stop, no blend
        return PathControlPlan(blends, frozenset(), ())
    n = len(toolpath)
    for k, seg in enumerate(toolpath):
        control = controls.get(seg.span.line, EXACT_PATH)
        if control.word:
            words[control.word] = None
        last_of_block = k == n - 1 or toolpath[k + 1].span.line != seg.span.line
        if control.mode is PathMode.EXACT_STOP:
            if last_of_block:
                stops.add(k)
        elif control.mode is PathMode.BLEND and k < n - 1:
            measure = control.kind
            if kind is not None and measure is not ToleranceKind.DISTANCE:
                measure = kind
            spec = FilletSpec(control.tolerance_mm, measure, length_share=control.length_share)
            nxt = toolpath[k + 1]
            if isinstance(seg.geometry, Line) and isinstance(nxt.geometry, Line):
                blends[k] = spec
            elif _rounded_as_smooth(seg, nxt, spec):
                smooth.add(k)
            elif element_joint(toolpath, k):
                blends[k] = spec  # a line–arc or arc–arc corner: the circle tangent to both
    return PathControlPlan(blends, frozenset(stops), tuple(words), frozenset(smooth))


def _rounded_as_smooth(a: Segment, b: Segment, spec: FilletSpec) -> bool:
    """Whether the kink between ``a`` and ``b`` (not two lines) is rounded by ``spec`` with a radius
    no smaller than the smaller radius of curvature of the two elements (so it does not limit the
    speed more than they do)."""
    if a.is_rapid or b.is_rapid or a.plane != b.plane or math.dist(a.geometry.end, b.geometry.start) > 1e-6:
        return False
    ga, gb = a.geometry, b.geometry
    ta, tb = ga.derivatives(ga.length)[1], gb.derivatives(0.0)[1]
    cos_t = max(-1.0, min(1.0, sum(x * y for x, y in zip(ta, tb, strict=True))))
    theta = math.acos(cos_t)
    if theta > 0.1:
        return False  # a real corner
    if theta <= 1e-12:
        return True
    radius = spec.bounded(ga.length, gb.length).radius(theta)
    curvature = max(_curvature(ga), _curvature(gb))
    return curvature > 0.0 and radius * curvature >= 1.0


def _curvature(g: object) -> float:
    if isinstance(g, Arc):
        return 1.0 / g.radius if g.radius > 0 else math.inf
    if isinstance(g, Poly) and g.curvatures is not None:
        return max(math.sqrt(c[0] ** 2 + c[1] ** 2 + c[2] ** 2) for c in g.curvatures)
    return 0.0


def _distance_to_segment(p: tuple[float, ...], a: tuple[float, ...], b: tuple[float, ...]) -> float:
    d = [b[i] - a[i] for i in range(3)]
    w = [p[i] - a[i] for i in range(3)]
    dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
    t = 0.0 if dd <= 0.0 else max(0.0, min(1.0, (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / dd))
    return math.dist(p, (a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]))


def merge_collinear(toolpath: Sequence[Segment], moves: Iterable[Move]) -> list[Segment]:
    """LinuxCNC's naive-CAM detector (``G64 Q``): consecutive straight feed moves of one feed,
    plane and compensation whose end points all lie within ``Q`` of the line from the first start
    to the last end become that line (at most :data:`MERGE_MAX_MOVES`; span of the last move)."""
    controls = _controls_by_line(moves)
    if not any(c.blends and c.merge_mm is not None for c in controls.values()):
        return list(toolpath)  # no G64 Q: nothing is merged

    def q_of(seg: Segment) -> float | None:
        control = controls.get(seg.span.line, EXACT_PATH)
        if seg.is_rapid or not isinstance(seg.geometry, Line) or seg.stop:
            return None
        return control.merge_mm if control.blends else None

    out: list[Segment] = []
    n = len(toolpath)
    i = 0
    while i < n:
        seg = toolpath[i]
        q = q_of(seg)
        if q is None:
            out.append(seg)
            i += 1
            continue
        start = seg.geometry.start
        inner: list[tuple[float, ...]] = []
        j = i
        while j + 1 < n and j + 1 - i < MERGE_MAX_MOVES:
            nxt = toolpath[j + 1]
            if q_of(nxt) != q or (nxt.plane, nxt.feed_mm_s, nxt.side, nxt.radius) != (
                seg.plane, seg.feed_mm_s, seg.side, seg.radius
            ):
                break
            end = nxt.geometry.end
            points = [*inner, toolpath[j].geometry.end]
            if any(_distance_to_segment(p, start, end) > q for p in points):
                break
            inner = points
            j += 1
        last = toolpath[j]
        out.append(seg if j == i else replace(last, geometry=Line(start, last.geometry.end)))
        i = j + 1
    return out


def with_stops(
    toolpath: Sequence[Segment], stops: frozenset[int], smooth: frozenset[int] = frozenset()
) -> list[Segment]:
    """``toolpath`` with an exact stop at the end of the segments ``stops`` and a joint passed as
    tangent at the end of the segments ``smooth``."""
    return [
        replace(s, stop=True) if k in stops else replace(s, smooth_end=True) if k in smooth else s
        for k, s in enumerate(toolpath)
    ]


def program_transitions(job: CornerJob) -> CornerResult:
    """The circular blends of the program's blending modes (``job.program``); the path is left as
    it is where the program blends nothing."""
    if not job.program:
        return job.unchanged()
    return fillet_path(job.toolpath, dict(job.program), job.strategy)
