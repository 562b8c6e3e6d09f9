"""Static calibration methods, each fitted on 256-bin histograms of calibration frames.

Every fit takes ``hist`` (n, 256) int64 and ``load_N`` (n,) of the *used* points and
returns a :class:`Fit` (model name, parameters, standard errors, details). The cost of a
fit does not depend on the number of sensels: ``sum_k X_k**b = hist @ arange(256)**b``.
"""

from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from tactilecal.calibration._models import LEVELS, force_table
from tactilecal.calibration._points import take_rows

__all__ = ["Fit", "FITTERS", "EXACT_METHODS", "OBJECTIVES", "DEFAULT_OBJECTIVE",
           "fit_censored"]

OBJECTIVES = ("l2", "l1", "relative")
DEFAULT_OBJECTIVE = "l1"
"""The power method's default: on the simulated family (``benchmarks/bench_static_family.py
--seeds 20 --test-patches 150``) l1 had the best worst case of the three objectives;
relative and l2 fell to 0.90-0.91 of the true law's worst share on 9500-b1.4."""
LS_OBJECTIVE = "relative"
"""Default of the least-squares-only methods (piecewise)."""
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


def _censored_median(ratio, weight, censored):
    """Minimiser of ``sum_unc w |A - r| + sum_cens w max(0, A - r)`` over A.

    Without censored terms this is the w-weighted median of r. The cost is convex and
    piecewise linear; its slope just above the k-th smallest r is
    ``2 W_unc(<= r_k) + W_cens(<= r_k) - W_unc(all)``, and the minimum is the first r_k
    where that slope is >= 0.
    """
    order = np.argsort(ratio, kind="stable")
    w, c = weight[order], censored[order]
    slope = 2.0 * np.cumsum(np.where(c, 0.0, w)) + np.cumsum(np.where(c, w, 0.0)) \
        - w[~c].sum()
    return float(ratio[order][np.argmax(slope >= 0)])


def _best_A(sums, load_N, objective, censored=None):
    """Optimal A for fixed b: closed form for l2/relative, weighted median for l1.

    For l1, ``sum |A S - F| = sum S |A - F/S|`` is minimised by the S-weighted median of
    F/S; censored patches (``censored``, l1 only) add ``S max(0, A - F/S)``.
    """
    if objective == "l1":
        flags = np.zeros(len(load_N), bool) if censored is None else censored
        return _censored_median(load_N / sums, sums, flags)
    w2s = _weights(load_N, objective) ** 2 * sums
    # elementwise products, not BLAS dot: cheaper than a threaded BLAS call on busy cores
    return float(np.sum(w2s * load_N) / np.sum(w2s * sums))


def _power_costs(b_values, hist, load_N, objective, censored=None):
    """Profiled cost and best A for several exponents in one pass over the histograms.

    One matrix product ``hist @ levels**b`` for all ``b`` reads the histograms once, which
    is what costs time for tens of thousands of points. ``censored`` (l1 only): patches
    whose residual counts only when the prediction exceeds the load.
    """
    sums = hist @ (LEVELS[:, None] ** np.asarray(b_values)[None, :])
    w = _weights(load_N, objective)[:, None]
    if objective == "l1":
        A = np.array([_best_A(col, load_N, "l1", censored) for col in sums.T])
        r = A * sums - load_N[:, None]
        if censored is not None:
            r = np.where(censored[:, None], np.maximum(r, 0.0), r)
        return np.abs(w * r).sum(axis=0), A
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


