"""The end-to-end example behind ``tactilecal demo``.

:func:`run_demo` calibrates the bundled synthetic dead-weight sessions by every static method
and Zvyagin's, validates each on a held-out session, applies the best calibration to a
simulated loading-machine recording, fits and tests a dynamic filter, and writes the HTML
report. :func:`make_bundle` regenerates the bundled sessions from their seeds.
"""

from tactilecal._deprecated import moved_names
from tactilecal.demo._bundle import bundle_path
from tactilecal.demo._run import run_demo

__all__ = ["bundle_path", "run_demo"]

__getattr__ = moved_names(__name__, {
    "BUNDLE": ("_bundle", "BUNDLE", "use bundle_path()"),
    "demo_sensor": ("_bundle", "demo_sensor", "use tactilecal.simulate.make_sensor()"),
    "make_bundle": ("_bundle", "make_bundle", "a maintainer's tool: run "
                    "python -m tactilecal.demo._bundle"),
})
