"""trcopt — optimisation-based CNC toolpath planner.

Exact SINUMERIK/Heidenhain/LinuxCNC tool radius compensation, tool-centre G-code, time-optimal
feed with toppra, and optimised lead-ins and corners. ``import trcopt`` stays cheap: casadi,
toppra, matplotlib and ezdxf load inside the functions that need them.
"""

from __future__ import annotations

__version__ = "0.1.0"

from .config import DEFAULT_MACHINE, AxisLimits, Machine, Tolerances, TrcSettings, load_machine
from .errors import (
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
from .geometry import Arc, Line, Plane, Poly
from .path import Role, Segment

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
    "SolverError",
    "SourceSpan",
    "TimingError",
    "Tolerances",
    "TrcSettings",
    "TrcoptError",
    "load_machine",
]
