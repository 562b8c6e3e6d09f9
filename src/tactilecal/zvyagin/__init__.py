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

from tactilecal.zvyagin._approx import (
    CLASS_VALUES,
    approximate_raw_sums,
    class_counts,
    loaded_cells,
    patch_discrepancy,
    raw_sums,
    search_separation,
    separation_domain,
)
from tactilecal.zvyagin._calibrate import MODES, SENSEL_AREA_5051_MM2, load_groups, zvyagin_fit
from tactilecal.zvyagin._compare import compare_table, format_compare_table, plot_compare
from tactilecal.zvyagin._fit import (
    energy,
    fit_power_law,
    minimise_energy,
    patch_power_sums,
    saturation_pressure_MPa,
)
from tactilecal.zvyagin._pairs import polynomial_roots, quartic_coefficients, solve_pairs
from tactilecal.zvyagin._plots import (
    as_zvyagin_result,
    plot_ab_scatter,
    plot_calibration_curves,
    plot_d_map,
    plot_energy,
    plot_error_histogram,
    plot_pair_chart,
    save_figures,
)
from tactilecal.zvyagin._points_api import OPTIONS, calibrate_zvyagin
from tactilecal.zvyagin._result import PAIR_CATEGORIES, ZvyaginResult

__all__ = [
    "plot_compare",
    "format_compare_table",
    "compare_table",
    "save_figures",
    "plot_pair_chart",
    "plot_error_histogram",
    "plot_energy",
    "plot_d_map",
    "plot_calibration_curves",
    "plot_ab_scatter",
    "as_zvyagin_result",
    "CLASS_VALUES",
    "MODES",
    "OPTIONS",
    "PAIR_CATEGORIES",
    "SENSEL_AREA_5051_MM2",
    "ZvyaginResult",
    "approximate_raw_sums",
    "calibrate_zvyagin",
    "class_counts",
    "energy",
    "fit_power_law",
    "load_groups",
    "loaded_cells",
    "minimise_energy",
    "patch_discrepancy",
    "patch_power_sums",
    "polynomial_roots",
    "quartic_coefficients",
    "raw_sums",
    "saturation_pressure_MPa",
    "search_separation",
    "separation_domain",
    "solve_pairs",
    "zvyagin_fit",
]
