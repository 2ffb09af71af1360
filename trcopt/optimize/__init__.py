"""Optimisation problems on the tool-centre geometry: leads and corner transitions.

* :mod:`trcopt.optimize.leads` — optimal lead-in/out (:func:`optimal_lead`,
  :func:`optimal_lead_out`) and :class:`SarProblem`;
* :mod:`trcopt.optimize.corners` — feed-optimised corner transitions (:func:`blend_corners`).

Every problem is an object that can be inspected before it is solved and returns a
:class:`~trcopt.solution.Solution`. The constraint model they share lives in :mod:`trcopt.verify`.
CasADi and OSQP are imported inside the functions that build problems, so importing this package
is cheap.
"""

from __future__ import annotations

from trcopt.optimize.leads import (
    Baseline,
    LeadCandidate,
    LeadOutResult,
    LeadResult,
    SarGeometry,
    SarProblem,
    SarShape,
    compare_with_sar,
    leadin_gcode,
    leadin_svg,
    optimal_lead,
    optimal_lead_out,
)

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
