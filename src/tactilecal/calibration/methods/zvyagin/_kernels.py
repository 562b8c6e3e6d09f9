"""numba kernels of the Zvyagin (2022) I* search (eq. 8-10) and pair stage (eq. 12).

:func:`abs_sum_map` accumulates the search's d-map: ``out[a, k] = sum_T |u[T, a] + v[T, k]|``
in float32, over tiles of 128 columns ``k`` and 4 rows ``a`` that stay in the L1 cache while
every patch is added to them, patches in order (as NumPy's ``sum(axis=0)`` adds them).

:func:`pair_roots` finds, for every pair of patches, the real roots above a threshold of
eq. (12)'s polynomial ``sum_m (F_j n_{i,m} - F_i n_{j,m}) Y**(m-1)``. Rather than the
eigenvalues of a companion matrix (LAPACK, ~3 us per quartic here) it isolates the real roots
with the derivatives: the roots of p' split the range above the threshold into intervals
where p is monotone, and each interval whose ends differ in sign holds one root, polished by
Newton's method kept inside the bracket (bisection when a step leaves it). The derivatives'
roots come the same way from theirs, down to the linear one. A pair is flagged for the
companion-matrix solver when the isolation is ill-conditioned: a polynomial (or a
derivative) nearly zero at one of its critical points (a near-double root, which
``numpy.linalg.eigvals`` may report either as two real roots or as a complex pair) or at the
threshold (a root that may fall on either side of it).

:func:`power_sums` scores the candidate roots of the best-fit root choice.

numba is imported with this module, i.e. on the first search or pair stage, not on
``import tactilecal.calibration.methods.zvyagin``.
"""

import numpy as np

from tactilecal._numba import njit

#: a polynomial is "nearly zero" at x when |p(x)| <= _NEAR_ZERO * sum_m |a_m| x**m
_NEAR_ZERO = 1e-9
#: Newton/bisection stop when the step or the bracket is this small relative to x
_REL_STEP = 4e-16
_MAX_ITER = 200
#: _FALLING[n, k] = n! / (n - k)!, the factor of a_n x**(n-k) in the k-th derivative
_FALLING = np.array([[1, 0, 0, 0, 0], [1, 1, 0, 0, 0], [1, 2, 2, 0, 0], [1, 3, 6, 6, 0],
                     [1, 4, 12, 24, 24]], dtype=np.float64)


@njit(nogil=True)
def abs_sum_map(u, c3, c4, inv_c, out, tile, rows):  # pragma: no cover (compiled)
    """Set ``out[a, k] = sum_T |u[T, a] + v[T, k]|`` (float32, patches T added in order).

    ``v[T, k]`` with ``k = k3 * n4 + k4`` is ``float32((c3[T, k3] + c4[T, k4]) * inv_c[T])``,
    built here one tile of columns at a time (the same float64 operations as NumPy's
    broadcast, so the same float32 values) rather than as an (n, n3 * n4) array.

    Parameters
    ----------
    u : numpy.ndarray of float32, shape (n_patches, n_a)
    c3 : numpy.ndarray of float64, shape (n_patches, n3)
    c4 : numpy.ndarray of float64, shape (n_patches, n4)
    inv_c : numpy.ndarray of float64, shape (n_patches,)
    out : numpy.ndarray of float32, shape (n_a, n3 * n4)
        Overwritten.
    tile : int
        Columns of ``out`` accumulated at a time.
    rows : int
        Rows of ``out`` accumulated together (each patch's tile of ``v`` is read once per
        ``rows`` rows).
    """
    n, n_a = u.shape
    n4 = c4.shape[1]
    n_k = c3.shape[1] * n4
    acc = np.empty((rows, tile), dtype=np.float32)
    v = np.empty((n, tile), dtype=np.float32)
    for k0 in range(0, n_k, tile):
        width = min(tile, n_k - k0)
        for t in range(n):
            k3, k4 = divmod(k0, n4)
            for k in range(width):
                v[t, k] = np.float32((c3[t, k3] + c4[t, k4]) * inv_c[t])
                k4 += 1
                if k4 == n4:
                    k3, k4 = k3 + 1, 0
        for a0 in range(0, n_a, rows):
            n_rows = min(rows, n_a - a0)
            acc[:] = np.float32(0.0)
            for t in range(n):
                v_t = v[t, :width]
                for q in range(n_rows):
                    u_ta = u[t, a0 + q]
                    acc_q = acc[q]
                    for k in range(width):  # float32 throughout, as NumPy adds them
                        acc_q[k] = acc_q[k] + np.float32(abs(u_ta + v_t[k]))
            # element by element: a slice assignment would compile numba's shape-mismatch
            # error (string formatting), most of this kernel's compile time
            for q in range(n_rows):
                for k in range(width):
                    out[a0 + q, k0 + k] = acc[q, k]


