"""Per-frame 256-bin histograms of raw readings in one pass over the frames (numba kernels).

A movie of 100,000 frames of 44 x 44 sensels is 1.55 GB in float64; its histograms are what
every calibration fit uses (Zvyagin 2022, eq. 2: ``sum_k f(X_k) = histogram @ f(0..255)``),
so counting them should cost about one read of the frames. NumPy needs several passes
(round, check the range, add frame offsets, ``bincount``); the kernels here make one:
for each frame, a vectorised loop rounds every reading to an index (NaN and masked sensels
to a discarded bin 256) while checking the range, then a scalar loop counts the indices
into four interleaved sub-histograms (consecutive equal readings, e.g. the zeros of an
unloaded area, would otherwise wait on one counter). ``benchmarks/bench_movie.py``
measures them against a ``numpy.sum`` over the same array and the former NumPy version.

The module imports numba, so it is imported only where histograms are counted.
"""

import numba
import numpy as np

N_LEVELS = 256
SATURATION_RAW = 255
_DISCARD = N_LEVELS  # bin of NaN and masked sensels, dropped


@numba.njit(nogil=True, cache=True)
def _count_row(index, counts, out, i):  # pragma: no cover (compiled; tested via count_into)
    """Count ``index`` (values 0..256) into ``out[i]`` using four sub-histograms ``counts``."""
    counts[:] = 0
    m = index.size
    m4 = m - m % 4
    for j in range(0, m4, 4):
        for u in range(4):
            counts[u, index[j + u]] += 1
    for j in range(m4, m):
        counts[0, index[j]] += 1
    for k in range(N_LEVELS):
        out[i, k] = counts[0, k] + counts[1, k] + counts[2, k] + counts[3, k]


@numba.njit(nogil=True, cache=True)
def _count_float(frames, skipped, out):  # pragma: no cover (compiled; tested via count_into)
    """Histograms of float frames (m, n_sensels), rounded half to even like ``numpy.rint``.

    ``skipped`` lists the sensels not counted. Returns -1, or the flat index of the first
    finite, counted reading whose rounded value lies outside 0..255 (counting stops there).
    """
    n, m = frames.shape
    index = np.empty(m, np.int32)
    counts = np.zeros((4, N_LEVELS + 1), np.int32)
    for i in range(n):
        row = frames[i]
        bad = 0
        for j in range(m):  # no branch, so that it vectorises
            r = np.rint(row[j])
            ok = (r >= 0.0) & (r <= 255.0)
            bad += (not ok) & (row[j] == row[j])
            index[j] = np.int32(r) if ok else _DISCARD
        for j in skipped:
            index[j] = _DISCARD
        if bad:
            for j in range(m):
                r = np.rint(row[j])
                if (r < 0.0 or r > 255.0) and not _member(j, skipped):
                    return i * m + j
        _count_row(index, counts, out, i)
    return -1


@numba.njit(nogil=True, cache=True)
def _count_int(frames, skipped, out):  # pragma: no cover (compiled; tested via count_into)
    """Histograms of integer frames (m, n_sensels); see :func:`_count_float`."""
    n, m = frames.shape
    index = np.empty(m, np.int32)
    counts = np.zeros((4, N_LEVELS + 1), np.int32)
    for i in range(n):
        row = frames[i]
        bad = 0
        for j in range(m):
            ok = (row[j] >= 0) & (row[j] <= 255)
            bad += not ok
            index[j] = np.int32(row[j]) if ok else _DISCARD
        for j in skipped:
            index[j] = _DISCARD
        if bad:
            for j in range(m):
                if (row[j] < 0 or row[j] > 255) and not _member(j, skipped):
                    return i * m + j
        _count_row(index, counts, out, i)
    return -1


