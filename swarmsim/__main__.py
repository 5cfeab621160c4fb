"""``python -m swarmsim`` is the same as the ``swarmsim`` command."""

import sys

from swarmsim.cli import main

sys.exit(main())
