"""The multirate filter at scale (issue 16): its equations, dask chunks, the causal chain,
and a dask.distributed cluster reading the recording from NetCDF in the workers."""

import pickle

import numpy as np
import pytest
import xarray as xr
from scipy import signal

from tactilecal.dynamic import CorrectionFilter, RationalModel, apply_filter
from tactilecal.dynamic._multirate import plan_multirate

FS_HZ = 1000.0

#: These tests check the realisations of a filter on random walks and white noise, whose
#: power lies mostly above the filters' bands: the warning that says so is tested in
#: tests/test_dynamic_band.py.
pytestmark = pytest.mark.filterwarnings("ignore::tactilecal.dynamic._apply.BandWarning")

VISCO = RationalModel.from_corners_hz(zeros_hz=[20.0], poles_hz=[5.0])


def _filters():
    """A zero-phase log filter and a rational (complex) one, both multirate with P = 5."""
    log = CorrectionFilter.from_model(("log", {"A": 0.05}), fs_hz=FS_HZ, band_hz=(1, 40))
    rational = CorrectionFilter("rational", {"order": 1}, FS_HZ, (1, 40), taper_hz=10.0,
                                n_taps=1001, rational=VISCO)
    return {"log": log, "rational": rational}


FILTERS = _filters()


def _walk(n_frames, shape, seed, offset=1000.0):
    """Random walk plus white noise on a large offset, time first."""
    rng = np.random.default_rng(seed)
    x = offset + 0.1 * rng.standard_normal((n_frames, *shape)).cumsum(axis=0)
    return x + rng.standard_normal(x.shape)


def _record(values):
    dims = ("frame", "row", "col")[:values.ndim] if values.ndim != 2 else ("frame", "sensel")
    return xr.DataArray(values, dims=dims,
                        coords={"time": ("frame", np.arange(values.shape[0]) / FS_HZ)})


def _reflected(x, margin):
    """``x`` (time first) with ``margin`` rows of odd reflection about each end row."""
    n = x.shape[0]
    idx = np.arange(-margin, n + margin)
    src = np.where(idx < 0, -idx, np.where(idx > n - 1, 2 * (n - 1) - idx, idx))
    ext = x[src]
    ext[idx < 0] = 2 * x[0] - ext[idx < 0]
    ext[idx > n - 1] = 2 * x[n - 1] - ext[idx > n - 1]
    return ext


def _by_equations(x, plan):
    """The multirate method written out with numpy convolutions, in float64 (module notes)."""
    factor, lowpass, taps = plan.factor, plan.lowpass, plan.correction
    margin = 2 * plan.reach + factor
    margin -= margin % factor  # frame 0 stays on the decimation grid
    out = np.empty_like(x)
    for s in range(x.shape[1]):
        ext = _reflected(x[:, s], margin)
        decimated = np.convolve(ext, lowpass, mode="same")[::factor]  # 1: low-pass, every P-th
        corrected = np.convolve(decimated, taps, mode="same")  # 2: D at fs / P
        up = np.zeros(ext.size)
        up[::factor] = corrected
        out[:, s] = x[:, s] + factor * np.convolve(up, lowpass, mode="same")[margin:-margin]
    return out


@pytest.mark.parametrize("name", sorted(FILTERS))
def test_multirate_output_follows_its_equations(name):
    filt = FILTERS[name]
    plan = plan_multirate(filt)
    assert plan.factor == 5 and plan.phase == (name == "rational")
    x = _walk(4003, (3,), seed=1)
    truth = _by_equations(x, plan)
    dynamic = np.ptp(x - x[0])  # the offset (1000) is 300 times the dynamic range
    double = apply_filter(_record(x), filt, precision="double").values
    single = apply_filter(_record(x), filt).values
    np.testing.assert_allclose(double, truth, rtol=0, atol=1e-11 * dynamic)  # measured 4e-14
    # float32 relative to each sensel's first value, not to the offset: measured 1.5e-7
    np.testing.assert_allclose(single, truth, rtol=0, atol=2e-6 * dynamic)


