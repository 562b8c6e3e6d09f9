"""Zvyagin (2022) multi-patch calibration using high-pressure zones.

Zvyagin, P. (2022). Tactile Pressure Sensors Calibration with the Use of High Pressure
Zones. Sensors 22(19), 7290. https://doi.org/10.3390/s22197290

The four steps of the paper are separate functions on raw-value histograms of the patches
(:func:`search_separation`, :func:`solve_pairs`, :func:`fit_power_law`,
:func:`minimise_energy`); :func:`zvyagin_fit` runs them all and returns a
:class:`ZvyaginResult` holding every intermediate; :func:`calibrate_zvyagin` does the same
from calibration points and returns a :class:`tactilecal.calibration.CalibrationResult`.
See ``docs/zvyagin.md`` for the choices the paper leaves open.
"""

from tactilecal._deprecated import moved_names
from tactilecal.zvyagin._approx import search_separation
from tactilecal.zvyagin._calibrate import MODES, zvyagin_fit
from tactilecal.zvyagin._compare import compare_table, plot_compare
from tactilecal.zvyagin._fit import fit_power_law, minimise_energy
from tactilecal.zvyagin._pairs import solve_pairs
from tactilecal.zvyagin._plots import (
    plot_ab_scatter,
    plot_calibration_curves,
    plot_d_map,
    plot_energy,
    plot_pair_chart,
    plot_patch_errors,
    save_figures,
)
from tactilecal.zvyagin._points_api import calibrate_zvyagin
from tactilecal.zvyagin._result import ZvyaginResult

__all__ = [
    "zvyagin_fit", "ZvyaginResult", "MODES", "calibrate_zvyagin",
    "search_separation", "solve_pairs", "fit_power_law", "minimise_energy",
    "plot_d_map", "plot_pair_chart", "plot_ab_scatter", "plot_calibration_curves",
    "plot_patch_errors", "plot_energy", "save_figures",
    "compare_table", "plot_compare",
]

_STEP = "an internal of the paper's steps; zvyagin_fit() keeps every intermediate"
__getattr__ = moved_names(__name__, {
    **{name: ("_approx", name, _STEP)
       for name in ("CLASS_VALUES", "approximate_raw_sums", "class_counts", "loaded_cells",
                    "patch_discrepancy", "raw_sums", "separation_domain")},
    **{name: ("_fit", name, _STEP)
       for name in ("energy", "patch_power_sums", "saturation_pressure_MPa")},
    **{name: ("_pairs", name, _STEP) for name in ("polynomial_roots", "quartic_coefficients")},
    "load_groups": ("_calibrate", "load_groups", _STEP),
    "SENSEL_AREA_5051_MM2": ("_calibrate", "SENSEL_AREA_5051_MM2",
                             "use tactilecal.sensors.get_sensor('5051').sensel_area_mm2"),
    "OPTIONS": ("_points_api", "OPTIONS", "see calibrate()'s docstring"),
    "PAIR_CATEGORIES": ("_result", "PAIR_CATEGORIES", "see ZvyaginResult's docstring"),
    "format_compare_table": ("_compare", "format_compare_table", "print compare_table()"),
    "as_zvyagin_result": ("_plots", "as_zvyagin_result", "the plots accept a "
                          "CalibrationResult of method 'zvyagin' directly"),
    "plot_error_histogram": ("_plots", "plot_patch_errors", "renamed plot_patch_errors (it "
                             "clashed with tactilecal.calibration.plot_error_histogram)"),
})
