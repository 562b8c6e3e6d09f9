"""Static calibration of matrix tactile sensors: points, methods, results, validation.

A calibration point is one loaded frame reduced to its 256-bin histogram of raw values
(:class:`CalibrationPoint`); every method fits a per-sensel law ``f(raw)`` in newtons on
those histograms (:func:`calibrate`), giving a :class:`CalibrationResult` with parameters,
uncertainty, the error on every point, its figures (``cal.plot_curve()``,
``cal.save_figures(folder)``) and a JSON round-trip (:func:`load_calibration`).
See ``docs/static-calibration.md``.
"""

from tactilecal.calibration._calibrate import METHODS, calibrate, validate
from tactilecal.calibration._header import header_calibration
from tactilecal.calibration._manifest import load_points
from tactilecal.calibration._movie import calibrate_movie
from tactilecal.calibration._points import CalibrationPoint, frame_histograms, points_from_frames
from tactilecal.calibration._result import CalibrationResult, load_calibration
from tactilecal.calibration._sensels import (
    Equilibration,
    NonWorkingSensels,
    equilibrate,
    find_dead_sensels,
)
from tactilecal.calibration._validation import ValidationResult

__all__ = [
    "calibrate", "validate", "METHODS", "CalibrationResult", "load_calibration",
    "CalibrationPoint", "load_points", "points_from_frames", "frame_histograms",
    "calibrate_movie", "header_calibration",
    "equilibrate", "Equilibration", "find_dead_sensels", "NonWorkingSensels",
    "ValidationResult",
]