def test_float32_recordings_are_filtered_as_they_are():
    x = _walk(4000, (2, 3), seed=2, offset=10.0).astype(np.float32)
    as_float32 = apply_filter(_record(x), FILTERS["log"], precision="double")
    as_float64 = apply_filter(_record(x.astype(float)), FILTERS["log"], precision="double")
    assert as_float32.dtype == np.float64
    np.testing.assert_allclose(as_float32.values, as_float64.values, rtol=0,
                               atol=1e-8 * np.ptp(x))  # margins reflected in float32: 2.4e-10


CAUSAL = CorrectionFilter("rational", {"order": 1}, FS_HZ, (1, 40), rational=VISCO)
#: (filter, apply_filter options, dask chunks or None): every path that makes an output.
PATHS = {
    "multirate": (FILTERS["log"], {}, None),
    "multirate, double": (FILTERS["rational"], {"precision": "double"}, None),
    "direct": (FILTERS["log"], {"method": "direct"}, None),
    "dask multirate": (FILTERS["rational"], {}, {"frame": 700, "row": 1}),
    "dask one time chunk": (FILTERS["log"], {}, {"frame": -1, "col": 2}),
    "dask direct": (FILTERS["log"], {"method": "direct"}, {"frame": 1500}),
    "causal": (CAUSAL, {"causal": True}, None),
    "dask causal": (CAUSAL, {"causal": True}, {"frame": 333}),
}


def _float32_output_cases():
    """Every path from float64 records; from float32 ones, the in-memory multirate path only
    (the others are slow: each other combination of types compiles kernels on a fresh
    install, seconds each)."""
    for path in sorted(PATHS):
        yield pytest.param(path, np.float64, id=f"{path}-float64")
        marks = () if path == "multirate" else pytest.mark.slow
        yield pytest.param(path, np.float32, id=f"{path}-float32", marks=marks)


@pytest.mark.parametrize(("path", "source"), list(_float32_output_cases()))
def test_float32_output_is_the_float64_result_rounded(path, source):
    filt, options, chunks = PATHS[path]
    x = _walk(3001, (2, 3), seed=9, offset=100.0).astype(source)
    rec = _record(x) if chunks is None else _record(x).chunk(chunks)
    wide = apply_filter(rec, filt, **options)
    narrow = apply_filter(rec, filt, dtype="float32", **options)
    assert wide.dtype == np.float64 and narrow.dtype == np.float32
    assert (narrow.chunks is None) == (chunks is None)
    values = narrow.values
    assert values.dtype == np.float32
    # only the final rounding differs (at most half a float32 step; allowed: 2 steps)
    step = np.spacing(np.float32(np.abs(wide.values).max()))
    np.testing.assert_allclose(values, wide.values, rtol=0, atol=2 * step)


@pytest.mark.slow  # a profile of numba's compilations: every combination of types
def test_every_type_combination_runs_on_few_compiled_kernels():
    """Record type x precision x result type (8 paths, in memory and in dask chunks) share
    the stage kernels: stage 1's long kernel per record type, stage 3's for five
    combinations of types (numba compiles a kernel for every combination it is called with,
    seconds each on a fresh install)."""
    from tactilecal.dynamic import _multirate

    x = _walk(3001, (2, 3), seed=12, offset=100.0)
    for source in (np.float32, np.float64):
        rec = _record(x.astype(source))
        for precision in ("single", "double"):
            wide = apply_filter(rec, FILTERS["log"], precision=precision)
            for data in (rec, rec.chunk({"frame": 1500})):
                narrow = apply_filter(data, FILTERS["log"], precision=precision,
                                      dtype="float32").values
                step = np.spacing(np.float32(np.abs(wide.values).max()))
                np.testing.assert_allclose(narrow, wide.values, rtol=0, atol=2 * step)
    assert len(_multirate._sum_tile.signatures) <= 2
    assert len(_multirate._store_tile.signatures) <= 2
    assert len(_multirate._interpolate_rows.signatures) <= 5


@pytest.mark.parametrize("dtype", ["float16", "int32", "complex64", "pressure", 3])
def test_an_output_type_other_than_float64_or_float32_is_refused(dtype):
    rec = _record(_walk(3001, (2,), seed=10))
    with pytest.raises(ValueError, match=r"dtype=.*expected 'float64' or 'float32'"):
        apply_filter(rec, FILTERS["log"], dtype=dtype)


