"""Censored fits by refitting: saturated patches as lower bounds of their load.

A patch with a sensel at 255 carries at least what the law predicts, so its load bounds the
prediction from below only: it adds a cost only when the prediction exceeds its load (a
Tobit-style one-sided residual). A method without its own censored fit is refitted on the
unsaturated patches plus the censored ones it over-predicts until that set stops changing:
the fixed point is a stationary point of ``sum_unc r**2 + sum_cens max(0, r)**2``, which for
the laws linear in their parameters (``linear``, ``linear-offset``, ``polynomial``, ``lut``)
is convex, so it is the minimum.
"""

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal.calibration._models import force_table
from tactilecal.calibration._powerfit import check_unsaturated

__all__ = ["ACTIVE_TOLERANCE", "refit_censored"]

ACTIVE_TOLERANCE = 1e-4
"""A censored patch predicted within this fraction below its load counts as over-predicted
(in the cost) when the refits decide their set: the l1 fits of piecewise and lut (a simplex
search, reweighted least squares) hold such a patch at its load only to their tolerance, and
its sign then flipped from refit to refit (piecewise on 5051-saturating did not settle in 50
refits)."""

MAX_REFITS = 50


def refit_censored(fit_uncensored, data, *, exact=False):
    """Fit with ``data.censored`` patches as lower bounds by refitting ``fit_uncensored``.

    Parameters
    ----------
    fit_uncensored : callable
        ``fit_uncensored(data) -> Fit`` on data whose loads are all exact.
    data : tactilecal.calibration._fit.FitData
        With ``censored`` set.
    exact : bool
        The law passes exactly through chosen points (I-Scan's 1- and 2-point
        calibrations): one fit on the unsaturated patches, a lower bound cannot be one of
        its points.

    Returns
    -------
    Fit
        With ``diagnostics["censored"]`` (patches given as lower bounds) and
        ``diagnostics["censored_active"]`` (those the law over-predicts, in the cost), and
        ``chosen`` as indices into all rows of ``data``.

    Raises
    ------
    TactilecalError
        Fewer than 2 unsaturated patches, or no stable set within 50 refits.
    """
    censored = np.asarray(data.censored, dtype=bool)
    check_unsaturated(censored)
    active = np.zeros_like(censored)
    for _ in range(1 if exact else MAX_REFITS):
        rows = ~censored | active
        fit = fit_uncensored(data.rows(rows))
        excess = data.hist @ force_table(fit.model, fit.params) - data.load_N
        # an l1 fit passes through some patches: an active lower bound held at its load
        # (to the fit's tolerance) stays active instead of flipping out and back
        now = censored & (excess > -ACTIVE_TOLERANCE * data.load_N)
        if exact or np.array_equal(now, active):
            if fit.chosen is not None:  # indices into the rows fitted -> into all rows
                fit.chosen = tuple(int(k) for k in np.flatnonzero(rows)[list(fit.chosen)])
            fit.diagnostics.update(censored=int(censored.sum()), censored_active=int(now.sum()))
            return fit
        active = now
    raise TactilecalError(f"the set of over-predicted saturated patches did not settle in "
                          f"{MAX_REFITS} refits; expected saturated='drop' for this session")
