"""Zvyagin's I* search and pair stage written plainly from the paper, as a test oracle.

Zvyagin (2022), eq. (6)-(12), as directly as they read: every candidate separation I of the
domain (eq. 10) classifies each patch's sensels, and the pair equation (12) of every pair of
patches is solved on its own with :func:`numpy.roots`. Slow, and meant to be obviously
right; it shares no code with the package's compiled search and pair solver, which
``tests/test_zvyagin_fast.py`` compares with it. Not part of the package.
"""

import itertools

import numpy as np

from tactilecal.calibration.methods.zvyagin._approx import separation_domain

CLASS_VALUES = 3.0 ** np.arange(1, 6)
"""A sensel of class m (between I_{m-1} and I_m) reads as 3**m (eq. 6)."""
REAL_TOL = 1e-7
"""A root is real when |imag| <= REAL_TOL * max(1, |root|) (the package's rule)."""
AT_THRESHOLD = 1e-12
"""A root within this relative distance of the threshold is on it: Y > 3 leaves it out."""


def _below(h):
    """Loaded sensels reading under I, n_T(0 < raw < I), for I = 0..256; (patches, 257)."""
    below = np.zeros((h.shape[0], 257))
    below[:, 2:] = np.cumsum(h[:, 1:], axis=1)
    return below


def search_separation(histograms, *, domain="strict"):
    """Return I*, d(I*) and d over the domain: d(I) = mean_T |R_T - Q_T(I)| / C_T (eq. 7-9)."""
    h = np.asarray(histograms, dtype=np.float64)
    raw_sum = (h @ np.arange(256.0))[:, None, None]      # R_T
    cells = h[:, 1:].sum(axis=1)[:, None, None]          # C_T
    below = _below(h)
    r1, r2, r3, r4 = separation_domain(domain)
    d = np.empty((len(r1), len(r2), len(r3), len(r4)))
    a3, a4 = below[:, r3, None], below[:, None, r4]
    for k1, k2 in itertools.product(range(len(r1)), range(len(r2))):
        a1, a2 = below[:, r1[k1], None, None], below[:, r2[k2], None, None]
        counts = (a1, a2 - a1, a3 - a2, a4 - a3, cells - a4)
        q = sum(value * n for value, n in zip(CLASS_VALUES, counts, strict=True))
        d[k1, k2] = np.mean(np.abs(raw_sum - q) / cells, axis=0)
    best = np.unravel_index(np.argmin(d), d.shape)  # ties: the first in lexicographic order
    separation = tuple(int(r[k]) for r, k in zip((r1, r2, r3, r4), best, strict=True))
    return separation, float(d[best]), d


_ROOTS = {}
"""numpy.roots of each polynomial solved, by its coefficients: the faithful and the robust
mode solve the same pairs (only their threshold differs)."""


def _roots(c):
    """``numpy.roots(c[::-1])``, once per coefficient vector."""
    key = c.tobytes()
    if key not in _ROOTS:
        _ROOTS[key] = np.roots(c[::-1])
    return _ROOTS[key]


def _pair_roots(counts_i, counts_j, f_i, f_j, threshold):
    """Real roots Y > threshold of F_j Q_i(Y) - F_i Q_j(Y) = 0, Q(Y) = sum_m n_m Y**m."""
    c = f_j * counts_i - f_i * counts_j                   # c[m - 1] multiplies Y**m
    roots = _roots(c) if np.any(c) else np.array([])  # / Y: the root Y = 0 is out
    real = np.sort(roots[np.abs(roots.imag) <= REAL_TOL * np.maximum(1.0, np.abs(roots))].real)
    for k in range(len(real) - 1):  # a double root split by rounding: its mean is the root
        if abs(real[k + 1] - real[k]) <= REAL_TOL * abs(real[k + 1]):
            real[k] = real[k + 1] = 0.5 * (real[k] + real[k + 1])
    return real[real > threshold * (1.0 + AT_THRESHOLD)]


def _fit_score(y, counts_i, f_i, f_j, h_i, h_j):
    """How well the (A, b) of root Y reproduces both loads from the patches' readings."""
    b = np.log(y) / np.log(3.0)
    a = f_i / np.sum(counts_i * y ** np.arange(1, 6))
    raw = np.arange(256.0)
    return ((a * np.sum(h_i * raw ** b) / f_i - 1) ** 2
            + (a * np.sum(h_j * raw ** b) / f_j - 1) ** 2)


def solve_pairs(counts, load_N, raw_relerr, *, histograms=None, root_choice="smallest",
                max_relerr=0.10, usable=None, b_min=1.0):
    """Solve eq. (12) pair by pair; same arguments and keys as the package's solve_pairs."""
    f = np.asarray(load_N, dtype=np.float64)
    i, j = np.triu_indices(len(f), k=1)
    n_roots, y = np.zeros(len(i), dtype=int), np.full(len(i), np.nan)
    for p, (a, b) in enumerate(zip(i, j, strict=True)):
        roots = _pair_roots(counts[a], counts[b], f[a], f[b], 3.0 ** b_min)
        n_roots[p] = len(roots)
        if len(roots) > 1 and root_choice == "best-fit":
            scores = [_fit_score(r, counts[a], f[a], f[b], histograms[a], histograms[b])
                      for r in roots]
            y[p] = roots[int(np.argmin(scores))]
        elif len(roots):
            y[p] = roots[0]
    q_i = np.array([np.sum(counts[a] * yy ** np.arange(1, 6)) for a, yy in zip(i, y, strict=True)])
    bad_raw = (raw_relerr[i] >= max_relerr) | (raw_relerr[j] >= max_relerr)
    category = np.where(n_roots == 0, "N", np.where(bad_raw, "R", "V"))
    if usable is not None:
        category = np.where(usable[i] & usable[j], category, "X")
    return {"i": i, "j": j, "n_roots": n_roots, "Y": y, "b": np.log(y) / np.log(3.0),
            "A": f[i] / q_i, "category": category.astype("<U1")}


def _usable_pairs(pairs, usable):
    for a, b, category, n in zip(pairs["i"], pairs["j"], pairs["category"],
                                 pairs["n_roots"], strict=True):
        if usable[a] and usable[b]:
            yield a, b, category, n


def pair_share_table(group, names, pairs, usable):
    """Pairs, valid pairs and pairs with a root per load combination (paper: 2-5 kg 34% ...)."""
    tally = {}
    for a, b, category, n in _usable_pairs(pairs, usable):
        key = (min(group[a], group[b]), max(group[a], group[b]))
        n_pairs, n_valid, n_root = tally.get(key, (0, 0, 0))
        tally[key] = (n_pairs + 1, n_valid + (category in ("V", "O")), n_root + (n > 0))
    rows = []
    for g, h in itertools.combinations_with_replacement(range(len(names)), 2):
        n_pairs, n_valid, n_root = tally.get((g, h), (0, 0, 0))
        rows.append({"loads": f"{names[g]} - {names[h]}", "pairs": n_pairs, "valid": n_valid,
                     "with_root": n_root, "share": n_valid / n_pairs if n_pairs else np.nan})
    return rows


def partner_share(pairs, usable, n):
    """Share of its usable partners with which each patch has a root Y > 3**b_min."""
    partners = np.zeros(n)
    for a, b, _, n_roots in _usable_pairs(pairs, usable):
        if n_roots > 0:
            partners[[a, b]] += 1
    return partners / max(int(np.sum(usable)) - 1, 1)
