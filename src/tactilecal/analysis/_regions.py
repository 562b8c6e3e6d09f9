"""Parts of a pressure map: regions, row/column profiles, loaded windows, high-pressure zones."""

import numpy as np
import pandas as pd
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._model import check_recording, recording_name
from tactilecal._units import KPA_MM2_TO_N, N_PER_MM2_TO_KPA
from tactilecal.analysis._units import (
    force_map_N,
    pressure_map_kPa,
    sensel_area_mm2,
    spacing_mm,
)

__all__ = ["select_region", "profile", "max_window_load",
           "label_zones", "high_pressure_zones"]


def _plane_mask(recording, mask, what):
    """Check a boolean ``(row, col)`` mask against the recording's sensel grid."""
    shape = (recording.sizes["row"], recording.sizes["col"])
    values = np.asarray(mask)
    if values.dtype != bool or values.shape != shape:
        raise TactilecalError(f"{what} has dtype {values.dtype} and shape {values.shape}; "
                              f"expected a boolean array of shape {shape} (rows, cols) "
                              f"of {recording_name(recording)}")
    return xr.DataArray(values, dims=("row", "col"),
                        coords={"row": recording["row"], "col": recording["col"]})


def select_region(recording, region):
    """Keep one region of every frame; sensels outside it become NaN.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model.
    region : tuple of 4 int or array_like of bool
        Either a box ``(row_start, row_stop, col_start, col_stop)`` in 0-based sensel
        indices, stops excluded (Python slices), or a boolean mask of shape (rows, cols).

    Returns
    -------
    xarray.DataArray
        Same shape and attributes; NaN outside the region, so every analysis function
        (force, area, centre, profiles) then describes the region alone.

    Raises
    ------
    ValueError
        If the box is empty or outside the sensor, or the mask has the wrong shape.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.ones((1, 3, 3)), dims=("frame", "row", "col"),
    ...                    coords={"row": [0, 1, 2], "col": [0, 1, 2]}, attrs={"units": "N"})
    >>> float(rec.tactile.select_region((0, 2, 1, 3)).sum())
    4.0
    """
    check_recording(recording)
    if isinstance(region, tuple) and len(region) == 4 and not np.asarray(region).dtype == bool:
        r0, r1, c0, c1 = (int(v) for v in region)
        rows, cols = recording.sizes["row"], recording.sizes["col"]
        if not (0 <= r0 < r1 <= rows and 0 <= c0 < c1 <= cols):
            raise TactilecalError(f"region box {region} is empty or outside the {rows} x {cols} "
                                  f"sensels of {recording_name(recording)}; expected 0 <= "
                                  f"row_start < "
                                  "row_stop <= rows and 0 <= col_start < col_stop <= cols")
        mask = np.zeros((rows, cols), dtype=bool)
        mask[r0:r1, c0:c1] = True
    else:
        mask = region
    return recording.where(_plane_mask(recording, mask, "region mask"))


def profile(recording, dim="row", *, nonworking=None, calibration=None):
    """Mean pressure of each sensel row (or column) in each frame [kPa].

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model with ``row_spacing_mm``/``col_spacing_mm``.
    dim : {"row", "col"}, default "row"
        The profile's axis: one mean per row (over its columns) or per column.
    nonworking : array_like of bool, optional
        (rows, cols) mask of non-working sensels, left out of the means like the blank
        (NaN) sensels outside the sensor's shape. Working sensels that read 0 are kept.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    xarray.DataArray
        ``row_profile_kPa`` with dims ``("frame", "row")`` and coordinate ``row_mm``
        (``col_profile_kPa``, ``("frame", "col")``, ``col_mm`` for columns).

    Notes
    -----
    Gillis (2013) section 5.7: each sensel row is averaged, omitting non-working sensels,
    to give the lateral earth pressure at the row's elevation (Figure 5.10).

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[10.0, 20.0], [0.0, np.nan]]]),
    ...                    dims=("frame", "row", "col"),
    ...                    attrs={"units": "kPa", "row_spacing_mm": 5.0, "col_spacing_mm": 5.0})
    >>> rec.tactile.profile().values
    array([[15.,  0.]])
    >>> rec.tactile.profile(nonworking=np.array([[True, False], [False, False]])).values
    array([[20.,  0.]])
    >>> rec.tactile.profile("col").values
    array([[ 5., 20.]])
    """
    if dim not in ("row", "col"):
        raise TactilecalError(f"profile dim is {dim!r}; expected 'row' or 'col'")
    pressure = pressure_map_kPa(recording, calibration=calibration)
    if nonworking is not None:
        pressure = pressure.where(~_plane_mask(recording, nonworking, "nonworking mask"))
    other = "col" if dim == "row" else "row"
    mean = pressure.mean(other, skipna=True)
    step = spacing_mm(recording)[0 if dim == "row" else 1]
    mean = mean.assign_coords({f"{dim}_mm": (dim, mean[dim].values * step)})
    mean.name = f"{dim}_profile_kPa"
    mean.attrs = {"units": "kPa"}
    return mean


