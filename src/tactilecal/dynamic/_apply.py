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
offset. Arrays backed by dask (``xarray.open_dataset(..., chunks=...)``) are filtered lazily,
so recordings larger than memory stream through: the multirate method as two tasks per
time chunk (decimate with the few rows around the chunk; then correct, with ``half``
decimated rows of the neighbours, a tenth of the bytes, and interpolate), whose tasks
read only their own chunk of the recording and small slices of its neighbours, so on
``dask.distributed`` each worker reads its chunks from the file and only the decimated
rows travel; the direct method by :func:`dask.array.map_overlap`. The causal filter
carries its IIR state from one time chunk to the next.
"""

import functools
import itertools
import os
import warnings

import numpy as np
import xarray as xr
from scipy import fft, signal

from tactilecal._errors import TactilecalError
from tactilecal._numba import njit, read_only
from tactilecal._validate import float_type
from tactilecal.dynamic._filter import PRECISIONS
from tactilecal.dynamic._multirate import (
    BlockLayout,
    apply_multirate,
    correct,
    decimate,
    fft_columns,
    interpolate,
    plan_multirate,
    run_tasks,
)
from tactilecal.dynamic._records import label, sampling_rate_hz, time_jitter_s

__all__ = ["apply_filter", "filter_values", "above_band_share", "BandWarning",
           "MAX_ABOVE_BAND"]

#: Share of a record's dynamic power above the filter's band (as corrected, see
#: :func:`above_band_share`) from which :func:`apply_filter` warns that the record is only
#: partly corrected: 1 % left with the 75 % error of a viscoelastic sensor's high
#: frequencies is a tenth of the dynamic RMS error.
MAX_ABOVE_BAND = 0.01
#: Sensels summed for that check: the most loaded contiguous run of the middle frame
#: (a contiguous run costs a thirtieth of a pass over a 1936-sensel recording).
STRIP_SENSELS = 64
#: Below this frequency a record's power is its static part (ramps, offset).
STATIC_CUTOFF_HZ = 0.5
#: Power above the band counts as content where it exceeds this many times the median
#: power above the band (the noise floor: white sensor noise alone does not warn).
FLOOR_FACTOR = 3.0


class BandWarning(UserWarning):
    """A record holds dynamic power above the filter's band, which it leaves uncorrected."""

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


def _apply_array(x2d, filt, workers, progress, precision, method, where=None, dtype=float):
    """Filter a ``(time, sensels)`` array in memory with the chosen method; ``dtype`` out.

    With ``where`` (the record's name), sensels with NaN gaps raise a ValueError. The
    multirate method reads float32 and float64 as they are; other types are converted.
    """
    threads = (os.cpu_count() or 1) if workers == -1 else max(int(workers), 1)
    plan = _plan(filt, x2d.shape[0], method)
    if plan is None:
        x2d = np.asarray(x2d, dtype=float)
        if where is not None:
            _check_nan_gaps(x2d, where, _nan_sensels(x2d.sum(axis=0)))
        return _apply_numpy(x2d, filt, threads, progress, precision, dtype)
    x2d = _native(x2d)
    check = None if where is None else (
        lambda sums: _check_nan_gaps(x2d, where, _nan_sensels(sums)))
    return apply_multirate(x2d, plan, threads, progress, precision, check, dtype=dtype)


def _native(x):
    """``x`` as a C-contiguous float32 or float64 array (other types become float64)."""
    dtype = x.dtype if x.dtype in (np.float32, np.float64) else np.float64
    return np.ascontiguousarray(x, dtype=dtype)


def _chunk(block, filt, precision, method, workers=1, dtype=float):
    """Filter one dask chunk (with its overlap) in memory (direct method, or a whole record).

    Rows within the method's reach of the chunk's ends see the reflection of the chunk, not
    the record; ``map_overlap`` trims exactly those rows. ``workers`` threads: 1 when dask
    runs several chunks at once (its threads are the parallelism; one per core inside
    each of them would oversubscribe the cores), -1 for an array of one chunk.
    """
    x2d = np.asarray(block).reshape(block.shape[0], -1)
    return _apply_array(x2d, filt, workers, None, precision, method,
                        dtype=dtype).reshape(block.shape)


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


