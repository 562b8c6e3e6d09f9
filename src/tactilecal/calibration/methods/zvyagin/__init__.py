"""``zvyagin``: Zvyagin's (2022) multi-patch calibration using high-pressure zones.

Zvyagin, P. (2022). Tactile Pressure Sensors Calibration with the Use of High Pressure
Zones. Sensors 22(19), 7290. https://doi.org/10.3390/s22197290

The four steps of the paper (Section 3): (1) the degrees-of-three approximation of each
patch and the exhaustive search for the separation I* (eq. 5-10, ``_approx.py``); (2) eq.
(12) for every pair of patches, (A, b) from each root Y > 3 (eq. 13, ``_pairs.py``); (3)
the power law A = alpha * b**beta through the (A, b) set (eq. 14); (4) (A0, b0) on that
curve minimising E (eq. 15) and the saturation pressure (eq. 16) (``_fit.py``). The
result of a calibration with ``method="zvyagin"`` holds every intermediate as its
``method_result`` (:class:`ZvyaginResult`), which draws the paper's figures. See
``docs/zvyagin.md`` for the choices the paper leaves open (``mode="faithful"`` follows it as
written, ``"robust"`` is the default).
"""

import warnings
from dataclasses import dataclass

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import to_jsonable
from tactilecal.calibration._fit import Fit, MethodOptions, check_positive_number, option
from tactilecal.calibration.methods.zvyagin._approx import DOMAINS
from tactilecal.calibration.methods.zvyagin._calibrate import (
    CHOICES,
    DEFAULT_MODE,
    MODES,
    resolve_mode,
    zvyagin_fit,
)
from tactilecal.calibration.methods.zvyagin._result import ZvyaginResult

__all__ = ["NAME", "Options", "fit", "ZvyaginResult"]

NAME = "zvyagin"
NAMES_POINTS = True
"""The procedure names the patches in its tables and figures: give it the points' names."""


def _b_range(text):
    """Parse a ``b_range`` given as text: ``pairs``, ``inliers`` or ``B_MIN,B_MAX``."""
    if text in ("pairs", "inliers"):
        return text
    try:
        return tuple(float(v) for v in text.split(","))
    except ValueError:
        raise TactilecalError(f"b_range={text!r}; expected 'pairs', 'inliers' or "
                              "B_MIN,B_MAX") from None


def _mode_choice(name):
    """Help text of a choice its mode sets: its values and each mode's."""
    by_mode = ", ".join(f"{mode}: {choices[name]}" for mode, choices in MODES.items())
    return f"(default: the mode's; {by_mode})"


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``zvyagin``: the mode, and any of its choices to override.

    ``None`` for a choice means the mode's (:data:`MODES`). ``"faithful"`` is the paper as
    written: smallest root Y > 3, plain log-log least squares on every valid pair, E along
    the curve over the b range of the pairs. ``"robust"``: roots Y > 3**0.5, the
    best-fitting root, the power law through the pairs between the 5 % and 95 % quantiles
    of b, then the law minimising the patches' misfit over A and b together
    (``final="free"``, ``objective="cv"``: l1 or relative, whichever predicts held-out
    patches better in 5-fold cross-validation).
    """

    mode: str = option(DEFAULT_MODE, "follow the paper as written (faithful) or the robust "
                                     "variant", choices=tuple(MODES))
    domain: str = option("strict", "search domain of the separation I (eq. 9)",
                         choices=DOMAINS)
    root_choice: str | None = option(None, f"root of eq. (12) per pair "
                                           f"{_mode_choice('root_choice')}",
                                     choices=(None, *CHOICES["root_choice"]))
    outliers: str | None = option(None, f"outliers of the (A, b) cloud {_mode_choice('outliers')}",
                                  choices=(None, *CHOICES["outliers"]))
    b_range: str | tuple | None = option(None, f"b range of E: pairs, inliers or B_MIN,B_MAX "
                                               f"{_mode_choice('b_range')}",
                                         metavar="RANGE")
    final: str | None = option(None, f"last step: E along the curve (eq. 15) or over A and b "
                                     f"together {_mode_choice('final')}",
                               choices=(None, *CHOICES["final"]))
    pair_b_min: float | None = option(None, f"pairs keep roots Y > 3**pair_b_min "
                                            f"{_mode_choice('pair_b_min')}")
    objective: str | None = option(None, f"objective of the free last step "
                                         f"{_mode_choice('objective')}",
                                   choices=(None, *CHOICES["objective"]))
    trim: float = option(0.05, "share of pairs cut at each end of the b range "
                               "(outliers=trim)")
    max_relerr: float = option(0.10, "raw-sum approximation error |R - Q(I*)| / R from "
                                     "which a patch's pairs are rejected")
    grey_share: float = option(0.05, "a patch is grey when fewer than this share of its "
                                     "pairs have a root Y > 3")
    group_tolerance: float = option(0.05, "relative load difference within which patches "
                                          "count as one dead weight")

    def _check(self):
        if isinstance(self.b_range, str) and self.b_range not in ("pairs", "inliers"):
            object.__setattr__(self, "b_range", _b_range(self.b_range))
        for name in ("trim", "max_relerr", "grey_share", "group_tolerance"):
            check_positive_number(getattr(self, name), name, NAME, zero=True)
        self.resolved()  # the mode's choices with these over them: checked once, here

    def resolved(self):
        """Return the mode's choices with the options that are not None over them (a dict)."""
        return resolve_mode(self.mode, {k: getattr(self, k) for k in MODES[self.mode]})


def fit(data, options):
    """Run Zvyagin's procedure on ``data`` (a :class:`FitData`); the law is ``A0 raw**b0``.

    Examples
    --------
    >>> from tactilecal.calibration._fit import FitData
    >>> from tactilecal.simulate import patch_histograms
    >>> h, f, _ = patch_histograms(40, A_N=0.0035, b=1.16, seed=3)
    >>> law = fit(FitData(h, f, sensel_area_mm2=1.6129), Options()).params
    >>> abs(law["b"] - 1.16) < 0.05
    True
    """
    if not np.isfinite(data.sensel_area_mm2):
        warnings.warn("the points carry no sensel area and sensel_area_mm2 was not given: "
                      "p_s (eq. 16) is unknown; pass sensel_area_mm2 (5051: 1.6129)",
                      UserWarning, stacklevel=3)
    res = zvyagin_fit(data.hist, data.load_N, options, censored=data.censored,
                      labels=list(data.labels) or None,
                      sensel_area_mm2=data.sensel_area_mm2)
    return Fit("power", {"A": res.A0, "b": res.b0}, to_jsonable(res.to_details()),
               method_result=res)
