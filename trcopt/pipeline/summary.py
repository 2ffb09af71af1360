"""The terminal summary of a plan, whole (:class:`~trcopt.pipeline.PlanResult`) or streamed
(:mod:`trcopt.pipeline.stream`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from trcopt.codes import family
from trcopt.errors import Diagnostic, Severity

__all__ = ["summary_text"]


def summary_text(
    program: str, dialect: str, blocks: int, segments: int, length_mm: float, timing: Any, corners: Any,
    verification: Any, diagnostics: Sequence[Diagnostic],
) -> str:
    """The terminal summary of a plan (:meth:`PlanResult.summary`); ``timing`` needs ``duration``,
    ``jerk_limited`` and ``machine.name``."""
    lines = [
        f"{program}: {dialect}, {blocks} blocks, {segments} tool-centre segments, path length {length_mm:.3f} mm",
    ]
    if timing is not None:
        kind = "jerk-limited " if timing.jerk_limited else ""
        lines.append(f"{kind}cycle time {timing.duration:.3f} s on {timing.machine.name}")
    if corners:
        lines.append(
            f"corners {corners['mode']} "
            + (f"within {corners['tolerance_mm']} mm" if corners["tolerance_mm"] is not None
               else f"without a tolerance ({' '.join(corners.get('path_control') or ()) or 'program'})")  # fmt: skip
            + f": {corners['blended']} blended "
            f"({corners['quintic']} G2 quintic, {corners.get('spline', 0)} on G2 splines, "
            f"{corners['arc']} circular"
            + (f"; {corners['curvature_jumps']} curvature jumps smoothed" if corners.get("curvature_jumps") else "")
            + "), "
            f"max deviation {corners['max_deviation_mm']:.4f} mm"
            + (
                f" (vertex {corners['max_vertex_mm']:.4f} mm, contour {corners['max_contour_mm']:.4f} mm)"
                if corners.get("max_vertex_mm") is not None and corners.get("max_contour_mm") is not None
                else ""
            )
            + (
                f"; under jerk limits the exact path is faster ({corners['exact_duration_s']:.3f} s vs "
                f"{corners['transitions_duration_s']:.3f} s) and is kept"
                if corners.get("kept") == "exact"
                else ""
            )
        )
    if verification is not None:
        lines.append(verification.summary_line())
        note = verification.lead_note()
        if note:
            lines.append(note)
    errors = [d for d in diagnostics if d.severity is Severity.ERROR]
    n_err, n_warn = len(errors), sum(d.severity is Severity.WARNING for d in diagnostics)
    stopped = any(family(d.code) != "verification" for d in errors)
    tail = "" if not errors else " — stopped at the alarm" if stopped else " — the verification failed (strict)"
    lines.append(f"{n_err} alarm(s), {n_warn} warning(s)" + tail)
    return "\n".join(lines)
