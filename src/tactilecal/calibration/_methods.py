"""Static calibration methods, each fitted on 256-bin histograms of calibration frames.

Every fit takes ``hist`` (n, 256) int64 and ``load_N`` (n,) of the *used* points and
returns a :class:`Fit` (model name, parameters, standard errors, details). The cost of a
fit does not depend on the number of sensels: ``sum_k X_k**b = hist @ arange(256)**b``.
"""

from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from tactilecal.calibration._models import LEVELS, force_table

__all__ = ["Fit", "FITTERS", "CENSORED_FITTERS", "OBJECTIVES", "DEFAULT_OBJECTIVE"]

OBJECTIVES = ("l2", "l1", "relative")
DEFAULT_OBJECTIVE = "relative"
B_BOUNDS = (0.2, 4.0)
with np.errstate(divide="ignore"):
    LOG_LEVELS = np.where(LEVELS > 0, np.log(LEVELS), 0.0)


@dataclass
class Fit:
    """What a method returns before it is wrapped into a CalibrationResult."""

    model: str
    params: dict
    params_stderr: dict
    details: dict = field(default_factory=dict)


# ---------------------------------------------------------------------- helpers
def _check_objective(objective):
    if objective not in OBJECTIVES:
        raise ValueError(f"objective={objective!r} is unknown; expected one of {OBJECTIVES}")


def _check_ls_objective(objective, method):
    if objective not in ("l2", "relative"):
        raise ValueError(f"objective={objective!r} is not available for {method}; "
                         "expected 'l2' or 'relative'")


def _weights(load_N, objective):
    """Residual weights: 1 for l2/l1, 1/F for ``relative`` (residuals as fractions)."""
    return 1.0 / load_N if objective == "relative" else np.ones_like(load_N)


def _power_sums(hist, b):
    """S_T(b) = sum_k X_k**b for each frame (Zvyagin 2022, eq. 2) as hist @ levels**b."""
    return hist @ (LEVELS ** b)


def _best_A(sums, load_N, objective):
    """Optimal A for fixed b: closed form for l2/relative, weighted median for l1."""
    if objective == "l1":
        # sum |A S - F| = sum S |A - F/S|: minimised by the S-weighted median of F/S.
        return float(np.quantile(load_N / sums, 0.5, weights=sums, method="inverted_cdf"))
    w2s = _weights(load_N, objective) ** 2 * sums
    # elementwise products, not BLAS dot: cheaper than a threaded BLAS call on busy cores
    return float(np.sum(w2s * load_N) / np.sum(w2s * sums))


def _power_costs(b_values, hist, load_N, objective):
    """Profiled cost and best A for several exponents in one pass over the histograms.

    One matrix product ``hist @ levels**b`` for all ``b`` reads the histograms once, which
    is what costs time for tens of thousands of points.
    """
    sums = hist @ (LEVELS[:, None] ** np.asarray(b_values)[None, :])
    w = _weights(load_N, objective)[:, None]
    if objective == "l1":
        A = np.array([_best_A(col, load_N, "l1") for col in sums.T])
        return np.abs(w * (A * sums - load_N[:, None])).sum(axis=0), A
    w2s = w ** 2 * sums
    A = (w2s * load_N[:, None]).sum(axis=0) / (w2s * sums).sum(axis=0)
    r = w * (A * sums - load_N[:, None])
    return (r * r).sum(axis=0), A


def _cost_slope(b, hist, load_N, w2):
    """Return d cost / d b of the profiled l2/relative cost ``<F,F> - <S,F>**2 / <S,S>``.

    ``<x, y> = sum w**2 x y``; ``S = hist @ levels**b`` and ``S' = hist @ levels**b ln
    levels`` come from one matrix product.
    """
    v = LEVELS ** b
    S, dS = (hist @ np.column_stack([v, v * LOG_LEVELS])).T
    p, q = np.sum(w2 * S * load_N), np.sum(w2 * S * S)
    dp, dq = np.sum(w2 * dS * load_N), 2.0 * np.sum(w2 * dS * S)
    return -(2.0 * p * dp * q - p * p * dq) / (q * q)


