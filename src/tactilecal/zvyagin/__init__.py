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
