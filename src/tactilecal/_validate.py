"""One validation layer for every file the toolkit reads.

Recordings, manifests, load-cell time series and the calibration, equilibration and filter
JSON files all pass their text and values through these helpers before use, so that bad
input gives one kind of message everywhere: the file, line or key, what was found and what
was expected (``docs/developer-guide.md``, "Errors for bad input").

The documented error classes are :class:`ValueError` for a bad value (also a file that is
not text, or not in the expected format) and :class:`TypeError` for a value of the wrong
type (a JSON string where a number belongs); :class:`OSError` comes from the operating system
(missing file, no permission) and the CLI prints it in one line naming the path.
"""

import csv
import math
import numbers
import re

from tactilecal._errors import TactilecalError, TactilecalTypeError

__all__ = ["decode_text", "read_text", "check_line_ends", "TextFault", "without_bom",
           "csv_rows", "csv_lines_rows", "parse_number", "check_number", "check_numbers",
           "check_type", "require_keys", "check_size", "float_type", "shorten", "MAX_VALUES",
           "MAX_FIELD_CHARS", "MAX_NUMBER_CHARS"]

_BOMS = ((b"\xef\xbb\xbf", "utf-8-sig"), (b"\xff\xfe", "utf-16"), (b"\xfe\xff", "utf-16"))


class TextFault:
    """The errors of a file that is no text: each method returns the one to raise.

    One owner of these messages for :func:`read_text`, :func:`decode_text`,
    :func:`check_line_ends` and :class:`tactilecal._textfile.TextFile` (which checks a file
    in pieces, to the same messages).
    """

    @staticmethod
    def not_a_file(path, expected):
        return TactilecalError(f"{path} is not a regular file (a folder, device or pipe); "
                               f"expected {expected}")

    @staticmethod
    def not_in_bom_codec(line, name, codec, expected):
        return TactilecalError(f"line {line} of {name}: bytes that are not {codec.upper()} "
                               f"after its byte-order mark; expected {expected}")

    @staticmethod
    def nul_character(line, name, expected):
        return TactilecalError(f"line {line} of {name}: a NUL character; expected {expected}")

    @staticmethod
    def nul_byte(line, name, expected):
        return TactilecalError(f"line {line} of {name}: a NUL byte (a binary file, or UTF-16 "
                               f"without byte-order mark?); expected {expected} in UTF-8")

    @staticmethod
    def not_text(line, name, byte, expected):
        return TactilecalError(f"line {line} of {name}: byte 0x{byte:02x} is not text (UTF-8 "
                               f"or Windows cp1252); expected {expected}")

    @staticmethod
    def lone_cr(line, name):
        return TactilecalError(f"line {line} of {name}: a carriage return (CR) inside the "
                               "line; expected CR only before the line feed (CRLF line ends)")


def without_bom(text):
    """``text`` without one leading U+FEFF (a second byte-order mark, as Python leaves it)."""
    return text[1:] if text.startswith("\ufeff") else text


MAX_VALUES = 2**31
"""The most values any array read from a text file may hold (checked before allocating)."""

MAX_FIELD_CHARS = 131072
"""Longest cell of a CSV, line of a Tekscan header or string of a JSON file (characters).

The limit of Python's :mod:`csv` module (``csv.field_size_limit()``), applied to every
text field the toolkit reads so that a value of megabytes is refused, not carried along.
"""

MAX_NUMBER_CHARS = 400
"""Longest number a file may write (characters); Python refuses integers over 4300 digits."""


def decode_text(raw, name, *, expected="a text file"):
    r"""Decode the bytes of a text file: UTF-8 (with or without BOM), UTF-16 with BOM, cp1252.

    Windows software (Tekscan's, Excel) writes cp1252 or UTF-16 with a byte-order mark; the
    fallback to cp1252 is strict, so bytes that are no text in any of these raise.

    Parameters
    ----------
    raw : bytes
        The file's bytes.
    name : str
        File name for error messages.
    expected : str, keyword-only
        What the file should be, to complete the message.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        A NUL character (in UTF-16 after its byte-order mark too; without one, NUL bytes
        are a binary file or UTF-16 without BOM), or bytes that decode in none of the
        encodings (cp1252 leaves 0x81, 0x8D, 0x8F, 0x90 and 0x9D undefined); the message
        names the line.

    Examples
    --------
    >>> decode_text("Time (µs),x\n".encode("cp1252"), "lc.csv")
    'Time (µs),x\n'
    >>> decode_text("\ufeffa,b\n".encode("utf-16"), "m.csv")
    'a,b\n'
    """
    for bom, codec in _BOMS:
        if raw.startswith(bom):
            try:
                text = raw.decode(codec)
            except UnicodeDecodeError as exc:  # utf-8-sig counts from after its mark
                at = exc.start + (len(bom) if len(exc.object) < len(raw) else 0)
                raise TextFault.not_in_bom_codec(_line_of(raw, at), name, codec,
                                                 expected) from None
            text = without_bom(text)
            nul = text.find("\x00")
            if nul >= 0:
                raise TextFault.nul_character(text.count("\n", 0, nul) + 1, name, expected)
            return text
    nul = raw.find(b"\x00")
    if nul >= 0:
        raise TextFault.nul_byte(_line_of(raw, nul), name, expected)
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as first:
        try:
            return raw.decode("cp1252")
        except UnicodeDecodeError:
            raise TextFault.not_text(_line_of(raw, first.start), name, raw[first.start],
                                     expected) from None


