"""Does the law describe the patches? Lack of fit by load, by reading, and by acquisition order.

Dead weights give replicates: several patches carry the same load. If the law describes
the sensor, the mean relative residual of each load is zero up to the scatter of that
load's patches about their mean (pure error; the lack-of-fit idea of Draper & Smith 1998,
sec. 2.1). Each load's mean is tested against zero with a one-sample Student t test on its
own scatter, Bonferroni-corrected over the ``g`` loads, and only with more loads than the
law has parameters: light loads, read by few sensels, scatter more than heavy ones, so
one pooled scatter (the classical F test) would make their ordinary error look
systematic. A response that bends away from the law shows instead against the readings:
patches whose sensels read high err one way, those that read low the other, whatever
their load. So the relative residual is also regressed on the log of each patch's mean
reading and its square, and the two slopes tested together (an F test). Either test says
the law does not fit when it rejects at :data:`ALPHA` *and* the systematic error is at
least :data:`BIAS_PCT` percent: an error that matters, not one that many patches make
significant.

Whether a power law describes the sensor at all is tested on the points themselves, for a
power-law method and for ``method="auto"`` whatever it chose: the power law against the
same law with a log-log curvature term (:func:`power_law_curvature`). ``auto`` choosing a
flexible law is not that evidence alone: on simulated power-law sensors a flexible law
predicted held-out patches a little better in up to a sixth of the sessions.

The order in which the patches were taken (the manifest's) is checked too: a residual that
trends with it is a drifting sensor, and loads taken in ascending order cannot tell drift
from the shape of the law, whatever the residuals say.
"""

from dataclasses import asdict, dataclass, field

import numpy as np
from scipy import optimize

from tactilecal._validate import check_type, require_keys

__all__ = ["ALPHA", "BIAS_PCT", "LackOfFit", "lack_of_fit", "load_levels", "law_parameters",
           "power_law_curvature"]

ALPHA = 1e-4
"""Significance level of the lack-of-fit and order tests. On the family of simulated sensors
whose sensels follow a power law without a noise threshold, the smallest p-values of the
power law over 30 sessions each were 4e-3 (by load) and 8e-4 (by reading), where the
sensor whose response bends (5051-bent) reached 5e-5 and 3e-14."""

BIAS_PCT = 1.5
"""Smallest systematic error (in percent) that counts as a lack of fit: the largest mean
residual of a load, or the range of the fitted trend over the patches' readings."""

DRIFT_PCT = 2.0
"""Smallest change of the residual over the run (in percent) that counts as a drift."""

MAX_POINTS = 2000
"""Points of the curvature test beyond which they are thinned evenly."""

ORDERED_RHO = 0.8
"""Spearman correlation of load with acquisition order from which a run counts as
ascending (or descending)."""


