"""NumPy reader for plain Tekscan exports: whole numbers and ``B``, no numba.

numba's import and the load of its cached kernels cost more, in a new process, than pandas'
whole parse of a 10,000-frame export. This reader needs NumPy only. It reads the
export the way the numba reader does, in blocks of whole frames, but with array operations
over each block's bytes: the line ends (LF), each line's first byte (blank line, ``F`` frame
line, row of values, ``@@``), the commas of the rows of values, and per value its last one to
:data:`_MAX_DIGITS` bytes (digits, ``B`` alone), combined in integers (:func:`_whole_numbers`),
exact, so that each value equals ``float(token)``.

It reads only the *plain* form every real export seen has (``docs/data-model.md``): rows of
whole numbers and ``B`` separated by single commas, LF or CR LF line ends, frame lines the
reader's regular expressions parse, the ``@@`` terminator. At the first departure from it
:func:`read_plain` returns None, having raised nothing: the numba reader
(``_tekscan_index``, ``_tekscan_blocks``) then reads the file from the start; it defines the
format, its checks and every error message, so a file reads the same, or fails with the same
message, whichever reader took it.
"""

import math
import os
import re
from collections import deque

import numpy as np

from tactilecal._validate import MAX_VALUES
from tactilecal.io._tekscan_layout import Index

__all__ = ["BLOCK_BYTES", "read_plain"]

BLOCK_BYTES = 2**21
"""Most bytes of the file parsed at a time (whole frames; a larger frame is one block)."""

VALUES_PER_BLOCK = 2**15
"""About as many values are parsed at a time (blocks of whole frames, at most BLOCK_BYTES).

Each array of one number per value is then 256 KiB at most, which the C allocator serves
again from block to block; from about 512 KiB on, each block's arrays came as fresh pages
(one page fault per 4 KiB: more system time than the parse's own in a new process).
"""

_MAX_DIGITS = 15  # a whole number of up to 15 digits is below 2**53: exact in float64
# per token length: the bytes of a little-endian word that are the token's (the last ones)
_MASKS = {size: np.array([(2**(8 * size) - 1) ^ (2**(8 * (size - n)) - 1) if n <= size else 0
                          for n in range(_MAX_DIGITS + 1)], dtype=f"<u{size}")
          for size in (4, 8)}
