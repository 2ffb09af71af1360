"""The ``exact`` corner strategy: the controller's tool-centre path, every corner left as it is."""

from __future__ import annotations

from trcopt.optimize.corners.records import CornerResult
from trcopt.optimize.corners.strategies import CornerJob

__all__ = ["exact_path"]


def exact_path(job: CornerJob) -> CornerResult:
    """The exact path of ``job``, unchanged and without corner records."""
    return job.unchanged()
