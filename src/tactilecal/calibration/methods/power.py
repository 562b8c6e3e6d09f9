"""``power``: the multi-point power law over every sensel, f = A * raw**b.

Objectives: ``l2`` minimises ``sum_T (A S_T(b) - F_T)**2`` (Zvyagin 2022, eq. 3), ``l1``
minimises ``sum_T |F_T - A S_T(b)|`` (Gillis 2013, eq. 5.1, I-Scan), ``relative`` minimises
``sum_T ((A S_T(b) - F_T) / F_T)**2``, where ``S_T(b) = hist_T @ arange(256)**b``. Patches
given as lower bounds (``saturated="censored"``) enter one-sided
(:func:`tactilecal.calibration._powerfit.fit_power_censored`).
"""

from dataclasses import dataclass

from tactilecal._errors import TactilecalError
from tactilecal.calibration._fit import MethodOptions, option
from tactilecal.calibration._powerfit import (
    B_BOUNDS,
    DEFAULT_OBJECTIVE,
    OBJECTIVES,
    fit_power_censored,
    fit_power_of,
)

__all__ = ["NAME", "Options", "fit"]

NAME = "power"


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``power``."""

    objective: str = option(DEFAULT_OBJECTIVE, "what the fit minimises: l1 (absolute errors "
                                               "in N), l2 (squared errors) or relative "
                                               "(squared errors as fractions of the load)",
                            choices=OBJECTIVES)
    b_bounds: tuple = option(B_BOUNDS, "range searched for the exponent b", metavar="B_MIN,B_MAX")

    def _check(self):
        if len(self.b_bounds) != 2 or not 0 < float(self.b_bounds[0]) < float(self.b_bounds[1]):
            raise TactilecalError(f"b_bounds={list(self.b_bounds)!r}; expected 0 < b_min < b_max")


def fit(data, options):
    """Fit the power law to ``data`` (a :class:`FitData`).

    Examples
    --------
    >>> import numpy as np
    >>> from tactilecal.calibration._fit import FitData
    >>> hist = np.zeros((3, 256)); hist[0, 10] = hist[1, 50] = hist[2, 200] = 5
    >>> load = 5 * 0.004 * np.array([10.0, 50.0, 200.0]) ** 1.2
    >>> law = fit(FitData(hist, load), Options(objective="l2")).params
    >>> round(law["A"], 6), round(law["b"], 6)
    (0.004, 1.2)
    """
    if data.censored is not None:
        return fit_power_censored(data.hist, data.load_N, data.censored,
                                  objective=options.objective, b_bounds=options.b_bounds)
    return fit_power_of(data, objective=options.objective, b_bounds=options.b_bounds)
