"""Typed solver results shared by the optimisation problems (design.md §3 "Solvers")."""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

from trcopt.codes import Code
from trcopt.errors import SolverError

__all__ = ["SolveStatus", "Solution", "binding_constraint"]

G = TypeVar("G")


class SolveStatus(enum.Enum):
    OPTIMAL = "optimal"
    INFEASIBLE = "infeasible"
    FAILED = "failed"


@dataclass(frozen=True, slots=True)
class Solution(Generic[G]):
    """Result of ``Problem.solve()``.

    Attributes
    ----------
    status:
        :class:`SolveStatus`; only ``OPTIMAL`` carries usable geometry.
    cost:
        Objective value at the returned point (problem units, documented by the problem).
    iterations:
        Solver iterations.
    solve_time_s:
        Wall time of the solve, s.
    geometry:
        The decoded geometry (problem specific), also present for a failed solve (last iterate).
    constraint_violation:
        Largest violation per constraint group at the returned point (mm unless stated).
    message:
        Solver return status text.
    """

    status: SolveStatus
    cost: float
    iterations: int
    solve_time_s: float
    geometry: G
    constraint_violation: dict[str, float] = field(default_factory=dict)
    message: str = ""
    solver: str = "ipopt"

    @property
    def ok(self) -> bool:
        return self.status is SolveStatus.OPTIMAL

    @property
    def binding(self) -> str | None:
        """The constraint group with the largest violation (None when all are satisfied)."""
        return binding_constraint(self.constraint_violation)

    def raise_for_status(self) -> Solution[G]:
        """Return ``self`` when optimal; else raise :class:`SolverError` naming the binding constraint."""
        if self.ok:
            return self
        name = self.binding or "unknown"
        worst = self.constraint_violation.get(name, float("nan"))
        raise SolverError(
            f"{self.solver} {self.status.value} ({self.message}): binding constraint '{name}' violated by {worst:.6g}",
            code=Code.SOLVER_INFEASIBLE if self.status is SolveStatus.INFEASIBLE else "SOLVER",
        )


def binding_constraint(violations: dict[str, float], tol: float = 1e-7) -> str | None:
    if not violations:
        return None
    name, value = max(violations.items(), key=lambda kv: kv[1])
    return name if value > tol else None


def ipopt_options(tol: float = 1e-12, max_iter: int = 500, print_level: int = 0) -> dict[str, Any]:
    """Quiet IPOPT options used by every problem (tight tolerances: the geometry is compared to
    analytic constructions at 1e-7 mm)."""
    return {
        "print_time": False,
        "ipopt": {
            "print_level": print_level,
            "sb": "yes",
            "tol": tol,
            "constr_viol_tol": tol,
            "acceptable_tol": 1e-10,
            "max_iter": max_iter,
        },
    }
