"""Pairwise quartic (Zvyagin 2022, eq. 11-13) for every pair of patches, vectorised.

For patches i != j with class counts n_i, n_j at I* and loads F_i, F_j, eliminating A from
Q_Ti(Y) = F_i / A and Q_Tj(Y) = F_j / A and dividing by Y gives eq. (12):
c1 + c2 Y + c3 Y^2 + c4 Y^3 + c5 Y^4 = 0 with c_m = F_j n_{i,m} - F_i n_{j,m}.
:func:`solve_pairs` finds every pair's real roots above the threshold with a compiled
isolate-and-polish loop (:func:`._kernels.pair_roots`: Descartes' rule,
the derivatives' roots, Newton's method in a bracket), ~20x faster than the companion
matrices; the few pairs it flags as ill-conditioned (a near-double root, a root at the
threshold) go to :func:`polynomial_roots`, the eigenvalues of their companion matrices
(``numpy.linalg.eigvals`` on a stack), as every pair did before. Both give the roots to
rounding: they differed by 1.9e-14 relative at most on simulated sessions of 150 and 1000
patches (``tests/test_zvyagin_fast.py`` holds every result to 1e-9).
"""

import numpy as np

from tactilecal._errors import TactilecalError

__all__ = ["pair_indices", "quartic_coefficients", "polynomial_roots", "roots_above",
           "solve_pairs"]

_ROOT_CHOICES = ("smallest", "best-fit")
#: a root is real when |imag| <= _REAL_TOL * max(1, |root|)
_REAL_TOL = 1e-7
#: a root within this relative distance of the threshold is at it, not above: rounding
#: cannot tell, and an exact root Y = 3 is common (two patches of one load whose class
#: sums Q(3) are equal, eq. 11), which the paper's Y > 3 leaves out
_AT_THRESHOLD = 1e-12


def pair_indices(n_patches):
    """Return the indices (i, j), i < j, of every unordered pair (eq. 12 is symmetric)."""
    return np.triu_indices(n_patches, k=1)


def quartic_coefficients(counts, load_N, i, j):
    """Coefficients c1..c5 of eq. (12) for the pairs (i, j); shape (n_pairs, 5).

    Column m-1 multiplies Y**(m-1). Swapping i and j only changes the sign.

    Examples
    --------
    >>> n = np.array([[2, 1, 0, 0, 0], [1, 1, 1, 0, 0]])
    >>> quartic_coefficients(n, np.array([10.0, 20.0]), np.array([0]), np.array([1])).tolist()
    [[30.0, 10.0, -10.0, 0.0, 0.0]]
    """
    f = np.asarray(load_N, dtype=np.float64)
    return f[j, None] * counts[i] - f[i, None] * counts[j]


def polynomial_roots(coeffs):
    """Complex roots of many polynomials at once via batched companion matrices.

    Parameters
    ----------
    coeffs : numpy.ndarray, shape (n_poly, k + 1)
        Column m multiplies x**m (ascending powers). A polynomial's degree is its highest
        exactly non-zero coefficient; polynomials of each degree are solved together.

    Returns
    -------
    numpy.ndarray of complex, shape (n_poly, k)
        Roots, NaN-padded where the degree is lower than k (no roots at all for a constant).

    Examples
    --------
    >>> r = polynomial_roots(np.array([[-6.0, 1.0, 1.0], [2.0, -1.0, 0.0]]))
    >>> np.sort_complex(r[0]).real.round(6).tolist(), r[1, 0].real.round(6)
    ([-3.0, 2.0], np.float64(2.0))
    """
    c = np.asarray(coeffs, dtype=np.float64)
    n_poly, kp1 = c.shape
    k = kp1 - 1
    roots = np.full((n_poly, k), np.nan + 0j)
    nonzero = c != 0
    degree = np.where(nonzero.any(axis=1), kp1 - 1 - np.argmax(nonzero[:, ::-1], axis=1), 0)
    for deg in range(1, k + 1):
        rows = np.nonzero(degree == deg)[0]
        if rows.size == 0:
            continue
        monic = c[rows, :deg] / c[rows, deg, None]
        comp = np.zeros((rows.size, deg, deg))
        if deg > 1:
            comp[:, np.arange(1, deg), np.arange(deg - 1)] = 1.0
        comp[:, :, -1] = -monic
        roots[rows, :deg] = np.linalg.eigvals(comp)
    return roots