_FRAME = re.compile(rb"Frame[ \t]+(\d+)[ \t]*(?:$|,[ \t]*([^,]*?)[ \t]*(?:,|$))")
_RAW_SUM = re.compile(rb"Raw Sum[ \t]*=[ \t,]*([-+]?\d+(?:\.\d*)?)[ \t]*(?:,|$)")
_TIME = re.compile(rb"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
# the same, over frame lines joined by LF: one match per line, at its start
_FRAMES = re.compile(rb"^Frame[ \t]+(\d+)[ \t]*(?:$|,[ \t]*([^,\n]*?)[ \t]*(?:,|$))", re.M)
_RAW_SUMS = re.compile(rb"^[^\n]*?Raw Sum[ \t]*=[ \t,]*([-+]?\d+(?:\.\d*)?)[ \t]*(?:,|$)", re.M)
_TIMES = re.compile(rb"(?:[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\n)*")
_SPACE = b" \t\x0b\x0c\r\n"
_LF, _CR, _COMMA, _AT, _B, _F = 10, 13, 44, 64, 66, 70


class _NotPlain(Exception):
    """The file departs from the plain form: the numba reader takes it."""


def read_plain(f, name, head):
    """Read the export ``f`` (binary, header ``head`` already read) if it is plain.

    Parameters
    ----------
    f : file
        The export, opened in binary mode.
    name : str
        File name for the index (error messages of later checks).
    head : tactilecal.io._tekscan_layout.Header

    Returns
    -------
    (values, index) or None
        ``values`` float64 (frames, ROWS, COLS), NaN for ``B``; ``index`` as the numba
        reader's :func:`~tactilecal.io._tekscan_index.index_export` would return it. None when
        the file is not plain (or not valid): nothing is raised, the caller reads it again
        with the numba reader.
    """
    try:
        return _read(f, name, head)
    except _NotPlain:
        return None


def _read(f, name, head):
    per_frame = head.rows * head.cols
    size = os.fstat(f.fileno()).st_size - head.body
    n_frames = _header_frames(head)
    if n_frames is None or 2 * n_frames * per_frame > size:
        n_frames = _count_frames(f, head.body)
    n_values = max(n_frames, 1) * per_frame
    if n_values > MAX_VALUES or 2 * n_values > size:
        raise _NotPlain  # more values than the file has room for (a value and a comma each)
    values = np.empty((max(n_frames, 1), head.rows, head.cols))
    flat = values.reshape(-1)
    raw = head.attrs.get("units") in (None, "raw")
    f.seek(head.body)
    block_bytes = min(BLOCK_BYTES, max(2**12, size * VALUES_PER_BLOCK // n_values))
    parts = _in_order(lambda job: _Block(head, flat, raw, n_frames == 0, *job),
                      _jobs(f, head, block_bytes), threads=size > block_bytes)
    if not parts or parts[-1].end is None or any(p.end is not None for p in parts[:-1]):
        raise _NotPlain  # no @@, or F lines after it
    return values, _index(f, name, head, parts, n_frames, raw)


def _header_frames(head):
    """``END_FRAME - START_FRAME + 1`` when both are given and say 2 frames or more, else None.

    Checked at the end (the frame lines found must be as many): a header that does not say
    how many frames follow (frames missing, or edited) sends the file to the numba reader.
    """
    first, last = (head.header.get(key, ("", 0))[0].strip() for key in ("START_FRAME",
                                                                       "END_FRAME"))
    if not (first.isascii() and first.isdigit() and last.isascii() and last.isdigit()):
        return None
    n = int(last) - int(first) + 1
    return n if n >= 2 else None


def _count_frames(f, body):
    """Count the lines starting with ``F`` after ``body`` (its first byte is an LF)."""
    f.seek(body)
    count, last = 0, b""
    while chunk := f.read(BLOCK_BYTES):
        count += (last + chunk[:1]).count(b"\nF") + chunk.count(b"\nF")
        last = chunk[-1:]
    return count


def _jobs(f, head, block_bytes):
    """Yield ``(bytes, file offset, first value)`` of each block.

    A block is whole lines, cut before a frame (``F``) line, so that it holds whole frames and
    its first value's index in the result follows from the frame lines before it. (Its lines
    are counted by the thread that parses it: :func:`_index` numbers them.)
    """
    base, k = head.body, 0
    pending, held = [], 0  # bytes read since the last cut (joined once, at the next cut)
    per_frame = head.rows * head.cols
    largest = 17 * per_frame + 2 * head.rows + 2**20  # a plain frame: 15 digits and a comma
    while True:
        chunk = f.read(block_bytes)
        if held > largest:
            raise _NotPlain  # more bytes than a plain frame holds: the numba reader says why
        if not chunk:
            data = b"".join(pending)
            if data:
                yield data if data.endswith(b"\n") else data + b"\n", base, k
            return
        tail = pending[-1][-1:] if pending else b""
        found = (tail + chunk).rfind(b"\nF")  # the bytes held before were searched already
        cut = found + held - len(tail) if found >= 0 else 0
        if cut <= 0:  # no frame line to cut before yet: read on
            pending.append(chunk)
            held += len(chunk)
            continue
        data = b"".join((*pending, chunk))
        block = data[:cut + 1]
        yield block, base, k
        k += (block.count(b"\nF") + block.startswith(b"F")) * per_frame
        pending, base = [data[cut + 1:]], base + cut + 1
        held = len(pending[0])


def _in_order(function, jobs, *, threads=True):
    """``[function(job) for job in jobs]`` on one thread per core, a few jobs ahead at most.

    NumPy releases the GIL inside its array operations, so the blocks parse in parallel;
    at most two jobs per thread are read ahead (memory: a few blocks, whatever the file).
    ``threads=False`` (a file no larger than a block, read as two jobs: its frames, then
    the last frame, cut off to start a next block) runs the jobs here: a pool would only
    add its threads' start-up, about as long as the read of a small export.
    """
    from concurrent.futures import ThreadPoolExecutor

    if not threads:
        return [function(job) for job in jobs]
    workers = os.cpu_count() or 1
    done, pending = [], deque()
    with ThreadPoolExecutor(max_workers=workers) as pool:
        try:
            for job in jobs:
                pending.append(pool.submit(function, job))
                if len(pending) > 2 * workers:
                    done.append(pending.popleft().result())
            done.extend(future.result() for future in pending)
        finally:
            for future in pending:
                future.cancel()
    return done


class _Block:
    """Parse one block into ``flat``: its frame lines, each frame's sum and the ``@@`` line."""

    def __init__(self, head, flat, raw, single, block, base, k):
        self.frames, self.sums, self.end = None, None, None
        self.n_values = 0
        if block.find(b"\x00") >= 0:
            raise _NotPlain  # numba's "a NUL byte"
        b = np.frombuffer(block, dtype=np.uint8)
        lf = np.flatnonzero(b == _LF)
        starts = np.empty_like(lf)
        starts[0], starts[1:] = 0, lf[:-1] + 1
        first = b[starts]
        ends = lf - ((lf > starts) & (b[lf - 1] == _CR))  # before CR LF
        is_frame, is_data = first == _F, (first == _B) | (first - 48 <= 9)
        at = np.flatnonzero(first == _AT)
        stop = len(lf) if at.size == 0 else int(at[0])
        if not (is_frame | is_data | (ends == starts))[:stop].all():
            raise _NotPlain  # another line (numba's "expected a 'Frame N' line ..."), lone CR
        if at.size:
            if block[starts[stop]:ends[stop]].strip(_SPACE) != b"@@":
                raise _NotPlain
            _check_space(block[lf[stop] + 1:])
            self.end = base + int(starts[stop])
            is_frame[stop:], is_data[stop:] = False, False
        frame_lines, data_lines = np.flatnonzero(is_frame), np.flatnonzero(is_data)
        self.frames = _frame_lines(block, starts[frame_lines], ends[frame_lines])
        self.frames = (base + starts[frame_lines], frame_lines, *self.frames)
        self.n_lines = lf.size  # its frame lines are numbered from its first line
        _check_rows(frame_lines, data_lines, head.rows, single)
        self.n_values = data_lines.size * head.cols
        if data_lines.size:
            whole = _values(b, starts[data_lines], ends[data_lines], starts[frame_lines],
                            ends[frame_lines], head.cols, flat, k, raw)
            if raw:
                self.sums = whole.reshape(-1, head.rows * head.cols).sum(axis=1,
                                                                          dtype=np.int64)


def _frame_lines(block, starts, ends):
    """``(numbers, times, raw sums)`` of the frame lines ``block[starts:ends]``.

    The lines are joined and parsed by one regular expression each (the per-line patterns
    anchored at each line's start); lines with and without a ``Raw Sum`` in one block are
    parsed one by one.
    """
    text = b"\n".join([block[start:end] for start, end in zip(starts.tolist(), ends.tolist(),
                                                             strict=True)])
    if not text.isascii() or b"\r" in text:  # else numba: regexes on decoded text
        raise _NotPlain
    heads = _FRAMES.findall(text)
    if len(heads) != len(starts) or any(len(number) > 18 for number, _ in heads):
        raise _NotPlain
    has_sum = text.count(b"Raw Sum")
    sums = _RAW_SUMS.findall(text) if has_sum else []
    if has_sum and (has_sum != len(starts) or len(sums) != len(starts)):
        return _frame_lines_one_by_one(block, starts, ends)
    given = [time for _, time in heads if time]
    if not _TIMES.fullmatch(b"\n".join(given) + b"\n" if given else b""):
        raise _NotPlain
    times = np.array([float(time) if time else math.nan for _, time in heads])
    raw_sums = np.array([float(raw) for raw in sums]) if sums else np.full(len(heads), np.nan)
    if np.isinf(times).any() or np.isinf(raw_sums).any():
        raise _NotPlain
    return np.array([int(number) for number, _ in heads], dtype=np.int64), times, raw_sums


def _frame_lines_one_by_one(block, starts, ends):
    """:func:`_frame_lines`, line by line (the lines are ASCII without CR: checked there)."""
    numbers, times, raw_sums = [], [], []
    for start, end in zip(starts.tolist(), ends.tolist(), strict=True):
        text = block[start:end]
        match = _FRAME.match(text)
        if match is None or len(match.group(1)) > 18:
            raise _NotPlain
        numbers.append(int(match.group(1)))
        times.append(_number(match.group(2)) if match.group(2) else math.nan)
        if b"Raw Sum" in text:
            raw_sum = _RAW_SUM.search(text)
            if raw_sum is None:
                raise _NotPlain  # numba's "Raw Sum is ..."
            raw_sums.append(_number(raw_sum.group(1)))
        else:
            raw_sums.append(math.nan)
    return (np.array(numbers, dtype=np.int64), np.array(times, dtype=np.float64),
            np.array(raw_sums, dtype=np.float64))


def _check_rows(frame_lines, data_lines, rows, single):
    """Every frame of the block has ``rows`` rows of values; none before its first frame."""
    if single:  # a single frame without a frame line: the row count is checked at the end
        if frame_lines.size:
            raise _NotPlain
        return
    if data_lines.size and (not frame_lines.size or data_lines[0] < frame_lines[0]):
        raise _NotPlain  # rows before the first frame line of the block
    per_frame = np.diff(np.searchsorted(data_lines, frame_lines), append=len(data_lines))
    if (per_frame != rows).any():
        raise _NotPlain


def _values(b, row_starts, row_ends, frame_starts, frame_ends, cols, flat, k, raw):
    """Parse the rows of values into ``flat[k:]``; return them as whole numbers (B as 0)."""
    n = len(row_starts) * cols
    if k + n > flat.size:
        raise _NotPlain
    sep = b == _COMMA
    for start, end in zip(frame_starts.tolist(), frame_ends.tolist(), strict=True):
        sep[start:end] = False
    sep[row_ends] = True
    stops = np.flatnonzero(sep)  # one past each value's last byte
    if stops.size != n or (stops[cols - 1::cols] != row_ends).any():
        raise _NotPlain  # a row without COLS values (or a comma outside the rows)
    length = np.empty_like(stops)
    np.subtract(stops[1:], stops[:-1] + 1, out=length[1:])
    length[::cols] = stops[::cols] - row_starts
    if length.min() < 1 or length.max() > _MAX_DIGITS:
        raise _NotPlain
    whole, blank = _whole_numbers(b, stops, length)
    if raw and whole.max() > 255:
        raise _NotPlain  # numba's "expected a whole number 0..255"
    out = flat[k:k + n]
    np.copyto(out, whole, casting="unsafe")
    np.copyto(out, np.nan, where=blank)
    return whole


def _index(f, name, head, parts, n_frames, raw):
    """Return the :class:`Index` of the file from its blocks; check what spans blocks."""
    if n_frames == 0:
        starts, lines, numbers, times, raw_sums = _single_frame(head)
    else:
        first_lines = np.cumsum([head.first_line] + [p.n_lines for p in parts[:-1]])
        frames = [(p.frames[0], p.frames[1] + first, *p.frames[2:])
                  for p, first in zip(parts, first_lines.tolist(), strict=True)]
        starts, lines, numbers, times, raw_sums = (
            np.concatenate(column) for column in zip(*frames, strict=True))
    if len(numbers) != max(n_frames, 1) or (np.diff(numbers) != 1).any():
        raise _NotPlain
    if sum(p.n_values for p in parts) != len(numbers) * head.rows * head.cols:
        raise _NotPlain  # numba's "... rows of values and no 'Frame N' line ..."
    if raw:
        sums = np.concatenate([p.sums for p in parts if p.sums is not None])
        if (~np.isnan(raw_sums) & (np.abs(sums - raw_sums) > 0.5)).any():
            raise _NotPlain  # numba's "Raw Sum in the frame line is ..."
    stat = os.fstat(f.fileno())
    return Index(name=name, rows=head.rows, cols=head.cols, header=head.header,
                 attrs=head.attrs, first_line=head.first_line, numbers=numbers,
                 times=times, raw_sums=raw_sums, lines=lines.astype(np.int64),
                 starts=np.append(starts, parts[-1].end).astype(np.int64), spaced=False,
                 stat=(stat.st_size, stat.st_mtime_ns), stray_f=None)


def _whole_numbers(b, stops, length):
    """Values of the tokens ending before ``stops``: whole numbers (0 for ``B``), ``B`` mask.

    Up to 8 digits, the bytes before each stop are loaded as one little-endian word, those
    before the token masked to 0 (leading zeros) and the digits combined pairwise by SWAR
    multiplications (``x * 10 + (x >> 8)``, then ``* 100`` and ``* 10000``; the eight-digit
    SWAR step of Lemire 2021, "Number parsing at a gigabyte per second", Software: Practice
    and Experience 51(8)); longer tokens digit by digit.
    """
    width = int(length.max())
    if width > 8:
        return _digit_by_digit(b, stops, length)
    dtype, size = (np.uint32, 4) if width <= 4 else (np.uint64, 8)
    padded = np.empty(b.size + 8, dtype=np.uint8)
    padded[:8], padded[8:] = 0, b
    words = np.ndarray((b.size + 1,), dtype=np.dtype(dtype).newbyteorder("<"),
                       buffer=padded, offset=8 - size, strides=(1,))
    x = words.take(stops)  # word k ends at byte k - 1
    x ^= _bytes(dtype, b"0")  # digits now 0..9
    x &= _MASKS[size].take(length)
    blank = x == dtype((_B ^ 48) << (8 * size - 8))
    blank &= length == 1
    np.copyto(x, 0, where=blank)
    bad = x + _bytes(dtype, b"\x76")  # a byte above 9 gets its high bit (or had it)
    bad |= x
    bad &= _bytes(dtype, b"\x80")
    if bad.any():
        raise _NotPlain
    steps = _SWAR_STEPS if size == 8 else _SWAR_STEPS[:2]  # digits in pairs, pairs in fours..
    for shift, lanes in steps:
        high = x >> dtype(shift)
        x *= dtype(10 ** (shift // 8))
        x += high
        x &= _bytes(dtype, lanes)
    return x, blank


_SWAR_STEPS = ((8, b"\xff\x00"), (16, b"\xff\xff\x00\x00"), (32, b"\xff" * 4 + b"\x00" * 4))
"""``(shift, lanes kept)`` per SWAR step: ``x = (x * 10**(shift / 8) + (x >> shift)) & lanes``."""


def _bytes(dtype, pattern):
    """``pattern`` repeated over a little-endian word of ``dtype``."""
    size = np.dtype(dtype).itemsize
    return dtype(int.from_bytes(pattern * (size // len(pattern)), "little"))


def _digit_by_digit(b, stops, length):
    """As :func:`_whole_numbers`, for tokens of up to :data:`_MAX_DIGITS` digits."""
    last = b[stops - 1]
    blank = last == _B
    whole = (last - 48).astype(np.int64)
    ok = (whole <= 9) | blank
    scale = 1
    for i in range(1, int(length.max())):
        scale *= 10
        longer = length > i
        digit = np.where(longer, b.take(stops - (1 + i), mode="clip") - 48, 0)
        ok &= digit <= 9
        whole += digit.astype(np.int64) * scale
    if not ok.all() or (blank & (length != 1)).any():
        raise _NotPlain
    whole[blank] = 0
    return whole, blank


def _number(text):
    """Return the finite number ``text`` (no ``nan``, ``inf``, ``1_0``), else the numba reader's."""
    if not _TIME.fullmatch(text):
        raise _NotPlain
    value = float(text)
    if not math.isfinite(value):
        raise _NotPlain
    return value


def _single_frame(head):
    number = head.header.get("START_FRAME", ("1", 0))[0]
    if not number.strip().isdigit():
        raise _NotPlain
    return (np.array([head.body]), np.array([head.first_line]), np.array([int(number)]),
            np.full(1, np.nan), np.full(1, np.nan))


def _check_space(text):
    if text.strip(_SPACE):
        raise _NotPlain
