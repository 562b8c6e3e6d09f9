"""JSON helpers shared by every result object: NumPy types to plain Python."""

import json
import math
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from tactilecal._atomic import write_text_atomic
from tactilecal._errors import TactilecalError


def to_jsonable(obj):
    """Convert NumPy scalars/arrays (recursively) to JSON-serialisable Python objects.

    Non-finite floats become ``None`` (JSON has no NaN); paths become strings.

    Examples
    --------
    >>> to_jsonable({"a": np.float64(1.5), "b": np.array([1, 2]), "c": float("nan")})
    {'a': 1.5, 'b': [1, 2], 'c': None}
    """
    if isinstance(obj, Mapping):  # also a mapping-like result (ValidationResult)
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        return to_jsonable(obj.item())
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


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


def read_json_object(path, expected):
    """Read a JSON object from ``path``; a ValueError names the file if it holds anything else.

    ``expected`` completes the message for text that is not JSON (``"a FILTER.json"``).
    """
    from tactilecal._validate import read_text

    try:
        data = json.loads(read_text(Path(path), expected=expected))
    except json.JSONDecodeError as exc:
        raise TactilecalError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno}); "
                              f"expected {expected}") from None
    if not isinstance(data, dict):
        raise TactilecalError(f"{path}: JSON {type(data).__name__}; expected an object")
    return data


def write_json(path, obj):
    """Write ``obj`` as JSON to ``path`` atomically."""
    write_text_atomic(path, dumps(obj) + "\n")
