"""Apply a correction filter to records and sensel recordings of any length.

Two realisations of the same filter (they differ by 2.7e-6 of the record's range on a
random walk plus noise, 1.8e-5 on white noise; see docs/dynamic-calibration.md):

* ``"direct"``: overlap-save convolution with the filter's centred FIR (:mod:`scipy.fft`
  ``rfft``/``irfft`` along the time axis of ``(time, sensels)`` blocks on a thread pool): each
  block of ``L`` frames is extended by ``n_taps // 2`` frames on each side, filtered, and the
  extension cut away, so the result does not depend on the block size.
* ``"multirate"`` (:mod:`tactilecal.dynamic._multirate`): the correction ``(G - 1) x``, which
  is band-limited to the band's top plus the taper, is computed at a ``P`` times lower rate
  and interpolated back. Used by ``method="auto"`` whenever ``P >= 2`` (a taper above the
  band, and a band's top plus taper below an eighth of the sampling rate).

The record's own ends are extended by an odd reflection about the end sample (value and
slope continuous), the same as the resampler, so the edges carry no transient from a large
offset. Arrays backed by dask (``xarray.open_dataset(..., chunks=...)``) are filtered lazily
with :func:`dask.array.map_overlap`, so recordings larger than memory stream through.
"""

import os

import numpy as np
import xarray as xr
from scipy import fft

from tactilecal.dynamic._filter import PRECISIONS
from tactilecal.dynamic._multirate import apply_multirate, plan_multirate, run_tasks
from tactilecal.dynamic._records import label, sampling_rate_hz, time_jitter_s

__all__ = ["apply_filter"]

#: FFT length (frames) of one in-memory block (at least 4 filter lengths) and sensels per
#: block: 32 x 16384 float32 (2 MiB) keeps a block's temporaries in cache, which measured
#: 1.5-2x faster than 64 x 32768 on the 2-core test machine (the work is memory-bound).
BLOCK_FRAMES = 1 << 14
BLOCK_SENSELS = 32
#: Relative mismatch allowed between the record's rate and the filter's ``fs_hz``.
RATE_TOLERANCE = 0.005
METHODS = ("auto", "direct")


def _filter_lines(block, filt, precision="single"):
    """Filter ``block`` (time first) circularly; return ``(filtered - offset, offset)``.

    Each sensel's first sample is subtracted (in float64) while casting to the FFT's type;
    the caller adds back ``offset``, that sample times the filter's DC gain. In single
    precision the FFT then rounds relative to the dynamic part, not to a large static
    offset. The circular convolution equals the linear one ``n_taps // 2`` samples away
    from both ends of the block (overlap-save).
    """
    real = PRECISIONS[precision]
    n = block.shape[0]
    n_fft = fft.next_fast_len(n, real=True)
    start = np.array(block[:1], dtype=float)
    lines = np.empty(block.shape, dtype=real)
    np.subtract(block, start, out=lines, casting="same_kind")
    gain = filt.spectrum(n_fft)
    spectrum = fft.rfft(lines, n=n_fft, axis=0)
    spectrum *= gain.astype(spectrum.dtype if filt.has_phase else real).reshape(
        (-1,) + (1,) * (block.ndim - 1))
    return fft.irfft(spectrum, n=n_fft, axis=0)[:n], start * gain[0].real


def _plan(filt, n_frames, method):
    """Return the multirate plan if ``method`` allows it and the record is long enough."""
    plan = plan_multirate(filt) if method == "auto" else None
    return plan if plan is not None and plan.reach + plan.factor < n_frames else None


def _apply_array(x2d, filt, workers, progress, precision, method, where=None):
    """Filter a float64 ``(time, sensels)`` array in memory with the chosen method.

    With ``where`` (the record's name), sensels with NaN gaps raise a ValueError.
    """
    threads = (os.cpu_count() or 1) if workers == -1 else max(int(workers), 1)
    plan = _plan(filt, x2d.shape[0], method)
    if plan is None:
        if where is not None:
            _check_nan_gaps(x2d, where, _nan_sensels(x2d.sum(axis=0)))
        return _apply_numpy(x2d, filt, threads, progress, precision)
    check = None if where is None else (
        lambda lines: _check_nan_gaps(x2d, where, _nan_sensels(lines.sum(axis=1))))
    return apply_multirate(x2d, plan, threads, progress, precision, check)


def _chunk(block, filt, precision, method):
    """Filter one dask chunk (with its overlap) in memory.

    Rows within the method's reach of the chunk's ends see the reflection of the chunk, not
    the record; ``map_overlap`` trims exactly those rows.
    """
    x2d = np.asarray(block, dtype=float).reshape(block.shape[0], -1)
    return _apply_array(x2d, filt, -1, None, precision, method).reshape(block.shape)


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


def _apply_numpy(x2d, filt, threads, progress, precision):
    """Overlap-save over (time, sensel) blocks, blocks spread over ``threads`` threads."""
    half = filt.n_taps // 2
    n, m = x2d.shape
    n_fft = fft.next_fast_len(max(min(BLOCK_FRAMES, n + 2 * half), 4 * filt.n_taps), real=True)
    step = n_fft - 2 * half
    out = np.empty_like(x2d)

    def run(t0, s0):
        t1, s1 = min(t0 + step, n), min(s0 + BLOCK_SENSELS, m)
        ext = _extended_rows(x2d[:, s0:s1], t0, t1, half)
        lines, offset = _filter_lines(ext, filt, precision)
        np.add(lines[half:half + t1 - t0], offset, out=out[t0:t1, s0:s1])  # in float64

    run_tasks([lambda t0=t0, s0=s0: run(t0, s0) for t0 in range(0, n, step)
               for s0 in range(0, m, BLOCK_SENSELS)], threads, progress)
    return out


