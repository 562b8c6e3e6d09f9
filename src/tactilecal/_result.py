"""The base of every saved result: one JSON format tag, dict/JSON round trip, short reprs.

Every object the toolkit saves (a calibration, an equilibration, the non-working sensels, a
dynamic filter, a validation) is a :class:`SavedResult`. Its JSON carries one tag,

``"format": "tactilecal-<kind>/<version>"`` (e.g. ``"tactilecal-calibration/1"``),

``version`` counts incompatible changes of that kind's keys; a reader refuses a version
newer than its own, and a file without the tag.

:func:`load_result` opens any saved result by its tag (``tactilecal.load`` calls it, importing
the subpackage that defines the file's kind once the file is read).
"""

import hashlib
import html
import re
from pathlib import Path

import numpy as np

from tactilecal._atomic import check_target, write_text_atomic
from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import dumps, read_json_object, to_jsonable
from tactilecal._validate import check_type

__all__ = ["SavedResult", "ShortRepr", "format_tag", "parse_format", "load_result",
           "result_class", "short_text"]

#: kind -> class, filled as the subclasses are defined.
_KINDS = {}
_TAG = re.compile(r"tactilecal-([a-z][a-z0-9-]*)/([0-9]+)")
#: Longest ``repr`` of a result (characters).
MAX_REPR = 1000


def format_tag(kind, version):
    """Return the format tag of a saved kind, e.g. ``"tactilecal-calibration/1"``."""
    return f"tactilecal-{kind}/{int(version)}"


def parse_format(tag, source):
    """Split a format tag into ``(kind, version)``; ValueError naming ``source`` otherwise.

    Examples
    --------
    >>> parse_format("tactilecal-dynamic-filter/1", "f.json")
    ('dynamic-filter', 1)
    """
    match = _TAG.fullmatch(tag) if isinstance(tag, str) else None
    if match is None:
        raise TactilecalError(f"key 'format' of {source} is {tag!r}; expected "
                              "'tactilecal-<kind>/<version>' such as 'tactilecal-calibration/1'")
    return match.group(1), int(match.group(2))


def short_text(value, width=70):
    """Return a one-line text of ``value`` at most ``width`` characters long.

    Floats with 6 significant digits, arrays as their shape, long texts cut with ``...``.

    Examples
    --------
    >>> short_text(np.zeros((44, 44)))
    'array(44, 44)'
    >>> short_text({"A": 0.0035123456, "b": 1.16})
    "{'A': 0.00351235, 'b': 1.16}"
    """
    if isinstance(value, np.ndarray) and value.ndim > 0:
        text = f"array{value.shape}".replace(",)", ")")
    elif isinstance(value, float | np.floating):
        text = f"{float(value):.6g}"
    elif isinstance(value, dict):
        text = "{" + ", ".join(f"{k!r}: {short_text(v, width)}" for k, v in value.items()) + "}"
    elif isinstance(value, list | tuple) and len(value) > 6:
        text = f"[{len(value)} items]"
    else:
        text = repr(value)
    text = " ".join(text.split())
    return text if len(text) <= width else text[:width - 3] + "..."


def _cell(value):
    return value[:120] if isinstance(value, str) else short_text(value, 120)


class ShortRepr:
    """A ``__repr__`` under :data:`MAX_REPR` characters and a ``_repr_html_`` table.

    Subclasses list what to show in :meth:`_repr_fields` as ``(name, value)`` pairs.
    """

    def _repr_fields(self):
        return []

    def __repr__(self):
        fields = ", ".join(f"{name}={short_text(value)}" for name, value in self._repr_fields())
        text = f"<{type(self).__name__} {fields}>"
        return text if len(text) <= MAX_REPR else text[:MAX_REPR - 4] + "...>"

    def _repr_html_(self):
        """Return a small HTML table of the same fields (shown by Jupyter)."""
        rows = "".join(f"<tr><th style='text-align:left'>{html.escape(str(name))}</th>"
                       f"<td style='text-align:left'>{html.escape(_cell(value))}</td>"
                       "</tr>" for name, value in self._repr_fields())
        return (f"<table><caption style='text-align:left'><b>{type(self).__name__}</b>"
                f"</caption>{rows}</table>")