@dataclass(frozen=True)
class LackOfFit:
    """The checks of a calibration law against its own patches.

    Attributes
    ----------
    flagged : bool
        True when the law does not describe the patches, or the acquisition order makes
        it unknowable; ``messages`` say which.
    messages : list of str
        One sentence per finding (empty when nothing was found).
    loads_N : list of float
        Mean load of each load level with at least two patches.
    bias_pct : list of float
        Mean relative residual ``100 (predicted / load - 1)`` of each of those levels.
    p_value : float or None
        That some load's mean residual is not zero (Bonferroni over the loads; None with
        fewer than ``parameters + 1`` replicated loads).
    curvature_p_value : float or None
        That a power law describes the points, against one with log-log curvature
        (:func:`power_law_curvature`; None when not tested).
    curvature_change_pct : float or None
        Largest change of a patch's predicted load the curvature makes, percent.
    reading_trend_pct : float or None
        Range of the residual's quadratic trend over the log of the patches' mean readings.
    reading_p_value : float or None
        Of that trend's F test.
    order_drift_pct : float or None
        Change of the relative residual from the first to the last patch, from a straight
        line over the acquisition order (within each load level, so the law's own shape
        does not count).
    order_p_value : float or None
    load_order_rho : float or None
        Spearman correlation of the loads with their acquisition order.
    better : str or None
        A method that predicted held-out patches better than the law's (``method="auto"``).
    """

    flagged: bool
    messages: list = field(default_factory=list)
    loads_N: list = field(default_factory=list)
    bias_pct: list = field(default_factory=list)
    p_value: float | None = None
    curvature_p_value: float | None = None
    curvature_change_pct: float | None = None
    reading_trend_pct: float | None = None
    reading_p_value: float | None = None
    order_drift_pct: float | None = None
    order_p_value: float | None = None
    load_order_rho: float | None = None
    better: str | None = None

    def to_dict(self):
        """Return the JSON-ready dictionary."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data, where):
        """Rebuild from :meth:`to_dict` output (``where`` names it in errors)."""
        require_keys(data, ("flagged", "messages"), where, expected="a lack-of-fit record")
        check_type(data["flagged"], bool, f"{where}, flagged", expected="true or false")
        check_type(data["messages"], list, f"{where}, messages", expected="a list of texts")
        known = {k: data[k] for k in cls.__dataclass_fields__ if k in data}
        return cls(**known)


def law_parameters(method, model, params):
    """Return the number of parameters a method fitted (the ``p`` of the F test).

    Examples
    --------
    >>> law_parameters("linear", "power", {"A": 0.1, "b": 1.0})
    1
    >>> law_parameters("lut", "table", {"knots": [0, 3, 255], "force_N": [0, 1, 9]})
    2
    """
    if method == "linear":  # b is fixed at 1
        return 1
    if model == "polynomial":
        return len(params["coefficients"])
    if model == "piecewise-power":
        return len(params["force_N"])
    if model == "table":  # f(0) = 0 is not fitted
        return len(params["force_N"]) - 1
    return 2


def load_levels(load_N, tolerance=0.02):
    """Group loads that differ by less than ``tolerance`` (relative) into levels.

    Returns the level of each point (0, 1, ... by increasing load).

    Examples
    --------
    >>> load_levels([19.62, 49.1, 19.64, 98.1, 49.05]).tolist()
    [0, 1, 0, 2, 1]
    """
    load = np.asarray(load_N, dtype=float)
    order = np.argsort(load, kind="stable")
    step = np.r_[False, load[order][1:] > load[order][:-1] * (1 + tolerance)]
    level = np.empty(len(load), dtype=int)
    level[order] = np.cumsum(step)
    return level


def lack_of_fit(load_N, predicted_N, mean_raw, *, n_parameters, selection=None, hist=None):
    """Check a law's predictions of its own (exact, used) patches, in acquisition order.

    Parameters
    ----------
    load_N, predicted_N : array_like
        Applied and predicted loads of the points the fit used whose load is exact, in the
        order they were taken.
    mean_raw : array_like
        Mean reading of each point's loaded sensels (``raw_sum / loaded_cells``).
    n_parameters : int
        Parameters of the law (2 for a power law).
    selection : tactilecal.calibration.methods.auto.Selection, optional
        How ``method="auto"`` chose the law: a better candidate is named in the advice.
    hist : array_like, optional
        The points' histograms (n, 256): when given, whether a power law describes them
        is tested too (:func:`power_law_curvature`), for a power law or ``auto``'s choice.

    Returns
    -------
    LackOfFit

    Examples
    --------
    >>> load = np.tile([10.0, 20.0, 40.0, 80.0], 6)  # four weights, in turn
    >>> wobble = np.repeat([-0.002, 0.002, 0.0, 0.001, -0.001, 0.0], 4)
    >>> raw = 2.0 * load ** 0.8 * (1 + np.repeat([-0.1, 0.1, 0.0, 0.05, -0.05, 0.0], 4))
    >>> lack_of_fit(load, load * (1 + wobble), raw, n_parameters=2).flagged
    False
    >>> bent = load * (1 + wobble + np.tile([0.05, -0.03, -0.03, 0.05], 6))
    >>> lack_of_fit(load, bent, raw, n_parameters=2).messages[0][:42]
    'the law misses loads systematically (by +5'
    """
    load = np.asarray(load_N, dtype=float)
    residual = 100.0 * (np.asarray(predicted_N, dtype=float) / load - 1.0)
    level = load_levels(load)
    counts = np.bincount(level)
    replicated = counts[level] >= 2
    means = np.bincount(level, weights=residual) / np.maximum(counts, 1)
    keep = counts >= 2
    found = {"loads_N": (np.bincount(level, weights=load) / np.maximum(counts, 1))[keep]
             .tolist(), "bias_pct": means[keep].tolist()}
    better = _better(selection)
    advice = (f"; {better} predicted held-out patches better" if better else
              "; a flexible method (lut, piecewise, method='auto') may follow the response")
    messages = []
    curvature = power_law_curvature(hist, load) if hist is not None else None
    if curvature is not None and curvature["p_value"] < ALPHA \
            and curvature["change_pct"] >= BIAS_PCT:
        messages.append(_curvature_message(curvature, selection, advice))
    p_value = _lof_p_value(residual[replicated], level[replicated], n_parameters)
    if p_value is not None and p_value < ALPHA and np.abs(means[keep]).max() >= BIAS_PCT:
        worst = int(np.flatnonzero(keep)[np.argmax(np.abs(means[keep]))])
        messages.append(
            f"the law misses loads systematically (by {means[worst]:+.1f} % at "
            f"{found['loads_N'][int(np.sum(keep[:worst]))]:.4g} N, lack-of-fit test "
            f"p = {p_value:.1g}){advice}")
    trend, trend_p = _reading_trend(residual, mean_raw)
    if trend_p is not None and trend_p < ALPHA and trend >= BIAS_PCT:
        messages.append(f"the errors follow the readings (a {trend:.1f} % trend over the "
                        f"patches' mean readings, p = {trend_p:.1g}): the response bends "
                        f"away from the law{advice}")
    rho, drift, order_p = _order_checks(load, residual, level, means)
    if rho is not None and abs(rho) >= ORDERED_RHO:
        messages.append(f"the loads were taken in {'as' if rho > 0 else 'des'}cending order "
                        f"(rank correlation {rho:.2f}): drift of the sensor cannot be told "
                        "from the shape of the law; take the patches in random order")
    elif order_p is not None and order_p < ALPHA and abs(drift) >= DRIFT_PCT:
        messages.append(f"the residuals drift by {drift:+.1f} % over the run (p = "
                        f"{order_p:.1g}): a drifting sensor; take the patches in random order "
                        "and let the sensor settle")
    return LackOfFit(flagged=bool(messages), messages=messages, p_value=p_value,
                     curvature_p_value=None if curvature is None else curvature["p_value"],
                     curvature_change_pct=(None if curvature is None
                                           else curvature["change_pct"]),
                     reading_trend_pct=trend, reading_p_value=trend_p,
                     order_drift_pct=drift, order_p_value=order_p, load_order_rho=rho,
                     better=better, **found)


def _better(selection):
    """Return the candidate with the smallest held-out error, when it is not the chosen one."""
    best = None if selection is None else selection.best()
    return best["candidate"] if best and best["candidate"] != selection.chosen else None


def _curvature_message(curvature, selection, advice):
    """Say that no power law describes the points, and what was chosen instead."""
    finding = (f"a log-log curvature term changes the predictions by up to "
               f"{curvature['change_pct']:.1f} % (p = {curvature['p_value']:.1g})")
    chosen = None if selection is None else selection.chosen
    if chosen is None or chosen.startswith("power"):
        kept = (f"; auto kept {chosen}: on held-out patches no flexible law was better by "
                f"more than {selection.margin_se:g} standard error(s)") if chosen else advice
        return f"the response bends away from a power law ({finding}){kept}"
    rms = {s["candidate"]: s["rms_rel"] for s in selection.scores}
    power = selection.best_power()
    versus = f", the best power law ({power}) {100 * rms[power]:.2f} %" if power else ""
    return (f"no power law describes this sensor ({finding}); {chosen} was chosen: held-out "
            f"RMS error {100 * rms[chosen]:.2f} %{versus}")


def power_law_curvature(hist, load_N):
    """Test a power law against one with log-log curvature on the same points.

    The nested alternative is ``f(r) = A r**b exp(c (ln r - m)**2)`` (``m`` the mean log
    reading), fitted with the power law (``c = 0``) by weighted least squares of the
    relative residual ``sum_r h(r) f(r) / F - 1``; the weights are the inverse scatter of
    each load's patches (pure error, so light loads read by few sensels weigh less). The
    F test of ``c = 0`` has 1 and ``n - 3`` degrees of freedom.

    More than :data:`MAX_POINTS` points (a movie's frames) are thinned evenly; neighbouring
    frames are not independent, so there the p-value is too small and the change in
    percent decides.

    Returns a dict ``p_value``, ``change_pct`` (largest change of a patch's predicted load
    between the two laws, percent) and ``curvature`` (``c``), or None with fewer than 6
    points or fits that fail.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> levels = np.repeat(np.geomspace(5, 200, 6), 5)  # 30 patches, 40 sensels each
    >>> readings = np.clip(rng.normal(levels[:, None], 0.1 * levels[:, None], (30, 40)), 1, 254)
    >>> hist = np.stack([np.bincount(row.astype(int), minlength=256) for row in readings])
    >>> r = np.maximum(np.arange(256.0), 1)
    >>> noise = 1 + rng.normal(0, 0.01, 30)
    >>> power_law_curvature(hist, hist @ (0.003 * r ** 1.2) * noise)["p_value"] > 1e-4
    True
    >>> bent = 0.003 * r ** 1.2 * np.exp(0.05 * np.log(r / 30) ** 2)
    >>> power_law_curvature(hist, hist @ bent * noise)["p_value"] < 1e-4
    True
    """
    from scipy import stats  # imported when used: it slows every import

    load = np.asarray(load_N, dtype=float)
    rows = np.linspace(0, len(load) - 1, min(len(load), MAX_POINTS)).astype(int)
    hist, load = np.asarray(hist[rows], dtype=float)[:, 1:], load[rows]
    n = len(load)
    counts = hist.sum(axis=0)
    if n < 6 or counts.sum() == 0:
        return None
    log_r = np.log(np.arange(1.0, 256.0))
    z = log_r - counts @ log_r / counts.sum()

    def residuals(p, weight):
        shape = p[1] * z + (p[2] * z * z if len(p) > 2 else 0.0)
        return weight * (hist @ np.exp(p[0] + shape) / load - 1.0)

    start = [np.log(np.median(load / np.maximum(hist @ np.exp(z), 1e-300))), 1.0]
    null = optimize.least_squares(residuals, start, args=(1.0,), method="lm")
    weight = 1.0 / np.sqrt(_level_variance(null.fun, load_levels(load)))
    null = optimize.least_squares(residuals, null.x, args=(weight,), method="lm")
    curved = optimize.least_squares(residuals, [*null.x, 0.0], args=(weight,), method="lm")
    rss0, rss1 = 2 * null.cost, 2 * curved.cost
    if not (null.success and curved.success and np.isfinite(rss1)) or rss1 <= 0:
        return None
    f = (rss0 - rss1) / (rss1 / (n - 3))
    change = (curved.fun / weight + 1.0) / (null.fun / weight + 1.0) - 1.0
    return {"p_value": float(stats.f.sf(max(f, 0.0), 1, n - 3)),
            "change_pct": float(100 * np.max(np.abs(change))),
            "curvature": float(curved.x[2])}


def _level_variance(residual, level):
    """Scatter of each point's load level about its mean (pooled for levels of < 3)."""
    counts = np.bincount(level)
    means = np.bincount(level, weights=residual) / counts
    ss = np.bincount(level, weights=(residual - means[level]) ** 2)
    pooled = ss.sum() / (len(residual) - len(counts)) if len(residual) > len(counts) \
        else float(np.var(residual))
    variance = np.where(counts >= 3, ss / np.maximum(counts - 1, 1), pooled)
    floor = max(pooled, float(np.var(residual)), 1e-30) * 1e-6
    return np.maximum(variance, floor)[level]


def _reading_trend(residual, mean_raw):
    """Range (percent) and p-value of the residual's quadratic trend over log mean reading."""
    from scipy import stats  # imported when used: it slows every import

    z = np.log(np.asarray(mean_raw, dtype=float))
    if len(z) < 8 or not np.all(np.isfinite(z)) or np.ptp(z) == 0:
        return None, None
    z = (z - z.mean()) / z.std()
    design = np.column_stack([np.ones_like(z), z, z * z])
    coef, *_ = np.linalg.lstsq(design, residual, rcond=None)
    fitted = design @ coef
    rss1 = float(np.sum((residual - fitted) ** 2))
    rss0 = float(np.sum((residual - residual.mean()) ** 2))
    n = len(z)
    if rss1 <= 0:
        return float(np.ptp(fitted)), 0.0 if rss0 > 0 else 1.0
    f = ((rss0 - rss1) / 2) / (rss1 / (n - 3))
    return float(np.ptp(fitted)), float(stats.f.sf(f, 2, n - 3))


def _lof_p_value(residual, level, n_parameters):
    """P-value that some load's mean relative residual is not zero (Bonferroni over loads).

    Each load's mean is tested against zero with its own scatter (Student's t), so a load
    whose patches scatter more (small contacts at light loads) is judged by its scatter,
    not by the pooled one of the heavier loads.
    """
    names, level = np.unique(level, return_inverse=True)
    g, n = len(names), len(residual)
    if g <= n_parameters or n <= g:
        return None
    p_values = [_mean_is_zero_p(residual[level == k]) for k in range(g)]
    return float(min(1.0, g * min(p_values)))


def _mean_is_zero_p(values):
    """Two-sided p-value of Student's one-sample t test that the mean is zero."""
    from scipy import stats  # imported when used: it slows every import

    mean, sd = float(np.mean(values)), float(np.std(values, ddof=1))
    if sd == 0:
        return 0.0 if mean != 0 else 1.0
    t = mean / (sd / np.sqrt(len(values)))
    return float(2 * stats.t.sf(abs(t), len(values) - 1))


def _order_checks(load, residual, level, means):
    """Spearman rho of load with order; drift of the within-level residual over the run."""
    from scipy import stats  # imported when used: it slows every import

    n = len(load)
    if n < 6 or np.ptp(load) == 0:
        return None, None, None
    order = np.arange(n, dtype=float)
    rho = float(stats.spearmanr(order, load).statistic)
    within = residual - means[level]
    if np.ptp(within) == 0:
        return rho, 0.0, 1.0
    fit = stats.linregress(order, within)
    return rho, float(fit.slope * (n - 1)), float(fit.pvalue)
