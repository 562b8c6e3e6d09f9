"""The power law f = A * raw**b fitted to whole frames.

``fit_power`` (uncensored patches) and ``fit_power_censored`` (patches with a sensel at 255
as lower bounds) are the ``power`` method (:mod:`tactilecal.calibration.methods.power`), the
free final step of Zvyagin's robust mode and the starting law of ``piecewise`` and ``lut``.
Every fit takes ``hist`` (n, 256) and ``load_N`` (n,) of the *used* points and returns a
:class:`tactilecal.calibration._fit.Fit`; its cost does not depend on the number of sensels:
``sum_k X_k**b = hist @ arange(256)**b`` (Zvyagin 2022, eq. 2).
"""

import dataclasses
import functools
import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from scipy import optimize

from tactilecal._errors import TactilecalError
from tactilecal._numba import read_only
from tactilecal.calibration._fit import Fit

__all__ = ["OBJECTIVES", "DEFAULT_OBJECTIVE", "B_BOUNDS", "LEVELS", "COMPILED_MIN_POINTS",
           "objective_weights", "fit_power", "fit_power_of", "fit_power_censored",
           "check_unsaturated", "hist_products"]

#: Raw levels 0..255 as floats (the columns of a frame histogram).
LEVELS = np.arange(256, dtype=float)
OBJECTIVES = ("l2", "l1", "relative")
DEFAULT_OBJECTIVE = "l1"
"""The power method's default: on the simulated family (``benchmarks/bench_static.py
--seeds 20 --test-patches 150``) l1 had the best worst case of the three objectives;
relative and l2 fell to 0.90-0.91 of the true law's worst share on 9500-b1.4."""
B_BOUNDS = (0.2, 4.0)
with np.errstate(divide="ignore"):
    LOG_LEVELS = np.where(LEVELS > 0, np.log(LEVELS), 0.0)


# ---------------------------------------------------------------------- helpers
def _check_objective(objective, method=None):
    """Refuse an objective not in :data:`OBJECTIVES`, naming ``method`` when given."""
    if objective not in OBJECTIVES:
        what = "is unknown" if method is None else f"is not available for {method}"
        raise TactilecalError(f"objective={objective!r} {what}; expected one of {OBJECTIVES}")


def objective_weights(load_N, objective):
    """Residual weights: 1 for l2/l1, 1/F for ``relative`` (residuals as fractions)."""
    return 1.0 / load_N if objective == "relative" else np.ones_like(load_N)


#: Rows per thread of :func:`hist_products` (fewer, and a thread's start-up outweighs its
#: share: ``benchmarks/bench_movie.py``).
PRODUCT_ROWS_PER_THREAD = 4096
#: Count types :func:`hist_products` passes to the kernel as they are: a movie's uint16 and
#: float64. numba would compile the product kernels again for every other type, in every
#: new process, so other counts are widened to float64 this many rows at a time (exact
#: below 2**53; 8 MiB per block).
KERNEL_COUNT_TYPES = (np.uint16, np.float64)
WIDEN_ROWS = 4096


