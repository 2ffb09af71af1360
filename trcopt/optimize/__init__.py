"""Optimisation problems on the tool-centre geometry: leads and corner transitions.

* :mod:`trcopt.optimize.leads` — optimal lead-in/out (:func:`optimal_lead`,
  :func:`optimal_lead_out`) and :class:`SarProblem`;
* :mod:`trcopt.optimize.corners` — feed-optimised corner transitions (:func:`blend_corners`) and
  the registry of corner strategies (:mod:`trcopt.optimize.corners.strategies`).

Every problem is an object that can be inspected before it is solved and returns a
:class:`~trcopt.solution.Solution`. The constraint model they share lives in :mod:`trcopt.verify`.
The names below load on first use (PEP 562) and CasADi and OSQP are imported inside the functions
that build problems, so importing this package — or the corner-strategy registry — loads no
numerical library.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
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

_LEADS = "trcopt.optimize.leads"
_LAZY = {
    name: _LEADS
    for name in (
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
    )
}


def __getattr__(name: str) -> object:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})


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
