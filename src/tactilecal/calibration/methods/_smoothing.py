"""Helpers of the smoothed flexible laws (``piecewise``, ``lut``): penalty scale, l1 by IRLS."""

import numpy as np

from tactilecal._errors import TactilecalError

__all__ = ["check_smoothing", "irls_l1", "penalty_weight"]


def penalty_weight(smoothing, load_N, objective):
    """Weight of a squared penalty so that it is ``smoothing * n`` times one median patch's loss.

    The loss of a patch missing its whole load is ``F`` (l1), ``F**2`` (l2) or 1 (relative);
    at the median load F this makes the penalty's units those of the objective's cost.
    """
    median_N = float(np.median(load_N))
    loss = {"l1": median_N, "l2": median_N ** 2, "relative": 1.0}[objective]
    return float(smoothing) * len(load_N) * loss


def check_smoothing(smoothing):
    if not (np.isfinite(smoothing) and smoothing >= 0):
        raise TactilecalError(f"smoothing={smoothing!r}; expected a number >= 0")


def irls_l1(solve, residual, load_N, n_iter=50, rtol=1e-4):
    """Minimise ``sum |residual|`` by iteratively reweighted least squares.

    ``solve(w)`` minimises ``sum (w r)**2`` (plus any penalty); weights ``1/sqrt(|r|)``
    (floored at 1e-6 of the mean load) make its cost ``sum |r|`` at the fixed point
    (Schlossmacher 1973).
    """
    w = np.ones_like(load_N)
    floor = 1e-6 * float(np.mean(load_N))  # a share of the load: not a unit factor
    for _ in range(n_iter):
        x = solve(w)
        w_new = 1.0 / np.sqrt(np.maximum(np.abs(residual(x)), floor))
        if np.allclose(w_new, w, rtol=rtol):
            break
        w = w_new
    return x
