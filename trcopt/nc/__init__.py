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

# --- NC front end: reading programs (lexer, dialects, modal interpreter) ---
from .dialects import detect_dialect  # noqa: E402
from .interpret import ReadOptions, read_program  # noqa: E402
from .tools import ToolEdge, ToolTable  # noqa: E402

__all__ += ["ReadOptions", "ToolEdge", "ToolTable", "detect_dialect", "read_program"]