@njit(nogil=True)
def _eval(a, deg, k, x):  # pragma: no cover (compiled)
    """k-th derivative of sum_m a[m] x**m at x: value, its derivative, sum of |terms|."""
    p = a[deg] * _FALLING[deg, k]
    dp = 0.0
    s = abs(p)
    for m in range(deg - 1, k - 1, -1):
        dp = dp * x + p
        c = a[m] * _FALLING[m, k]
        p = p * x + c
        s = s * x + abs(c)
    return p, dp, s


@njit(nogil=True)
def _polish(a, deg, k, lo, hi, p_lo, x):  # pragma: no cover (compiled)
    """Return the root of the k-th derivative in [lo, hi] (one crossing there), from ``x``.

    Newton's method inside the bracket; a step that leaves it is replaced by bisection.
    """
    for _ in range(_MAX_ITER):
        p, dp, _s = _eval(a, deg, k, x)
        if p == 0.0:
            return x
        if (p < 0.0) == (p_lo < 0.0):
            lo = x
        else:
            hi = x
        new = 0.5 * (lo + hi)  # bisection, unless Newton's step stays in the bracket
        if dp != 0.0:
            step = x - p / dp
            if lo <= step <= hi and abs(step - x) <= _REL_STEP * abs(x):
                return step
            if lo < step < hi:
                new = step
        if hi - lo <= _REL_STEP * abs(x):
            return new
        x = new
    return x


@njit(nogil=True)
def _start(a, deg, k, lo, hi, p_lo):  # pragma: no cover (compiled)
    """First guess in (lo, hi): Newton's step from ``lo``, or the midpoint."""
    _p, dp, _s = _eval(a, deg, k, lo)
    x = lo - p_lo / dp if dp != 0.0 else lo
    return x if lo < x < hi else 0.5 * (lo + hi)


@njit(nogil=True)
def _sign_changes(a, deg, lo):  # pragma: no cover (compiled)
    """Descartes' sign changes of p(lo + z) (the k-th derivatives at lo), or -1 if unsure.

    The number of roots above ``lo`` is the count or less by an even number. Unsure when a
    derivative is nearly zero at ``lo`` (its sign is lost in rounding).
    """
    changes = 0
    previous = 1.0  # the leading coefficient of the monic polynomial
    for k in range(deg - 1, -1, -1):
        p, _dp, s = _eval(a, deg, k, lo)
        if abs(p) <= _NEAR_ZERO * s:
            return -1
        if (p < 0.0) != (previous < 0.0):
            changes += 1
        previous = p
    return changes


@njit(nogil=True)
def _isolate(a, deg, lo, hi, crit, found):  # pragma: no cover (compiled)
    """Real roots of sum_m a[m] x**m (a[deg] = 1) in (lo, hi) into ``found``, ascending.

    Returns the number of roots, or -1 when the isolation is ill-conditioned (p nearly zero
    at ``lo`` or at a critical point, or a derivative nearly zero at one of its own).
    """
    n_crit = 0
    for k in range(deg - 1, -1, -1):  # k-th derivative, from the linear one down to p
        n_new = 0
        left = lo
        p_left, _dp, s_left = _eval(a, deg, k, lo)
        if k == 0 and abs(p_left) <= _NEAR_ZERO * s_left:
            return -1
        for c in range(n_crit + 1):
            right = crit[c] if c < n_crit else hi
            p_right, _dp, s_right = _eval(a, deg, k, right)
            if c < n_crit and abs(p_right) <= _NEAR_ZERO * s_right:
                return -1
            if (p_left < 0.0) != (p_right < 0.0):
                x = _start(a, deg, k, left, right, p_left)
                found[n_new] = _polish(a, deg, k, left, right, p_left, x)
                n_new += 1
            left, p_left = right, p_right
        for c in range(n_new):
            crit[c] = found[c]
        n_crit = n_new
    return n_crit


