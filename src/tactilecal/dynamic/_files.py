"""Dynamic correction of files: a time-series CSV, a recording, an evaluation folder.

What ``tactilecal dynamic apply`` and ``tactilecal dynamic evaluate --out`` do with files,
as library calls: every value column of a CSV or every sensel of a recording is filtered
with :func:`apply_filter`; an evaluation is written as ``evaluation.json`` plus its figures
(Gillis 2013, Figs 4.9-4.14).
"""

from pathlib import Path

import numpy as np

from tactilecal._atomic import atomic_path
from tactilecal._errors import TactilecalError
from tactilecal._png import write_png
from tactilecal._provenance import provenance_attr, provenance_of, write_sidecar
from tactilecal.dynamic._apply import apply_filter
from tactilecal.dynamic._plots import plot_error, plot_spectra, plot_time, plot_transfer

__all__ = ["filter_recording", "filter_timeseries_csv", "write_evaluation"]


def filter_timeseries_csv(filt, path, out, *, method="auto", causal=False, progress=None,
                          dtype="float64"):
    """Filter every numeric value column of a time-series CSV; write the same columns.

    Parameters
    ----------
    filt : CorrectionFilter
        The correction filter (:func:`load_filter`).
    path : str or os.PathLike
        Time-series CSV (:func:`tactilecal.io.read_timeseries` checks its time column).
    out : str or os.PathLike
        Output CSV, written atomically: the input's columns, the numeric value columns
        filtered along time, numbers with 10 significant digits. Its provenance (input
        file with SHA-256, the filter, package version) goes to ``OUT.provenance.json``.
    method, causal, progress, dtype
        As in :func:`apply_filter`.

    Returns
    -------
    tuple of int
        ``(columns, rows)``: how many value columns were filtered, over how many rows.

    Raises
    ------
    TactilecalError
        A value the filter made non-finite (nothing is written).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import pandas as pd
    >>> from tactilecal.dynamic import CorrectionFilter
    >>> filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000, band_hz=(1, 100))
    >>> t, folder = np.arange(0, 4, 1e-3), pathlib.Path(tempfile.mkdtemp())
    >>> table = pd.DataFrame({"Time (s)": t, "left (N)": 100 + np.sin(2 * np.pi * 99 * t),
    ...                       "right (N)": 50 + np.sin(2 * np.pi * 10 * t)})
    >>> table.to_csv(folder / "in.csv", index=False)
    >>> filter_timeseries_csv(filt, folder / "in.csv", folder / "out.csv")  # (columns, rows)
    (2, 4000)
    >>> out = pd.read_csv(folder / "out.csv")  # each sine's amplitude, 1 N before
    >>> [round(float((out[c] - out[c].mean())[1000:-1000].abs().max()), 2) for c in out.columns[1:]]
    [1.22, 1.11]
    """
    import pandas as pd
    import xarray as xr

    from tactilecal.io import read_timeseries

    series = read_timeseries(path)  # checks the time column, units, numbers
    table = pd.read_csv(path, encoding="utf-8-sig", skipinitialspace=True)
    table.columns = [str(c).strip() for c in table.columns]
    time_col = series.attrs["time_column"]
    value_cols = [c for c in table.columns
                  if c != time_col and pd.api.types.is_numeric_dtype(table[c])]
    data = xr.DataArray(table[value_cols].to_numpy(float), dims=("time", "column"),
                        coords={"time": series["time"].values}, attrs={"source": str(path)})
    filtered = apply_filter(data, filt, progress=progress, method=method, causal=causal,
                            dtype=dtype)
    values = np.asarray(filtered.values)
    bad = ~np.isfinite(values) & np.isfinite(data.values)
    if bad.any():  # never write a cell the filter could not compute
        row, col = (int(k[0]) for k in np.nonzero(bad))
        raise TactilecalError(f"{path}: filtering column {value_cols[col]!r} with the filter "
                              f"gave a non-finite value at row {row + 2}; expected finite "
                              "values (is the filter file damaged?)")
    table[value_cols] = values
    with atomic_path(out) as tmp:
        table.to_csv(tmp, index=False, float_format="%.10g")
    options = {"method": method, "causal": causal, "dtype": str(filtered.dtype)}
    write_sidecar(out, {**provenance_of([series], options=options),
                        "dynamic_filter": filt.to_dict()})
    return len(value_cols), len(table)


