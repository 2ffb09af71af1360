"""Optimisation: the constraint model, plan verification, SAR as a constrained problem, optimal leads.

CasADi is imported inside the functions that build problems, so importing this package is cheap.
"""

from __future__ import annotations

from .verify import FamilyResidual, VerificationReport, verify_plan

__all__ = ["FamilyResidual", "VerificationReport", "verify_plan"]
