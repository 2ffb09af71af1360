"""What every timed tool path offers: the :class:`Trajectory` protocol and the values it returns.

Both kinds of feed profile satisfy the protocol, the acceleration-limited
:class:`~trcopt.timing.TimedTrajectory` and the jerk-limited
:class:`~trcopt.timing.jerk.JerkTrajectory`, so the pipeline, the command line and the writers in
:mod:`trcopt.io` handle either without knowing which one they hold. :class:`Samples` (states at
given times) and :class:`LimitReport` (the limit check) are the value types both return.

numpy is only named in annotations here (imported for type checking), so that this base module
and the output writers that depend on it stay cheap to import.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

from trcopt.config import Machine
from trcopt.path import Segment

if TYPE_CHECKING:
    import numpy as np

__all__ = ["Trajectory", "Samples", "LimitReport"]


@dataclass(frozen=True)
class Samples:
    """States of a trajectory at given times (arrays of equal length, one entry per time).

    Attributes
    ----------
    t:
        Times, s.
    s:
        Arc length along the whole tool path, mm.
    xyz:
        Tool-centre position, mm (3 columns X, Y, Z).
    speed:
        Path speed ṡ, mm/s.
    v:
        Velocity per axis, mm/s (3 columns).
    a:
        Acceleration per axis, mm/s² (3 columns).
    segment:
        Index into the tool path of the segment the tool is on.
    block:
        Source block label of that segment (str).
    sdd:
        Path acceleration s̈, mm/s².
    j:
        Jerk per axis, mm/s³ (3 columns), or None for a profile that does not bound the jerk
        (the acceleration-limited one: its jerk is unbounded, see ``max_jerk_mm_s3`` in its JSON).
    """

    t: np.ndarray
    s: np.ndarray
    xyz: np.ndarray
    speed: np.ndarray
    v: np.ndarray
    a: np.ndarray
    segment: np.ndarray
    block: np.ndarray
    sdd: np.ndarray
    j: np.ndarray | None = None


@dataclass(frozen=True)
class LimitReport:
    """Result of :meth:`Trajectory.check_limits`: ratios to the machine limits, max over the samples.

    Attributes
    ----------
    ok:
        Every ratio within ``tolerance``, speed 0 at every tangent discontinuity (≤ 1e-6 mm/s) and
        the sampled positions on the exact path (≤ 1e-6 mm).
    v_ratio, a_ratio:
        Largest |v|/vmax and |a|/amax per axis X, Y, Z (dimensionless).
    feed_ratio:
        Largest path speed / programmed feed (dimensionless).
    corner_speed_mm_s:
        Largest path speed at a section end (tangent discontinuity), mm/s.
    path_deviation_mm:
        Largest distance of a sampled position from the exact geometry, mm.
    tolerance:
        The ratio the check allowed (dimensionless, e.g. 1.001).
    samples:
        Number of states checked.
    """

    ok: bool
    v_ratio: tuple[float, float, float]
    a_ratio: tuple[float, float, float]
    feed_ratio: float
    corner_speed_mm_s: float
    path_deviation_mm: float
    tolerance: float
    samples: int

    def __str__(self) -> str:
        v = ", ".join(f"{r:.4f}" for r in self.v_ratio)
        a = ", ".join(f"{r:.4f}" for r in self.a_ratio)
        return (
            f"{'PASS' if self.ok else 'FAIL'}: v/vmax (X,Y,Z) = {v}; a/amax = {a}; feed {self.feed_ratio:.4f}; "
            f"corner speed {self.corner_speed_mm_s:.2e} mm/s; deviation {self.path_deviation_mm:.1e} mm"
        )

    def to_json(self) -> dict[str, Any]:
        return {
            "ok": self.ok,
            "v_ratio": dict(zip("XYZ", self.v_ratio, strict=True)),
            "a_ratio": dict(zip("XYZ", self.a_ratio, strict=True)),
            "feed_ratio": self.feed_ratio,
            "corner_speed_mm_s": self.corner_speed_mm_s,
            "path_deviation_mm": self.path_deviation_mm,
        }


@runtime_checkable
class Trajectory(Protocol):
    """A time-parameterised tool-centre path that follows the exact geometry.

    ``isinstance(x, Trajectory)`` checks that the members exist, not their signatures.
    """

    @property
    def jerk_limited(self) -> bool:
        """True for a profile with bounded jerk (its samples carry ``j``)."""
        ...

    @property
    def machine(self) -> Machine:
        """The machine whose limits the profile respects."""
        ...

    @property
    def segments(self) -> Sequence[Segment]:
        """The tool path, in path order."""
        ...

    @property
    def feeds(self) -> np.ndarray:
        """Path-speed limit per segment (programmed feed or rapid rate), mm/s."""
        ...

    @property
    def duration(self) -> float:
        """Cycle time, s."""
        ...

    @property
    def length(self) -> float:
        """Path length, mm."""
        ...

    def segments_with_times(self) -> list[Segment]:
        """The tool path with ``t_start_s``/``t_end_s`` (s) set on every segment."""
        ...

    def evaluate(self, ts: np.ndarray) -> Samples:
        """States at the times ``ts`` (s)."""
        ...

    def sample(self, dt: float = 1e-3) -> Samples:
        """States every ``dt`` seconds from 0 to the duration, both included."""
        ...

    def check_limits(self, dt: float = 1e-4, tolerance: float = 1.001) -> LimitReport:
        """Check the profile against the machine limits, sampled every ``dt`` seconds.

        ``tolerance`` is the largest ratio to a limit that passes (dimensionless).
        """
        ...

    def to_json(self, samples: str | None = None) -> dict[str, Any]:
        """The ``timing`` object of the plan JSON; ``samples`` names the CSV feed profile, if any."""
        ...
