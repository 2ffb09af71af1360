"""Axis ticks of the pictures: a readable step and its labels."""

from __future__ import annotations

import math

__all__ = ["nice_step", "tick_label"]


def nice_step(x: float) -> float:
    """1, 2 or 5 × a power of ten, the nearest to ``x`` (> 0) on a logarithmic scale."""
    e = 10.0 ** math.floor(math.log10(x))
    f = x / e
    return (1.0 if f < 1.5 else 2.0 if f < 3.5 else 5.0 if f < 7.5 else 10.0) * e


def tick_label(v: float, step: float) -> str:
    """``v`` with as many decimals as ``step`` needs, and no ``-0``."""
    decimals = max(0, min(6, -math.floor(math.log10(step) + 1e-9)))
    text = f"{v:.{decimals}f}"
    return text[1:] if text.startswith("-") and float(text) == 0.0 else text
