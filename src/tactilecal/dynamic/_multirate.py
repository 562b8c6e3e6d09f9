"""Multirate application of a correction filter: decimate, correct, interpolate back.

A correction filter with ``outside="taper"`` changes only frequencies below
``f_c = band_hz[1] + taper_hz``; above ``f_c`` its gain is 1. So the corrected record is

    y = x + c,    c = (G - 1) * x,

and the correction ``c`` is band-limited to ``f_c``. It can be computed at the rate
``fs / P`` (Crochiere & Rabiner 1983, *Multirate digital signal processing*: decimation,
interpolation and their polyphase structures). ``P = floor(fs / (4 f_c))`` leaves the
low-pass a transition band at least ``2 f_c`` wide (from ``f_c`` to ``fs / P - f_c``), so it
stays short (41 taps for the thesis filter: 4000 Hz, band 1..140 Hz, 35 Hz taper, P = 5):

1. ``x_d = (h * x)[::P]``: a zero-phase Kaiser low-pass ``h`` (pass band to ``f_c``, stop band
   from ``fs / P - f_c``, ``STOPBAND_DB`` down) and every P-th sample;
2. ``c_d = D x_d`` at ``fs / P`` by overlap-save FFTs, with ``D(f) = (G(f) - 1) / H(f)^2``
   (complex for a filter that undoes the sensor's phase)
   for ``f <= f_c`` and 0 above (``H`` the low-pass's gain, so the low-pass and the
   interpolation filter are compensated), designed like the full-rate FIR
   (:func:`~tactilecal.dynamic._filter.zero_phase_fir`) at the same frequency resolution;
3. ``y = x + P (h * up(c_d))``: zero-stuffing and the same low-pass, as ``P`` polyphase
   filters of ``ceil(len(h) / P)`` taps (only the non-zero samples are multiplied).

Aliases and images are ``STOPBAND_DB`` down on the correction, which is itself at most
``G - 1`` of the record (about 0.25 for the thesis filter). The record's ends are extended
by the same odd reflection as the direct method.

Blocks: decimated sample ``g`` sits at frame ``P g`` of the record (frame 0 its first), so a
block of frames starting anywhere decimates on the record's own grid. :func:`filter_block`
filters a block given the rows around it (the record's neighbours, or its reflection at
the record's ends); :func:`decimate`, :func:`correct` and :func:`interpolate` are its three
stages, which the dask path (:mod:`tactilecal.dynamic._apply`) runs chunk by chunk.
Stages 1 and 3 are numba kernels that stream whole rows of the ``(time, sensels)`` record
(NumPy would make one pass per filter tap): stage 1 sums two decimated rows per pass over
the rows they share, in float64, and writes the decimated record sensel-major through a
small tile, so stage 2's FFTs run along contiguous lines, on a fifth of the rows and in
float32 by default (a tenth of the bytes); stage 3 transposes a tile of those lines back
and applies the ``P`` polyphase filters. In memory each stage runs as tasks on a thread
pool. Measured in ``benchmarks/bench_dynamic.py`` (and the kernels' variants in the
commit messages).
"""

import os
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numba
import numpy as np
from scipy import fft, signal

from tactilecal._errors import TactilecalError
from tactilecal._numba import njit, read_only
from tactilecal.dynamic._filter import PRECISIONS, centred_fir, centred_spectrum

__all__ = ["MultiratePlan", "plan_multirate", "BlockLayout", "apply_multirate",
           "filter_block", "decimate", "fft_length", "fft_columns",
           "correct", "interpolate", "run_tasks"]

#: Attenuation (dB) of the anti-aliasing / interpolation low-pass in its stop band.
STOPBAND_DB = 70.0
#: Decimated rows per stage-1 task, frames per stage-3 task.
DECIMATED_PER_TASK = 256
FRAMES_PER_TASK = 1024
#: Stage 2: the FFT length of the overlap-save blocks (at least 4 filter lengths), and the
#: lines per FFT call: enough for 32 MiB of spectrum (at least 32). Large temporaries are
#: mapped in huge pages: on dask.distributed workers, where MALLOC_TRIM_THRESHOLD_ makes
#: every freed large array go back to the system, 32 lines per call (1 MB temporaries
#: faulted in again and again) measured 2.5x slower than one call per 1936 lines.
BLOCK_FFT = 1 << 14
SENSELS_PER_TASK = 32
SPECTRUM_BYTES = 1 << 25
#: Decimated rows per tile of the transposing kernels (a tile of all sensels stays in L2).
TILE = 32


