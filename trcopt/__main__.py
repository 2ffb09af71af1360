"""``python -m trcopt`` — the same as the ``trcopt`` command."""

import sys

from .cli import main

sys.exit(main())
