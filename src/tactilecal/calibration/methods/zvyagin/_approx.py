"""Degrees-of-three approximation and the exhaustive search for I* (Zvyagin 2022, eq. 5-10).

Everything here works on histograms of raw readings: ``histograms[T, x]`` is the number of
sensels of patch ``T`` that read ``x`` (0..255). Raw 0 means "not loaded" and is ignored;
raw 1 and 2 (below Tekscan's usual threshold of 3, if a file has them) are loaded sensels and
fall in the first class, like 3..I1-1.
"""

import numpy as np

from tactilecal._errors import TactilecalError

__all__ = [
    "CLASS_VALUES",
    "check_histograms",
    "loaded_cells",
    "raw_sums",
    "class_counts",
    "approximate_raw_sums",
    "patch_discrepancy",
    "separation_domain",
    "search_separation",
]

#: The five approximating values Y_m = 3**m, m = 1..5 (eq. 5).
CLASS_VALUES = 3 ** np.arange(1, 6)
_RAW = np.arange(256)
DOMAINS = ("strict", "closed")
#: float32 values per working block of the exact re-evaluation (~0.5 MB, stays in cache)
_BLOCK_VALUES = 131_072
#: (columns (I3, I4), rows (I1, I2)) of the d-map accumulated at a time (fit in L1)
_MAP_TILE = (128, 4)


def check_histograms(histograms):
    """Return ``histograms`` as an int64 array of shape (n, 256), or raise ValueError."""
    h = np.asarray(histograms)
    if h.ndim != 2 or h.shape[1] != 256:
        raise TactilecalError(f"histograms has shape {h.shape}; expected (n_patches, 256) counts "
                              "of raw values 0..255")
    if h.dtype.kind == "f":
        if not np.all(np.isfinite(h)) or np.any(h != np.round(h)):
            raise TactilecalError("histograms holds non-integer or non-finite counts; expected "
                                  "whole numbers of sensels per raw value")
    elif h.dtype.kind not in "iub":
        raise TypeError(f"histograms has dtype {h.dtype}; expected integer counts")
    if np.any(h < 0):
        bad = np.unique(np.nonzero(h < 0)[0])
        raise TactilecalError(f"histograms of patches {bad.tolist()} hold negative counts; "
                              "expected counts >= 0")
    return h.astype(np.int64)


def loaded_cells(histograms):
    """Count the loaded sensels C_T of each patch (raw reading > 0)."""
    return histograms[:, 1:].sum(axis=1)


def raw_sums(histograms):
    """Raw sum R_T of each patch (Zvyagin 2022, eq. 4): sum over loaded sensels of X_k."""
    return histograms @ _RAW


def _cumulative_below(histograms):
    """``cum[T, I]`` = number of loaded sensels of patch T with raw value < I (I = 0..256)."""
    cum = np.zeros((histograms.shape[0], 257), dtype=np.int64)
    cum[:, 2:] = np.cumsum(histograms[:, 1:], axis=1)
    return cum


def class_counts(histograms, separation):
    """Count each patch's sensels in the five classes set by ``separation`` (eq. 5-6).

    Parameters
    ----------
    histograms : array_like of int, shape (n_patches, 256)
        Counts of raw values 0..255 per patch.
    separation : sequence of 4 int
        The boundaries (I1, I2, I3, I4): raw [1, I1) -> 3, [I1, I2) -> 9, [I2, I3) -> 27,
        [I3, I4) -> 81, [I4, 255] -> 243.

    Returns
    -------
    numpy.ndarray of int64, shape (n_patches, 5)

    Examples
    --------
    >>> h = np.zeros((1, 256), dtype=int); h[0, [3, 8, 20, 100, 255]] = 1
    >>> class_counts(h, (6, 18, 54, 162)).tolist()
    [[1, 1, 1, 1, 1]]
    """
    h = check_histograms(histograms)
    edges = _check_separation(separation)
    cum = _cumulative_below(h)
    below = cum[:, [1, *edges, 256]]  # below[:, 0] is 0 (raw 0 is not loaded)
    return np.diff(below, axis=1)


def approximate_raw_sums(histograms, separation):
    """Approximate raw sums Q_T(I) = sum_m n_m 3**m (Zvyagin 2022, eq. 6)."""
    return class_counts(histograms, separation) @ CLASS_VALUES


def patch_discrepancy(histograms, separation):
    """Per-patch discrepancy d_T(I) = |R_T - Q_T(I)| / C_T in raw units (eq. 7)."""
    h = check_histograms(histograms)
    return np.abs(raw_sums(h) - approximate_raw_sums(h, separation)) / loaded_cells(h)


