"""Zvyagin (2022) multi-patch calibration using high-pressure zones.

Zvyagin, P. (2022). Tactile Pressure Sensors Calibration with the Use of High Pressure
Zones. Sensors 22(19), 7290. https://doi.org/10.3390/s22197290

The four steps of the paper are separate functions on raw-value histograms of the patches
(:func:`search_separation`, :func:`solve_pairs`, :func:`fit_power_law`,
:func:`minimise_energy`); :func:`zvyagin_fit` runs them all and returns a
:class:`ZvyaginResult` holding every intermediate and drawing the paper's figures
(``result.plot_d_map()``, ... ``result.save_figures(folder)``). From calibration points,
``tactilecal.calibrate(points, method="zvyagin")`` runs it and returns a
:class:`tactilecal.calibration.CalibrationResult` whose ``method_result`` is the
:class:`ZvyaginResult` (this package does not import :mod:`tactilecal.calibration`: the
adapter lives there).
See ``docs/zvyagin.md`` for the choices the paper leaves open.
"""

from tactilecal._deprecated import moved_names
from tactilecal.zvyagin._approx import search_separation
from tactilecal.zvyagin._calibrate import MODES, OPTIONS, zvyagin_fit
from tactilecal.zvyagin._compare import compare_calibrations
from tactilecal.zvyagin._fit import energy, fit_power_law, minimise_energy
from tactilecal.zvyagin._pairs import solve_pairs
from tactilecal.zvyagin._result import ZvyaginResult

__all__ = [
    "zvyagin_fit", "ZvyaginResult", "MODES", "OPTIONS", "energy",
    "search_separation", "solve_pairs", "fit_power_law", "minimise_energy",
    "compare_calibrations",
]

_STEP = "an internal of the paper's steps; zvyagin_fit() keeps every intermediate"
__getattr__ = moved_names(__name__, {
    **{name: ("_approx", name, _STEP)
       for name in ("CLASS_VALUES", "approximate_raw_sums", "class_counts", "loaded_cells",
                    "patch_discrepancy", "raw_sums", "separation_domain")},
    **{name: ("_fit", name, _STEP)
       for name in ("patch_power_sums", "saturation_pressure_MPa")},
    **{name: ("_pairs", name, _STEP) for name in ("polynomial_roots", "quartic_coefficients")},
    "load_groups": ("_calibrate", "load_groups", _STEP),
    **{name: ("_plots", name, f"use the method ZvyaginResult.{name}() (a calibration's "
                              f"cal.method_result.{name}())")
       for name in ("plot_d_map", "plot_pair_chart", "plot_ab_scatter",
                    "plot_calibration_curves", "plot_patch_errors", "plot_energy",
                    "save_figures")},
    "SENSEL_AREA_5051_MM2": ("_calibrate", "SENSEL_AREA_5051_MM2",
                             "use tactilecal.sensors.get_sensor('5051').sensel_area_mm2"),
    "PAIR_CATEGORIES": ("_result", "PAIR_CATEGORIES", "see ZvyaginResult's docstring"),
    "as_zvyagin_result": ("_plots", "as_zvyagin_result", "a calibration of method "
                          "'zvyagin' holds it as cal.method_result"),
    "plot_error_histogram": ("_plots", "plot_patch_errors", "use the method "
                             "ZvyaginResult.plot_patch_errors()"),
    "compare_table": ("_compare", "compare_table", "use compare_calibrations(cals, names).rows"),
    "format_compare_table": ("_compare", "format_compare_table",
                             "use compare_calibrations(cals, names).table()"),
    "plot_compare": ("_compare", "plot_compare", "use compare_calibrations(cals, names).plot()"),
    "calibrate_zvyagin": ("tactilecal.zvyagin", "_calibrate_zvyagin",
                          "use tactilecal.calibrate(points, method='zvyagin', **options)"),
})


def _calibrate_zvyagin(points, **options):
    """Calibrate with Zvyagin's method (deprecated name of ``calibrate(method="zvyagin")``).

    The same options and result as before (the bootstrap options of ``calibrate`` are
    refused, as they were).
    """
    unknown = sorted(set(options) - set(OPTIONS))
    if unknown:
        raise ValueError(f"calibrate_zvyagin: unknown options {unknown}; expected some of "
                         f"{list(OPTIONS)}")
    # The one import of this package from a layer above it, and only for this deprecated
    # name: the adapter from calibration points lives in tactilecal.calibration.
    from tactilecal.calibration import calibrate

    return calibrate(points, method="zvyagin", **options)
