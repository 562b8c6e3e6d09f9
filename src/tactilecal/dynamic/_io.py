"""Reading the inputs of the dynamic-calibration commands.

A *record* file is a time-series CSV (``read_timeseries``: time and one value column), or a
Tekscan ASCII export / NetCDF recording whose frames are summed over all sensels.
"""

from pathlib import Path

NETCDF_SUFFIXES = (".nc", ".nc4", ".netcdf")
_SNIFF_BYTES = 1 << 16


def kind_of(path):
    """Return ``"netcdf"``, ``"tekscan"`` or ``"timeseries"`` for ``path``.

    A file whose first 64 KiB contain ``ASCII_DATA`` is a Tekscan export (whatever its
    extension: I-Scan exports are often ``.csv``).
    """
    path = Path(path)
    if path.suffix.lower() in NETCDF_SUFFIXES:
        return "netcdf"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    with path.open("rb") as fh:
        head = fh.read(_SNIFF_BYTES)
    return "tekscan" if b"ASCII_DATA" in head.upper() else "timeseries"


def read_recording(path, *, chunks=None):
    """Read a Tekscan export or NetCDF recording (NetCDF lazily when ``chunks`` is given)."""
    from tactilecal import io

    kind = kind_of(path)
    if kind == "tekscan":
        return io.read_tekscan(path)
    if kind == "netcdf":
        if chunks is None:
            return io.read_netcdf(path)
        import xarray as xr

        data = xr.open_dataarray(path, chunks=chunks, decode_times=False,
                                 decode_timedelta=False)
        data.attrs.setdefault("source", str(path))
        return data
    raise ValueError(f"{path}: no 'ASCII_DATA' header and not NetCDF; expected a Tekscan "
                     "recording or a .nc file")


def read_record(path):
    """Read a 1-D record: a time-series CSV, or a recording summed over its sensels.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    xarray.DataArray
        1-D with a ``time`` coordinate (s) and ``source``. A recording's frames are summed
        over ``row`` and ``col`` (NaN sensels skipped); ``summed_sensels`` says how many.
    """
    from tactilecal import io

    if kind_of(path) == "timeseries":
        return io.read_timeseries(path)
    data = read_recording(path)
    total = data.sum(dim=[d for d in data.dims if d != data.dims[0]], skipna=True)
    total.attrs = {"source": str(path), "units": data.attrs.get("units", "unknown"),
                   "summed_sensels": int(data.isel({data.dims[0]: 0}).notnull().sum())}
    return total