@dataclass(frozen=True)
class MultiratePlan:
    """The three filters of the multirate method for one correction filter.

    Attributes
    ----------
    factor : int
        Decimation factor ``P``.
    lowpass : numpy.ndarray
        Zero-phase low-pass (odd length, unit DC gain) of stages 1 and 3.
    correction : numpy.ndarray
        Taps of ``D`` at ``fs / P`` (centred, zero DC gain; symmetric unless ``phase``).
    phase : bool
        The correction is complex (a filter of :data:`~tactilecal.dynamic._filter.PHASE_MODELS`).
    """

    factor: int
    lowpass: np.ndarray
    correction: np.ndarray
    phase: bool = False

    @property
    def reach(self):
        """Frames on each side of an output frame that it depends on."""
        c, half = self.lowpass.size // 2, self.correction.size // 2
        return 2 * c + self.factor * (half + 1)

    def polyphase(self, dtype):
        """Return ``weights[phi, q] = P h[phi - P (q - Q_h) + c]`` (zero off the low-pass).

        Frame ``f = P M + phi`` of the interpolated correction is
        ``sum_q weights[phi, q] c_d[M - Q_h + q]`` (stage 3), ``Q_h = c // P``.
        """
        h, factor = self.lowpass, self.factor
        c = h.size // 2
        q_half, q_max = c // factor, (factor - 1 + c) // factor
        weights = np.zeros((factor, q_half + q_max + 1))
        for phi in range(factor):
            for q in range(weights.shape[1]):
                j = phi - factor * (q - q_half) + c
                if 0 <= j < h.size:
                    weights[phi, q] = factor * h[j]
        return weights.astype(dtype)


