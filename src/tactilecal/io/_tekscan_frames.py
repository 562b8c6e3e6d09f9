"""Frame lines of a Tekscan export: ``Frame N[, time[, ..., Raw Sum=,,S]]``.

The one owner of the frame line's format, for both readers. :func:`parse_frame_line` reads
one line (decoded text), or raises the message that names it. :func:`plain_frame_lines`
reads all the frame lines of a block of bytes at once, by the same patterns over the lines
joined, and returns None when any of them is not plain (not ASCII, a CR, a number past 18
digits, a time that is not a plain finite number...): each is then read by
:func:`parse_frame_line`, which accepts it or says why not.
"""

import math
import re

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._validate import MAX_NUMBER_CHARS, parse_number, shorten

__all__ = ["frame_line_text", "parse_frame_line", "plain_frame_lines", "plain_frame_number"]

_FRAME = r"Frame[ \t]+(\d+)[ \t]*(?:$|,[ \t]*([^,]*?)[ \t]*(?:,|$))"
_RAW_SUM = r"Raw Sum[ \t]*=[ \t,]*([-+]?\d+(?:\.\d*)?)[ \t]*(?:,|$)"
_TIME = rb"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_FRAME_TEXT, _RAW_SUM_TEXT = re.compile(_FRAME), re.compile(_RAW_SUM)
_FRAME_BYTES, _RAW_SUM_BYTES = re.compile(_FRAME.encode()), re.compile(_RAW_SUM.encode())
# the same, over lines joined by LF: one match per line, at its start
_FRAMES = re.compile(b"^" + _FRAME.replace("[^,]", "[^,\n]").encode(), re.M)
_RAW_SUMS = re.compile(b"^[^\n]*?" + _RAW_SUM.encode(), re.M)
_TIMES = re.compile(b"(?:" + _TIME + b"\n)*")
_MAX_NUMBER_DIGITS = 18  # a frame number below 10**18 (< 2**63): plain


def frame_line_text(raw, line, name):
    """Decode a frame line: UTF-8, else strict cp1252 (undefined bytes are an error)."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        try:
            return raw.decode("cp1252")
        except UnicodeDecodeError as exc:
            raise TactilecalError(f"line {line} of {name}: byte 0x{raw[exc.start]:02x} is not "
                                  "text (UTF-8 or Windows cp1252); expected a 'Frame N' line"
                                  ) from None


def parse_frame_line(text, line, name):
    """Return ``(number, time in s or NaN, Raw Sum or NaN)`` of a frame line, or raise.

    A frame line is ``Frame N`` alone or followed by ``, <time in s>, ...``; a time that
    is not a finite number (``nan``, ``-``) and a ``Raw Sum`` that is not a number are
    errors, never read as absent.
    """
    match = _FRAME_TEXT.match(text)
    if match is None:
        raise TactilecalError(f"line {line} of {name}: {shorten(text, 60)}; expected 'Frame N' "
                              "optionally followed by ', <time in s>, ...'")
    digits = match.group(1).lstrip("0") or "0"
    if len(digits) > 19 or int(digits) >= 2**63:
        shown = match.group(1) if len(match.group(1)) <= 30 else match.group(1)[:27] + "..."
        raise TactilecalError(f"line {line} of {name}: frame number {shown}; "
                              "expected at most 2**63 - 1")
    number = int(digits)
    time_s = raw_sum = np.nan
    if match.group(2):
        time_s = parse_number(match.group(2), f"line {line} of {name}: the frame time")
    if "Raw Sum" in text:
        found = _RAW_SUM_TEXT.search(text)
        if found is None:
            after = text[text.index("Raw Sum") + 7:].lstrip(" \t=,")
            raise TactilecalError(f"line {line} of {name}: Raw Sum is {shorten(after)}; "
                                  "expected the sum of the frame's readings (a number)")
        raw_sum = float(found.group(1))
    return number, time_s, raw_sum


def plain_frame_lines(block, starts, ends):
    """``(numbers, times, raw sums)`` of the frame lines ``block[starts:ends]``, or None.

    ``block`` is bytes (a memoryview); ``ends`` are before any CR LF. The lines are joined
    and parsed by one regular expression each (the per-line patterns anchored at each line's
    start); lines with and without a ``Raw Sum`` in one block are parsed one by one. None
    when any line is not plain: :func:`parse_frame_line` then reads each.
    """
    text = b"\n".join([block[start:end] for start, end in zip(starts.tolist(), ends.tolist(),
                                                             strict=True)])
    if not text.isascii() or b"\r" in text or b"\x00" in text:
        return None
    heads = _FRAMES.findall(text)
    if len(heads) != len(starts) or any(len(number) > _MAX_NUMBER_DIGITS
                                        for number, _ in heads):
        return None
    has_sum = text.count(b"Raw Sum")
    sums = _RAW_SUMS.findall(text) if has_sum else []
    if has_sum and (has_sum != len(starts) or len(sums) != len(starts)):
        return _one_by_one(block, starts, ends)
    given = [time for _, time in heads if time]
    if any(len(time) > MAX_NUMBER_CHARS for time in given) or not _TIMES.fullmatch(
            b"\n".join(given) + b"\n" if given else b""):
        return None
    times = np.array([float(time) if time else math.nan for _, time in heads])
    raw_sums = np.array([float(raw) for raw in sums]) if sums else np.full(len(heads), np.nan)
    if np.isinf(times).any() or np.isinf(raw_sums).any():
        return None
    return np.array([int(number) for number, _ in heads], dtype=np.int64), times, raw_sums


def plain_frame_number(line):
    """Return the number of the frame line ``line`` (bytes, no line end) if plain, else None."""
    match = _FRAME_BYTES.match(line)
    if match is None or len(match.group(1)) > _MAX_NUMBER_DIGITS:
        return None
    return int(match.group(1))


def _one_by_one(block, starts, ends):
    """:func:`plain_frame_lines`, line by line (ASCII lines without CR: checked there)."""
    numbers, times, raw_sums = [], [], []
    for start, end in zip(starts.tolist(), ends.tolist(), strict=True):
        text = bytes(block[start:end])
        match = _FRAME_BYTES.match(text)
        if match is None or len(match.group(1)) > _MAX_NUMBER_DIGITS:
            return None
        numbers.append(int(match.group(1)))
        raw_sum = _RAW_SUM_BYTES.search(text) if b"Raw Sum" in text else None
        if b"Raw Sum" in text and raw_sum is None:
            return None  # parse_frame_line's "Raw Sum is ..."
        time = _number(match.group(2)) if match.group(2) else math.nan
        total = _number(raw_sum.group(1)) if raw_sum is not None else math.nan
        if time is None or total is None:
            return None
        times.append(time)
        raw_sums.append(total)
    return (np.array(numbers, dtype=np.int64), np.array(times, dtype=np.float64),
            np.array(raw_sums, dtype=np.float64))


def _number(text):
    """Return the finite number ``text`` (no ``nan``, ``inf``, ``1_0``), else None."""
    if len(text) > MAX_NUMBER_CHARS or not re.fullmatch(_TIME, text):
        return None
    value = float(text)
    return value if math.isfinite(value) else None
