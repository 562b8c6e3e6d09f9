"""Zvyagin (2022) steps on arrays: approximation, I* search, pair roots, power law, E."""

import itertools

import numpy as np
import pytest

from tactilecal.calibration.methods.zvyagin._approx import (
    CLASS_VALUES,
    approximate_raw_sums,
    class_counts,
    patch_discrepancy,
    search_separation,
    separation_domain,
)
from tactilecal.calibration.methods.zvyagin._fit import energy, fit_power_law, minimise_energy
from tactilecal.calibration.methods.zvyagin._pairs import (
    polynomial_roots,
    quartic_coefficients,
    solve_pairs,
)
from tactilecal.simulate import patch_histograms


def _hist(values_per_patch):
    h = np.zeros((len(values_per_patch), 256), dtype=np.int64)
    for t, vals in enumerate(values_per_patch):
        np.add.at(h[t], np.asarray(vals, dtype=np.int64), 1)
    return h


def _random_hist(n, seed):
    rng = np.random.default_rng(seed)
    return _hist([np.clip(np.round(rng.lognormal(3, 1, rng.integers(20, 200))), 0, 255)
                  .astype(int) for _ in range(n)])


# ---------------------------------------------------------------- eq. 5-7
def test_class_boundaries_follow_eq5():
    # [1, I1) -> 3 (raw 1 and 2 included), [I1, I2) -> 9, ..., [I4, 255] -> 243
    h = _hist([[1, 2, 5, 6, 17, 18, 53, 54, 161, 162, 255, 0, 0]])
    assert class_counts(h, (6, 18, 54, 162)).tolist() == [[3, 2, 2, 2, 2]]
    assert approximate_raw_sums(h, (6, 18, 54, 162)).tolist() == [3 * 3 + 2 * (9 + 27 + 81 + 243)]


def test_discrepancy_is_eq7():
    h = _hist([[4, 10, 30], [100, 200]])
    r = np.array([44, 300])
    q = np.array([3 + 9 + 27, 81 + 243])
    c = np.array([3, 2])
    np.testing.assert_allclose(patch_discrepancy(h, (6, 18, 54, 162)), np.abs(r - q) / c)


def test_separation_out_of_domain_is_refused():
    with pytest.raises(ValueError, match=r"separation I2 = 30; expected 9 < I2 <= 27"):
        class_counts(_hist([[5]]), (6, 30, 54, 162))


# ---------------------------------------------------------------- eq. 8-10
def test_domain_sizes():
    assert np.prod([len(r) for r in separation_domain("strict")]) == 725_305
    closed = separation_domain("closed")
    assert np.prod([len(r) for r in closed]) == 944_784
    assert closed[0][-1] == 9 and closed[3][-1] == 243
    with pytest.raises(ValueError, match=r"domain = 'open'; expected one of"):
        separation_domain("open")


def test_search_map_equals_plain_eq8_everywhere_sampled():
    h = _random_hist(12, seed=4)
    sep, d_min, d_map = search_separation(h)
    ranges = separation_domain()
    rng = np.random.default_rng(0)
    for _ in range(40):
        k = [rng.integers(len(r)) for r in ranges]
        vec = [int(r[i]) for r, i in zip(ranges, k, strict=True)]
        # the map is accumulated in float32
        assert d_map[tuple(k)] == pytest.approx(patch_discrepancy(h, vec).mean(), rel=1e-5)
    assert d_min == pytest.approx(patch_discrepancy(h, sep).mean(), rel=1e-12)
    assert d_min == pytest.approx(float(d_map.min()), rel=1e-5)
    # no vector of the domain beats I* (exact float64 check on the near-minimal ones)
    assert d_min <= min(patch_discrepancy(h, v).mean() for v in [(4, 10, 28, 82), sep])


def test_search_is_exhaustive_on_a_small_case():
    """Brute force over the whole domain by itertools agrees (few patches, so it is quick)."""
    h = _random_hist(2, seed=9)
    _, d_min, _ = search_separation(h)
    r1, r2, r3, r4 = separation_domain()
    cells = h[:, 1:].sum(1)
    cum = np.concatenate([np.zeros((2, 2), int), np.cumsum(h[:, 1:], 1)], axis=1)
    r = h @ np.arange(256)
    best = min(
        np.mean(np.abs(r - 243 * cells + 6 * cum[:, a] + 18 * cum[:, b] + 54 * cum[:, c]
                       + 162 * cum[:, d]) / cells)
        for a, b, c, d in itertools.product(r1, r2, r3[::4], r4[::8]))
    assert d_min <= best + 1e-12


