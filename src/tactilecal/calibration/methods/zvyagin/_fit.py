"""Power law through the (A, b) set (eq. 14) and the final (A0, b0) minimising E (eq. 15)."""

import numpy as np
from scipy.optimize import minimize_scalar

from tactilecal._errors import TactilecalError
from tactilecal.calibration._powerfit import fit_power, fit_power_censored

__all__ = ["fit_power_law", "patch_power_sums", "energy", "minimise_energy",
           "minimise_energy_free", "choose_objective", "saturation_pressure_MPa"]

_RAW = np.arange(256, dtype=np.float64)
#: MAD -> standard deviation for normal residuals
_MAD_TO_SIGMA = 1.4826


def _lstsq_loglog(a_N, b):
    design = np.column_stack([np.ones_like(b), np.log(b)])
    coef, *_ = np.linalg.lstsq(design, np.log(a_N), rcond=None)
    return coef, np.log(a_N) - design @ coef


def _r_squared(residual, y):
    total = np.sum((y - y.mean()) ** 2)
    return float(1.0 - np.sum(residual ** 2) / total) if total > 0 else float("nan")


def fit_power_law(a_N, b, *, outliers="none", trim=0.05, clip=3.5, max_iter=50):
    """Fit A = alpha * b**beta to the (A, b) set by least squares in log-log (eq. 14).

    Parameters
    ----------
    a_N, b : numpy.ndarray
        The pair estimates (A in newtons per sensel, b dimensionless, b > 0).
    outliers : {"none", "trim", "mad"}
        ``"none"`` (paper as written): one least-squares fit of log A on log b over all
        pairs. ``"trim"``: the same fit over the pairs whose b lies between the ``trim`` and
        ``1 - trim`` quantiles of b (the cloud bends in log-log, and a few pairs with b far
        from the bulk have large leverage). ``"mad"``: iterate the fit, each time keeping
        the pairs whose log residual lies within ``clip`` robust standard deviations
        (1.4826 x median absolute deviation) of the median residual, until the kept set
        stops changing.
    trim : float
        Share of pairs cut at each end of the b range by ``"trim"``.
    clip : float
        Clipping threshold in robust standard deviations (``"mad"``).
    max_iter : int
        Iteration cap for ``"mad"``.

    Returns
    -------
    dict
        ``alpha``, ``beta``, ``r2`` (coefficient of determination of log A on log b over the
        pairs kept), ``r2_all`` (the same line scored on every pair), ``inlier`` (bool mask).

    Examples
    --------
    >>> b = np.linspace(1.0, 1.5, 20); a = 0.0035 * (b / 1.16) ** -6.0
    >>> fit = fit_power_law(a, b)
    >>> round(fit["beta"], 6), round(fit["alpha"] * 1.16 ** fit["beta"], 6), round(fit["r2"], 6)
    (-6.0, 0.0035, 1.0)
    """
    a_N = np.asarray(a_N, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    if outliers not in ("none", "trim", "mad"):
        raise TactilecalError(f"outliers = {outliers!r}; expected 'none', 'trim' or 'mad'")
    inlier = np.ones(b.shape, dtype=bool)
    if outliers == "trim":
        if not 0 <= trim < 0.5:
            raise TactilecalError(f"trim = {trim}; expected 0 <= trim < 0.5")
        lo, hi = np.quantile(b, [trim, 1 - trim])
        inlier = (b >= lo) & (b <= hi)
    coef, _ = _lstsq_loglog(a_N[inlier], b[inlier])
    resid = np.log(a_N) - (coef[0] + coef[1] * np.log(b))
    for _ in range(max_iter if outliers == "mad" else 0):
        centre = np.median(resid[inlier])
        scale = _MAD_TO_SIGMA * np.median(np.abs(resid[inlier] - centre))
        keep = np.abs(resid - centre) <= clip * scale if scale > 0 else inlier
        if np.array_equal(keep, inlier):
            break
        inlier = keep
        coef, _ = _lstsq_loglog(a_N[inlier], b[inlier])
        resid = np.log(a_N) - (coef[0] + coef[1] * np.log(b))
    log_a = np.log(a_N)
    return {"alpha": float(np.exp(coef[0])), "beta": float(coef[1]),
            "r2": _r_squared(resid[inlier], log_a[inlier]), "r2_all": _r_squared(resid, log_a),
            "inlier": inlier}


def patch_power_sums(histograms, b):
    """S_T(b) = sum_k X_k**b for every patch and every exponent; shape (n_patches, n_b).

    Raw 0 contributes nothing (0**b = 0 for b > 0).
    """
    b = np.atleast_1d(np.asarray(b, dtype=np.float64))
    return np.asarray(histograms, dtype=np.float64) @ (_RAW[:, None] ** b[None, :])


def _misfit_N(predicted_N, load_N, censored):
    """Return load minus prediction, shape (n_patches, n_b), one-sided where censored.

    A censored patch (a sensel at 255) only counts when the law predicts more than its
    load, which the prediction (255 read as 255) only bounds from below.
    """
    misfit = np.asarray(load_N, dtype=np.float64)[:, None] - predicted_N
    if censored is None:
        return misfit
    return np.where(np.asarray(censored, dtype=bool)[:, None], np.minimum(misfit, 0.0), misfit)


def energy(b0, histograms, load_N, alpha, beta, censored=None):
    """E(b0) = sum_T (F_T - A0 sum_k X_k**b0)**2 with A0 = alpha * b0**beta (eq. 15), in N^2.

    ``censored`` (bool per patch, optional): patches with a sensel at 255 add to E only
    where the law predicts more than their load (a Tobit-style one-sided term).

    Examples
    --------
    >>> h = np.zeros((1, 256), dtype=int); h[0, 100] = 10
    >>> float(energy(1.0, h, np.array([10.0]), 0.01, 0.0)[0])
    0.0
    """
    b0 = np.atleast_1d(np.asarray(b0, dtype=np.float64))
    predicted = alpha * b0 ** beta * patch_power_sums(histograms, b0)
    return np.sum(_misfit_N(predicted, load_N, censored) ** 2, axis=0)


def minimise_energy(histograms, load_N, alpha, beta, b_range, *, censored=None, n_grid=201,
                    max_step=0.005):
    """Find b0 minimising E on the power-law curve within ``b_range`` (eq. 15).

    A grid of at least ``n_grid`` exponents, at most ``max_step`` apart, locates the global
    minimum over the range (E may have several local minima and a narrow valley), then
    :func:`scipy.optimize.minimize_scalar` (bounded) refines it between the grid neighbours.

    Returns
    -------
    dict
        ``b0``, ``A0`` = alpha * b0**beta, ``E`` (N^2), ``b_range``, ``at_bound`` (True when the
        minimum sits on an end of the range: E keeps falling beyond it), ``b_grid``, ``E_grid``.
    """
    lo, hi = float(b_range[0]), float(b_range[1])
    n_grid = max(n_grid, int(np.ceil((hi - lo) / max_step)) + 1)
    grid = np.linspace(lo, hi, n_grid) if hi > lo else np.array([lo])
    e_grid = energy(grid, histograms, load_N, alpha, beta, censored)
    k = int(np.argmin(e_grid))
    if grid.size > 1:
        bracket = (grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)])
        opt = minimize_scalar(lambda x: energy(x, histograms, load_N, alpha, beta, censored)[0],
                              bounds=bracket, method="bounded",
                              options={"xatol": 1e-7})
        b0 = float(opt.x) if opt.fun <= e_grid[k] else float(grid[k])
    else:
        b0 = float(grid[0])
    e0 = float(energy(b0, histograms, load_N, alpha, beta, censored)[0])
    at_bound = grid.size > 1 and k in (0, grid.size - 1)
    return {"b0": b0, "A0": float(alpha * b0 ** beta), "E": e0, "b_range": (lo, hi),
            "at_bound": bool(at_bound), "b_grid": grid, "E_grid": e_grid}


