"""numba kernels of the Zvyagin (2022) I* search (eq. 8-10) and pair stage (eq. 12).

:func:`abs_sum_map` accumulates the search's d-map: ``out[a, k] = sum_T |u[T, a] + v[T, k]|``
in float32, over tiles of ``k`` small enough that the tile of ``out`` stays in the L1 cache
while every patch is added to it, patches in order (as NumPy's ``sum(axis=0)`` adds them, so
the map is the same to the last bit).

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

numba is imported with this module, i.e. on the first search or pair stage, not on
``import tactilecal.zvyagin``.
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
def abs_sum_map(u, v, out, tile):  # pragma: no cover (compiled)
    """Set ``out[a, k] = sum_T |u[T, a] + v[T, k]|`` (float32, patches T added in order).

    Parameters
    ----------
    u : numpy.ndarray of float32, shape (n_patches, n_a)
    v : numpy.ndarray of float32, shape (n_patches, n_k)
    out : numpy.ndarray of float32, shape (n_a, n_k)
        Overwritten.
    tile : int
        Columns of ``out`` accumulated at a time (``n_a * tile`` floats should fit in L1).
    """
    n, n_a = u.shape
    n_k = v.shape[1]
    for k0 in range(0, n_k, tile):
        k1 = min(k0 + tile, n_k)
        for a in range(n_a):
            out[a, k0:k1] = np.float32(0.0)
        for t in range(n):
            v_t = v[t, k0:k1]
            for a in range(n_a):
                u_ta = u[t, a]
                out_a = out[a, k0:k1]
                for k in range(k1 - k0):  # float32 throughout, as NumPy adds them
                    out_a[k] = out_a[k] + np.float32(abs(u_ta + v_t[k]))


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
        p_lo, _dp, _s = _eval(a, deg, 0, lo)
        found[0] = _polish(a, deg, 0, lo, hi, p_lo, _start(a, deg, 0, lo, hi, p_lo))
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
        deg = 0
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
        for m in range(deg):
            a[m] = a[m] / lead
            bound = max(bound, abs(a[m]))
        a[deg] = 1.0
        bound += 1.0  # Cauchy: every root has |Y| < 1 + max |a_m|
        if bound <= threshold:
            continue
        got = _roots_above(a, deg, threshold, bound, crit, found)
        if got < 0:
            flagged[p] = True
            continue
        for m in range(got):
            roots[p, m] = found[m]
        n_roots[p] = got
