"""``python -m trcopt`` — the same as the ``trcopt`` command."""

import sys

from trcopt.cli import main

sys.exit(main())
