"""Time-optimal feed along the exact tool-centre path (toppra and an own reachability solver).

``time_parameterize(toolpath, machine) -> TimedTrajectory``; the jerk-limited variant is
:func:`trcopt.timing.jerk.jerk_limited`. Both results satisfy the :class:`Trajectory` protocol
(re-exported here from :mod:`trcopt.trajectory` with its value types ``Samples`` and
``LimitReport``). toppra and casadi are imported inside the functions that need them, so importing
this package stays cheap.
"""

from __future__ import annotations

from trcopt.timing.solve import time_parameterize
from trcopt.timing.trajectory import TimedTrajectory
from trcopt.trajectory import LimitReport, Samples, Trajectory

__all__ = ["time_parameterize", "TimedTrajectory", "Trajectory", "LimitReport", "Samples"]