def _minimise_b(hist, load_N, objective, b_bounds, n_grid=13, xtol=1e-10):
    """Minimise the profiled cost over b.

    A grid of ``n_grid`` exponents (one matrix product) brackets the minimum; for l2 and
    relative the zero of the cost's derivative in that bracket is found by
    :func:`scipy.optimize.brentq` (each step one product with two columns); for l1, whose
    cost has no derivative everywhere, the bracket is refined by nested grids.
    Returns ``(b, A, cost, n_evaluations)``.
    """
    lo, hi = (float(v) for v in b_bounds)
    grid = np.linspace(lo, hi, n_grid)
    cost, _ = _power_costs(grid, hist, load_N, objective)
    k = int(np.nanargmin(cost))
    if k in (0, n_grid - 1):
        raise ValueError(f"power fit: best exponent b = {grid[k]:.3f} is at the edge of "
                         f"b_bounds {tuple(b_bounds)}; expected an interior optimum "
                         "(check the loads)")
    lo, hi, n_eval = grid[k - 1], grid[k + 1], n_grid
    if objective == "l1":
        while hi - lo > xtol:
            grid = np.linspace(lo, hi, n_grid)
            cost, _ = _power_costs(grid, hist, load_N, objective)
            k, n_eval = int(np.nanargmin(cost)), n_eval + n_grid
            lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, n_grid - 1)]
        b = float(grid[k])
    else:
        w2 = _weights(load_N, objective) ** 2
        slope_lo, slope_hi = (_cost_slope(x, hist, load_N, w2) for x in (lo, hi))
        if slope_lo < 0 < slope_hi:
            b, info = optimize.brentq(_cost_slope, lo, hi, args=(hist, load_N, w2),
                                      xtol=xtol, full_output=True)
            n_eval += 2 + info.function_calls
        else:  # flat or kinked cost: keep the grid's best
            b = float(grid[k])
    cost, A = _power_costs(np.array([b]), hist, load_N, objective)
    return float(b), float(A[0]), float(cost[0]), n_eval + 1


def _ols_stderr(jac, resid, n_params):
    """Return standard errors from the Jacobian: cov = s2 (J^T J)^-1, s2 = RSS / (n - p)."""
    n = len(resid)
    if n <= n_params:
        return None
    s2 = float(resid @ resid) / (n - n_params)
    cov = np.linalg.pinv(jac.T @ jac) * s2
    return np.sqrt(np.clip(np.diag(cov), 0.0, None)), cov


# ---------------------------------------------------------------------- methods
def fit_linear(hist, load_N, *, point=None, **_):
    """I-Scan linear calibration through zero, f = A * raw (thesis sec. 3.5).

    I-Scan's 1-point calibration is ``A = F / R`` (raw sum ``R``) of one point: give
    ``point`` (index into the usable points), or pass a single point. Without ``point``
    and with several points, the least-squares line through zero
    ``A = sum(F R) / sum(R**2)``.
    """
    details = {}
    if point is not None:
        if not 0 <= int(point) < len(load_N):
            raise ValueError(f"point={point!r} is invalid; expected an index into the "
                             f"{len(load_N)} usable points")
        hist, load_N = hist[[int(point)]], load_N[[int(point)]]
        details["point"] = int(point)
    raw_sum = hist @ LEVELS
    A = float(raw_sum @ load_N / (raw_sum @ raw_sum))
    err = _ols_stderr(raw_sum[:, None], A * raw_sum - load_N, 1)
    details["stderr_method"] = "jacobian" if err else "none (one point)"
    return Fit("power", {"A": A, "b": 1.0},
               {"A": None if err is None else float(err[0][0]), "b": 0.0}, details)