def test_closed_domain_reaches_I1_equal_9():
    # the closed domain adds I1 = 9 (and I2 = 27, ...); its map entries are eq. (8) too
    h = _hist([[4, 4, 8, 9, 9, 26, 80, 242]])
    _, _, d_closed = search_separation(h, domain="closed")
    assert d_closed.shape == (6, 18, 54, 162)
    assert d_closed[5, 0, 0, 0] == pytest.approx(patch_discrepancy(h, (9, 10, 28, 82))[0])


def test_search_refuses_empty_patch():
    with pytest.raises(ValueError, match=r"patches \[1\] have no loaded sensel"):
        search_separation(_hist([[5, 6], []]))


def test_histogram_shape_is_checked():
    with pytest.raises(ValueError, match=r"histograms has shape \(3, 10\); expected"):
        search_separation(np.zeros((3, 10), dtype=int))
    with pytest.raises(ValueError, match=r"patches \[0\] hold negative counts"):
        search_separation(-np.ones((1, 256), dtype=int))


# ---------------------------------------------------------------- eq. 11-13
def test_batched_roots_match_numpy_roots_for_every_degree():
    rng = np.random.default_rng(1)
    c = rng.normal(size=(60, 5))
    c[10:20, 4] = 0.0           # cubics
    c[20:30, 3:] = 0.0          # quadratics
    c[30:35, 2:] = 0.0          # linear
    c[35:38, 1:] = 0.0          # constants: no roots
    roots = polynomial_roots(c)
    for row, got in zip(c, roots, strict=True):
        nz = np.nonzero(row)[0]
        want = np.roots(row[: nz.max() + 1][::-1]) if nz.max() > 0 else np.array([])
        got = got[~np.isnan(got)]
        assert got.size == want.size
        np.testing.assert_allclose(np.sort_complex(got), np.sort_complex(want), atol=1e-9)


def test_exact_powers_of_three_give_the_true_A_b_for_every_pair():
    """Readings exactly 3**m and loads F = A sum X**b: eq. (12) has the root Y = 3**b."""
    rng = np.random.default_rng(2)
    a_true, b_true = 0.0035, 1.16
    counts = rng.integers(0, 40, size=(8, 5))
    counts[:, 0] += 1
    h = np.zeros((8, 256), dtype=np.int64)
    h[:, CLASS_VALUES] = counts
    load = a_true * (counts @ CLASS_VALUES ** b_true)
    assert class_counts(h, (6, 18, 54, 162)).tolist() == counts.tolist()
    res = solve_pairs(counts, load, np.zeros(8))
    with_root = res["n_roots"] > 0
    assert with_root.mean() > 0.9
    # pairs with one root > 3: it is the truth
    one = res["n_roots"] == 1
    assert one.sum() >= 20
    np.testing.assert_allclose(res["b"][one], b_true, rtol=1e-9)
    np.testing.assert_allclose(res["A"][one], a_true, rtol=1e-9)
    # pairs with several roots: 3**b_true is one of them (exact readings cannot tell which)
    from tactilecal.calibration.methods.zvyagin._pairs import roots_above
    multi = np.nonzero(res["n_roots"] > 1)[0]
    cand = roots_above(polynomial_roots(quartic_coefficients(counts, load, res["i"][multi],
                                                     res["j"][multi])))
    assert np.all(np.nanmin(np.abs(cand - 3 ** b_true), axis=1) < 1e-8)
    # swapping the patches only flips the sign of the coefficients (symmetric chart)
    c_ij = quartic_coefficients(counts, load, np.array([0]), np.array([1]))
    c_ji = quartic_coefficients(counts, load, np.array([1]), np.array([0]))
    np.testing.assert_allclose(c_ij, -c_ji)


