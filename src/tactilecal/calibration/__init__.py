"""Static calibration of matrix tactile sensors: points, methods, results, validation.

A calibration point is one loaded frame reduced to its 256-bin histogram of raw values
(:class:`CalibrationPoint`); every method fits a per-sensel law ``f(raw)`` in newtons on
those histograms (:func:`calibrate`), giving a :class:`CalibrationResult` with parameters,
uncertainty, the error on every point, its figures (``cal.plot_curve()``,
``cal.save_figures(folder)``) and a JSON round-trip (:func:`load_calibration`).
See ``docs/static-calibration.md``.
"""

from tactilecal._deprecated import moved_names
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

_RESULT = "use CalibrationResult.force_table() or .predict_sensel_force(raw)"
__getattr__ = moved_names(__name__, {
    "MODELS": ("_models", "MODELS", "the model of each method is CalibrationResult.model"),
    "OBJECTIVES": ("_methods", "OBJECTIVES", "see calibrate()'s objective= docstring"),
    "force_table": ("_models", "force_table", _RESULT),
    "sensel_force": ("_models", "sensel_force", _RESULT),
    "make_result": ("_calibrate", "make_result", "use calibrate()"),
    "select_points": ("_calibrate", "select_points", "select the points before calibrate()"),
    "find_plateau": ("_manifest", "find_plateau", "load_points() finds the plateau"),
    "load_frames": ("_manifest", "load_frames", "calibrate(manifest, mask='detect') finds "
                    "the non-working sensels over the manifest's frames"),
    "movie_points": ("_movie", "movie_points", "use calibrate_movie()"),
    "read_movie_loads": ("_movie", "read_movie_loads", "use calibrate_movie()"),
    "points_to_arrays": ("_points", "points_to_arrays", "use calibrate()"),
    "PredictionInterval": ("_uncertainty", "PredictionInterval",
                           "use calibrate(..., n_interval_resamples=N)"),
    "prediction_interval": ("_uncertainty", "prediction_interval",
                            "use calibrate(..., n_interval_resamples=N)"),
    "plot_calibration_curve": ("_plots", "plot_calibration_curve",
                               "use the method CalibrationResult.plot_curve()"),
    "plot_points": ("_plots", "plot_points", "use the method CalibrationResult.plot_points()"),
    "plot_error_histogram": ("_plots", "plot_error_histogram",
                             "use the method CalibrationResult.plot_error_histogram()"),
    "load_equilibration": ("_sensels", "load_equilibration", "use "
                           "Equilibration.from_json(path) or tactilecal.load(path)"),
})
