"""Reading the inputs of the dynamic-calibration commands.

A *record* file is a time-series CSV (``read_timeseries``: time and one value column), or a
recording (anything :func:`tactilecal.io.open_recording` reads) whose frames are summed over
all sensels.
"""

__all__ = ["read_record"]


def read_record(path):
    r"""Read a 1-D record: a time-series CSV, or a recording summed over its sensels.

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

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "rec.csv").write_text("ROWS 1\nCOLS 2\nSECONDS_PER_FRAME 0.01\n"
    ...                                     "ASCII_DATA @@\nFrame 1\n3,4\n\nFrame 2\n5,6\n@@\n")
    >>> rec = read_record(folder / "rec.csv")  # a Tekscan export, summed over its sensels
    >>> rec.values.tolist(), rec["time"].values.tolist(), rec.attrs["summed_sensels"]
    ([7.0, 11.0], [0.0, 0.01], 2)
    >>> _ = (folder / "lc.csv").write_text("Time (ms),Load (kN)\n0,1.5\n250,2\n")
    >>> read_record(folder / "lc.csv").values.tolist()  # a time series, in N
    [1500.0, 2000.0]
    """
    from tactilecal import io

    if io.recording_format(path) is None:
        return io.read_timeseries(path)
    data = io.open_recording(path)
    total = data.sum(dim=[d for d in data.dims if d != data.dims[0]], skipna=True)
    total.attrs = {"source": str(path), "units": data.attrs.get("units", "unknown"),
                   "summed_sensels": int(data.isel({data.dims[0]: 0}).notnull().sum())}
    return total
