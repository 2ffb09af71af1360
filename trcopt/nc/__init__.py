"""NC front end: lexer, dialects, and the modal interpreter producing canonical moves."""

from .model import (
    ApproachMode,
    ApproachStrategy,
    CollisionMode,
    CompState,
    CornerMode,
    Move,
    MoveKind,
    NcProgram,
    SarContour,
    SarSegmentation,
    SarSide,
    SarSpec,
    Side,
)

__all__ = [
    "ApproachMode",
    "ApproachStrategy",
    "CollisionMode",
    "CompState",
    "CornerMode",
    "Move",
    "MoveKind",
    "NcProgram",
    "SarContour",
    "SarSegmentation",
    "SarSide",
    "SarSpec",
    "Side",
]
