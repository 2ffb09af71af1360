"""Where the pictures put a diagnostic: the SVG and the HTML preview mark the same places.

* an omitted block (alarm 10763) is its programmed segment: the tool path has none for it, the
  mark sits at the middle of the programmed block, which the pictures draw highlighted;
* any other diagnostic sits at the start of the first segment of its source line, the tool path
  searched first, then the programmed path;
* an error that no segment carries (the program stopped at it: the block was never turned into a
  path) sits at the end of the tool path, where the machine stops (``kind`` ``"stop"``);
* the rest cannot be located (``kind`` ``"unlocated"``): the pictures list them.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity
from trcopt.geometry.vec import Vec3
from trcopt.path import Segment

__all__ = ["Mark", "locate_diagnostics", "midpoint_xyz"]


@dataclass(frozen=True, slots=True)
class Mark:
    """A diagnostic and its place in the pictures.

    Attributes
    ----------
    diagnostic:
        The diagnostic.
    kind:
        ``"located"``, ``"omitted"`` (alarm 10763: the programmed block that was not traversed),
        ``"stop"`` (an error at the end of the tool path) or ``"unlocated"``.
    path:
        ``"toolpath"`` or ``"programmed"``: the path whose segment ``index`` carries the mark
        (None when unlocated).
    index:
        Index of that segment in its path.
    point:
        The mark's position in workpiece coordinates (x, y, z), mm; None when unlocated.
    """

    diagnostic: Diagnostic
    kind: str
    path: str | None = None
    index: int | None = None
    point: Vec3 | None = None


def midpoint_xyz(seg: Segment) -> Vec3:
    """The point halfway along a segment, workpiece coordinates, mm."""
    g = seg.geometry
    return seg.plane.to_xyz(g.point(0.5 * g.length))


def _same_file(diag: Diagnostic, seg: Segment) -> bool:
    return diag.span.file in (seg.span.file, "<program>")


def _first_of_line(diag: Diagnostic, segs: Sequence[Segment]) -> int | None:
    if not diag.span.line:
        return None
    return next((i for i, s in enumerate(segs) if s.span.line == diag.span.line and _same_file(diag, s)), None)


def locate_diagnostics(
    programmed: Sequence[Segment],
    toolpath: Sequence[Segment],
    diagnostics: Iterable[Diagnostic],
    severities: tuple[Severity, ...] = (Severity.ERROR, Severity.WARNING),
) -> list[Mark]:
    """The marks of the diagnostics of the given severities, in their order (module docstring)."""
    marks: list[Mark] = []
    for d in diagnostics:
        if d.severity not in severities:
            continue
        if d.code == Code.ALARM_10763:
            i = _first_of_line(d, programmed)
            if i is not None:
                marks.append(Mark(d, "omitted", "programmed", i, midpoint_xyz(programmed[i])))
                continue
        i = _first_of_line(d, toolpath)
        if i is not None:
            marks.append(Mark(d, "located", "toolpath", i, toolpath[i].start_xyz))
            continue
        i = _first_of_line(d, programmed)
        if i is not None:
            marks.append(Mark(d, "located", "programmed", i, programmed[i].start_xyz))
            continue
        if d.severity is Severity.ERROR and toolpath:
            last = len(toolpath) - 1
            marks.append(Mark(d, "stop", "toolpath", last, toolpath[last].end_xyz))
            continue
        marks.append(Mark(d, "unlocated"))
    return marks
