"""``linear``: I-Scan's linear calibration through zero, f = A * raw (Gillis 2013, sec. 3.5).

I-Scan's 1-point calibration is ``A = F / R`` (raw sum ``R``) of one point: give ``point``
(an index into the usable points), or pass a single point. Without ``point`` and with
several points, the least-squares line through zero ``A = sum(F R) / sum(R**2)``.
"""

from dataclasses import dataclass

from tactilecal._errors import TactilecalError
from tactilecal.calibration._fit import Fit, MethodOptions, option
from tactilecal.calibration._powerfit import LEVELS
from tactilecal.calibration.methods._censored import refit_censored

__all__ = ["NAME", "Options", "fit"]

NAME = "linear"


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``linear``."""

    point: int | None = option(None, "index of the one usable point of I-Scan's 1-point "
                                     "calibration (default: a line through zero fitted to "
                                     "every usable point)")
    scale_by_working: bool = option(False, "multiply each load by working / all sensels "
                                           "(Gillis 2013, sec. 3.5)")

    def _check(self):
        if self.point is not None and (isinstance(self.point, bool)
                                       or not isinstance(self.point, int) or self.point < 0):
            raise TactilecalError(f"point={self.point!r}; expected an index >= 0 into the "
                                  "usable points")


def _fit(data, options):
    hist, load_N = data.hist, data.load_N
    chosen = None
    if options.point is not None:
        if not options.point < len(load_N):
            raise TactilecalError(f"point={options.point!r} is invalid; expected an index into "
                                  f"the {len(load_N)} usable points")
        chosen = (options.point,)
        hist, load_N = hist[[options.point]], load_N[[options.point]]
    raw_sum = hist @ LEVELS
    A = float(raw_sum @ load_N / (raw_sum @ raw_sum))
    return Fit("power", {"A": A, "b": 1.0}, chosen=chosen)


def fit(data, options):
    """Fit I-Scan's linear law to ``data`` (a :class:`FitData`) with ``options``.

    Examples
    --------
    >>> import numpy as np
    >>> from tactilecal.calibration._fit import FitData
    >>> hist = np.zeros((2, 256)); hist[0, 10] = 4; hist[1, 20] = 4
    >>> fit(FitData(hist, np.array([4.0, 8.0])), Options()).params
    {'A': 0.1, 'b': 1.0}
    """
    if data.censored is not None:
        return refit_censored(lambda d: _fit(d, options), data,
                              exact=options.point is not None)
    return _fit(data, options)
