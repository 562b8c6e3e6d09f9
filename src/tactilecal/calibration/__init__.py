"""Static calibration of matrix tactile sensors: points, methods, results, validation.

A calibration point is one loaded frame reduced to its 256-bin histogram of raw values
(:class:`CalibrationPoint`); every method fits a per-sensel law ``f(raw)`` in newtons on
those histograms. :func:`calibrate` is the one door to every method
(:mod:`tactilecal.calibration.methods`: the I-Scan methods, the literature's and Zvyagin's
2022 multi-patch method); it returns a :class:`CalibrationResult` with the law, the
preprocessing, the error on every point, its figures (``cal.plot_curve()``,
``cal.save_figures(folder)``) and a JSON round-trip (``cal.to_json(path)``,
``tactilecal.load(path)``). See ``docs/static-calibration.md``.
"""

from tactilecal.calibration._calibrate import (
    DEFAULT_METHOD,
    METHODS,
    CommonOptions,
    calibrate,
    validate,
)
from tactilecal.calibration._compare import compare_calibrations
from tactilecal.calibration._header import header_calibration
from tactilecal.calibration._manifest import load_points
from tactilecal.calibration._movie import calibrate_movie
from tactilecal.calibration._points import CalibrationPoint, frame_histograms, points_from_frames
from tactilecal.calibration._result import CalibrationResult
from tactilecal.calibration._sensels import (
    Equilibration,
    NonWorkingSensels,
    equilibrate,
    find_dead_sensels,
)
from tactilecal.calibration._uncertainty import PredictionInterval
from tactilecal.calibration._validation import ValidationResult
from tactilecal.calibration.methods import MODULES as _MODULES
from tactilecal.calibration.methods import auto as _auto
from tactilecal.calibration.methods.zvyagin import ZvyaginResult

METHOD_OPTIONS = {_auto.NAME: _auto.Options,
                  **{name: module.Options for name, module in _MODULES.items()}}
"""Method name -> the frozen dataclass of its options (fields, defaults, help text)."""

__all__ = [
    "calibrate", "validate", "METHODS", "DEFAULT_METHOD", "METHOD_OPTIONS", "CommonOptions",
    "CalibrationResult", "CalibrationPoint", "load_points", "points_from_frames",
    "frame_histograms", "calibrate_movie", "header_calibration",
    "equilibrate", "Equilibration", "find_dead_sensels", "NonWorkingSensels",
    "PredictionInterval", "ValidationResult", "ZvyaginResult", "compare_calibrations",
]
