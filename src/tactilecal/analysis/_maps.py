"""Per-frame quantities of a pressure map: force, contact area, centre of force, pressures.

Every function works on whole recordings at once (vectorised over frames, lazy on
dask-backed arrays) and returns a DataArray with dim ``frame`` and the recording's
``time`` coordinate.
"""

import numpy as np
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._model import check_recording
from tactilecal._units import KPA_MM2_TO_N
from tactilecal.analysis._units import (
    force_map_N,
    pressure_map_kPa,
    saturated_sensels,
    sensel_area_mm2,
    spacing_mm,
)

__all__ = ["total_force", "contact_area", "centre_of_force", "peak_pressure",
           "mean_pressure", "summary", "loaded_mask"]

_PLANE = ("row", "col")


def _named(da, name, unit):
    da.name = name
    da.attrs = {"units": unit}
    return da


def loaded_mask(recording, *, threshold_kPa=0.0, calibration=None):
    """Return a boolean map of loaded sensels (pressure above ``threshold_kPa``).

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model.
    threshold_kPa : float, default 0
        A sensel is loaded when its pressure is strictly above this level.
    calibration : CalibrationResult or path, optional
        For a raw recording. Without one, a raw sensel is loaded when its reading is
        above 0 (Tekscan reports readings below the noise threshold as 0), and
        ``threshold_kPa`` must then be 0.

    Returns
    -------
    xarray.DataArray of bool
        ``True`` where loaded; NaN sensels (outside the sensor) are ``False``.

    Raises
    ------
    ValueError
        If ``threshold_kPa`` is negative, or non-zero for a raw recording without
        calibration.
    """
    _, kind = check_recording(recording)
    threshold_kPa = _non_negative("threshold_kPa", threshold_kPa)
    if kind == "raw" and calibration is None:
        if threshold_kPa != 0:
            raise TactilecalError(f"threshold_kPa is {threshold_kPa!r} but the recording is raw "
                                  "and no calibration was given; expected 0 (loaded = raw > 0)")
        return recording > 0
    return pressure_map_kPa(recording, calibration=calibration) > threshold_kPa


def total_force(recording, *, calibration=None):
    """Total force on the sensor in each frame [N].

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model (pressure or force units; raw needs ``calibration``).
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    xarray.DataArray
        ``force_N`` with dim ``frame``.

    Notes
    -----
    ``F = sum_k p_k a * 1e-3`` with ``p_k`` in kPa and the sensel area ``a`` in mm2
    (data model, ``sensel_area_mm2``); NaN sensels are skipped.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[0.0, 100.0], [100.0, np.nan]]]),
    ...                    dims=("frame", "row", "col"),
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 10.0})
    >>> rec.tactile.force().values
    array([2.])
    """
    force = force_map_N(recording, calibration=calibration).sum(_PLANE, skipna=True)
    return _named(force, "force_N", "N")


def contact_area(recording, *, threshold_kPa=0.0, calibration=None):
    """Contact area in each frame: loaded sensels x sensel area [mm2].

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model (raw allowed, see :func:`loaded_mask`).
    threshold_kPa : float, default 0
        Pressure a sensel must exceed to count as loaded.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    xarray.DataArray
        ``contact_area_mm2`` with dim ``frame``.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[0.0, 3.0], [9.0, np.nan]]]),
    ...                    dims=("frame", "row", "col"),
    ...                    attrs={"units": "raw", "sensel_area_mm2": 1.6129})
    >>> round(float(rec.tactile.area()[0]), 4)
    3.2258
    """
    mask = loaded_mask(recording, threshold_kPa=threshold_kPa, calibration=calibration)
    area = mask.sum(_PLANE) * sensel_area_mm2(recording)
    return _named(area.astype(float), "contact_area_mm2", "mm2")


def centre_of_force(recording, *, calibration=None, min_force_N=0.0):
    """Centre of force in each frame, in mm from the centre of sensel (0, 0).

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model with ``row_spacing_mm`` and ``col_spacing_mm``.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.
    min_force_N : float, default 0
        Frames whose total force is not above this are NaN: with almost no load the centre
        is the mean of noise and jumps across the sensor between steps.

    Returns
    -------
    xarray.Dataset
        ``cof_row_mm`` and ``cof_col_mm`` with dim ``frame``; NaN in frames with no force
        (or not more than ``min_force_N``).

    Notes
    -----
    ``x_c = sum_k F_k x_k / sum_k F_k`` with ``x_k = row_k * row_spacing_mm`` (and the
    same for columns): the force-weighted mean sensel position (Tekscan's centre of force).

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[0.0, 0.0], [30.0, 10.0]]]),
    ...                    dims=("frame", "row", "col"),
    ...                    attrs={"units": "N", "row_spacing_mm": 2.0, "col_spacing_mm": 4.0})
    >>> cof = rec.tactile.centre()
    >>> float(cof.cof_row_mm[0]), float(cof.cof_col_mm[0])
    (2.0, 1.0)
    """
    min_force_N = _non_negative("min_force_N", min_force_N)
    force = force_map_N(recording, calibration=calibration).fillna(0.0)
    row_mm, col_mm = spacing_mm(recording)
    rows = xr.DataArray(force["row"].values * row_mm, dims="row")
    cols = xr.DataArray(force["col"].values * col_mm, dims="col")
    total = force.sum(_PLANE)
    total = total.where((total > 0) & (total > min_force_N))
    return xr.Dataset({
        "cof_row_mm": _named((force * rows).sum(_PLANE) / total, "cof_row_mm", "mm"),
        "cof_col_mm": _named((force * cols).sum(_PLANE) / total, "cof_col_mm", "mm"),
    })