def test_ten_percent_rule_and_no_root_categories():
    counts = np.array([[10, 5, 2, 1, 0], [20, 5, 1, 0, 0], [10, 0, 0, 0, 0], [5, 5, 5, 5, 1]])
    load = 0.0035 * (counts @ CLASS_VALUES ** 1.16)
    load[2] = 100.0   # patch 2 is heavier yet reads lower than patch 0 in every class
    relerr = np.array([0.0, 0.10, 0.0, 0.0999])  # the rule rejects at >= 10%
    res = solve_pairs(counts, load, relerr)
    cat = {(int(i), int(j)): c for i, j, c in zip(res["i"], res["j"], res["category"],
                                                    strict=True)}
    assert cat[(0, 2)] == "N"
    assert cat[(0, 1)] == "R" and cat[(1, 3)] == "R"
    assert cat[(0, 3)] == "V"
    usable = np.array([True, True, True, False])
    assert solve_pairs(counts, load, relerr, usable=usable)["category"][2] == "X"


def test_root_choice_smallest_vs_best_fit_and_bad_choice():
    with pytest.raises(ValueError, match=r"root_choice = 'largest'; expected one of"):
        solve_pairs(np.ones((2, 5), int), np.ones(2), np.zeros(2), root_choice="largest")
    with pytest.raises(ValueError, match=r"needs the histograms"):
        # a pair with two roots > 3: (Y - 4)(Y - 5) Y^0 ... built from counts
        counts = np.array([[20, 0, 1, 0, 0], [0, 9, 0, 0, 0]])
        load = np.array([1.0, 1.0])
        assert (solve_pairs(counts, load, np.zeros(2))["n_roots"] == 2).all()
        solve_pairs(counts, load, np.zeros(2), root_choice="best-fit")


# ---------------------------------------------------------------- eq. 14-15
def test_power_law_recovers_alpha_beta_with_noise():
    rng = np.random.default_rng(3)
    b = rng.uniform(1.0, 1.6, 500)
    a = 0.006 * b ** -4.5 * np.exp(rng.normal(0, 0.02, b.size))
    fit = fit_power_law(a, b)
    assert fit["beta"] == pytest.approx(-4.5, abs=0.1)
    assert fit["alpha"] == pytest.approx(0.006, rel=0.02)
    assert fit["r2"] > 0.95


def test_trim_and_mad_resist_far_pairs():
    rng = np.random.default_rng(5)
    b = np.r_[rng.uniform(1.0, 1.5, 400), rng.uniform(4, 8, 20)]
    a = np.r_[0.006 * b[:400] ** -4.5, np.full(20, 1e-3)] * np.exp(rng.normal(0, 0.01, 420))
    plain = fit_power_law(a, b)
    assert abs(plain["beta"] + 4.5) > 1.0          # pulled hard by the 20 far pairs
    trimmed = fit_power_law(a, b, outliers="trim")
    assert trimmed["beta"] == pytest.approx(-4.5, abs=0.15)
    assert trimmed["inlier"][400:].sum() == 0
    # residual clipping is masked by high-leverage pairs: why the robust mode trims b
    assert abs(fit_power_law(a, b, outliers="mad")["beta"] + 4.5) > 1.0
    # ... but it does remove outliers in A at ordinary b
    a2 = a[:400].copy()
    a2[:30] *= 3.0
    mad = fit_power_law(a2, b[:400], outliers="mad")
    assert mad["beta"] == pytest.approx(-4.5, abs=0.15) and mad["inlier"][:30].sum() == 0
    with pytest.raises(ValueError, match=r"outliers = 'huber'; expected"):
        fit_power_law(a, b, outliers="huber")
    with pytest.raises(ValueError, match=r"trim = 0.6; expected 0 <= trim < 0.5"):
        fit_power_law(a, b, outliers="trim", trim=0.6)


def test_energy_minimum_on_the_true_curve():
    h, load, _ = patch_histograms(30, A_N=0.0035, b=1.16, threshold=0, seed=6)
    beta = -5.0
    alpha = 0.0035 / 1.16 ** beta
    res = minimise_energy(h, load, alpha, beta, (1.0, 1.5))
    assert res["b0"] == pytest.approx(1.16, abs=0.01)
    assert not res["at_bound"]
    assert res["E"] <= energy(np.linspace(1.0, 1.5, 51), h, load, alpha, beta).min() + 1e-12