@pytest.mark.parametrize("chunks", [{"frame": 7}, {"frame": 703}, {"frame": 1999, "row": 1},
                                    {"frame": 2500, "col": 2}])
@pytest.mark.parametrize("name", sorted(FILTERS))
def test_dask_chunks_of_any_size_equal_memory(name, chunks):
    x = _walk(3001, (2, 3), seed=3)
    rec = _record(x)
    memory = apply_filter(rec, FILTERS[name], precision="double").values
    lazy = apply_filter(rec.chunk(chunks), FILTERS[name], precision="double")
    assert lazy.chunks is not None
    if chunks["frame"] > 5 * 101:  # chunks as long as stage 2's reach are kept
        assert lazy.data.chunks == rec.chunk(chunks).data.chunks
    np.testing.assert_allclose(lazy.values, memory, rtol=0, atol=1e-10 * np.ptp(x - x[0]))


def test_chunks_shorter_than_the_decimation_factor_own_no_sample_and_still_work():
    x = _walk(1203, (2,), seed=8)
    memory = apply_filter(_record(x), FILTERS["log"], precision="double").values
    lazy = apply_filter(_record(x).chunk({"frame": 3}), FILTERS["log"], precision="double")
    np.testing.assert_allclose(lazy.values, memory, rtol=0, atol=1e-10 * np.ptp(x - x[0]))


def test_dask_single_precision_equals_memory_to_float32_rounding():
    x = _walk(6000, (4,), seed=4)
    memory = apply_filter(_record(x), FILTERS["log"]).values
    lazy = apply_filter(_record(x).chunk({"frame": 1000}), FILTERS["log"]).values
    # the FFT blocks differ (per chunk): measured 1.8e-8
    np.testing.assert_allclose(lazy, memory, rtol=0, atol=1e-6 * np.ptp(x - x[0]))


def test_causal_filter_is_scipy_sosfilt_in_memory_and_chunk_by_chunk():
    filt = CorrectionFilter("rational", {"order": 3}, FS_HZ, (1, 40), rational=(
        RationalModel.from_corners_hz(zeros_hz=[20.0, 35.0, 60.0], poles_hz=[5.0, 8.0, 12.0])))
    sos = filt.sos()
    assert sos.shape[0] == 2  # two sections: the state of both is carried
    x = _walk(2500, (2, 3), seed=5)
    flat = x.reshape(x.shape[0], -1)
    truth = (signal.sosfilt(sos, flat - flat[0], axis=0) + flat[0]).reshape(x.shape)
    eager = apply_filter(_record(x), filt, causal=True).values
    lazy = apply_filter(_record(x).chunk({"frame": 333, "row": 1}), filt, causal=True)
    span = np.ptp(x - x[0])
    np.testing.assert_allclose(eager, truth, rtol=0, atol=1e-12 * span)
    np.testing.assert_allclose(lazy.values, truth, rtol=0, atol=1e-12 * span)


def test_causal_chunks_pass_on_their_state_not_their_output():
    """Chunk i's task needs chunk i - 1's filter state only, so no output waits for it."""
    from dask.core import get_dependencies

    filt = CorrectionFilter("rational", {"order": 1}, FS_HZ, (1, 40), rational=VISCO)
    x = _walk(1000, (2, 3), seed=8)
    lazy = apply_filter(_record(x).chunk({"frame": 250}), filt, causal=True)
    graph = dict(lazy.data.__dask_graph__())
    runs = sorted(key for key in graph if isinstance(key, tuple) and key[0].endswith("-run"))
    assert len(runs) == 4
    outputs = {key for key in graph if isinstance(key, tuple) and key[0] == lazy.data.name}
    for key in runs[1:]:
        needs = get_dependencies(graph, key)
        assert any(dep[0].endswith("-state") for dep in needs)
        assert not needs & outputs
    eager = apply_filter(_record(x), filt, causal=True, workers=1).values
    np.testing.assert_allclose(lazy.values, eager, rtol=0, atol=1e-12 * np.ptp(x - x[0]))


