"""frame_histograms (NumPy and compiled paths) against a per-frame np.bincount, every input."""

import numpy as np
import pytest

from tactilecal.calibration import frame_histograms, points_from_frames
from tactilecal.calibration._histogram import COMPILED_MIN_VALUES
from tactilecal.calibration._points import _frame_histograms, keep_rows_in_place


@pytest.fixture(params=[False, True], ids=["numpy", "compiled"])
def count(request):
    """frame_histograms forced onto one of its two counting paths."""
    def count(raw, **kwargs):
        return _frame_histograms(raw, compiled=request.param, **kwargs)
    return count


def reference_histograms(raw, mask=None):
    """Per-frame np.bincount of the rounded finite readings (the definition)."""
    frames = np.array(raw, dtype=float)
    if frames.ndim == 2:
        frames = frames[None]
    if mask is not None:
        frames[:, mask] = np.nan
    return np.stack([np.bincount(np.rint(f[np.isfinite(f)]).astype(int), minlength=256)
                     for f in frames])


@pytest.fixture(scope="module")
def movie():
    """Integer readings 0..255 with NaN cells outside the shape and many zeros."""
    rng = np.random.default_rng(3)
    raw = rng.integers(0, 256, size=(301, 9, 11)).astype(float)  # 301: not a chunk multiple
    raw[rng.random(raw.shape) < 0.5] = 0.0
    raw[:, :2, :2] = np.nan
    raw[7] = 255.0
    return raw


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.float16])
def test_float_storage_matches_bincount(count, movie, dtype):
    np.testing.assert_array_equal(count(movie.astype(dtype)),
                                  reference_histograms(movie))


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.int16, np.int32, np.int64,
                                   np.uint64])
def test_integer_storage_matches_bincount(count, movie, dtype):
    ints = np.nan_to_num(movie).astype(dtype)
    np.testing.assert_array_equal(count(ints), reference_histograms(ints))


def test_bool_frames_count_zeros_and_ones(count):
    frames = np.random.default_rng(0).random((5, 4, 4)) < 0.3
    np.testing.assert_array_equal(count(frames), reference_histograms(frames))


def test_rounding_is_half_to_even_like_numpy_rint(count):
    frame = np.array([[2.5, 3.5, -0.4, -0.0], [255.4, 0.5, 1.5, 7.49999]])
    hist = count(frame)[0]
    assert hist.sum() == 8
    assert {int(k): int(c) for k, c in enumerate(hist) if c} == {0: 3, 2: 2, 4: 1, 7: 1,
                                                                  255: 1}


def test_non_contiguous_frames_and_chunks(count, movie):
    transposed = np.swapaxes(movie, 1, 2)  # not C-contiguous: copied chunk by chunk
    expected = reference_histograms(transposed)
    np.testing.assert_array_equal(count(transposed, chunk_frames=7), expected)
    np.testing.assert_array_equal(count(movie[::3]), reference_histograms(movie[::3]))


@pytest.mark.parametrize("dtype", [np.float64, np.int64, np.int32, np.float32])
def test_out_of_any_dtype_is_filled(count, movie, dtype):
    out = np.full((len(movie), 256), -1, dtype=dtype)
    assert count(movie, out=out) is out
    np.testing.assert_array_equal(out, reference_histograms(movie))
    wide = np.zeros((len(movie), 512))
    count(movie, out=wide[:, ::2])  # not contiguous
    np.testing.assert_array_equal(wide[:, ::2], reference_histograms(movie))


def test_mask_skips_sensels_and_their_values(count, movie):
    mask = np.zeros(movie.shape[1:], bool)
    mask[4, 5] = mask[8, 10] = True
    bad = movie.copy()
    bad[:, 4, 5] = 999.0  # out of range but masked: neither counted nor refused
    expected = reference_histograms(movie, mask)
    np.testing.assert_array_equal(count(bad, mask=mask), expected)
    ints = np.nan_to_num(bad).astype(np.int64)
    np.testing.assert_array_equal(count(ints, mask=mask),
                                  reference_histograms(ints, mask))
    u8 = np.nan_to_num(movie).astype(np.uint8)
    np.testing.assert_array_equal(count(u8, mask=mask),
                                  reference_histograms(u8, mask))


def test_prepare_is_applied_per_chunk(count, movie):
    seen = []

    def halve(block):
        seen.append(len(block))
        return block / 2

    hist = count(movie, prepare=halve, chunk_frames=100)
    np.testing.assert_array_equal(hist, reference_histograms(movie / 2))
    assert seen == [100, 100, 100, 1]


@pytest.mark.parametrize(("value", "shown"), [(300.0, "300"), (-1.0, "-1"), (255.5, "256"),
                                              (-0.6, "-1"), (np.inf, "inf"),
                                              (-np.inf, "-inf")])