def roots_above(roots, threshold=3.0):
    """Real roots above ``threshold`` (NaN elsewhere), sorted ascending per row.

    A root within 1e-12 relative of the threshold counts as on it, not above; the two
    halves of a split double root are put at their mean (:func:`_merge_double_roots`).
    """
    real = roots.real
    is_real = np.abs(roots.imag) <= _REAL_TOL * np.maximum(1.0, np.abs(real))
    real = _merge_double_roots(np.sort(np.where(is_real, real, np.nan), axis=1))
    keep = real > threshold * (1.0 + _AT_THRESHOLD)
    return np.sort(np.where(keep, real, np.nan), axis=1)


def _merge_double_roots(real):
    """Put both roots of a split double root at their mean (rows sorted, NaN last).

    Rounding moves a double root r of eq. (12) to r +- d, d ~ sqrt(eps) r ~ 1e-8 r (two real
    roots, or a complex pair); their mean is r to rounding. Adjacent roots closer than
    ``_REAL_TOL`` relative are taken for one such root.
    """
    close = np.abs(np.diff(real, axis=1)) <= _REAL_TOL * np.abs(real[:, 1:])
    rows, k = np.nonzero(close)
    mean = 0.5 * (real[rows, k] + real[rows, k + 1])
    real[rows, k], real[rows, k + 1] = mean, mean
    return real


def _class_sums(counts, rows, y):
    """Q(Y) = sum_m n_m Y**m of patches ``rows`` (eq. 11), by Horner's rule (no ``pow``)."""
    c = np.asarray(counts, dtype=np.float64).T  # one gather per class, not per (pair, class)
    q = c[4][rows] * y
    for m in (3, 2, 1, 0):
        q = (q + c[m][rows]) * y
    return q


def _patch_power_sums(histograms, rows, b):
    """S_T(b) = sum_k X_k**b for patches ``rows`` and exponents ``b`` (equal lengths).

    Compiled (:func:`._kernels.power_sums`): only the raw values a patch
    holds are raised to the power.
    """
    from tactilecal.calibration.methods.zvyagin._kernels import power_sums

    out = np.empty(len(rows))
    power_sums(np.ascontiguousarray(histograms, dtype=np.int64),
               np.ascontiguousarray(rows, dtype=np.int64),
               np.ascontiguousarray(b, dtype=np.float64), out)
    return out