def hist_products(hist, matrix):
    """Return ``(hist @ matrix).T``, (c, n), for histograms of counts in any dtype.

    From :data:`COMPILED_MIN_POINTS` rows the numba kernel
    :func:`._powerfit_kernels.hist_dot` reads the counts as they are (a movie's
    uint16 histograms, with no float64 copy; counts of other types are widened to float64
    :data:`WIDEN_ROWS` rows at a time): up to four columns every bin in vector
    registers, in one thread (faster than a pool of two for a movie's 90,821 rows); for
    more, skipping empty bins, on one block of rows per core (of at least
    :data:`PRODUCT_ROWS_PER_THREAD` rows) in threads; below, NumPy's product.

    Parameters
    ----------
    hist : numpy.ndarray, shape (n, 256)
        Frame histograms (counts).
    matrix : numpy.ndarray, shape (256,) or (256, c)
        Functions of the raw level 0..255.

    Returns
    -------
    numpy.ndarray, shape (c, n)
        Equal to the dense product to round-off (the terms are added in another order).
    """
    matrix = np.asarray(matrix, dtype=float)
    if len(hist) < COMPILED_MIN_POINTS:
        product = np.asarray(hist, dtype=float) @ matrix
        return product[None] if matrix.ndim == 1 else np.ascontiguousarray(product.T)
    matrix = read_only(np.ascontiguousarray(matrix[:, None] if matrix.ndim == 1 else matrix))
    from tactilecal.calibration._powerfit_kernels import DENSE_MAX_COLUMNS, hist_dot

    hist, out = np.ascontiguousarray(hist), np.empty((matrix.shape[1], len(hist)))
    threads = max(1, min(os.cpu_count() or 1, len(hist) // PRODUCT_ROWS_PER_THREAD))
    if matrix.shape[1] <= DENSE_MAX_COLUMNS:  # a few ms of SIMD work: no thread pool
        threads = 1
    bounds = np.linspace(0, len(hist), threads + 1).astype(int)
    direct = hist.dtype in KERNEL_COUNT_TYPES

    def product(a, b):
        if direct:
            return hist_dot(read_only(hist[a:b]), matrix, out, a)
        for c in range(a, b, WIDEN_ROWS):
            d = min(c + WIDEN_ROWS, b)
            hist_dot(read_only(hist[c:d].astype(np.float64)), matrix, out, c)
        return out

    with ThreadPoolExecutor(max_workers=threads) as pool:  # the kernel releases the GIL
        for _ in pool.map(product, bounds[:-1], bounds[1:]):
            pass
    return out


def _power_sums(hist, b):
    """S_T(b) = sum_k X_k**b for each frame (Zvyagin 2022, eq. 2) as hist @ levels**b."""
    return hist @ (LEVELS ** b)


def _censored_median(ratio, weight, censored):
    """Minimiser of ``sum_unc w |A - r| + sum_cens w max(0, A - r)`` over A.

    Without censored terms this is the w-weighted median of r. The cost is convex and
    piecewise linear; its slope just above the k-th smallest r is
    ``2 W_unc(<= r_k) + W_cens(<= r_k) - W_unc(all)``, and the minimum is the first r_k
    where that slope is >= 0 (:func:`_median_slopes`). One set of points (1-D arrays): the
    cost of the simplex search of ``piecewise``, evaluated hundreds of times per fit.
    """
    order = ratio.argsort(kind="stable")
    slope = _median_slopes(weight[order], censored[order] if censored.any() else None)
    return float(ratio[order[(slope >= 0).argmax()]])


def _censored_medians(ratio, weight, censored):
    """:func:`_censored_median` of every row of ``ratio`` and ``weight``, shape (sets, points)."""
    order = np.argsort(ratio, axis=1, kind="stable")
    flat = (order + ratio.shape[1] * np.arange(len(ratio))[:, None]).ravel()
    w = weight.ravel()[flat].reshape(order.shape)
    slope = _median_slopes(w, censored[order] if censored.any() else None)
    return ratio.ravel()[flat].reshape(order.shape)[np.arange(len(ratio)),
                                                    np.argmax(slope >= 0, axis=1)]


def _median_slopes(w, c):
    """Slopes ``2 W_unc(<= r_k) + W_cens(<= r_k) - W_unc(all)`` along the last axis.

    ``w``: the weights in increasing order of their ratios; ``c``: their censored flags in
    that order, or None when no point is censored.
    """
    if c is None:
        return 2.0 * w.cumsum(axis=-1) - np.add.reduce(w, axis=-1, keepdims=True)
    uncensored = np.where(c, 0.0, w)
    return 2.0 * np.cumsum(uncensored, axis=-1) + np.cumsum(np.where(c, w, 0.0), axis=-1) \
        - uncensored.sum(axis=-1, keepdims=True)


def _costs_numpy(sums, load_N, objective, censored=None, window=None):
    """Profiled cost and best A of (m, n) ``sums``, one row per exponent (NumPy only).

    l1: A is the S-weighted median of F/S (``sum |A S - F| = sum S |A - F/S|``), censored
    patches adding ``S max(0, A - F/S)`` (:func:`_censored_medians`); l2/relative: the
    closed form. ``window`` (the compiled medians' hint) is not used.
    """
    if objective == "l1":  # weights of 1 (objective_weights)
        flags = np.zeros(len(load_N), bool) if censored is None else censored
        A = _censored_medians(load_N / sums, sums, flags)
        r = A[:, None] * sums - load_N
        if censored is not None:
            r = np.where(censored, np.maximum(r, 0.0), r)
        return np.abs(r).sum(axis=1), A
    w = objective_weights(load_N, objective)
    w2s = w ** 2 * sums
    A = (w2s * load_N).sum(axis=1) / (w2s * sums).sum(axis=1)
    r = w * (A[:, None] * sums - load_N)
    return (r * r).sum(axis=1), A


def _profiled_slope(S, dS, load_N, w2):
    """Return d cost / d b of the profiled l2/relative cost ``<F,F> - <S,F>**2 / <S,S>``.

    ``<x, y> = sum w**2 x y``, with ``S = S_T(b)`` and ``dS = dS_T/db`` at one exponent.
    """
    p, q = np.sum(w2 * S * load_N), np.sum(w2 * S * S)
    dp, dq = np.sum(w2 * dS * load_N), 2.0 * np.sum(w2 * dS * S)
    return -(2.0 * p * dp * q - p * p * dq) / (q * q)


def _minimise_b(hist, load_N, objective, b_bounds, n_grid=13, xtol=1e-10, censored=None):
    """Minimise the profiled cost over b.

    A grid of ``n_grid`` exponents (one matrix product) brackets the minimum; for l2 and
    relative the zero of the cost's derivative in that bracket is found by
    :func:`scipy.optimize.brentq`; for l1, whose cost has no derivative everywhere, the
    bracket is refined by nested grids (:func:`_nested_grids`, in NumPy). ``censored``:
    patches that are lower bounds (l1 only). From :data:`COMPILED_MIN_POINTS` points on,
    :func:`_minimise_b_many` minimises the same cost to the same ``xtol`` with one pass
    over all the histograms (a bracket from a subsample, then Brent's method). Returns
    ``(b, A, cost, n_evaluations)``.
    """
    if len(load_N) >= COMPILED_MIN_POINTS:
        return _minimise_b_many(hist, load_N, objective, b_bounds, n_grid, xtol, censored)
    return _nested_grids(hist, load_N, objective, b_bounds, n_grid, xtol, censored, False)


def _best(cost):
    """Index of the smallest cost, NaN costs left out: :func:`numpy.nanargmin`, faster."""
    k = int(np.argmin(cost))
    return int(np.nanargmin(cost)) if np.isnan(cost[k]) else k


def _check_interior(k, grid, b_bounds):
    if k in (0, len(grid) - 1):
        raise TactilecalError(f"power fit: best exponent b = {grid[k]:.3f} is at the edge of "
                              f"b_bounds {tuple(b_bounds)}; expected an interior optimum "
                              "(check the loads)")


# ------------------------------------------------------- many points (movie calibration)
#: Points from which :func:`_minimise_b` reads the histograms only twice and finds the
#: l1 medians by selection (:mod:`._powerfit_kernels`, numba) instead of sorting.
#: Below it numba's start-up in a new process would cost more than it saves.
COMPILED_MIN_POINTS = 4096
#: Points of the subsample on which :func:`_minimise_b_many` brackets the minimum.
BRACKET_POINTS = 4096
#: Half width in b of the bracket around the subsample's minimum searched on all the points:
#: hundreds of times the spread of b between subsamples (1e-5 between a 4,542-frame and the
#: 90,821-frame fit of ``benchmarks/bench_movie.py``), and a Chebyshev series of 10 terms.
BRACKET_HALF_WIDTH = 0.02


@functools.lru_cache(maxsize=64)
def _chebyshev_basis(lo, hi, rel_error=1e-18):
    """Chebyshev coefficients of ``LEVELS**b`` over ``lo <= b <= hi`` (read-only, remembered).

    ``k**b = exp(b ln k)`` is entire in b, so its interpolant at J Chebyshev nodes has
    coefficients falling like ``(x / 2)**j / j!`` with ``x = (hi - lo) / 2 * ln 255``
    (Trefethen, *Approximation Theory and Approximation Practice*, 2013, ch. 8); J is
    chosen so that the first one left out, relative to the smallest value ``k**lo``, is
    below ``rel_error``. Returns ``(coef (256, J), mid, half)``: for
    ``t = (b - mid) / half``, ``LEVELS**b = coef @ T(t)`` (:func:`_chebyshev_t`). The
    brackets of small fits are those of one grid over ``B_BOUNDS``, so each is computed
    once per process.
    """
    mid, half = (hi + lo) / 2.0, (hi - lo) / 2.0
    x = half * LOG_LEVELS[-1]
    n_terms, term = 1, 1.0
    while term * np.exp(x) >= rel_error:
        term *= (x / 2.0) / n_terms
        n_terms += 1
    n_terms = max(n_terms, 4)
    theta = np.pi * (np.arange(n_terms) + 0.5) / n_terms
    values = LEVELS[:, None] ** (mid + half * np.cos(theta))[None, :]
    coef = values @ np.cos(np.outer(np.arange(n_terms), theta)).T * (2.0 / n_terms)
    coef[:, 0] /= 2.0
    coef.flags.writeable = False
    return coef, mid, half


def _chebyshev_t(t, n_terms):
    """``T_j(t)`` and ``T_j'(t)`` for j < n_terms: two (n_terms, len(t)) arrays.

    One ``t`` (each trial exponent of a Brent search) takes the recurrence in Python
    floats (:func:`_chebyshev_t_one`): the same operations in the same order, without the
    cost of numpy calls on one-element arrays.
    """
    t = np.atleast_1d(np.asarray(t, dtype=float))
    if t.size == 1:
        return _chebyshev_t_one(float(t[0]), n_terms)
    T, dT = np.zeros((n_terms, t.size)), np.zeros((n_terms, t.size))
    T[0], T[1], dT[1] = 1.0, t, 1.0
    for j in range(1, n_terms - 1):
        T[j + 1] = 2.0 * t * T[j] - T[j - 1]
        dT[j + 1] = 2.0 * T[j] + 2.0 * t * dT[j] - dT[j - 1]
    return T, dT


def _chebyshev_t_one(t, n_terms):
    """:func:`_chebyshev_t` of one ``t`` (at least 2 terms): two (n_terms, 1) arrays."""
    T, dT = [1.0, t], [0.0, 1.0]
    for j in range(1, n_terms - 1):
        T.append(2.0 * t * T[j] - T[j - 1])
        dT.append(2.0 * T[j] + 2.0 * t * dT[j] - dT[j - 1])
    return np.array(T[:n_terms])[:, None], np.array(dT[:n_terms])[:, None]


class _Sums:
    """``S_T(b)`` (Zvyagin 2022, eq. 2) for exponents in a bracket, from one product.

    ``hist @ coef`` of :func:`_chebyshev_basis` reads the histograms once; every later
    ``S_T(b) = hist @ LEVELS**b`` in the bracket is then a product with ``T(t(b))``, of
    about 20 rather than 256 terms, equal to the direct sum to round-off. ``compiled``:
    the moments by :func:`hist_products` and the sums by the numba kernel ``series_sums``;
    else NumPy alone (below :data:`COMPILED_MIN_POINTS` points), the moments by ``einsum``'s
    own loop, not BLAS: a product this size (150 x 256 x 18) goes to OpenBLAS's threads,
    which wait for each other on busy shared cores.
    """

    def __init__(self, hist, lo, hi, compiled=True):
        coef, self.mid, self.half = _chebyshev_basis(lo, hi)
        self.compiled = compiled
        self.moments = (hist_products(hist, coef) if compiled
                        else np.einsum("pk,kj->jp", hist, coef))  # (J, n)

    def __call__(self, b_values, slope=False):
        """(m, n) sums at ``b_values`` (and their derivatives in b if ``slope``)."""
        t = (np.asarray(b_values, dtype=float) - self.mid) / self.half
        n_terms = self.moments.shape[0]
        if not (self.compiled or slope):  # T_j(t) = cos(j arccos t): a grid in 3 NumPy calls
            return np.cos(np.outer(np.arccos(np.clip(t, -1, 1)), np.arange(n_terms))) \
                @ self.moments
        T, dT = _chebyshev_t(t, n_terms)
        if self.compiled:
            from tactilecal.calibration._powerfit_kernels import series_sums

            sums, d_sums = series_sums(self.moments, T), series_sums(self.moments, dT)
        else:
            sums, d_sums = T.T @ self.moments, dT.T @ self.moments
        return (sums, d_sums / self.half) if slope else sums


def _costs_many(sums, load_N, objective, censored, window=None):
    """:func:`_costs_numpy` with the l1 medians selected by :func:`l1_costs` (numba).

    ``window``: (lo, hi) arrays where each exponent's median is expected, default anywhere.
    """
    if objective == "l1":
        from tactilecal.calibration._powerfit_kernels import l1_costs

        flags = np.zeros(len(load_N), bool) if censored is None else censored
        if window is None:
            window = np.full(len(sums), -np.inf), np.full(len(sums), np.inf)
        # contiguous, as the kernel was compiled for (a strided load would compile again)
        return l1_costs(np.ascontiguousarray(sums, dtype=float),
                        np.ascontiguousarray(load_N, dtype=float),
                        np.ascontiguousarray(flags, dtype=bool),
                        *(np.ascontiguousarray(w, dtype=float) for w in window))
    return _costs_numpy(sums, load_N, objective)


def _median_window(b_values, grid, A):
    """Where the l1 medians at ``b_values`` are expected, from A at the exponents ``grid``.

    A is interpolated (it changes smoothly with b); each window's half width is a twentieth
    of A's change over the step of ``grid`` around it, so that few ratios fall in it. A
    window is a hint: one that misses costs time, never the result (:func:`l1_costs`).
    """
    b_values, grid, A = (np.asarray(v, dtype=float) for v in (b_values, grid, A))
    guess = np.interp(b_values, grid, A)
    i = np.clip(np.searchsorted(grid, b_values), 1, len(grid) - 1)
    half = 0.05 * np.abs(A[i] - A[i - 1]) + 1e-13 * np.abs(guess)
    return guess - half, guess + half


def _direct_sums(hist, b_values):
    """(m, n) ``S_T(b) = hist @ LEVELS**b`` for m exponents (one product)."""
    return hist_products(hist, LEVELS[:, None] ** np.asarray(b_values, dtype=float)[None, :])


def _minimise_b_many(hist, load_N, objective, b_bounds, n_grid, xtol, censored):
    """:func:`_minimise_b` for many points: one product over all the histograms.

    The same profiled cost, minimised to the same ``xtol`` in b, but searched differently:

    1. the grid of ``n_grid`` exponents over ``b_bounds`` and a search of its bracket run on
       every ``step``-th point only (at most :data:`BRACKET_POINTS` of them), giving ``b_s``;
    2. Chebyshev moments of all the points (:class:`_Sums`) over ``b_s +- BRACKET_HALF_WIDTH``
       (about 10 terms, one product over the histograms);
    3. that bracket is accepted only if the full cost at ``b_s`` is below the cost at both
       ends (l1), or the full cost's slope changes sign in it (l2, relative); then
       :func:`scipy.optimize.brent` (l1) or :func:`scipy.optimize.brentq` on the slope
       (l2, relative) finds b to ``xtol`` on all the points. Otherwise the search falls back
       to the grid's bracket on all the points, and if that does not hold either, to the
       whole grid on all the points (:func:`_minimise_b_grid`).

    l1 medians are selected, not sorted (:mod:`tactilecal.calibration._powerfit_kernels`). Returns
    ``(b, A, cost, n_evaluations)``; the evaluations include those on the subsample.
    Agrees with the nested grids of :func:`_minimise_b` to ~1e-9 (``tests/test_powerfit_many.py``).
    """
    step = max(1, len(load_N) // BRACKET_POINTS)
    flags = None if censored is None else censored[::step]
    grid = np.linspace(*(float(v) for v in b_bounds), n_grid)
    cost, A = _costs_many(_direct_sums(hist[::step], grid), load_N[::step], objective, flags)
    k = _best(cost)
    if k in (0, n_grid - 1):  # the edge on the subsample: decide on all the points
        return _minimise_b_grid(hist, load_N, objective, b_bounds, n_grid, xtol, censored)
    n_eval = n_grid
    wide = (grid[k - 1], grid[k + 1])
    if step > 1:
        sub = _Search(_Sums(hist[::step], *wide), load_N[::step], objective, flags)
        b_s, _ = sub.minimise(*wide, grid[k], xtol=1e-6 * grid[k])
        n_eval += sub.n_eval
        half = BRACKET_HALF_WIDTH
        narrow = (max(b_s - half, wide[0]), min(b_s + half, wide[1]))
        if narrow[0] < b_s < narrow[1]:
            found = _search_bracket(hist, load_N, objective, censored, narrow, b_s, xtol)
            if found is not None:
                return (*found[:3], n_eval + found[3])
    found = _search_bracket(hist, load_N, objective, censored, wide, grid[k], xtol)
    if found is not None:
        return (*found[:3], n_eval + found[3])
    b, A, cost, n_full = _minimise_b_grid(hist, load_N, objective, b_bounds, n_grid, xtol,
                                          censored)
    return b, A, cost, n_eval + n_full


def _search_bracket(hist, load_N, objective, censored, bracket, inside, xtol):
    """Minimise over ``bracket`` on all the points if it holds a minimum; else None."""
    search = _Search(_Sums(hist, *bracket), load_N, objective, censored)
    found = search.minimise(*bracket, inside, xtol=xtol, check=True)
    if found is None:
        return None
    b, (A, cost) = found
    return b, A, cost, search.n_eval


class _Search:
    """The profiled cost of all exponents in one bracket (:class:`_Sums`), remembered."""

    def __init__(self, sums_at, load_N, objective, censored):
        self.sums_at, self.load_N = sums_at, load_N
        self.objective, self.censored = objective, censored
        self.seen = {}  # b -> (A, cost)
        self.n_eval = 0

    def cost(self, b):
        """l1 or squared cost at ``b`` with A profiled out (median window from the last A)."""
        b = float(b)
        if b not in self.seen:
            self.n_eval += 1
            window = self._window(b) if self.objective == "l1" else None
            cost, A = _costs_many(self.sums_at([b]), self.load_N, self.objective,
                                  self.censored, window)
            self.seen[b] = (float(A[0]), float(cost[0]))
        return self.seen[b][1]

    def _window(self, b):
        """Where the l1 median at ``b`` is expected: A interpolated from two earlier b."""
        if len(self.seen) < 2:
            return None
        bs = sorted(self.seen)
        return _median_window([b], bs, [self.seen[x][0] for x in bs])

    def slope(self, b):
        """Slope d cost / d b of the l2/relative cost (:func:`_profiled_slope`, on the moments)."""
        self.n_eval += 1
        w2 = objective_weights(self.load_N, self.objective) ** 2
        (S,), (dS,) = self.sums_at([b], slope=True)
        return _profiled_slope(S, dS, self.load_N, w2)

    def minimise(self, lo, hi, inside, *, xtol, check=False):
        """Return ``(b, (A, cost))`` of the minimum in ``(lo, hi)`` to ``xtol`` in b.

        With ``check``, None where there is no sign of a minimum in the bracket (l1: the
        cost at ``inside`` is not below both ends; l2/relative: the slope does not go from
        negative to positive); without, ``inside`` is returned there.
        """
        if self.objective == "l1":
            ends = self.cost(lo), self.cost(inside), self.cost(hi)
            if not ends[1] < min(ends[0], ends[2]):
                if check:
                    return None
                return inside, self.seen[float(inside)]
            b = optimize.brent(self.cost, brack=(lo, inside, hi), tol=xtol / abs(inside))
        else:
            if not self.slope(lo) < 0 < self.slope(hi):
                if check:
                    return None
                b = inside
            else:
                b = optimize.brentq(self.slope, lo, hi, xtol=xtol)
        self.cost(b)
        return float(b), self.seen[float(b)]


def _minimise_b_grid(hist, load_N, objective, b_bounds, n_grid, xtol, censored):
    """Run :func:`_nested_grids` with the compiled kernels.

    The fallback of :func:`_minimise_b_many`, and its search until session 8.
    """
    return _nested_grids(hist, load_N, objective, b_bounds, n_grid, xtol, censored, True)


def _nested_grids(hist, load_N, objective, b_bounds, n_grid, xtol, censored, compiled):
    """Minimise the profiled cost over b by a grid, then nested grids or Brent in its bracket.

    The first grid over ``b_bounds`` reads the histograms (:func:`_direct_sums`); every
    later exponent lies in that grid's bracket, where Chebyshev moments give ``S_T(b)`` from
    one more pass (:class:`_Sums`). l1: nested
    grids of ``n_grid`` exponents until the bracket is below ``xtol``; l2, relative: the
    zero of the cost's slope by :func:`scipy.optimize.brentq`. ``compiled``: the numba
    kernels (l1 medians selected, not sorted: :mod:`._powerfit_kernels`) or NumPy
    alone. Returns ``(b, A, cost, n_evaluations)``.
    """
    costs = _costs_many if compiled else _costs_numpy
    windows = compiled and objective == "l1"
    lo, hi = (float(v) for v in b_bounds)
    grid = np.linspace(lo, hi, n_grid)
    cost, A = costs(_direct_sums(hist, grid), load_N, objective, censored)
    k = _best(cost)
    _check_interior(k, grid, b_bounds)
    lo, hi, n_eval = grid[k - 1], grid[k + 1], n_grid
    sums_at = _Sums(hist, lo, hi, compiled)
    if objective == "l1":
        while hi - lo > xtol:
            last, last_A, grid = grid, A, np.linspace(lo, hi, n_grid)
            window = _median_window(grid, last, last_A) if windows else None
            cost, A = costs(sums_at(grid), load_N, objective, censored, window)
            k, n_eval = _best(cost), n_eval + n_grid
            lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, n_grid - 1)]
        b = float(grid[k])
    else:
        w2 = objective_weights(load_N, objective) ** 2

        def slope(x):
            (S,), (dS,) = sums_at([x], slope=True)
            return _profiled_slope(S, dS, load_N, w2)

        if slope(lo) < 0 < slope(hi):
            b, info = optimize.brentq(slope, lo, hi, xtol=xtol, full_output=True)
            n_eval += 2 + info.function_calls
        else:  # flat or kinked cost: keep the grid's best
            b = float(grid[k])
    window = _median_window([b], grid, A) if windows else None
    cost, A = costs(sums_at([b]), load_N, objective, censored, window)
    return float(b), float(A[0]), float(cost[0]), n_eval + 1


def fit_power(hist, load_N, *, objective=DEFAULT_OBJECTIVE, b_bounds=B_BOUNDS):
    """Multi-point power law over every sensel, f = A * raw**b.

    Objectives: ``l2`` minimises ``sum_T (A S_T(b) - F_T)**2`` (Zvyagin 2022, eq. 3),
    ``l1`` minimises ``sum_T |F_T - A S_T(b)|`` (Gillis 2013, eq. 5.1, I-Scan), and
    ``relative`` minimises ``sum_T ((A S_T(b) - F_T) / F_T)**2``. ``A`` is profiled out
    (closed form, or the weighted median for ``l1``) and ``b`` found by nested grids
    over ``b_bounds`` (each pass one matrix product over the histograms).
    """
    _check_objective(objective)
    if len(hist) < COMPILED_MIN_POINTS:  # else products of the counts (hist_products)
        hist = np.asarray(hist, dtype=float)  # one conversion, then BLAS products
    b, A, cost, n_eval = _minimise_b(hist, load_N, objective, b_bounds)
    return Fit("power", {"A": A, "b": b},
               {"objective": objective, "cost": cost, "n_evaluations": n_eval})


def fit_power_of(data, *, objective=DEFAULT_OBJECTIVE, b_bounds=B_BOUNDS):
    """:func:`fit_power` of the points of ``data`` (a :class:`FitData`), remembered on it.

    Every load is taken as exact (``data.censored`` is not read). The power method, and
    ``lut`` and ``piecewise`` as their starting law, fit the same law to the same points
    (``auto`` fits all three on each fold): the fit is made once per objective and bounds,
    and each caller gets its own copy of the :class:`Fit`.
    """
    key = ("fit_power", objective, tuple(float(v) for v in b_bounds))
    if key not in data.memo:
        data.memo[key] = fit_power(data.hist, data.load_N, objective=objective,
                                   b_bounds=b_bounds)
    fit = data.memo[key]
    return dataclasses.replace(fit, params=dict(fit.params), diagnostics=dict(fit.diagnostics))


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
    raise TactilecalError(f"{n_clean} {kind} without a saturated sensel; a censored fit needs at "
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
    return Fit("power", {"A": A, "b": b},
               {"objective": objective, "censored": int(censored.sum()),
                "censored_active": int((censored & (excess > 0)).sum()), "cost": cost})


def _censored_least_squares(hist, load_N, censored, objective, b_bounds):
    """Return (A, b, cost) minimising the one-sided squared cost of fit_power_censored."""
    start = fit_power(hist[~censored], load_N[~censored], objective=objective,
                      b_bounds=b_bounds)
    w = objective_weights(load_N, objective)

    def residuals(x):
        excess = np.exp(x[0]) * _power_sums(hist, x[1]) - load_N
        return w * np.where(censored, np.maximum(excess, 0.0), excess)

    sol = optimize.least_squares(residuals, [np.log(start.params["A"]), start.params["b"]],
                                 bounds=([-np.inf, b_bounds[0]], [np.inf, b_bounds[1]]))
    return float(np.exp(sol.x[0])), float(sol.x[1]), float(sol.cost)