def _minimise_b(hist, load_N, objective, b_bounds, n_grid=13, xtol=1e-10, censored=None):
    """Minimise the profiled cost over b.

    A grid of ``n_grid`` exponents (one matrix product) brackets the minimum; for l2 and
    relative the zero of the cost's derivative in that bracket is found by
    :func:`scipy.optimize.brentq` (each step one product with two columns); for l1, whose
    cost has no derivative everywhere, the bracket is refined by nested grids.
    ``censored`` is passed to :func:`_power_costs` (l1 only).
    Returns ``(b, A, cost, n_evaluations)``.
    """
    lo, hi = (float(v) for v in b_bounds)
    grid = np.linspace(lo, hi, n_grid)
    cost, _ = _power_costs(grid, hist, load_N, objective, censored)
    k = int(np.nanargmin(cost))
    if k in (0, n_grid - 1):
        raise ValueError(f"power fit: best exponent b = {grid[k]:.3f} is at the edge of "
                         f"b_bounds {tuple(b_bounds)}; expected an interior optimum "
                         "(check the loads)")
    lo, hi, n_eval = grid[k - 1], grid[k + 1], n_grid
    if objective == "l1":
        while hi - lo > xtol:
            grid = np.linspace(lo, hi, n_grid)
            cost, _ = _power_costs(grid, hist, load_N, objective, censored)
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
    cost, A = _power_costs(np.array([b]), hist, load_N, objective, censored)
    return float(b), float(A[0]), float(cost[0]), n_eval + 1


NO_STDERR = ("none: pass n_bootstrap (a single fit's Jacobian errors held the true b in only "
             "22-90 % of 50 simulated sessions per family member, issue 12)")


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
    details["stderr_method"] = NO_STDERR
    return Fit("power", {"A": A, "b": 1.0}, {"A": None, "b": None}, details)


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
    details = {"objective": objective, "cost": cost, "n_evaluations": n_eval,
               "stderr_method": NO_STDERR}
    return Fit("power", {"A": A, "b": b}, {"A": None, "b": None}, details)


def check_unsaturated(censored, name_of=None, kind="patch(es)"):
    """Raise unless 2 patches are unsaturated: a censored fit starts from them.

    ``name_of(k)`` names the ``k``-th patch in the message (the first 8 saturated ones).
    """
    censored = np.asarray(censored, dtype=bool)
    n_clean = int((~censored).sum())
    if n_clean >= 2:
        return
    listed = ""
    if name_of is not None:
        saturated = np.flatnonzero(censored)
        listed = (f"; saturated: {', '.join(name_of(k) for k in saturated[:8])}"
                  f"{' ...' if len(saturated) > 8 else ''}")
    raise ValueError(f"{n_clean} {kind} without a saturated sensel; a censored fit needs at "
                     f"least 2 to start from (every other one is only a lower bound{listed})")


def fit_power_censored(hist, load_N, censored, *, objective=DEFAULT_OBJECTIVE,
                       b_bounds=B_BOUNDS):
    """Power law f = A * raw**b where a patch with a sensel at 255 is a lower bound.

    A sensel at 255 carries at least f(255), so for a censored patch the law's prediction
    (255 counted as 255) is a lower bound of its load: only a prediction above the load is
    an error (a Tobit-style one-sided residual on the patch load). ``l1`` minimises
    ``sum_unc |A S_T(b) - F_T| + sum_cens max(0, A S_T(b) - F_T)`` with A profiled out
    (:func:`_censored_median`) and b by nested grids, as :func:`fit_power`; ``l2`` and
    ``relative`` minimise the squared form over ``(log A, b)`` with
    :func:`scipy.optimize.least_squares`, from the fit to the uncensored patches.

    Parameters
    ----------
    hist, load_N : array_like
        Histograms (n, 256) and loads (n,) of the used patches.
    censored : array_like of bool
        Patches with at least one sensel at 255.
    """
    _check_objective(objective)
    hist = np.asarray(hist, dtype=float)
    censored = np.asarray(censored, dtype=bool)
    check_unsaturated(censored)
    if objective == "l1":
        b, A, cost, _ = _minimise_b(hist, load_N, objective, b_bounds, censored=censored)
    else:
        A, b, cost = _censored_least_squares(hist, load_N, censored, objective, b_bounds)
    excess = A * _power_sums(hist, b) - load_N
    details = {"objective": objective, "censored": int(censored.sum()),
               "censored_active": int((censored & (excess > 0)).sum()), "cost": cost,
               "stderr_method": NO_STDERR}
    return Fit("power", {"A": A, "b": b}, {"A": None, "b": None}, details)


