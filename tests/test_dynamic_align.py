"""Alignment and resampling (Gillis 2013, 4.3.2.1): known lags and rates recovered."""

import numpy as np
import pytest
import xarray as xr

from tactilecal.dynamic import align, estimate_lag, resample_to


def _record(t, values, source=None, dim="time"):
    attrs = {"source": source} if source else {}
    return xr.DataArray(values, dims=dim, coords={"time": (dim, t)}, attrs=attrs)


def _chirp_load(t_s):
    """A broadband, non-periodic load (N): offset plus a chirp switched on at 1 s."""
    on = np.clip(t_s - 1.0, 0.0, None)
    return 500.0 + 80.0 * np.sin(2 * np.pi * (2.0 * on + 6.0 * on**2)) * (t_s > 1.0)


@pytest.mark.parametrize("true_lag_s", [0.7371, -0.2133])
def test_xcorr_lag_within_a_tenth_of_a_sample(true_lag_s):
    rng = np.random.default_rng(5)
    fs_s, fs_r = 4000.0, 5000.0
    t_s = np.arange(0.0, 4.0, 1 / fs_s)
    sensor = _record(t_s, _chirp_load(t_s) + rng.normal(0, 1.0, t_s.size))
    t_r = np.arange(0.0, 3.0, 1 / fs_r)  # its own clock: event at t_r happens at t_r + lag
    reference = _record(t_r, _chirp_load(t_r + true_lag_s) + rng.normal(0, 1.0, t_r.size))
    lag = estimate_lag(sensor, reference)
    assert abs(lag - true_lag_s) < 0.1 / fs_s  # measured 0.009 and 0.017 sample


def test_movie_calibration_case_ramp_and_hold_500_vs_100_hz():
    """Load cell at 500 Hz starting 1.3 s after a 100 Hz summed raw sensor signal."""
    rng = np.random.default_rng(1)

    def load_N(t):  # three ramp-and-hold steps, 0 before
        return np.interp(t, [0, 2, 3, 6, 7, 10, 11, 14, 15],
                         [0, 0, 400, 400, 900, 900, 1500, 1500, 0])

    t_s = np.arange(0, 16, 0.01)
    raw_sum = 3.0 * load_N(t_s) ** 0.8 + rng.normal(0, 2, t_s.size)  # nonlinear, raw
    t_r = np.arange(0, 14, 0.002)
    cell = _record(t_r, load_N(t_r + 1.3) + rng.normal(0, 1, t_r.size), "cell.csv")
    sensor = _record(t_s, raw_sum, "movie.csv", dim="frame")
    lag = estimate_lag(sensor, cell)
    assert abs(lag - 1.3) < 0.01  # within one sensor frame
    on_frames = resample_to(cell, sensor, lag_s=lag)
    assert on_frames.dims == ("frame",)
    # covers only the overlap: the load cell spans 1.3 .. 15.298 s on the sensor clock
    assert on_frames.time[0] >= 1.3 - 1e-9 and on_frames.time[-1] <= 15.298 + 1e-9
    assert on_frames.sizes["frame"] in (1399, 1400)
    truth = load_N(on_frames.time.values)
    assert np.max(np.abs(on_frames.values - truth)) < 8.0  # noise 1 N, ramps smoothed


def test_first_peak_method_of_the_thesis():
    fs = 1000.0
    t = np.arange(0, 3, 1 / fs)
    pulse = np.exp(-(((t - 1.2) / 0.02) ** 2)) + 0.3 * np.exp(-(((t - 2.0) / 0.02) ** 2))
    tr = np.arange(0, 3, 1 / 800)
    ref_pulse = np.exp(-(((tr - 0.9) / 0.02) ** 2))
    lag = estimate_lag(_record(t, pulse), _record(tr, ref_pulse), method="first-peak")
    assert abs(lag - 0.3) < 0.5 / fs


def test_resample_has_no_edge_transient_on_offset_record():
    """120 N offset and a 140 Hz sine cut mid-cycle: edges as good as the middle."""
    tr = np.arange(0.0, 1.0, 1 / 5000)
    ref = _record(tr, 120 + 20 * np.sin(2 * np.pi * 140 * tr + 0.7))
    out = resample_to(ref, np.arange(-0.5, 2.0, 1 / 4000))
    err = out.values - (120 + 20 * np.sin(2 * np.pi * 140 * out.time.values + 0.7))
    assert abs(float(out.time[0])) < 1e-9
    assert np.max(np.abs(err[:-1])) < 0.01  # 0.05 % of the amplitude
    assert np.max(np.abs(err[40:-40])) < 5e-4


