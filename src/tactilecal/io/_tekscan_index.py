"""Index of a Tekscan ASCII export: header, frame offsets and the structural checks.

:func:`index_export` reads the file once, in blocks of ``BLOCK_BYTES``, through the numba
kernel :func:`~tactilecal.io._tekscan_kernels.index_lines`, and keeps per frame only its byte
offset, line number, number, time and ``Raw Sum`` (about 40 bytes a frame, whatever the frame
size). Every check that needs no value of the data is done here, in the order (and with the
messages) of the earlier pandas-based reader, so that the first fault a file has is the one
reported: terminator, lines after it, unknown lines, frame lines, rows per frame, frame order,
``_`` inside a value, lone CR, row lengths, size.
"""

import os

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._validate import check_size, shorten
from tactilecal.io import _tekscan_kernels as kernels
from tactilecal.io._header import integer
from tactilecal.io._tekscan_frames import frame_line_text, parse_frame_line, plain_frame_lines
from tactilecal.io._tekscan_layout import Index, line_text, max_line_bytes, read_header

__all__ = ["BLOCK_BYTES", "Index", "index_export", "line_text"]

BLOCK_BYTES = 16 * 2**20
"""Bytes read at a time while indexing, and bytes of frames parsed at a time when eager."""


_COLUMNS = {"starts": np.int64, "lines": np.int64, "counts": np.int64, "numbers": np.int64,
            "times": np.float64, "raw_sums": np.float64}
_INFO = kernels.INFO_SLOTS
_STATE = kernels.STATE_SLOTS


def index_export(f, name, *, whole=True, header=None):
    """Index the open export ``f`` (binary); raise the first structural fault found.

    ``whole`` (the values will be read into one array) also checks their number against
    :data:`tactilecal._validate.MAX_VALUES`; a lazy read checks each block instead.
    ``header`` is the file's :class:`~tactilecal.io._tekscan_layout.Header` if already read.

    Returns
    -------
    Index
    """
    head = read_header(f, name) if header is None else header
    rows, cols, first_line = head.rows, head.cols, head.first_line
    scan = _scan(f, head.body, first_line, cols, name)
    numbers, times, raw_sums, lines = _check_structure(f, scan, first_line, rows,
                                                       head.header, name)
    _check_lines(f, scan, rows, cols, lines, name, whole)
    starts = scan["starts"] if len(scan["starts"]) else np.array([head.body])
    stat = os.fstat(f.fileno())
    return Index(name=name, rows=rows, cols=cols, header=head.header, attrs=head.attrs,
                 first_line=first_line, numbers=numbers, times=times, raw_sums=raw_sums,
                 lines=lines, starts=np.append(starts, scan["state"][_STATE["end"]]),
                 spaced=bool(scan["state"][_STATE["spaced"]] == 1),
                 stat=(stat.st_size, stat.st_mtime_ns),
                 stray_f=_slot(scan["info"], "stray_f"))


def _scan(f, offset, first_line, cols, name):
    """Run the index kernel over the file from ``offset``; collect frames and first faults."""
    state, info = kernels.new_state(first_line)
    left = os.fstat(f.fileno()).st_size - offset
    buf = np.empty(max(1, min(BLOCK_BYTES, left + 1)), dtype=np.uint8)  # small files: small
    f.seek(offset)
    columns = {key: [] for key in _COLUMNS}  # per block: 48 bytes a frame, nothing per value
    carry, base, frame_errors = 0, offset, []
    while True:
        got = f.readinto(memoryview(buf)[carry:])
        n = carry + got
        final = got == 0
        lf = np.flatnonzero(buf[:n] == 10)
        if not final and lf.size == 0:  # no whole line yet: read on (a longer buffer if full)
            if n == buf.size:
                if n >= max_line_bytes(cols):
                    raise TactilecalError(f"line {state[_STATE['line']]} of {name}: more than {n} "
                                          "bytes without a line end; expected rows of "
                                          f"{cols} values (COLS)")
                buf = np.concatenate((buf, np.empty_like(buf)))
            carry = n
            continue
        used, fr, rows_before = kernels.index_lines(
            buf, n, lf, base, final, min(cols, 2**62), state, info)
        if columns["counts"]:  # rows before the block's first frame line: the frame before
            columns["counts"][-1][-1] += rows_before
        if len(fr):
            numbers, times, raw_sums = _parse_frame_lines(buf, base, fr, name, frame_errors)
            for key, column in (("starts", fr[:, 0]), ("lines", fr[:, 2]),
                                ("counts", fr[:, 3]), ("numbers", numbers), ("times", times),
                                ("raw_sums", raw_sums)):
                columns[key].append(column.copy())
        if final:
            break
        buf[:n - used] = buf[used:n]
        carry, base = n - used, base + used
    scan = {"state": state, "info": info, "frame_errors": frame_errors}
    for key, dtype in _COLUMNS.items():  # one column at a time: no second copy of them all
        scan[key] = np.concatenate(columns.pop(key)) if columns[key] else np.zeros(0, dtype)
    return scan


def _parse_frame_lines(buf, base, frames, name, errors):
    """``(numbers, times, raw sums)`` of a block's frame lines (``_tekscan_frames``).

    All at once where they are plain, else line by line; a line's fault is kept in
    ``errors`` (raised later, in the order of the checks) and its values left 0 and NaN.
    """
    starts, ends = frames[:, 0] - base, frames[:, 1] - base
    plain = plain_frame_lines(memoryview(buf), starts, ends)
    if plain is not None:
        return plain
    numbers, times, raw_sums = (np.zeros(len(frames), dtype=np.int64),
                                np.full(len(frames), np.nan), np.full(len(frames), np.nan))
    for k, (start, end, line) in enumerate(zip(starts.tolist(), ends.tolist(),
                                               frames[:, 2].tolist(), strict=True)):
        try:
            text = frame_line_text(bytes(buf[start:end]), line, name)
            numbers[k], times[k], raw_sums[k] = parse_frame_line(text, line, name)
        except ValueError as exc:
            errors.append(exc)
    return numbers, times, raw_sums


