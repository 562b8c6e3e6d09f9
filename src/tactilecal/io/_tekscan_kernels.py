"""Numba kernels over the bytes of a Tekscan export's data block (used by ``_tekscan_read``).

Two passes over the bytes after ``ASCII_DATA @@``, each one loop over the bytes in compiled
code (no Python object per line or value):

* :func:`index_lines` classifies every line (blank, ``Frame N`` line, row of values, ``@@``),
  counts the values of each row by its commas, records each frame line's byte offsets, line
  number and number of rows (the reader parses the frame lines themselves:
  ``_tekscan_frames``), and records the first line of each kind of structural fault. It
  allocates nothing per value.
* :func:`parse_rows` parses the rows of values of a byte range of whole frames into a float64
  array, sums each frame and finds the first raw value that is not a whole number 0..255.

Numbers follow the grammar of pandas' C parser, which the reader used before:
``[ws][+-](digits[.digits] | .digits)[(e|E)[+-]digits][ws]`` with ``ws`` any of space, tab,
VT or FF; ``B`` (no sensel) is NaN. A number with at most 19 significant digits and a decimal
exponent within +-22 is converted exactly (Clinger's fast path: one correctly rounded
multiplication or division of two exactly representable doubles, Clinger 1990, "How to read
floating point numbers accurately", PLDI, sec. 5); any other number is returned to the caller
to be converted by Python's correctly rounded :class:`float`, so every value equals
``float(token)``.
"""

import numpy as np

from tactilecal._numba import njit

__all__ = ["index_lines", "parse_rows", "INFO_SLOTS", "STATE_SLOTS", "new_state"]

_LF, _CR, _COMMA, _SPACE = 10, 13, 44, 32
_B, _F, _AT, _UNDERSCORE = 66, 70, 64, 95
_POW10 = np.array([10.0 ** i for i in range(23)])
_MAX_EXACT = 2**53
# first occurrence of each structural fact: (line number, byte offset of the line, a, b)
INFO_SLOTS = {"other": 0, "first_data": 1, "underscore": 2, "lone_cr": 3, "row_length": 4,
              "stray_f": 5, "terminator": 6, "after": 7, "first_frame": 8, "nul": 9}
# running state carried from one block of lines to the next
STATE_SLOTS = {"line": 0, "stopped": 1, "n_data": 2, "widest": 3, "spaced": 4,
               "n_lines": 5, "end": 6}


def new_state(first_line):
    """Return ``(state, info)`` arrays for :func:`index_lines` before the first block."""
    state = np.zeros(len(STATE_SLOTS), dtype=np.int64)
    state[STATE_SLOTS["line"]] = first_line
    state[STATE_SLOTS["spaced"]] = -1
    info = np.full((len(INFO_SLOTS), 4), -1, dtype=np.int64)
    return state, info


@njit(nogil=True, inline="always")
def _is_space(c):
    """ASCII whitespace that C's ``isspace`` skips inside a value (LF/CR end the line)."""
    return c == 32 or c == 9 or c == 11 or c == 12


@njit(nogil=True, inline="always")
def _is_data_start(c):
    """First byte of a row of values: a digit, ``B``, a sign or a point."""
    return (48 <= c <= 57) or c == 66 or c == 45 or c == 43 or c == 46


@njit(nogil=True, inline="always")
def _skip_space(buf, pos, end):
    """First position from ``pos`` that is not a space, tab, VT or FF (``end - 1`` at most)."""
    while pos < end - 1 and _is_space(buf[pos]):
        pos += 1
    return pos


@njit(nogil=True)
def _number(buf, pos, end):
    """Parse a plain decimal number starting at ``buf[pos]`` (no surrounding whitespace).

    Returns ``(status, value, stop)``: status 0 parsed exactly, 1 valid but to be converted
    by Python (too many digits or a large exponent), 2 not a number; ``stop`` is the first
    byte after the number.
    """
    neg = False
    if pos < end and (buf[pos] == 43 or buf[pos] == 45):
        neg = buf[pos] == 45
        pos += 1
    mantissa, significant, exponent, digits, slow = 0, 0, 0, 0, False
    while pos < end and 48 <= buf[pos] <= 57:
        digits += 1
        if significant < 19:
            mantissa = mantissa * 10 + (buf[pos] - 48)
            significant += mantissa > 0
        else:
            exponent += 1
            slow = True
        pos += 1
    if pos < end and buf[pos] == 46:
        pos += 1
        while pos < end and 48 <= buf[pos] <= 57:
            digits += 1
            if significant < 19:
                mantissa = mantissa * 10 + (buf[pos] - 48)
                significant += mantissa > 0
                exponent -= 1
            else:
                slow = True
            pos += 1
    if digits == 0:
        return 2, 0.0, pos
    if pos < end and (buf[pos] == 101 or buf[pos] == 69):
        pos += 1
        sign = 1
        if pos < end and (buf[pos] == 43 or buf[pos] == 45):
            sign = -1 if buf[pos] == 45 else 1
            pos += 1
        power, n_power = 0, 0
        while pos < end and 48 <= buf[pos] <= 57:
            power = min(power * 10 + (buf[pos] - 48), 100_000)
            n_power += 1
            pos += 1
        if n_power == 0:
            return 2, 0.0, pos
        exponent += sign * power
    if mantissa == 0 and not slow:
        return 0, -0.0 if neg else 0.0, pos
    if slow or mantissa >= _MAX_EXACT or exponent > 22 or exponent < -22:
        return 1, 0.0, pos
    value = float(mantissa)
    value = value * _POW10[exponent] if exponent >= 0 else value / _POW10[-exponent]
    return 0, -value if neg else value, pos


