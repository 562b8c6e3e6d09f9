"""Header and frame index of a Tekscan ASCII export, in Python and NumPy only (no numba).

:func:`read_header` reads and checks everything up to the ``ASCII_DATA @@`` line;
:class:`Index` is what both readers of the data (the numba kernels of ``_tekscan_index`` and
the NumPy parser of ``_tekscan_numpy``) find about the frames. Neither imports numba, so the
NumPy parser can read a small export without numba's start-up.
"""

import os
import re
from dataclasses import dataclass, field

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._validate import MAX_FIELD_CHARS, check_line_ends, decode_text
from tactilecal.io._header import header_attrs, integer, parse_header_lines

__all__ = ["Header", "Index", "read_header", "line_text", "max_line_bytes",
           "check_line_lengths"]

_MARKER = re.compile(rb"^[ \t]*ASCII_DATA[ \t]*@@[ \t]*\r?$", re.MULTILINE)
_HEADER_STEP = 2**20
_LINE_STEP = 2**20  # bytes read at a time by check_line_lengths


@dataclass(frozen=True)
class Header:
    """The parsed header of an export and where its data begin."""

    header: dict
    attrs: dict
    rows: int
    cols: int
    first_line: int
    body: int
    """Byte offset of the first line after ``ASCII_DATA @@``."""


@dataclass
class Index:
    """Where the frames of an export are, and what its header says.

    ``starts[k]`` is the byte offset of frame ``k``'s first line and ``starts[-1]`` that of the
    ``@@`` terminator, so frame ``k`` is the byte range ``starts[k]:starts[k + 1]``.
    """

    name: str
    rows: int
    cols: int
    header: dict
    attrs: dict
    first_line: int
    numbers: np.ndarray
    times: np.ndarray
    raw_sums: np.ndarray
    lines: np.ndarray
    starts: np.ndarray
    spaced: bool
    stat: tuple = field(default=())
    stray_f: tuple | None = None

    @property
    def raw(self):
        """True when the values must be raw readings (``UNITS raw``, or no UNITS)."""
        return self.attrs.get("units") in (None, "raw")


MAX_HEADER_BYTES = 16 * 2**20
"""Most bytes before ``ASCII_DATA @@`` (real headers are about 1 KB)."""

UTF8_BOM = b"\xef\xbb\xbf"


def read_header(f, name):
    """Read and check the header of the open export ``f`` (binary) up to ``ASCII_DATA @@``.

    The header is decoded by :func:`tactilecal._validate.decode_text` (UTF-8 with or without
    byte-order mark, else strict cp1252; a NUL byte is an error); a carriage return inside a
    line is an error, not a line break.

    Raises
    ------
    ValueError
        Empty file, no ``ASCII_DATA @@`` line, a header over :data:`MAX_HEADER_BYTES` or a
        header line over :data:`tactilecal._validate.MAX_FIELD_CHARS`, no ``ROWS``/``COLS``
        line, or a header value :func:`~tactilecal.io._header.header_attrs` refuses;
        messages name the file and line.
    """
    raw, marker = _read_header(f, name)
    lines = _header_lines(raw[:marker.start()], name)
    header = parse_header_lines(lines, name)
    header_lines = raw.count(b"\n", 0, marker.start()) + 1
    for key in ("ROWS", "COLS"):
        if key not in header:
            raise TactilecalError(f"{name} has no {key} line in its header (lines 1-"
                                  f"{header_lines}); expected "
                                  f"'{key} <number of sensel {key.lower()}>'")
    rows = integer(header, "ROWS", name, minimum=1)
    cols = integer(header, "COLS", name, minimum=1)
    attrs = header_attrs(header, name)
    return Header(header=header, attrs=attrs, rows=rows, cols=cols,
                  first_line=raw.count(b"\n", 0, marker.end()) + 1, body=marker.end())


def _header_lines(header_bytes, name):
    """Return the header's lines, decoded; NUL, undefined bytes, a lone CR, a huge line refused."""
    text = decode_text(header_bytes.removeprefix(UTF8_BOM), name,
                       expected="a Tekscan ASCII export")
    check_line_ends(text, name)
    lines = text.replace("\r\n", "\n").split("\n")
    long = next((k for k, line in enumerate(lines) if len(line) > MAX_FIELD_CHARS), None)
    if long is not None:
        raise TactilecalError(f"line {long + 1} of {name}: a header line of {len(lines[long])} "
                              f"characters; expected at most {MAX_FIELD_CHARS}")
    return lines


