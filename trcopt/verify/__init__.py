"""The constraint model of the tool-centre geometry and the verification of every plan.

* :mod:`.model` — closed-form residual functions (distance to an element = radius, tangency at
  joints, no reversal of the infeed, clearance from the programmed contour); the optimisation
  problems of :mod:`trcopt.optimize` use the same functions as constraints;
* :mod:`.plan` — :func:`verify_plan`: the largest residual of each family over a planned path;
* :mod:`.contour` — the part contour, without approach/retraction and CAM lead blocks;
* :mod:`.joints` — where the controller's own rules bring the tool nearer than R (near-tangent
  joints left as they are, the transitions at the contour's start and end, its closing joint);
* :mod:`.index` — the uniform grid that keeps the clearance check linear in the plan's length;
* :mod:`.table`, :mod:`.contact`, :mod:`.batch`, :mod:`.pairs`, :mod:`.clearance` — the path as
  arrays and the residuals of whole paths at once (the values of the per-segment functions);
* :mod:`.report` — the per-family result and its JSON and diagnostics.
"""

from __future__ import annotations

from trcopt.verify.plan import FAMILIES, FamilyResidual, VerificationReport, verify_plan

__all__ = ["FAMILIES", "FamilyResidual", "VerificationReport", "verify_plan"]
