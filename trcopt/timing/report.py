"""Checks and exports of a :class:`~trcopt.timing.trajectory.TimedTrajectory`.

``check_limits`` (sampled and at every grid end), the plan-JSON ``timing`` object with the binding
constraint per section, the CSV feed profile and the speed plot (matplotlib imported lazily).
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from trcopt.timing.sections import axis_limits

if TYPE_CHECKING:
    from trcopt.timing.trajectory import LimitReport, Samples, TimedTrajectory

__all__ = ["check_limits", "timing_json", "write_csv", "plot_speed", "max_jerk", "binding_constraints"]

CSV_COLUMNS = (
    "t_s", "s_mm", "x_mm", "y_mm", "z_mm", "path_speed_mm_s",
    "vx_mm_s", "vy_mm_s", "vz_mm_s", "ax_mm_s2", "ay_mm_s2", "az_mm_s2", "segment", "block",
)


def _ratios(traj: TimedTrajectory, smp: Samples) -> tuple[np.ndarray, np.ndarray, float]:
    vmax, amax = axis_limits(traj.machine)
    if smp.t.shape[0] == 0:
        return np.zeros(3), np.zeros(3), 0.0
    vr = (np.abs(smp.v) / vmax).max(axis=0)
    ar = (np.abs(smp.a) / amax).max(axis=0)
    fr = float((smp.speed / traj.feeds[smp.segment]).max()) if traj.feeds.size else 0.0
    return vr, ar, fr


def check_limits(traj: TimedTrajectory, dt: float, tolerance: float) -> LimitReport:
    from trcopt.timing.trajectory import LimitReport

    if not traj.segments:
        return LimitReport(True, (0.0,) * 3, (0.0,) * 3, 0.0, 0.0, 0.0, tolerance, 0)
    vr1, ar1, fr1 = _ratios(traj, traj.sample(dt))
    grid = traj.grid_states()
    vr2, ar2, fr2 = _ratios(traj, grid)
    vr, ar = np.maximum(vr1, vr2), np.maximum(ar1, ar2)
    fr = max(fr1, fr2)
    corner = float(traj.sd[traj.section_points].max())
    # deviation: the sampled positions are evaluated on the exact geometry; compare with the
    # segment's own point() at a few grid states as an independent check of the evaluator
    dev = 0.0
    pick = np.linspace(0, grid.t.shape[0] - 1, min(grid.t.shape[0], 64)).astype(int)
    assert traj.arrays is not None
    for j in pick:
        k = int(grid.segment[j])
        seg = traj.segments[k]
        local = float(grid.s[j] - traj.arrays.start[k])
        ref = np.array(seg.plane.to_xyz(seg.geometry.point(min(max(local, 0.0), seg.geometry.length))))
        dev = max(dev, float(np.linalg.norm(ref - grid.xyz[j])))
    ok = bool(vr.max() <= tolerance and ar.max() <= tolerance and fr <= tolerance and corner <= 1e-6 and dev <= 1e-6)
    return LimitReport(
        ok, tuple(float(r) for r in vr), tuple(float(r) for r in ar), fr, corner, dev, tolerance, int(grid.t.shape[0])
    )


def max_jerk(traj: TimedTrajectory, dt: float = 1e-3) -> np.ndarray:
    """Finite-difference per-axis jerk max |Δa|/dt at ``dt`` sampling, mm/s³ (unbounded as dt→0)."""
    if not traj.segments or traj.duration <= dt:
        return np.zeros(3)
    smp = traj.sample(dt)
    return (np.abs(np.diff(smp.a, axis=0)) / np.diff(smp.t)[:, None]).max(axis=0)


def binding_constraints(traj: TimedTrajectory) -> list[str]:
    """Per section, the constraint active for the largest share of time.

    At the time midpoint of every grid interval the constraint with the largest ratio to its limit
    (``feed``, ``velocity X``, ``acceleration Y``, …) is active; shares are weighted by duration.
    """
    if not traj.segments:
        return []
    vmax, amax = axis_limits(traj.machine)
    tm = 0.5 * (traj.t[:-1] + traj.t[1:])
    smp = traj.evaluate(tm)
    ratios = np.column_stack(
        (smp.speed / traj.feeds[smp.segment], np.abs(smp.v) / vmax, np.abs(smp.a) / amax)
    )
    names = np.array(
        ["feed", "velocity X", "velocity Y", "velocity Z", "acceleration X", "acceleration Y", "acceleration Z"]
    )
    which = ratios.argmax(axis=1)
    w = np.diff(traj.t)
    out = []
    for k in range(len(traj.sections)):
        a, b = traj.section_points[k], traj.section_points[k + 1]
        share = np.bincount(which[a:b], weights=w[a:b], minlength=7)
        out.append(str(names[int(share.argmax())]))
    return out


def timing_json(traj: TimedTrajectory, samples: str | None) -> dict[str, Any]:
    rep = check_limits(traj, 1e-3, 1.001) if traj.segments else None
    jerk = max_jerk(traj)
    binding = binding_constraints(traj)
    sections = []
    for k, sec in enumerate(traj.sections):
        a, b = traj.section_points[k], traj.section_points[k + 1]
        sections.append({
            "index": sec.index,
            "first_segment": sec.first,
            "last_segment": sec.last,
            "first_block": traj.segments[sec.first].span.block,
            "last_block": traj.segments[sec.last].span.block,
            "s_start_mm": round(sec.s_start, 9),
            "length_mm": round(sec.length, 9),
            "t_start_s": float(traj.t[a]),
            "t_end_s": float(traj.t[b]),
            "engine": traj.engines[k],
            "binding": binding[k],
        })
    jmax = [traj.machine.axis(n).jmax_mm_s3 for n in "XYZ"]
    return {
        "duration_s": traj.duration,
        "machine": traj.machine.to_json(),
        "samples": samples,
        "length_mm": traj.length,
        "method": (
            "TOPP-RA interpolation scheme on the exact path; const-acceleration output; "
            "speed 0 at tangent discontinuities"
        ),
        "sections": sections,
        "max_ratios": None if rep is None else {
            "v": dict(zip("XYZ", rep.v_ratio, strict=True)),
            "a": dict(zip("XYZ", rep.a_ratio, strict=True)),
            "feed": rep.feed_ratio,
        },
        "limits_ok": None if rep is None else rep.ok,
        "max_jerk_mm_s3": dict(zip("XYZ", (float(j) for j in jerk), strict=True)),
        "max_jerk_ratio": {
            n: (None if jm is None else float(j) / jm) for n, j, jm in zip("XYZ", jerk, jmax, strict=True)
        },
        "jerk_note": "finite difference at 1 kHz; acceleration-limited profiles have unbounded jerk",
    }


def write_csv(traj: TimedTrajectory, path: Path, dt: float) -> Path:
    smp = traj.sample(dt)
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_COLUMNS)
        for i in range(smp.t.shape[0]):
            w.writerow([
                f"{smp.t[i]:.6f}", f"{smp.s[i]:.6f}",
                *(f"{c:.6f}" for c in smp.xyz[i]), f"{smp.speed[i]:.6f}",
                *(f"{c:.6f}" for c in smp.v[i]), *(f"{c:.3f}" for c in smp.a[i]),
                int(smp.segment[i]), smp.block[i],
            ])
    return path


def plot_speed(traj: TimedTrajectory, path: str | Path | None, ax: Any = None) -> Any:
    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    smp = traj.sample(max(traj.duration / 4000.0, 1e-4)) if traj.segments else None
    if ax is None:
        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(12, 4.5))
    else:
        ax0, ax1 = ax
        fig = ax0.figure
    if smp is not None:
        ax0.plot(smp.s, smp.speed, lw=1.2, label="path speed")
        ax0.step(smp.s, traj.feeds[smp.segment], where="post", lw=0.8, ls="--", label="feed limit")
        ax0.set_xlabel("s [mm]")
        ax0.set_ylabel("speed [mm/s]")
        ax0.set_title(f"feed profile, T = {traj.duration:.4f} s")
        ax0.legend(loc="best")
        pts = smp.xyz[:, :2]
        segs = np.stack((pts[:-1], pts[1:]), axis=1)
        lc = LineCollection(segs, array=smp.speed[:-1], cmap="viridis", linewidths=2)
        ax1.add_collection(lc)
        ax1.autoscale()
        ax1.set_aspect("equal")
        ax1.set_xlabel("X [mm]")
        ax1.set_ylabel("Y [mm]")
        fig.colorbar(lc, ax=ax1, label="speed [mm/s]")
        ax1.set_title("speed over the path")
    if path is not None:
        fig.tight_layout()
        fig.savefig(str(path))
        plt.close(fig)
    return fig