def _read_header(f, name):
    """Read up to the ``ASCII_DATA @@`` line; return the bytes read and the marker match."""
    raw = b""
    while True:
        chunk = f.read(_HEADER_STEP if len(raw) < 64 * _HEADER_STEP else len(raw))
        raw += chunk
        # the marker line may straddle the previous read: search from the last line start
        marker = _MARKER.search(raw, max(0, raw.rfind(b"\n", 0, len(raw) - len(chunk))))
        if marker is not None and (marker.end() < len(raw) or not chunk):
            if marker.start() > MAX_HEADER_BYTES:
                break
            return raw, marker
        if not chunk or len(raw) > MAX_HEADER_BYTES:
            break
    if not raw or raw.isspace():
        raise TactilecalError(f"{name} is empty; expected a Tekscan ASCII export "
                              "('KEY value' header, 'ASCII_DATA @@', frames, '@@')")
    if len(raw) > MAX_HEADER_BYTES:
        raise TactilecalError(f"{name} has no 'ASCII_DATA @@' line in its first "
                              f"{MAX_HEADER_BYTES} bytes; expected a Tekscan ASCII export (a "
                              "header of a few KB)")
    n_lines = len(raw.splitlines())
    raise TactilecalError(f"{name} has no 'ASCII_DATA @@' line (after {n_lines} lines); "
                          "expected a Tekscan ASCII export")


def line_text(f, offset, length):
    """Return the first 60 characters of the line at byte ``offset`` (``length`` bytes)."""
    f.seek(offset)
    return f.read(length).decode("utf-8", errors="replace")[:60]


def max_line_bytes(cols):
    """Longest line a file of ``cols`` values a row may have: 32 bytes a value, 32 MiB at least.

    A longer line is an error before it is held in memory whole (memory of any read stays
    within 3x its array + 100 MB, whatever the file).
    """
    return max(2**25, 32 * cols)


def check_line_lengths(f, head, name):
    """Refuse a line after the header longer than :func:`max_line_bytes`; hold 1 MiB at most.

    Runs before either reader of the data, so that a file that is no export (one huge line,
    a binary file) is refused before numba is imported or a line is held whole. A line of at
    most ``limit`` bytes ends within ``limit + 1`` bytes of its start: the last line end in
    that stretch starts the next one, found by reading back from the stretch's end in pieces
    of 1 MiB. An ordinary file is read here at one piece every ``limit`` bytes; a line
    without end is read through once, a piece at a time, and its line number counted (as
    :func:`~tactilecal.io._tekscan_kernels.index_lines` numbers lines) only then.

    Raises
    ------
    ValueError
        ``line N of <file>: more than <limit> bytes without a line end; ...``.
    """
    limit = max_line_bytes(head.cols)
    size = os.fstat(f.fileno()).st_size
    start = head.body
    while size - start > limit:
        end = _last_line_end(f, start, start + limit + 1)
        if end < 0:
            line = head.first_line + _count_line_ends(f, head.body, start)
            raise TactilecalError(f"line {line} of {name}: more than {limit} bytes without a "
                                  f"line end; expected rows of {head.cols} values (COLS)")
        start = end + 1
    f.seek(head.body)


def _last_line_end(f, start, stop):
    """Return the offset of the last LF in the bytes ``start:stop`` of ``f``, or -1."""
    while stop > start:
        begin = max(start, stop - _LINE_STEP)
        f.seek(begin)
        found = f.read(stop - begin).rfind(b"\n")
        if found >= 0:
            return begin + found
        stop = begin
    return -1


def _count_line_ends(f, start, stop):
    """Count the LF bytes in the bytes ``start:stop`` of ``f``."""
    f.seek(start)
    count = 0
    while start < stop:
        piece = f.read(min(_LINE_STEP, stop - start))
        if not piece:
            break
        count += piece.count(b"\n")
        start += len(piece)
    return count
