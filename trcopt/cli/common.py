"""What every subcommand shares: exit codes and the error line."""

from __future__ import annotations

import sys

__all__ = ["EXIT_OK", "EXIT_ALARM", "EXIT_USAGE", "err"]

EXIT_OK, EXIT_ALARM, EXIT_USAGE = 0, 1, 2


def err(message: str) -> None:
    """One error line on stderr, prefixed like every trcopt error."""
    print(f"trcopt: error: {message}", file=sys.stderr)
