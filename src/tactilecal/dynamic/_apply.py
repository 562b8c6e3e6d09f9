"""Apply a correction filter to records and sensel recordings of any length.

Overlap-save convolution with the filter's centred FIR (:mod:`scipy.fft` ``rfft``/``irfft``
along the time axis of ``(time, sensels)`` blocks, ``workers`` threads): each block of
``L`` frames is extended by ``n_taps // 2`` frames on each side, filtered, and the extension
cut away, so the result does not depend on the block size. The record's own ends are
extended by an odd reflection about the end sample (value and slope continuous), the same
as the resampler, so the edges carry no transient from a large offset.

In-memory arrays are processed block by block on a thread pool (one thread per core;
bounded memory for the FFT work, single-precision FFTs by default); arrays
backed by dask (``xarray.open_dataset(..., chunks=...)``) are filtered lazily with
:func:`dask.array.map_overlap`, so recordings larger than memory stream through.
"""

import os

import numpy as np
import xarray as xr
from scipy import fft

from tactilecal.dynamic._records import label, sampling_rate_hz

__all__ = ["apply_filter"]

#: FFT length (frames) of one in-memory block (at least 4 filter lengths) and sensels per
#: block: 32 x 16384 float32 (2 MiB) keeps a block's temporaries in cache, which measured
#: 1.5-2x faster than 64 x 32768 on the 2-core test machine (the work is memory-bound).
BLOCK_FRAMES = 1 << 14
BLOCK_SENSELS = 32
#: Relative mismatch allowed between the record's rate and the filter's ``fs_hz``.
RATE_TOLERANCE = 0.005
#: Floating-point types of the FFT work.
PRECISIONS = {"single": (np.float32, np.complex64), "double": (np.float64, np.complex128)}


def _filter_lines(block, filt, workers=1, precision="single"):
    """Filter ``block`` (time first) circularly; return ``(filtered - start, start)``.

    Each sensel's first sample is subtracted (in float64) while casting to the FFT's type
    and must be added back by the caller (the filter's DC gain is exactly 1, so this
    changes nothing but the rounding): in single precision the FFT then rounds relative to
    the dynamic part, not to a large static offset. The circular convolution equals the
    linear one ``n_taps // 2`` samples away from both ends of the block (overlap-save).
    """
    real, _ = PRECISIONS[precision]
    n = block.shape[0]
    n_fft = fft.next_fast_len(n, real=True)
    start = np.array(block[:1], dtype=float)
    lines = np.empty(block.shape, dtype=real)
    np.subtract(block, start, out=lines, casting="same_kind")
    spectrum = fft.rfft(lines, n=n_fft, axis=0, workers=workers)
    spectrum *= filt.spectrum(n_fft).astype(real).reshape((-1,) + (1,) * (block.ndim - 1))
    return fft.irfft(spectrum, n=n_fft, axis=0, workers=workers)[:n], start


def _chunk(block, filt, precision):
    """Filter one dask chunk (with its overlap) in cache-sized blocks on the thread pool.

    Rows within ``n_taps // 2`` of the chunk's ends see the reflection of the chunk, not
    the record; ``map_overlap`` trims exactly those rows.
    """
    x2d = np.asarray(block, dtype=float).reshape(block.shape[0], -1)
    return _apply_numpy(x2d, filt, -1, None, precision).reshape(block.shape)


def _extended_rows(x, start, stop, half):
    """Rows ``start - half .. stop + half`` of ``x`` with odd reflection beyond its ends."""
    n = x.shape[0]
    if start - half >= 0 and stop + half <= n:
        return x[start - half:stop + half]
    idx = np.arange(start - half, stop + half)
    low, high = idx < 0, idx > n - 1
    src = np.where(low, -idx, np.where(high, 2 * (n - 1) - idx, idx))
    ext = x[src]
    if low.any():
        ext[low] = 2.0 * x[0] - ext[low]
    if high.any():
        ext[high] = 2.0 * x[n - 1] - ext[high]
    return ext


def _apply_numpy(x2d, filt, workers, progress, precision):
    """Overlap-save over (time, sensel) blocks, blocks spread over a thread pool."""
    from concurrent.futures import ThreadPoolExecutor

    half = filt.n_taps // 2
    n, m = x2d.shape
    n_fft = fft.next_fast_len(max(BLOCK_FRAMES, 4 * filt.n_taps), real=True)
    step = n_fft - 2 * half
    out = np.empty_like(x2d)
    blocks = [(t0, s0) for t0 in range(0, n, step) for s0 in range(0, m, BLOCK_SENSELS)]

    def run(block):
        t0, s0 = block
        t1, s1 = min(t0 + step, n), min(s0 + BLOCK_SENSELS, m)
        ext = _extended_rows(x2d[:, s0:s1], t0, t1, half)
        lines, start = _filter_lines(ext, filt, 1, precision)
        np.add(lines[half:half + t1 - t0], start, out=out[t0:t1, s0:s1])  # offset in float64

    threads = (os.cpu_count() or 1) if workers == -1 else max(int(workers), 1)
    if threads == 1:
        for block in (progress(blocks, total=len(blocks)) if progress else blocks):
            run(block)
        return out
    with ThreadPoolExecutor(max_workers=threads) as pool:
        done = pool.map(run, blocks)
        for _ in (progress(done, total=len(blocks)) if progress else done):
            pass
    return out


