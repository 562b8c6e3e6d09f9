"""Allow ``python -m tactilecal``."""

import sys

from tactilecal.cli import main

sys.exit(main())