def test_align_returns_equal_stamps():
    t = np.arange(0, 2, 1 / 1000)
    s = _record(t, _chirp_load(t + 0.5))
    tr = np.arange(0, 1.5, 1 / 1250)
    r = _record(tr, _chirp_load(tr + 0.8))
    s2, r2, lag = align(s, r)
    assert abs(lag - 0.3) < 1e-3
    np.testing.assert_allclose(s2.time.values, r2.time.values)
    np.testing.assert_allclose(s2.values, r2.values, atol=0.5)


def test_no_overlap_error_names_file():
    t = np.arange(0, 1, 1e-3)
    ref = _record(t, np.sin(t), "cell.csv")
    with pytest.raises(ValueError, match="cell.csv: records do not overlap in time"):
        resample_to(ref, t + 5.0)


def test_unrelated_records_do_not_overlap():
    rng = np.random.default_rng(0)
    t = np.arange(0, 2, 1e-3)
    with pytest.raises(ValueError, match=r"s.csv and c.csv: the records correlate at best "
                                         r"0.\d+ \(at lag .* s\): they do not show the same "
                                         "loading"):
        estimate_lag(_record(t, rng.normal(size=t.size), "s.csv"),
                     _record(t, rng.normal(size=t.size), "c.csv"))


def test_nan_gap_error():
    t = np.arange(0, 1, 1e-3)
    v = np.sin(t)
    v[100:120] = np.nan
    with pytest.raises(ValueError, match=r"cell.csv: 20 NaN/inf values \(gap starting at t = 0.1"):
        estimate_lag(_record(t, np.sin(t)), _record(t, v, "cell.csv"))


def test_irregular_time_error():
    t = np.cumsum(np.r_[0, np.full(99, 1e-3), 5e-3, np.full(99, 1e-3)])
    with pytest.raises(ValueError, match="cell.csv: irregular time column"):
        estimate_lag(_record(np.arange(200) / 1e3, np.sin(t)), _record(t, np.sin(t), "cell.csv"))


def test_other_bad_inputs():
    t = np.arange(0, 1, 1e-3)
    good = _record(t, np.sin(7 * t))
    with pytest.raises(ValueError, match="method='peak'; expected 'xcorr' or 'first-peak'"):
        estimate_lag(good, good, method="peak")
    with pytest.raises(ValueError, match="sensor: expected a 1-D record"):
        estimate_lag(xr.DataArray(np.zeros((3, 3))), good)
    with pytest.raises(ValueError, match="reference: no 'time' coordinate"):
        estimate_lag(good, xr.DataArray(np.zeros(10), dims="x"))
    with pytest.raises(ValueError, match="flat.csv: no peak with prominence"):
        estimate_lag(good, _record(t, np.ones(t.size), "flat.csv"), method="first-peak")
    with pytest.raises(ValueError, match="time stamps do not increase"):
        estimate_lag(good, _record(t[::-1], np.sin(t)))
    with pytest.raises(ValueError, match="max_lag_s=-1"):
        estimate_lag(good, good, max_lag_s=-1)
    with pytest.raises(ValueError, match="3 samples; expected at least 4"):
        estimate_lag(good, _record(t[:3], t[:3]))


def test_jittered_iscan_frame_times_are_accepted_for_alignment():
    """Real I-Scan movies step 0.10 s and sometimes 0.11 s; alignment must cope."""
    steps = np.where(np.arange(299) % 10 == 4, 0.11, 0.10)
    t_s = np.r_[0.0, np.cumsum(steps)]

    def load_N(t):
        return np.interp(t, [0, 5, 8, 14, 17, 24, 27, 40], [0, 0, 300, 300, 800, 800, 0, 0])

    sensor = _record(t_s, 2.0 * load_N(t_s) ** 0.9, "iscan.csv", dim="frame")
    t_r = np.arange(0, 28, 0.002)
    cell = _record(t_r, load_N(t_r + 2.37), "cell.csv")
    lag = estimate_lag(sensor, cell)
    assert abs(lag - 2.37) < 0.02  # a fifth of a frame
    on_frames = resample_to(cell, sensor, lag_s=lag)
    np.testing.assert_allclose(on_frames.values, load_N(on_frames.time.values), atol=10.0)
    assert on_frames.dims == ("frame",)


def test_real_iscan_movie_against_a_shifted_copy(iscan_csv):
    from tactilecal.io import read_tekscan

    movie = read_tekscan(iscan_csv)
    total = movie.sum(("row", "col"))
    total.attrs["source"] = str(iscan_csv)
    t_r = np.arange(0.0, float(total.time[-1]) - 1.0, 0.002)  # 500 Hz "load cell"
    cell = _record(t_r, np.interp(t_r + 0.73, total.time.values, total.values), "cell.csv")
    assert abs(estimate_lag(total, cell) - 0.73) < 0.05  # half a frame


