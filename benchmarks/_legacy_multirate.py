"""The multirate filter as it was before issue 16 (commit dae8474), kept for timing only.

Its kernels and stages; the filter design (``plan_multirate``) is the package's, unchanged.

``benchmarks/bench_dynamic.py`` times it against the current one in the same run and checks
that both give the same output (to float32 rounding). Not used by the package; its numba
kernels compile on first use (cached next to this file).
"""

from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np
from scipy import fft

from tactilecal.dynamic._filter import PRECISIONS, centred_spectrum
from tactilecal.dynamic._multirate import MultiratePlan, plan_multirate  # design unchanged

__all__ = ["MultiratePlan", "plan_multirate", "apply_multirate", "run_tasks"]

#: Rows (frames or decimated frames) per task of the thread pool.
ROWS_PER_TASK = 2048
#: Sensels per task of stage 2, and its FFT length (at least 4 filter lengths).
LINES_PER_TASK = 32
BLOCK_FFT = 1 << 14
#: Decimated rows per tile of the transposing kernels (a tile of all sensels stays in L2).
TILE = 32


@numba.njit(nogil=True, cache=True, fastmath={"contract"})
def _decimate_to_lines(x, lowpass, factor, first, k0, k1, lines):  # pragma: no cover
    """``lines[s, k] = sum_j lowpass[j] x~[factor (first + k) + j - c, s] - x[0, s]``.

    ``x~`` is ``x`` odd-reflected about its end rows. Rows ``k0..k1`` are computed a tile
    at a time into a row-major buffer, then written transposed (time along ``lines``' rows).
    """
    n, m = x.shape
    c = lowpass.size // 2
    tile = np.empty((TILE, m))
    for a in range(k0, k1, TILE):
        b = min(a + TILE, k1)
        for k in range(a, b):
            row = tile[k - a]
            row[:] = 0.0
            centre = factor * (first + k) - c
            for j in range(lowpass.size):
                t, w = centre + j, lowpass[j]
                if 0 <= t < n:
                    for s in range(m):
                        row[s] += w * x[t, s]
                else:
                    end = 0 if t < 0 else n - 1
                    src = -t if t < 0 else 2 * (n - 1) - t
                    for s in range(m):
                        row[s] += w * (2.0 * x[end, s] - x[src, s])
        for s in range(m):
            for k in range(a, b):
                lines[s, k] = tile[k - a, s] - x[0, s]


