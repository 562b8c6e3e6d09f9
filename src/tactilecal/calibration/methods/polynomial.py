"""``polynomial``: a polynomial per-sensel law through the origin, f = sum_j c_j raw**j.

Linear least squares on the moments ``hist @ raw**j``, j = 1..degree (computed on raw/255
for conditioning). A law that decreases anywhere on raw 1..255 or is negative there is
refused: a higher reading would mean a smaller force.
"""

from dataclasses import dataclass

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal.calibration._fit import Fit, MethodOptions, option
from tactilecal.calibration._powerfit import LEVELS, objective_weights
from tactilecal.calibration.methods._censored import refit_censored

__all__ = ["NAME", "Options", "fit"]

NAME = "polynomial"


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``polynomial``."""

    degree: int = option(3, "polynomial degree (>= 1)")
    objective: str = option("l2", "least squares on the errors in N (l2) or as fractions of "
                                  "the load (relative)", choices=("l2", "relative"))

    def _check(self):
        if isinstance(self.degree, bool) or not isinstance(self.degree, int) or self.degree < 1:
            raise TactilecalError(f"degree={self.degree!r}; expected an integer >= 1")


def _fit(data, options):
    powers = np.arange(1, options.degree + 1)
    design = data.hist @ ((LEVELS / 255.0)[:, None] ** powers)
    w = objective_weights(data.load_N, options.objective)
    coef, *_ = np.linalg.lstsq(w[:, None] * design, w * data.load_N, rcond=None)
    return Fit("polynomial", {"coefficients": (coef / 255.0 ** powers).tolist()},
               {"objective": options.objective})


def fit(data, options):
    """Fit the polynomial law to ``data`` (a :class:`FitData`).

    Examples
    --------
    >>> from tactilecal.calibration._fit import FitData
    >>> hist = np.zeros((3, 256)); hist[0, 10] = hist[1, 50] = hist[2, 200] = 5
    >>> load = 5 * (0.01 * np.array([10.0, 50.0, 200.0]) + 1e-4 * np.array([10, 50, 200]) ** 2)
    >>> np.round(fit(FitData(hist, load), Options(degree=2)).params["coefficients"], 8).tolist()
    [0.01, 0.0001]
    """
    if data.censored is not None:
        return refit_censored(lambda d: _fit(d, options), data)
    return _fit(data, options)
