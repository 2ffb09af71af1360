"""Matplotlib pictures of a plan: the paths, and the speed profile of a timed path.

matplotlib is imported inside the functions, so importing this module stays cheap. A picture
written to a file is rendered to bytes first and written atomically.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from io import BytesIO
from pathlib import Path
from typing import Any

from trcopt.io.atomic import write_bytes_atomic
from trcopt.path import Role, Segment
from trcopt.trajectory import Trajectory

__all__ = ["plot_paths", "plot_speed", "render_speed", "picture_file"]

SPEED_PLOT_SAMPLES = 4000  # samples over the whole profile (at most one every 0.1 ms)

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


def plot_speed(trajectory: Trajectory, path: str | os.PathLike[str] | None = None, *, ax: Any = None) -> Any:
    """Plot the path speed over arc length and, colour-coded, over the path (X/Y).

    Parameters
    ----------
    trajectory:
        Either kind of timed path; the programmed feed limit is drawn beside its speed (mm/s).
    path:
        Picture file to write (format from the suffix, e.g. ``.png`` or ``.svg``; without one
        matplotlib's default format, whose suffix is appended). Without ``path`` nothing is written
        and the figure stays open.
    ax:
        Two axes ``(speed over s, speed over the path)`` to draw into; a new figure otherwise.

    Returns
    -------
    The matplotlib figure.

    Raises
    ------
    OutputError
        The picture cannot be written; an existing file at ``path`` is left untouched.
    """
    # the backend in use is kept (a notebook's inline backend still shows its figures after a
    # picture was written); savefig renders with any backend, and matplotlib picks Agg without a display
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.collections import LineCollection

    smp = None
    if trajectory.segments:
        smp = trajectory.sample(max(trajectory.duration / SPEED_PLOT_SAMPLES, 1e-4))
    if ax is None:
        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(12, 4.5))
    else:
        ax0, ax1 = ax
        fig = ax0.figure
    if smp is not None:
        ax0.plot(smp.s, smp.speed, lw=1.2, label="path speed")
        ax0.step(smp.s, trajectory.feeds[smp.segment], where="post", lw=0.8, ls="--", label="feed limit")
        ax0.set_xlabel("s [mm]")
        ax0.set_ylabel("speed [mm/s]")
        ax0.set_title(f"feed profile, T = {trajectory.duration:.4f} s")
        ax0.legend(loc="best")
        pts = smp.xyz[:, :2]
        pieces = np.stack((pts[:-1], pts[1:]), axis=1)
        # the colour scale spans the cutting moves; rapids (drawn grey, dashed) would squash it
        rapid = np.array([s.is_rapid for s in trajectory.segments], dtype=bool)[smp.segment[:-1]]
        cut = ~rapid if (~rapid).any() else np.ones_like(rapid)
        speed = smp.speed[:-1]
        lc = LineCollection(list(pieces[cut]), array=speed[cut], cmap="viridis", linewidths=2)
        lc.set_clim(0.0, max(float(speed[cut].max()), 1e-9))
        ax1.add_collection(lc)
        if (rapid & ~cut).any():
            ax1.add_collection(LineCollection(list(pieces[rapid]), colors="0.6", linewidths=0.8, linestyles="--"))
        ax1.autoscale()
        ax1.set_aspect("equal")
        ax1.set_xlabel("X [mm]")
        ax1.set_ylabel("Y [mm]")
        label = "speed [mm/s]" + (" (rapids grey)" if (rapid & ~cut).any() else "")
        fig.colorbar(lc, ax=ax1, label=label)
        ax1.set_title("speed over the path")
    if path is not None:
        dest, picture = _render(fig, path)
        write_bytes_atomic(dest, picture)
    return fig


def render_speed(trajectory: Trajectory, path: str | os.PathLike[str]) -> tuple[Path, bytes]:
    """The picture :func:`plot_speed` writes to ``path``, rendered but not written: the file it
    goes to (``path``, with the default format's suffix when it has none) and its bytes."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    return _render(plot_speed(trajectory), path)


def _render(fig: Any, path: str | os.PathLike[str]) -> tuple[Path, bytes]:
    """Render ``fig`` in the format ``path`` names and close it."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    dest, image_format = picture_file(path, fig.canvas.get_default_filetype())
    picture = BytesIO()
    fig.savefig(picture, format=image_format)
    plt.close(fig)
    return dest, picture.getvalue()


def picture_file(path: str | os.PathLike[str], default_format: str) -> tuple[Path, str]:
    """The file and format matplotlib's ``savefig(path)`` would use: the suffix names the format;
    without one the default format is used and its suffix appended."""
    name = os.fspath(path)
    image_format = os.path.splitext(name)[1][1:]
    if not image_format:
        image_format = default_format
        name = name.rstrip(".") + "." + image_format
    return Path(name), image_format.lower()
