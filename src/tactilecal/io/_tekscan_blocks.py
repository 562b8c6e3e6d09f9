"""Parse the values of whole frames of an indexed Tekscan export (eager and dask reads).

A :class:`Block` is everything needed to parse frames ``k0:k1`` of a file without its
:class:`~tactilecal.io._tekscan_index.Index` (a few numbers and four short arrays), so that it
travels cheaply inside a dask graph: each task opens the file, reads the block's byte range
and parses it with :func:`~tactilecal.io._tekscan_kernels.parse_rows`.
"""

import os
from dataclasses import dataclass

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal.io import _tekscan_kernels as kernels

__all__ = ["Block", "blocks", "parse_block", "parse_into", "read_block", "check_stray_f",
           "raise_range", "check_block_sums"]

_SLOW = 4096  # numbers converted by Python per kernel call at most


@dataclass(frozen=True)
class Block:
    """Frames ``k0:k0 + len(numbers)`` of an export: byte offsets, line numbers and checks."""

    name: str
    rows: int
    cols: int
    spaced: bool
    raw: bool
    units: str | None
    stat: tuple
    k0: int
    starts: np.ndarray
    lines: np.ndarray
    numbers: np.ndarray
    raw_sums: np.ndarray

    @property
    def n_frames(self):
        """Number of frames in the block."""
        return len(self.numbers)

    @property
    def n_bytes(self):
        """Bytes of the file the block spans."""
        return int(self.starts[-1] - self.starts[0])


def blocks(index, frames_per_block=None, *, max_bytes=None):
    """Split ``index`` into :class:`Block` s of ``frames_per_block`` frames (or ``max_bytes``)."""
    n = len(index.numbers)
    if frames_per_block is not None:
        edges = list(range(0, n, frames_per_block)) + [n]
    else:  # greedy: whole frames, about max_bytes each
        size = index.starts - index.starts[0]
        edges, k = [0], 0
        while k < n:
            k = max(k + 1, int(np.searchsorted(size, size[k] + max_bytes, side="right")) - 1)
            edges.append(min(k, n))
    return [_block(index, a, b) for a, b in zip(edges[:-1], edges[1:], strict=True)]


def _block(index, a, b):
    return Block(name=index.name, rows=index.rows, cols=index.cols, spaced=index.spaced,
                 raw=index.raw, units=index.attrs.get("units"), stat=index.stat, k0=a,
                 starts=index.starts[a:b + 1], lines=index.lines[a:b],
                 numbers=index.numbers[a:b], raw_sums=index.raw_sums[a:b])


def read_block(path, block):
    """Open ``path``, check it is the file indexed, parse ``block``; return its values.

    The values are checked as the eager read checks them (raw readings whole 0..255, each
    frame's ``Raw Sum``); a fault raises ``ValueError`` naming the file and line.
    """
    out = np.empty((block.n_frames, block.rows, block.cols))
    with open(path, "rb") as f:
        _check_unchanged(f, block)
        sums, bad = parse_block(f, block, out)
    if bad is not None:
        raise_range(bad, block)
    check_block_sums(block, sums)
    return out


def parse_into(path, block, out):
    """Parse ``block`` of ``path`` into ``out``; return ``(sums, first bad raw value, error)``.

    A fault in the values is returned (``error``), not raised, so that the caller can report
    the first in file order whichever thread found it first.
    """
    try:
        with open(path, "rb") as f:
            _check_unchanged(f, block)
            sums, bad = parse_block(f, block, out)
    except ValueError as exc:
        return None, None, exc
    return sums, bad, None


def _check_unchanged(f, block):
    stat = os.fstat(f.fileno())
    if (stat.st_size, stat.st_mtime_ns) != block.stat:
        raise TactilecalError(f"{block.name} changed since it was indexed (size or time "
                              "stamp differ); expected the file unchanged while it is read: "
                              "read it again")


def parse_block(f, block, out, buf=None):
    """Parse ``block`` of the open file ``f`` into ``out`` (shape (frames, ROWS, COLS)).

    Returns
    -------
    sums : ndarray
        Sum of each frame's finite values.
    bad : tuple or None
        ``(value index in out, line number, value)`` of the first value that is no raw
        reading (whole 0..255) when ``block.raw``, else None.

    Raises
    ------
    ValueError
        A value that is not a finite number (file, line, value number), or a file that
        changed since it was indexed.
    """
    size = block.n_bytes
    if buf is None or buf.size < size:
        buf = np.empty(size, dtype=np.uint8)
    f.seek(int(block.starts[0]))
    if f.readinto(memoryview(buf)[:size]) != size:
        raise _changed(block)
    flat = out.reshape(-1)
    per_frame = block.rows * block.cols
    sums, bad = np.zeros(block.n_frames), np.full(2, -1, dtype=np.int64)
    slow = np.empty((max(_SLOW, block.cols), 3), dtype=np.int64)  # room for a whole row
    pos, k, first_slow_bad = 0, 0, None
    while True:
        status, pos, k, n_slow = kernels.parse_rows(
            buf, pos, size, flat, k, block.cols, per_frame, block.spaced, block.raw, sums,
            bad, slow, 0)
        first_slow_bad = _convert_slow(buf, slow[:n_slow], flat, sums, per_frame, block,
                                       first_slow_bad)
        if status == 1:
            raise TactilecalError(_bad_value_message(buf, pos, k, block))
        if status == 3:
            raise _changed(block)
        if status == 0:
            break
    if k != flat.size:
        raise _changed(block)
    found = [(int(bad[0]), int(bad[1]))] if bad[0] >= 0 else []
    found += [first_slow_bad] if first_slow_bad else []
    if not found:
        return sums, None
    k_bad, line_start = min(found)
    line = int(block.lines[0]) + int(np.count_nonzero(buf[:line_start] == 10))
    return sums, (k_bad, line, float(flat[k_bad]))