def solve_pairs(counts, load_N, raw_relerr, *, histograms=None, root_choice="smallest",
                max_relerr=0.10, usable=None, b_min=1.0):
    """Solve eq. (12) for every pair of patches and apply the 10% raw-sum rule.

    Parameters
    ----------
    counts : numpy.ndarray of int, shape (n_patches, 5)
        Class counts n_1..n_5 at I*.
    load_N : numpy.ndarray, shape (n_patches,)
        Applied loads F_T in newtons.
    raw_relerr : numpy.ndarray, shape (n_patches,)
        ``|R_T - Q_T(I*)| / R_T``, the raw-sum approximation error of each patch.
    histograms : numpy.ndarray of int, shape (n_patches, 256), optional
        Needed for ``root_choice="best-fit"``.
    root_choice : {"smallest", "best-fit"}
        Which root Y > 3 a pair keeps when it has several: the smallest, or the one whose
        (A, b) best reproduces both patches' loads from their actual readings.
    max_relerr : float
        Pairs where either patch has ``raw_relerr >= max_relerr`` are rejected (paper: 10%).
    usable : numpy.ndarray of bool, optional
        Patches allowed into pairs (others are marked excluded).
    b_min : float
        Roots Y > 3**b_min count (the paper: Y > 3, i.e. b > 1).

    Returns
    -------
    dict
        ``i``, ``j`` (pair indices, i < j), ``n_roots`` (number of roots Y > 3**b_min), ``Y``,
        ``b`` = log3 Y, ``A`` = F_i / Q_i(Y) (NaN without root), ``category`` (str codes:
        ``"V"`` valid, ``"R"`` root but rejected by the raw-sum rule, ``"N"`` no root > 3,
        ``"X"`` a patch excluded from pairing).
    """
    if root_choice not in _ROOT_CHOICES:
        raise TactilecalError(f"root_choice = {root_choice!r}; expected one of {_ROOT_CHOICES}")
    n = counts.shape[0]
    i, j = pair_indices(n)
    cand, n_roots = _pair_candidates(counts, load_N, i, j, 3.0 ** b_min)
    y = cand[:, 0].copy()
    if root_choice == "best-fit":
        multi = np.nonzero(n_roots > 1)[0]
        if multi.size:
            y[multi] = _best_fit_roots(cand[multi], histograms, load_N, counts,
                                       i[multi], j[multi])
    b = np.log(y) / np.log(3.0)
    a = np.asarray(load_N, dtype=np.float64)[i] / _class_sums(counts, i, y)
    bad_raw = (raw_relerr[i] >= max_relerr) | (raw_relerr[j] >= max_relerr)
    category = np.where(n_roots == 0, "N", np.where(bad_raw, "R", "V"))
    if usable is not None:
        category = np.where(usable[i] & usable[j], category, "X")
    return {"i": i, "j": j, "n_roots": n_roots, "Y": y, "b": b, "A": a,
            "category": category.astype("<U1")}


def _pair_candidates(counts, load_N, i, j, threshold):
    """Real roots > ``threshold`` of eq. (12) per pair, ascending, NaN-padded to 4; counts.

    The compiled solver takes every pair; those it flags are solved again here with the
    companion matrices (:func:`polynomial_roots`, :func:`roots_above`).
    """
    from tactilecal.calibration.methods.zvyagin._kernels import pair_roots

    i = np.ascontiguousarray(i, dtype=np.int64)
    j = np.ascontiguousarray(j, dtype=np.int64)
    cand = np.empty((i.size, 4))
    n_roots = np.empty(i.size, dtype=np.int64)
    flagged = np.empty(i.size, dtype=bool)
    pair_roots(np.ascontiguousarray(counts, dtype=np.float64),
               np.ascontiguousarray(load_N, dtype=np.float64), i, j, float(threshold),
               cand, n_roots, flagged)
    hard = np.nonzero(flagged)[0]
    if hard.size:
        cand[hard] = roots_above(polynomial_roots(quartic_coefficients(
            counts, load_N, i[hard], j[hard])), threshold=threshold)
        n_roots[hard] = np.sum(~np.isnan(cand[hard]), axis=1)
    return cand, n_roots


def _best_fit_roots(cand, histograms, load_N, counts, i, j):
    """Pick, per row of ``cand``, the root Y whose (A, b) best fits patches i and j."""
    if histograms is None:
        raise TactilecalError("root_choice='best-fit' needs the histograms of the patches")
    f = np.asarray(load_N, dtype=np.float64)
    score = np.full(cand.shape, np.inf)
    for k in range(cand.shape[1]):
        yk = cand[:, k]
        ok = ~np.isnan(yk)
        if not ok.any():
            continue
        y, ii, jj = yk[ok], i[ok], j[ok]
        bk = np.log(y) / np.log(3.0)
        a = f[ii] / _class_sums(counts, ii, y)
        s_i = _patch_power_sums(histograms, ii, bk)
        s_j = _patch_power_sums(histograms, jj, bk)
        score[ok, k] = (a * s_i / f[ii] - 1) ** 2 + (a * s_j / f[jj] - 1) ** 2
    return cand[np.arange(cand.shape[0]), np.argmin(score, axis=1)]
