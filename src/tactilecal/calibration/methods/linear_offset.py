"""``linear-offset``: Paikowsky & Hajduk's (1997) linear law with an offset, P = K (RSD - b).

Per loaded sensel ``f = K (raw - offset)``; a frame gives ``F = K R - K offset C`` (raw sum
``R``, loaded sensels ``C``), linear least squares in ``(K, K offset)`` (Gillis 2013,
sec. 3.5). A reading at or below the offset carries no force: the law is clipped at 0
(the published formula would give it a negative force), and the fit says how many raw
values that concerns.
"""

from dataclasses import dataclass

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal.calibration._fit import Fit, MethodOptions, option
from tactilecal.calibration._powerfit import LEVELS, objective_weights
from tactilecal.calibration.methods._censored import refit_censored

__all__ = ["NAME", "Options", "fit"]

NAME = "linear-offset"


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``linear-offset``."""

    objective: str = option("l2", "least squares on the errors in N (l2) or as fractions of "
                                  "the load (relative)", choices=("l2", "relative"))


def _fit(data, options):
    design = np.column_stack([data.hist @ LEVELS, -data.hist[:, 1:].sum(axis=1)])
    w = objective_weights(data.load_N, options.objective)
    coef, *_ = np.linalg.lstsq(w[:, None] * design, w * data.load_N, rcond=None)
    K, c = (float(v) for v in coef)
    if not K > 0:
        raise TactilecalError(f"linear-offset: fitted slope K = {K:.4g} N per raw count; "
                              "expected K > 0 (the loads do not grow with the readings)")
    offset = c / K
    below = int(np.clip(np.floor(offset), 0, 255))  # raw 1..below carry no force
    return Fit("linear-offset", {"K": K, "offset": offset},
               {"objective": options.objective, "raw_values_without_force": below,
                "note": f"readings up to raw {below} are at or below the offset {offset:.3g} "
                        "and carry no force (the law is clipped at 0)" if below else ""})

def fit(data, options):
    """Fit the offset law to ``data`` (a :class:`FitData`).

    Examples
    --------
    >>> import numpy as np
    >>> from tactilecal.calibration._fit import FitData
    >>> hist = np.zeros((3, 256)); hist[0, 10] = hist[1, 50] = hist[2, 200] = 5
    >>> load = 5 * 0.02 * (np.array([10.0, 50.0, 200.0]) - 4)
    >>> law = fit(FitData(hist, load), Options()).params
    >>> round(law["K"], 6), round(law["offset"], 6)
    (0.02, 4.0)
    """
    if data.censored is not None:
        return refit_censored(lambda d: _fit(d, options), data)
    return _fit(data, options)
