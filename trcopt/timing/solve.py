"""``time_parameterize``: the time-optimal feed along the tool-centre path.

Pipeline: split at tangent discontinuities (:mod:`.sections`) → adaptive grid on the exact
geometry (:mod:`.grid`) → per section either the own vectorised reachability solver
(:mod:`.reach`, sections made of lines and arcs/helices) or toppra (:mod:`.toppra_engine`,
sections with Poly curves, sections where the own solver reports an infeasible step, or every
section with ``engine="toppra"``) → exact closed-form profile on lines → :class:`TimedTrajectory`.

The machine's vector limits (``machine.path``) join the per-axis ones: the path speed limit caps
the feed of every segment, and the limit on |a| adds the rows of
:func:`~trcopt.timing.reach.solve_lockstep_vector` to the own solver (exact on lines and arcs) and
an inscribed polygon of the (s̈, κṡ²) disc to toppra.
"""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from trcopt.config import DEFAULT_MACHINE, Machine
from trcopt.modes import TimingEngine, parse_enum
from trcopt.path import Segment
from trcopt.timing.own import solve_own
from trcopt.timing.path import PathArrays
from trcopt.timing.profiles import Profiles
from trcopt.timing.sections import Section, axis_limits, path_speed_caps, segment_feeds, split_sections
from trcopt.timing.toppra_engine import solve_section_toppra
from trcopt.timing.trajectory import TimedTrajectory

__all__ = ["time_parameterize"]


def time_parameterize(
    toolpath: Sequence[Segment],
    machine: Machine = DEFAULT_MACHINE,
    *,
    engine: TimingEngine | str = TimingEngine.AUTO,
    workers: int = 1,
    tangent_tol_rad: float = 1e-6,
) -> TimedTrajectory:
    """Time-optimal feed profile of a tool-centre path under the machine's limits.

    Parameters
    ----------
    toolpath:
        Tool-centre segments in path order (lines, arcs/helices, Poly curves).
    machine:
        Per-axis ``vmax`` (mm/s) and ``amax`` (mm/s²), the optional vector limits
        ``machine.path`` (path speed, |a|), rapid feed and feed reference.
    engine:
        ``AUTO`` (own reachability solver on every section — lines and arcs in closed form, Poly
        curves on their turning-refined grid — and toppra on a section it cannot solve), ``OWN``
        (same, spelled out) or ``TOPPRA`` (toppra on every section); the value strings are accepted.
    workers:
        Processes for the toppra sections (independent sections run in parallel).
    tangent_tol_rad:
        Joints turning more than this are tangent discontinuities (speed 0 there), rad.

    Returns
    -------
    TimedTrajectory
        ``duration``, ``sample(dt)``, ``check_limits()``, ``segments_with_times()``, ``to_json()``.

    Raises
    ------
    TimingError
        A section cannot be parameterised; names section, s, source block and a remedy.
    """
    engine = parse_enum(TimingEngine, engine, "timing engine")
    segments = list(toolpath)
    vmax, amax = axis_limits(machine)
    if not segments:
        return TimedTrajectory.empty(machine)
    arrays = PathArrays(segments)
    feeds = segment_feeds(segments, machine)
    speed = path_speed_caps(feeds, machine)
    path_amax = machine.path.amax_mm_s2
    sections = split_sections(segments, arrays, tangent_tol_rad)
    use_toppra = [engine is TimingEngine.TOPPRA] * len(sections)
    results = Profiles()
    own = [sec for sec, t in zip(sections, use_toppra, strict=True) if not t]
    if own:
        results, failed = solve_own(own, arrays, speed, vmax, amax, path_amax)
        for k in failed:
            use_toppra[k] = True
    tsecs = [sec for sec, t in zip(sections, use_toppra, strict=True) if t]
    toppra_results = _solve_toppra_all(tsecs, segments, speed, vmax, amax, path_amax, workers)
    for sec, (grid, x) in zip(tsecs, toppra_results, strict=True):
        local_start = arrays.start[sec.first : sec.last + 1] - sec.s_start
        # the segment of an interval by its midpoint: a grid point on a knot may round to either side
        mid = 0.5 * (grid[:-1] + grid[1:])
        iseg = sec.first + np.clip(np.searchsorted(local_start, mid, side="right") - 1, 0, sec.last - sec.first)
        results.add(sec.index, grid + sec.s_start, x, iseg)
    engines = ["toppra" if t else "own" for t in use_toppra]
    return TimedTrajectory.assemble(segments, machine, feeds, arrays, sections, engines, results)


def _solve_toppra_all(
    secs: list[Section], segments: list[Segment], feeds: np.ndarray, vmax: np.ndarray, amax: np.ndarray,
    path_amax: float | None, workers: int,
) -> list[tuple[np.ndarray, np.ndarray]]:
    jobs = [
        (sec, segments[sec.first : sec.last + 1], feeds[sec.first : sec.last + 1], vmax, amax, path_amax)
        for sec in secs
    ]
    if workers > 1 and len(jobs) > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            return list(pool.map(_toppra_job, jobs))
    return [_toppra_job(j) for j in jobs]


def _toppra_job(job: tuple) -> tuple[np.ndarray, np.ndarray]:
    sec, segs, feeds, vmax, amax, path_amax = job
    return solve_section_toppra(sec, segs, feeds, vmax, amax, path_amax=path_amax)