def _slot(info, key):
    line, offset, a, b = (int(v) for v in info[_INFO[key]])
    return (line, offset, a, b) if line >= 0 else None


def _check_structure(f, scan, first_line, rows, header, name):
    """Terminator, lines after it, unknown lines and the frame lines; return the frames."""
    state, info = scan["state"], scan["info"]
    nul = _slot(info, "nul")
    if nul:
        raise TactilecalError(f"line {nul[0]} of {name}: a NUL byte (character {nul[2] + 1} of "
                              "the line); expected text (a Tekscan ASCII export)")
    if not state[_STATE["stopped"]]:
        raise TactilecalError(f"{name} ends at line {state[_STATE['line']] - 1} without the '@@' "
                              "terminator; expected '@@' after the last frame (truncated file?)")
    stop_line, stop_offset, length, exact = _slot(info, "terminator")
    if not exact:
        raise TactilecalError(f"line {stop_line} of {name}: "
                              f"{line_text(f, stop_offset, length)!r}; expected '@@' (end of data)")
    for key, message in (
            ("after", f" after the '@@' terminator on line {stop_line}; expected the end of "
                      "the file (one ASCII_DATA block per file)"),
            ("other", "; expected a 'Frame N' line, a row of values or '@@'")):
        found = _slot(info, key)
        if found:
            line, offset, length, _ = found
            raise TactilecalError(f"line {line} of {name}: "
                                  f"{line_text(f, offset, length)!r}{message}")
    return _frame_lines(scan, first_line, rows, header, name)


def _frame_lines(scan, first_line, rows, header, name):
    """Check each frame has ``rows`` rows and increasing numbers (main's ``_frame_lines``)."""
    n_data = int(scan["state"][_STATE["n_data"]])
    if len(scan["lines"]) == 0:
        if n_data != rows:
            raise TactilecalError(f"{name} has {n_data} rows of values and no 'Frame N' "
                                  f"line; expected {rows} rows (ROWS) for a single frame")
        number = integer(header, "START_FRAME", name, minimum=0) if "START_FRAME" in header \
            else 1
        return (np.array([number], dtype=np.int64), np.full(1, np.nan), np.full(1, np.nan),
                np.array([first_line]))
    first_data = _slot(scan["info"], "first_data")
    if first_data and first_data[0] < scan["lines"][0]:
        raise TactilecalError(f"line {first_data[0]} of {name}: a row of values before "
                              "the first 'Frame N' line; expected 'Frame N' first")
    if scan["frame_errors"]:
        raise scan["frame_errors"][0]
    numbers, counts, lines = scan["numbers"], scan["counts"], scan["lines"]
    bad = np.flatnonzero(counts != rows)
    if bad.size:
        k = bad[0]
        raise TactilecalError(f"frame {numbers[k]} of {name} (line {lines[k]}) "
                              f"has {counts[k]} rows of values; expected {rows} (ROWS)"
                              + (" (truncated file?)" if k == len(numbers) - 1 else ""))
    check_numbering(numbers, lines, name)
    return numbers, scan["times"], scan["raw_sums"], lines


def check_numbering(numbers, lines, name):
    """Frames numbered one by one: a missing, repeated or out-of-order number is an error."""
    order = np.flatnonzero(np.diff(numbers) != 1)
    if order.size:
        k = order[0] + 1
        what = ("frames missing or out of order" if numbers[k] > numbers[k - 1] else
                "a frame repeated" if numbers[k] == numbers[k - 1] else "frames out of order")
        raise TactilecalError(f"line {lines[k]} of {name}: frame {numbers[k]} follows frame "
                              f"{numbers[k - 1]} ({what}); expected frame {numbers[k - 1] + 1}: "
                              "frames are numbered one by one")


def _check_lines(f, scan, rows, cols, lines, name, whole):
    """``_`` inside a value, lone CR, row lengths and the size, in the order of main."""
    state, info = scan["state"], scan["info"]
    found = _slot(info, "underscore")
    if found:
        line, offset, length, _ = found
        f.seek(offset)
        raise TactilecalError(f"line {line} of {name}: {shorten(f.read(length)[:60], 60)} has "
                              "'_' inside a "
                              "value; expected numbers or 'B' separated by commas")
    found = _slot(info, "lone_cr")
    if found:
        raise TactilecalError(f"line {found[0]} of {name}: a carriage return (CR) inside the "
                              "line; expected CR only before the line feed (CRLF line ends)")
    widest, n_data = int(state[_STATE["widest"]]), int(state[_STATE["n_data"]])
    row_length = _slot(info, "row_length")
    if row_length and cols > (widest + 1) // 2:
        _raise_row_length(row_length, rows, cols, lines, scan, name)
    if whole:
        check_size(n_data * cols, name)
    if row_length:
        _raise_row_length(row_length, rows, cols, lines, scan, name)


def _raise_row_length(found, rows, cols, lines, scan, name):
    line, _, n_values, k = found
    where = f"line {line} of {name}"
    if len(scan["lines"]):
        frame_line = lines[np.searchsorted(lines, line) - 1]
        where = (f"row {k % rows} of the frame on line {frame_line} of {name} "
                 f"(line {line})")
    raise TactilecalError(f"{where} has {n_values} values; expected {cols} (COLS)")