def decimation_factor(filt):
    """Return ``P = floor(fs / (4 f_c))``, or 1 when the correction is not band-limited."""
    if filt.outside != "taper":
        return 1
    f_c = filt.band_hz[1] + filt.taper_hz
    return max(1, int(filt.fs_hz // (4.0 * f_c)))


def plan_multirate(filt):
    """Design the multirate filters for ``filt``; None when it gains nothing (``P < 2``)."""
    factor = decimation_factor(filt)
    if factor < 2:
        return None
    fs, f_c = filt.fs_hz, filt.band_hz[1] + filt.taper_hz
    fs_low = fs / factor
    n_low, beta = signal.kaiserord(STOPBAND_DB, (fs_low - 2 * f_c) / (fs / 2))
    lowpass = signal.firwin(n_low | 1, fs_low / 2, window=("kaiser", beta), fs=fs)
    lowpass /= lowpass.sum()
    n_taps = max(filt.n_taps // factor, 3) | 1  # same frequency resolution as the full FIR
    grid = np.linspace(0.0, fs_low / 2, 8 * n_taps + 1)
    _, h = signal.freqz(lowpass, worN=grid, fs=fs)
    inside = grid <= f_c
    gain = np.zeros(grid.size, dtype=complex if filt.has_phase else float)
    gain[inside] = (filt.target(grid[inside]) - 1.0) / np.abs(h[inside]) ** 2
    return MultiratePlan(factor, lowpass, centred_fir(n_taps, grid, gain, fs_low),
                         filt.has_phase)


@dataclass(frozen=True)
class BlockLayout:
    """Where the decimated and corrected rows of a block of frames sit.

    The block holds ``n_frames`` frames starting at a frame ``offset`` past a multiple of
    ``P`` (only the frame's place on the decimation grid matters). In block coordinates the
    decimated sample ``g`` sits at frame ``P g - offset``; the block needs the corrected
    samples ``g = -q_half .. (offset + n_frames - 1) // P + q_max`` (``corrected`` rows, the
    first at ``g = -q_half``) and the decimated ones ``half`` further on each side
    (``decimated`` rows, the first at frame ``first_frame``).
    """

    factor: int
    offset: int
    n_frames: int
    lowpass_half: int
    correction_half: int

    @classmethod
    def of(cls, plan, offset, n_frames):
        """Layout of ``n_frames`` frames starting ``offset`` frames past the grid (any int)."""
        return cls(plan.factor, offset % plan.factor, n_frames, plan.lowpass.size // 2,
                   plan.correction.size // 2)

    @property
    def q_half(self):
        """Corrected samples before the block's first grid point that stage 3 reads."""
        return self.lowpass_half // self.factor

    @property
    def corrected(self):
        """Number of corrected rows stage 3 reads."""
        q_max = (self.factor - 1 + self.lowpass_half) // self.factor
        return (self.offset + self.n_frames - 1) // self.factor + q_max + self.q_half + 1

    @property
    def decimated(self):
        """Number of decimated rows stage 2 reads."""
        return self.corrected + 2 * self.correction_half

    @property
    def first_frame(self):
        """Frame (block coordinates) of the first decimated row."""
        return -self.factor * (self.q_half + self.correction_half) - self.offset

    @property
    def margins(self):
        """Rows needed before and after the block: ``(before, after)``."""
        c = self.lowpass_half
        last = self.first_frame + self.factor * (self.decimated - 1) + c
        return max(c - self.first_frame, 0), max(last - (self.n_frames - 1), 0)


@numba.njit
def _row(before, rows, after, t, reflect, spare):  # pragma: no cover
    """Row ``t`` of ``rows`` extended by ``before`` (ending at row -1) and ``after``.

    With ``reflect``, ``before`` and ``after`` are not read: a row beyond the ends is the
    odd reflection of ``rows`` about its end row (``2 x[0] - x[-t]``, ``2 x[n - 1] -
    x[2 (n - 1) - t]``), computed into ``spare`` (a row of ``rows``' type) and returned.
    Called, not inlined into :func:`_sum_tile`: numba's ``inline="always"`` types and
    lowers it again at each of the six calls, which nearly doubled the kernel's compile
    time; one call per row read costs nothing next to the pass over that row.
    """
    n = rows.shape[0]
    if 0 <= t < n:
        return rows[t]
    if not reflect:
        return before[before.shape[0] + t] if t < 0 else after[t - n]
    end, source = (rows[0], rows[-t]) if t < 0 else (rows[n - 1], rows[2 * (n - 1) - t])
    for s in range(spare.size):
        spare[s] = 2 * end[s] - source[s]
    return spare


def _decimate_rows(before, rows, after, reflect, lowpass, factor, first, k0, k1, s0, s1, ref,
                   lines, sums):
    """``lines[s, k] = sum_j lowpass[j] x[first + factor k + j - c, s] - ref[s]``.

    For ``k0 <= k < k1`` and ``s0 <= s < s1``; ``x`` is ``rows`` extended by ``before``
    and ``after``, or with ``reflect`` by its odd reflection, computed row by row where
    it is read (:func:`_row`): no margins are allocated. A tile of ``TILE`` decimated
    rows is summed in float64 (:func:`_sum_tile`), then written sensel-major in the type
    of ``lines`` (:func:`_store_tile`); ``sums`` (float64) accumulates the stored values,
    so a NaN anywhere in a sensel shows in its sum. The two are kernels of their own,
    called tile by tile from here, so that numba compiles the long one once per type of
    ``rows`` and the short one once per type of ``lines``, not both for every pair of
    types (a kernel calling them would compile them again, inlined, for every pair).
    """
    width = s1 - s0
    n_taps = lowpass.size
    span = n_taps + factor
    taps0, taps1 = np.zeros(span), np.zeros(span)  # of rows k and k + 1 over the span
    taps0[:n_taps] = lowpass
    taps1[factor:] = lowpass
    tile = np.empty((TILE, width))
    spare = np.empty((4, rows.shape[1]), dtype=rows.dtype)  # reflected rows r0 .. r3
    for a in range(k0, k1, TILE):
        b = min(a + TILE, k1)
        _sum_tile(before, rows, after, reflect, lowpass, taps0, taps1, factor, first, a, b,
                  s0, s1, tile, spare)
        _store_tile(tile, a, b, s0, ref, lines, sums)


@njit(nogil=True, fastmath={"contract"})
def _sum_tile(before, rows, after, reflect, lowpass, taps0, taps1, factor, first, a, b, s0,
              s1, tile, spare):  # pragma: no cover
    """``tile[k - a, s - s0] = sum_j lowpass[j] x[first + factor k + j - c, s]``, float64.

    For ``a <= k < b`` (at most ``TILE`` rows). Two consecutive decimated rows are summed
    in one pass over the ``len(lowpass) + P`` rows they read (``taps0`` and ``taps1``:
    the low-pass placed for each over that span; each row loaded once for both: 17 %
    faster than one at a time), over whole rows.
    """
    width = s1 - s0
    n_taps = lowpass.size
    c = n_taps // 2
    span = n_taps + factor
    for k in range(a, b - 1, 2):
        base = first + factor * k - c
        acc0, acc1 = tile[k - a], tile[k + 1 - a]
        acc0[:] = 0.0
        acc1[:] = 0.0
        j = 0
        while j + 4 <= span:
            r0 = _row(before, rows, after, base + j, reflect, spare[0])[s0:s1]
            r1 = _row(before, rows, after, base + j + 1, reflect, spare[1])[s0:s1]
            r2 = _row(before, rows, after, base + j + 2, reflect, spare[2])[s0:s1]
            r3 = _row(before, rows, after, base + j + 3, reflect, spare[3])[s0:s1]
            p0, p1, p2, p3 = taps0[j], taps0[j + 1], taps0[j + 2], taps0[j + 3]
            q0, q1, q2, q3 = taps1[j], taps1[j + 1], taps1[j + 2], taps1[j + 3]
            for s in range(width):
                v0, v1, v2, v3 = r0[s], r1[s], r2[s], r3[s]
                acc0[s] += (p0 * v0 + p1 * v1) + (p2 * v2 + p3 * v3)
                acc1[s] += (q0 * v0 + q1 * v1) + (q2 * v2 + q3 * v3)
            j += 4
        while j < span:
            r0 = _row(before, rows, after, base + j, reflect, spare[0])[s0:s1]
            p0, q0 = taps0[j], taps1[j]
            for s in range(width):
                acc0[s] += p0 * r0[s]
                acc1[s] += q0 * r0[s]
            j += 1
    if (b - a) % 2:  # the tile's last row alone, reading only its own rows
        base = first + factor * (b - 1) - c
        acc0 = tile[b - 1 - a]
        acc0[:] = 0.0
        for j in range(n_taps):
            r0 = _row(before, rows, after, base + j, reflect, spare[0])[s0:s1]
            p0 = lowpass[j]
            for s in range(width):
                acc0[s] += p0 * r0[s]


@njit(nogil=True)
def _store_tile(tile, a, b, s0, ref, lines, sums):  # pragma: no cover
    """``lines[s0 + s, k] = tile[k - a, s] - ref[s0 + s]`` for ``a <= k < b``; ``sums`` too."""
    for s in range(tile.shape[1]):
        line, offset, total = lines[s0 + s], ref[s0 + s], 0.0
        for k in range(a, b):
            value = tile[k - a, s] - offset
            line[k] = value
            total += value
        sums[s0 + s] += total


@njit(nogil=True, fastmath={"contract"})
def _interpolate_rows(rows, corrected, weights, offset, t0, t1, s0, s1,
                      out):  # pragma: no cover
    """``out[t, s] = rows[t, s] + sum_q weights[phi, q] corrected[s, M + q]``.

    For ``t0 <= t < t1``, ``s0 <= s < s1``, with ``t + offset = P M + phi``. ``corrected``
    is sensel-major; a tile of its columns is transposed first, so the sum streams whole
    rows. It runs in the type of ``corrected`` (float32 for single precision: twice the
    SIMD lanes; the correction is a fraction of the dynamic part, so its rounding is too).
    The taps are summed four rows per pass into ``acc`` (the first pass assigns it) and
    the last one to four are added in the pass that writes the output row, so a row of
    ``out`` costs ``ceil((n_q - 1) / 4)`` passes over ``acc`` plus the output pass (the
    thesis filter, 9 taps: 3 passes, where 3-tap passes plus zeroing and a final add made
    5; measured 1.05x faster best, 1.10x median, see ``git log`` of this kernel).
    """
    factor, n_q = weights.shape
    width = s1 - s0
    tile = np.empty((TILE + n_q + 1, width), dtype=corrected.dtype)
    acc = np.zeros(width, dtype=corrected.dtype)
    for a in range(t0, t1, TILE * factor):
        b = min(a + TILE * factor, t1)
        i0 = (a + offset) // factor
        i1 = (b - 1 + offset) // factor + n_q
        for s in range(width):
            line = corrected[s0 + s]
            for i in range(i0, i1):
                tile[i - i0, s] = line[i]
        for t in range(a, b):
            frame = t + offset
            first, w = frame // factor - i0, weights[frame % factor]
            q = 0
            while q + 4 < n_q:  # at least one tap is left for the output pass
                w0, w1, w2, w3 = w[q], w[q + 1], w[q + 2], w[q + 3]
                c0, c1 = tile[first + q], tile[first + q + 1]
                c2, c3 = tile[first + q + 2], tile[first + q + 3]
                if q == 0:
                    for s in range(width):
                        acc[s] = (w0 * c0[s] + w1 * c1[s]) + (w2 * c2[s] + w3 * c3[s])
                else:
                    for s in range(width):
                        acc[s] += (w0 * c0[s] + w1 * c1[s]) + (w2 * c2[s] + w3 * c3[s])
                q += 4
            if q == 0:  # four taps or fewer: no pass over acc at all
                acc[:] = 0
            _add_last_taps(rows[t][s0:s1], acc, tile, first + q, w[q:], out[t][s0:s1])


@numba.njit(inline="always")
def _add_last_taps(x, acc, tile, first, w, y):  # pragma: no cover
    """``y = x + acc + sum_q w[q] tile[first + q]`` for the last one to four taps ``w``."""
    width = y.size
    c0, w0 = tile[first], w[0]
    if w.size == 1:
        for s in range(width):
            y[s] = x[s] + (acc[s] + w0 * c0[s])
        return
    c1, w1 = tile[first + 1], w[1]
    if w.size == 2:
        for s in range(width):
            y[s] = x[s] + (acc[s] + (w0 * c0[s] + w1 * c1[s]))
        return
    c2, w2 = tile[first + 2], w[2]
    if w.size == 3:
        for s in range(width):
            y[s] = x[s] + (acc[s] + (w0 * c0[s] + w1 * c1[s] + w2 * c2[s]))
        return
    c3, w3 = tile[first + 3], w[3]
    for s in range(width):
        y[s] = x[s] + (acc[s] + ((w0 * c0[s] + w1 * c1[s]) + (w2 * c2[s] + w3 * c3[s])))


def _ranges(n, size, start=0):
    return [(a, min(a + size, n)) for a in range(start, n, size)]


def run_tasks(tasks, workers, progress=None):
    """Run callables on ``workers`` threads (the kernels and FFTs release the GIL).

    ``progress`` wraps the iterator of finished tasks, called with ``total=``.
    """
    if workers <= 1:
        done = (task() for task in tasks)
    else:
        pool = ThreadPoolExecutor(max_workers=workers)
        done = pool.map(lambda task: task(), tasks)
    try:
        for _ in (progress(done, total=len(tasks)) if progress else done):
            pass
    finally:
        if workers > 1:
            pool.shutdown()


def _threads(workers):
    return (os.cpu_count() or 1) if workers == -1 else max(int(workers), 1)


def decimate(before, rows, after, plan, first, n_lines, *, precision="single", workers=1,
             reference=None, spare=0):
    """Stage 1: the decimated record, sensel-major, and each sensel's sum over it.

    Decimated row ``k`` is centred on frame ``first + P k`` of ``rows`` (block
    coordinates; ``before`` and ``after`` hold the rows around the block, or are both None
    for the odd reflection of ``rows`` about its end rows, the record's own) and is relative
    to ``reference`` (default ``rows[0]``; removed in float64, so single precision rounds
    relative to the dynamic part; the correction ``D`` has no DC gain, so the reference
    does not change the result). Returns ``(lines, sums)``: ``(sensels, n_lines)`` of the
    precision's type, and float64 sums (NaN for a sensel with a NaN anywhere under the
    low-pass). ``lines`` has ``spare`` more columns of zeros, so that stage 2's last FFT
    block reads them in place (:func:`correct`).
    """
    m = rows.shape[1]
    reflect = before is None and after is None
    if reflect:
        before = after = rows[:0]
    before, rows, after = (read_only(x) for x in (before, rows, after))
    ref = np.array(rows[0] if reference is None else reference, dtype=float)
    lines = np.empty((m, n_lines + spare), dtype=PRECISIONS[precision])
    lines[:, n_lines:] = 0
    ranges = _ranges(n_lines, DECIMATED_PER_TASK if _threads(workers) > 1 else max(n_lines, 1))
    sums = np.zeros((max(len(ranges), 1), m))  # one row per task: no shared writes
    tasks = [lambda i=i, a=a, b=b: _decimate_rows(
        before, rows, after, reflect, plan.lowpass, plan.factor, first, a, b, 0, m, ref, lines,
        sums[i]) for i, (a, b) in enumerate(ranges)]
    run_tasks(tasks, _threads(workers))
    return lines, sums.sum(axis=0)


def fft_length(plan, n_out):
    """FFT length of stage 2 for ``n_out`` corrected samples (even, 5-smooth).

    One block when the window of ``n_out + 2 half`` samples fits (a dask chunk's window is
    often shorter than 4 correction lengths, and padding it to that length measured 1.1x
    slower), else blocks of ``BLOCK_FFT`` samples, at least 4 correction lengths.
    """
    window = n_out + 2 * (plan.correction.size // 2)
    n_fft = fft.next_fast_len(min(window, max(BLOCK_FFT, 4 * plan.correction.size)),
                              real=True)
    return n_fft + n_fft % 2  # even, so that the half-spectrum's length gives it back


def fft_columns(plan, n_out):
    """Columns of decimated samples stage 2's FFT blocks span for ``n_out`` outputs.

    At least the ``n_out + 2 half`` it needs; the rest, up to the end of the last block,
    may hold any finite values (:func:`correct`).
    """
    n_fft = fft_length(plan, n_out)
    step = n_fft - 2 * (plan.correction.size // 2)
    return (max(-(-n_out // step), 1) - 1) * step + n_fft


def correct(lines, plan, n_out, *, workers=1, out=None):
    """Stage 2: ``out[:, q] = sum_j D[j] lines[:, q + j]`` for ``q < n_out``.

    Overlap-save FFTs along the (contiguous) lines of ``lines`` (sensel-major, at least
    ``n_out + 2 half`` columns). Columns beyond those (any finite values, e.g. the zeros
    of :func:`decimate`'s ``spare``) are read instead of padding a copy of the last
    block to the FFT length (:func:`fft_length`). ``out`` may be ``lines`` itself: each
    line's blocks are done left to right and a block's result lands left of the columns
    the next one reads. Returns ``out[:, :n_out]``.
    """
    half = plan.correction.size // 2
    m, n_in = lines.shape
    if n_in < n_out + 2 * half:
        raise TactilecalError(f"stage 2 needs {n_out + 2 * half} decimated rows; got {n_in}")
    n_fft = fft_length(plan, n_out)
    step = n_fft - 2 * half
    gain = centred_spectrum(plan.correction, n_fft, phase=plan.phase)
    gain = gain.astype(np.result_type(lines.dtype, np.complex64) if plan.phase else lines.dtype)
    out = np.empty((m, n_out), dtype=lines.dtype) if out is None else out

    def run(s0, s1):
        for t0 in range(0, n_out, step):
            width = min(step, n_out - t0)
            block = lines[s0:s1, t0:min(t0 + n_fft, n_in)]
            spectrum = fft.rfft(block, n=n_fft, axis=-1)
            spectrum *= gain
            y = fft.irfft(spectrum, n=n_fft, axis=-1, overwrite_x=True)
            out[s0:s1, t0:t0 + width] = y[:, half:half + width]

    threads = _threads(workers)
    per_call = SPECTRUM_BYTES // (8 * n_fft)
    if threads > 1:  # at least 4 tasks per thread, so that they share the work evenly
        per_call = min(per_call, -(-m // (4 * threads)))
    per_call = int(np.clip(per_call, SENSELS_PER_TASK, max(m, 1)))
    run_tasks([lambda a=a, b=b: run(a, b) for a, b in _ranges(m, per_call)], threads)
    return out[:, :n_out]


def interpolate(rows, corrected, plan, offset, *, workers=1, progress=None, dtype=float):
    """Stage 3: ``rows + P (h * up(corrected))`` as ``dtype`` (see :class:`BlockLayout`).

    ``corrected`` is sensel-major, its column 0 the corrected sample ``q_half`` grid points
    before the block's first one, and may have more columns than are read (pass the
    buffer :func:`correct` wrote into, which is contiguous, rather than its first
    columns); ``offset`` is the block's first frame modulo ``P``.

    numba compiles the kernel once for every combination of argument types (seconds
    each), so it sees five: float32 rows with a float32 correction into either type, and
    float64 rows with a float64 correction into float64 or with a float32 one into either.
    A float64 correction for a float32 result is rounded to float32 first (a fifth of the
    rows or fewer, and the result is float32 anyway); float32 rows with a float64
    correction are widened into the result, which the kernel corrects in place (the same
    sums).
    """
    n, m = rows.shape
    out = np.empty((n, m), dtype=dtype)
    if out.dtype == np.float32 and corrected.dtype != np.float32:
        corrected = corrected[:, :BlockLayout.of(plan, offset, n).corrected].astype(np.float32)
    corrected = np.ascontiguousarray(corrected)
    if corrected.dtype == np.float64 and rows.dtype != np.float64:
        out[...] = rows
        rows = out
    weights = plan.polyphase(corrected.dtype)
    rows = read_only(rows)
    threads = _threads(workers)
    size = FRAMES_PER_TASK if threads > 1 or progress else n  # one call: its buffers once
    run_tasks([lambda a=a, b=b: _interpolate_rows(rows, corrected, weights, offset % plan.factor,
                                                  a, b, 0, m, out)
               for a, b in _ranges(n, max(size, 1))], threads, progress)
    return out


def filter_block(before, rows, after, offset, plan, *, precision="single", workers=1,
                 progress=None, check=None, timings=None, dtype=float):
    """Return ``x + c`` for the frames ``rows`` (time first, 2-D), see the module notes.

    Parameters
    ----------
    before, after : numpy.ndarray or None
        The rows just before and after ``rows`` in the (extended) record, at least
        ``BlockLayout.margins`` of them, same type as ``rows``; both None when ``rows`` is
        the whole record (the kernel reflects it about its end rows where it reads them).
    rows : numpy.ndarray
        ``(frames, sensels)``, float32 or float64, rows contiguous.
    offset : int
        Frame index of ``rows[0]`` in the record (only its remainder modulo ``P`` counts).
    plan : MultiratePlan
    precision : {"single", "double"}
        Type of the decimated record, its FFTs and the correction.
    workers : int
        Threads (-1: one per core).
    progress : callable, optional
        Wraps the iterator of finished stage-3 tasks, called with ``total=``.
    check : callable, optional
        Called with each sensel's sum over the decimated record (float64; NaN when the
        sensel has a NaN anywhere) before the FFTs.
    timings : dict, optional
        Receives the seconds of each stage.
    dtype : numpy.dtype
        Type of the result (float64 or float32).

    Returns
    -------
    numpy.ndarray
        ``(frames, sensels)`` of type ``dtype``.
    """
    layout = BlockLayout.of(plan, offset, rows.shape[0])
    need_before, need_after = layout.margins
    if (before is None) != (after is None):
        raise TactilecalError("filter_block needs both before and after, or neither")
    if before is not None and (before.shape[0] < need_before or after.shape[0] < need_after):
        raise TactilecalError(f"filter_block needs {need_before} rows before and {need_after} "
                              f"after; got {before.shape[0]} and {after.shape[0]}")
    clock = [time.perf_counter()]

    def lap(stage):
        if timings is not None:
            clock.append(time.perf_counter())
            timings[stage] = clock[-1] - clock[-2]

    spare = fft_columns(plan, layout.corrected) - layout.decimated
    lines, sums = decimate(before, rows, after, plan, layout.first_frame, layout.decimated,
                           precision=precision, workers=workers, spare=spare)
    lap("decimate")
    if check is not None:
        check(sums)
    correct(lines, plan, layout.corrected, workers=workers, out=lines)
    lap("correct")
    out = interpolate(rows, lines, plan, layout.offset, workers=workers, progress=progress,
                      dtype=dtype)
    lap("interpolate into the new output")
    return out


def apply_multirate(x2d, plan, workers, progress, precision, check=None, timings=None,
                    dtype=float):
    """Return ``x + c`` for ``x2d`` (time, sensels); see the module notes.

    ``x2d`` float32 or float64 (the result is ``dtype``). ``precision`` ("single" or
    "double") is the type of the decimated record and its FFTs. ``progress`` wraps the
    tasks of stage 3 (the last and longest). ``check(sums)``, if given, sees each sensel's
    sum over the decimated record before stage 2: a NaN anywhere in a sensel's record
    reaches it (every frame is under the low-pass), so NaN gaps are found in 1/P of the
    data. ``timings``, if a dict, receives the seconds of each stage
    (``benchmarks/bench_dynamic.py --stages``).
    """
    x2d = np.ascontiguousarray(x2d)  # the kernels stream whole rows
    return filter_block(None, x2d, None, 0, plan, precision=precision, workers=workers,
                        progress=progress, check=check, timings=timings, dtype=dtype)