@numba.njit(nogil=True, cache=True)
def _count_uint8(frames, skipped, out):  # pragma: no cover (compiled; tested via count_into)
    """Histograms of uint8 frames: every reading is a bin, counted without an index pass."""
    n, m = frames.shape
    counts = np.zeros((4, N_LEVELS), np.int32)
    m4 = m - m % 4
    for i in range(n):
        row = frames[i]
        counts[:] = 0
        for j in range(0, m4, 4):
            for u in range(4):
                counts[u, row[j + u]] += 1
        for j in range(m4, m):
            counts[0, row[j]] += 1
        for j in skipped:
            counts[0, row[j]] -= 1
        for k in range(N_LEVELS):
            out[i, k] = counts[0, k] + counts[1, k] + counts[2, k] + counts[3, k]
    return -1


@numba.njit(nogil=True, cache=True)
def _member(j, sorted_values):  # pragma: no cover (compiled; tested via count_into)
    k = np.searchsorted(sorted_values, j)
    return k < sorted_values.size and sorted_values[k] == j


def count_into(frames, skip, out):
    """Count each frame's raw readings 0..255 into ``out`` (m, 256).

    Parameters
    ----------
    frames : numpy.ndarray, shape (m, n_sensels)
        Raw readings, any real dtype; floats are rounded half to even (``numpy.rint``),
        NaN are not counted.
    skip : numpy.ndarray of bool, shape (n_sensels,)
        Sensels not to count (non-working); their readings are not checked either.
    out : numpy.ndarray, shape (m, 256)
        Filled in place (any numeric dtype; int64 and float64 are written directly).

    Raises
    ------
    ValueError
        If a counted reading (rounded) lies outside 0..255.
    TypeError
        If the readings are not real numbers.
    """
    kind = frames.dtype.kind
    if kind == "b":
        frames = frames.view(np.uint8)
    elif kind == "f" and frames.dtype.itemsize < 4:
        frames = frames.astype(np.float32)  # exact; numba has no float16 arithmetic
    elif kind not in "fui":
        raise TypeError(f"raw frames have dtype {frames.dtype}; expected real numbers "
                        "(raw readings 0..255)")
    frames = np.ascontiguousarray(frames)
    direct = out.dtype in (np.int64, np.float64) and out.flags.c_contiguous
    target = out if direct else np.empty(out.shape, np.int64)
    kernel = (_count_uint8 if frames.dtype == np.uint8
              else _count_float if frames.dtype.kind == "f" else _count_int)
    bad = kernel(frames, np.flatnonzero(skip), target)
    if bad >= 0:
        value = frames.flat[bad]
        value = np.rint(value) if frames.dtype.kind == "f" else value
        raise ValueError(f"raw frames contain the value {value:g}; expected raw readings "
                         "0..255")
    if not direct:
        out[...] = target
    return out


@numba.njit(nogil=True, cache=True)
def _compact(rows, keep):  # pragma: no cover (compiled; tested via keep_rows_in_place)
    m = 0
    for i in range(rows.shape[0]):
        if keep[i]:
            if m != i:
                rows[m] = rows[i]
            m += 1
    return m


def keep_rows_in_place(rows, keep):
    """Move the rows selected by ``keep`` to the top of ``rows``, in order; return that view.

    ``rows[keep]`` would allocate and fill a new array: for the (100,000, 256) float64
    histograms of a movie that is 205 MB of fresh pages, several times the cost of moving
    the rows within the array. The rows below the returned view are left as they were.

    Examples
    --------
    >>> a = np.arange(8.0).reshape(4, 2)
    >>> keep_rows_in_place(a, np.array([False, True, False, True])).tolist()
    [[2.0, 3.0], [6.0, 7.0]]
    """
    keep = np.asarray(keep, dtype=np.bool_)
    if rows.ndim != 2 or not rows.flags.c_contiguous or len(keep) != len(rows):
        raise ValueError("keep_rows_in_place needs a C-contiguous 2-D array and one flag per "
                         "row")
    return rows[:_compact(rows, keep)]