def _aligned_chunks(total, size, minimum):
    """Chunk sizes along time: ``size`` each, the remainder merged into the last if short."""
    chunks = [size] * (total // size)
    rest = total - sum(chunks)
    if rest and chunks and rest < minimum:
        chunks[-1] += rest
    elif rest:
        chunks.append(rest)
    return tuple(chunks)


def _apply_dask(arr, filt, precision, method):
    """Lazy filtering: :func:`_chunk` on chunks overlapping by the method's reach.

    The first and last chunks are filtered with the odd reflection about their outer rows,
    which are the record's ends, so the result equals the in-memory one. With the multirate
    method the chunk boundaries and the overlap are multiples of the decimation factor, so
    every chunk decimates on the record's own sample grid.
    """
    import dask.array as da

    plan = _plan(filt, arr.shape[0], method)
    step = 1 if plan is None else plan.factor
    reach = filt.n_taps // 2 if plan is None else plan.reach
    depth = -(-reach // step) * step
    bounds = np.cumsum(arr.chunks[0])[:-1]
    if len(arr.chunks[0]) > 1 and (min(arr.chunks[0]) < depth or np.any(bounds % step)):
        size = -(-max(4 * filt.n_taps, arr.chunks[0][0], depth) // step) * step
        arr = arr.rechunk({0: _aligned_chunks(arr.shape[0], size, depth)})
    return da.map_overlap(_chunk, arr, depth={0: depth} | {axis: 0 for axis in range(1, arr.ndim)},
                          boundary="none", trim=True, dtype=float, filt=filt,
                          precision=precision, method="direct" if plan is None else method)


def _apply_causal(data, filt):
    """Filter every sensel with the causal inverse ``1 / H`` (``scipy.signal.sosfilt``).

    Each sensel's first value is removed before and added back after, so the filter starts
    at rest on the record's first state (``1 / H`` has unit gain at 0 Hz). A dask-backed
    recording is filtered lazily, chunked over sensels (time in one chunk: the IIR carries
    its state along time).
    """
    from scipy import signal

    sos = filt.sos()

    def run(block):
        x = np.asarray(block, dtype=float)
        first = x[:1]
        return signal.sosfilt(sos, x - first, axis=0) + first

    if data.chunks is None:
        return run(data.values)
    arr = data.data.astype(float).rechunk({0: -1})
    return arr.map_blocks(run, dtype=float)


def _nan_sensels(sums):
    """Sensels whose sum over time is NaN (NaN propagates): one pass finds the suspects."""
    return np.flatnonzero(np.isnan(sums))


def _check_nan_gaps(x2d, where, suspects):
    """Raise if a suspect sensel has NaN in some frames but not all."""
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


def apply_filter(data, filt, *, precision="single", workers=-1, progress=None,
                 method="auto", causal=False):
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
    method : {"auto", "direct"}
        ``"auto"`` (default) uses the multirate method when the filter's correction is
        band-limited well below the Nyquist frequency (see the module notes; 3-5x faster on
        the thesis' 4000 Hz filter), else the direct overlap-save; ``"direct"`` always
        convolves with the FIR at the full rate.
    causal : bool
        For a rational filter (``filt.rational``): apply the causal inverse ``1 / H``
        (second-order sections, :func:`scipy.signal.sosfilt`; for streaming and real time)
        instead of the offline one (default: the centred FIR of ``1 / H``, tapered to 1
        above the band like every filter, so noise above the band is not amplified, through
        the same multirate and dask paths). Zero-phase (log) and ``wiener`` filters have no
        causal form.

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
    if method not in METHODS:
        raise ValueError(f"method={method!r}; expected 'auto' or 'direct'")
    if "time" not in data.coords or data["time"].dims != data.dims[:1]:
        raise ValueError(f"{where}: expected a 'time' coordinate (s) along the first "
                         f"dimension; found dims {data.dims}")
    fs_hz = sampling_rate_hz(data["time"].values, where)
    if abs(fs_hz / filt.fs_hz - 1.0) > RATE_TOLERANCE:
        raise ValueError(f"{where} is sampled at {fs_hz:.6g} Hz; the filter was built for "
                         f"{filt.fs_hz:.6g} Hz (expected the same rate: resample first or "
                         "build a filter for this rate)")
    if data.shape[0] < filt.n_taps and not causal:
        raise ValueError(f"{where} has {data.shape[0]} frames ({data.shape[0] / fs_hz:.3g} "
                         f"s); expected at least the filter length {filt.n_taps} frames "
                         f"({filt.length_s:.3g} s)")
    if causal:  # filt.sos() raises first for a filter with no causal form
        values = _apply_causal(data, filt)
    elif data.chunks is not None:
        values = _apply_dask(data.data.astype(float), filt, precision, method)
    else:
        x2d = np.asarray(data.values, dtype=float).reshape(data.shape[0], -1)
        values = _apply_array(x2d, filt, workers, progress, precision, method, where)
        values = values.reshape(data.shape)
    out = xr.DataArray(values, dims=data.dims, coords=data.coords, name=data.name,
                       attrs={**data.attrs, "dynamic_filter": dumps(filt.to_dict(),
                                                                     indent=None),
                              "sampling_rate_hz": fs_hz,
                              "time_jitter_s": time_jitter_s(data["time"].values)})
    return out
