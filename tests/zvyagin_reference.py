"""The Zvyagin I* search and pair stage as they were before issue 16 (reference for tests).

A verbatim copy of ``search_separation`` (with ``_exact_minimum``) from
``tactilecal/zvyagin/_approx.py``, of ``tactilecal/zvyagin/_pairs.py`` and of the pair tables
of ``tactilecal/zvyagin/_calibrate.py`` (``pair_share_table``, ``partner_share``) at main
18f2dcf, doctest examples removed. ``tests/test_zvyagin_fast.py`` runs
:func:`tactilecal.zvyagin.zvyagin_fit` once with these and once with the package's current
functions and compares the results. Not part of the package.
"""

import numpy as np

from tactilecal.zvyagin._approx import (
    check_histograms,
    loaded_cells,
    raw_sums,
    separation_domain,
)

_BLOCK_VALUES = 131_072


def _cumulative_below(histograms):
    cum = np.zeros((histograms.shape[0], 257), dtype=np.int64)
    cum[:, 2:] = np.cumsum(histograms[:, 1:], axis=1)
    return cum


def search_separation(histograms, *, domain="strict"):
    """Exhaustive search for I* minimising the mean discrepancy d_{T}(I) (eq. 8-10).

    Every vector of the domain is evaluated; nothing is restricted to the interval midpoints.
    With cumulative counts a_m(T, I) = n_T(raw < I), the approximation is
    Q_T(I) = 243 C_T - 6 a(I1) - 18 a(I2) - 54 a(I3) - 162 a(I4), so
    R_T - Q_T(I) = u_T(I1, I2) + v_T(I3, I4): the search is a broadcast sum of two small
    tables per patch, reduced over patches one (I1, I2) slice at a time.

    Parameters
    ----------
    histograms : array_like of int, shape (n_patches, 256)
        Counts of raw values 0..255 per patch; every patch needs a loaded sensel.
    domain : {"strict", "closed"}
        See :func:`separation_domain`.

    Returns
    -------
    separation : tuple of 4 int
        I* = (I1, I2, I3, I4). Ties (flat regions, where no sensel reads a value between two
        candidates) go to the first vector in lexicographic order.
    d_min : float
        d_{T}(I*) in raw units per loaded sensel.
    d_map : numpy.ndarray of float32, shape (n1, n2, n3, n4)
        d_{T}(I) over the whole domain, indexed like :func:`separation_domain` (accumulated
        in float32; d_min is recomputed exactly).

    """
    h = check_histograms(histograms)
    cells = loaded_cells(h)
    if np.any(cells == 0):
        empty = np.nonzero(cells == 0)[0].tolist()
        raise ValueError(f"patches {empty} have no loaded sensel; expected at least one "
                         "raw reading > 0 per patch")
    r1, r2, r3, r4 = separation_domain(domain)
    cum = _cumulative_below(h).astype(np.float64)
    inv_c = 1.0 / cells
    base = raw_sums(h) - 243.0 * cells
    u = ((base[:, None, None] + 6 * cum[:, r1, None] + 18 * cum[:, None, r2])
         * inv_c[:, None, None]).astype(np.float32)
    v = ((54 * cum[:, r3, None] + 162 * cum[:, None, r4]) * inv_c[:, None, None]).astype(
        np.float32)
    n = h.shape[0]
    v = v.reshape(n, -1)
    d_map = np.empty((len(r1), len(r2), v.shape[1]), dtype=np.float32)
    width = max(1, _BLOCK_VALUES // n)  # keep the working block in cache
    for start in range(0, v.shape[1], width):
        block = v[:, start:start + width]
        buf = np.empty_like(block)
        for i1 in range(len(r1)):
            for i2 in range(len(r2)):
                np.add(block, u[:, i1, i2, None], out=buf)
                np.abs(buf, out=buf)
                np.sum(buf, axis=0, out=d_map[i1, i2, start:start + width])
    d_map = d_map.reshape(len(r1), len(r2), len(r3), len(r4)) / n
    return _exact_minimum(h, d_map, (r1, r2, r3, r4))


def _exact_minimum(h, d_map, ranges):
    """Re-evaluate in float64 every vector within float32 noise of the minimum; pick the best.

    The map is accumulated in float32 (half the memory traffic); vectors whose float32 d is
    within 1e-4 relative of the smallest are recomputed exactly with eq. (7)-(8), in chunks,
    and ties go to the first in lexicographic order.
    """
    d32 = d_map.min()
    near = np.argwhere(d_map <= d32 + 1e-4 * max(float(d32), 1e-3))
    vectors = np.column_stack([r[k] for r, k in zip(ranges, near.T, strict=True)])
    cum = _cumulative_below(h).astype(np.float64)
    cells = loaded_cells(h)
    base = (raw_sums(h) - 243.0 * cells)[:, None]
    weights = np.array([6.0, 18.0, 54.0, 162.0])
    step = max(1, _BLOCK_VALUES // h.shape[0])
    exact = np.empty(len(vectors))
    for start in range(0, len(vectors), step):
        vec = vectors[start:start + step]
        diff = base + sum(w * cum[:, vec[:, m]] for m, w in enumerate(weights))
        exact[start:start + step] = np.mean(np.abs(diff) / cells[:, None], axis=0)
    k = int(np.argmin(exact))
    return tuple(int(x) for x in vectors[k]), float(exact[k]), d_map


_ROOT_CHOICES = ("smallest", "best-fit")
#: a root is real when |imag| <= _REAL_TOL * max(1, |root|)
_REAL_TOL = 1e-7


def pair_indices(n_patches):
    """Return the indices (i, j), i < j, of every unordered pair (eq. 12 is symmetric)."""
    return np.triu_indices(n_patches, k=1)


def quartic_coefficients(counts, load_N, i, j):
    """Coefficients c1..c5 of eq. (12) for the pairs (i, j); shape (n_pairs, 5).

    Column m-1 multiplies Y**(m-1). Swapping i and j only changes the sign.

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
    """Real roots strictly above ``threshold`` (NaN elsewhere), sorted ascending per row."""
    real = roots.real
    is_real = np.abs(roots.imag) <= _REAL_TOL * np.maximum(1.0, np.abs(real))
    keep = is_real & (real > threshold)
    out = np.where(keep, real, np.nan)
    return np.sort(out, axis=1)


def _patch_power_sums(histograms, b):
    """S_T(b) = sum_k X_k**b for patch/exponent pairs given as equal-length arrays."""
    raw = np.arange(256, dtype=np.float64)
    return np.einsum("pk,pk->p", histograms, raw[None, :] ** b[:, None])


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
        |R_T - Q_T(I*)| / R_T, the raw-sum approximation error of each patch.
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
        raise ValueError(f"root_choice = {root_choice!r}; expected one of {_ROOT_CHOICES}")
    n = counts.shape[0]
    i, j = pair_indices(n)
    cand = roots_above(polynomial_roots(quartic_coefficients(counts, load_N, i, j)),
                       threshold=3.0 ** b_min)
    n_roots = np.sum(~np.isnan(cand), axis=1)
    y = cand[:, 0].copy()
    if root_choice == "best-fit":
        multi = np.nonzero(n_roots > 1)[0]
        if multi.size:
            y[multi] = _best_fit_roots(cand[multi], histograms, load_N, counts,
                                       i[multi], j[multi])
    b = np.log(y) / np.log(3.0)
    q_i = np.einsum("pm,pm->p", counts[i], y[:, None] ** np.arange(1, 6))
    a = np.asarray(load_N, dtype=np.float64)[i] / q_i
    bad_raw = (raw_relerr[i] >= max_relerr) | (raw_relerr[j] >= max_relerr)
    category = np.where(n_roots == 0, "N", np.where(bad_raw, "R", "V"))
    if usable is not None:
        category = np.where(usable[i] & usable[j], category, "X")
    return {"i": i, "j": j, "n_roots": n_roots, "Y": y, "b": b, "A": a,
            "category": category.astype("<U1")}


def _best_fit_roots(cand, histograms, load_N, counts, i, j):
    """Pick, per row of ``cand``, the root Y whose (A, b) best fits patches i and j."""
    if histograms is None:
        raise ValueError("root_choice='best-fit' needs the histograms of the patches")
    f = np.asarray(load_N, dtype=np.float64)
    powers = np.arange(1, 6)
    score = np.full(cand.shape, np.inf)
    for k in range(cand.shape[1]):
        yk = cand[:, k]
        ok = ~np.isnan(yk)
        if not ok.any():
            continue
        y, ii, jj = yk[ok], i[ok], j[ok]
        bk = np.log(y) / np.log(3.0)
        a = f[ii] / np.einsum("pm,pm->p", counts[ii], y[:, None] ** powers)
        s_i = _patch_power_sums(histograms[ii], bk)
        s_j = _patch_power_sums(histograms[jj], bk)
        score[ok, k] = (a * s_i / f[ii] - 1) ** 2 + (a * s_j / f[jj] - 1) ** 2
    return cand[np.arange(cand.shape[0]), np.argmin(score, axis=1)]


def pair_share_table(group, names, pairs, usable):
    """Share of pairs that gave (A, b) per load combination (paper: 2-5 kg 34% ...)."""
    i, j = pairs["i"], pairs["j"]
    both = usable[i] & usable[j]
    gave = np.isin(pairs["category"], ("V", "O"))
    lo, hi = np.minimum(group[i], group[j]), np.maximum(group[i], group[j])
    rows = []
    for g in range(len(names)):
        for h in range(g, len(names)):
            sel = both & (lo == g) & (hi == h)
            n_pairs = int(sel.sum())
            n_valid = int((sel & gave).sum())
            rows.append({"loads": f"{names[g]} - {names[h]}", "pairs": n_pairs,
                         "valid": n_valid, "with_root": int((sel & (pairs["n_roots"] > 0)).sum()),
                         "share": n_valid / n_pairs if n_pairs else float("nan")})
    return rows


def partner_share(pairs, usable, n):
    """Share of its usable partners with which a patch has a root (former zvyagin_fit lines)."""
    with_root = pairs["n_roots"] > 0
    partner_share = np.zeros(n)
    both = usable[pairs["i"]] & usable[pairs["j"]]
    np.add.at(partner_share, pairs["i"][both & with_root], 1)
    np.add.at(partner_share, pairs["j"][both & with_root], 1)
    return partner_share / max(int(usable.sum()) - 1, 1)
