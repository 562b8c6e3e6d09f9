"""numba kernel of the l1 power fit for many points: weighted medians without sorting.

For a fixed exponent b the l1 fit's best A is a weighted median of ``F_T / S_T(b)``
(:func:`tactilecal.calibration._powerfit._censored_median`, which sorts). With 100,000 movie frames
and about 170 trial exponents, those sorts were most of a movie calibration's time. Here
each median is found by selection (Hoare's quickselect with a three-way partition, expected
O(n)), first among the ratios inside a window the caller expects it in (the previous
round's A), so most trial exponents cost two passes over the points: one for the ratios,
one for the cost.

Imported only for large fits (:data:`tactilecal.calibration._powerfit.COMPILED_MIN_POINTS`): numba's
start-up in a new process costs more than it saves on a small one.
"""

import numpy as np

from tactilecal._numba import njit

_SMALL = 24  # ranges sorted by insertion


@njit(nogil=True)
def l1_costs(sums, load, censored, window_lo, window_hi):  # pragma: no cover (compiled)
    """Best A and l1 cost of the power law for each row of ``sums`` (one exponent each).

    Parameters
    ----------
    sums : numpy.ndarray, shape (m, n)
        ``S_T(b)`` of the n points for m exponents (positive).
    load : numpy.ndarray, shape (n,)
        ``F_T``.
    censored : numpy.ndarray of bool, shape (n,)
        Points whose residual counts only when the prediction exceeds the load.
    window_lo, window_hi : numpy.ndarray, shape (m,)
        Where each median is expected (``-inf``, ``inf``: anywhere). A window that misses
        is moved and widened 4-fold towards the median until it holds it: a wrong window
        costs time, never the result.

    Returns
    -------
    cost, A : numpy.ndarray, shape (m,)
        ``sum_unc |A S - F| + sum_cens max(0, A S - F)`` and its minimiser A, the smallest
        ratio ``F / S`` at which ``2 W_unc(<= r) + W_cens(<= r) >= W_unc(all)`` (weights
        ``S``), as :func:`tactilecal.calibration._powerfit._censored_median`.
    """
    m, n = sums.shape
    cost, best = np.empty(m), np.empty(m)
    work_r, work_w = np.empty(n), np.empty(n)
    for c in range(m):
        s = sums[c]
        a = _windowed_median(s, load, censored, window_lo[c], window_hi[c], work_r, work_w)
        total = 0.0
        for i in range(n):
            r = a * s[i] - load[i]
            if censored[i] and r < 0.0:
                r = 0.0
            total += abs(r)
        cost[c], best[c] = total, a
    return cost, best


@njit(nogil=True)
def _windowed_median(s, load, censored, lo, hi, work_r, work_w):  # pragma: no cover
    """Return the l1 median of ``load / s``, looked for among the ratios in [lo, hi] first.

    Ratios below ``lo`` only add their weight; those in the window are copied and
    selected among. A window that misses the median is moved towards it and widened; after
    a few misses the median is selected among all ratios.
    """
    for _ in range(6):
        target, below, inside, k = 0.0, 0.0, 0.0, 0
        for i in range(s.size):
            r = load[i] / s[i]
            w = s[i] if censored[i] else 2.0 * s[i]
            target += 0.0 if censored[i] else s[i]
            if r < lo:
                below += w
            elif r <= hi:
                work_r[k], work_w[k] = r, w
                k += 1
                inside += w
        width = 4.0 * (hi - lo)
        if below >= target:  # the median is below the window
            lo, hi = lo - width, lo
        elif below + inside < target:  # above it
            lo, hi = hi, hi + width
        else:
            return _select(work_r[:k], work_w[:k], target - below)
        if not width < np.inf:
            break
    for i in range(s.size):
        work_r[i] = load[i] / s[i]
        work_w[i] = s[i] if censored[i] else 2.0 * s[i]
    return _select(work_r[:s.size], work_w[:s.size], target)