def read_text(path, *, expected="a text file"):
    """Read and decode a text file with :func:`decode_text` (``OSError`` passes through).

    A folder or a device (``/dev/null``) is a ValueError naming it, not an empty file.
    """
    import os

    if os.path.exists(path) and not os.path.isfile(path):
        raise TextFault.not_a_file(path, expected)
    with open(path, "rb") as f:
        return decode_text(f.read(), str(path), expected=expected)


def check_line_ends(text, name):
    r"""Raise TactilecalError naming the line of a carriage return that ends no line (not CRLF).

    CSV parsers end a line at a lone CR, so a row would silently split in two.

    Examples
    --------
    >>> check_line_ends("a,b\r\n1,2\r\n", "m.csv")
    >>> check_line_ends("a,b\n1\r,2\n", "m.csv")
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: line 2 of m.csv: a carriage return (CR) inside the line; ...
    """
    lone = _LONE_CR.search(text)  # no copy of the text (memory of a read is bounded)
    if lone:
        raise TextFault.lone_cr(text.count("\n", 0, lone.start()) + 1, name)


def csv_rows(text, name):
    r"""Yield ``(line number, cells)`` of a CSV, header first; every row as wide as the header.

    Blank lines are skipped; a row with more or fewer values than the header (an extra comma
    shifts every later column) is a ValueError naming its line. Cells are stripped.

    Examples
    --------
    >>> list(csv_rows("a,b\n1,2\n\n3,4\n", "m.csv"))
    [(1, ['a', 'b']), (2, ['1', '2']), (4, ['3', '4'])]
    >>> list(csv_rows("a,b\n1,,2\n", "m.csv"))
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: line 2 of m.csv has 3 values; expected 2, one per column ['a', 'b']
    """
    check_line_ends(text, name)
    yield from csv_lines_rows(_lines(text), name)  # line by line: no copy of the whole text


def csv_lines_rows(lines, name):
    """:func:`csv_rows` of the lines ``lines`` (each with its line end), line ends unchecked.

    For a file read line by line (:class:`tactilecal._textfile.TextFile`, which checks the
    line ends as it is opened).
    """
    reader = csv.reader(lines)
    width = None
    for cells in _csv_lines(reader, name):
        if not any(cell.strip() for cell in cells):
            continue
        cells = [cell.strip() for cell in cells]
        if width is None:
            width, header = len(cells), cells
        elif len(cells) != width:
            raise TactilecalError(f"line {reader.line_num} of {name} has {len(cells)} values; "
                                  f"expected {width}, one per column {header}")
        yield reader.line_num, cells


_LONE_CR = re.compile("\r(?!\n)")


def _lines(text):
    """Yield the lines of ``text`` with their line ends, one at a time."""
    start, size = 0, len(text)
    while start < size:
        end = text.find("\n", start)
        end = size if end < 0 else end + 1
        yield text[start:end]
        start = end


def _csv_lines(reader, name):
    """Yield the rows of ``reader``; a cell over :data:`MAX_FIELD_CHARS` is an error (its line).

    ``csv.field_size_limit()`` is that limit by default; the check here does not depend on
    what another library set it to.
    """
    while True:
        try:
            cells = next(reader)
        except StopIteration:
            return
        except csv.Error as exc:  # the field limit, or a quote the csv module cannot parse
            raise TactilecalError(f"line {reader.line_num} of {name}: {exc}; expected cells of "
                                  f"at most {MAX_FIELD_CHARS} characters") from None
        if any(len(cell) > MAX_FIELD_CHARS for cell in cells):
            raise TactilecalError(f"line {reader.line_num} of {name}: a cell of more than "
                                  f"{MAX_FIELD_CHARS} characters; expected cells of at most "
                                  f"{MAX_FIELD_CHARS} characters")
        yield cells


_NUMBER = re.compile(r"\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*")


def parse_number(text, where, **limits):
    """Parse the text of a number strictly (no ``1_0``, ``nan``, ``inf``), then check it.

    ``limits`` are those of :func:`check_number`; ``where`` names the file, line and column.

    Examples
    --------
    >>> parse_number(" 2.5", "line 3 of m.csv, mass_kg", minimum=0)
    2.5
    >>> parse_number("1_0", "line 3 of m.csv, mass_kg")
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: line 3 of m.csv, mass_kg is '1_0'; expected a number
    """
    if not isinstance(text, str) or len(text) > MAX_NUMBER_CHARS or not _NUMBER.fullmatch(text):
        raise TactilecalError(f"{where} is {shorten(text)}; expected a number")
    return check_number(float(text), where, **limits)


