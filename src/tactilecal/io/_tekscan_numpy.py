"""NumPy reader for plain Tekscan exports: numbers ``[-]digits[.digits]`` and ``B``, no numba.

numba's import and the load of its cached kernels cost more, in a new process, than pandas'
whole parse of a 10,000-frame export. This reader needs NumPy only. It reads the export
the way the numba reader does, in blocks of whole frames, but with array operations over
each block's bytes: the line ends (LF), each line's first byte (blank line, ``F`` frame
line, row of values, ``@@``), the commas of the rows of values, and per value its bytes
from its end (one by one up to 3, else in words of 8: digits, a point, ``B`` alone),
combined in integers (:func:`_whole_numbers`, :func:`_decimals`) and divided by a power
of ten correctly rounded (:func:`_to_float`), so that each value equals ``float(token)``.

The data is cut at frame lines into one part per core (:func:`_parts`: a part's first
value follows from its first frame's number, checked when the parts are joined), each
parsed by its own thread. A part's blocks are parsed one after another, through arrays
kept from block to block (:class:`_Scratch`): a block's operations are a few long calls,
which release the GIL, and the only fresh pages they map hold the positions NumPy returns
(in a new process, a page fault per 4 KiB of every temporary array cost more than the
parse; blocks of a few thousand values on a thread pool fought over the GIL and were no
faster than one thread).

It reads only the *plain* form every real export seen has (``docs/data-model.md``): rows of
numbers and ``B`` separated by single commas (whole numbers 0..255 in raw files; in others
``[-](digits[.digits] | .digits)`` of up to :data:`_MAX_TOKEN` bytes), LF or CR LF line
ends, frame lines the reader's regular expressions parse, the ``@@`` terminator. At the
first departure from it :func:`read_plain` returns None, having raised nothing: the numba
reader (``_tekscan_index``, ``_tekscan_blocks``) then reads the file from the start; it
defines the format, its checks and every error message, so a file reads the same, or fails
with the same message, whichever reader took it.
"""

import os
from itertools import pairwise

import numpy as np

from tactilecal._validate import MAX_VALUES
from tactilecal.io._tekscan_frames import plain_frame_lines, plain_frame_number
from tactilecal.io._tekscan_layout import Index

__all__ = ["BLOCK_BYTES", "read_plain"]

BLOCK_BYTES = 2**20
"""Bytes of the file read at a time; each read's whole frames are parsed as one block.

About 300,000 values of raw readings: each array of the parse is then a few MB, kept from
block to block; larger blocks were no faster and need more memory.
"""

_MAX_DIGITS = 19  # a whole number of up to 19 digits is below 2**64: one uint64
_MAX_TOKEN = 40  # bytes of the longest value read here (Python's float past 19 digits)
_PAD = 8  # bytes before a block, so that a word can end at any of its bytes
_SPACE = b" \t\x0b\x0c\r\n"
_LF, _CR, _COMMA, _AT, _B, _F, _POINT, _MINUS = 10, 13, 44, 64, 66, 70, 46, 45


class _NotPlain(Exception):
    """The file departs from the plain form: the numba reader takes it."""


class _NotWhole(_NotPlain):
    """A token is not a whole number (or ``B``): a decimal, or not plain."""


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
    first, n_frames = _header_frames(head)
    if n_frames is None or 2 * n_frames * per_frame > size:
        first, n_frames = None, _count_frames(f, head.body)
    n_values = max(n_frames, 1) * per_frame
    if n_values > MAX_VALUES or 2 * n_values > size:
        raise _NotPlain  # more values than the file has room for (a value and a comma each)
    values = np.empty((max(n_frames, 1), head.rows, head.cols))
    raw = head.attrs.get("units") in (None, "raw")
    parsers = [_Parser(head, values.reshape(-1), raw, n_frames == 0, part)
               for part in _parts(f, head, size, first, n_values)]
    _run(parsers, f.name)
    return values, _index(f, name, head, parsers, n_frames, raw)