class SavedResult(ShortRepr):
    """Base of every result that is saved as JSON.

    A subclass sets ``FORMAT_KIND`` (and ``FORMAT_VERSION`` when its keys change), and
    implements ``_to_dict`` (the JSON object without the tag), ``_from_dict`` (the reverse,
    after the tag was checked), ``summary`` (text) and ``_repr_fields``.

    ``to_dict`` puts ``"format"`` first; ``from_dict`` accepts a dict with this kind's tag
    (a version up to ``FORMAT_VERSION``).
    """

    FORMAT_KIND = None
    FORMAT_VERSION = 1
    #: What the file is, for messages ("a calibration JSON").
    DESCRIPTION = "a tactilecal result JSON"
    #: Where the result came from (:func:`tactilecal._provenance.provenance`): package
    #: version, input files with SHA-256, sensor; saved as the ``"provenance"`` key.
    provenance = None

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("FORMAT_KIND"):  # the first definition stays (a doctest run
            _KINDS.setdefault(cls.FORMAT_KIND, cls)  # may execute a module a second time)

    # ---------------------------------------------------------------- the tag
    @classmethod
    def format_tag(cls):
        """Return this kind's tag, ``"tactilecal-<kind>/<version>"``."""
        return format_tag(cls.FORMAT_KIND, cls.FORMAT_VERSION)

    @classmethod
    def check_format(cls, data, source):
        """Raise (naming ``source``) unless ``data`` is this kind, by its tag.

        Raises
        ------
        TypeError
            ``data`` is not a dict.
        ValueError
            No tag, another kind's tag, or a newer version.
        """
        check_type(data, dict, source, expected=f"{cls.DESCRIPTION} object")
        if "format" not in data:
            raise TactilecalError(f"{source} has no key 'format'; expected {cls.DESCRIPTION} "
                                  f"('format': {cls.format_tag()!r})")
        kind, version = parse_format(data["format"], source)
        if kind != cls.FORMAT_KIND:
            raise TactilecalError(f"key 'format' of {source} is {data['format']!r}; expected "
                                  f"{cls.format_tag()!r} ({cls.DESCRIPTION})")
        if version > cls.FORMAT_VERSION:
            raise TactilecalError(f"key 'format' of {source} is {data['format']!r}, newer than "
                                  f"this "
                                  f"tactilecal reads; expected version <= {cls.FORMAT_VERSION}")

    # ---------------------------------------------------------------- equality
    def __eq__(self, other):
        """Equal when of one kind and equal in everything saved but the creation time."""
        if type(other) is not type(self):
            return NotImplemented
        return _without_created(self.to_dict()) == _without_created(other.to_dict())

    __hash__ = None  # mutable results

    def fingerprint(self):
        """SHA-256 of the saved JSON without the creation time: equal results, equal prints.

        Examples
        --------
        >>> from tactilecal.calibration import header_calibration
        >>> cal = header_calibration({"sensel_area_mm2": 2.0, "calibration_point_1_load_N": 10.0,
        ...                           "calibration_point_1_raw_sum": 100.0})
        >>> cal.fingerprint() == type(cal).from_dict(cal.to_dict()).fingerprint()
        True
        """
        text = dumps(_without_created(self.to_dict()), indent=None, sort_keys=True)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()

    # ---------------------------------------------------------------- dict and JSON
    def to_dict(self):
        """JSON-ready dictionary: ``"format"`` first, then the kind's keys."""
        body = self._to_dict()
        body.pop("format", None)
        if self.provenance and "provenance" not in body:
            body["provenance"] = self.provenance
        return {"format": self.format_tag(), **body}

    @classmethod
    def from_dict(cls, data, *, source=None):
        """Rebuild from :meth:`to_dict` output (``source`` names it in error messages).

        A value that the kind's own checks let through but that fails to build the result
        (a ``ValueError``, ``TypeError`` or ``OverflowError`` from NumPy, say) is still bad
        input: it is raised as :class:`TactilecalError` naming ``source``.
        """
        source = source or cls.FORMAT_KIND
        cls.check_format(data, source)
        try:
            result = cls._from_dict(data, source)
        except TactilecalError:
            raise
        except (ValueError, TypeError, OverflowError) as exc:  # a value no check foresaw
            raise TactilecalError(f"{source}: {type(exc).__name__}: {exc}; expected "
                                  f"{cls.DESCRIPTION} as tactilecal writes it") from exc
        if data.get("provenance") is not None and not result.provenance:
            result.provenance = check_type(data["provenance"], dict,
                                           f"key 'provenance' of {source}",
                                           expected="an object")
        return result

    def to_json_text(self):
        """Return the JSON text of :meth:`to_dict`."""
        return dumps(self.to_dict())

    def to_json(self, path, *, overwrite=False):
        """Write the JSON atomically to ``path`` (a reader never sees a partial file).

        An existing ``path`` is replaced only with ``overwrite=True``, and only if it is a
        JSON file (never a recording or a table).
        """
        check_target(path, overwrite=overwrite, kind="json")
        write_text_atomic(path, self.to_json_text() + "\n")

    @classmethod
    def from_json(cls, path):
        """Read a JSON file written by :meth:`to_json`.

        Raises
        ------
        ValueError, TypeError
            Not JSON, another kind, or a bad key; the message names the file and the key.
        """
        data = read_json_object(Path(path), cls.DESCRIPTION)
        return cls.from_dict(data, source=str(path))

    # ---------------------------------------------------------------- to implement
    def _to_dict(self):
        raise NotImplementedError

    @classmethod
    def _from_dict(cls, data, source):
        raise NotImplementedError

    def summary(self):
        """Human-readable description (str)."""
        raise NotImplementedError


def _without_created(data):
    """Return the saved dict without its creation time (NaN is null: equal when unknown)."""
    return to_jsonable({k: v for k, v in data.items() if k != "created"})


def result_class(data, source):
    """Return the :class:`SavedResult` subclass a JSON object is, by its tag.

    Raises
    ------
    ValueError
        No tag or an unknown one; the message names ``source``.
    """
    if "format" not in data:
        raise TactilecalError(f"{source} has no key 'format'; expected a tactilecal result JSON "
                              f"('format': 'tactilecal-<kind>/<version>', kind one of "
                              f"{', '.join(sorted(_KINDS))})")
    kind, _ = parse_format(data["format"], source)
    if kind not in _KINDS:
        raise TactilecalError(f"key 'format' of {source} is {data['format']!r}, a kind this "
                              f"tactilecal does not know; expected one of {sorted(_KINDS)}")
    return _KINDS[kind]


def load_result(path, *, register=None):
    """Open a saved result of any registered kind by its format tag.

    Parameters
    ----------
    path : str or os.PathLike
    register : callable, optional
        Called with the file's JSON object before its class is looked up, to import what
        defines its kind.

    Returns
    -------
    SavedResult
        Of the class that registered the file's kind.

    Raises
    ------
    ValueError, TypeError
        Not JSON, not an object, unknown tag, or a bad key; the message names the file and
        the key.
    """
    data = read_json_object(Path(path), "a tactilecal result JSON")
    if register is not None:
        register(data)
    return result_class(data, str(path)).from_dict(data, source=str(path))