def peak_pressure(recording, *, calibration=None):
    """Highest sensel pressure in each frame [kPa] (NaN sensels skipped).

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[1.0, 0.5], [np.nan, 0.0]]]),
    ...                    dims=("frame", "row", "col"), attrs={"units": "MPa"})
    >>> rec.tactile.peak().values
    array([1000.])
    """
    peak = pressure_map_kPa(recording, calibration=calibration).max(_PLANE, skipna=True)
    return _named(peak, "peak_kPa", "kPa")


def mean_pressure(recording, *, threshold_kPa=0.0, calibration=None):
    """Mean pressure over the loaded sensels of each frame [kPa].

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model.
    threshold_kPa : float, default 0
        A sensel is loaded when its pressure is strictly above this level.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    xarray.DataArray
        ``mean_kPa`` with dim ``frame``; NaN in frames with no loaded sensel.

    Notes
    -----
    With equal sensel areas this is total force over contact area
    (``p_mean = F / A * 1e3``), the mean pressure Tekscan software reports.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[0.0, 100.0], [300.0, np.nan]]]),
    ...                    dims=("frame", "row", "col"), attrs={"units": "kPa"})
    >>> rec.tactile.mean_pressure().values
    array([200.])
    """
    pressure = pressure_map_kPa(recording, calibration=calibration)
    mean = pressure.where(pressure > threshold_kPa).mean(_PLANE, skipna=True)
    return _named(mean, "mean_kPa", "kPa")


def _non_negative(name, value):
    """Return ``value`` as a float, checked to be finite and >= 0 (else ValueError)."""
    if not np.isfinite(value) or value < 0:
        raise TactilecalError(f"{name} is {value!r}; expected a finite value >= 0")
    return float(value)


def summary(recording, *, threshold_kPa=0.0, calibration=None, cof_min_force_N=0.0):
    """Per-frame summary of a recording as one :class:`xarray.Dataset`.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model (raw needs ``calibration``).
    threshold_kPa : float, default 0
        Loaded-sensel threshold for contact area and mean pressure.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording (once).
    cof_min_force_N : float, default 0
        The centre of force is NaN in frames whose force is not above this (see
        :func:`centre_of_force`).

    Returns
    -------
    xarray.Dataset
        Variables ``force_N``, ``contact_area_mm2``, ``cof_row_mm``, ``cof_col_mm``,
        ``peak_kPa``, ``mean_kPa``, dim ``frame`` (with the ``time`` coordinate).
        ``attrs`` carry the recording's ``source`` and ``calibration_json`` when present.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[0.0, 100.0], [300.0, 0.0]]]),
    ...                    dims=("frame", "row", "col"),
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 1.0,
    ...                           "row_spacing_mm": 1.0, "col_spacing_mm": 1.0})
    >>> s = rec.tactile.frame_summary()
    >>> [round(float(s[v][0]), 3) for v in s.data_vars]
    [0.4, 2.0, 0.75, 0.25, 300.0, 200.0]
    """
    threshold_kPa = _non_negative("threshold_kPa", threshold_kPa)
    cof_min_force_N = _non_negative("cof_min_force_N", cof_min_force_N)
    pressure = pressure_map_kPa(recording, calibration=calibration)
    area_mm2 = sensel_area_mm2(recording)
    row_mm, col_mm = spacing_mm(recording)
    # one NaN-free copy, then plain sums and dot products (no temporary per quantity)
    filled = pressure.fillna(0.0)
    loaded = pressure > threshold_kPa
    n_loaded = loaded.sum(_PLANE)
    load_kPa = filled.sum(_PLANE)
    force = load_kPa * (area_mm2 * KPA_MM2_TO_N)
    weight = load_kPa.where((load_kPa > 0) & (force > cof_min_force_N))
    rows = xr.DataArray(pressure["row"].values * row_mm, dims="row")
    cols = xr.DataArray(pressure["col"].values * col_mm, dims="col")
    ds = xr.Dataset({
        "force_N": _named(force, "force_N", "N"),
        "contact_area_mm2": _named((n_loaded * area_mm2).astype(float),
                                   "contact_area_mm2", "mm2"),
        "cof_row_mm": _named(filled.dot(rows).sum("col") / weight, "cof_row_mm", "mm"),
        "cof_col_mm": _named(filled.dot(cols).sum("row") / weight, "cof_col_mm", "mm"),
        "peak_kPa": _named(pressure.max(_PLANE, skipna=True), "peak_kPa", "kPa"),
        "mean_kPa": _named(xr.dot(filled, loaded.astype(float), dim=_PLANE)
                           / n_loaded.where(n_loaded > 0), "mean_kPa", "kPa"),
    })
    ds.attrs = {k: pressure.attrs[k] for k in ("source", "calibration_json", "sensor_type")
                if k in pressure.attrs}
    ds.attrs["threshold_kPa"] = threshold_kPa
    ds.attrs["cof_min_force_N"] = cof_min_force_N
    _mark_saturation(ds, recording)
    return ds


def _mark_saturation(ds, recording):
    """Add ``saturated_sensels`` per frame; where > 0, force and pressures are lower bounds."""
    counts, rule = saturated_sensels(recording)
    ds.attrs["saturation_rule"] = rule
    if counts is None:
        return
    ds["saturated_sensels"] = counts.astype(np.int64).assign_attrs(
        long_name="saturated sensels", units="1",
        description="sensels at saturation; where > 0 the frame's force_N, peak_kPa and "
                    "mean_kPa are lower bounds")
    for name in ("force_N", "peak_kPa", "mean_kPa"):
        ds[name].attrs["lower_bound_where"] = "saturated_sensels > 0"