PART_BYTES = BLOCK_BYTES
"""Smallest part of the data a thread parses on its own (one part per core at most).

One block: a file of two blocks or more is shared by the cores."""


def _parts(f, head, size, first, n_values):
    """``(start, stop, first value, last)`` of each part of the data, cut at frame lines.

    One part per core, each at least :data:`PART_BYTES`. A cut's first value follows from
    its frame's number and the first frame's (``first``, the header's ``START_FRAME``; None:
    one part); the parse checks it (each part must end at the value where the next begins).
    """
    end = head.body + size
    cores = min(os.cpu_count() or 1, size // PART_BYTES) if first is not None else 1
    cuts = [(head.body, 0)]
    for i in range(1, cores):
        found = _frame_line_after(f, head.body + size * i // cores, end, head)
        if found is not None:
            offset, number = found
            k = (number - first) * head.rows * head.cols
            if offset > cuts[-1][0] and cuts[-1][1] < k < n_values:
                cuts.append((offset, k))
    stops = [offset for offset, _ in cuts[1:]] + [end]
    return [(start, stop, k, stop == end) for (start, k), stop in zip(cuts, stops, strict=True)]


def _frame_line_after(f, offset, end, head):
    """``(offset, frame number)`` of the first frame line after ``offset``, or None."""
    f.seek(offset)
    chunk = f.read(min(end - offset, 2 * _largest(head)))
    at = chunk.find(b"\nF") + 1
    line_end = chunk.find(b"\n", at)
    number = plain_frame_number(chunk[at:line_end].rstrip(b"\r")) if at and line_end > 0 else None
    return None if number is None else (offset + at, number)


def _largest(head):
    """Return the most bytes a plain frame holds (15 digits and a comma a value, CR LF a row)."""
    return 17 * head.rows * head.cols + 2 * head.rows + 2**20


def _run(parsers, path):
    """Run each parser's :meth:`_Parser.read`, the first here, the others on threads.

    The first part to fail stops the others at their next block.
    """
    if len(parsers) == 1:
        parsers[0].read(path)
        return
    import threading
    from concurrent.futures import ThreadPoolExecutor

    failed = threading.Event()
    for parser in parsers:
        parser.failed = failed
    with ThreadPoolExecutor(max_workers=len(parsers) - 1) as pool:
        others = [pool.submit(parser.read, path) for parser in parsers[1:]]
        parsers[0].read(path)
        for other in others:
            other.result()


def _header_frames(head):
    """``(first frame, frames)`` from ``START_FRAME`` and ``END_FRAME``, else ``(None, None)``.

    Given when both are whole numbers and say 2 frames or more. Checked at the end (the
    frame lines found must be as many): a header that does not say how many frames follow
    (frames missing, or edited) sends the file to the numba reader.
    """
    first, last = (head.header.get(key, ("", 0))[0].strip() for key in ("START_FRAME",
                                                                       "END_FRAME"))
    if not (first.isascii() and first.isdigit() and last.isascii() and last.isdigit()):
        return None, None
    n = int(last) - int(first) + 1
    return (int(first), n) if n >= 2 else (None, None)


def _count_frames(f, body):
    """Count the lines starting with ``F`` after ``body`` (its first byte is an LF)."""
    f.seek(body)
    count, last = 0, b""
    while chunk := f.read(BLOCK_BYTES):
        count += (last + chunk[:1]).count(b"\nF") + chunk.count(b"\nF")
        last = chunk[-1:]
    return count


class _Scratch:
    """Arrays kept from block to block: views of the first ``n`` items, grown when needed."""

    def __init__(self):
        self._arrays = {}

    def get(self, key, n, dtype):
        array = self._arrays.get((key, np.dtype(dtype)))
        if array is None or array.size < n:
            array = np.empty(max(n, 2 * (0 if array is None else array.size)), dtype=dtype)
            self._arrays[key, np.dtype(dtype)] = array
        return array[:n]


class _Parser:
    """Parse the blocks of a part of an export, one after another, into ``flat``.

    Each read of :data:`BLOCK_BYTES` is appended to the bytes held; the whole frames among
    them (up to the last frame line, or to ``@@``) are parsed, the rest held for the next.
    Collected per block: the frame lines (file offsets, line numbers from the part's start,
    frame numbers, times, raw sums) and, for raw files, each frame's sum. ``part`` is
    ``(start, stop, first value, last part)``: the bytes ``start:stop`` of the file, whose
    first value is ``flat[first value]``; only the last part ends with ``@@``.
    """

    def __init__(self, head, flat, raw, single, part):
        self.head, self.flat, self.raw, self.single = head, flat, raw, single
        self.start, self.stop, self.k0, self.last = part
        self.scratch = _Scratch()
        self.frames, self.sums = [], []
        self.end = None  # file offset of the ``@@`` line
        self.k = self.k0  # next value
        self.line = 0  # number of the first line held, from the part's first
        self.failed = None  # set by any part's failure (:func:`_run`): stop at the next block
        self.decimal = False  # a block had decimals: the next ones are read as decimals

    def read(self, path):
        """Parse the part of the file at ``path`` (opened here: one offset per thread)."""
        try:
            with open(path, "rb") as f:
                f.seek(self.start)
                self._read(f)
        except BaseException:
            if self.failed is not None:
                self.failed.set()
            raise

    def _read(self, f):
        largest = _largest(self.head)
        buf = np.zeros(_PAD + BLOCK_BYTES + largest + 1, dtype=np.uint8)  # pages as used
        view, held, base = memoryview(buf), 0, self.start
        while True:
            want = min(BLOCK_BYTES, self.stop - base - held)
            n = f.readinto(view[_PAD + held:_PAD + held + want]) if want else 0
            held += n
            if not n and held and buf[_PAD + held - 1] != _LF:
                buf[_PAD + held], held = _LF, held + 1  # a last line without its LF
            done = self._block(buf[:_PAD + held], base, last=not n)
            if self.end is not None or not n:
                break
            buf[_PAD:_PAD + held - done] = buf[_PAD + done:_PAD + held]
            held, base = held - done, base + done
            if held > largest:
                raise _NotPlain  # more bytes than a plain frame holds: numba says why
            if self.failed is not None and self.failed.is_set():
                raise _NotPlain  # another part departed from the plain form
        if (self.end is None) == self.last:
            raise _NotPlain  # no @@ (or one before the last part)
        while self.last and (chunk := f.read(2**20)):
            _check_space(chunk)  # after @@

    def _block(self, padded, base, last):
        """Parse the whole frames of ``padded[_PAD:]``; return the bytes parsed."""
        b = padded[_PAD:]
        lf = np.flatnonzero(np.equal(b, _LF, out=self.scratch.get("bytes", b.size, bool)))
        if not lf.size:
            return 0
        starts = np.empty_like(lf)
        starts[0], starts[1:] = 0, lf[:-1] + 1
        first = b[starts]
        is_frame = first == _F
        at = np.flatnonzero(first == _AT)
        if at.size:  # the end: its lines, then what follows it
            stop = int(at[0])
            if bytes(b[starts[stop]:lf[stop]]).strip(_SPACE) != b"@@":
                raise _NotPlain
            _check_space(bytes(b[lf[stop] + 1:]))
            self.end = base + int(starts[stop])
        elif last:
            stop = lf.size
        else:  # up to the last frame line: the frames before it are whole
            frame_lines = np.flatnonzero(is_frame)
            stop = int(frame_lines[-1]) if frame_lines.size else 0
        if stop == 0:
            return 0
        lf, starts, first, is_frame = lf[:stop], starts[:stop], first[:stop], is_frame[:stop]
        ends = lf - ((lf > starts) & (b[lf - 1] == _CR))  # before CR LF
        is_data = (first == _B) | (first - 48 <= 9) | (first == _MINUS) | (first == _POINT)
        if not (is_frame | is_data | (ends == starts)).all():
            raise _NotPlain  # another line (numba's "expected a 'Frame N' line ..."), lone CR
        frame_lines, data_lines = np.flatnonzero(is_frame), np.flatnonzero(is_data)
        view = memoryview(b)
        parsed = plain_frame_lines(view, starts[frame_lines], ends[frame_lines])
        if parsed is None:
            raise _NotPlain  # numba's reader reads each line, or says what is wrong
        numbers, times, raw_sums = parsed
        self.frames.append((base + starts[frame_lines], self.line + frame_lines, numbers,
                            times, raw_sums))
        _check_rows(frame_lines, data_lines, self.head.rows, self.single)
        if data_lines.size:
            sums = self._values(padded[:_PAD + int(lf[-1]) + 1], starts[data_lines],
                                ends[data_lines], starts[frame_lines], ends[frame_lines])
            if sums is not None:
                self.sums.append(sums)
        self.line += stop
        return int(lf[-1]) + 1

    def _values(self, padded, row_starts, row_ends, frame_starts, frame_ends):
        """Parse the rows of values into ``flat``; return a raw file's frame sums, else None.

        The values are parsed in runs of about :data:`BLOCK_BYTES` of text
        (:func:`_runs`), so that a frame larger than a block (one row of millions of values)
        needs no more memory per value than a block of small frames.
        """
        cols, b = self.head.cols, padded[_PAD:]
        n = len(row_starts) * cols
        if self.k + n > self.flat.size:
            raise _NotPlain
        sep = np.equal(b, _COMMA, out=self.scratch.get("bytes", b.size, bool))
        for start, end in zip(frame_starts.tolist(), frame_ends.tolist(), strict=True):
            sep[start:end] = False
        sep[row_ends] = True
        stops = np.flatnonzero(sep)  # one past each value's last byte
        if stops.size != n or (stops[cols - 1::cols] != row_ends).any():
            raise _NotPlain  # a row without COLS values (or a comma outside the rows)
        length = self.scratch.get("length", n, np.int32)  # a line is shorter than 2**31
        np.subtract(stops[1:], stops[:-1], out=length[1:], casting="unsafe")
        length[1:] -= 1
        length[::cols] = stops[::cols] - row_starts
        if length.min() < 1 or length.max() > _MAX_TOKEN:
            raise _NotPlain
        out = self.flat[self.k:self.k + n]
        runs = _runs(stops)
        if len(runs) == 1:  # the block as it is
            whole = self._run(padded, stops, length, out)
        else:
            for a, z in runs:
                first = int(stops[a] - length[a])  # the run's bytes, after _PAD bytes before
                run = padded[first:_PAD + int(stops[z - 1])]
                whole = self._run(run, stops[a:z] - first, length[a:z], out[a:z])
        self.k += n
        if not self.raw:
            return None
        per_frame = self.head.rows * self.head.cols
        if len(runs) == 1:
            return whole.reshape(-1, per_frame).sum(axis=1, dtype=np.int64)
        return np.nansum(out.reshape(-1, per_frame), axis=1)  # whole numbers below 2**53

    def _run(self, padded, stops, length, out):
        """Parse a run of tokens into ``out``; return a raw file's as whole numbers (B: 0)."""
        if not self.raw:
            self.decimal = _numbers(padded, stops, length, out, self.scratch, self.decimal)
            return None
        # whole numbers 0..255 (numba's "expected a whole number 0..255")
        whole, blank = _whole_numbers(padded, stops, length, self.scratch)
        if whole.max() > 255:
            raise _NotPlain
        np.copyto(out, whole, casting="unsafe")
        _blank_to_nan(out, blank)
        return whole


def _blank_to_nan(out, blank):
    """``out[blank] = NaN``; a block without ``B`` (an I-Scan sensor's) skips the masked pass."""
    if blank.any():
        np.copyto(out, np.nan, where=blank)


def _runs(stops):
    """Return ``(first, stop)`` ranges of the tokens ending at ``stops``.

    Each holds about :data:`BLOCK_BYTES` of text (a single range up to twice that).
    """
    size = int(stops[-1])
    if size <= 2 * BLOCK_BYTES:
        return [(0, stops.size)]
    cuts = np.searchsorted(stops, np.arange(BLOCK_BYTES, size, BLOCK_BYTES), side="right")
    bounds = np.unique(np.concatenate(([0], cuts, [stops.size])))
    return list(pairwise(bounds.tolist()))


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


def _index(f, name, head, parsers, n_frames, raw):
    """Return the :class:`Index` of the file from its parts; check what spans blocks."""
    if n_frames == 0:
        starts, lines, numbers, times, raw_sums = _single_frame(head)
    else:
        first_lines = np.cumsum([head.first_line] + [p.line for p in parsers[:-1]])
        frames = [(start, line + first, *rest) for parser, first
                  in zip(parsers, first_lines.tolist(), strict=True)
                  for start, line, *rest in parser.frames]
        starts, lines, numbers, times, raw_sums = (
            np.concatenate(column) for column in zip(*frames, strict=True))
    if len(numbers) != max(n_frames, 1) or (np.diff(numbers) != 1).any():
        raise _NotPlain
    if any(p.k != q.k0 for p, q in pairwise(parsers)) or (
            parsers[-1].k != len(numbers) * head.rows * head.cols):
        raise _NotPlain  # a part not ending where the next begins, or rows without a frame
    sums = [s for parser in parsers for s in parser.sums]
    if raw and sums:
        sums = np.concatenate(sums)
        if (~np.isnan(raw_sums) & (np.abs(sums - raw_sums) > 0.5)).any():
            raise _NotPlain  # numba's "Raw Sum in the frame line is ..."
    stat = os.fstat(f.fileno())
    return Index(name=name, rows=head.rows, cols=head.cols, header=head.header,
                 attrs=head.attrs, first_line=head.first_line, numbers=numbers,
                 times=times, raw_sums=raw_sums, lines=lines.astype(np.int64),
                 starts=np.append(starts, parsers[-1].end).astype(np.int64), spaced=False,
                 stat=(stat.st_size, stat.st_mtime_ns), stray_f=None)


def _numbers(padded, stops, length, out, scratch, decimal=False):
    """Write the values of the tokens ending before ``stops`` into ``out`` (float64).

    Whole numbers (:func:`_whole_numbers`) or, at the first other byte or when ``decimal``,
    decimals (:func:`_decimals`); ``B`` is NaN. Each value equals ``float(token)``. Returns
    whether the tokens were read as decimals.
    """
    if not decimal:
        try:
            whole, blank = _whole_numbers(padded, stops, length, scratch)
        except _NotWhole:
            pass
        else:
            np.copyto(out, whole, casting="unsafe")  # up to 8 digits: exact
            _blank_to_nan(out, blank)
            return False
    whole, blank, frac, neg, longest = _decimals(padded, stops, length, scratch)
    _to_float(whole, frac, out)
    np.negative(out, out=out, where=neg)
    _blank_to_nan(out, blank)
    if longest.size:
        b = padded[_PAD:]
        out[longest] = [float(bytes(b[stop - size:stop])) for stop, size
                        in zip(stops[longest].tolist(), length[longest].tolist(), strict=True)]
    return True


def _decimals(padded, stops, length, scratch):
    """Read tokens ``[-](digits[.digits] | .digits)`` as whole numbers and fraction digits.

    Returns ``(digits, blank, fraction digits, negative, longest)``. The bytes after a minus
    sign are read in words of 8 from the token's end (:func:`_swar`), each dropping a point
    it holds; a token's digits are then ``sum(word * 10**(digits in the words after it))``,
    its fraction digits those after the point. Any other byte raises :class:`_NotPlain`.
    ``longest`` indexes the tokens of more than :data:`_MAX_DIGITS` digits, whose values
    are left to Python's ``float``.
    """
    neg = padded[_PAD:][stops - length] == _MINUS
    body = length - neg.view(np.int8)  # the bytes after the sign
    n_words = max(1, (int(body.max()) + 7) // 8)
    words = _words(padded, np.uint64)
    if n_words > 1:  # several takes: the overlapping words copied once
        contiguous = scratch.get("words", words.size, np.uint64)
        np.copyto(contiguous, words)
        words = contiguous
    for w in range(n_words):
        size = np.clip(body - 8 * w, 0, 8)
        ends = np.maximum(stops - 8 * w, 0)  # (a token that ended sooner has no byte left)
        x, blank, frac_w, has = _swar(padded, ends, size, scratch, f"{w}", point=True,
                                      words=words)
        frac_w = frac_w.view(np.int64)  # 0..7
        digits_w = size - has.view(np.int8)
        if w == 0:
            whole, frac, points, digits, first_blank = x, frac_w * has, has, digits_w, blank
            continue
        if blank.any():
            raise _NotPlain  # a B before 8 bytes
        x *= _POW10_WHOLE[np.minimum(digits, _MAX_DIGITS)]
        whole += x  # wraps past 19 digits: those are longest
        frac += has * (frac_w + digits)
        points += has
        digits += digits_w
    if digits.min() < 1 or points.max() > 1 or (first_blank & neg).any():
        raise _NotPlain  # ".", "-", "-.", a point in two words, "-B"
    return whole, first_blank, frac, neg, np.flatnonzero(digits > _MAX_DIGITS)


def _to_float(whole, frac, out):
    """``out = whole / 10**frac``, correctly rounded (``whole`` uint64).

    Below ``2**53`` the quotient of two exactly representable doubles is correctly rounded
    (Clinger 1990, "How to read floating point numbers accurately", PLDI, sec. 5); above it,
    :func:`_round_big`.
    """
    np.copyto(out, whole.view(np.int64), casting="unsafe")  # exact below 2**53; int64: faster
    frac = np.minimum(frac, _MAX_DIGITS)  # (past 19 digits a value is replaced: _numbers)
    low, high = int(frac.min()), int(frac.max())
    np.divide(out, _POW10[low] if low == high else _POW10[frac], out=out)
    if int(whole.max()) < 2**53:
        return
    big = np.flatnonzero(whole >= 2**53)
    out[big] = _round_big(whole[big], frac[big])


def _round_big(m, places):
    """Return ``m / 10**places`` correctly rounded, for ``2**53 <= m < 2**64``.

    ``m = hi + lo`` exactly (``hi`` its double, ``lo`` a whole number below ``2**11``);
    ``q = hi / P`` (``P = 10**places``, exact) leaves the remainder ``hi - q * P``, exact
    (Dekker 1971, "A floating-point technique for extending the available precision", Numer.
    Math. 18, with Veltkamp's split), so that ``m / P = q + d``, ``d = (hi - q * P + lo) / P``
    to within a relative ``2**-51``, at most two units in the last place of ``q``. ``r =
    q + d`` rounded is the correctly rounded quotient unless ``m / P`` lies within that error
    of a midpoint between ``r`` and a neighbour: those (exact midpoints among them) are
    converted by Python's correctly rounded ``float``.
    """
    hi = m.astype(np.float64)
    lo = (m - hi.astype(np.uint64)).view(np.int64).astype(np.float64)
    power, power_high, power_low = _POW10[places], _POW10_HIGH[places], _POW10_LOW[places]
    q = hi / power
    q_high, q_low = _veltkamp(q)
    product = q * power
    error = ((q_high * power_high - product) + q_high * power_low + q_low * power_high
             + q_low * power_low)
    d = ((hi - product) - error + lo) / power
    r = q + d
    left = d - (r - q)  # m / P - r, to within the error of d
    gap = np.spacing(r)
    below = (np.frexp(r)[0] == 0.5) & (left < 0)  # below a power of 2, half the gap
    half = np.where(below, gap / 4, gap / 2)
    for k in np.flatnonzero(np.abs(left) >= half - gap * 2.0**-30).tolist():
        r[k] = float(f"{int(m[k])}e-{int(places[k])}")
    return r


def _veltkamp(x):
    """Split ``x`` into ``(high, low)``, ``x = high + low``, each of 26 bits at most."""
    split = x * _SPLIT
    high = split - (split - x)
    return high, x - high


_SPLIT = 2.0**27 + 1
_POW10 = np.array([10.0**k for k in range(_MAX_DIGITS + 1)])  # exact to 10**22
_POW10_HIGH, _POW10_LOW = _veltkamp(_POW10)
_POW10_WHOLE = np.array([10**k for k in range(_MAX_DIGITS + 1)], dtype=np.uint64)


def _whole_numbers(padded, stops, length, scratch=None):
    """Values of the tokens ending before ``stops``: whole numbers (0 for ``B``), ``B`` mask.

    ``stops`` index the bytes ``padded[_PAD:]`` (the block; any bytes before it). Tokens of
    up to 3 bytes (raw readings) are read by :func:`_three_digits`, of up to 8 digits by
    :func:`_swar`; any other token (more digits, a point, a sign) raises
    :class:`_NotWhole` (:func:`_decimals` reads it). The results are views of
    ``scratch``'s arrays (:class:`_Scratch`), valid until their next use.
    """
    longest = int(length.max())
    if longest > 8:
        raise _NotWhole
    if longest <= 3:
        return _three_digits(padded, stops, length, scratch or _Scratch())
    return _swar(padded, stops, length, scratch or _Scratch(), "")


def _three_digits(padded, stops, length, scratch):
    """:func:`_whole_numbers` of tokens of 1 to 3 bytes, digit by digit (raw readings).

    The last, second last and third last byte before each stop are gathered from the
    block itself (a take from a contiguous array copies nothing more), those before the
    token set to 0, and ``100 c + 10 b + a`` formed in uint16: fewer operations than
    :func:`_swar`'s words, whose overlapping view ``take`` copies whole.
    """
    n = stops.size
    ones, tens, hundreds = digits = [
        padded[_PAD - k:].take(stops, out=scratch.get(f"digit{k}", n, np.uint8))
        for k in (1, 2, 3)]
    for digit in digits:
        digit -= np.uint8(48)  # digits now 0..9, any other byte above 9
    one = np.equal(length, 1, out=scratch.get("one", n, bool))
    blank = np.equal(ones, _B - 48, out=scratch.get("blank", n, bool))
    blank &= one
    np.copyto(ones, 0, where=blank)
    np.copyto(tens, 0, where=one)
    hundreds *= np.equal(length, 3, out=one)
    largest = np.maximum(ones, tens, out=scratch.get("largest", n, np.uint8))
    np.maximum(largest, hundreds, out=largest)
    if largest.max() > 9:
        raise _NotWhole
    whole = np.multiply(hundreds, np.uint16(100), out=scratch.get("whole", n, np.uint16))
    whole += np.multiply(tens, np.uint16(10), out=scratch.get("tens", n, np.uint16))
    whole += ones
    return whole, blank


def _swar(padded, stops, length, scratch, key, point=False, words=None):
    """:func:`_whole_numbers` of tokens of 0 to 8 digits (or ``B``; no digit: 0).

    The bytes before each stop are loaded as one little-endian word, those before the token
    masked to 0 (leading zeros) and the digits combined pairwise by SWAR multiplications
    (``x * 10 + (x >> 8)``, then ``* 100`` and ``* 10000``; the eight-digit SWAR step of
    Lemire 2021, "Number parsing at a gigabyte per second", Software: Practice and
    Experience 51(8)). ``key`` names the scratch arrays used. With ``point``, a token may
    hold a decimal point (:func:`_drop_point`); the fraction digits are returned as well.
    ``words``: :func:`_words` of ``padded`` as a contiguous array, for several calls.
    """
    dtype, size = (np.uint32, 4) if int(length.max()) <= 4 and not point else (np.uint64, 8)
    n = stops.size
    words = _words(padded, dtype) if words is None else words
    x = words.take(stops, out=scratch.get(key + "x", n, dtype))  # word k ends at byte k - 1
    other = scratch.get(key + "other", n, dtype)
    x ^= _bytes(dtype, b"0")  # digits now 0..9
    before = np.subtract(size, length, out=other, casting="unsafe")  # bytes before the token
    before <<= dtype(2)  # half the bits before the token: two shifts, each below the width
    mask = np.left_shift(dtype(2**(8 * size) - 1), before, out=scratch.get(key + "mask", n,
                                                                            dtype))
    x &= np.left_shift(mask, before, out=mask)  # only the token's (none: length 0)
    frac, has = _drop_point(x, mask, other) if point else (None, None)
    blank = np.equal(x, dtype((_B ^ 48) << (8 * size - 8)),
                     out=scratch.get(key + "blank", n, bool))
    blank &= np.equal(length, 1, out=scratch.get(key + "one", n, bool))
    np.copyto(x, 0, where=blank)
    bad = np.add(x, _bytes(dtype, b"\x76"), out=other)  # a byte above 9: its high bit set
    bad |= x  # (or had it)
    bad &= _bytes(dtype, b"\x80")
    if bad.any():
        raise _NotWhole
    steps = _SWAR_STEPS if size == 8 else _SWAR_STEPS[:2]  # digits in pairs, pairs in fours..
    for shift, lanes in steps:
        high = np.right_shift(x, dtype(shift), out=other)
        x *= dtype(10 ** (shift // 8))
        x += high
        x &= _bytes(dtype, lanes)
    return (x, blank) if not point else (x, blank, frac, has)


def _words(padded, dtype):
    """Return the little-endian words of ``dtype`` ending at each byte of a block (a view).

    ``take`` copies such a view, overlapping and unaligned, whole: for several takes from
    one block, copy it once.
    """
    size = np.dtype(dtype).itemsize
    return np.ndarray((padded.size - _PAD + 1,), dtype=np.dtype(dtype).newbyteorder("<"),
                      buffer=padded, offset=_PAD - size, strides=(1,))


def _drop_point(x, mask, other):
    r"""Remove the lowest point byte from each word ``x`` (after ``^ b"0"``), in place.

    Returns the fraction digits (the bytes above the point, 0 where there is none) and
    where there is one. The point's byte is the lowest zero byte of ``y = x ^ b"\x1e"``,
    found exactly by Mycroft's test ``(y - 0x01..) & ~y & 0x80..`` (false positives only
    above it) and its lowest set bit; its index ``j`` gives ``7 - j`` as the top byte of
    ``(bit >> 7) * 0x0706..00``. The bytes below the point move up one byte over it.
    ``mask`` and ``other`` are scratch.
    """
    y = np.bitwise_xor(x, _bytes(np.uint64, b"\x1e"), out=mask)
    low = np.subtract(y, _bytes(np.uint64, b"\x01"), out=other)
    low &= np.invert(y, out=y)
    low &= _bytes(np.uint64, b"\x80")
    np.negative(low, out=mask)  # two's complement: low & -low is the lowest set bit
    low &= mask
    frac = np.right_shift(low, np.uint64(7))
    frac *= np.uint64(0x0706050403020100)
    frac >>= np.uint64(56)
    below = np.subtract(low, np.uint64(1), out=mask)  # the point's byte and those below it
    below |= low
    has = low != 0
    below *= has
    moved = np.left_shift(x, np.uint64(8), out=other)
    moved ^= x
    moved &= below
    x ^= moved
    return frac, has


_SWAR_STEPS = ((8, b"\xff\x00"), (16, b"\xff\xff\x00\x00"), (32, b"\xff" * 4 + b"\x00" * 4))
"""``(shift, lanes kept)`` per SWAR step: ``x = (x * 10**(shift / 8) + (x >> shift)) & lanes``."""


def _bytes(dtype, pattern):
    """``pattern`` repeated over a little-endian word of ``dtype``."""
    size = np.dtype(dtype).itemsize
    return dtype(int.from_bytes(pattern * (size // len(pattern)), "little"))


def _single_frame(head):
    number = head.header.get("START_FRAME", ("1", 0))[0]
    if not number.strip().isdigit():
        raise _NotPlain
    return (np.array([head.body]), np.array([head.first_line]), np.array([int(number)]),
            np.full(1, np.nan), np.full(1, np.nan))


def _check_space(text):
    if text.strip(_SPACE):
        raise _NotPlain
