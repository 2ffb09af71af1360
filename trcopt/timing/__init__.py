"""Time-optimal feed along the exact tool-centre path (toppra and an own reachability solver).

``time_parameterize(toolpath, machine) -> TimedTrajectory``. toppra and matplotlib are imported
inside the functions that need them, so importing this package stays cheap.
"""

from __future__ import annotations

from trcopt.timing.solve import time_parameterize
from trcopt.timing.trajectory import LimitReport, Samples, TimedTrajectory

__all__ = ["time_parameterize", "TimedTrajectory", "LimitReport", "Samples"]