@njit(nogil=True)
def _select(r, w, target):  # pragma: no cover (compiled)
    """Weighted lower quantile by quickselect (reorders ``r`` and ``w``)."""
    lo, hi = 0, r.size
    while hi - lo > _SMALL:
        a, b, c = r[lo], r[(lo + hi) // 2], r[hi - 1]
        pivot = max(min(a, b), min(max(a, b), c))  # median of three
        lt, i, gt = lo, lo, hi
        w_lt, w_eq = 0.0, 0.0
        while i < gt:
            if r[i] < pivot:
                w_lt += w[i]
                r[i], r[lt] = r[lt], r[i]
                w[i], w[lt] = w[lt], w[i]
                lt += 1
                i += 1
            elif r[i] > pivot:
                gt -= 1
                r[i], r[gt] = r[gt], r[i]
                w[i], w[gt] = w[gt], w[i]
            else:
                w_eq += w[i]
                i += 1
        if w_lt >= target and lt > lo:
            hi = lt
        elif w_lt + w_eq >= target:
            return pivot
        else:
            target -= w_lt + w_eq
            lo = gt
    for i in range(lo + 1, hi):  # insertion sort of the rest, then accumulate
        x, y, j = r[i], w[i], i - 1
        while j >= lo and r[j] > x:
            r[j + 1], w[j + 1] = r[j], w[j]
            j -= 1
        r[j + 1], w[j + 1] = x, y
    acc = 0.0
    for i in range(lo, hi):
        acc += w[i]
        if acc >= target:
            return r[i]
    return r[hi - 1]  # round-off left the target just above the total


@njit(nogil=True)
def series_sums(moments, terms):  # pragma: no cover (compiled)
    """``terms.T @ moments``, (m, n), in one thread.

    ``moments`` (J, n) are the points' Chebyshev moments and ``terms`` (J, m) the
    polynomials at m exponents. A threaded BLAS product of these shapes was 4-10 times
    slower than one thread on the shared 2 cores (its threads wait for each other).
    """
    n_terms, n = moments.shape
    m = terms.shape[1]
    out = np.zeros((m, n))
    for c in range(m):
        row = out[c]
        for j in range(n_terms):
            t = terms[j, c]
            mj = moments[j]
            for i in range(n):
                row[i] += t * mj[i]
    return out


#: Columns up to which :func:`hist_dot` multiplies every bin (:func:`_dense_dot`).
DENSE_MAX_COLUMNS = 4


@njit(nogil=True)
def hist_dot(hist, matrix, out, start):  # pragma: no cover (compiled)
    """``(hist @ matrix).T`` into ``out[:, start:start + len(hist)]`` in one thread.

    Up to :data:`DENSE_MAX_COLUMNS` columns every bin is multiplied (:func:`_dense_dot`);
    beyond, empty bins are skipped (:func:`_sparse_dot`). ``out`` is the whole (c, n)
    result, contiguous, whichever block of rows a thread fills: a block of its columns
    would be another array type, for which numba would compile the kernels again.
    """
    if matrix.shape[1] <= DENSE_MAX_COLUMNS:
        return _dense_dot(hist, np.ascontiguousarray(matrix.T), out, start)
    return _sparse_dot(hist, matrix, out, start)


@njit(nogil=True, fastmath={"reassoc", "contract"})
def _dense_dot(hist, matrix_t, out, start):  # pragma: no cover (compiled)
    """``(hist @ matrix_t.T).T`` into ``out[:, start:]`` (c, n): every bin, in vector registers.

    Each sum is reassociated (``fastmath``) so that the compiler keeps several partial
    sums in SIMD registers: equal to the ordered sum to round-off, and exact for
    integer-valued ``matrix_t`` (the raw sum ``hist @ (0..255)``, below 2**53). With one
    or two columns, 0.19-0.42 of :func:`_sparse_dot`'s time on the 100,000-frame movie of
    ``benchmarks/bench_movie.py`` (whose branch per bin is mispredicted); with ten, the
    same time.
    """
    n, k = hist.shape
    c = matrix_t.shape[0]
    for i in range(n):
        row = hist[i]
        for q in range(c):
            weights = matrix_t[q]
            acc = 0.0
            for j in range(k):
                acc += row[j] * weights[j]
            out[q, start + i] = acc
    return out


@njit(nogil=True)
def _sparse_dot(hist, matrix, out, start):  # pragma: no cover (compiled)
    """``(hist @ matrix).T`` into ``out[:, start:]`` (c, n), skipping empty bins, one thread.

    ``hist`` (n, 256) holds counts (any dtype; uint16 for a movie) and ``matrix`` (256, c)
    a few functions of the raw level. A frame's histogram is mostly empty bins (29 of 256
    filled on average on the simulated 100,000-frame movie of ``benchmarks/bench_movie.py``),
    so skipping them does a ninth of the multiplications of a dense product, and reading
    uint16 counts a quarter of the bytes of float64.
    """
    n, k = hist.shape
    c = matrix.shape[1]
    acc = np.empty(c)
    for i in range(n):
        acc[:] = 0.0
        row = hist[i]
        for j in range(k):
            h = row[j]
            if h != 0:
                x = float(h)
                for q in range(c):
                    acc[q] += x * matrix[j, q]
        for q in range(c):
            out[q, start + i] = acc[q]
    return out