def _apply_dask(arr, filt, precision):
    import dask.array as da

    half = filt.n_taps // 2
    head = 2.0 * arr[:1] - arr[half:0:-1]
    tail = 2.0 * arr[-1:] - arr[-2:-half - 2:-1]
    padded = da.concatenate([head, arr, tail], axis=0)
    min_chunk = min(padded.chunks[0])
    if min_chunk < half:
        padded = padded.rechunk({0: max(4 * filt.n_taps, arr.chunks[0][0])})
    depth = {0: half} | {axis: 0 for axis in range(1, arr.ndim)}
    out = da.map_overlap(_chunk, padded, depth=depth, boundary="none", trim=True,
                         dtype=float, filt=filt, precision=precision)
    return out[half:half + arr.shape[0]]


def _check_nan_gaps(x2d, where):
    suspects = np.flatnonzero(np.isnan(x2d.sum(axis=0)))  # one pass; NaN propagates
    if suspects.size == 0:
        return
    nan = np.isnan(x2d[:, suspects])
    partial = np.flatnonzero(nan.any(axis=0) & ~nan.all(axis=0))
    if partial.size:
        k = int(partial[0])
        raise ValueError(f"{where}: sensel {int(suspects[k])} (flattened) has NaN from frame "
                         f"index {int(np.flatnonzero(nan[:, k])[0])} while other frames are "
                         f"finite ({partial.size} sensels with gaps); expected complete "
                         "sensels (all-NaN sensels outside the sensor shape are fine)")


def apply_filter(data, filt, *, precision="single", workers=-1, progress=None):
    """Correct a record or every sensel of a recording with a dynamic filter.

    Implements the application of the digital filter of Gillis (2013), section 4.3.3, to
    any number of channels.

    Parameters
    ----------
    data : xarray.DataArray
        Time along the first dimension (``frame`` or ``time``) with a ``time`` coordinate
        (s): a 1-D record or a ``("frame", "row", "col")`` recording. NumPy-backed or
        dask-backed (then the result is lazy).
    filt : CorrectionFilter
        Built for the record's sampling rate.
    precision : {"single", "double"}
        Floating-point type of the FFT work. ``"single"`` (default) makes the FFTs about
        4x faster (twice the SIMD lanes); each sensel's first value is removed (in float64)
        before the FFT and added back after it, so the rounding is relative to the dynamic
        part: differences from ``"double"`` measured at most 7e-7 of the record's range
        (RMS 4e-8) on the thesis sweep, far below an 8-bit sensel's resolution (1/255).
        The result is float64 either way.
    workers : int
        Threads over the blocks of in-memory data (-1: one per core).
    progress : callable, optional
        Wraps the iterator of finished blocks, called with ``total=`` the number of blocks
        (e.g. ``tactilecal.cli._common.progress``).

    Returns
    -------
    xarray.DataArray
        Same dims, coords and attrs, plus ``dynamic_filter`` (the filter as JSON text).
        Sensels that are NaN in every frame stay NaN.

    Raises
    ------
    ValueError
        Sampling rate not that of the filter, a record shorter than the filter, NaN gaps
        inside a sensel (NumPy-backed data only; dask data is not scanned).

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> from tactilecal.dynamic import CorrectionFilter
    >>> filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000,
    ...                                    band_hz=(1, 100))
    >>> t = np.arange(0, 4, 1e-3)
    >>> rec = xr.DataArray(100 + np.sin(2 * np.pi * 99 * t), dims="time",
    ...                    coords={"time": t})
    >>> out = apply_filter(rec, filt)
    >>> amp = np.abs(out - 100)[1000:-1000].max()
    >>> round(float(amp), 2), round(float(out.mean()), 2)
    (1.22, 100.0)
    """
    from tactilecal._jsonutil import dumps

    where = label(data, "data")
    if precision not in PRECISIONS:
        raise ValueError(f"precision={precision!r}; expected 'single' or 'double'")
    if "time" not in data.coords or data["time"].dims != data.dims[:1]:
        raise ValueError(f"{where}: expected a 'time' coordinate (s) along the first "
                         f"dimension; found dims {data.dims}")
    fs_hz = sampling_rate_hz(data["time"].values, where)
    if abs(fs_hz / filt.fs_hz - 1.0) > RATE_TOLERANCE:
        raise ValueError(f"{where} is sampled at {fs_hz:.6g} Hz; the filter was built for "
                         f"{filt.fs_hz:.6g} Hz (expected the same rate: resample first or "
                         "build a filter for this rate)")
    if data.shape[0] < filt.n_taps:
        raise ValueError(f"{where} has {data.shape[0]} frames ({data.shape[0] / fs_hz:.3g} "
                         f"s); expected at least the filter length {filt.n_taps} frames "
                         f"({filt.length_s:.3g} s)")
    if data.chunks is not None:
        values = _apply_dask(data.data.astype(float), filt, precision)
    else:
        x2d = np.asarray(data.values, dtype=float).reshape(data.shape[0], -1)
        _check_nan_gaps(x2d, where)
        values = _apply_numpy(x2d, filt, workers, progress, precision).reshape(data.shape)
    out = xr.DataArray(values, dims=data.dims, coords=data.coords, name=data.name,
                       attrs={**data.attrs, "dynamic_filter": dumps(filt.to_dict(),
                                                                     indent=None)})
    return out