def _apply_numpy(x2d, filt, threads, progress, precision, dtype=float):
    """Overlap-save over (time, sensel) blocks, blocks spread over ``threads`` threads."""
    half = filt.n_taps // 2
    n, m = x2d.shape
    n_fft = fft.next_fast_len(max(min(BLOCK_FRAMES, n + 2 * half), 4 * filt.n_taps), real=True)
    step = n_fft - 2 * half
    out = np.empty(x2d.shape, dtype=dtype)

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


def _apply_dask(arr, filt, precision, method, dtype=float):
    """Lazy filtering of a dask array, time along axis 0 (see the module notes).

    A record in one time chunk is filtered in memory chunk by chunk of sensels; the
    multirate method otherwise runs as its three stages per time chunk
    (:func:`_multirate_dask`); the direct method by :func:`_chunk` on chunks overlapping by
    its reach: the first and last chunks are filtered with the odd reflection about their
    outer rows, which are the record's ends, so the result equals the in-memory one.
    """
    import dask.array as da

    plan = _plan(filt, arr.shape[0], method)
    if arr.dtype not in (np.float32, np.float64):
        arr = arr.astype(float)

    def chunk(a):  # its threads: one per core for an array of one chunk (after rechunking)
        return functools.partial(_chunk, filt=filt, precision=precision, dtype=dtype,
                                 workers=-1 if a.npartitions == 1 else 1)

    if len(arr.chunks[0]) == 1:
        return arr.map_blocks(chunk(arr), dtype=dtype, method=method)
    if plan is not None:
        minimum = plan.factor * (plan.correction.size // 2 + 1)  # stage 2's reach, frames
        if min(arr.chunks[0][:-1]) < minimum:  # else its windows span many chunks
            size = max(minimum, arr.chunks[0][0])
            arr = arr.rechunk({0: _aligned_chunks(arr.shape[0], size, minimum)})
        return _multirate_dask(arr, plan, precision, dtype)
    depth = filt.n_taps // 2
    if min(arr.chunks[0]) < depth:
        size = max(4 * filt.n_taps, arr.chunks[0][0], depth)
        arr = arr.rechunk({0: _aligned_chunks(arr.shape[0], size, depth)})
    depths = {0: depth} | {axis: 0 for axis in range(1, arr.ndim)}
    return da.map_overlap(chunk(arr), arr, depth=depths, boundary="none", trim=True,
                          dtype=dtype, method="direct")


def _dask_array(name, layer, chunks, dtype, dependencies):
    """Make a dask array ``name`` from ``layer`` (its tasks, keyed ``(name, *index)``)."""
    import dask.array as da
    from dask.highlevelgraph import HighLevelGraph

    graph = HighLevelGraph.from_collections(name, layer, dependencies=dependencies)
    return da.Array(graph, name, chunks=chunks, dtype=dtype)


def _covering(bounds, start, stop):
    """Return the chunks (edges ``bounds``) holding rows ``start .. stop - 1``."""
    if stop <= start:
        return []
    return list(range(int(np.searchsorted(bounds, start, side="right")) - 1,
                      int(np.searchsorted(bounds, stop - 1, side="right"))))


def _source_rows(n, start, stop):
    """Rows ``[lo, hi)`` of the record that rows ``start .. stop - 1`` of its reflection use."""
    v = np.arange(start, stop)
    src = np.where(v < 0, -v, np.where(v > n - 1, 2 * (n - 1) - v, v))
    rows = [int(src.min()), int(src.max())]
    rows += [0] if start < 0 else []
    rows += [n - 1] if stop > n else []
    return min(rows), max(rows) + 1


def _slice(block, axis, a, b):
    """Task body: a copy of ``block[a:b]`` along ``axis`` (0 or -1; only that travels)."""
    return np.array(block[a:b] if axis == 0 else block[..., a:b])


def _pieces(layer, key, source, index, bounds, axis, lo, hi):
    """Add to ``layer`` the tasks cutting ``[lo, hi)`` along ``axis`` out of ``source``.

    ``bounds`` are the edges of ``source``'s chunks along ``axis``, ``index(k)`` the block
    index of its chunk ``k``; ``key`` starts the new keys. Returns the keys, in order.
    """
    keys = []
    for k in _covering(bounds, lo, hi):
        a, b = max(lo, bounds[k]) - bounds[k], min(hi, bounds[k + 1]) - bounds[k]
        layer[(*key, k)] = (_slice, (source.name, *index(k)), axis, a, b)
        keys.append((*key, k))
    return keys


def _reflected_rows(blocks, first_row, n, start, stop):
    """Rows ``start .. stop - 1`` of the odd-reflected record from consecutive ``blocks``.

    ``blocks`` (2-D, time first) hold the record's rows from ``first_row`` on. Rows inside
    the record are a view when one block holds them; the reflections beyond its ends
    (``2 x[0] - x[-v]`` and ``2 x[n - 1] - x[2 (n - 1) - v]``) are reversed slices, so
    no row is gathered by index (that took 3x longer on the 2040-row edges of the
    thesis filter).
    """
    rows = np.concatenate(blocks) if len(blocks) > 1 else blocks[0]
    inner = max(start, 0) - first_row, min(stop, n) - first_row
    if start >= 0 and stop <= n:
        return rows[inner[0]:inner[1]]
    out = np.empty((stop - start, *rows.shape[1:]), dtype=rows.dtype)
    low = min(stop, 0) - start  # rows of out before the record's first
    if low > 0:  # v = start .. start + low - 1 reflects rows -start .. -start - low + 1
        top = -start - first_row
        np.subtract(2 * rows[-first_row], rows[top - low + 1:top + 1][::-1], out=out[:low])
    if inner[1] > inner[0]:
        out[max(-start, 0):max(-start, 0) + inner[1] - inner[0]] = rows[inner[0]:inner[1]]
    high = stop - max(start, n)  # rows of out after the record's last
    if high > 0:  # v = max(start, n) .. stop - 1 reflects rows 2 (n - 1) - v
        top = 2 * (n - 1) - max(start, n) - first_row
        np.subtract(2 * rows[n - 1 - first_row], rows[top - high + 1:top + 1][::-1],
                    out=out[out.shape[0] - high:])
    return out


def _flat(block):
    """Return a block of the recording as ``(time, sensels)``, float32 or float64."""
    return _native(block.reshape(block.shape[0], -1))


def _decimate_task(ref, rows, *pieces, spec):
    """Stage 1 of one chunk: its decimated samples, time last (see :func:`decimate`).

    ``pieces`` hold the record's rows the rows before and after the chunk are made of
    (``spec["before"]`` and ``spec["after"]``: ``(start, stop, first row, pieces)``).
    """
    pieces = [_flat(p) for p in pieces]
    (start, stop, lo, count), after = spec["before"], spec["after"]
    before = _reflected_rows(pieces[:count], lo, spec["n"], start, stop)
    after = _reflected_rows(pieces[count:], after[2], spec["n"], after[0], after[1])
    lines, _ = decimate(before, _flat(rows), after, spec["plan"], spec["first"],
                        spec["n_lines"], precision=spec["precision"],
                        reference=np.asarray(ref[0], dtype=float).reshape(-1))
    return lines.reshape(*rows.shape[1:], -1)


def _correct_interpolate_task(rows, *pieces, spec):
    """Stages 2 and 3 of one chunk: the chunk plus its interpolated correction.

    ``pieces`` hold the decimated samples stage 2 reads for the corrected samples stage 3
    needs (see :class:`BlockLayout`): they are copied into a window as long as the FFT
    blocks read, its end zeroed, and corrected in place (:func:`correct`), so the
    corrected samples neither travel nor are copied again (one task per chunk where a
    stage each made two, and the neighbours' corrected columns were cut and sent).
    """
    plan, n_out = spec["plan"], spec["n_out"]
    flat = [p.reshape(-1, p.shape[-1]) for p in pieces]
    window = np.empty((flat[0].shape[0], fft_columns(plan, n_out)), dtype=flat[0].dtype)
    end = 0
    for piece in flat:
        window[:, end:end + piece.shape[-1]] = piece
        end += piece.shape[-1]
    window[:, end:] = 0
    correct(window, plan, n_out, out=window)
    return interpolate(_flat(rows), window, plan, spec["offset"],
                       dtype=spec["dtype"]).reshape(rows.shape)


def _owned(n, bounds, plan):
    """Decimated samples owned by each time chunk (edges of global grid indices).

    Sample ``g`` (at frame ``P g``) belongs to the chunk holding that frame; the first and
    last chunks also own the samples beyond the record's ends that the edges need. Returns
    the edges, the first at the grid index of the record's first decimated sample.
    """
    whole = BlockLayout.of(plan, 0, n)
    lines0 = -(whole.q_half + plan.correction.size // 2)
    inner = [-(-int(b) // plan.factor) for b in bounds[1:-1]]
    return [lines0, *inner, lines0 + whole.decimated]


def _first_row(arr):
    """Return ``arr[0:1]`` as a copy.

    A view would keep the whole first chunk in memory until the last task that reads the
    first row (every chunk's) has run.
    """
    return arr[0:1].map_blocks(np.copy, dtype=arr.dtype)


def _sensel_blocks(arr):
    """Block indices of ``arr`` over its sensel dimensions (all but the first)."""
    return list(itertools.product(*[range(len(c)) for c in arr.chunks[1:]]))


def _multirate_dask(arr, plan, precision, dtype=float):
    """Run the multirate method on a dask array with several time chunks (time first).

    Stage 1 per chunk (with the ``c``-odd rows around it, or the reflection at the record's
    ends) gives the decimated samples the chunk owns (time last); one task per chunk then
    runs stages 2 and 3 (:func:`_correct_interpolate_task`): from the decimated samples it
    owns and ``half`` plus a few more of each neighbour's, the corrected samples its
    interpolation reads, then the chunk. The rows and columns a task needs from its
    neighbours are cut out by small tasks that run where those chunks are, so on a
    cluster only they travel. Chunks over sensels are kept. Equal to the in-memory method;
    the FFT blocks differ, so in single precision to float32 rounding.
    """
    from dask.base import tokenize

    n, c, half = arr.shape[0], plan.lowpass.size // 2, plan.correction.size // 2
    bounds = [int(b) for b in np.r_[0, np.cumsum(arr.chunks[0])]]
    owned = _owned(n, bounds, plan)
    token = tokenize(arr, plan.lowpass, plan.correction, precision, dtype)
    ref, sensels, n_chunks = _first_row(arr), _sensel_blocks(arr), len(bounds) - 1
    real = PRECISIONS[precision]
    name = f"tactilecal-decimate-{token}"
    tasks = {}
    for i in range(n_chunks):
        first = plan.factor * owned[i] - bounds[i]
        last = first + plan.factor * (owned[i + 1] - owned[i] - 1) + c
        sides = ((bounds[i] - max(c - first, 1), bounds[i]),
                 (bounds[i + 1], bounds[i + 1] + max(last - (bounds[i + 1] - bounds[i]) + 1, 1)))
        rows = [_source_rows(n, *side) for side in sides]
        spec = {"plan": plan, "precision": precision, "n": n, "first": first,
                "n_lines": owned[i + 1] - owned[i],
                "before": (*sides[0], rows[0][0], len(_covering(bounds, *rows[0]))),
                "after": (*sides[1], rows[1][0], len(_covering(bounds, *rows[1])))}
        for j in sensels:
            keys = [key for side, (lo, hi) in zip(("before", "after"), rows, strict=True)
                    for key in _pieces(tasks, (f"{name}-{side}", i, *j), arr,
                                       lambda k, j=j: (k, *j), bounds, 0, lo, hi)]
            tasks[(name, *j, i)] = (functools.partial(_decimate_task, spec=spec),
                                    (ref.name, 0, *j), (arr.name, i, *j), *keys)
    lines = _dask_array(name, tasks, (*arr.chunks[1:], tuple(np.diff(owned))), real,
                        [arr, ref])
    edges = [k - owned[0] for k in owned]
    name = f"tactilecal-filter-{token}"
    tasks = {}
    for i in range(n_chunks):
        layout = BlockLayout.of(plan, bounds[i], bounds[i + 1] - bounds[i])
        start = bounds[i] // plan.factor - layout.q_half - half - owned[0]
        spec = {"plan": plan, "offset": bounds[i], "n_out": layout.corrected, "dtype": dtype}
        for j in sensels:
            keys = _pieces(tasks, (f"{name}-window", i, *j), lines, lambda k, j=j: (*j, k),
                           edges, -1, start, start + layout.decimated)
            tasks[(name, i, *j)] = (functools.partial(_correct_interpolate_task, spec=spec),
                                    (arr.name, i, *j), *keys)
    return _dask_array(name, tasks, arr.chunks, dtype, [arr, lines])


@njit(nogil=True, fastmath={"contract"})
def _sosfilt_rows(sos, rows, first, state, s0, s1, out):  # pragma: no cover
    """``out[:, s] = sosfilt(sos, rows[:, s] - first[s]) + first[s]`` for ``s0 <= s < s1``.

    Transposed direct form II, section by section, as :func:`scipy.signal.sosfilt`;
    ``state`` (sections x 2 x sensels, float64) is the filters' state, updated in place,
    so a record can be filtered in consecutive blocks. The loops run along the rows
    (all sensels of a frame at once).
    """
    n_sections = sos.shape[0]
    width = s1 - s0
    x = np.empty(width)
    for t in range(rows.shape[0]):
        row = rows[t]
        for s in range(width):
            x[s] = row[s0 + s] - first[s0 + s]
        for k in range(n_sections):
            b0, b1, b2 = sos[k, 0], sos[k, 1], sos[k, 2]
            a1, a2 = sos[k, 4], sos[k, 5]
            z0, z1 = state[k, 0], state[k, 1]
            for s in range(width):
                v = x[s]
                y = b0 * v + z0[s0 + s]
                z0[s0 + s] = b1 * v - a1 * y + z1[s0 + s]
                z1[s0 + s] = b2 * v - a2 * y
                x[s] = y
        y_row = out[t]
        for s in range(width):
            y_row[s0 + s] = x[s] + first[s0 + s]


def _causal_block(rows, first, state, sos, workers=1, dtype=float):
    """Filter ``rows`` (time first) causally from ``state``; return ``(out, state)``."""
    shape = rows.shape
    rows = read_only(_flat(rows))  # one kernel for a dask chunk and an array of our own
    m = rows.shape[1]
    first = np.array(first, dtype=float).reshape(m)  # writable, as the kernel was compiled
    state = np.zeros((sos.shape[0], 2, m)) if state is None else state.copy()
    out = np.empty(rows.shape, dtype=dtype)
    threads = (os.cpu_count() or 1) if workers == -1 else max(int(workers), 1)
    step = max(-(-m // threads), 256)
    run_tasks([lambda a=a: _sosfilt_rows(sos, rows, first, state, a, min(a + step, m), out)
               for a in range(0, m, step)], threads)
    return out.reshape(shape), state


def _apply_causal(data, filt, workers=-1, dtype=float):
    """Filter ``data`` with the causal inverse (second-order sections), time first.

    Each sensel's first value is removed before and added back after, so the filter starts
    at rest on the record's first state (``1 / H`` has unit gain at 0 Hz). A dask-backed
    recording is filtered lazily chunk by chunk along time, each chunk's task starting
    from the filters' state at the end of the previous one (see :func:`_causal_dask`).
    """
    sos = filt.sos()
    if data.chunks is None:
        x = data.values
        return _causal_block(x, x[0], None, sos, workers=workers, dtype=dtype)[0]
    arr = data.data
    if arr.dtype not in (np.float32, np.float64):
        arr = arr.astype(float)
    return _causal_dask(arr, sos, dtype)


def _causal_dask(arr, sos, dtype=float):
    """Filter a dask array causally: chunk ``(i, J)`` starts from ``(i - 1, J)``'s state.

    Each chunk's task returns ``(out, state)``; the next chunk depends on the state alone
    (sections x 2 x sensels), so a chunk's output is neither kept for, nor sent to, the
    task of the next one.
    """
    import operator

    from dask.base import tokenize

    token = f"tactilecal-causal-{tokenize(arr, sos, dtype)}"
    first = _first_row(arr)
    layer = {}
    for j in _sensel_blocks(arr):
        state = None
        for i in range(len(arr.chunks[0])):
            run = (token + "-run", i, *j)
            layer[run] = (_causal_task, sos, (arr.name, i, *j), (first.name, 0, *j), state,
                          dtype)
            layer[(token, i, *j)] = (operator.getitem, run, 0)
            state = (token + "-state", i, *j)
            layer[state] = (operator.getitem, run, 1)
    return _dask_array(token, layer, arr.chunks, dtype, [arr, first])


def _causal_task(sos, rows, first, state, dtype):
    """Task body of :func:`_causal_dask`: ``(out, state)`` from the previous chunk's state."""
    return _causal_block(rows, first[0], state, sos, dtype=dtype)


def _nan_sensels(sums):
    """Sensels whose sum over time is not finite (NaN propagates): the suspects."""
    return np.flatnonzero(~np.isfinite(sums))


def _check_nan_gaps(x2d, where, suspects):
    """Raise if a suspect sensel has NaN in some frames but not all, or an infinite value.

    An infinite value (or one so large the sum over time overflows) would make the whole
    filtered sensel non-finite.
    """
    if suspects.size == 0:
        return
    big = ~np.isfinite(np.where(np.isnan(x2d[:, suspects]), 0.0, x2d[:, suspects]).sum(axis=0))
    if big.any():
        k = int(np.flatnonzero(big)[0])
        raise TactilecalError(f"{where}: sensel {int(suspects[k])} (flattened) holds an infinite "
                              "value or values too large to filter; expected finite readings "
                              "(NaN for sensels outside the sensor shape)")
    nan = np.isnan(x2d[:, suspects])
    partial = np.flatnonzero(nan.any(axis=0) & ~nan.all(axis=0))
    if partial.size:
        k = int(partial[0])
        raise TactilecalError(f"{where}: sensel {int(suspects[k])} (flattened) has NaN from frame "
                              f"index {int(np.flatnonzero(nan[:, k])[0])} while other frames are "
                              f"finite ({partial.size} sensels with gaps); expected complete "
                              "sensels (all-NaN sensels outside the sensor shape are fine)")


def above_band_share(data, filt):
    """Share of a record's dynamic power that is content above ``filt``'s band, and where.

    Measured on the sum of the most loaded contiguous run of ``STRIP_SENSELS`` sensels of
    the middle frame (the whole record for a 1-D one), over the first time chunk of
    dask-backed data, with Welch power in 1 Hz bins, as the load would have it: inside the
    band (above ``STATIC_CUTOFF_HZ``) the power times ``|G|^2`` (the correction), above it
    the power in excess of ``FLOOR_FACTOR`` times its median (the noise floor) times
    ``|G(band top)|^2``, the best guess of the correction there (a sensor under-reads its
    high frequencies, so its own power there understates them). Broadband content that
    fills the whole range above the band raises that floor too, and is underestimated.

    Returns
    -------
    (float, str)
    """
    arr = data.data if data.chunks is not None else data.values
    flat = arr.reshape(arr.shape[0], -1)
    if data.chunks is not None:
        flat = flat[:data.chunks[0][0]]
    m = flat.shape[1]
    width = min(m, STRIP_SENSELS)
    middle = np.nan_to_num(np.abs(np.asarray(flat[flat.shape[0] // 2], dtype=float)))
    start = int(np.argmax(np.convolve(middle, np.ones(width), "valid")))
    series = np.asarray(np.sum(flat[:, start:start + width], axis=1, dtype=float))
    if not np.isfinite(series).all():  # NaN sensels in the strip (outside the shape)
        series = np.nansum(np.asarray(flat[:, start:start + width], dtype=float), axis=1)
    fs_hz = filt.fs_hz
    f_hz, power = signal.welch(series, fs=fs_hz, nperseg=min(series.size, int(round(fs_hz))))
    top = filt.band_hz[1]
    inside = (f_hz > STATIC_CUTOFF_HZ) & (f_hz <= top)
    above = power[f_hz > top]
    excess = np.maximum(above - FLOOR_FACTOR * np.median(above), 0.0).sum() if above.size \
        else 0.0
    excess *= float(np.abs(filt.target(top)) ** 2)
    total = float(np.sum(power[inside] * np.abs(filt.target(f_hz[inside])) ** 2)) + excess
    share = float(excess / total) if total > 0 else 0.0
    what = "the record" if m == 1 else f"the sum of sensels {start}-{start + width - 1}"
    if data.chunks is not None and len(data.chunks[0]) > 1:
        what += f" over its first {flat.shape[0]} frames"
    return share, what


def apply_filter(data, filt, *, precision="single", workers=-1, progress=None,
                 method="auto", causal=False, dtype="float64"):
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
        The result's type is ``dtype`` either way.
    workers : int
        Threads over the blocks of in-memory data (-1: one per core).
    progress : callable, optional
        Wraps the iterator of finished blocks, called with ``total=`` the number of blocks
        (the protocol of :mod:`tactilecal._progress`).
    method : {"auto", "direct"}
        ``"auto"`` (default) uses the multirate method when the filter's correction is
        band-limited well below the Nyquist frequency (see the module notes; 3-5x faster on
        the thesis' 4000 Hz filter), else the direct overlap-save; ``"direct"`` always
        convolves with the FIR at the full rate.
    causal : bool
        For a rational filter (``filt.rational``): apply the causal inverse ``1 / H``
        (second-order sections in transposed direct form II, as
        :func:`scipy.signal.sosfilt`, run by a numba kernel over whole rows of the
        recording; for streaming and real time)
        instead of the offline one (default: the centred FIR of ``1 / H``, tapered to 1
        above the band like every filter, so noise above the band is not amplified, through
        the same multirate and dask paths). Zero-phase (log) and ``wiener`` filters have no
        causal form.
    dtype : {"float64", "float32"}
        Type of the result (default float64). ``"float32"`` halves the result's memory
        and, for a float32 recording, the bytes written: the fastest path for long
        recordings (``benchmarks/bench_dynamic.py``). It rounds each value to float32
        (relative 6e-8 of the value, offset included: for an 8-bit sensel a ten-thousandth
        of a count); a float32 recording is filtered in float32 already.

    Returns
    -------
    xarray.DataArray
        Same dims, coords and attrs, plus ``dynamic_filter`` (the filter as JSON text).
        Sensels that are NaN in every frame stay NaN.

    Raises
    ------
    TactilecalError
        Sampling rate not that of the filter, a record shorter than the filter, NaN gaps
        inside a sensel or infinite values (NumPy-backed data only; dask data is not
        scanned), a ``dtype`` other than float64 or float32.

    Warns
    -----
    BandWarning
        When more than ``MAX_ABOVE_BAND`` (1 %) of the record's dynamic power is content
        above the filter's band (:func:`above_band_share`): that part is left as recorded.

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
    out = filter_values(data, filt, precision=precision, workers=workers, progress=progress,
                        method=method, causal=causal, dtype=dtype)
    share, what = above_band_share(data, filt)
    if share > MAX_ABOVE_BAND:
        warnings.warn(f"{label(data, 'data')}: {share:.0%} of the dynamic power of {what} is "
                      f"content above the filter's band ({filt.band_hz[1]:g} Hz), where the "
                      "sweep carried no coherent energy: that part is left uncorrected",
                      BandWarning, stacklevel=2)
    return out


def filter_values(data, filt, *, precision="single", workers=-1, progress=None,
                  method="auto", causal=False, dtype="float64"):
    """:func:`apply_filter` without the check of the power above the band."""
    from tactilecal._jsonutil import dumps

    where = label(data, "data")
    if precision not in PRECISIONS:
        raise TactilecalError(f"precision={precision!r}; expected 'single' or 'double'")
    if method not in METHODS:
        raise TactilecalError(f"method={method!r}; expected 'auto' or 'direct'")
    dtype = float_type(dtype)
    if "time" not in data.coords or data["time"].dims != data.dims[:1]:
        raise TactilecalError(f"{where}: expected a 'time' coordinate (s) along the first "
                              f"dimension; found dims {data.dims}")
    time_s = data["time"].values  # once: on a cluster each .values is a round trip
    fs_hz = sampling_rate_hz(time_s, where)
    if abs(fs_hz / filt.fs_hz - 1.0) > RATE_TOLERANCE:
        raise TactilecalError(f"{where} is sampled at {fs_hz:.6g} Hz; the filter was built for "
                              f"{filt.fs_hz:.6g} Hz (expected the same rate: resample first or "
                              "build a filter for this rate)")
    if data.shape[0] < filt.n_taps and not causal:
        raise TactilecalError(f"{where} has {data.shape[0]} frames ({data.shape[0] / fs_hz:.3g} "
                              f"s); expected at least the filter length {filt.n_taps} frames "
                              f"({filt.length_s:.3g} s)")
    if causal:  # filt.sos() raises first for a filter with no causal form
        values = _apply_causal(data, filt, workers, dtype)
    elif data.chunks is not None:
        values = _apply_dask(data.data, filt, precision, method, dtype)
    else:
        x2d = data.values.reshape(data.shape[0], -1)
        values = _apply_array(x2d, filt, workers, progress, precision, method, where, dtype)
        values = values.reshape(data.shape)
    out = xr.DataArray(values, dims=data.dims, coords=data.coords, name=data.name,
                       attrs={**data.attrs, "dynamic_filter": dumps(filt.to_dict(),
                                                                     indent=None),
                              "sampling_rate_hz": fs_hz,
                              "time_jitter_s": time_jitter_s(time_s)})
    return out
