"""The power fit for many points (movie calibration) equals the direct one to round-off.

``_minimise_b_many`` brackets the minimum on a subsample, then reads all the histograms once
(Chebyshev moments) for a Brent search, and finds l1 medians by selection; ``_minimise_b``
below ``COMPILED_MIN_POINTS`` sums ``hist @ LEVELS**b`` for every trial exponent of nested
grids and sorts. Both minimise the same cost to 1e-10 in b, so they must agree to about that;
1e-9 relative is the tolerance the movie path promises.
"""

import numpy as np
import pytest

import tactilecal.calibration._powerfit as powerfit
from tactilecal.calibration import calibrate_movie, find_dead_sensels, frame_histograms
from tactilecal.simulate import make_sensor, ramp_hold


@pytest.fixture(scope="module", params=[(0, 1), (3, 4)], ids=["sensor0", "sensor3"])
def movie(request):
    """Histograms and loads of the loaded frames of a simulated ramp-and-hold movie."""
    sensor_seed, seed = request.param
    session = ramp_hold(make_sensor("5051", seed=sensor_seed), seed=seed)
    hist = frame_histograms(session.raw.values).astype(float)
    keep = (session.load_N > 0.02 * session.load_N.max()) & (hist[:, 1:].sum(axis=1) > 0)
    return hist[keep], session.load_N[keep], session


def _both(hist, load, objective, censored, monkeypatch):
    monkeypatch.setattr(powerfit, "COMPILED_MIN_POINTS", 0)  # 2,179 points: force each path
    many = powerfit._minimise_b(hist, load, objective, powerfit.B_BOUNDS, censored=censored)
    monkeypatch.setattr(powerfit, "COMPILED_MIN_POINTS", 2 ** 62)
    direct = powerfit._minimise_b(hist, load, objective, powerfit.B_BOUNDS, censored=censored)
    return many, direct


@pytest.mark.parametrize("objective", ["l1", "l2", "relative", "l1-censored"])
def test_many_points_fit_equals_direct_fit(movie, objective, monkeypatch):
    hist, load, _ = movie
    censored = None
    if objective == "l1-censored":
        objective, censored = "l1", np.random.default_rng(2).random(len(load)) < 0.05
    (b, A, cost, n_eval), (b0, A0, cost0, n_eval0) = _both(hist, load, objective, censored,
                                                           monkeypatch)
    # both searches stop within 1e-10 of b: that is the agreement to expect
    assert b == pytest.approx(b0, rel=1e-9, abs=0)
    assert A == pytest.approx(A0, rel=1e-9, abs=0)
    assert cost == pytest.approx(cost0, rel=1e-9, abs=0)
    assert n_eval <= n_eval0


