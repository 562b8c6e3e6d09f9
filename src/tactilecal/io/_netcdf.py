"""NetCDF files for any recording or result (thin wrappers around xarray)."""

import contextlib
import importlib.util
import json

import numpy as np
import xarray as xr

from tactilecal._atomic import (
    atomic_path,
    check_target,
    compute_drained,
    dask_tasks_finished,
    distributed_client,
)
from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import dumps
from tactilecal._validate import TextFault, float_type, shorten

__all__ = ["read_netcdf", "write_netcdf"]

_JSON_ATTRS = "tactilecal_json_attrs"
_INT_COORDS = ("frame", "row", "col")


def _engine():
    """``h5netcdf`` (NetCDF4) when h5py is installed, else ``scipy`` (NetCDF3)."""
    return "h5netcdf" if importlib.util.find_spec("h5py") else "scipy"


def write_netcdf(data, path, *, compress=False, dtype=None, overwrite=False):
    """Write a DataArray to NetCDF atomically; non-scalar attributes are stored as JSON.

    Attributes that NetCDF cannot hold (dicts, lists, ``None``, booleans) are written as
    JSON text and listed in the ``tactilecal_json_attrs`` attribute, so
    :func:`read_netcdf` restores them.

    Parameters
    ----------
    data : xarray.DataArray
        Any recording or result.
    path : str or os.PathLike
        Output file.
    compress : bool, keyword-only
        Compress the values (zlib level 4 with the shuffle filter, NetCDF4 only): a
        recording's many zeros and repeated values shrink several times.
    dtype : {None, "float32"}, keyword-only
        Store the values as float32 (7 significant digits), recorded in the attribute
        ``stored_dtype``; None keeps them as they are.
    overwrite : bool, keyword-only
        Replace an existing ``path`` (only a NetCDF file; default False: an error).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np, xarray as xr
    >>> a = xr.DataArray(np.arange(3.0), dims="time", coords={"time": [0.0, 0.1, 0.2]},
    ...                  attrs={"units": "N", "fit": {"A": 0.11, "ok": True}})
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "a.nc"
    >>> write_netcdf(a, out)
    >>> read_netcdf(out).identical(a)
    True
    """
    check_target(path, overwrite=overwrite, kind="netcdf")
    out = data.copy(deep=False)
    if dtype is not None:
        out = out.astype(float_type(dtype, "dtype"), keep_attrs=True)
        out.attrs["stored_dtype"] = out.dtype.name
    encoded = []
    for key, value in data.attrs.items():
        if not isinstance(value, str | int | float | np.number) or isinstance(value, bool):
            out.attrs[key] = dumps(value, indent=None)
            encoded.append(key)
    if encoded:
        out.attrs[_JSON_ATTRS] = ",".join(encoded)
    engine = _engine()
    options = {"engine": engine}
    if compress and engine == "h5netcdf":
        out.encoding.update({"zlib": True, "complevel": 4, "shuffle": True})
    with atomic_path(path, suffix=".nc") as tmp:
        try:
            # the temporary file is removed only after every block stopped writing
            client = distributed_client() if out.chunks is not None else None
            if client is not None:
                compute_drained(client, out.to_netcdf(tmp, compute=False, **options))
            else:
                with dask_tasks_finished() if out.chunks is not None else \
                        contextlib.nullcontext():
                    out.to_netcdf(tmp, **options)
        except ValueError as exc:
            if engine != "scipy":
                raise
            raise TactilecalError(f"cannot write {path} as NetCDF3 (h5py is not installed, so "
                                  f"the scipy engine is used): {exc}; expected values NetCDF3 "
                                  "can hold (e.g. int64 within the int32 range): install h5py "
                                  "or convert to float64") from None


def read_netcdf(path):
    """Read a DataArray written by :func:`write_netcdf` (or ``DataArray.to_netcdf``).

    The data are loaded into memory and the file closed. ``frame``, ``row`` and ``col``
    coordinates come back as int64 (NetCDF3 stores them as int32); times are not decoded
    to datetimes.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    xarray.DataArray

    Raises
    ------
    FileNotFoundError
        No such file.
    ValueError
        A path that is no regular file (a folder, device or pipe), or not a NetCDF file
        holding one data variable.

    Examples
    --------
    >>> import tempfile, pathlib, numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.arange(8.0).reshape(2, 2, 2), dims=("frame", "row", "col"),
    ...                    attrs={"units": "raw", "sensel_area_mm2": 1.6129})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "rec.nc"
    >>> write_netcdf(rec, path)
    >>> back = read_netcdf(path)
    >>> back.values.tolist() == rec.values.tolist(), back.attrs["units"]
    (True, 'raw')
    """
    from pathlib import Path

    if Path(path).exists() and not Path(path).is_file():
        raise TextFault.not_a_file(path, "a NetCDF file (.nc)")
    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: no such file; expected a NetCDF file (.nc)")
    data = open_store(lambda: xr.load_dataarray(path, decode_times=False,
                                                decode_timedelta=False),
                      path, "NetCDF file", "write_netcdf or DataArray.to_netcdf")
    for name in _INT_COORDS:
        if name in data.coords and np.issubdtype(data[name].dtype, np.integer):
            data = data.assign_coords({name: data[name].astype(np.int64)})
    names = data.attrs.pop(_JSON_ATTRS, "")
    for key in filter(None, str(names).split(",")):
        try:
            data.attrs[key] = json.loads(data.attrs[key])
        except (KeyError, TypeError, ValueError, RecursionError):
            raise TactilecalError(f"{path}: attribute {shorten(key)} is listed in "
                                  f"{_JSON_ATTRS} but holds no JSON; expected a file written by "
                                  "write_netcdf") from None
    return data


def open_store(function, path, what, writer):
    """Return ``function()`` (which opens ``path``); turn any failure into one line naming it.

    A damaged file makes HDF5 or Zarr raise whatever their parsers meet (``KeyError`` for a
    bad metadata checksum, ``RuntimeError``, ``OSError``...): all of it is bad input. The
    half-built file objects that the failure leaves are collected here, with Python's report
    of their failing clean-up silenced, so that nothing but the one line reaches the user.
    """
    import gc
    import sys

    hook = sys.unraisablehook
    sys.unraisablehook = lambda unraisable: None
    try:
        try:
            return function()
        except Warning:  # a warning turned into an error (python -W error) stays itself
            raise
        except Exception as exc:  # noqa: BLE001 - a parser's failure on a damaged file
            detail = " ".join(str(exc).split())
            detail = detail if len(detail) <= 120 else detail[:117] + "..."
            message = (f"{path}: not a {what} with one data variable ({type(exc).__name__}: "
                       f"{detail}); expected a file written by {writer}")
        gc.collect()  # the failure's frames are gone: collect what they held, silently
        raise TactilecalError(message)
    finally:
        sys.unraisablehook = hook