@njit(nogil=True, inline="always")
def _first(info, slot, line, offset, a, b):
    if info[slot, 0] < 0:
        info[slot, 0], info[slot, 1], info[slot, 2], info[slot, 3] = line, offset, a, b


@njit(nogil=True)
def index_lines(buf, n, lf, base, final, cols, state, info):
    """Index the complete lines of ``buf[:n]`` (a block of the data after ``ASCII_DATA @@``).

    Parameters
    ----------
    buf : ndarray of uint8
        The block; lines end with LF (CR LF counts as one line end).
    n : int
        Number of valid bytes.
    lf : ndarray of int64
        Positions of the LF bytes in ``buf[:n]``.
    base : int
        Offset of ``buf[0]`` in the file.
    final : bool
        The block ends at the end of the file (its last line may lack an LF).
    cols : int
        Values expected per row (COLS), for the row-length check.
    state, info : ndarray of int64
        Running state and first occurrences (:func:`new_state`), updated in place.

    Returns
    -------
    used : int
        Bytes of complete lines indexed (the rest starts the next block).
    frames : ndarray of int64, shape (n_frames, 4)
        Per frame line: offset, offset of the line end (before CR LF), line number, rows of
        values after it in this block.
    rows_before : int
        Rows of values before the block's first frame line (they belong to the frame
        before).
    """
    s_line, s_stop, s_ndata, s_widest, s_spaced, s_nlines, s_end = 0, 1, 2, 3, 4, 5, 6
    n_frames = 0
    if state[s_stop] == 0:
        n_frames = 1 if n and buf[0] == _F else 0
        for j in range(lf.size):
            n_frames += lf[j] + 1 < n and buf[lf[j] + 1] == _F
    frames = np.zeros((n_frames, 4), dtype=np.int64)
    k_frame, rows_before = -1, 0
    line = state[s_line]
    pos = np.int64(0)
    for j in range(lf.size + (1 if final else 0)):
        stop = lf[j] if j < lf.size else n
        commas, special = 0, 0
        for i in range(pos, stop):  # branch-free, so the compiler vectorises it
            c = buf[i]
            commas += c == _COMMA
            special += (c == _UNDERSCORE) | (c == _F) | (c == _CR) | (c == 0)
        end = stop - 1 if stop > pos and buf[stop - 1] == _CR else stop
        under, has_f, lone = False, False, -1
        offset = base + pos
        if special:
            for i in range(pos, stop):
                under |= buf[i] == _UNDERSCORE
                has_f |= buf[i] == _F
                if buf[i] == _CR and lone < 0 and i != end:
                    lone = i
                if buf[i] == 0:
                    _first(info, 9, line, offset, i - pos, 0)
        if state[s_stop]:
            for i in range(pos, end):
                if not (_is_space(buf[i]) or buf[i] == _CR or buf[i] == _LF):
                    _first(info, 7, line, offset, end - pos, 0)
                    break
        elif end > pos and buf[pos] == _AT:
            state[s_stop] = 1
            state[s_end] = offset
            lo, hi = pos, end
            while lo < hi and (_is_space(buf[lo]) or buf[lo] == _CR):
                lo += 1
            while hi > lo and (_is_space(buf[hi - 1]) or buf[hi - 1] == _CR):
                hi -= 1
            exact = hi - lo == 2 and buf[lo] == _AT and buf[lo + 1] == _AT
            _first(info, 6, line, offset, end - pos, 1 if exact else 0)
        else:
            if lone >= 0:
                _first(info, 3, line, offset, lone - pos, 0)
            if end == pos:
                pass
            elif buf[pos] == _F:
                k_frame += 1
                frames[k_frame, 0], frames[k_frame, 1] = offset, base + end
                frames[k_frame, 2] = line
                _first(info, 8, line, offset, 0, 0)
            elif _is_data_start(buf[_skip_space(buf, pos, end)]):
                if state[s_spaced] < 0:
                    state[s_spaced] = 0
                    for i in range(pos, end - 1):
                        if buf[i] == _COMMA and buf[i + 1] == _SPACE:
                            state[s_spaced] = 1
                            break
                    _first(info, 1, line, offset, end - pos, 0)
                if k_frame >= 0:
                    frames[k_frame, 3] += 1
                else:
                    rows_before += 1
                if under:
                    _first(info, 2, line, offset, end - pos, 0)
                if has_f:
                    _first(info, 5, line, offset, end - pos, 0)
                if commas + 1 != cols:
                    _first(info, 4, line, offset, commas + 1, state[s_ndata])
                state[s_widest] = max(state[s_widest], end - pos)
                state[s_ndata] += 1
            else:
                _first(info, 0, line, offset, end - pos, 0)
        line += 1
        state[s_nlines] += 1
        pos = stop + 1
    state[s_line] = line
    return min(pos, n), frames[:k_frame + 1], rows_before


