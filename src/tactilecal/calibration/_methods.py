"""Static calibration methods, each fitted on 256-bin histograms of calibration frames.

Every fit takes ``hist`` (n, 256) int64 and ``load_N`` (n,) of the *used* points and
returns a :class:`Fit` (model name, parameters, standard errors, details). The cost of a
fit does not depend on the number of sensels: ``sum_k X_k**b = hist @ arange(256)**b``.
"""

import numpy as np
from scipy import optimize

from tactilecal._errors import TactilecalError
from tactilecal._powerfit import (
    B_BOUNDS,
    DEFAULT_OBJECTIVE,
    LEVELS,
    LOG_LEVELS,
    NO_STDERR,
    OBJECTIVES,
    Fit,
    _censored_median,
    _check_objective,
    check_unsaturated,
    fit_power,
    fit_power_censored,
)
from tactilecal._powerfit import objective_weights as _weights
from tactilecal.calibration._models import force_table
from tactilecal.calibration._points import take_rows

__all__ = ["Fit", "FITTERS", "EXACT_METHODS", "OBJECTIVES", "DEFAULT_OBJECTIVE",
           "fit_censored", "fit_power", "fit_power_censored", "check_unsaturated",
           "B_BOUNDS"]


def _check_ls_objective(objective, method):
    if objective not in ("l2", "relative"):
        raise TactilecalError(f"objective={objective!r} is not available for {method}; "
                              "expected 'l2' or 'relative'")



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
            raise TactilecalError(f"point={point!r} is invalid; expected an index into the "
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
        raise TactilecalError(f"power-2pt needs 2 usable points; found {len(load_N)}")
    if pair is None:
        top = load_N.max()
        i = int(np.argmin(np.abs(load_N - 0.2 * top)))
        j = int(np.argmin(np.abs(load_N - 0.8 * top)))
        if load_N[i] == load_N[j]:
            j = int(np.argmax(load_N))
        if load_N[i] == load_N[j]:
            raise TactilecalError("power-2pt needs two different loads; all usable points have "
                                  f"load_N = {load_N[i]:.6g}")
        return i, j
    i, j = (int(k) for k in pair)
    if not (0 <= i < len(load_N) and 0 <= j < len(load_N)) or i == j:
        raise TactilecalError(f"pair={pair!r} is invalid; expected two different indices "
                              f"into the {len(load_N)} usable points")
    return i, j



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
        raise TactilecalError(f"degree={degree!r}; expected an integer >= 1")
    powers = np.arange(1, int(degree) + 1)
    design = hist @ ((LEVELS / 255.0)[:, None] ** powers)
    w = _weights(load_N, objective)
    coef, *_ = np.linalg.lstsq(w[:, None] * design, w * load_N, rcond=None)
    return Fit("polynomial", {"coefficients": (coef / 255.0 ** powers).tolist()},
               {"coefficients": None}, {"objective": objective, "stderr_method": NO_STDERR})


PIECEWISE_SMOOTHING = 0.1
"""Default ``smoothing`` of ``piecewise`` (:func:`fit_piecewise`): on the simulated family
(20 sessions, 150 held-out patches) 0.1 and 1 both reached 0.96 of the true law's worst
share on 9500-b1.4 (0 reached 0.91, 0.01 0.93); 0.1 kept 1.59 on 4010N-noisy, 1 only 1.47."""


def penalty_weight(smoothing, load_N, objective):
    """Weight of a squared penalty so that it is ``smoothing * n`` times one median patch's loss.

    The loss of a patch missing its whole load is ``F`` (l1), ``F**2`` (l2) or 1 (relative);
    at the median load F this makes the penalty's units those of the objective's cost.
    """
    median_N = float(np.median(load_N))
    loss = {"l1": median_N, "l2": median_N ** 2, "relative": 1.0}[objective]
    return float(smoothing) * len(load_N) * loss


def _check_smoothing(smoothing):
    if not (np.isfinite(smoothing) and smoothing >= 0):
        raise TactilecalError(f"smoothing={smoothing!r}; expected a number >= 0")


def _piecewise_shape(knots, slopes):
    """Piecewise power law through 1 N at the first knot with exponents ``slopes``, raw 0..255.

    The same law as ``force_table("piecewise-power", ...)``, computed directly on the log
    levels (about 50x faster: the simplex search of the l1 fit evaluates it hundreds of times).
    """
    log_knots = np.log(knots)
    log_force = np.r_[0.0, np.cumsum(slopes * np.diff(log_knots))]
    log_raw = LOG_LEVELS[1:]
    value = np.interp(log_raw, log_knots, log_force)
    below = log_raw < log_knots[0]
    value[below] = slopes[0] * (log_raw[below] - log_knots[0])
    return np.r_[0.0, np.exp(value)]


def _piecewise_l1(hist, load_N, knots, start, weight):
    """l1 fit: the force at the first knot profiled (weighted median), slopes by Nelder-Mead.

    For fixed exponents the sum of absolute errors is minimised by the S-weighted median of
    F/S (as the power method's A); the exponents, kept in ``B_BOUNDS``, minimise that profiled
    cost plus ``weight * sum(diff(slopes)**2)`` (a cost without derivative everywhere, hence
    the simplex search).
    """
    none = np.zeros(len(load_N), dtype=bool)

    def scale_and_cost(slopes):
        slopes = np.clip(slopes, *B_BOUNDS)
        sums = hist @ _piecewise_shape(knots, slopes)
        scale = _censored_median(load_N / sums, sums, none)
        cost = np.sum(np.abs(scale * sums - load_N)) + weight * np.sum(np.diff(slopes) ** 2)
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


def fit_piecewise(hist, load_N, *, knots=(1, 16, 64, 255), objective=DEFAULT_OBJECTIVE,
                  smoothing=PIECEWISE_SMOOTHING, **_):
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
    Until issue 12's review the fit was unpenalised least squares (``relative``). On
    ``9500-b1.4`` (readings 3-240, half the force above raw 91) the range 1-16 carries
    almost no force and its exponent went to 210 or 0.21 in some sessions (sensels below 16
    read as no force, or as 4x theirs), and least squares on patches with heavy-tailed errors
    (12 % gains, few large sensels) lost to l1 as the power method does: its worst session
    reached 0.94 of the true law's.
    """
    _check_objective(objective, "piecewise")
    _check_smoothing(smoothing)
    knots = np.asarray(knots, dtype=float)
    if len(knots) < 2 or np.any(np.diff(knots) <= 0) or knots[0] <= 0:
        raise TactilecalError(f"knots={knots.tolist()} must increase and be > 0; expected e.g. "
                              "(1, 16, 64, 255)")
    start = fit_power(hist, load_N, objective=objective).params
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
               {"knots": None, "force_N": None},
               {"objective": objective, "smoothing": float(smoothing),
                "segments_A": A_r.tolist(), "segments_b": b_r.tolist(),
                "stderr_method": NO_STDERR})


LUT_SMOOTHING = 0.1
"""Default ``smoothing`` of ``lut``: the best worst case of 0.01, 0.1, 1 and 10 on the
simulated family (benchmarks/bench_static_family.py, 20 sessions, 150 held-out patches):
0.97 of the true law's worst share on 9500-b1.4 (0.91-0.96 for the others) and 1.66 on
4010N-noisy, where 1 and 10 pull the table onto the power law (1.51, 1.47)."""


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


def _irls_l1(solve, residual, load_N, n_iter=50, rtol=1e-4):
    """Minimise ``sum |residual|`` by iteratively reweighted least squares.

    ``solve(w)`` minimises ``sum (w r)**2`` (plus any penalty); weights ``1/sqrt(|r|)``
    (floored at 1e-6 of the mean load) make its cost ``sum |r|`` at the fixed point
    (Schlossmacher 1973).
    """
    w = np.ones_like(load_N)
    floor = 1e-6 * float(np.mean(load_N))
    for _ in range(n_iter):
        x = solve(w)
        w_new = 1.0 / np.sqrt(np.maximum(np.abs(residual(x)), floor))
        if np.allclose(w_new, w, rtol=rtol):
            break
        w = w_new
    return x


def fit_lut(hist, load_N, *, knots=None, objective="l1", smoothing=LUT_SMOOTHING, **_):
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
    Before issue 12's review the table was linear in raw, unpenalised and fitted by l2: on
    ``9500-b1.4`` (12 % gains, readings 3-240 with most force above 64) its increments at
    the lowest knots went to 0 (sensels below raw 8 carried no force) and the last segment,
    fitted on the few readings between 169 and the largest training reading, extrapolated
    up to 1.43x the true force at 240; its worst session reached 0.93 of the true law's.
    """
    _check_objective(objective, "lut")
    _check_smoothing(smoothing)
    if knots is None:
        knots = np.r_[0, np.unique(np.rint(np.geomspace(3, 255, 12)))]
    knots = np.asarray(knots, dtype=float)
    if knots[0] != 0 or knots[-1] < 255 or np.any(np.diff(knots) <= 0):
        raise TactilecalError(f"knots={knots.tolist()} must increase from 0 to 255; expected e.g. "
                              "[0, 3, 5, ..., 255]")
    shape = fit_power(hist, load_N, objective="l1").params
    design, cumulative = _lut_design(hist, knots, shape["b"])
    # squared rows: with IRLS's weights an l1 cost, so the l1 weight holds for the l1 fit too
    penalty = np.sqrt(penalty_weight(smoothing, load_N, objective)) \
        * _lut_penalty(knots, shape["b"], shape["A"])
    zeros = np.zeros(len(penalty))

    def solve(w):
        return optimize.nnls(np.r_[w[:, None] * design, penalty], np.r_[w * load_N, zeros])[0]

    if objective == "l1":
        increments = _irls_l1(solve, lambda x: design @ x - load_N, load_N)
    else:
        increments = solve(_weights(load_N, objective))
    force = np.r_[0.0, cumulative @ increments]
    return Fit("table", {"knots": knots.tolist(), "force_N": force.tolist(),
                         "exponent": shape["b"]},
               {"knots": None, "force_N": None, "exponent": None},
               {"objective": objective, "smoothing": float(smoothing),
                "stderr_method": NO_STDERR})


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


ACTIVE_TOLERANCE = 1e-4
"""A censored patch predicted within this fraction below its load counts as over-predicted
(in the cost) when the censored refits decide their set: the l1 fits of piecewise and lut
(a simplex search, reweighted least squares) hold such a patch at its load only to their
tolerance, and its sign then flipped from refit to refit (piecewise on 5051-saturating did
not settle in 50 refits)."""


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
        # an l1 fit passes through some patches: an active lower bound held at its load
        # (to the fit's tolerance) stays active instead of flipping out and back
        now = censored & (excess > -ACTIVE_TOLERANCE * load_N)
        if exact or np.array_equal(now, active):
            for key in ("pair", "point"):  # indices into the rows fitted -> into all rows
                if key in fit.details:
                    fit.details[key] = np.flatnonzero(rows)[fit.details[key]].tolist()
            fit.details.update(censored=int(censored.sum()), censored_active=int(now.sum()))
            return fit
        active = now
    raise TactilecalError(f"censored {method} fit: the set of over-predicted saturated patches "
                          "did not settle in 50 refits; expected 'drop' for this session")
