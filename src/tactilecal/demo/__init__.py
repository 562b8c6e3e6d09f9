"""The end-to-end example behind ``tactilecal demo``.

:func:`run_demo` calibrates the bundled synthetic dead-weight sessions by every static method
and Zvyagin's, validates each on a held-out session, applies the best calibration to a
simulated loading-machine recording, fits and tests a dynamic filter, and writes the HTML
report. :func:`make_bundle` regenerates the bundled sessions from their seeds.
"""

from tactilecal.demo._bundle import bundle_path
from tactilecal.demo._run import run_demo

__all__ = ["bundle_path", "run_demo"]

