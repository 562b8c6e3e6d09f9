"""``piecewise``: one power law per low/medium/high raw range (after Stith), continuous.

The law is a straight line between ``knots`` in log-log coordinates, continuous at the
knots, so each range has its own ``A_r`` and ``b_r``. ``objective="l1"`` (the default, as
the power method's) profiles the force at the first knot by a weighted median and finds the
exponents by a simplex search; ``"l2"``/``"relative"`` fit the log forces at the knots by
nonlinear least squares (:func:`scipy.optimize.least_squares`). A penalty
``smoothing * n * loss(median F) * sum(diff(b_r)**2)`` on the changes of exponent between
ranges keeps the law on one power law where the patches do not say otherwise;
``smoothing=0`` turns it off.
"""

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from tactilecal._errors import TactilecalError
from tactilecal.calibration._fit import Fit, MethodOptions, option
from tactilecal.calibration._models import force_table
from tactilecal.calibration._powerfit import (
    B_BOUNDS,
    DEFAULT_OBJECTIVE,
    LOG_LEVELS,
    OBJECTIVES,
    _censored_median,
    fit_power_of,
)
from tactilecal.calibration._powerfit import objective_weights as _weights
from tactilecal.calibration.methods._censored import refit_censored
from tactilecal.calibration.methods._smoothing import check_smoothing, penalty_weight

__all__ = ["NAME", "Options", "fit"]

NAME = "piecewise"

