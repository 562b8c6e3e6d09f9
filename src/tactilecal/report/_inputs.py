"""Recognise and load the inputs of a report: calibration JSON, FILTER.json, recordings."""

import hashlib
from datetime import UTC, datetime
from pathlib import Path

import xarray as xr

from tactilecal._jsonutil import read_json_object

__all__ = ["load_input", "file_provenance"]

_FILTER_KEYS = ("model", "fs_hz", "band_hz")


def file_provenance(path):
    """Absolute path, size, modification time (UTC) and SHA-256 of a file."""
    path = Path(path).resolve()
    digest = hashlib.sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    stat = path.stat()
    return {"path": str(path), "size_bytes": stat.st_size,
            "modified_utc": datetime.fromtimestamp(stat.st_mtime, UTC).isoformat(
                timespec="seconds"),
            "sha256": digest.hexdigest()}


def _classify_dict(data, where):
    from tactilecal.calibration._result import REQUIRED_KEYS, CalibrationResult

    if str(data.get("format", "")).startswith("tactilecal-dynamic-filter") or all(
            k in data for k in _FILTER_KEYS):
        return "filter", data
    if all(k in data for k in REQUIRED_KEYS):
        return "calibration", CalibrationResult.from_dict(data, source=where)
    raise ValueError(f"{where}: JSON with keys {sorted(data)[:8]} is neither a calibration "
                     f"(keys {list(REQUIRED_KEYS)}) nor a dynamic filter (keys "
                     f"{list(_FILTER_KEYS)})")


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
    kind : {"calibration", "filter", "recording"}
    obj : CalibrationResult, dict (FILTER.json content) or xarray.DataArray
    provenance : dict
        For a file, :func:`file_provenance` plus ``input``; for an object, what it is.

    Raises
    ------
    ValueError
        For a JSON that is neither kind, a file that is no recording, or an object of an
        unknown type.
    FileNotFoundError
        For a missing file.
    """
    if isinstance(item, xr.DataArray):
        return "recording", item, {"input": "DataArray in memory",
                                   "source": str(item.attrs.get("source", ""))}
    if isinstance(item, dict):
        kind, obj = _classify_dict(item, "dict input")
        return kind, obj, {"input": f"{kind} dict in memory"}
    if hasattr(item, "apply") and hasattr(item, "to_dict") and hasattr(item, "method"):
        return "calibration", item, {"input": "CalibrationResult in memory",
                                     "created": getattr(item, "created", "")}
    if hasattr(item, "to_dict") and hasattr(item, "fs_hz"):
        return "filter", item.to_dict(), {"input": "CorrectionFilter in memory"}
    if not isinstance(item, str | Path):
        raise ValueError(f"{what} of type {type(item).__name__}; expected a file path, "
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
