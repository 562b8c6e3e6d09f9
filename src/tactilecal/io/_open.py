"""One entry point for recordings: sniff the format of a path and read it.

Formats: a Tekscan ASCII export (any extension: I-Scan exports are often ``.csv``), NetCDF
(written by :func:`tactilecal.io.write_netcdf`, ``tactilecal apply`` or ``convert``) and a
Zarr store (written by :func:`tactilecal.io.convert`).
"""

from pathlib import Path

from tactilecal._errors import TactilecalError
from tactilecal._sniff import ZARR_METADATA, sniff

__all__ = ["open_recording", "recording_format", "NETCDF_SUFFIXES", "FORMATS"]

NETCDF_SUFFIXES = (".nc", ".nc4", ".netcdf")
FORMATS = ("tekscan", "netcdf", "zarr")
"""What :func:`recording_format` recognises."""


def recording_format(path):
    r"""Return the recording format of ``path``: "tekscan", "netcdf", "zarr" or None.

    Sniffed, in this order: a folder with Zarr metadata (``.zgroup``, ``.zarray`` or
    ``zarr.json``) is ``"zarr"``; a file ending in ``.nc``, ``.nc4`` or ``.netcdf``, or
    starting with the HDF5 or NetCDF3 signature, is ``"netcdf"``; a file whose first 64 KiB
    contain ``ASCII_DATA`` is ``"tekscan"``. Anything else (a load-cell CSV, say) is None.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    str or None

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    ValueError
        ``path`` is a device, pipe or socket (``/dev/null``), not a file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "a.csv").write_text("ROWS 1\nCOLS 1\nASCII_DATA @@\nFrame 1\n3\n@@\n")
    >>> _ = (folder / "load.csv").write_text("time_s,load_N\n0,1\n")
    >>> recording_format(folder / "a.csv"), recording_format(folder / "load.csv")
    ('tekscan', None)
    """
    path = Path(path)
    kind = sniff(path)
    if kind is None:
        raise FileNotFoundError(f"{path}: no such file")
    if kind == "special":
        raise TactilecalError(f"{path} is not a regular file (a device, pipe or socket); "
                              "expected a recording (Tekscan export, NetCDF file or Zarr store)")
    if kind == "folder":
        return None
    if path.suffix.lower() in NETCDF_SUFFIXES:
        return "netcdf"
    return kind if kind in FORMATS else None


def open_recording(path, *, chunks=None):
    r"""Read a recording of any supported format into a DataArray (format sniffed).

    Parameters
    ----------
    path : str or os.PathLike
        A Tekscan ASCII export, a NetCDF file or a Zarr store (see
        :func:`recording_format`).
    chunks : int, optional
        Frames per block of a lazy, dask-backed result. None (default): a Tekscan export
        or NetCDF file is read into memory (:func:`read_tekscan`, :func:`read_netcdf`); a
        Zarr store is always opened lazily, in its own chunks unless ``chunks`` is given.

    Returns
    -------
    xarray.DataArray
        Dims ``("frame", "row", "col")`` with the attributes of ``docs/data-model.md``;
        ``source`` names the file when the file did not already say.

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    ValueError
        ``path`` is in none of the formats, or is malformed (the reader's message names
        the file and line).
    TypeError
        ``chunks`` is not an integer.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "a.csv").write_text("ROWS 1\nCOLS 2\nASCII_DATA @@\nFrame 1\n3,4\n@@\n")
    >>> open_recording(folder / "a.csv").values.tolist()
    [[[3.0, 4.0]]]
    """
    kind = recording_format(path)
    if chunks is not None and (isinstance(chunks, bool) or not isinstance(chunks, int)):
        raise TypeError(f"chunks of type {type(chunks).__name__}; expected an integer "
                        "number of frames per block")
    if kind == "tekscan":
        from tactilecal.io._tekscan_read import read_tekscan

        return read_tekscan(path, chunks=chunks)
    if kind == "netcdf" and chunks is None:
        from tactilecal.io._netcdf import read_netcdf

        return read_netcdf(path)
    if kind in ("netcdf", "zarr"):
        return _open_lazy(path, kind, chunks)
    if Path(path).is_dir():
        raise TactilecalError(f"{path} is a folder without Zarr metadata "
                              f"({', '.join(ZARR_METADATA)}); expected a recording file or a "
                              "Zarr store")
    raise TactilecalError(f"{path}: not a recording: no 'ASCII_DATA' line in its first 64 KiB "
                          "(Tekscan export), not NetCDF, not a Zarr store; expected one of these")


def _open_lazy(path, kind, chunks):
    """Open a NetCDF file or Zarr store lazily (dask) in blocks of ``chunks`` frames."""
    import xarray as xr

    from tactilecal.io._netcdf import open_store

    options = {"engine": "zarr"} if kind == "zarr" else {}
    data = open_store(lambda: xr.open_dataarray(
        path, chunks={} if chunks is None else {"frame": chunks}, decode_times=False,
        decode_timedelta=False, **options), path, f"{kind} store", "write_netcdf or convert")
    data.attrs.setdefault("source", str(path))
    return data
