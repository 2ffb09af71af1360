"""Tool radius compensation: the engine and its controller profiles."""

from .engine import Compensator, compensate

__all__ = ["Compensator", "compensate"]
