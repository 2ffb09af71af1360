"""Optimisation: the constraint model, plan verification, SAR as a constrained problem, optimal leads.

* :func:`verify_plan` — per-family residuals of a planned path (radius, tangency, continuity,
  no_reversal, clearance; lead_clearance informational);
* :class:`SarProblem` — SINUMERIK SAR geometry as a ``casadi.Opti`` problem;
* :func:`optimal_lead` — time-optimal lead-in under the constraint model; :func:`leadin_gcode`,
  :func:`compare_with_sar`; :func:`optimal_lead_out` — the lead-out (the mirrored lead-in);
* :func:`register` / :func:`run_leadin` — the ``trcopt leadin`` subcommand.

CasADi is imported inside the functions that build problems, so importing this package is cheap.
"""

from __future__ import annotations

from .cli import register, run_leadin
from .lead_io import Baseline, compare_with_sar, leadin_gcode, leadin_svg
from .leadin import LeadCandidate, LeadResult, SarShape, optimal_lead
from .leadout import LeadOutResult, optimal_lead_out
from .sar_problem import SarGeometry, SarProblem
from .solution import Solution, SolveStatus
from .verify import FamilyResidual, VerificationReport, verify_plan

__all__ = [
    "Baseline",
    "FamilyResidual",
    "LeadCandidate",
    "LeadOutResult",
    "LeadResult",
    "SarGeometry",
    "SarProblem",
    "SarShape",
    "Solution",
    "SolveStatus",
    "VerificationReport",
    "compare_with_sar",
    "leadin_gcode",
    "leadin_svg",
    "optimal_lead",
    "optimal_lead_out",
    "register",
    "run_leadin",
    "verify_plan",
]