def check_type(value, types, where, *, expected):
    """Return ``value`` if it is one of ``types`` (``bool`` is no number), else TypeError.

    Examples
    --------
    >>> check_type("x", str, "key 'method' of cal.json", expected="a string")
    'x'
    """
    if isinstance(value, bool) and bool not in _as_tuple(types):
        ok = False
    else:
        ok = isinstance(value, types)
    if not ok:
        raise TactilecalTypeError(f"{where} is {shorten(value)} ({type(value).__name__}); "
                                  f"expected {expected}")
    return value


def check_number(value, where, *, minimum=None, maximum=None, min_inclusive=True,
                 max_inclusive=True, integer=False, allow_none=False):
    """Return ``value`` as a float (or int) after checking type, finiteness and range.

    Parameters
    ----------
    value : object
        The value as read (a JSON number, a NumPy scalar...). Strings are not numbers.
    where : str
        What the value is and where it came from, e.g. ``"key 'params.A' of cal.json"``.
    minimum, maximum : float, optional
        Allowed range.
    min_inclusive, max_inclusive : bool
        Whether the bounds themselves are allowed.
    integer : bool
        Require a whole number (returned as ``int``).
    allow_none : bool
        Return ``None`` for ``None`` (JSON ``null``) instead of raising.

    Raises
    ------
    TypeError
        Not a number.
    ValueError
        NaN, infinite, not whole when ``integer``, or outside the range.

    Examples
    --------
    >>> check_number(2, "b", minimum=0, min_inclusive=False)
    2.0
    >>> check_number(-1.0, "key 'A' of cal.json", minimum=0, min_inclusive=False)
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: key 'A' of cal.json is -1.0; expected a finite number > 0
    """
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TactilecalTypeError(f"{where} is {shorten(value)} ({type(value).__name__}); "
                                  f"expected a {'whole ' if integer else ''}number")
    try:
        number = float(value)
    except OverflowError:  # an integer beyond float64 (JSON allows 400 digits)
        number = math.inf if value > 0 else -math.inf
    expected = _range_text(minimum, maximum, min_inclusive, max_inclusive, integer)
    bad = not math.isfinite(number) or (integer and not number.is_integer())
    if minimum is not None:
        bad |= number < minimum or (number == minimum and not min_inclusive)
    if maximum is not None:
        bad |= number > maximum or (number == maximum and not max_inclusive)
    if bad:
        raise TactilecalError(f"{where} is {shorten(value)}; expected {expected}")
    return int(number) if integer else number


def check_numbers(values, where):
    """Return ``values`` if it is a list of finite numbers (each by :func:`check_number`).

    Examples
    --------
    >>> check_numbers([1, 2.5], "key 'f_hz' of e.json")
    [1, 2.5]
    """
    for value in check_type(values, list, where, expected="a list of numbers"):
        check_number(value, where)
    return values


def require_keys(data, keys, where, *, expected):
    """Raise ValueError naming the missing keys of a JSON object (``expected`` says what)."""
    missing = [k for k in keys if k not in data]
    if missing:
        raise TactilecalError(f"{where} lacks the keys {missing}; expected {expected} with "
                              f"{list(keys)}")


def check_size(count, where, *, limit=MAX_VALUES):
    """Raise ValueError when ``count`` values would be more than ``limit`` (before allocating)."""
    if count > limit:
        raise TactilecalError(f"{where}: {count:.4g} values; expected at most {limit:.4g}")
    return count


def float_type(dtype, where="dtype"):
    """``dtype`` as ``numpy.dtype`` float64 or float32, else a ValueError naming ``where``.

    The types a recording's values may be stored and returned in (``convert(dtype=)``,
    ``apply_filter(dtype=)``); numpy's own spellings are accepted ("float32", ``np.float32``).
    """
    import numpy as np

    try:
        out = np.dtype(dtype)
    except (TypeError, ValueError):
        out = None  # compared with a dtype, None means float64: test it first
    if out is None or out not in (np.dtype(np.float64), np.dtype(np.float32)):
        raise TactilecalError(f"{where}={dtype!r}; expected 'float64' or 'float32'")
    return out


def _line_of(raw, offset):
    return raw.count(b"\n", 0, offset) + 1


def _as_tuple(types):
    return types if isinstance(types, tuple) else (types,)


def shorten(value, width=40):
    """Return ``repr(value)``, cut to ``width`` characters with "..." (for messages).

    Examples
    --------
    >>> shorten("x" * 100, 12)
    "'xxxxxxxx..."
    """
    if isinstance(value, str) and len(value) > width:  # no repr of megabytes
        value = value[:width]
    text = repr(value)
    return text if len(text) <= width else text[:width - 3] + "..."




def _range_text(minimum, maximum, min_inclusive, max_inclusive, integer):
    kind = "a whole number" if integer else "a finite number"
    parts = []
    if minimum is not None:
        parts.append(f"{'>=' if min_inclusive else '>'} {minimum:g}")
    if maximum is not None:
        parts.append(f"{'<=' if max_inclusive else '<'} {maximum:g}")
    return f"{kind} {' and '.join(parts)}".rstrip()
