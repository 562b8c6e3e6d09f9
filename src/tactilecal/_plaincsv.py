"""The header of a CSV whose rows pass :func:`~tactilecal._validate.csv_lines_rows`, found fast.

:meth:`TextFile.rows() <tactilecal._textfile.TextFile.rows>` checks a CSV line by line in
Python: every row as wide as the header, no cell over the field limit. Most load-cell files
are plain, and for their bytes the outcome of that check follows from a few NumPy passes over
blocks of whole lines. :func:`checked_header` makes those passes where it can prove the
outcome and runs the line-by-line check itself where it cannot, so that every accepted file,
every error and every message stays that of the line-by-line check.

Why the passes prove it. After the header, take a text in UTF-8 or cp1252 (so its ASCII
bytes are its ASCII characters; :class:`~tactilecal._textfile.TextFile` has refused NUL and a
carriage return (CR) that ends no line) whose bytes are all printable ASCII but the double
quote, space, tab, CR or line feed (LF). For such a line :mod:`csv` (excel dialect) ends the
line at its CR or LF and cuts cells at commas only (no quote character); :meth:`str.strip`
removes only spaces and tabs, so the row is skipped exactly when every byte of its line is a
space, tab, comma, CR or LF; any other row has one cell more than it has commas; and no cell
is longer than its line. So every row passes when each line that is not skipped has as many
commas as the header has cells less one, and no line reaches the field limit.
"""

import collections
import csv

import numpy as np

from tactilecal import _textfile
from tactilecal._validate import MAX_FIELD_CHARS, csv_lines_rows

__all__ = ["checked_header"]

BLOCK_BYTES = 2**19
"""Bytes checked at a time at most (and a piece at most): NumPy's temporaries are 3x that."""

#: Codecs in which every ASCII byte is that ASCII character and no other byte is LF.
_ASCII_CODECS = ("utf-8", "utf-8-sig", "cp1252")
#: Bytes the proof covers: printable ASCII without the quote, space, tab, CR, LF.
_PLAIN = bytes(range(0x21, 0x7F)).replace(b'"', b"") + b" \t\r\n"
_LF, _COMMA, _SPACE = ord("\n"), ord(","), ord(" ")
#: Bytes of _PLAIN that a row keeps after stripping: not space, tab, comma, CR or LF.
_CONTENT = np.zeros(256, dtype=bool)
_CONTENT[0x21:0x7F] = True
_CONTENT[_COMMA] = False


def checked_header(text):
    """Return the header's cells of a CSV after every row passed the line-by-line check.

    Parameters
    ----------
    text : tactilecal._textfile.TextFile

    Returns
    -------
    list of str or None
        The first row's cells, as :meth:`~tactilecal._textfile.TextFile.rows` gives them;
        ``None`` when the file has no row.

    Raises
    ------
    ValueError
        As :meth:`~tactilecal._textfile.TextFile.rows` raises (a row of another width, a
        cell over the field limit), with its message: raised by it.
    """
    lines = text.lines()
    try:
        first = next(csv_lines_rows(lines, text.name), None)
    finally:
        lines.close()
    if first is None:
        return None
    line, header = first
    if not _plain_after(text, line, len(header)):
        collections.deque(text.rows(), maxlen=0)  # the line-by-line check: raises, or passes
    return header


def _plain_after(text, header_lines, width):
    """Whether the lines after the first ``header_lines`` provably pass (module docstring)."""
    if text.codec not in _ASCII_CODECS:
        return False
    limit = min(MAX_FIELD_CHARS, csv.field_size_limit())
    with open(text.path, "rb") as f:
        for _ in range(header_lines):
            f.readline()
        return all(_plain_block(block, width, limit) for block in _blocks(f, limit))


def _blocks(f, limit):
    """Yield the rest of ``f`` in blocks of whole lines, each ending with LF.

    A last line without LF gets one (:mod:`csv` reads it the same). A line still without
    LF after ``limit`` bytes is yielded as it is, and nothing after it: it is too long.
    """
    rest, size = b"", min(_textfile.PIECE_BYTES, BLOCK_BYTES)
    while piece := f.read(size):
        cut = piece.rfind(b"\n") + 1
        if cut:
            yield rest + piece[:cut]
            rest = piece[cut:]
        else:
            rest += piece
        if len(rest) >= limit:
            yield rest
            return
    if rest:
        yield rest + b"\n"


def _plain_block(block, width, limit):
    """Whether every line of ``block`` (whole lines, each ending with LF) provably passes."""
    if block.translate(None, _PLAIN) or not block.endswith(b"\n"):
        return False
    data = np.frombuffer(block, dtype=np.uint8)
    is_cut = data == _LF
    is_cut |= data == _COMMA
    cuts = np.flatnonzero(is_cut)  # every comma and LF, in order
    lf = np.flatnonzero(data[cuts] == _LF)  # which of them end lines
    commas = np.diff(lf, prepend=-1) - 1
    ends = cuts[lf]
    starts = np.concatenate(([0], ends[:-1] + 1))
    if (ends - starts).max() >= limit:  # a line of `limit` bytes or more before its LF
        return False
    kept = _CONTENT[data[starts]]  # a line that starts with content is kept
    if not kept.all():
        kept = np.logical_or.reduceat((data > _SPACE) & (data != _COMMA), starts)
    return bool((commas[kept] == width - 1).all())