def _window_shape(recording, window, area_mm2):
    rows, cols = recording.sizes["row"], recording.sizes["col"]
    if (window is None) == (area_mm2 is None):
        raise TactilecalError("give exactly one of window=(rows, cols) in sensels or area_mm2; "
                              f"got window={window!r}, area_mm2={area_mm2!r}")
    if area_mm2 is not None:
        if not np.isfinite(area_mm2) or area_mm2 <= 0:
            raise TactilecalError(f"area_mm2 is {area_mm2!r}; expected a positive area in mm2")
        side_mm = np.sqrt(area_mm2)
        row_mm, col_mm = spacing_mm(recording)
        window = (max(1, round(side_mm / row_mm)), max(1, round(side_mm / col_mm)))
    h, w = (int(v) for v in window)
    if not (1 <= h <= rows and 1 <= w <= cols):
        raise TactilecalError(f"window of {h} x {w} sensels does not fit the {rows} x {cols} "
                              f"sensels of {recording_name(recording)}; expected 1..{rows} rows "
                              f"and "
                              f"1..{cols} columns")
    return h, w


def _window_sums(force, h, w):
    """Sum of every h x w window over the last two axes (summed-area table)."""
    table = np.cumsum(np.cumsum(force, axis=-2), axis=-1)
    table = np.pad(table, [(0, 0)] * (force.ndim - 2) + [(1, 0), (1, 0)])
    return (table[..., h:, w:] - table[..., :-h, w:] - table[..., h:, :-w]
            + table[..., :-h, :-w])


def max_window_load(recording, *, window=None, area_mm2=None, calibration=None):
    """Largest force on any window of a given size, in each frame.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model.
    window : tuple of 2 int, optional
        Window size in sensels ``(rows, cols)``.
    area_mm2 : float, optional
        Window area instead: a square of side ``sqrt(area_mm2)``, rounded to whole
        sensels along each axis (the area actually used is in ``attrs``).
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    xarray.Dataset
        Per frame: ``force_N`` (the largest window load), ``mean_kPa`` (that load over
        the window area), ``row``/``col`` (first sensel of the window) and
        ``centre_row_mm``/``centre_col_mm``. ``attrs``: ``window_rows``, ``window_cols``,
        ``window_area_mm2``.

    Raises
    ------
    ValueError
        If both or neither of ``window`` and ``area_mm2`` are given, or the window does
        not fit the sensor.

    Notes
    -----
    Local (ice) loads: the largest load on any contact area of a given size, as used
    with tactile sensors in ice tanks (Zvyagin 2022, introduction). Window sums come
    from a summed-area table, ``S(i, j) = sum_{r<i, c<j} F(r, c)``, so each window
    costs four look-ups; only windows lying wholly on the sensor are considered, and
    NaN sensels count as zero force.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> f = np.zeros((1, 4, 4)); f[0, 2:4, 1:3] = [[1.0, 2.0], [3.0, 4.0]]
    >>> rec = xr.DataArray(f, dims=("frame", "row", "col"),
    ...                    attrs={"units": "N", "sensel_area_mm2": 1.0,
    ...                           "row_spacing_mm": 1.0, "col_spacing_mm": 1.0})
    >>> out = rec.tactile.max_window_load(window=(2, 2))
    >>> float(out.force_N[0]), int(out.row[0]), int(out.col[0])
    (10.0, 2, 1)
    """
    force = force_map_N(recording, calibration=calibration).fillna(0.0)
    h, w = _window_shape(recording, window, area_mm2)
    rows, cols = recording.sizes["row"], recording.sizes["col"]
    sums = xr.apply_ufunc(
        _window_sums, force, kwargs={"h": h, "w": w},
        input_core_dims=[["row", "col"]], output_core_dims=[["wrow", "wcol"]],
        dask="parallelized", output_dtypes=[float],
        dask_gufunc_kwargs={"output_sizes": {"wrow": rows - h + 1, "wcol": cols - w + 1},
                            "allow_rechunk": True},
    )
    where = sums.argmax(dim=["wrow", "wcol"])
    best = sums.max(["wrow", "wcol"])
    area = h * w * sensel_area_mm2(recording)
    row_mm, col_mm = spacing_mm(recording)
    first_row = force["row"].values[0]
    first_col = force["col"].values[0]
    row = where["wrow"] + first_row
    col = where["wcol"] + first_col
    ds = xr.Dataset({
        "force_N": best,
        "mean_kPa": best / area * N_PER_MM2_TO_KPA,
        "row": row,
        "col": col,
        "centre_row_mm": (row + (h - 1) / 2) * row_mm,
        "centre_col_mm": (col + (w - 1) / 2) * col_mm,
    })
    ds.attrs = {"window_rows": h, "window_cols": w, "window_area_mm2": area}
    return ds