def test_out_of_range_reading_is_named(count, movie, value, shown):
    bad = movie.copy()
    bad[200, 3, 3] = value
    with pytest.raises(ValueError, match=f"contain the value {shown}; expected raw "
                                         r"readings 0\.\.255"):
        count(bad)


def test_out_of_range_integer_and_first_one_named(count):
    frames = np.zeros((3, 2, 2), np.int16)
    frames[1, 1, 0], frames[2, 0, 0] = -7, 400
    with pytest.raises(ValueError, match="contain the value -7; expected"):
        count(frames)


def test_compiled_counts_of_every_type_use_three_kernels(movie):
    """Frames of any type into counts of any type, over several kernel blocks: float32,
    float64 or uint8 frames into int64 counts are all the kernels see (numba compiles one
    for every pair of types it is called with)."""
    from tactilecal.calibration import _histogram_kernels as kernels
    from tactilecal.calibration._histogram import KERNEL_FRAMES

    frames = np.concatenate([np.nan_to_num(movie)] * (2 * KERNEL_FRAMES // len(movie) + 1))
    expected = reference_histograms(frames)
    for dtype in (np.float64, np.float32, np.uint8, np.uint16, np.int16, np.int64):
        for counts in (np.int64, np.uint16, np.float64):
            out = np.empty((len(frames), 256), counts)
            _frame_histograms(frames.astype(dtype), compiled=True, out=out)
            np.testing.assert_array_equal(out, expected)
    bad = frames.astype(np.int32)
    bad[2 * KERNEL_FRAMES + 3, 1, 2] = -7  # in the third block: its flat index is kept
    with pytest.raises(ValueError, match="contain the value -7; expected"):
        _frame_histograms(bad, compiled=True, out=np.empty((len(bad), 256), np.uint16))
    kinds = {(sig[0].dtype.name, sig[2].dtype.name)
             for kernel in (kernels._count_values, kernels._count_uint8)
             for sig in kernel.signatures}
    assert kinds <= {("float64", "int64"), ("float32", "int64"), ("uint8", "int64")}


def test_bad_types_and_shapes(count):
    with pytest.raises(TypeError, match="raw frames have dtype complex128; expected real"):
        count(np.zeros((1, 2, 2), complex))
    with pytest.raises(ValueError, match=r"mask has shape \(3,\); expected \(2, 2\)"):
        count(np.zeros((1, 2, 2)), mask=np.zeros(3, bool))


def test_empty_movie_gives_no_rows(count):
    assert count(np.zeros((0, 3, 3))).shape == (0, 256)


def test_points_from_uint8_frames_equal_float_frames(movie):
    u8 = np.nan_to_num(movie).astype(np.uint8)
    load = np.linspace(1.0, 2.0, len(u8))
    a = points_from_frames(u8, load, mask=np.eye(9, 11, dtype=bool))
    b = points_from_frames(u8.astype(float), load, mask=np.eye(9, 11, dtype=bool))
    assert [(p.raw_sum, p.working_cells) for p in a] == [(p.raw_sum, p.working_cells)
                                                          for p in b]
    np.testing.assert_array_equal(np.stack([p.histogram for p in a]),
                                  reference_histograms(u8, np.eye(9, 11, dtype=bool)))


def test_size_chooses_the_path(movie, monkeypatch):
    import tactilecal.calibration._histogram as histogram

    def refuse(*args, **kwargs):
        raise AssertionError("NumPy path used")

    monkeypatch.setattr(histogram, "_count_numpy", refuse)
    monkeypatch.setattr(histogram, "COMPILED_MIN_VALUES", movie.size)
    np.testing.assert_array_equal(frame_histograms(movie), reference_histograms(movie))
    with pytest.raises(AssertionError, match="NumPy path used"):
        frame_histograms(movie[:-1])
    assert COMPILED_MIN_VALUES == 2 ** 26


@pytest.mark.parametrize("piece_rows", [1, 3, 4096])
def test_keep_rows_in_place_equals_boolean_indexing(piece_rows):
    rng = np.random.default_rng(1)
    rows = rng.random((50, 4))
    keep = rng.random(50) < 0.6
    keep[20:35] = True  # a long run moved in pieces
    expected = rows[keep].copy()
    kept = keep_rows_in_place(rows, keep, piece_rows=piece_rows)
    assert np.shares_memory(kept, rows)
    np.testing.assert_array_equal(kept, expected)


def test_keep_rows_in_place_edges():
    rows = np.arange(12.0).reshape(6, 2)
    assert keep_rows_in_place(rows.copy(), np.zeros(6, bool)).shape == (0, 2)
    np.testing.assert_array_equal(keep_rows_in_place(rows.copy(), np.ones(6, bool)), rows)
    with pytest.raises(ValueError, match="keep has 5 flags for 6 rows; expected one per row"):
        keep_rows_in_place(rows, np.ones(5, bool))
