"""Zvyagin (2022) multi-patch calibration using high-pressure zones.

Zvyagin, P. (2022). Tactile Pressure Sensors Calibration with the Use of High Pressure
Zones. Sensors 22(19), 7290. https://doi.org/10.3390/s22197290

The four steps of the paper are separate functions on raw-value histograms of the patches
(:func:`search_separation`, :func:`solve_pairs`, :func:`fit_power_law`,
:func:`minimise_energy`); :func:`zvyagin_fit` runs them all and returns a
:class:`ZvyaginResult` holding every intermediate. From calibration points,
``tactilecal.calibrate(points, method="zvyagin")`` runs it and returns a
:class:`tactilecal.calibration.CalibrationResult` whose ``method_result`` is the
:class:`ZvyaginResult` (this package does not import :mod:`tactilecal.calibration`: the
adapter lives there).
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
from tactilecal.zvyagin._calibrate import (
    MODES,
    OPTIONS,
    SENSEL_AREA_5051_MM2,
    load_groups,
    zvyagin_fit,
)
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


def __getattr__(name):
    """Return the deprecated ``calibrate_zvyagin`` (with a DeprecationWarning)."""
    if name != "calibrate_zvyagin":
        raise AttributeError(f"module 'tactilecal.zvyagin' has no attribute {name!r}")
    import warnings

    warnings.warn("tactilecal.zvyagin.calibrate_zvyagin is deprecated; use "
                  "tactilecal.calibrate(points, method='zvyagin', **options)",
                  DeprecationWarning, stacklevel=2)
    return _calibrate_zvyagin
