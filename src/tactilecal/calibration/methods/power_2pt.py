"""``power-2pt``: I-Scan's 2-point power law on the mean raw reading of the loaded sensels.

I-Scan assumes every loaded sensel of point i reads its mean ``x_i = R_i / C_i`` and carries
``F_i / C_i``, so ``F_i / C_i = A x_i**b`` (Gillis 2013, sec. 3.5, ``y = a x**b`` with points
at about 20 % and 80 % of the maximum load). With more than two points the two nearest 20 %
and 80 % of the largest load are used (or ``pair=(i, j)``, indices into the usable points).
"""

from dataclasses import dataclass

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal.calibration._fit import Fit, MethodOptions, option
from tactilecal.calibration._powerfit import LEVELS
from tactilecal.calibration.methods._censored import refit_censored

__all__ = ["NAME", "Options", "fit"]

NAME = "power-2pt"


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``power-2pt``."""

    pair: tuple | None = option(None, "two usable-point indices I,J (default: the points "
                                      "nearest 20 % and 80 % of the largest load)",
                                metavar="I,J")
    scale_by_working: bool = option(False, "multiply each load by working / all sensels "
                                           "(Gillis 2013, sec. 3.5)")

    def _check(self):
        if self.pair is None:
            return
        if len(self.pair) != 2 or any(isinstance(k, bool) or not isinstance(k, int) or k < 0
                                      for k in self.pair) or self.pair[0] == self.pair[1]:
            raise TactilecalError(f"pair={list(self.pair)!r} is invalid; expected two "
                                  "different indices >= 0 into the usable points")


def _choose_pair(load_N, pair):
    if len(load_N) < 2:
        raise TactilecalError(f"power-2pt needs 2 usable points; found {len(load_N)}")
    if pair is None:
        top = load_N.max()
        i = int(np.argmin(np.abs(load_N - 0.2 * top)))
        j = int(np.argmin(np.abs(load_N - 0.8 * top)))
        if load_N[i] == load_N[j]:
            j = int(np.argmax(load_N))
        if load_N[i] == load_N[j]:
            raise TactilecalError("power-2pt needs two different loads; all usable points "
                                  f"have load_N = {load_N[i]:.6g}")
        return i, j
    i, j = pair
    if not (i < len(load_N) and j < len(load_N)):
        raise TactilecalError(f"pair={list(pair)!r} is invalid; expected two different "
                              f"indices into the {len(load_N)} usable points")
    return i, j


def _fit(data, options):
    hist, load_N = data.hist, data.load_N
    loaded = hist[:, 1:].sum(axis=1)
    mean_raw = (hist @ LEVELS) / loaded
    per_cell = load_N / loaded
    i, j = _choose_pair(load_N, options.pair)
    b = float(np.log(per_cell[j] / per_cell[i]) / np.log(mean_raw[j] / mean_raw[i]))
    A = float(per_cell[i] / mean_raw[i] ** b)
    return Fit("power", {"A": A, "b": b}, {"mean_raw": [mean_raw[i], mean_raw[j]]},
               chosen=(int(i), int(j)))


def fit(data, options):
    """Fit I-Scan's 2-point power law to ``data`` (a :class:`FitData`).

    Examples
    --------
    >>> import numpy as np
    >>> from tactilecal.calibration._fit import FitData
    >>> hist = np.zeros((2, 256)); hist[0, 10] = 4; hist[1, 40] = 4
    >>> load = 4 * 0.01 * np.array([10.0, 40.0]) ** 1.5
    >>> {k: round(v, 6) for k, v in fit(FitData(hist, load), Options()).params.items()}
    {'A': 0.01, 'b': 1.5}
    """
    if data.censored is not None:
        return refit_censored(lambda d: _fit(d, options), data, exact=True)
    return _fit(data, options)
