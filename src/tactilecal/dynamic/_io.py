"""Reading the inputs of the dynamic-calibration commands.

A *record* file is a time-series CSV (``read_timeseries``: time and one value column), or a
recording (anything :func:`tactilecal.io.open_recording` reads) whose frames are summed over
all sensels.
"""

__all__ = ["read_record"]


def read_record(path):
    """Read a 1-D record: a time-series CSV, or a recording summed over its sensels.

    A path that :func:`tactilecal.io.recording_format` recognises is a recording (a Tekscan
    export whatever its extension, NetCDF, Zarr); anything else is read as a time series.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    xarray.DataArray
        1-D with a ``time`` coordinate (s) and ``source``. A recording's frames are summed
        over ``row`` and ``col`` (NaN sensels skipped); ``summed_sensels`` says how many.

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    ValueError
        A malformed file (the reader's message names the file and line).
    """
    from tactilecal import io

    if io.recording_format(path) is None:
        return io.read_timeseries(path)
    data = io.open_recording(path)
    total = data.sum(dim=[d for d in data.dims if d != data.dims[0]], skipna=True)
    total.attrs = {"source": str(path), "units": data.attrs.get("units", "unknown"),
                   "summed_sensels": int(data.isel({data.dims[0]: 0}).notnull().sum())}
    return total
