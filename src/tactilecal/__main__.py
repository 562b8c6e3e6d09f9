"""Allow ``python -m tactilecal``."""

import sys

from tactilecal.cli import console_main

sys.exit(console_main())
