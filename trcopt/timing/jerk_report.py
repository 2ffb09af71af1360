"""What a jerk-limited profile reports: its samples with jerk, its limit report, and its method texts.

:class:`JerkSamples` and :class:`JerkLimitReport` extend the value types of
:mod:`trcopt.trajectory` by the jerk; :func:`jerk_limits` reads the per-axis jerk limits of a
machine; ``METHOD``, ``KNOT_RULE`` and ``JERK_MEASURE`` are the texts the plan JSON states the
method with (see :mod:`trcopt.timing.jerk` for what they mean).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from trcopt.config import Machine
from trcopt.errors import ConfigError
from trcopt.timing.checks import PathLimitReport
from trcopt.trajectory import Samples

__all__ = ["JerkSamples", "JerkLimitReport", "jerk_limits", "METHOD", "KNOT_RULE", "JERK_MEASURE"]

METHOD = (
    "jerk-limited: CasADi/IPOPT NLP per section (triple integrator, constant path jerk between nodes fixed "
    "in arc length; per-axis v, a, jerk limits with exact q', q'', q'''), warm-started from the "
    "acceleration-limited TOPP profile; sections of collinear lines with one feed: closed-form double-S; "
    "speed and acceleration 0 at tangent discontinuities"
)
KNOT_RULE = (
    "curvature jumps passed at |dq''_k| v^2 <= jmax_k * cycle_s "
    "(the acceleration step is absorbed in one interpolation cycle)"
)
JERK_MEASURE = "max(analytic per-axis jerk of the smooth pieces, knot acceleration step / cycle_s) / jmax"


def jerk_limits(machine: Machine) -> np.ndarray:
    """jmax per axis X, Y, Z (mm/s³); ConfigError if an axis has none."""
    out = []
    for k in "XYZ":
        j = machine.axis(k).jmax_mm_s3
        if j is None:
            raise ConfigError(
                f"machine {machine.name!r}: axes.{k} has no jmax_mm_s3; jerk-limited feed needs it on every axis"
            )
        out.append(float(j))
    return np.array(out)


@dataclass(frozen=True)
class JerkSamples(Samples):
    """:class:`~trcopt.trajectory.Samples` with the per-axis jerk ``j`` always present (mm/s³, 3
    columns) and the path jerk ``sddd`` (mm/s³)."""

    # field() without a default: a plain annotation would inherit the base class default None
    j: np.ndarray = field()
    sddd: np.ndarray


@dataclass(frozen=True, kw_only=True)
class JerkLimitReport(PathLimitReport):
    """:class:`~trcopt.timing.checks.PathLimitReport` plus the jerk (ratios to jmax, max over X, Y, Z
    each); its own fields are keyword-only.

    Attributes
    ----------
    jerk_ratio:
        The documented jerk measure: the larger of ``jerk_smooth_ratio`` and ``jerk_knot_ratio``.
    jerk_smooth_ratio:
        Analytic jerk of the smooth pieces, sampled and at both ends of every interval.
    jerk_knot_ratio:
        Acceleration step at the curvature-jump knots divided by the cycle time.
    jerk_fd_1khz_ratio, jerk_fd_10khz_ratio:
        Finite-difference jerk of the sampled acceleration at 1 kHz and 10 kHz, for information.
    jerk_tolerance:
        The jerk ratio the check allowed.
    jerk_checked:
        Whether the jerk counted for ``ok``.
    """

    jerk_ratio: tuple[float, float, float]
    jerk_smooth_ratio: tuple[float, float, float]
    jerk_knot_ratio: tuple[float, float, float]
    jerk_fd_1khz_ratio: tuple[float, float, float]
    jerk_fd_10khz_ratio: tuple[float, float, float]
    jerk_tolerance: float
    jerk_checked: bool

    def __str__(self) -> str:
        def f(r: tuple[float, ...]) -> str:
            return ", ".join(f"{x:.4f}" for x in r)

        return (
            f"{'PASS' if self.ok else 'FAIL'}: v/vmax (X,Y,Z) = {f(self.v_ratio)}; a/amax = {f(self.a_ratio)}; "
            f"j/jmax = {f(self.jerk_ratio)} (knots {f(self.jerk_knot_ratio)}; 1 kHz FD {f(self.jerk_fd_1khz_ratio)}); "
            f"feed {self.feed_ratio:.4f}; corner speed {self.corner_speed_mm_s:.2e} mm/s; "
            f"deviation {self.path_deviation_mm:.1e} mm{self.path_text()}"
        )

    def to_json(self) -> dict[str, Any]:
        def d(r: tuple[float, ...]) -> dict[str, float]:
            return dict(zip("XYZ", r, strict=True))

        out: dict[str, Any] = {
            "ok": self.ok,
            "v_ratio": d(self.v_ratio),
            "a_ratio": d(self.a_ratio),
            "jerk_ratio": d(self.jerk_ratio),
            "jerk_smooth_ratio": d(self.jerk_smooth_ratio),
            "jerk_knot_ratio": d(self.jerk_knot_ratio),
            "jerk_fd_1khz_ratio": d(self.jerk_fd_1khz_ratio),
            "jerk_fd_10khz_ratio": d(self.jerk_fd_10khz_ratio),
            "feed_ratio": self.feed_ratio,
            "corner_speed_mm_s": self.corner_speed_mm_s,
            "path_deviation_mm": self.path_deviation_mm,
            "jerk_measure": JERK_MEASURE,
        }
        if self.path_given:
            out["path_ratio"] = self.path_json()
        return out
