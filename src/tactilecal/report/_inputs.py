"""Recognise and load the inputs of a report.

Calibration and validation JSON, FILTER.json, evaluation JSON (``tactilecal dynamic
evaluate``), all read by their format tag as :func:`tactilecal.load` reads them, and
recordings.
"""

from pathlib import Path

import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import read_json_object
from tactilecal._provenance import file_provenance

__all__ = ["load_input"]

#: Saved kinds a report shows, by their class's ``FORMAT_KIND``.
_KINDS = {"calibration": "calibration", "validation": "validation",
          "dynamic-filter": "filter", "dynamic-evaluation": "evaluation"}


def _classify_dict(data, where):
    """Return ``(kind, object)`` of a saved result's JSON object, by its format tag.

    The class comes from the tag, as :func:`tactilecal.load` finds it; only the kinds a
    report shows are accepted.
    """
    import tactilecal.calibration  # noqa: F401  (their saved kinds register on import)
    import tactilecal.dynamic  # noqa: F401
    from tactilecal._result import result_class

    cls = result_class(data, where)
    if cls.FORMAT_KIND not in _KINDS:
        raise TactilecalError(f"{where} is {cls.DESCRIPTION} (format {data['format']!r}); "
                              "expected a calibration, a validation, a dynamic filter or an "
                              "evaluation of one")
    return _KINDS[cls.FORMAT_KIND], cls.from_dict(data, source=where)


def load_input(item, *, what="report input"):
    """Return ``(kind, obj, provenance)`` for one report input.

    Parameters
    ----------
    item : str, os.PathLike, CalibrationResult, CorrectionFilter, dict or xarray.DataArray
        A file (``.json``: calibration or FILTER.json; anything else: a recording read by
        :func:`tactilecal.io.open_recording`) or an object in memory.
    what : str, keyword-only
        What the input is to the caller, for messages (a command names its argument).

    Returns
    -------
    kind : {"calibration", "validation", "filter", "evaluation", "recording"}
    obj : CalibrationResult, ValidationResult, CorrectionFilter, Evaluation or
        xarray.DataArray
    provenance : dict
        For a file, :func:`file_provenance` plus ``input``; for an object, what it is.

    Raises
    ------
    ValueError
        For a JSON that is neither kind, a file that is no recording, or an object of an
        unknown type.
    FileNotFoundError
        For a missing file.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.zeros((1, 2, 2)), dims=("frame", "row", "col"),
    ...                    attrs={"units": "kPa"})
    >>> kind, obj, provenance = load_input(rec)
    >>> kind, provenance["input"]
    ('recording', 'DataArray in memory')
    """
    if isinstance(item, xr.DataArray):
        return "recording", item, {"input": "DataArray in memory",
                                   "source": str(item.attrs.get("source", ""))}
    kind = _KINDS.get(getattr(item, "FORMAT_KIND", None))
    if kind is not None and hasattr(item, "to_dict"):  # a saved kind in memory
        return kind, item, {"input": f"{type(item).__name__} in memory",
                            **({"created": item.created} if hasattr(item, "created") else {})}
    if isinstance(item, dict):
        kind, obj = _classify_dict(item, "dict input")
        return kind, obj, {"input": f"{kind} dict in memory"}
    if not isinstance(item, str | Path):
        raise TactilecalError(f"{what} of type {type(item).__name__}; expected a file path, "
                              "a CalibrationResult, a ValidationResult, a CorrectionFilter, "
                              "an Evaluation, a dict or a DataArray")
    from tactilecal.io import open_recording, recording_format

    path = Path(item)
    if path.is_dir() and recording_format(path) == "zarr":  # a folder: no single digest
        return "recording", open_recording(path), {"input": str(item),
                                                   "path": str(path.resolve())}
    if not path.is_file():
        raise FileNotFoundError(f"{what} {path} does not exist or is not a file")
    prov = {"input": str(item), **file_provenance(path)}
    if path.suffix.lower() == ".json":
        data = read_json_object(path, "a tactilecal result JSON")
        kind, obj = _classify_dict(data, str(path))
        return kind, obj, prov
    return "recording", open_recording(path), prov
