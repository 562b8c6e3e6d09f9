"""Where a result came from: input files with their SHA-256, the sensor, the package version.

Every saved result can say which files it was computed from (so that a number in a paper can
be traced back to the bytes it came from) and on which sensor: the export header's
``SENSOR_TYPE`` and its ``HARDWARE`` field, the serial number of the sensor handle
(``tekscan_HARDWARE`` in the recording's attributes).
"""

import functools
import hashlib
from datetime import UTC, datetime
from pathlib import Path

from tactilecal._atomic import write_text_atomic
from tactilecal._jsonutil import dumps
from tactilecal._version import __version__

__all__ = ["file_provenance", "sensor_of", "provenance", "provenance_of", "provenance_attr",
           "sidecar_path", "write_sidecar"]


def file_provenance(path):
    """Absolute path, size, modification time (UTC) and SHA-256 of a file.

    A file read twice in one process (a recording that is calibrated and then summarised,
    a manifest calibrated and validated) is hashed once: the digest is kept for as long as
    the file's size and modification time (in ns) stay the same.
    """
    path = Path(path).resolve()
    stat = path.stat()
    return {"path": str(path), "size_bytes": stat.st_size,
            "modified_utc": datetime.fromtimestamp(stat.st_mtime, UTC).isoformat(
                timespec="seconds"),
            "sha256": _sha256(str(path), stat.st_size, stat.st_mtime_ns)}


@functools.lru_cache(maxsize=1024)
def _sha256(path, size_bytes, mtime_ns):
    """SHA-256 of ``path`` (its size and mtime are part of the cache key only)."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def sensor_of(attrs):
    """Return ``{"sensor_type", "sensor_serial"}`` from a recording's attributes (None: unknown).

    The serial is the export header's ``HARDWARE`` field (e.g. ``116-1974-1``).
    """
    return {"sensor_type": attrs.get("sensor_type"),
            "sensor_serial": attrs.get("tekscan_HARDWARE")}


def provenance(files, sensors=()):
    """Return the provenance record of a result computed from ``files``.

    Parameters
    ----------
    files : iterable of path
        The input files (existing files only are hashed; each once).
    sensors : iterable of dict
        :func:`sensor_of` of every recording read; distinct values are kept, so a
        calibration from two sensor handles says so.

    Returns
    -------
    dict
        ``tactilecal_version``, ``inputs`` (:func:`file_provenance` of each file, path order
        as given), ``sensor_type`` and ``sensor_serial`` (a string, a list when the inputs
        disagree, None when unknown).
    """
    seen, inputs = set(), []
    for path in map(Path, files):
        if path.is_file() and path.resolve() not in seen:
            seen.add(path.resolve())
            inputs.append(file_provenance(path))
    sensors = list(sensors)
    out = {"tactilecal_version": __version__, "inputs": inputs}
    for key in ("sensor_type", "sensor_serial"):
        values = sorted({str(s[key]) for s in sensors if s.get(key) is not None})
        out[key] = values[0] if len(values) == 1 else (values or None)
    return out


def provenance_of(records=(), files=(), options=None):
    """Return the provenance of a result computed from ``records`` (and more ``files``).

    Parameters
    ----------
    records : iterable
        xarray or pandas objects; the file each was read from (``encoding["source"]`` or
        ``attrs["source"]``, when there is one) is hashed and its sensor
        (:func:`sensor_of`) recorded.
        Objects without attributes (plain arrays) add nothing.
    files : iterable of path
        Further input files (a manifest, a filter).
    options : dict, optional
        The options the result was computed with (stored as ``options``), for outputs that
        do not record them otherwise (a CSV table, a filtered NetCDF).

    Returns
    -------
    dict
        As :func:`provenance`, plus ``options`` when given.
    """
    records = [r for r in records if hasattr(r, "attrs")]
    sources = [_source(r) for r in records]
    out = provenance([*files, *filter(None, sources)], [sensor_of(r.attrs) for r in records])
    return out if options is None else {**out, "options": dict(options)}


def _source(record):
    """Return the file ``record`` was read from, or None.

    xarray's ``encoding["source"]`` (the NetCDF or Zarr file opened, whatever its ``source``
    attribute says of the data's origin), else the reader's ``attrs["source"]``.
    """
    for where in (getattr(record, "encoding", {}), record.attrs):
        if isinstance(where.get("source"), str):
            return where["source"]
    return None


def provenance_attr(prov):
    """Return ``prov`` as JSON text, for a NetCDF/Zarr attribute (``attrs["provenance"]``).

    Through :func:`tactilecal._jsonutil.dumps`, as the sidecar: NumPy numbers in the
    options (``chunk_frames=np.int64(8192)``) are written as numbers, not refused.
    """
    return dumps(prov, indent=None)


def sidecar_path(path):
    """Return the provenance file of a CSV output: ``OUT.csv`` -> ``OUT.provenance.json``.

    A CSV has no place for metadata that every reader skips, so its provenance sits beside
    it, as BIDS puts a JSON sidecar beside each tabular file.
    """
    path = Path(path)
    return path.with_name(path.stem + ".provenance.json")


def write_sidecar(path, prov):
    """Write ``prov`` atomically as the sidecar of the CSV ``path``; return the sidecar's path."""
    side = sidecar_path(path)
    write_text_atomic(side, dumps(prov) + "\n")
    return side