SMOOTHING = 0.1
"""Default ``smoothing``: on the simulated family (20 sessions, 150 held-out patches) 0.1
and 1 both reached 0.96 of the true law's worst share on 9500-b1.4 (0 reached 0.91, 0.01
0.93); 0.1 kept 1.59 on 4010N-noisy, 1 only 1.47."""


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``piecewise``."""

    knots: tuple = option((1, 16, 64, 255), "raw values where the law's exponent may change "
                                            "(increasing, > 0)", metavar="K1,K2,...")
    objective: str = option(DEFAULT_OBJECTIVE, "l1, l2 or relative (see power)",
                            choices=OBJECTIVES)
    smoothing: float = option(SMOOTHING, "weight of the penalty on changes of exponent "
                                         "between ranges (0: none)")

    def _check(self):
        check_smoothing(self.smoothing)
        knots = np.asarray(self.knots, dtype=float)
        if len(knots) < 2 or np.any(np.diff(knots) <= 0) or knots[0] <= 0:
            raise TactilecalError(f"knots={knots.tolist()} must increase and be > 0; expected "
                                  "e.g. (1, 16, 64, 255)")


def _piecewise_shape(knots):
    """Piecewise power law through 1 N at the first knot, raw 0..255, as a function of slopes.

    Returns ``shape(slopes)``, the same law as ``force_table("piecewise-power", ...)`` with
    exponents ``slopes``, computed directly on the log levels (about 50x faster), with what
    depends on the knots alone computed once: the simplex search of the l1 fit evaluates it
    hundreds of times.
    """
    log_knots = np.log(knots)
    steps = np.diff(log_knots)
    log_raw = LOG_LEVELS[1:]
    below = log_raw < log_knots[0]
    below_offset = log_raw[below] - log_knots[0]

    def shape(slopes):
        log_force = np.concatenate(([0.0], (slopes * steps).cumsum()))
        value = np.interp(log_raw, log_knots, log_force)
        if below_offset.size:
            value[below] = slopes[0] * below_offset
        return np.concatenate(([0.0], np.exp(value)))

    return shape


def _piecewise_l1(hist, load_N, knots, start, weight):
    """l1 fit: the force at the first knot profiled (weighted median), slopes by Nelder-Mead.

    For fixed exponents the sum of absolute errors is minimised by the S-weighted median of
    F/S (as the power method's A); the exponents, kept in ``B_BOUNDS``, minimise that profiled
    cost plus ``weight * sum(diff(slopes)**2)`` (a cost without derivative everywhere, hence
    the simplex search).
    """
    none = np.zeros(len(load_N), dtype=bool)
    shape = _piecewise_shape(knots)
    lo, hi = B_BOUNDS

    def scale_and_cost(slopes):
        slopes = np.minimum(np.maximum(slopes, lo), hi)  # np.clip, without its wrapper
        sums = hist @ shape(slopes)
        scale = _censored_median(load_N / sums, sums, none)
        bends = slopes[1:] - slopes[:-1]  # np.diff(slopes)
        cost = np.add.reduce(np.abs(scale * sums - load_N)) \
            + weight * np.add.reduce(bends * bends)  # the sums without ndarray.sum's wrapper
        return scale, slopes, cost

    sol = optimize.minimize(lambda x: scale_and_cost(x)[2], start, method="Nelder-Mead",
                            options={"xatol": 1e-5, "fatol": 1e-9 * float(np.sum(load_N)),
                                     "maxiter": 4000})
    scale, slopes, _ = scale_and_cost(sol.x)
    return np.log(scale) + np.r_[0.0, np.cumsum(slopes * np.diff(np.log(knots)))]


def _piecewise_ls(hist, load_N, knots, start_log_force, objective, weight):
    """l2/relative fit of the log forces at the knots (:func:`scipy.optimize.least_squares`)."""
    w = _weights(load_N, objective)
    root = np.sqrt(weight)
    log_knots = np.log(knots)

    def resid(log_force):
        table = force_table("piecewise-power", {"knots": knots, "force_N": np.exp(log_force)})
        bends = np.diff(np.diff(log_force) / np.diff(log_knots))
        return np.r_[w * (hist @ table - load_N), root * bends]

    return optimize.least_squares(resid, start_log_force, method="lm").x


def _fit(data, options):
    """Piecewise power law: one power law per low/medium/high raw range (after Stith).

    The law is a straight line between ``knots`` in log-log coordinates, continuous at
    the knots, so each range has its own ``A_r`` and ``b_r``. ``objective="l1"`` (the
    default, as the power method's) profiles the force at the first knot by a weighted
    median and finds the exponents by a simplex search; ``"l2"``/``"relative"`` fit the log
    forces at the knots by nonlinear least squares (:func:`scipy.optimize.least_squares`).
    A penalty ``smoothing * n * loss(median F) * sum(diff(b_r)**2)`` (:func:`penalty_weight`)
    on the changes of exponent between ranges keeps the law on one power law where the
    patches do not say otherwise; ``smoothing=0`` turns it off.

    Notes
    -----
    Until the review of the static defaults the fit was unpenalised least squares (``relative``). On
    ``9500-b1.4`` (readings 3-240, half the force above raw 91) the range 1-16 carries
    almost no force and its exponent went to 210 or 0.21 in some sessions (sensels below 16
    read as no force, or as 4x theirs), and least squares on patches with heavy-tailed errors
    (12 % gains, few large sensels) lost to l1 as the power method does: its worst session
    reached 0.94 of the true law's.
    """
    knots = np.asarray(options.knots, dtype=float)
    objective, smoothing = options.objective, options.smoothing
    hist, load_N = data.hist, data.load_N
    start = fit_power_of(data, objective=objective).params
    weight = penalty_weight(smoothing, load_N, objective)
    if objective == "l1":
        log_force = _piecewise_l1(hist, load_N, knots, np.full(len(knots) - 1, start["b"]),
                                  weight)
    else:
        log_force = _piecewise_ls(hist, load_N, knots, np.log(start["A"] * knots ** start["b"]),
                                  objective, weight)
    force = np.exp(log_force)
    b_r = np.diff(np.log(force)) / np.diff(np.log(knots))
    A_r = force[:-1] / knots[:-1] ** b_r
    return Fit("piecewise-power", {"knots": knots.tolist(), "force_N": force.tolist()},
               {"objective": objective, "smoothing": float(smoothing),
                "segments_A": A_r.tolist(), "segments_b": b_r.tolist()})




def fit(data, options):
    """Fit the piecewise power law to ``data`` (a :class:`FitData`)."""
    if data.censored is not None:
        return refit_censored(lambda d: _fit(d, options), data)
    return _fit(data, options)
