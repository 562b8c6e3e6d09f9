"""apply_filter's multirate method against the direct FIR and against the gain law."""

import re

import numpy as np
import pytest
import xarray as xr

from tactilecal.dynamic import CorrectionFilter, apply_filter
from tactilecal.dynamic._multirate import plan_multirate

FS_HZ = 4000.0


#: These tests check the realisations of a filter on random walks and white noise, whose
#: power lies mostly above the filters' bands: the warning that says so is tested in
#: tests/test_dynamic_band.py.
pytestmark = pytest.mark.filterwarnings("ignore::tactilecal.dynamic._apply.BandWarning")


@pytest.fixture(scope="module")
def thesis_filter():
    """Gillis (2013) law 1 + 0.11 log10(f + 1), band 1..140 Hz, sampled at 4000 Hz."""
    return CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=FS_HZ, band_hz=(1, 140))


def _record(values):
    n = values.shape[0]
    return xr.DataArray(values, dims=("frame", "sensel")[:values.ndim],
                        coords={"time": ("frame", np.arange(n) / FS_HZ)},
                        attrs={"source": "rec.nc"})


@pytest.fixture(scope="module")
def walk():
    """Random walk plus white noise on a large offset, 6 sensels, one outside the sensor."""
    rng = np.random.default_rng(11)
    x = 100 + 0.1 * rng.standard_normal((12_000, 6)).cumsum(axis=0)
    x += rng.standard_normal(x.shape)
    x[:, 4] = np.nan
    return _record(x)


def test_plan_decimates_only_a_band_limited_correction(thesis_filter):
    plan = plan_multirate(thesis_filter)
    assert plan.factor == 5  # floor(4000 / (4 * (140 + 35)))
    assert plan.correction.size == 801  # 4001 / 5: the same 1 Hz resolution
    assert np.sum(plan.lowpass) == pytest.approx(1.0, abs=1e-12)
    assert abs(np.sum(plan.correction)) < 1e-12  # no change to a static load
    hold = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=FS_HZ, band_hz=(1, 140),
                                       outside="hold")
    assert plan_multirate(hold) is None  # gain held to Nyquist: nothing to decimate
    wide = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000, band_hz=(1, 140))
    assert plan_multirate(wide) is None  # P = floor(1000 / 700) = 1


def test_multirate_equals_direct_fir(walk, thesis_filter):
    direct = apply_filter(walk, thesis_filter, method="direct", precision="double").values
    auto = apply_filter(walk, thesis_filter, precision="double").values
    single = apply_filter(walk, thesis_filter).values
    span = np.nanmax(walk.values) - np.nanmin(walk.values)
    np.testing.assert_allclose(auto, direct, atol=2e-5 * span)  # measured 2.7e-6
    np.testing.assert_allclose(single, auto, atol=1e-6 * span)  # measured 1.6e-8
    assert np.isnan(auto[:, 4]).all() and np.isfinite(np.delete(auto, 4, axis=1)).all()


@pytest.mark.parametrize("chunk", [700, 3001])
def test_multirate_dask_chunks_equal_memory(walk, thesis_filter, chunk):
    memory = apply_filter(walk, thesis_filter, precision="double")
    lazy = apply_filter(walk.chunk({"frame": chunk}), thesis_filter, precision="double")
    assert lazy.chunks is not None
    np.testing.assert_allclose(lazy.values, memory.values, atol=1e-9)


def test_multirate_restores_the_gain_law_and_leaves_high_frequencies(thesis_filter):
    t = np.arange(16_000) / FS_HZ
    f_hz = np.array([5.0, 99.0, 140.0, 700.0, 1500.0])  # in band, at its top, far above
    x = 50 + np.sin(2 * np.pi * f_hz[:, None] * t).T  # one sine per sensel
    out = apply_filter(_record(x), thesis_filter).values[4000:-4000] - 50
    amplitude = np.abs(np.fft.rfft(out, axis=0)).max(axis=0) * 2 / out.shape[0]
    np.testing.assert_allclose(amplitude, thesis_filter.gain(f_hz), rtol=2e-3)
    assert thesis_filter.gain(99.0) == pytest.approx(1 + 0.11 * np.log10(100))