#: Objectives the cross-validated free step chooses between (l1 first: it wins ties).
CV_OBJECTIVES = ("l1", "relative")
CV_FOLDS = 5


def _fit_free(h, f, censored, objective):
    """Fit the power method's law to these patches, censored ones as lower bounds."""
    if censored is not None and np.any(censored):
        return fit_power_censored(h, f, censored, objective=objective)
    return fit_power(h, f, objective=objective)


def choose_objective(histograms, load_N, *, censored=None, objectives=CV_OBJECTIVES,
                     folds=CV_FOLDS):
    """Pick the free step's objective by ``folds``-fold cross-validation over the patches.

    Patch ``k`` is held out in fold ``k % folds``; each objective's law is fitted on the
    other folds and predicts the held-out unsaturated patches. The objective with the
    largest share of held-out patches within 5 % of their load wins (then the smaller
    mean absolute relative error, to 1e-6; then the first of ``objectives``). An objective
    whose fit fails on a fold (b at the edge of its bounds) is not chosen.

    Returns
    -------
    objective : str
    scores : dict
        Per objective: ``[share within 5 %, mean absolute relative error]`` of its
        cross-validated predictions (None for an objective whose fit failed).
    """
    h = np.asarray(histograms, dtype=np.float64)
    f = np.asarray(load_N, dtype=np.float64)
    cens = np.zeros(f.size, dtype=bool) if censored is None else np.asarray(censored, bool)
    fold = np.arange(f.size) % folds
    scores = {}
    for objective in objectives:
        errors = []
        try:
            for k in range(folds):
                train, held = fold != k, (fold == k) & ~cens
                fit = _fit_free(h[train], f[train], cens[train], objective)
                predicted = fit.params["A"] * patch_power_sums(h[held], fit.params["b"])[:, 0]
                errors.append(np.abs(predicted / f[held] - 1))
        except ValueError:
            scores[objective] = None
            continue
        errors = np.concatenate(errors)
        scores[objective] = [float(np.mean(errors <= 0.05)), float(np.mean(errors))]
    ranked = [o for o in objectives if scores[o] is not None]
    if not ranked:
        return objectives[0], scores
    # mean errors closer than 1e-6 (a ten-thousandth of a percent) are a tie
    return max(ranked, key=lambda o: (scores[o][0], -round(scores[o][1], 6))), scores


