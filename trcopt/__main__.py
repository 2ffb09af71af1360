"""``python -m trcopt`` — the same as the ``trcopt`` command."""

import sys

try:
    from trcopt.cli import main
except KeyboardInterrupt:  # Ctrl-C while the interpreter loads the command line: no traceback
    sys.exit(130)

sys.exit(main())