@numba.njit(nogil=True, cache=True, fastmath={"contract"})
def _interpolate_add(x, lines, first, lowpass, factor, t0, t1, out):  # pragma: no cover
    """``out[t] = x[t] + factor sum_i lowpass[t - factor i + c] lines[:, i - first]``.

    The sum runs in the type of ``lines`` (float32 for single precision: twice the SIMD
    lanes; the correction is a fraction of the dynamic part, so its rounding is too).
    """
    m = x.shape[1]
    c = lowpass.size // 2
    weights = (factor * lowpass).astype(lines.dtype)
    tile = np.empty(((TILE * factor + 2 * c) // factor + 2, m), dtype=lines.dtype)
    acc = np.empty(m, dtype=lines.dtype)
    for a in range(t0, t1, TILE * factor):
        b = min(a + TILE * factor, t1)
        i0 = -((c - a) // factor)  # ceil((a - c) / factor): first decimated row used
        for s in range(m):
            for i in range(i0, (b - 1 + c) // factor + 1):
                tile[i - i0, s] = lines[s, i - first]
        for t in range(a, b):
            acc[:] = 0.0
            for i in range(-((c - t) // factor), (t + c) // factor + 1):
                w, row = weights[t - factor * i + c], tile[i - i0]
                for s in range(m):
                    acc[s] += w * row[s]
            for s in range(m):
                out[t, s] = x[t, s] + acc[s]


def run_tasks(tasks, workers, progress=None):
    """Run callables on ``workers`` threads (the kernels and FFTs release the GIL).

    ``progress`` wraps the iterator of finished tasks, called with ``total=``.
    """
    with ThreadPoolExecutor(max_workers=workers) as pool:
        done = pool.map(lambda task: task(), tasks)
        for _ in (progress(done, total=len(tasks)) if progress else done):
            pass


def _ranges(n, size):
    return [(a, min(a + size, n)) for a in range(0, n, size)]


def _convolve_lines(lines, gain, half, a, b):
    """Convolve ``lines[a:b]`` (time along rows) in place, keeping the valid part left-aligned.

    ``gain`` is the FIR's centred half-spectrum on the FFT grid (overlap-save blocks); after
    the call ``lines[a:b, :n - 2 half]`` holds the convolution centred at columns
    ``half .. n - half``.
    """
    n_fft = 2 * (gain.size - 1)
    n, step = lines.shape[1], n_fft - 2 * half
    for t0 in range(0, n - 2 * half, step):
        block = lines[a:b, t0:t0 + n_fft]
        y = fft.irfft(fft.rfft(block, n=n_fft, axis=-1) * gain, n=n_fft, axis=-1)
        width = min(step, n - 2 * half - t0)
        lines[a:b, t0:t0 + width] = y[:, half:half + width]  # rows past t0 + width unread


def apply_multirate(x2d, plan, workers, progress, precision, check=None, timings=None):
    """Return ``x + c`` for ``x2d`` (time, sensels) float64; see the module notes.

    ``precision`` ("single" or "double") is the type of the decimated record and its FFTs.
    ``progress`` wraps the tasks of stage 3 (the last and longest). ``check(lines)``, if
    given, sees the decimated record (sensels x decimated frames) before stage 2: a NaN
    anywhere in a sensel's record reaches its decimated line (every frame is under the
    low-pass), so NaN gaps are found in 1/P of the data. ``timings``, if a dict, receives
    the seconds of each stage (``benchmarks/bench_dynamic.py --stages``).
    """
    import time

    clock = [time.perf_counter()]

    def lap(stage):
        if timings is not None:
            clock.append(time.perf_counter())
            timings[stage] = clock[-1] - clock[-2]

    x2d = np.ascontiguousarray(x2d)  # the kernels stream whole rows
    n, m = x2d.shape
    factor, lowpass, taps = plan.factor, plan.lowpass, plan.correction
    c, half = lowpass.size // 2, taps.size // 2
    first = -(c // factor) - half  # decimated rows that stage 3 needs, plus stage 2's reach
    n_low = (n - 1 + c) // factor + half - first + 1
    lines = np.empty((m, n_low), dtype=PRECISIONS[precision])
    run_tasks([lambda a=a, b=b: _decimate_to_lines(x2d, lowpass, factor, first, a, b, lines)
          for a, b in _ranges(n_low, ROWS_PER_TASK)], workers)
    lap("decimate")
    if check is not None:
        check(lines)
    n_fft = fft.next_fast_len(max(min(BLOCK_FFT, n_low), 4 * taps.size), real=True)
    n_fft += n_fft % 2  # even, so that the half-spectrum's length gives it back
    gain = centred_spectrum(taps, n_fft, phase=plan.phase)
    gain = gain.astype(np.result_type(lines.dtype, np.complex64) if plan.phase else lines.dtype)
    run_tasks([lambda a=a, b=b: _convolve_lines(lines, gain, half, a, b)
          for a, b in _ranges(m, LINES_PER_TASK)], workers)
    lap("correct")
    out = np.empty_like(x2d)
    run_tasks([lambda a=a, b=b: _interpolate_add(x2d, lines, first + half, lowpass, factor, a, b,
                                            out)
          for a, b in _ranges(n, ROWS_PER_TASK)], workers, progress)
    lap("interpolate into the new output")
    return out


def legacy_apply_dask(arr, filt, precision="single"):
    """The dask path before issue 16: ``map_overlap`` of the in-memory method (multirate).

    Chunks overlap by the method's reach (rechunked so that chunk edges and the overlap are
    multiples of ``P``); each chunk plus its overlap is filtered by :func:`apply_multirate`.
    """
    import dask.array as da

    plan = plan_multirate(filt)
    reach, step = plan.reach, plan.factor
    depth = -(-reach // step) * step
    bounds = np.cumsum(arr.chunks[0])[:-1]
    if len(arr.chunks[0]) > 1 and (min(arr.chunks[0]) < depth or np.any(bounds % step)):
        size = -(-max(4 * filt.n_taps, arr.chunks[0][0], depth) // step) * step
        chunks = [size] * (arr.shape[0] // size)
        rest = arr.shape[0] - sum(chunks)
        if rest and chunks and rest < depth:
            chunks[-1] += rest
        elif rest:
            chunks.append(rest)
        arr = arr.rechunk({0: tuple(chunks)})

    def chunk(block):
        x2d = np.asarray(block, dtype=float).reshape(block.shape[0], -1)
        if x2d.shape[0] <= plan.reach + plan.factor:
            raise ValueError("chunk shorter than the method's reach")
        return apply_multirate(x2d, plan, 2, None, precision).reshape(block.shape)

    return da.map_overlap(chunk, arr.astype(float),
                          depth={0: depth} | {axis: 0 for axis in range(1, arr.ndim)},
                          boundary="none", trim=True, dtype=float)
