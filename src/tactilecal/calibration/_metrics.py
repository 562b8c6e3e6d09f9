"""How well predicted loads match applied loads: one set of scores for fits and validations.

Both :func:`tactilecal.calibration.calibrate` (over the points a fit used) and
:func:`tactilecal.calibration.validate` (over held-out points) score with
:func:`fit_metrics`, so a calibration's metrics and its validation's read the same.
"""

import numpy as np

__all__ = ["METRICS", "fit_metrics"]

METRICS = ("n", "rmse_N", "mean_error_pct", "median_abs_error_pct", "max_abs_error_pct",
           "within_3pct", "within_5pct", "within_10pct", "r2")
"""The keys of :func:`fit_metrics`; ``within_*pct`` are shares in 0..1."""


def fit_metrics(load_N, predicted_N):
    """Scores of predicted loads against applied loads (errors in N and in % of the load).

    Parameters
    ----------
    load_N, predicted_N : array_like
        Applied and predicted loads of the scored points (same length; may be empty).

    Returns
    -------
    dict
        :data:`METRICS`: ``n``; ``rmse_N``; the mean signed, median and largest absolute
        error in percent of the applied load; the shares of points within 3, 5 and 10 %
        (0..1); ``r2`` = 1 - SS_res / SS_tot (NaN for fewer than two distinct loads). Every
        score but ``n`` is NaN without points.

    Examples
    --------
    >>> m = fit_metrics([10.0, 20.0], [10.5, 20.0])
    >>> m["n"], m["max_abs_error_pct"], m["within_3pct"], m["within_10pct"]
    (2, 5.0, 0.5, 1.0)
    """
    load = np.asarray(load_N, dtype=float)
    predicted = np.asarray(predicted_N, dtype=float)
    if load.size == 0:  # e.g. a header's power law, which carries no points to score
        return {"n": 0, **dict.fromkeys(METRICS[1:], float("nan"))}
    err = predicted - load
    pct = 100.0 * err / load
    abs_pct = np.abs(pct)
    ss_tot = float(((load - load.mean()) ** 2).sum())
    return {
        "n": int(load.size),
        "rmse_N": float(np.sqrt(np.mean(err ** 2))),
        "mean_error_pct": float(np.mean(pct)),
        "median_abs_error_pct": float(np.median(abs_pct)),
        "max_abs_error_pct": float(abs_pct.max()),
        "within_3pct": float(np.mean(abs_pct <= 3.0)),
        "within_5pct": float(np.mean(abs_pct <= 5.0)),
        "within_10pct": float(np.mean(abs_pct <= 10.0)),
        "r2": float(1.0 - np.sum(err * err) / ss_tot) if ss_tot > 0 else float("nan"),
    }