def filter_recording(filt, path, *, chunk_frames=65536, method="auto", causal=False,
                     progress=None, dtype="float64"):
    """Filter every sensel of a recording along time (lazily, by chunks, for NetCDF).

    Parameters
    ----------
    filt : CorrectionFilter
        The correction filter.
    path : str or os.PathLike
        Tekscan export (read whole), NetCDF or Zarr (opened lazily in chunks of
        ``chunk_frames`` frames, so a recording larger than memory streams through).
    chunk_frames : int
        Frames per chunk for NetCDF.
    method, causal, progress, dtype
        As in :func:`apply_filter` (``dtype="float32"`` halves the output's size).

    Returns
    -------
    xarray.DataArray
        The corrected recording (dask-backed for NetCDF: write it with
        :func:`tactilecal.io.write_netcdf`), with ``time_jitter_s``,
        ``sampling_rate_hz``, ``dynamic_filter`` (the filter) and ``provenance`` (JSON
        text: the input file with SHA-256, sensor, package version) attributes.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import xarray as xr
    >>> from tactilecal.dynamic import CorrectionFilter
    >>> from tactilecal.io import write_netcdf
    >>> filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000, band_hz=(1, 100))
    >>> t, folder = np.arange(0, 4, 1e-3), pathlib.Path(tempfile.mkdtemp())
    >>> sine = (100 + np.sin(2 * np.pi * 99 * t))[:, None, None] * np.ones((1, 2, 2))
    >>> write_netcdf(xr.DataArray(sine, dims=("frame", "row", "col"), attrs={"units": "N"},
    ...                           coords={"time": ("frame", t)}), folder / "rec.nc")
    >>> out = filter_recording(filt, folder / "rec.nc", chunk_frames=1000)  # read lazily
    >>> out.shape, np.abs(out - 100)[1000:-1000].max("frame").round(2).values.tolist()
    ((4000, 2, 2), [[1.22, 1.22], [1.22, 1.22]])
    """
    from tactilecal.io import open_recording, recording_format

    lazy = recording_format(path) in ("netcdf", "zarr")
    data = open_recording(path, chunks=chunk_frames if lazy else None)
    if lazy and data.dims and data.dims[0] in data.chunksizes:
        data = data.chunk({data.dims[0]: chunk_frames})
    out = apply_filter(data, filt, progress=progress, method=method, causal=causal, dtype=dtype)
    options = {"method": method, "causal": causal, "chunk_frames": chunk_frames,
               "dtype": str(out.dtype)}
    out.attrs["provenance"] = provenance_attr(provenance_of([data], options=options))
    return out


def write_evaluation(evaluation, filt, folder):
    """Write ``evaluation.json`` and the figures of an evaluation into ``folder``.

    Parameters
    ----------
    evaluation : Evaluation
        From :func:`evaluate`; its ``figures`` become the names written.
    filt : CorrectionFilter
        The evaluated filter (its transfer-function figure).
    folder : str or os.PathLike
        An existing folder; ``time.png`` (the whole record and a zoomed window),
        ``spectra.png``, ``error.png``, ``transfer.png`` and ``evaluation.json`` are
        written atomically.

    Returns
    -------
    Evaluation
        ``evaluation``, with ``figures`` set.
    """
    folder = Path(folder)
    figures = {"time.png": plot_time(evaluation), "spectra.png": plot_spectra(evaluation),
               "error.png": plot_error(evaluation), "transfer.png": plot_transfer(filt)}
    for name, fig in figures.items():
        write_png(fig, folder / name, dpi=120)
    evaluation.figures = tuple(sorted(figures))
    evaluation.to_json(folder / "evaluation.json")
    return evaluation