def minimise_energy_free(histograms, load_N, curve, *, censored=None, objective="l1"):
    """Minimise the patch misfit over A and b together (robust mode's step 4).

    The misfit is eq. 15's without the constraint A = alpha b**beta, i.e. eq. 3 over every
    patch: the power method's fit (:func:`tactilecal.calibration._powerfit.fit_power`, or
    ``fit_power_censored`` when ``censored`` is given) with its ``objective`` ("l2" is E
    itself; "l1" and "relative" weigh each patch's error as the power method does) and its
    b bounds. ``objective="cv"`` (robust mode's default) takes l1 or relative, whichever
    predicts held-out patches better in 5-fold cross-validation (:func:`choose_objective`).
    The curve of eq. 14 keeps its optimum as a diagnostic: where the pair cloud
    is biased (e.g. b near 1, where roots Y <= 3 are cut) the constrained minimum
    is biased with it.

    Parameters
    ----------
    histograms, load_N : numpy.ndarray
        The usable patches.
    curve : dict
        ``minimise_energy``'s result (the curve's optimum), kept as a diagnostic.
    censored : numpy.ndarray of bool, optional
        Patches with a sensel at 255 (lower bounds of their load).
    objective : {"l1", "l2", "relative", "cv"}
        The power method's objective, or "cv".

    Returns
    -------
    dict
        ``curve`` with ``A0``, ``b0`` and ``E`` (the objective's cost) of the free fit, plus
        ``curve_A0``, ``curve_b0`` (the constrained optimum), ``free`` = True,
        ``objective`` (the one used) and, for "cv", ``objective_cv`` (the scores).
    """
    h = np.asarray(histograms, dtype=np.float64)
    f = np.asarray(load_N, dtype=np.float64)
    extra = {}
    if objective == "cv":
        objective, scores = choose_objective(h, f, censored=censored)
        extra["objective_cv"] = scores
    fit = _fit_free(h, f, censored, objective)
    return {**curve, "A0": fit.params["A"], "b0": fit.params["b"],
            "E": float(fit.diagnostics["cost"]), "at_bound": False,
            "curve_A0": curve["A0"], "curve_b0": curve["b0"], "free": True,
            "objective": objective, **extra}


def saturation_pressure_MPa(a_N, b, sensel_area_mm2):
    """Saturation pressure p_s = A * 255**b / S_sensel in MPa (Zvyagin 2022, eq. 16).

    Parameters
    ----------
    a_N : float
        A of f = A * X**b, newtons per sensel.
    b : float
        Exponent.
    sensel_area_mm2 : float
        Sensel area in mm2 (5051: 1.27 x 1.27 = 1.6129); N / mm2 = MPa.

    Examples
    --------
    >>> round(saturation_pressure_MPa(0.00358, 1.164, 1.27 * 1.27), 3)  # Table 2, row 1: 1.403
    1.404
    """
    return a_N * 255.0 ** b / sensel_area_mm2
