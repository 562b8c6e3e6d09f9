"""Static calibration of matrix tactile sensors: points, methods, results, validation.

A calibration point is one loaded frame reduced to its 256-bin histogram of raw values
(:class:`CalibrationPoint`); every method fits a per-sensel law ``f(raw)`` in newtons on
those histograms (:func:`calibrate`), giving a :class:`CalibrationResult` with parameters,
uncertainty, the error on every point and a JSON round-trip (:func:`load_calibration`).
See ``docs/static-calibration.md``.
"""

from tactilecal.calibration._calibrate import (
    METHODS,
    calibrate,
    make_result,
    select_points,
    validate,
)
from tactilecal.calibration._header import header_calibration
from tactilecal.calibration._manifest import find_plateau, load_frames, load_points
from tactilecal.calibration._methods import OBJECTIVES
from tactilecal.calibration._models import MODELS, force_table, sensel_force
from tactilecal.calibration._movie import calibrate_movie, movie_points, read_movie_loads
from tactilecal.calibration._plots import (
    plot_calibration_curve,
    plot_error_histogram,
    plot_points,
)
from tactilecal.calibration._points import (
    CalibrationPoint,
    frame_histograms,
    points_from_frames,
    points_to_arrays,
)
from tactilecal.calibration._result import CalibrationResult, load_calibration
from tactilecal.calibration._sensels import (
    Equilibration,
    NonWorkingSensels,
    equilibrate,
    find_dead_sensels,
    load_equilibration,
)
from tactilecal.calibration._uncertainty import PredictionInterval, prediction_interval
from tactilecal.calibration._validation import ValidationResult

__all__ = [
    "Equilibration", "NonWorkingSensels", "equilibrate", "find_dead_sensels", "load_frames",
    "load_equilibration", "header_calibration", "calibrate_movie", "movie_points",
    "read_movie_loads",
    "METHODS", "MODELS", "OBJECTIVES", "CalibrationPoint", "CalibrationResult", "calibrate",
    "find_plateau", "force_table", "frame_histograms", "load_calibration", "load_points",
    "make_result",
    "plot_calibration_curve", "plot_error_histogram", "plot_points", "points_from_frames",
    "points_to_arrays", "select_points", "sensel_force", "validate", "PredictionInterval",
    "prediction_interval", "ValidationResult",
]
