"""Self-contained HTML reports of calibrations, dynamic filters and recordings.

One page, figures embedded as base64 PNG, with a provenance section (inputs with their
paths and SHA-256, package versions, date) so the numbers can be traced back.
"""

from tactilecal.report._html import build_report, write_report
from tactilecal.report._inputs import load_input

__all__ = ["build_report", "load_input", "write_report"]

