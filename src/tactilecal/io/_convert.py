"""Stream a Tekscan export to Zarr or NetCDF, block by block (``tactilecal convert``)."""

from pathlib import Path

from tactilecal._atomic import atomic_folder, check_target, dask_tasks_finished
from tactilecal._errors import TactilecalError
from tactilecal._provenance import provenance_attr, provenance_of
from tactilecal._validate import float_type
from tactilecal.io._netcdf import write_netcdf
from tactilecal.io._tekscan_read import read_tekscan

__all__ = ["convert", "write_lazy", "DEFAULT_CHUNK_FRAMES"]

DEFAULT_CHUNK_FRAMES = 1000
"""Frames per block of :func:`convert` (44 x 44 sensels: 15.5 MB of float64 a block)."""

_SUFFIXES = (".zarr", ".nc")


def convert(source, target, *, chunks=DEFAULT_CHUNK_FRAMES, dtype="float64",
            overwrite=False):
    r"""Write a Tekscan export as Zarr or NetCDF without holding it in memory.

    The export is indexed once (every structural check of :func:`read_tekscan`), then each
    block of ``chunks`` frames is parsed and written in turn by dask, so memory is bounded by
    a few blocks (the dask threads' in flight), not by the file. The output is written under
    a temporary name next to ``target`` and renamed onto it at the end: on any error nothing
    is left at ``target`` (an existing ``target`` is left as it was).

    Parameters
    ----------
    source : str or os.PathLike
        A Tekscan ASCII export (see :func:`read_tekscan`).
    target : str or os.PathLike
        Output: a ``.zarr`` folder (a Zarr store in format 2 with consolidated metadata,
        chunked like the blocks: ``xr.open_zarr(path)`` or ``xr.open_dataarray(path,
        engine="zarr")`` open it as they expect by default, without a warning, with
        zarr-python 2 or 3) or a ``.nc`` file (NetCDF4, the layout of
        :func:`write_netcdf`, read by :func:`read_netcdf`).
    chunks : int, keyword-only
        Frames per block.
    overwrite : bool, keyword-only
        Replace an existing ``target`` (only a Zarr store or NetCDF file, as its suffix
        says; never ``source``). Default False: an existing ``target`` is an error.
    dtype : {"float64", "float32"}, keyword-only
        Type of the stored values (default float64, what :func:`read_tekscan` returns).
        float32 halves the array (and an uncompressed NetCDF file; a compressed Zarr store
        shrinks less); it holds raw 8-bit readings and NaN exactly, other values to 7
        significant digits, and a float32 recording is what
        ``apply_filter(..., dtype="float32")`` filters fastest.

    Returns
    -------
    xarray.DataArray
        The lazy recording that was written (dask-backed, nothing in memory).

    Raises
    ------
    ValueError
        ``target`` does not end in ``.zarr`` or ``.nc``, exists (without ``overwrite``, or
        is neither a Zarr store nor a NetCDF file, or is ``source``), the export is
        malformed (the message names the file and line), or ``dtype`` is neither float64
        nor float32.
    OSError
        ``target`` cannot be written (the message names it).

    Examples
    --------
    >>> import tempfile, pathlib, xarray as xr
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "m.csv").write_text("ROWS 1\nCOLS 2\nUNITS raw\nASCII_DATA @@\n"
    ...                                   "Frame 1\n1,2\nFrame 2\n3,B\n@@\n")
    >>> _ = convert(folder / "m.csv", folder / "m.zarr", chunks=1)
    >>> xr.open_dataarray(folder / "m.zarr", engine="zarr").values.tolist()
    [[[1.0, 2.0]], [[3.0, nan]]]
    """
    _check_suffix(target)
    if Path(target).exists() and Path(target).resolve() == Path(source).resolve():
        raise TactilecalError(f"output {target} is the input {source}; expected another path")
    dtype = float_type(dtype)
    data = read_tekscan(source, chunks=chunks)
    if data.dtype != dtype:
        data = data.astype(dtype, keep_attrs=True)
    options = {"chunks": chunks, "dtype": dtype.name}
    data.attrs["provenance"] = provenance_attr(provenance_of([data], options=options))
    write_lazy(data, target, overwrite=overwrite)
    return data


def _check_suffix(target):
    target = Path(target)
    if target.suffix.lower() not in _SUFFIXES:
        what = f"ends in {target.suffix!r}" if target.suffix else "has no suffix"
        raise TactilecalError(f"output {target} {what}; expected .zarr (Zarr store) or .nc "
                              "(NetCDF)")
    return target


def write_lazy(data, target, *, overwrite=False):
    """Write the (dask-backed) DataArray ``data`` to ``target`` (.zarr or .nc) atomically.

    Blocks are computed and written in turn; on any error nothing is left at ``target`` (an
    existing one is left as it was), nor any temporary output: the blocks still running
    when one fails finish before the temporary output is removed.
    """
    target = _check_suffix(target)
    if target.suffix.lower() == ".nc":
        write_netcdf(data, target, overwrite=overwrite)
        return
    check_target(target, overwrite=overwrite, kind="zarr")
    with atomic_folder(target) as tmp, dask_tasks_finished():
        # format 2: its consolidated metadata (.zmetadata) is in the format's spec, which
        # xarray reads first by default; format 3 has none in its spec (zarr-python 3
        # warns when writing it) and zarr-python 2 cannot read format 3 at all
        data.to_zarr(tmp, mode="w", consolidated=True, zarr_format=2)
