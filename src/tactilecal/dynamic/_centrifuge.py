"""Centrifuge water-test helpers (Gillis 2013, section 4.4.2).

The sensel row at a pore-pressure transducer's elevation is averaged (non-working sensels
left out), the sensor is calibrated statically from the water head above it at the
g-level (:func:`tactilecal.geotech.hydrostatic_pressure_kPa`); model records go to prototype
scale with :func:`tactilecal.geotech.to_prototype`.
"""

import numpy as np
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal.geotech import hydrostatic_pressure_kPa

__all__ = ["row_mean", "water_head_factor", "RHO_WATER_KG_M3"]

#: Density of water used by default (kg/m3).
RHO_WATER_KG_M3 = 1000.0


def row_mean(recording, row, *, working=None):
    """Average one sensel row per frame, skipping NaN and non-working sensels.

    Gillis (2013), 4.4.2: "the ninth row of sensels ... averaged to produce one pressure
    sensor value per time step".

    Parameters
    ----------
    recording : xarray.DataArray
        ``("frame", "row", "col")`` with a ``time`` coordinate.
    row : int
        Row label (0 = top of the sensor; the thesis' ninth row is 8).
    working : array_like of bool, optional
        ``(row, col)`` mask, False for non-working sensels (they are left out even when
        they read numbers).

    Returns
    -------
    xarray.DataArray
        1-D along ``frame`` with ``time``; attrs of the recording plus ``row`` and
        ``sensels_averaged``.

    Raises
    ------
    ValueError
        Row not in the recording, mask of the wrong shape, or no usable sensel in the row.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.arange(12.0).reshape(2, 2, 3), dims=("frame", "row", "col"),
    ...                    coords={"row": [0, 1], "time": ("frame", [0.0, 0.1])})
    >>> row_mean(rec, 1, working=[[1, 1, 1], [1, 1, 0]]).values.tolist()
    [3.5, 9.5]
    """
    where = recording.attrs.get("source", "recording")
    rows = recording["row"].values if "row" in recording.coords else np.arange(
        recording.sizes["row"])
    if row not in rows:
        raise TactilecalError(f"{where}: row {row} not found; expected one of "
                              f"{rows.min()}..{rows.max()}")
    data = recording.sel(row=row) if "row" in recording.coords else recording.isel(row=row)
    if working is not None:
        mask = np.asarray(working, dtype=bool)
        if mask.shape != recording.shape[1:]:
            raise TactilecalError(f"working mask has shape {mask.shape}; expected "
                                  f"{recording.shape[1:]} (rows, cols) of {where}")
        data = data.where(xr.DataArray(mask[list(rows).index(row)], dims="col"))
    usable = int(data.notnull().any("frame").sum())
    if usable == 0:
        raise TactilecalError(f"{where}: row {row} has no working, non-NaN sensel; expected at "
                              "least one")
    out = data.mean("col", skipna=True)
    out.attrs = {**recording.attrs, "row": int(row), "sensels_averaged": usable}
    return out


def water_head_factor(record, head_m, g_level, *, rho_kg_m3=RHO_WATER_KG_M3, window_s=None):
    """Return the static calibration factor (kPa per unit) from a water head at a g-level.

    ``factor = rho_w g N h / mean(record)`` with the mean over ``window_s`` (a quiet stretch
    in flight before shaking; default the whole record).

    Parameters
    ----------
    record : xarray.DataArray
        1-D with a ``time`` coordinate (e.g. from :func:`row_mean`, in raw units).
    head_m, g_level, rho_kg_m3
        Water head above the row (m), g-level ``N`` and water density (kg/m3): the
        pressure is :func:`tactilecal.geotech.hydrostatic_pressure_kPa`.
    window_s : tuple of float, optional
        ``(start, stop)`` in s.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.full(10, 20.0), dims="frame",
    ...                    coords={"time": ("frame", np.arange(10) / 4000)})
    >>> round(water_head_factor(rec, 0.070, 77.0), 4)
    2.6429
    """
    time_s = record["time"].values
    values = record.values
    if window_s is not None:
        values = values[(time_s >= window_s[0]) & (time_s <= window_s[1])]
    mean = float(np.nanmean(values)) if values.size else np.nan
    if not np.isfinite(mean) or mean == 0:
        raise TactilecalError(f"{record.attrs.get('source', 'record')}: mean reading {mean} over "
                              f"window_s={window_s}; expected a loaded, non-empty stretch")
    return float(hydrostatic_pressure_kPa(head_m, g_level, density_kg_m3=rho_kg_m3)) / mean
