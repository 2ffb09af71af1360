"""trcopt — optimisation-based CNC toolpath planner.

Exact SINUMERIK/Heidenhain/LinuxCNC tool radius compensation, tool-centre G-code, time-optimal
feed with toppra, and optimised lead-ins and corners. ``import trcopt`` stays cheap: casadi,
toppra, matplotlib and ezdxf load inside the functions that need them.
"""

from __future__ import annotations

from trcopt.lazy import lazy_exports

__version__ = "0.1.0"

from trcopt.config import DEFAULT_MACHINE, AxisLimits, Machine, Tolerances, TrcSettings, load_machine
from trcopt.errors import (
    AlarmError,
    ConfigError,
    Diagnostic,
    GeometryError,
    NcSyntaxError,
    NcUnsupportedError,
    Severity,
    SolverError,
    SourceSpan,
    TimingError,
    TrcoptError,
)
from trcopt.geometry import Arc, Line, Plane, Poly
from trcopt.modes import Side
from trcopt.path import Role, Segment

# The stages load on first use (PEP 562), so ``import trcopt`` loads no numerical library.
_LAZY = {
    "plan": "trcopt.pipeline",
    "plan_file": "trcopt.pipeline",
    "PlanOptions": "trcopt.pipeline",
    "PlanResult": "trcopt.pipeline",
    "read_program": "trcopt.controllers",
    "compensate": "trcopt.compensation",
    "time_parameterize": "trcopt.timing",
    "Trajectory": "trcopt.timing",
}


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)


__all__ = [
    "__version__",
    "AlarmError",
    "Arc",
    "AxisLimits",
    "ConfigError",
    "DEFAULT_MACHINE",
    "Diagnostic",
    "GeometryError",
    "Line",
    "Machine",
    "NcSyntaxError",
    "NcUnsupportedError",
    "Plane",
    "Poly",
    "Role",
    "Segment",
    "Severity",
    "Side",
    "SolverError",
    "SourceSpan",
    "TimingError",
    "Tolerances",
    "TrcSettings",
    "TrcoptError",
    "load_machine",
    *_LAZY,
]
