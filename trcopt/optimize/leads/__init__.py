"""Optimal lead-in and lead-out, and SINUMERIK SAR as a constrained problem.

* :func:`optimal_lead` — time-optimal lead-in under the constraint model; :func:`optimal_lead_out`
  — the lead-out (the mirrored lead-in);
* :class:`SarProblem` — the SAR construction as a ``casadi.Opti`` problem;
* :func:`compare_with_sar`, :func:`leadin_gcode`, :func:`leadin_svg` — against the controller's
  SAR defaults, and as G-code and SVG.
"""

from __future__ import annotations

from trcopt.optimize.leads.leadin import optimal_lead
from trcopt.optimize.leads.leadout import LeadOutResult, optimal_lead_out
from trcopt.optimize.leads.records import LeadCandidate, LeadResult, SarShape
from trcopt.optimize.leads.report import Baseline, compare_with_sar, leadin_gcode, leadin_svg
from trcopt.optimize.leads.sar_geometry import SarGeometry
from trcopt.optimize.leads.sar_problem import SarProblem

__all__ = [
    "Baseline",
    "LeadCandidate",
    "LeadOutResult",
    "LeadResult",
    "SarGeometry",
    "SarProblem",
    "SarShape",
    "compare_with_sar",
    "leadin_gcode",
    "leadin_svg",
    "optimal_lead",
    "optimal_lead_out",
]