def test_multirate_edges_follow_the_odd_reflection(thesis_filter):
    x = np.linspace(0.0, 10.0, 9000) + 1000.0  # a 1-D record: a ramp on a large offset
    out = apply_filter(_record(x), thesis_filter).values
    np.testing.assert_allclose(out, x, atol=1e-6 * 10)  # G(0) = 1: a ramp passes unchanged


def test_multirate_nan_gap_and_method_errors(walk, thesis_filter):
    gap = walk.copy()
    gap[2500, 1] = np.nan
    with pytest.raises(ValueError, match="rec.nc: sensel 1 .* NaN from frame index 2500"):
        apply_filter(gap, thesis_filter)
    with pytest.raises(ValueError, match="method='fast'; expected 'auto' or 'direct'"):
        apply_filter(walk, thesis_filter, method="fast")


def _streamed_peak_bytes(tmp_path, n_frames, filt):
    """Filter a NetCDF recording opened lazily and stream it to NetCDF; return peak memory."""
    import tracemalloc

    from tactilecal.io import read_netcdf, write_netcdf

    rng = np.random.default_rng(5)
    x = 20 + 0.01 * rng.standard_normal((n_frames, 4, 8)).cumsum(axis=0)
    rec = xr.DataArray(x, dims=("frame", "row", "col"),
                       coords={"time": ("frame", np.arange(n_frames) / filt.fs_hz)})
    src, dst = tmp_path / f"rec{n_frames}.nc", tmp_path / f"out{n_frames}.nc"
    write_netcdf(rec, src)
    expected = apply_filter(rec, filt).values
    del rec, x
    tracemalloc.start()  # NumPy reports its buffers to tracemalloc
    with xr.open_dataarray(src, chunks={"frame": 2500}) as lazy:
        write_netcdf(apply_filter(lazy, filt), dst)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    back = read_netcdf(dst).values
    np.testing.assert_allclose(back, expected, atol=1e-6 * np.ptp(expected))
    return peak


@pytest.mark.slow  # a memory profile of two long records (7.7 and 31 MB), 4 s
def test_streamed_recording_memory_does_not_grow_with_its_length(tmp_path):
    # the streamed path itself (a NetCDF recording opened lazily, filtered, written) runs in
    # the default tests: tests/test_dynamic_cli.py (dynamic apply --chunk-frames,
    # filter_recording) and tests/test_dynamic_apply_scale.py (the lazy read's graph)
    filt = CorrectionFilter.from_model(("log", {"A": 0.05}), fs_hz=1000.0, band_hz=(1, 40))
    assert plan_multirate(filt).factor == 5
    size = {n: n * 32 * 8 for n in (30_000, 120_000)}  # 7.7 and 31 MB of float64
    short, long = (_streamed_peak_bytes(tmp_path, n, filt) for n in size)
    # 12 and 48 chunks of 2500 frames: measured, the peak grows by 0.12 of the added data and
    # is 0.30 of the long record (twice the sizes and chunks: 0.15-0.22 and 0.33-0.35;
    # map_overlap before issue 16: 0.07-0.08 and 0.30). Why: stage 3 of a chunk adds
    # its correction to the chunk itself, so dask keeps each input chunk from its stage 1
    # until its stage 3, which waits (through stage 2 of the next chunk) for stage 1 of the
    # chunk after next and rows of the one after that: at least 4 input chunks resident,
    # where map_overlap needed 2-3; and dask's order of this graph, written to NetCDF, runs
    # ahead in several places at once, each holding its edge chunks. Counted with a dask
    # callback: 7 of 12 input chunks (1.28 MB each) resident at the peak at 60k frames, 13
    # of 48 at 240k. Re-reading each chunk for stage 3 (a copy of its load task) brought the
    # growth to 0.095, but copies dask's private task objects (and for a computed input
    # computes its last step twice) and reads the input twice: 1.15x the time on a 69 MB
    # record, 0.82x on a 1.5 GB one, best of 4 on the shared 2 cores. Not done: bound 0.3.
    assert long - short < 0.3 * (size[120_000] - size[30_000])
    assert long < 0.45 * size[120_000]