@pytest.mark.parametrize("sizes", [(40, 25), (25, 40), (30, 30), (3, 7)])
def test_normalised_xcorr_is_pearson_on_each_lags_overlap(sizes):
    """Cumulative sums and one FFT give the correlation of the overlapping parts."""
    from scipy import signal

    from tactilecal.dynamic._align import _normalised_xcorr

    rng = np.random.default_rng(4)
    s, r = rng.normal(5.0, 1.0, sizes[0]), rng.normal(-2.0, 3.0, sizes[1])
    got = _normalised_xcorr(s, r, min_overlap=0.5)
    lags = signal.correlation_lags(s.size, r.size, mode="full")
    assert got.shape == lags.shape
    for value, lag in zip(got, lags, strict=True):
        a = s[max(lag, 0):min(s.size, lag + r.size)]  # s[i] meets r[i - lag]
        b = r[max(-lag, 0):max(-lag, 0) + a.size]
        if a.size < 0.5 * min(s.size, r.size) or a.size < 2:
            assert value == -np.inf
        else:
            assert value == pytest.approx(np.corrcoef(a, b)[0, 1], abs=1e-12)


@pytest.mark.parametrize("sizes", [(40, 25), (25, 40), (30, 30)])
def test_normalised_xcorr_at_chosen_lags_equals_every_lag(sizes):
    """Dot products at a few lags give the FFT correlation's values at those lags."""
    from scipy import signal

    from tactilecal.dynamic._align import _normalised_xcorr

    rng = np.random.default_rng(6)
    s, r = rng.normal(5.0, 1.0, sizes[0]), rng.normal(-2.0, 3.0, sizes[1])
    lags = signal.correlation_lags(s.size, r.size, mode="full")
    chosen = np.arange(5, lags.size - 5, 3)
    every = _normalised_xcorr(s, r, min_overlap=0.5)
    some = _normalised_xcorr(s, r, min_overlap=0.5, lag=lags[chosen])
    np.testing.assert_allclose(some, every[chosen], rtol=0, atol=1e-12)


@pytest.mark.parametrize("near_lag_s", [0.7371, 0.7350, 0.2, -0.5])
def test_xcorr_near_a_lag_equals_the_search_over_every_lag(near_lag_s):
    """Near the true lag, or far from it (the window's edge: every lag), the same lag."""
    rng = np.random.default_rng(5)
    t_s = np.arange(0.0, 4.0, 1 / 4000.0)
    sensor = _record(t_s, _chirp_load(t_s) + rng.normal(0, 1.0, t_s.size))
    t_r = np.arange(0.0, 3.0, 1 / 5000.0)
    reference = _record(t_r, _chirp_load(t_r + 0.7371) + rng.normal(0, 1.0, t_r.size))
    every = estimate_lag(sensor, reference)
    near = estimate_lag(sensor, reference, near_lag_s=near_lag_s, near_width_s=16 / 4000.0)
    assert near == pytest.approx(every, abs=1e-9)  # round-off of FFT against dot products
    assert estimate_lag(sensor, reference, near_lag_s=near_lag_s) == pytest.approx(near,
                                                                                 abs=1e-12)
    wide = estimate_lag(sensor, reference, near_lag_s=near_lag_s, near_width_s=0.05)
    assert wide == pytest.approx(every, abs=1e-9)  # 401 lags: cut from the FFT correlation


def test_near_lag_is_refused_for_first_peak_and_a_window_below_a_sample():
    t = np.arange(0.0, 2.0, 1 / 1000.0)
    s = _record(t, np.exp(-((t - 1.0) / 0.05) ** 2))
    with pytest.raises(ValueError, match="near_lag_s=0.1 is for method='xcorr'"):
        estimate_lag(s, s, method="first-peak", near_lag_s=0.1)
    with pytest.raises(ValueError, match=r"near_width_s=0.0001; expected at least one sample"):
        estimate_lag(s, s, near_lag_s=0.0, near_width_s=1e-4)


def test_cubic_through_is_the_not_a_knot_spline_of_make_interp_spline():
    """CubicSpline and the B-spline interpolant are one spline: equal to round-off."""
    from scipy import interpolate

    from tactilecal.dynamic._align import _cubic_through

    rng = np.random.default_rng(9)
    t = np.arange(500) / 4000.0
    y = 120 + 20 * np.sin(2 * np.pi * 10 * t) + rng.normal(0, 0.5, t.size)
    x = np.linspace(-0.001, t[-1] + 0.001, 2000)  # inside and just beyond the ends
    expected = interpolate.make_interp_spline(t, y, k=3)(x, extrapolate=True)
    np.testing.assert_allclose(_cubic_through(t, y)(x), expected, rtol=0, atol=1e-9)
