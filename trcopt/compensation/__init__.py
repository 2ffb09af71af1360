"""Tool radius compensation: the engine and its controller profiles."""

from trcopt.compensation.engine import Compensator, compensate, programmed_segment

__all__ = ["Compensator", "compensate", "programmed_segment"]
