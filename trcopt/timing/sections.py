"""Splitting a tool path into sections at tangent discontinuities, and the per-segment limits.

TOPP theory needs a tangent-continuous path: where the tangent jumps, exact path following with
bounded acceleration forces the path speed to zero (spec timing.md §4.5). A *section* is a maximal
run of segments whose joints are tangent within ``tangent_tol_rad``; every section starts and ends
at rest and is solved independently (and may be solved in parallel).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from trcopt.codes import Code
from trcopt.config import Machine
from trcopt.errors import TimingError
from trcopt.geometry.primitives import Arc
from trcopt.modes import FeedReference, Side
from trcopt.path import Role, Segment
from trcopt.timing.path import PathArrays

__all__ = [
    "Section",
    "split_sections",
    "segment_feeds",
    "axis_limits",
    "path_speed_caps",
    "TANGENT_TOL_RAD",
]

TANGENT_TOL_RAD = 1e-6
MIN_LENGTH_MM = 1e-9


@dataclass(frozen=True, slots=True)
class Section:
    """Segments ``first..last`` (inclusive, indices into the tool path) joined tangentially."""

    index: int
    first: int
    last: int
    s_start: float  # arc length of the whole path at the section start, mm
    length: float  # mm

    @property
    def segment_indices(self) -> range:
        return range(self.first, self.last + 1)


def axis_limits(machine: Machine) -> tuple[np.ndarray, np.ndarray]:
    """(vmax, amax) per axis X, Y, Z as arrays, mm/s and mm/s²."""
    v = np.array([machine.axis(k).vmax_mm_s for k in "XYZ"])
    a = np.array([machine.axis(k).amax_mm_s2 for k in "XYZ"])
    return v, a


def path_speed_caps(feeds: np.ndarray, machine: Machine) -> np.ndarray:
    """The path-speed limit per segment the solvers plan with, mm/s.

    The feed of each segment (:func:`segment_feeds`) capped by the machine's vector speed limit
    ``machine.path.vmax_mm_s``; ``feeds`` itself when the machine has none. The reports keep
    comparing the profile with the feed itself.
    """
    vmax = machine.path.vmax_mm_s
    return feeds if vmax is None else np.minimum(feeds, vmax)


def segment_feeds(segments: Sequence[Segment], machine: Machine) -> np.ndarray:
    """Path-speed limit of each segment at the tool centre, mm/s.

    Rapids (``feed_mm_s is None``) run at the machine's rapid feed. With
    ``machine.feed_reference`` is ``FeedReference.CONTOUR`` the programmed feed holds on the contour: on a
    compensated arc the tool-centre feed is ``F·R_centre/R_contour`` (lines are unchanged;
    corner transition circles, whose contour radius is zero, keep the programmed feed).
    """
    out = np.empty(len(segments))
    for i, seg in enumerate(segments):
        f = machine.rapid_mm_s if seg.feed_mm_s is None else float(seg.feed_mm_s)
        if (
            machine.feed_reference is FeedReference.CONTOUR
            and seg.feed_mm_s is not None
            and isinstance(seg.geometry, Arc)
            and seg.side is not Side.OFF
            and seg.radius > 0
            and seg.role is not Role.CORNER
        ):
            g = seg.geometry
            sign = 1.0 if seg.side is Side.LEFT else -1.0
            r_contour = g.radius + sign * g.sense * seg.radius
            if r_contour > 0:
                f *= g.radius / r_contour
        if not (f > 0 and math.isfinite(f)):
            raise TimingError(
                f"segment {i} has no positive feed ({f!r} mm/s); remedy: program a feed (F word)",
                seg.span,
                Code.TIMING_FEED,
            )
        out[i] = f
    return out


def split_sections(
    segments: Sequence[Segment], arrays: PathArrays, tangent_tol_rad: float = TANGENT_TOL_RAD
) -> list[Section]:
    """Cut the path at every tangent discontinuity (3D angle > ``tangent_tol_rad``), between a rapid
    and a feed move, and after every segment with an exact stop (:attr:`Segment.stop`); a kink the
    path-control mode rounds (:attr:`Segment.smooth_end`) is passed as a tangent joint."""
    n = len(segments)
    if n == 0:
        return []
    short = np.nonzero(arrays.length <= MIN_LENGTH_MM)[0]
    if short.shape[0]:
        i = int(short[0])
        k = int(np.count_nonzero(_breaks(segments, arrays, tangent_tol_rad)[:i])) if i else 0
        raise TimingError(
            f"section {k}: zero-length element at s={arrays.start[i]:.6f} mm (segment {i}, block "
            f"{segments[i].span.block_label()}) cannot be time-parameterised; remedy: remove the "
            "block or merge it with its neighbour",
            segments[i].span,
            Code.TIMING_ZERO_LENGTH,
        )
    brk = _breaks(segments, arrays, tangent_tol_rad)
    ends = np.append(np.nonzero(brk)[0], n - 1)
    firsts = np.concatenate(([0], ends[:-1] + 1))
    s0 = arrays.start[firsts]
    lengths = arrays.start[ends] + arrays.length[ends] - s0
    return [
        Section(k, first, last, a, b)
        for k, (first, last, a, b) in enumerate(
            zip(firsts.tolist(), ends.tolist(), s0.tolist(), lengths.tolist(), strict=True)
        )
    ]


def _breaks(segments: Sequence[Segment], arrays: PathArrays, tol: float) -> np.ndarray:
    """Boolean per joint k (between segment k and k+1): True where the path must stop."""
    n = len(segments)
    idx = np.arange(n)
    t_end = arrays.eval(idx, arrays.length, 1)
    t_start = arrays.eval(idx, np.zeros(n), 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        a = t_end[:-1] / np.linalg.norm(t_end[:-1], axis=1)[:, None]
        b = t_start[1:] / np.linalg.norm(t_start[1:], axis=1)[:, None]
        angle = np.arccos(np.clip((a * b).sum(axis=1), -1.0, 1.0))
    rapid = np.array([s.is_rapid for s in segments], dtype=bool)
    stop = np.array([s.stop for s in segments[:-1]], dtype=bool)
    smooth = np.array([s.smooth_end for s in segments[:-1]], dtype=bool)
    return (~(angle <= tol) & ~smooth) | (rapid[:-1] != rapid[1:]) | stop