@njit(nogil=True)
def _roots_above(a, deg, lo, hi, crit, found):  # pragma: no cover (compiled)
    """Real roots of the monic sum_m a[m] x**m in (lo, hi), ``hi`` above them all.

    Descartes' rule on p(lo + z) settles the common cases (no root, or exactly one, which
    Newton's method finds in the bracket (lo, hi)); the rest are isolated with the
    derivatives. Returns the number of roots, or -1 when ill-conditioned.
    """
    changes = _sign_changes(a, deg, lo)
    if changes == 0:
        return 0
    if changes == 1:
        k = np.int64(0)  # typed: a literal 0 would compile each callee once more for it
        p_lo, _dp, _s = _eval(a, deg, k, lo)
        found[0] = _polish(a, deg, k, lo, hi, p_lo, _start(a, deg, k, lo, hi, p_lo))
        return 1
    return _isolate(a, deg, lo, hi, crit, found)


@njit(nogil=True)
def pair_roots(counts, load_n, first, second, threshold, roots, n_roots,
               flagged):  # pragma: no cover (compiled)
    """Real roots > ``threshold`` of eq. (12) for the pairs (first[p], second[p]).

    Parameters
    ----------
    counts : numpy.ndarray of float64, shape (n_patches, 5)
        Class counts n_1..n_5.
    load_n : numpy.ndarray of float64, shape (n_patches,)
        Loads F in newtons.
    first, second : numpy.ndarray of int64, shape (n_pairs,)
        Pair indices i, j.
    threshold : float
        Roots must exceed it (3**b_min > 1).
    roots : numpy.ndarray of float64, shape (n_pairs, 4)
        Filled with the roots ascending, NaN after them.
    n_roots : numpy.ndarray of int64, shape (n_pairs,)
        Number of roots found.
    flagged : numpy.ndarray of bool, shape (n_pairs,)
        True where the isolation was ill-conditioned (``roots``, ``n_roots`` not set):
        solve those pairs with the companion matrix.
    """
    a = np.empty(5)
    crit = np.empty(4)
    found = np.empty(4)
    for p in range(first.size):
        i, j = first[p], second[p]
        deg = np.int64(0)  # typed: as the literal 0, the callees would compile for it too
        for m in range(5):
            a[m] = load_n[j] * counts[i, m] - load_n[i] * counts[j, m]
            if a[m] != 0.0:
                deg = m
        for m in range(4):
            roots[p, m] = np.nan
        n_roots[p] = 0
        flagged[p] = False
        if deg == 0:
            continue
        lead = a[deg]
        bound = 0.0
        finite = np.isfinite(lead)
        for m in range(deg):
            a[m] = a[m] / lead
            finite = finite and np.isfinite(a[m])
            bound = max(bound, abs(a[m]))
        if not finite:  # a load that is not finite: the companion matrix says what happens
            flagged[p] = True
            continue
        a[deg] = 1.0
        bound += 1.0  # Cauchy: every root has |Y| < 1 + max |a_m|
        if bound * (1.0 + 1e-9) <= threshold:  # clear of it: a root near both goes on
            continue
        got = _roots_above(a, deg, threshold, bound, crit, found)
        if got < 0:
            flagged[p] = True
            continue
        for m in range(got):
            roots[p, m] = found[m]
        n_roots[p] = got


@njit(nogil=True)
def power_sums(histograms, rows, b, out):  # pragma: no cover (compiled)
    """Set ``out[p] = sum_x histograms[rows[p], x] * x**b[p]`` over x = 1..255.

    The power sums S_T(b) of Zvyagin (2022), eq. (2), for one exponent per entry (the
    best-fit root choice scores every candidate root of every pair); raw values a patch
    does not hold cost no ``pow``.
    """
    for p in range(rows.size):
        h = histograms[rows[p]]
        total = 0.0
        for x in range(1, h.size):
            if h[x] != 0:
                total += h[x] * float(x) ** b[p]
        out[p] = total