def _check_separation(separation):
    edges = [int(v) for v in np.asarray(separation).ravel()]
    if len(edges) != 4:
        raise TactilecalError(f"separation has {len(edges)} values; expected 4 (I1, I2, I3, I4)")
    lows, highs = (3, 9, 27, 81), (9, 27, 81, 243)
    for m, (v, lo, hi) in enumerate(zip(edges, lows, highs, strict=True), start=1):
        if not lo < v <= hi:
            raise TactilecalError(f"separation I{m} = {v}; expected {lo} < I{m} <= {hi} (eq. 10)")
    return edges


def separation_domain(domain="strict"):
    """Return the candidate values of I1..I4 (Zvyagin 2022, eq. 10).

    Parameters
    ----------
    domain : {"strict", "closed"}
        ``"strict"``: 3 < I1 < 9 < I2 < 27 < I3 < 81 < I4 < 243, exactly as eq. (10) prints
        (5 x 17 x 53 x 161 = 725,305 vectors). ``"closed"``: each boundary may also equal the
        power of three above it (3 < I1 <= 9 < I2 <= 27 < I3 <= 81 < I4 <= 243; 6 x 18 x 54
        x 162 = 944,784 vectors), which admits the ``I1 = 9`` printed in one row of Table 2.

    Returns
    -------
    tuple of 4 numpy.ndarray

    Examples
    --------
    >>> [len(r) for r in separation_domain()]
    [5, 17, 53, 161]
    """
    if domain not in DOMAINS:
        raise TactilecalError(f"domain = {domain!r}; expected one of {DOMAINS}")
    extra = 1 if domain == "closed" else 0
    return tuple(np.arange(lo + 1, hi + extra)
                 for lo, hi in ((3, 9), (9, 27), (27, 81), (81, 243)))


def search_separation(histograms, *, domain="strict"):
    """Exhaustive search for I* minimising the mean discrepancy d_{T}(I) (eq. 8-10).

    Every vector of the domain is evaluated; nothing is restricted to the interval midpoints.
    With cumulative counts a_m(T, I) = n_T(raw < I), the approximation is
    Q_T(I) = 243 C_T - 6 a(I1) - 18 a(I2) - 54 a(I3) - 162 a(I4), so
    R_T - Q_T(I) = u_T(I1, I2) + v_T(I3, I4): the search is a broadcast sum of two small
    tables per patch, reduced over patches by a compiled loop
    (:func:`._kernels.abs_sum_map`) that keeps a tile of the map in cache
    while it adds every patch to it.

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

    Examples
    --------
    >>> h = np.zeros((2, 256), dtype=int); h[0, [3, 9, 27]] = 4; h[1, [81, 243]] = 2
    >>> sep, d, dmap = search_separation(h)
    >>> float(d), dmap.shape
    (0.0, (5, 17, 53, 161))
    """
    h = check_histograms(histograms)
    cells = loaded_cells(h)
    if np.any(cells == 0):
        empty = np.nonzero(cells == 0)[0].tolist()
        raise TactilecalError(f"patches {empty} have no loaded sensel; expected at least one "
                              "raw reading > 0 per patch")
    r1, r2, r3, r4 = separation_domain(domain)
    cum = _cumulative_below(h).astype(np.float64)
    inv_c = 1.0 / cells
    base = raw_sums(h) - 243.0 * cells
    u = ((base[:, None, None] + 6 * cum[:, r1, None] + 18 * cum[:, None, r2])
         * inv_c[:, None, None]).astype(np.float32)
    n = h.shape[0]
    # v_T(I3, I4) = (54 a(I3) + 162 a(I4)) / C_T, built tile by tile inside the kernel
    d_map = _abs_sum_map(u.reshape(n, -1), 54 * cum[:, r3], 162 * cum[:, r4], inv_c,
                         len(r3) * len(r4))
    d_map = d_map.reshape(len(r1), len(r2), len(r3), len(r4)) / n
    return _exact_minimum(h, d_map, (r1, r2, r3, r4))


def _abs_sum_map(u, c3, c4, inv_c, n_k):
    """d-map sums ``sum_T |u[T, a] + v[T, k]|`` in float32 (numba, imported on first use)."""
    from tactilecal.calibration.methods.zvyagin._kernels import abs_sum_map

    out = np.empty((u.shape[1], n_k), dtype=np.float32)
    abs_sum_map(np.ascontiguousarray(u), np.ascontiguousarray(c3), np.ascontiguousarray(c4),
                np.ascontiguousarray(inv_c, dtype=np.float64), out, *_MAP_TILE)
    return out


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