def test_rounded_frame_times_are_filtered_at_their_mean_rate():
    """I-Scan prints frame times to 0.01 s: a 0.10097 s step reads as 0.10 or 0.11 s."""
    from tactilecal.dynamic import CorrectionFilter, apply_filter

    n = 400
    true_s = np.arange(n) * 0.10097402597402598
    data = xr.DataArray(np.random.default_rng(0).normal(100, 5, (n, 2, 2)),
                        dims=("frame", "row", "col"),
                        coords={"time": ("frame", np.round(true_s, 2))})
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1 / 0.10097402597402598,
                                       band_hz=(0.1, 2), n_taps=31)
    out = apply_filter(data, filt)
    assert out.attrs["sampling_rate_hz"] == pytest.approx(1 / 0.10097402597402598, rel=1e-4)
    assert 0.004 < out.attrs["time_jitter_s"] <= 0.01  # rounding of the stamp and the ends


def test_truly_irregular_frame_times_are_refused_naming_the_record():
    from tactilecal.dynamic import CorrectionFilter, apply_filter

    time_s = np.cumsum(np.where(np.arange(400) % 2, 0.05, 0.15))  # steps 0.05 / 0.15 s
    data = xr.DataArray(np.ones((400, 2, 2)), dims=("frame", "row", "col"),
                        coords={"time": ("frame", time_s)}, attrs={"source": "walk.csv"})
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=10, band_hz=(0.1, 2),
                                       n_taps=31)
    with pytest.raises(ValueError, match="walk.csv: irregular time column"):
        apply_filter(data, filt)


def test_real_iscan_movie_is_accepted_by_dynamic_apply(iscan_csv, tmp_path, capsys):
    from tactilecal.cli import main
    from tactilecal.dynamic import CorrectionFilter

    filt = tmp_path / "f.json"
    CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=309 / 31.1 * 308 / 309,
                                band_hz=(0.1, 2), n_taps=31).to_json(filt)
    assert main(["dynamic", "apply", str(filt), str(iscan_csv), "--out",
                 str(tmp_path / "o.nc")]) == 0
    assert re.search(r"off a uniform 9.90\d* Hz grid", capsys.readouterr().err)


@pytest.mark.parametrize("export", ["iscan_csv", "fscan_asf", "fscan_right_asf"])
@pytest.mark.parametrize("method", ["auto", "direct"])
def test_real_exports_filtered_to_float32_are_the_float64_result_rounded(export, method,
                                                                        request):
    from tactilecal.io import read_tekscan

    rec = read_tekscan(request.getfixturevalue(export))
    fs_hz = (rec.sizes["frame"] - 1) / float(rec["time"][-1] - rec["time"][0])
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=fs_hz,
                                       band_hz=(fs_hz / 200, fs_hz / 10), n_taps=101)
    wide = apply_filter(rec, filt, method=method).values
    narrow = apply_filter(rec, filt, method=method, dtype="float32").values
    assert narrow.dtype == np.float32
    np.testing.assert_array_equal(np.isnan(narrow), np.isnan(wide))  # outside the shape
    # measured 0.25-0.50 float32 steps of the largest value (final rounding only)
    step = np.spacing(np.float32(np.nanmax(np.abs(wide))))
    np.testing.assert_allclose(narrow, wide, rtol=0, atol=2 * step)
