"""The corner strategies and their registry — the only place that knows them by name.

A corner strategy decides what replaces the tangent discontinuities of a tool-centre path: a
function ``(CornerJob) -> CornerResult`` in a module of its own. The registry holds where each
one lives (module path and function name) and imports it on first use, so naming the strategies
(``trcopt plan --corners``) loads no numerical library. Adding a strategy is one module plus one
line in ``_BUILTIN`` below (or :func:`register` at run time).

* ``exact`` — the controller's path, untouched (:mod:`trcopt.optimize.corners.exact`);
* ``arc`` — the largest same-ε circular blends (:mod:`trcopt.optimize.corners.arc`);
* ``optimal`` — G2 quintics and splines by SQP, the fastest of G2, circular and a per-corner mix
  (:mod:`trcopt.optimize.corners.optimal`).

:func:`names` lists the registered names, :func:`get` finds one (rejecting an unknown name with
the valid ones), :func:`register` / :func:`unregister` add and remove strategies at run time.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from trcopt.config import Machine
from trcopt.modes import CornerObjective, ToleranceKind
from trcopt.optimize.corners.records import CornerResult
from trcopt.path import Segment

if TYPE_CHECKING:
    from trcopt.optimize.corners.fillet import FilletSpec

__all__ = [
    "EXACT", "PROGRAM", "CornerJob", "CornerStrategy", "StrategyFunction", "get", "names", "register", "unregister",
]

EXACT = "exact"  # the strategy that keeps the controller's path, exact stop at every corner
PROGRAM = "program"  # what the program's path-control mode does (the default of --corners)


@dataclass(frozen=True)
class CornerJob:
    """What a corner strategy is asked to do (built by
    :func:`~trcopt.optimize.corners.blend.blend_corners`).

    Attributes
    ----------
    strategy:
        The registry name the job runs under (the result's ``mode``).
    toolpath:
        Exact tool-centre path (output of compensation).
    programmed:
        The programmed (uncompensated) path: the no-gouge and deviation reference.
    tolerance_mm:
        Contour tolerance ε, mm: material left beyond the exact cut ≤ ε.
    machine:
        Axis limits for choices made by timing (None: the default machine).
    workers:
        Processes for independent per-corner problems (``1``: this process).
    select:
        Time the alternatives and keep the fastest (see :func:`blend_corners`).
    objective:
        What optimised transitions minimise.
    jerk_limits:
        ``(amax mm/s², jmax mm/s³)`` of the machine's X/Y axes for the ``jerk`` objective, else None.
    chains:
        Replace runs of small CAM corners by one G2 spline each.
    kind:
        How the tolerance of a corner of an uncompensated path is measured (a compensated path's
        tolerance bounds its cut part).
    tolerances:
        Tolerance by joint index where the program sets its own (its path-control mode), mm;
        ``tolerance_mm`` elsewhere.
    program:
        The blends of the program's path-control modes by joint index (the ``program`` strategy).
    """

    strategy: str
    toolpath: Sequence[Segment]
    programmed: Sequence[Segment]
    tolerance_mm: float
    machine: Machine | None = None
    workers: int = 1
    select: bool = True
    objective: CornerObjective = CornerObjective.CURVATURE
    jerk_limits: tuple[float, float] | None = None
    chains: bool = True
    kind: ToleranceKind = ToleranceKind.CONTOUR
    tolerances: Mapping[int, float] | None = None
    program: Mapping[int, FilletSpec] | None = None

    def tolerance_at(self, joint: int) -> float:
        """The tolerance of the corner at ``joint``, mm."""
        if self.tolerances is not None:
            return self.tolerances.get(joint, self.tolerance_mm)
        return self.tolerance_mm

    def unchanged(self) -> CornerResult:
        """The exact path with no corner touched."""
        return CornerResult(list(self.toolpath), [], 0.0, self.strategy)


StrategyFunction = Callable[[CornerJob], CornerResult]


@dataclass(frozen=True)
class CornerStrategy:
    """A registered strategy: its name, where its function lives, one line of help.

    Attributes
    ----------
    name:
        Registry name (lower case; ``--corners`` value, ``PlanOptions.corners``, JSON ``corners.mode``).
    module:
        Import path of the module holding the function.
    function:
        Name of the ``(CornerJob) -> CornerResult`` function in ``module``.
    summary:
        What the strategy puts at a corner, one line.
    """

    name: str
    module: str
    function: str
    summary: str

    def load(self) -> StrategyFunction:
        """The strategy's function (imports its module on first use)."""
        fn: StrategyFunction = getattr(importlib.import_module(self.module), self.function)
        return fn


_BUILTIN = (
    CornerStrategy(
        PROGRAM, "trcopt.optimize.corners.program", "program_transitions", "the program's path-control mode"
    ),
    CornerStrategy(EXACT, "trcopt.optimize.corners.exact", "exact_path", "the controller's path, untouched"),
    CornerStrategy("optimal", "trcopt.optimize.corners.optimal", "optimal_transitions", "G2 quintics/splines by SQP"),
    CornerStrategy("arc", "trcopt.optimize.corners.arc", "arc_transitions", "largest same-ε circular blends"),
)
_REGISTRY: dict[str, CornerStrategy] = {s.name: s for s in _BUILTIN}


def names() -> tuple[str, ...]:
    """Registered strategy names, in registration order."""
    return tuple(_REGISTRY)


def get(name: str | CornerStrategy) -> CornerStrategy:
    """The strategy called ``name`` (case-insensitive); an unknown name raises :class:`ValueError`
    listing the valid ones."""
    if isinstance(name, CornerStrategy):
        return name
    found = _REGISTRY.get(str(name).strip().lower())
    if found is None:
        raise ValueError(f"unknown corner strategy {name!r}; valid: {', '.join(names())}")
    return found


def register(strategy: CornerStrategy) -> CornerStrategy:
    """Add a strategy; its name must be new and lower case."""
    if strategy.name != strategy.name.strip().lower() or not strategy.name:
        raise ValueError(f"a corner strategy name is lower case without blanks, got {strategy.name!r}")
    if strategy.name in _REGISTRY:
        raise ValueError(f"a corner strategy called {strategy.name!r} is registered")
    _REGISTRY[strategy.name] = strategy
    return strategy


def unregister(name: str) -> None:
    """Remove a strategy added with :func:`register` (the built-in strategies stay)."""
    strategy = get(name)
    if strategy in _BUILTIN:
        raise ValueError(f"{strategy.name!r} is a built-in corner strategy")
    del _REGISTRY[strategy.name]