def fit_power_2pt(hist, load_N, *, pair=None, **_):
    """I-Scan 2-point power law on the mean raw reading of the loaded sensels.

    I-Scan assumes every loaded sensel of point i reads its mean ``x_i = R_i / C_i`` and
    carries ``F_i / C_i``, so ``F_i / C_i = A x_i**b`` (thesis sec. 3.5, ``y = a x**b``
    with points at about 20 % and 80 % of the maximum load). With more than two points the
    two nearest 20 % and 80 % of the largest load are used (or ``pair=(i, j)``, indices
    into the used points).
    """
    loaded = hist[:, 1:].sum(axis=1)
    mean_raw = (hist @ LEVELS) / loaded
    per_cell = load_N / loaded
    i, j = _choose_pair(load_N, pair)
    b = float(np.log(per_cell[j] / per_cell[i]) / np.log(mean_raw[j] / mean_raw[i]))
    A = float(per_cell[i] / mean_raw[i] ** b)
    return Fit("power", {"A": A, "b": b}, {"A": None, "b": None},
               {"pair": [int(i), int(j)], "mean_raw": [mean_raw[i], mean_raw[j]],
                "stderr_method": "none (two points define the curve exactly)"})


def _choose_pair(load_N, pair):
    if len(load_N) < 2:
        raise ValueError(f"power-2pt needs 2 usable points; found {len(load_N)}")
    if pair is None:
        top = load_N.max()
        i = int(np.argmin(np.abs(load_N - 0.2 * top)))
        j = int(np.argmin(np.abs(load_N - 0.8 * top)))
        if load_N[i] == load_N[j]:
            j = int(np.argmax(load_N))
        if load_N[i] == load_N[j]:
            raise ValueError("power-2pt needs two different loads; all usable points have "
                             f"load_N = {load_N[i]:.6g}")
        return i, j
    i, j = (int(k) for k in pair)
    if not (0 <= i < len(load_N) and 0 <= j < len(load_N)) or i == j:
        raise ValueError(f"pair={pair!r} is invalid; expected two different indices "
                         f"into the {len(load_N)} usable points")
    return i, j


def fit_power(hist, load_N, *, objective=DEFAULT_OBJECTIVE, b_bounds=B_BOUNDS, **_):
    """Multi-point power law over every sensel, f = A * raw**b.

    Objectives: ``l2`` minimises ``sum_T (A S_T(b) - F_T)**2`` (Zvyagin 2022, eq. 3),
    ``l1`` minimises ``sum_T |F_T - A S_T(b)|`` (Gillis 2013, eq. 5.1, I-Scan), and
    ``relative`` minimises ``sum_T ((A S_T(b) - F_T) / F_T)**2``. ``A`` is profiled out
    (closed form, or the weighted median for ``l1``) and ``b`` found by nested grids
    over ``b_bounds`` (each pass one matrix product over the histograms).
    """
    _check_objective(objective)
    hist = np.asarray(hist, dtype=float)  # one conversion, then BLAS products
    b, A, cost, n_eval = _minimise_b(hist, load_N, objective, b_bounds)
    sums = _power_sums(hist, b)
    w = _weights(load_N, objective)
    jac = w[:, None] * np.column_stack([sums, A * (hist @ (LEVELS ** b * LOG_LEVELS))])
    err = _ols_stderr(jac, w * (A * sums - load_N), 2)
    stderr = {"A": None, "b": None} if err is None else {"A": float(err[0][0]),
                                                          "b": float(err[0][1])}
    details = {"objective": objective, "cost": cost, "n_evaluations": n_eval,
               "stderr_method": "jacobian" + (" (L2 approximation at the L1 optimum)"
                                              if objective == "l1" else "")}
    if err is not None:
        details["corr_A_b"] = float(err[1][0, 1] / np.sqrt(err[1][0, 0] * err[1][1, 1]))
    return Fit("power", {"A": A, "b": b}, stderr, details)


