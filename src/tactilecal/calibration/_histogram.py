"""Per-frame 256-bin histograms of raw readings: a NumPy path and a one-pass compiled path.

A movie of 100,000 frames of 44 x 44 sensels is 1.55 GB in float64; its histograms are what
every calibration fit uses (Zvyagin 2022, eq. 2: ``sum_k f(X_k) = histogram @ f(0..255)``),
so counting them should cost about one read of the frames. NumPy needs several passes over
each chunk (round, check the range, add frame offsets, ``bincount``): 6-9 times a
``numpy.sum`` over the same float64 array. The numba kernels of
:mod:`tactilecal.calibration._histogram_kernels` make one, 2-3 times a ``numpy.sum``
(``benchmarks/bench_movie.py``), but numba's start-up in a new process
outweighs that below about :data:`COMPILED_MIN_VALUES` readings, so smaller inputs
(single frames, dead-weight sessions, short movies) are counted with NumPy. Both paths give
the same counts and the same errors.
"""

import numpy as np

from tactilecal._errors import TactilecalError

N_LEVELS = 256
SATURATION_RAW = 255
#: Readings from which the compiled kernel is used (2**26: 35,000 frames of 44 x 44, where
#: the NumPy path takes about as long as numba's start-up).
COMPILED_MIN_VALUES = 2 ** 26
#: Frames per kernel call when the counts are copied into another type (an int64 block of
#: 512 KiB, which stays in cache while it is copied).
KERNEL_FRAMES = 256


def count_into(frames, skip, out, *, compiled):
    """Count each frame's raw readings 0..255 into ``out`` (m, 256).

    Parameters
    ----------
    frames : numpy.ndarray, shape (m, n_sensels)
        Raw readings, any real dtype; floats are rounded half to even (``numpy.rint``),
        NaN are not counted.
    skip : numpy.ndarray of bool, shape (n_sensels,)
        Sensels not to count (non-working); their readings are not checked either.
    out : numpy.ndarray, shape (m, 256)
        Filled in place (any numeric dtype; uint16 holds the counts of frames of fewer
        than 2**16 sensels). The NumPy path writes uint16, int64 and float64 directly, the
        compiled one int64, and other types through blocks of int64 counts.
    compiled : bool
        Use the numba kernel (one pass) rather than NumPy (a few passes per 64 frames).

    Returns
    -------
    numpy.ndarray
        ``out``.

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
    if compiled:
        bad = _count_compiled(frames, np.flatnonzero(skip), out)
    else:
        direct = out.dtype in (np.uint16, np.int64, np.float64) and out.flags.c_contiguous
        target = out if direct else np.empty(out.shape, np.int64)
        bad = _count_numpy(frames, skip, target)
        if not direct:
            out[...] = target
    if bad >= 0:
        value = frames.flat[bad]
        value = np.rint(value) if frames.dtype.kind == "f" else value
        raise out_of_range(value)
    return out


def out_of_range(value, where=""):
    """Return the error for a raw reading outside 0..255 (every door of raw frames)."""
    return TactilecalError(f"{where}raw frames contain the value {value:g}; expected raw "
                           "readings 0..255")


def check_range(frames, where=""):
    """Raise :func:`out_of_range` for the first reading outside 0..255 (NaN aside).

    The counting's rule: a reading is rounded to the nearest level (fractions are readings:
    equilibrated frames), so the message quotes it rounded. Two reductions when every
    reading is in range (``fmin``/``fmax`` skip NaN).
    """
    frames = np.asarray(frames)
    if frames.size == 0 or frames.dtype.kind == "u" and frames.itemsize == 1:
        return
    lowest, highest = np.fmin.reduce(frames, axis=None), np.fmax.reduce(frames, axis=None)
    if np.rint(lowest) < 0 or np.rint(highest) > N_LEVELS - 1:
        levels = np.rint(frames)
        raise out_of_range(levels[(levels < 0) | (levels > N_LEVELS - 1)][0], where)


def _count_compiled(frames, skipped, out):
    """Count with the numba kernels; return -1 or the flat index of the first bad reading.

    The kernels see uint8, float32 or float64 frames and int64 counts only: numba compiles
    a kernel for every pair of types, each in about half a second. Other integer frames
    are widened to float64 (exact below 2**53; larger values are out of range either way,
    and the error quotes the reading itself) and counts of another type or layout are
    copied from an int64 block, :data:`KERNEL_FRAMES` frames at a time.
    """
    from tactilecal.calibration._histogram_kernels import kernel_for

    widen = frames.dtype not in (np.uint8, np.float32, np.float64)
    if not widen and out.dtype == np.int64 and out.flags.c_contiguous:
        return kernel_for(frames.dtype)(frames, skipped, out)
    n, m = frames.shape
    target = np.empty((min(n, KERNEL_FRAMES), N_LEVELS), np.int64)
    for start in range(0, n, KERNEL_FRAMES):
        block = frames[start:start + KERNEL_FRAMES]
        if widen:
            block = block.astype(np.float64)
        counts = target[:len(block)]
        bad = kernel_for(block.dtype)(block, skipped, counts)
        if bad >= 0:
            return start * m + bad
        out[start:start + len(block)] = counts
    return -1


def _count_numpy(frames, skip, out, chunk_frames=64):
    """NumPy version of the kernels: per chunk, round, check, add 257 * frame, ``bincount``.

    Bin 256 of each frame collects NaN and skipped sensels and is dropped. Returns -1 or
    the flat index of the first counted reading outside 0..255, like the kernels.
    """
    n, m = frames.shape
    offsets = (np.arange(chunk_frames, dtype=np.intp) * (N_LEVELS + 1))[:, None]
    index = np.empty((chunk_frames, m), dtype=np.intp)
    work = np.empty((chunk_frames, m))
    for start in range(0, n, chunk_frames):
        block = frames[start:start + chunk_frames]
        k = len(block)
        if skip.any():
            block = np.where(skip, np.nan, block)
        if block.dtype.kind in "ui":
            values = block
            lo, hi = block.min(initial=0), block.max(initial=0)
        else:
            values = np.rint(block, out=work[:k])
            lo = np.fmin.reduce(values, axis=None, initial=0.0)
            hi = np.fmax.reduce(values, axis=None, initial=0.0)
        if lo < 0 or hi > SATURATION_RAW:
            return start * m + int(np.flatnonzero((values < 0) | (values > SATURATION_RAW))[0])
        if values.dtype.kind == "f":
            nan = np.isnan(values)
            if nan.any():
                values[nan] = N_LEVELS
        np.add(values, offsets[:k], out=index[:k], casting="unsafe")
        counts = np.bincount(index[:k].ravel(), minlength=k * (N_LEVELS + 1))
        out[start:start + k] = counts.reshape(k, N_LEVELS + 1)[:, :N_LEVELS]
    return -1