def label_zones(recording, level_kPa, *, connectivity=1, calibration=None):
    """Label the connected regions above a pressure level, frame by frame.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model.
    level_kPa : float
        A sensel belongs to a zone when its pressure is strictly above this level.
    connectivity : {1, 2}, default 1
        1: sensels sharing an edge are connected (4-neighbourhood); 2: corners too
        (8-neighbourhood). Zones never connect across frames.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    xarray.DataArray of int
        Same dims; 0 outside zones, zone labels unique over the whole recording.

    Raises
    ------
    ValueError
        If ``connectivity`` is not 1 or 2.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> p = np.array([[[5.0, 0.0, 5.0], [5.0, 0.0, 0.0], [0.0, 5.0, 0.0]]])
    >>> rec = xr.DataArray(p, dims=("frame", "row", "col"), attrs={"units": "kPa"})
    >>> zones = rec.tactile.label_zones(1.0), rec.tactile.label_zones(1.0, connectivity=2)
    >>> [int(z.max()) for z in zones]
    [3, 2]
    """
    from scipy import ndimage

    if connectivity not in (1, 2):
        raise TactilecalError(f"connectivity is {connectivity!r}; expected 1 (edges) or 2 "
                              "(edges and corners)")
    pressure = pressure_map_kPa(recording, calibration=calibration)
    plane = ndimage.generate_binary_structure(2, connectivity)
    structure = np.zeros((3, 3, 3), dtype=bool)
    structure[1] = plane
    labels, _ = ndimage.label(np.asarray(pressure > level_kPa), structure=structure)
    out = xr.DataArray(labels, dims=pressure.dims, coords=pressure.coords, name="zone")
    out.attrs = {"level_kPa": float(level_kPa), "connectivity": connectivity}
    return out


def high_pressure_zones(recording, level_kPa, *, connectivity=1, min_sensels=1,
                        calibration=None):
    """Table of the connected regions above a pressure level in every frame.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model with sensel area and spacings.
    level_kPa : float
        A sensel belongs to a zone when its pressure is strictly above this level.
    connectivity : {1, 2}, default 1
        See :func:`label_zones`.
    min_sensels : int, default 1
        Smaller zones are left out of the table.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    pandas.DataFrame
        One row per zone: ``frame``, ``time_s`` (when the recording has ``time``),
        ``zone`` (1 = largest force in that frame), ``n_sensels``, ``area_mm2``,
        ``force_N``, ``peak_kPa``, ``mean_kPa``, ``cof_row_mm``, ``cof_col_mm``
        (force-weighted centre of the zone).

    Notes
    -----
    Zones are the connected components (:func:`scipy.ndimage.label`) of
    ``p > level_kPa``; Zvyagin (2022) calls the uneven peaks under a pad
    "high pressure zones".

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> p = np.zeros((1, 3, 4)); p[0, 0, 0:2] = 100.0; p[0, 2, 3] = 300.0
    >>> rec = xr.DataArray(p, dims=("frame", "row", "col"),
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 10.0,
    ...                           "row_spacing_mm": 1.0, "col_spacing_mm": 1.0})
    >>> table = rec.tactile.high_pressure_zones(50.0)
    >>> table[["zone", "n_sensels", "force_N"]].values.tolist()
    [[1.0, 1.0, 3.0], [2.0, 2.0, 2.0]]
    """
    from scipy import ndimage

    labels = label_zones(recording, level_kPa, connectivity=connectivity,
                         calibration=calibration)
    pressure = np.nan_to_num(np.asarray(pressure_map_kPa(recording, calibration=calibration)))
    index = np.arange(1, int(labels.max()) + 1)
    lab = labels.values
    area = sensel_area_mm2(recording)
    row_mm, col_mm = spacing_mm(recording)
    n = ndimage.sum_labels(np.ones_like(pressure), lab, index)
    force = ndimage.sum_labels(pressure, lab, index) * area * KPA_MM2_TO_N
    centre = np.array(ndimage.center_of_mass(pressure, lab, index)).reshape(-1, 3)
    frame_pos = np.array([s[0].start for s in ndimage.find_objects(lab)], dtype=int)
    table = pd.DataFrame({
        "frame": labels["frame"].values[frame_pos],
        "n_sensels": n, "area_mm2": n * area, "force_N": force,
        "peak_kPa": ndimage.maximum(pressure, lab, index),
        "mean_kPa": force / (n * area) * N_PER_MM2_TO_KPA,
        "cof_row_mm": (centre[:, 1] + labels["row"].values[0]) * row_mm,
        "cof_col_mm": (centre[:, 2] + labels["col"].values[0]) * col_mm,
    })
    if "time" in labels.coords:
        table.insert(1, "time_s", labels["time"].values[frame_pos])
    table = table[table["n_sensels"] >= min_sensels]
    table = table.sort_values(["frame", "force_N"], ascending=[True, False])
    table.insert(1, "zone", table.groupby("frame").cumcount() + 1)
    return table.reset_index(drop=True)