def fit_power_censored(hist, load_N, censored, *, objective=DEFAULT_OBJECTIVE,
                       b_bounds=B_BOUNDS):
    """Power law f = A * raw**b where a patch with a sensel at 255 is a lower bound.

    A sensel at 255 carries at least f(255), so for a censored patch the law's prediction
    (255 counted as 255) is a lower bound of its load: only a prediction above the load is
    an error. The cost is ``sum_uncensored w**2 (A S_T(b) - F_T)**2 + sum_censored w**2
    max(0, A S_T(b) - F_T)**2`` (a Tobit-style one-sided residual on the patch load; weights
    as :func:`fit_power`), minimised over ``(log A, b)`` by
    :func:`scipy.optimize.least_squares` from the fit to the uncensored patches.

    Parameters
    ----------
    hist, load_N : array_like
        Histograms (n, 256) and loads (n,) of the used patches.
    censored : array_like of bool
        Patches with at least one sensel at 255.
    """
    if objective == "l1":
        raise ValueError("objective='l1' has no censored fit; expected 'l2' or 'relative'")
    hist = np.asarray(hist, dtype=float)
    censored = np.asarray(censored, dtype=bool)
    if (~censored).sum() < 2:
        raise ValueError(f"{(~censored).sum()} patch(es) without a saturated sensel; a "
                         "censored fit needs at least 2 to start from (every other patch "
                         "is only a lower bound)")
    start = fit_power(hist[~censored], load_N[~censored], objective=objective,
                      b_bounds=b_bounds)
    w = _weights(load_N, objective)

    def residuals(x):
        excess = np.exp(x[0]) * _power_sums(hist, x[1]) - load_N
        return w * np.where(censored, np.maximum(excess, 0.0), excess)

    sol = optimize.least_squares(residuals, [np.log(start.params["A"]), start.params["b"]],
                                 bounds=([-np.inf, b_bounds[0]], [np.inf, b_bounds[1]]))
    A, b = float(np.exp(sol.x[0])), float(sol.x[1])
    active = censored & (residuals(sol.x) > 0)
    details = {"objective": objective, "censored": int(censored.sum()),
               "censored_active": int(active.sum()), "cost": float(sol.cost),
               "stderr_method": "none (censored fit: use n_bootstrap)"}
    return Fit("power", {"A": A, "b": b}, {"A": None, "b": None}, details)


def fit_linear_offset(hist, load_N, *, objective="l2", **_):
    """Paikowsky & Hajduk (1997) linear calibration with offset, P = K (RSD - b).

    Per loaded sensel ``f = K (raw - offset)``; a frame gives ``F = K R - K offset C``,
    linear least squares in ``(K, K offset)`` (thesis sec. 3.5). Readings below the
    offset give negative forces, as the published formula does.
    """
    _check_ls_objective(objective, "linear-offset")
    design = np.column_stack([hist @ LEVELS, -hist[:, 1:].sum(axis=1)])
    w = _weights(load_N, objective)
    coef, *_ = np.linalg.lstsq(w[:, None] * design, w * load_N, rcond=None)
    K, c = (float(v) for v in coef)
    err = _ols_stderr(w[:, None] * design, w * (design @ coef - load_N), 2)
    stderr = {"K": None, "offset": None}
    if err is not None:
        grad = np.array([-c / K**2, 1.0 / K])
        stderr = {"K": float(err[0][0]), "offset": float(np.sqrt(grad @ err[1] @ grad))}
    return Fit("linear-offset", {"K": K, "offset": c / K}, stderr,
               {"objective": objective, "stderr_method": "jacobian (delta method for offset)"})


def fit_polynomial(hist, load_N, *, degree=3, objective="l2", **_):
    """Polynomial per-sensel law through the origin, f = sum_j c_j raw**j, j = 1..degree.

    Linear least squares on the moments ``hist @ raw**j`` (computed on raw/255 for
    conditioning).
    """
    _check_ls_objective(objective, "polynomial")
    if int(degree) < 1:
        raise ValueError(f"degree={degree!r}; expected an integer >= 1")
    powers = np.arange(1, int(degree) + 1)
    design = hist @ ((LEVELS / 255.0)[:, None] ** powers)
    w = _weights(load_N, objective)
    coef, *_ = np.linalg.lstsq(w[:, None] * design, w * load_N, rcond=None)
    err = _ols_stderr(w[:, None] * design, w * (design @ coef - load_N), len(powers))
    scale = 255.0 ** powers
    stderr = None if err is None else (err[0] / scale).tolist()
    return Fit("polynomial", {"coefficients": (coef / scale).tolist()},
               {"coefficients": stderr}, {"objective": objective, "stderr_method": "jacobian"})


