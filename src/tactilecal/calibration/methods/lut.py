"""``lut``: a monotone lookup table, nondecreasing force at ``knots``, smoothed toward a power law.

Force at the knots is the cumulative sum of nonnegative increments found by nonnegative
least squares (:func:`scipy.optimize.nnls`), so the table is monotone and ``f(0) = 0``.
Between knots the table is linear in ``raw**b`` where ``b`` is the power method's exponent
on the same patches, so a power law is exactly a table; a P-spline-like penalty (Eilers &
Marx 1996) on the changes of the segments' slopes keeps it on that power law where the
patches do not say otherwise.
"""

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from tactilecal._errors import TactilecalError
from tactilecal.calibration._fit import Fit, MethodOptions, option
from tactilecal.calibration._powerfit import LEVELS, OBJECTIVES, fit_power_of
from tactilecal.calibration._powerfit import objective_weights as _weights
from tactilecal.calibration.methods._censored import refit_censored
from tactilecal.calibration.methods._smoothing import check_smoothing, irls_l1, penalty_weight

__all__ = ["NAME", "Options", "fit"]

NAME = "lut"

SMOOTHING = 0.1
"""Default ``smoothing``: the best worst case of 0.01, 0.1, 1 and 10 on the simulated family
(20 sessions, 150 held-out patches): 0.97 of the true law's worst share on 9500-b1.4
(0.91-0.96 for the others) and 1.66 on 4010N-noisy, where 1 and 10 pull the table onto the
power law (1.51, 1.47)."""

DEFAULT_KNOTS = (0.0, *np.unique(np.rint(np.geomspace(3, 255, 12))).tolist())
"""0 and 12 log-spaced raw values 3..255."""


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``lut``."""

    knots: tuple | None = option(None, "raw values of the table, increasing from 0 to 255 "
                                       "(default: 0 and 12 log-spaced values 3..255)",
                                 metavar="0,K2,...,255")
    objective: str = option("l1", "l1, l2 or relative (see power)", choices=OBJECTIVES)
    smoothing: float = option(SMOOTHING, "weight of the penalty on bends of the table away "
                                         "from the power law (0: none)")

    def _check(self):
        check_smoothing(self.smoothing)
        if self.knots is not None:
            knots = np.asarray(self.knots, dtype=float)
            if len(knots) < 2 or knots[0] != 0 or knots[-1] < 255 or np.any(np.diff(knots) <= 0):
                raise TactilecalError(f"knots={knots.tolist()} must increase from 0 to 255; "
                                      "expected e.g. [0, 3, 5, ..., 255]")


def _lut_design(hist, knots, exponent):
    """Design matrix of the table's nonnegative increments: load = design @ increments.

    The force at the knots is the cumulative sum of the increments; between knots the table
    is linear in ``raw**exponent`` (hat functions in that coordinate).
    """
    t_levels, t_knots = LEVELS ** exponent, knots ** exponent
    interp = np.stack([np.interp(t_levels, t_knots, e) for e in np.eye(len(knots))], axis=1)
    cumulative = np.tril(np.ones((len(knots) - 1, len(knots) - 1)))
    return hist @ interp[:, 1:] @ cumulative, cumulative


def _lut_penalty(knots, exponent, A_N):
    """Rows whose squares sum the squared changes of the table's slope relative to A_N.

    In the coordinate ``t = raw**exponent`` the power law ``A_N raw**exponent`` is a straight
    line of slope ``A_N``; the penalty is zero for it and grows where the table bends.
    """
    slope_of_increment = np.diag(1.0 / (A_N * np.diff(knots ** exponent)))
    return np.diff(slope_of_increment, axis=0)


def _fit(data, options):
    """Monotone lookup table: nondecreasing force at ``knots``, smoothed toward a power law.

    Force at the knots is the cumulative sum of nonnegative increments found by
    nonnegative least squares (:func:`scipy.optimize.nnls`), so the table is monotone
    and ``f(0) = 0``. Default knots: 0 and 12 log-spaced raw values 3..255.

    Between knots the table is linear in ``raw**b`` where ``b`` is the power method's
    exponent on the same patches (``params["exponent"]``): a power law is then exactly a
    table, where linear interpolation in raw would put every chord of the convex law above
    it. A penalty ``smoothing * n * loss(median F) * sum(diff(s_k / A)**2)``
    (:func:`penalty_weight`) on the changes of the segments' slopes ``s_k`` (in ``raw**b``,
    relative to the power law's A) keeps the table
    on the power law where the patches do not say otherwise (a P-spline-like penalty, Eilers
    & Marx 1996); ``smoothing=0`` turns it off. ``objective="l1"`` (the default, as the power
    method's) minimises the sum of absolute errors by iteratively reweighted least squares.

    Notes
    -----
    Before the review of the static defaults the table was linear in raw, unpenalised and
    fitted by l2: on ``9500-b1.4`` (12 % gains, readings 3-240 with most force above 64) its
    increments at the lowest knots went to 0 (sensels below raw 8 carried no force) and the
    last segment, fitted on the few readings between 169 and the largest training reading,
    extrapolated up to 1.43x the true force at 240; its worst session reached 0.93 of the
    true law's.
    """
    knots = np.asarray(DEFAULT_KNOTS if options.knots is None else options.knots, dtype=float)
    objective, smoothing = options.objective, options.smoothing
    hist, load_N = data.hist, data.load_N
    shape = fit_power_of(data, objective="l1").params
    design, cumulative = _lut_design(hist, knots, shape["b"])
    # squared rows: with IRLS's weights an l1 cost, so the l1 weight holds for the l1 fit too
    penalty = np.sqrt(penalty_weight(smoothing, load_N, objective)) \
        * _lut_penalty(knots, shape["b"], shape["A"])
    zeros = np.zeros(len(penalty))

    def solve(w):
        return optimize.nnls(np.concatenate((w[:, None] * design, penalty)),
                             np.concatenate((w * load_N, zeros)))[0]

    if objective == "l1":
        increments = irls_l1(solve, lambda x: design @ x - load_N, load_N)
    else:
        increments = solve(_weights(load_N, objective))
    force = np.r_[0.0, cumulative @ increments]
    return Fit("table", {"knots": knots.tolist(), "force_N": force.tolist(),
                         "exponent": shape["b"]},
               {"objective": objective, "smoothing": float(smoothing)})


def fit(data, options):
    """Fit the lookup table to ``data`` (a :class:`FitData`)."""
    if data.censored is not None:
        return refit_censored(lambda d: _fit(d, options), data)
    return _fit(data, options)