def test_first_row_reference_is_a_copy_not_a_view_of_the_first_chunk():
    import dask.array as da

    from tactilecal.dynamic._apply import _first_row

    x = np.arange(24.0).reshape(8, 3)
    first = _first_row(da.from_array(x, chunks=(4, 3))).compute()
    assert first.tolist() == [[0.0, 1.0, 2.0]] and not np.shares_memory(first, x)


def test_the_graph_holds_no_data_when_the_recording_is_read_lazily(tmp_path):
    from tactilecal.io import write_netcdf

    x = _walk(20_000, (4, 8), seed=6)
    write_netcdf(_record(x), tmp_path / "rec.nc")
    with xr.open_dataarray(tmp_path / "rec.nc", chunks={"frame": 4000}) as lazy:
        out = apply_filter(lazy, FILTERS["rational"])
        size = len(pickle.dumps(dict(out.data.__dask_graph__())))
    assert size < 0.01 * x.nbytes  # measured 0.13 % (the taps and the file's name)


def test_a_local_cluster_reads_netcdf_in_its_workers_and_matches_memory(tmp_path):
    from dask.distributed import Client, LocalCluster

    from tactilecal.io import write_netcdf

    x = _walk(12_000, (3, 4), seed=7)
    write_netcdf(_record(x), tmp_path / "rec.nc")
    memory = apply_filter(_record(x), FILTERS["log"]).values
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        with xr.open_dataarray(tmp_path / "rec.nc", chunks={"frame": 3000}) as lazy:
            future = client.compute(apply_filter(lazy, FILTERS["log"]).data)
            values = future.result()
        who = client.run(lambda: True)
    assert len(who) == 2
    np.testing.assert_allclose(values, memory, rtol=0, atol=1e-6 * np.ptp(x - x[0]))


@pytest.mark.parametrize("n_q", [1, 2, 3, 4, 5, 6, 8, 9, 13])
def test_interpolation_kernel_sums_any_number_of_polyphase_taps(n_q):
    """Stage 3's kernel: ``x + sum_q w[phi, q] c[s, M + q]`` for every tap count it splits
    into passes of four plus a last pass of one to four (written out in float64)."""
    from tactilecal.dynamic._multirate import _interpolate_rows

    rng = np.random.default_rng(n_q)
    factor, offset, n_frames, width = 5, 3, 700, 11
    weights = rng.standard_normal((factor, n_q))
    corrected = rng.standard_normal((width, (n_frames + offset) // factor + n_q + 1))
    x = rng.standard_normal((n_frames, width))
    x.flags.writeable = False  # as interpolate() passes the rows: no kernel of its own
    out = np.full_like(x, np.nan)
    _interpolate_rows(x, corrected, weights, offset, 0, n_frames, 0, width, out)
    frame = np.arange(n_frames) + offset
    expected = x + sum(weights[frame % factor, q][:, None] * corrected[:, frame // factor + q].T
                       for q in range(n_q))
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12 * n_q)  # float64 sums


def test_filter_block_reflects_a_whole_record_or_needs_both_margins():
    """``before=after=None``: the record's own odd reflection, the same as given margins."""
    from tactilecal.dynamic._multirate import BlockLayout, filter_block

    plan = plan_multirate(FILTERS["log"])
    x = _walk(3000, (5,), seed=4)
    need_before, need_after = BlockLayout.of(plan, 0, x.shape[0]).margins
    ext = _reflected(x, max(need_before, need_after))
    top = max(need_before, need_after)
    given = filter_block(ext[top - need_before:top], x, ext[top + x.shape[0]:][:need_after], 0,
                         plan, precision="double")
    reflected = filter_block(None, x, None, 0, plan, precision="double")
    np.testing.assert_allclose(reflected, given, rtol=0, atol=1e-12 * np.ptp(x))
    with pytest.raises(ValueError, match="needs both before and after, or neither"):
        filter_block(None, x, ext[:need_after], 0, plan)
    with pytest.raises(ValueError, match=f"needs {need_before} rows before"):
        filter_block(ext[:10], x, ext[:need_after], 0, plan)