def fit_piecewise(hist, load_N, *, knots=(1, 16, 64, 255), objective=DEFAULT_OBJECTIVE, **_):
    """Piecewise power law: one power law per low/medium/high raw range (after Stith).

    The law is a straight line between ``knots`` in log-log coordinates, continuous at
    the knots, so each range has its own ``A_r`` and ``b_r``. The log forces at the knots
    are fitted by nonlinear least squares (:func:`scipy.optimize.least_squares`).
    """
    _check_ls_objective(objective, "piecewise")
    knots = np.asarray(knots, dtype=float)
    if len(knots) < 2 or np.any(np.diff(knots) <= 0) or knots[0] <= 0:
        raise ValueError(f"knots={knots.tolist()} must increase and be > 0; expected e.g. "
                         "(1, 16, 64, 255)")
    start = fit_power(hist, load_N, objective=objective).params
    w = _weights(load_N, objective)

    def resid(log_force):
        table = force_table("piecewise-power", {"knots": knots, "force_N": np.exp(log_force)})
        return w * (hist @ table - load_N)

    sol = optimize.least_squares(resid, np.log(start["A"] * knots ** start["b"]), method="lm")
    force = np.exp(sol.x)
    err = _ols_stderr(sol.jac, sol.fun, len(knots))
    stderr = None if err is None else (force * err[0]).tolist()
    b_r = np.diff(np.log(force)) / np.diff(np.log(knots))
    A_r = force[:-1] / knots[:-1] ** b_r
    return Fit("piecewise-power", {"knots": knots.tolist(), "force_N": force.tolist()},
               {"knots": None, "force_N": stderr},
               {"objective": objective, "segments_A": A_r.tolist(), "segments_b": b_r.tolist(),
                "stderr_method": "jacobian (delta method from log forces)"})


def fit_lut(hist, load_N, *, knots=None, objective="l2", **_):
    """Monotone lookup table: nondecreasing force at ``knots``, linear in between.

    Force at the knots is the cumulative sum of nonnegative increments found by
    nonnegative least squares (:func:`scipy.optimize.nnls`), so the table is monotone
    and ``f(0) = 0``. Default knots: 0 and 12 log-spaced raw values 3..255.
    """
    _check_ls_objective(objective, "lut")
    if knots is None:
        knots = np.r_[0, np.unique(np.rint(np.geomspace(3, 255, 12)))]
    knots = np.asarray(knots, dtype=float)
    if knots[0] != 0 or knots[-1] < 255 or np.any(np.diff(knots) <= 0):
        raise ValueError(f"knots={knots.tolist()} must increase from 0 to 255; expected e.g. "
                         "[0, 3, 5, ..., 255]")
    interp = np.stack([np.interp(LEVELS, knots, e) for e in np.eye(len(knots))], axis=1)
    cumulative = np.tril(np.ones((len(knots) - 1, len(knots) - 1)))
    design = hist @ interp[:, 1:] @ cumulative
    w = _weights(load_N, objective)
    increments, _ = optimize.nnls(w[:, None] * design, w * load_N)
    force = np.r_[0.0, cumulative @ increments]
    return Fit("table", {"knots": knots.tolist(), "force_N": force.tolist()},
               {"knots": None, "force_N": None},
               {"objective": objective, "stderr_method": "none (use n_bootstrap)"})


FITTERS = {
    "linear": fit_linear,
    "power-2pt": fit_power_2pt,
    "power": fit_power,
    "linear-offset": fit_linear_offset,
    "piecewise": fit_piecewise,
    "lut": fit_lut,
    "polynomial": fit_polynomial,
}

CENSORED_FITTERS = {"power": fit_power_censored}
"""Methods with a censored fit (``saturated="censored"``): patches at 255 as lower bounds."""
