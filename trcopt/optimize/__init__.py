"""Optimisation problems on the tool-centre geometry: leads and corner transitions.

* :mod:`trcopt.optimize.leads` — optimal lead-in/out (:func:`optimal_lead`,
  :func:`optimal_lead_out`) and :class:`SarProblem`;
* :mod:`trcopt.optimize.corners` — feed-optimised corner transitions (:func:`blend_corners`) and
  the registry of corner strategies (:mod:`trcopt.optimize.corners.strategies`).

Every problem is an object that can be inspected before it is solved and returns a
:class:`~trcopt.solution.Solution`. The constraint model they share lives in :mod:`trcopt.verify`.
CasADi and Clarabel are imported inside the functions that build problems; importing this package —
or the corner-strategy registry — loads no numerical library.
"""
