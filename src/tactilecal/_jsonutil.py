"""JSON helpers shared by every result object: NumPy types to plain Python."""

import json
import math
import os
import re
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from tactilecal._atomic import write_text_atomic
from tactilecal._errors import TactilecalError


def to_jsonable(obj):
    """Convert NumPy scalars/arrays (recursively) to JSON-serialisable Python objects.

    Non-finite floats become ``None`` (JSON has no NaN); paths become strings. Arrays of
    numbers are converted whole (:func:`_array`), not element by element.

    Examples
    --------
    >>> to_jsonable({"a": np.float64(1.5), "b": np.array([1, 2]), "c": float("nan")})
    {'a': 1.5, 'b': [1, 2], 'c': None}
    """
    kind = type(obj)
    if kind in _ATOMS:
        return obj
    if kind is float:
        return obj if math.isfinite(obj) else None
    if isinstance(obj, Mapping):  # also a mapping-like result (ValidationResult)
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [v if type(v) in _ATOMS else to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _array(obj)
    if isinstance(obj, np.generic):
        return to_jsonable(obj.item())
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


_ATOMS = frozenset({str, int, bool, type(None)})


def _array(array):
    """:func:`to_jsonable` of an array: nested lists, non-finite floats as ``None``."""
    if array.dtype.kind in "biu":
        return array.tolist()
    if array.dtype.kind == "f":
        finite = np.isfinite(array)
        if finite.all():
            return array.tolist()
        return np.where(finite, array.astype(object), None).tolist()
    return to_jsonable(array.tolist())


def to_python(obj):
    """Convert NumPy scalars/arrays (recursively) to plain Python numbers and lists.

    Paths become strings. Unlike :func:`to_jsonable`, NaN and infinities stay floats (for
    results used in Python; JSON writing goes through :func:`to_jsonable`).

    Examples
    --------
    >>> to_python({"a": np.float64(1.5), "b": [np.int64(2)], "c": np.float64("nan")})
    {'a': 1.5, 'b': [2], 'c': nan}
    """
    if isinstance(obj, dict):
        return {k: to_python(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [to_python(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    return obj


def dumps(obj, **kwargs):
    """Serialise ``obj`` with :func:`to_jsonable` applied first."""
    kwargs.setdefault("indent", 2)
    return json.dumps(to_jsonable(obj), **kwargs)


MAX_JSON_BYTES = 64 * 2**20
"""Largest JSON file read (bytes): a result of the toolkit is at most a few megabytes."""

MAX_JSON_DEPTH = 32
"""Deepest nesting of arrays and objects in a JSON file (the toolkit writes at most 5)."""

_STRING = re.compile(r'"(?:[^"\\]|\\.)*"', re.DOTALL)
_NUL_ESCAPE = re.compile(r'(?<!\\)(?:\\\\)*\\u0000', re.IGNORECASE)


class _LongNumber(Exception):
    """A number longer than :data:`tactilecal._validate.MAX_NUMBER_CHARS` (its text)."""


def _number(convert):
    from tactilecal._validate import MAX_NUMBER_CHARS

    def parse(text):
        if len(text) > MAX_NUMBER_CHARS:
            raise _LongNumber(text)
        return convert(text)

    return parse


def _check_depth(text, skeleton, path):
    """Raise unless arrays and objects nest at most :data:`MAX_JSON_DEPTH` deep.

    ``skeleton`` is ``text`` without its strings (``_STRING.sub("", text)``).
    """
    depth, deepest = 0, 0
    for bracket in re.finditer(r"[\[\]{}]", skeleton):
        depth += 1 if bracket.group() in "[{" else -1
        if depth > MAX_JSON_DEPTH:
            line = text.count("\n", 0, _nth_bracket(text, bracket.start())) + 1
            raise TactilecalError(f"line {line} of {path}: arrays or objects nested more than "
                                  f"{MAX_JSON_DEPTH} deep; expected {MAX_JSON_DEPTH} levels at "
                                  "most")
        deepest = max(deepest, depth)
    return deepest


_NUMBER_BYTES = bytes(48 if chr(c) in "+-.0123456789Ee" else 32 for c in range(256))


def _short_numbers(skeleton):
    """Return True when no run of number characters outside strings is over the limit.

    Then no number is longer than :data:`tactilecal._validate.MAX_NUMBER_CHARS` and
    :func:`json.loads` may convert them itself (a Python call per number costs more than the
    rest of the parse). Checked a MiB at a time, each piece overlapping the next by the limit.
    """
    from tactilecal._validate import MAX_NUMBER_CHARS

    long_run = b"0" * (MAX_NUMBER_CHARS + 1)
    step = 2**20
    for start in range(0, len(skeleton), step):
        piece = skeleton[start:start + step + MAX_NUMBER_CHARS]
        if long_run in piece.encode("utf-8", "replace").translate(_NUMBER_BYTES):
            return False
    return True


def _nth_bracket(text, offset):
    """Offset in ``text`` of the character at ``offset`` of its string-free skeleton."""
    removed = 0
    for string in _STRING.finditer(text):
        if string.start() - removed > offset:
            break
        removed += string.end() - string.start()
    return offset + removed


def read_json_object(path, expected):
    r"""Read a JSON object from ``path``; a ValueError names the file if it holds anything else.

    ``expected`` completes the message for text that is not JSON (``"a FILTER.json"``). The
    file is bounded before it is parsed: at most :data:`MAX_JSON_BYTES`, nesting at most
    :data:`MAX_JSON_DEPTH` deep, numbers of at most
    :data:`tactilecal._validate.MAX_NUMBER_CHARS` characters, strings of at most
    :data:`tactilecal._validate.MAX_FIELD_CHARS`, no NUL character (``\\u0000``).

    Raises
    ------
    TactilecalError
        Not JSON, not an object, or outside those bounds; the message names the file (and
        the line where it can).
    OSError
        The file cannot be read.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "deep.json"
    >>> _ = path.write_text('{"a": ' + "[" * 50 + "]" * 50 + "}")
    >>> read_json_object(path, "a calibration JSON")
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: line 1 of ...deep.json: arrays or objects nested more than 32 ...
    """
    from tactilecal._validate import MAX_FIELD_CHARS, read_text, shorten

    path = Path(path)
    if path.is_file() and path.stat().st_size > MAX_JSON_BYTES:
        raise TactilecalError(f"{path} has {path.stat().st_size} bytes; expected {expected} of "
                              f"at most {MAX_JSON_BYTES} bytes")
    text = read_text(path, expected=expected)
    nul = _NUL_ESCAPE.search(text) if "\\u0000" in text or "\\U0000" in text else None
    if nul:
        raise TactilecalError(f"line {text.count(chr(10), 0, nul.start()) + 1} of {path}: a NUL "
                              f"character (\\u0000) in a string; expected {expected}")
    long_string = next((m for m in _STRING.finditer(text)
                        if m.end() - m.start() > MAX_FIELD_CHARS + 2), None)
    if long_string:
        raise TactilecalError(f"line {text.count(chr(10), 0, long_string.start()) + 1} of {path}: "
                              f"a string of {long_string.end() - long_string.start() - 2} "
                              f"characters; expected at most {MAX_FIELD_CHARS}")
    skeleton = _STRING.sub("", text)
    _check_depth(text, skeleton, path)
    short = _short_numbers(skeleton)
    del skeleton
    checked = {} if short else {"parse_int": _number(int), "parse_float": _number(float)}
    try:
        data = json.loads(text, **checked)
    except json.JSONDecodeError as exc:
        raise TactilecalError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno}); "
                              f"expected {expected}") from None
    except _LongNumber as exc:
        from tactilecal._validate import MAX_NUMBER_CHARS

        number = str(exc)
        raise TactilecalError(f"line {text.count(chr(10), 0, text.find(number)) + 1} of {path}: "
                              f"a number of {len(number)} characters ({shorten(number, 24)}); "
                              f"expected at most {MAX_NUMBER_CHARS}") from None
    if not isinstance(data, dict):
        raise TactilecalError(f"{path}: JSON {type(data).__name__}; expected an object")
    return data


def write_json(path, obj):
    """Write ``obj`` as JSON to ``path`` atomically."""
    write_text_atomic(path, dumps(obj) + "\n")