def _censored_least_squares(hist, load_N, censored, objective, b_bounds):
    """Return (A, b, cost) minimising the one-sided squared cost of fit_power_censored."""
    start = fit_power(hist[~censored], load_N[~censored], objective=objective,
                      b_bounds=b_bounds)
    w = _weights(load_N, objective)

    def residuals(x):
        excess = np.exp(x[0]) * _power_sums(hist, x[1]) - load_N
        return w * np.where(censored, np.maximum(excess, 0.0), excess)

    sol = optimize.least_squares(residuals, [np.log(start.params["A"]), start.params["b"]],
                                 bounds=([-np.inf, b_bounds[0]], [np.inf, b_bounds[1]]))
    return float(np.exp(sol.x[0])), float(sol.x[1]), float(sol.cost)


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
    return Fit("linear-offset", {"K": K, "offset": c / K}, {"K": None, "offset": None},
               {"objective": objective, "stderr_method": NO_STDERR})


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
    return Fit("polynomial", {"coefficients": (coef / 255.0 ** powers).tolist()},
               {"coefficients": None}, {"objective": objective, "stderr_method": NO_STDERR})


def fit_piecewise(hist, load_N, *, knots=(1, 16, 64, 255), objective=LS_OBJECTIVE, **_):
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
    b_r = np.diff(np.log(force)) / np.diff(np.log(knots))
    A_r = force[:-1] / knots[:-1] ** b_r
    return Fit("piecewise-power", {"knots": knots.tolist(), "force_N": force.tolist()},
               {"knots": None, "force_N": None},
               {"objective": objective, "segments_A": A_r.tolist(), "segments_b": b_r.tolist(),
                "stderr_method": NO_STDERR})


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
               {"objective": objective, "stderr_method": NO_STDERR})


FITTERS = {
    "linear": fit_linear,
    "power-2pt": fit_power_2pt,
    "power": fit_power,
    "linear-offset": fit_linear_offset,
    "piecewise": fit_piecewise,
    "lut": fit_lut,
    "polynomial": fit_polynomial,
}

EXACT_METHODS = ("power-2pt",)
"""Methods whose curve passes exactly through chosen points: a lower bound cannot be one of
them, so a censored fit takes its points from the unsaturated patches."""


def fit_censored(method, hist, load_N, censored, **options):
    """Fit ``method`` with the patches flagged ``censored`` (a sensel at 255) as lower bounds.

    A censored patch's load is only bounded below by the law's prediction, so it adds a
    cost only when the prediction exceeds its load (a Tobit-style one-sided residual).
    ``power`` has its own fit (:func:`fit_power_censored`). Every other least-squares
    method is refitted on the unsaturated patches plus the censored ones it over-predicts
    until that set stops changing: the fixed point is a stationary point of the one-sided
    cost ``sum_unc r**2 + sum_cens max(0, r)**2``, which for the linear methods
    (``linear``, ``linear-offset``, ``polynomial``, ``lut``) is convex, so it is the
    minimum. ``power-2pt`` and ``linear`` with ``point`` take their points from the
    unsaturated patches (:data:`EXACT_METHODS`).

    Returns
    -------
    Fit
        With ``details["censored"]`` (patches given as lower bounds) and
        ``details["censored_active"]`` (those the law over-predicts, which enter the cost).

    Raises
    ------
    ValueError
        Fewer than 2 unsaturated patches, or no stable set within 50 refits.
    """
    if method == "power":  # its own fit, which checks the unsaturated patches itself
        return fit_power_censored(hist, load_N, censored, **options)
    censored = np.asarray(censored, dtype=bool)
    check_unsaturated(censored)
    exact = method in EXACT_METHODS or options.get("point") is not None
    active = np.zeros_like(censored)
    for _ in range(1 if exact else 50):
        rows = ~censored | active
        fit = FITTERS[method](take_rows(hist, rows), load_N[rows], **options)
        excess = hist @ force_table(fit.model, fit.params) - load_N
        now = censored & (excess > 0)
        if exact or np.array_equal(now, active):
            for key in ("pair", "point"):  # indices into the rows fitted -> into all rows
                if key in fit.details:
                    fit.details[key] = np.flatnonzero(rows)[fit.details[key]].tolist()
            fit.details.update(censored=int(censored.sum()), censored_active=int(now.sum()))
            return fit
        active = now
    raise ValueError(f"censored {method} fit: the set of over-predicted saturated patches "
                     "did not settle in 50 refits; expected 'drop' for this session")
