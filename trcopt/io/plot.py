"""Matplotlib pictures of a plan (matplotlib is imported inside the functions)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from trcopt.path import Role, Segment

__all__ = ["plot_paths"]

_ROLE_STYLE = {
    Role.CONTOUR: {"color": "tab:blue", "lw": 1.6},
    Role.CORNER: {"color": "tab:orange", "lw": 2.2},
    Role.APPROACH: {"color": "tab:green", "lw": 1.8},
    Role.RETRACT: {"color": "tab:green", "lw": 1.8},
    Role.RAPID: {"color": "0.6", "lw": 1.0, "ls": "--"},
    Role.POSITIONING: {"color": "tab:purple", "lw": 1.0},
}


def _uv(seg: Segment, n: int = 0) -> tuple[list[float], list[float]]:
    g = seg.geometry
    count = n or max(2, int(g.length / 0.5) + 2)
    pts = [g.point(g.length * k / (count - 1)) for k in range(count)]
    return [p[0] for p in pts], [p[1] for p in pts]


def plot_paths(
    programmed: Sequence[Segment],
    toolpath: Sequence[Segment],
    *,
    ax: Any = None,
    title: str | None = None,
    tool_circles: bool = True,
    markers: Sequence[tuple[float, float, str]] = (),
) -> Any:
    """Draw the programmed contour (black) and the tool-centre path coloured by role.

    Coordinates are the (u, v) of each segment's plane (X/Y for G17). Returns the axes.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 6))
    for seg in programmed:
        if seg.role is Role.RAPID:
            continue
        u, v = _uv(seg)
        ax.plot(u, v, color="black", lw=0.9)
    seen: set[Role] = set()
    for seg in toolpath:
        style = _ROLE_STYLE.get(seg.role, {"color": "tab:blue"})
        u, v = _uv(seg)
        label = seg.role.value if seg.role not in seen else None
        seen.add(seg.role)
        ax.plot(u, v, label=label, **style)
        if tool_circles and seg.radius > 0 and seg.role in (Role.CONTOUR, Role.CORNER):
            end = seg.geometry.end
            ax.add_patch(plt.Circle((end[0], end[1]), seg.radius, fill=False, color="tab:blue", alpha=0.15))
    for x, y, text in markers:
        ax.plot([x], [y], "o", color="red")
        ax.annotate(text, (x, y), color="red", fontsize=8, xytext=(4, 4), textcoords="offset points")
    ax.plot([], [], color="black", lw=0.9, label="programmed")
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    if title:
        ax.set_title(title)
    return ax