@pytest.mark.parametrize("half_width", [0.02, 1e-7], ids=["narrow", "missed"])
@pytest.mark.parametrize("objective", ["l1", "relative"])
def test_bracket_from_a_subsample_gives_the_direct_fit(movie, objective, half_width,
                                                       monkeypatch):
    """A bracket found on every 4th point; one that misses b (1e-7 wide) falls back."""
    hist, load, _ = movie
    step = len(load) // (len(load) // 4)
    b_all, b_sub = (powerfit._minimise_b_grid(h, f, objective, powerfit.B_BOUNDS, 13, 1e-10,
                                              None)[0]
                    for h, f in ((hist, load), (hist[::step], load[::step])))
    assert abs(b_sub - b_all) > 1e-5  # so the 1e-7 bracket around b_sub misses b_all
    monkeypatch.setattr(powerfit, "BRACKET_POINTS", len(load) // 4)
    monkeypatch.setattr(powerfit, "BRACKET_HALF_WIDTH", half_width)
    (b, A, _, _), (b0, A0, _, _) = _both(hist, load, objective, None, monkeypatch)
    assert b == pytest.approx(b0, rel=1e-9, abs=0)
    assert A == pytest.approx(A0, rel=1e-9, abs=0)


def test_search_falls_back_to_the_grid_without_a_minimum_in_the_bracket(movie):
    """A bracket whose middle is not below its ends is refused (None), not searched."""
    hist, load, _ = movie
    b0 = powerfit._minimise_b_grid(hist, load, "l1", powerfit.B_BOUNDS, 13, 1e-10, None)[0]
    assert powerfit._search_bracket(hist, load, "l1", None, (b0 + 0.01, b0 + 0.05),
                                    b0 + 0.03, 1e-10) is None
    assert powerfit._search_bracket(hist, load, "l2", None, (b0 + 0.01, b0 + 0.05),
                                    b0 + 0.03, 1e-10) is None


def test_many_points_fit_raises_at_the_edge_of_b_bounds(movie, monkeypatch):
    hist, load, _ = movie
    monkeypatch.setattr(powerfit, "COMPILED_MIN_POINTS", 0)
    with pytest.raises(ValueError, match="at the edge of b_bounds"):
        powerfit._minimise_b(hist, load, "l1", (1.3, 4.0))


def test_chebyshev_sums_equal_direct_sums(movie):
    hist, _, _ = movie
    sums = powerfit._Sums(hist, 0.85, 1.5)
    b = np.array([0.85, 0.9, 1.16, 1.2345, 1.5])
    direct = (hist @ powerfit.LEVELS[:, None] ** b).T
    np.testing.assert_allclose(sums(b), direct, rtol=1e-13, atol=0)
    _, slope = sums(b, slope=True)
    np.testing.assert_allclose(slope, (hist @ (powerfit.LEVELS ** b[:, None]
                                               * powerfit.LOG_LEVELS).T).T,
                               rtol=1e-11, atol=0)


@pytest.mark.parametrize("window", [(-np.inf, np.inf), (0.9, 1.1), (5.0, 6.0)])
def test_selected_median_equals_sorted_median(window):
    """With integer weights every sum is exact, so the two must be equal, ties included."""
    from tactilecal.calibration._powerfit_kernels import l1_costs

    rng = np.random.default_rng(3)
    for n in (1, 2, 7, 30, 1000, 5001):
        load = rng.integers(1, 40, n).astype(float)
        sums = rng.integers(1, 30, (3, n)).astype(float)  # ratios with many ties
        censored = rng.random(n) < 0.3
        censored[:2] = False
        m = len(sums)
        cost, A = l1_costs(sums, load, censored, np.full(m, window[0]), np.full(m, window[1]))
        for c in range(3):
            expected = powerfit._censored_median(load / sums[c], sums[c], censored)
            assert A[c] == expected
            r = A[c] * sums[c] - load
            assert cost[c] == pytest.approx(np.abs(np.where(censored, np.maximum(r, 0), r))
                                            .sum(), rel=1e-12)


def test_dead_sensels_of_a_dask_movie_are_found_block_by_block(movie):
    _, _, session = movie
    raw = session.raw.copy()
    raw[:, 7, 9] = 0.0  # a dead sensel inside the loaded area
    lazy = raw.chunk({"frame": 700})
    found, streamed = find_dead_sensels(raw), find_dead_sensels(lazy.data)
    np.testing.assert_array_equal(found.mask, streamed.mask)
    np.testing.assert_array_equal(found.evidence_frames, streamed.evidence_frames)
    assert found.mask[7, 9]
    a = calibrate_movie(raw, session.loadcell, mask_dead=True, lag_s=0.37, method="power")
    b = calibrate_movie(lazy, session.loadcell, mask_dead=True, lag_s=0.37, method="power")
    assert a.params == b.params
    assert a.non_working == b.non_working


@pytest.mark.parametrize("storage", ["float64", "float32", "uint8", "dask"])
def test_movie_calibration_is_the_same_on_either_path(movie, storage, monkeypatch):
    _, _, session = movie
    raw = session.raw
    if storage in ("float32", "uint8"):
        raw = raw.astype(storage)
    elif storage == "dask":
        raw = raw.chunk({"frame": 500})
    # the prediction interval's refits run on the same path (3 refits: each is a whole
    # movie fit on both paths, and any one that differed would move the bounds)
    options = {"n_interval_resamples": 3} if storage == "float64" else {}
    monkeypatch.setattr(powerfit, "COMPILED_MIN_POINTS", 0)
    many = calibrate_movie(raw, session.loadcell, **options, method="power")
    monkeypatch.setattr(powerfit, "COMPILED_MIN_POINTS", 2 ** 62)
    direct = calibrate_movie(raw, session.loadcell, **options, method="power")
    assert many.diagnostics["movie"]["lag_s"] == pytest.approx(direct.diagnostics["movie"]["lag_s"],
                                                           rel=1e-9)
    for key in ("A", "b"):
        assert many.params[key] == pytest.approx(direct.params[key], rel=1e-9, abs=0)
    if options:  # refits equal to 1e-9 give relative bounds (~1e-2 wide) equal to ~1e-6
        ours, theirs = (r.prediction_interval.to_dict() for r in (many, direct))
        assert ours.keys() == theirs.keys() and ours["n_failed"] == theirs["n_failed"] == 0
        for key in ("rel_low", "rel_high"):
            assert ours[key] == pytest.approx(theirs[key], rel=1e-6)


@pytest.mark.parametrize("n", [50, 5000, 9000], ids=["numpy", "compiled", "compiled-blocks"])
@pytest.mark.parametrize("dtype", [np.uint16, np.int64, np.float64])
@pytest.mark.parametrize("columns", [3, 10], ids=["every-bin", "filled-bins"])
def test_hist_products_equal_the_dense_product(n, dtype, columns):
    """Counts in any dtype, mostly empty bins as a movie's: the dense product to round-off.

    Up to ``DENSE_MAX_COLUMNS`` (4) columns the kernel multiplies every bin, beyond it the
    filled ones only.
    """
    rng = np.random.default_rng(5)
    hist = np.zeros((n, 256), dtype)
    rows, levels = rng.integers(0, n, 20 * n), rng.integers(0, 256, 20 * n)
    np.add.at(hist, (rows, levels), 1)
    matrix = rng.random((256, columns))
    dense = hist.astype(float) @ matrix
    np.testing.assert_allclose(powerfit.hist_products(hist, matrix), dense.T, rtol=1e-13)
    np.testing.assert_allclose(powerfit.hist_products(hist, matrix[:, 0]), dense.T[:1],
                               rtol=1e-13)
    if n >= 2 * powerfit.PRODUCT_ROWS_PER_THREAD:  # blocks of rows on the cores, each row as alone
        from tactilecal._numba import read_only
        from tactilecal.calibration._powerfit_kernels import hist_dot

        counts = hist if hist.dtype in powerfit.KERNEL_COUNT_TYPES else hist.astype(float)
        whole = hist_dot(read_only(counts), read_only(matrix), np.empty((columns, n)), 0)
        np.testing.assert_array_equal(powerfit.hist_products(hist, matrix), whole)


def test_the_product_kernel_sees_uint16_and_float64_counts_only():
    """Other counts are widened, and every input is read-only (a remembered Chebyshev table
    is): numba compiles the kernel for no third type and no writable twin."""
    from numba import types

    from tactilecal.calibration._powerfit_kernels import hist_dot

    hist = np.zeros((powerfit.COMPILED_MIN_POINTS, 256), np.int32)
    hist[:, 7] = 3
    levels = np.arange(256.0)
    frozen = levels.copy()
    frozen.flags.writeable = False
    for counts in (hist, hist.astype(np.uint16)):
        for matrix in (levels, frozen):
            np.testing.assert_array_equal(powerfit.hist_products(counts, matrix), 21.0)
    assert {sig[0].dtype for sig in hist_dot.signatures} <= {types.uint16, types.float64}
    assert all(sig[0].mutable is False and sig[1].mutable is False
               for sig in hist_dot.signatures)


def test_raw_sums_from_the_reassociated_product_are_exact():
    """Integer sums below 2**53 come out exact in any order of addition (the raw sum)."""
    rng = np.random.default_rng(8)
    hist = rng.integers(0, 1936, (6000, 256)).astype(np.uint16)
    levels = np.column_stack([np.arange(256.0), np.ones(256)])
    raw_sum, working = powerfit.hist_products(hist, levels)
    np.testing.assert_array_equal(raw_sum, (hist.astype(np.int64) * np.arange(256)).sum(axis=1))
    np.testing.assert_array_equal(working, hist.astype(np.int64).sum(axis=1))


def test_movie_histograms_are_uint16_counts_equal_to_frame_histograms(movie):
    from tactilecal.calibration._movie import _histograms

    raw = movie[2].raw.values
    hist = _histograms(raw, None, None, lambda spans, **_: spans, numba_loaded=True)
    assert hist.dtype == np.uint16
    np.testing.assert_array_equal(hist, frame_histograms(raw))


@pytest.mark.parametrize("n_terms", [2, 4, 10, 23])
def test_chebyshev_polynomials_of_one_exponent_equal_the_array_recurrence(n_terms):
    """The Python-float path for one t is bit for bit the numpy recurrence (same operations)."""
    for t in (-1.0, -0.37, 0.0, 0.123456789, 1.0):
        one = powerfit._chebyshev_t(t, n_terms)
        many = powerfit._chebyshev_t(np.array([t, 0.5]), n_terms)
        assert one[0].shape == one[1].shape == (n_terms, 1)
        np.testing.assert_array_equal(one[0][:, 0], many[0][:, 0])
        np.testing.assert_array_equal(one[1][:, 0], many[1][:, 0])
    t = np.cos(0.3)  # T_j(cos x) = cos(j x): a known truth
    np.testing.assert_allclose(powerfit._chebyshev_t(t, n_terms)[0][:, 0],
                               np.cos(0.3 * np.arange(n_terms)), atol=1e-13)