def _convert_slow(buf, slow, flat, sums, per_frame, block, first_bad):
    """Convert the numbers the kernel left to Python (correctly rounded ``float``)."""
    for k, start, stop in slow:
        value = float(bytes(buf[start:stop]))
        if not np.isfinite(value):
            raise TactilecalError(_bad_value_message(buf, start, k, block))
        flat[k] = value
        sums[k // per_frame] += value
        whole = 0 <= value <= 255 and value == int(value)
        if block.raw and not whole and (first_bad is None or k < first_bad[0]):
            first_bad = (int(k), int(bytes(buf[:start]).rfind(b"\n") + 1))
    return first_bad


def _line_at(buf, pos):
    """``(line start, line bytes without CR LF)`` of the line holding ``buf[pos]``."""
    head, tail = bytes(buf[:pos]), bytes(buf[pos:])
    start, stop = head.rfind(b"\n") + 1, tail.find(b"\n")
    text = head[start:] + (tail if stop < 0 else tail[:stop])
    return start, text[:-1] if text.endswith(b"\r") else text


def _bad_value_message(buf, pos, k, block):
    start, text = _line_at(buf, pos)
    line = int(block.lines[0]) + int(np.count_nonzero(buf[:start] == 10))
    col = k % block.cols
    token = text.split(b",")[col] if col < text.count(b",") + 1 else b""
    token = token.lstrip(b" ") if block.spaced else token
    return (f"line {line} of {block.name}, value {col + 1}: "
            f"{token.decode('utf-8', errors='replace')!r} is not a finite number; "
            "expected a number or 'B' (no sensel)")


def _changed(block):
    return TactilecalError(f"{block.name} changed since it was indexed (its rows of values no "
                           "longer match the frames found); expected the file unchanged while it "
                           "is read: read it again")


def check_stray_f(f, index):
    """Raise for the first bad value of the first row of values holding an ``F``.

    The earlier pandas-based reader gave this fault precedence over any other bad value (pandas
    read the ``F`` as a comment); so does this one.
    """
    if index.stray_f is None:
        return
    line, offset, length, _ = index.stray_f
    f.seek(offset)
    # writable, as the blocks' buffers: one compiled parse_rows for both
    buf = np.frombuffer(bytearray(f.read(length) + b"\n"), dtype=np.uint8)
    out = np.empty(index.cols)
    status, pos, k, _ = kernels.parse_rows(
        buf, 0, buf.size, out, 0, index.cols, index.cols, index.spaced, False,
        np.zeros(1), np.full(2, -1, dtype=np.int64), np.empty((index.cols, 3), np.int64), 0)
    lines = np.array([line])
    block = Block(name=index.name, rows=index.rows, cols=index.cols, spaced=index.spaced,
                  raw=False, units=None, stat=(), k0=0, starts=np.zeros(2, np.int64),
                  lines=lines, numbers=lines, raw_sums=lines)
    raise TactilecalError(_bad_value_message(buf, pos, k, block))


def raise_range(bad, block):
    """Raise for the first value that is no raw reading (main's ``_check_values`` message)."""
    k, line, value = bad
    expected = ("a whole number 0..255 (UNITS raw)" if block.units else
                "a whole number 0..255: the file has no UNITS line, so it is read as raw; "
                "add e.g. 'UNITS kPa' before ASCII_DATA if its values are calibrated")
    raise TactilecalError(f"line {line} of {block.name}, value {k % block.cols + 1}: "
                          f"{value:.17g}; expected {expected}")


def check_block_sums(block, sums):
    """Compare each frame line's ``Raw Sum`` with the sum of the frame's readings."""
    if not block.raw:
        return
    raw_sums = block.raw_sums
    bad = np.flatnonzero(~np.isnan(raw_sums) & (np.abs(sums - raw_sums) > 0.5))
    if bad.size:
        k = bad[0]
        raise TactilecalError(f"frame {block.numbers[k]} of {block.name} (line {block.lines[k]}): "
                              f"Raw Sum in the frame line is {raw_sums[k]:g}; expected "
                              f"{sums[k]:g}, "
                              "the sum of the frame's readings")
