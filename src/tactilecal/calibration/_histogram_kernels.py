"""numba kernels of :func:`tactilecal.calibration._histogram.count_into` (one pass per frame).

For each frame a vectorised loop rounds every reading to an index (NaN to a discarded bin
256) while checking the range, the non-working sensels are set to that bin, then a scalar
loop counts the indices: zeros (an unloaded area) on their own, the others into two
interleaved sub-histograms (consecutive equal readings would otherwise wait on one
counter). uint8 readings are their own indices and are counted directly. Each kernel
returns -1, or the flat index of the first counted reading outside 0..255 (counting stops
there).

Imported only when a large input is counted: numba's start-up in a new process costs more
than it saves on a small one.
"""

import numpy as np

from tactilecal._numba import njit

N_LEVELS = 256
_DISCARD = N_LEVELS  # bin of NaN and masked sensels, dropped


@njit(nogil=True)
def _count_row(index, counts, out, i):  # pragma: no cover (compiled)
    """Count ``index`` (values 0..256) into ``out[i]`` using two sub-histograms ``counts``.

    Zeros (the unloaded sensels: often half a frame or more, in long runs) are counted on
    their own behind a well-predicted branch; the other readings go to two interleaved
    sub-histograms (faster than four sub-histograms for every reading, most for uint8
    frames: ``benchmarks/bench_movie.py``).
    """
    counts[:] = 0
    zeros = 0
    for j in range(index.size):
        v = index[j]
        if v == 0:
            zeros += 1
        else:
            counts[j & 1, v] += 1
    out[i, 0] = zeros
    for k in range(1, N_LEVELS):
        out[i, k] = counts[0, k] + counts[1, k]


@njit(nogil=True)
def _count_values(frames, skipped, out):  # pragma: no cover (compiled)
    """Histograms of float frames (m, n_sensels), rounded half to even like ``numpy.rint``.

    Compiled once per type of ``frames`` and ``out``, so
    :func:`~tactilecal.calibration._histogram.count_into` passes only float32 or float64
    frames (integers widened to float64) and int64 counts.

    ``skipped`` lists the sensels not counted. Returns -1, or the flat index of the first
    finite, counted reading whose rounded value lies outside 0..255 (counting stops there).
    """
    n, m = frames.shape
    index = np.empty(m, np.int32)
    counts = np.zeros((2, N_LEVELS + 1), np.int32)
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


@njit(nogil=True)
def _count_uint8(frames, skipped, out):  # pragma: no cover (compiled)
    """Histograms of uint8 frames: every reading is a bin, counted without an index pass."""
    n, m = frames.shape
    counts = np.zeros((2, N_LEVELS), np.int32)
    for i in range(n):
        row = frames[i]
        counts[:] = 0
        zeros = 0
        for j in range(m):  # as _count_row
            v = row[j]
            if v == 0:
                zeros += 1
            else:
                counts[j & 1, v] += 1
        counts[0, 0] = zeros
        for j in skipped:
            counts[0, row[j]] -= 1
        for k in range(N_LEVELS):
            out[i, k] = counts[0, k] + counts[1, k]
    return -1


@njit(nogil=True)
def _member(j, sorted_values):  # pragma: no cover (compiled)
    """``j`` is in ``sorted_values``: bisection, as ``numpy.searchsorted`` (side "left").

    Written out: numba's ``np.searchsorted`` compiles a generic (NaN- and complex-aware)
    comparison that took longer to compile than the rest of :func:`_count_values`.
    """
    lo, hi = 0, sorted_values.size
    while lo < hi:
        mid = (lo + hi) // 2
        if sorted_values[mid] < j:
            lo = mid + 1
        else:
            hi = mid
    return lo < sorted_values.size and sorted_values[lo] == j


def kernel_for(dtype):
    """Return the kernel counting frames of ``dtype`` (uint8, other integers, float32/64)."""
    return _count_uint8 if dtype == np.uint8 else _count_values