@njit(nogil=True)
def parse_rows(buf, pos, end, out, k, cols, per_frame, spaced, raw, sums, bad, slow, n_slow):
    """Parse the rows of values in ``buf[pos:end]`` into ``out[k:]`` (flat, row-major).

    ``buf[pos:end]`` holds whole frames as indexed by :func:`index_lines`: blank lines and
    ``F`` (frame) lines are skipped, every other line is a row of ``cols`` values.

    Parameters
    ----------
    out : ndarray of float64, 1-D
        Values of the block's frames; ``k`` is the next index to fill.
    per_frame : int
        ROWS x COLS: ``sums[k // per_frame]`` accumulates the frame's finite values.
    spaced : bool
        Spaces after a comma are skipped (files written with ", ").
    raw : bool
        Check that every value is a whole number 0..255; ``bad`` gets ``(k, line offset)``
        of the first that is not.
    slow : ndarray of int64, shape (capacity, 3)
        ``(k, token start, token end)`` of valid numbers left for Python to convert (NaN in
        ``out`` and not in ``sums`` until then); ``n_slow`` of them are filled.

    Returns
    -------
    status : int
        0 done; 1 a value that is not a number at ``position`` (``k`` its index); 2 ``slow``
        is full (call again from ``position``, ``k``); 3 a row that does not hold ``cols``
        values, or more rows than ``out`` holds (the file changed since it was indexed).
    position, k, n_slow : int
    """
    capacity = slow.shape[0]
    while pos < end:
        c = buf[pos]
        if c == _LF:
            pos += 1
            continue
        if c == _CR and pos + 1 < end and buf[pos + 1] == _LF:
            pos += 2
            continue
        if c == _F:
            while pos < end and buf[pos] != _LF:
                pos += 1
            pos += 1
            continue
        if n_slow + cols > capacity:
            return 2, pos, k, n_slow
        if k + cols > out.size:
            return 3, pos, k, n_slow
        line_start = pos
        row_sum = 0.0
        for j in range(cols):
            if spaced:
                while pos < end and buf[pos] == _SPACE:
                    pos += 1
            token = pos
            status = 3
            if pos < end and 48 <= buf[pos] <= 57:  # fast path: a whole number
                whole, stop = 0, pos
                while stop < end and 48 <= buf[stop] <= 57 and stop - pos < 15:
                    whole = whole * 10 + (buf[stop] - 48)
                    stop += 1
                if stop < end and (buf[stop] == _COMMA or buf[stop] == _LF or buf[stop] == _CR):
                    status, value, pos = 0, float(whole), stop
            if status == 3:  # spaces around a number or a B are read alike
                while pos < end and _is_space(buf[pos]):
                    pos += 1
                if pos < end and buf[pos] == _B:
                    pos += 1
                    value = np.nan
                    status = 0
                else:
                    status, value, pos = _number(buf, pos, end)
                while pos < end and _is_space(buf[pos]):
                    pos += 1
            at_end = pos >= end or buf[pos] == _LF or (
                buf[pos] == _CR and pos + 1 < end and buf[pos + 1] == _LF)
            if not (at_end or buf[pos] == _COMMA):
                return 1, token, k, n_slow
            if status == 2:
                return 1, token, k, n_slow
            if at_end != (j == cols - 1):
                return 3, line_start, k, n_slow
            if status == 1:
                slow[n_slow, 0], slow[n_slow, 1], slow[n_slow, 2] = k, token, pos
                n_slow += 1
                value = np.nan
            elif value == value:
                row_sum += value
                if raw and bad[0] < 0 and (value < 0 or value > 255 or value != np.floor(value)):
                    bad[0], bad[1] = k, line_start
            out[k] = value
            k += 1
            if at_end and pos < end and buf[pos] == _CR:
                pos += 1
            pos += 1  # the comma or the LF
        sums[(k - 1) // per_frame] += row_sum
    return 0, pos, k, n_slow
