"""Recognise and load the inputs of a report.

Calibration and validation JSON, FILTER.json, blind-test JSON (``tactilecal dynamic
evaluate``) and recordings.
"""

from pathlib import Path

import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import read_json_object
from tactilecal._provenance import file_provenance

__all__ = ["load_input"]

_FILTER_KEYS = ("model", "fs_hz", "band_hz")
_EVALUATION_KEYS = ("rms_before_N", "rms_after_N", "fs_hz")


def _classify_dict(data, where):
    """Return ``(kind, object)`` of a JSON object by its format tag (or an untagged filter's keys).

    The tag is that of :mod:`tactilecal._result` (``tactilecal.load``); a FILTER.json is
    passed on as its dict, a calibration as a CalibrationResult.
    """
    from tactilecal._result import result_class
    from tactilecal.calibration import CalibrationResult, ValidationResult
    from tactilecal.dynamic import CorrectionFilter

    if "format" not in data and all(k in data for k in _FILTER_KEYS):
        return "filter", data  # a filter's dict built in memory, without the tag
    try:
        cls = result_class(data, where)
    except ValueError:
        cls = None
    if cls is CorrectionFilter:
        return "filter", data
    if cls is CalibrationResult:
        return "calibration", CalibrationResult.from_dict(data, source=where)
    if cls is ValidationResult:
        return "validation", ValidationResult.from_dict(data, source=where)
    if "format" not in data and all(k in data for k in _EVALUATION_KEYS):
        return "evaluation", data  # tactilecal dynamic evaluate's JSON (untagged)
    found = f"format {data['format']!r}" if "format" in data else \
        f"keys {sorted(data)[:8]}"
    raise TactilecalError(f"{where}: JSON with {found} is neither a calibration (format "
                          f"{CalibrationResult.format_tag()!r}), a validation (format "
                          f"{ValidationResult.format_tag()!r}), a dynamic filter (format "
                          f"{CorrectionFilter.format_tag()!r}, or keys {list(_FILTER_KEYS)}) nor "
                          f"a blind test (keys {list(_EVALUATION_KEYS)})")


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
    obj : CalibrationResult, ValidationResult, dict (FILTER.json or blind-test content) or
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
    if hasattr(item, "to_dict") and getattr(item, "FORMAT_KIND", None) == "validation":
        return "validation", item, {"input": "ValidationResult in memory"}
    if isinstance(item, dict):
        kind, obj = _classify_dict(item, "dict input")
        return kind, obj, {"input": f"{kind} dict in memory"}
    if hasattr(item, "apply") and hasattr(item, "to_dict") and hasattr(item, "method"):
        return "calibration", item, {"input": "CalibrationResult in memory",
                                     "created": getattr(item, "created", "")}
    if hasattr(item, "to_dict") and hasattr(item, "fs_hz"):
        return "filter", item.to_dict(), {"input": "CorrectionFilter in memory"}
    if not isinstance(item, str | Path):
        raise TactilecalError(f"{what} of type {type(item).__name__}; expected a file path, "
                              "a CalibrationResult, a filter, a dict or a DataArray")
    from tactilecal.io import open_recording, recording_format

    path = Path(item)
    if path.is_dir() and recording_format(path) == "zarr":  # a folder: no single digest
        return "recording", open_recording(path), {"input": str(item),
                                                   "path": str(path.resolve())}
    if not path.is_file():
        raise FileNotFoundError(f"{what} {path} does not exist or is not a file")
    prov = {"input": str(item), **file_provenance(path)}
    if path.suffix.lower() == ".json":
        data = read_json_object(path, "a calibration JSON or a FILTER.json")
        kind, obj = _classify_dict(data, str(path))
        return kind, obj, prov
    return "recording", open_recording(path), prov
