"""What a recording holds, and its per-frame table with the headline numbers.

:func:`describe` is the summary ``tactilecal info`` prints; :func:`frame_table` and
:func:`overview` are the table and headline numbers of ``tactilecal analyze``. Each returns
plain data (a JSON-ready dict or a DataFrame); the command line only formats it.
"""

import numpy as np
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._units import N_PER_MM2_TO_KPA, pressure_to_kPa, unit_kind
from tactilecal.analysis._maps import summary
from tactilecal.analysis._units import saturation_threshold
from tactilecal.io import header_law

__all__ = ["FRAME_COLUMNS", "describe", "frame_table", "overview"]

_CALIBRATION_PREFIXES = ("calibration_point_", "calibration_mode_", "saturation_pressure",
                         "scale_factor", "exponent")

FRAME_COLUMNS = ("force_N", "contact_area_mm2", "cof_row_mm", "cof_col_mm", "peak_kPa",
                 "mean_kPa")
"""The per-frame quantities of :func:`frame_table` (after ``frame`` and ``time_s``)."""


def describe(recording):
    """Summarise what a recording holds, as a JSON-ready dict.

    Parameters
    ----------
    recording : xarray.DataArray
        A recording as returned by :func:`tactilecal.io.read_tekscan`.

    Returns
    -------
    dict
        Keys ``file, sensor_type, catalogue_sensor, catalogue_match, rows, cols, sensels,
        frames, first_frame, last_frame, duration_s, seconds_per_frame, units,
        row_spacing_mm, col_spacing_mm, sensel_area_mm2, sensitivity, noise_threshold,
        calibration, blank_sensels, never_loaded_sensels, max_value, max_raw,
        max_raw_source, saturation_rule, saturated_frames, saturated_frame_numbers``.

    Notes
    -----
    A blank sensel is NaN in every frame (outside the sensor shape); a never-loaded sensel
    exists but never reads above 0. For calibrated files ``max_raw`` is the largest value
    turned back into raw units through the header's calibration where it can be inverted:
    ``SCALE_FACTOR``/``EXPONENT`` (p = SCALE_FACTOR x raw^EXPONENT) or a single
    ``CALIBRATION_POINT_1`` (linear through zero, p = load_N / (raw_sum x sensel_area_mm2)
    per raw count); else None (also for a largest value below 0, or one so large that no
    finite reading gives it).

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[0.0, 7.0], [np.nan, 255.0]]]),
    ...                    dims=("frame", "row", "col"),
    ...                    coords={"frame": [1], "time": ("frame", [0.0])},
    ...                    attrs={"units": "raw"})
    >>> d = rec.tactile.describe()
    >>> d["blank_sensels"], d["never_loaded_sensels"], d["max_raw"], d["saturated_frames"]
    (1, 1, 255.0, 1)
    """
    from tactilecal.sensors import match_sensor

    # NumPy only: an xarray operation on a new process imports dask.array and SciPy
    attrs, values = recording.attrs, recording.values
    blank = np.isnan(values).all(axis=0)
    never_loaded = ~blank & ~(np.nan_to_num(values, nan=0.0) > 0).any(axis=0)
    sizes = recording.sizes
    times = recording.coords.variables["time"].values
    frames = recording.coords.variables["frame"].values
    threshold, rule = saturation_threshold(recording)
    saturated = None if threshold is None else (values >= threshold).any(axis=(1, 2))
    match = match_sensor(attrs.get("sensor_type"), rows=sizes["row"], cols=sizes["col"],
                         row_spacing_mm=attrs.get("row_spacing_mm"),
                         col_spacing_mm=attrs.get("col_spacing_mm"))
    finite = values[np.isfinite(values)]
    max_value = float(finite.max()) if finite.size else None
    return {
        "file": attrs.get("source"), "sensor_type": attrs.get("sensor_type"),
        "catalogue_sensor": None if match.entry is None else match.entry.name,
        "catalogue_match": match.how, "rows": sizes["row"], "cols": sizes["col"],
        "sensels": sizes["row"] * sizes["col"], "frames": sizes["frame"],
        "first_frame": int(frames[0]) if sizes["frame"] else None,
        "last_frame": int(frames[-1]) if sizes["frame"] else None,
        "duration_s": float(times[-1] - times[0]) if times.size else None,
        **{key: attrs.get(key) for key in (
            "seconds_per_frame", "units", "row_spacing_mm", "col_spacing_mm",
            "sensel_area_mm2", "sensitivity", "noise_threshold")},
        "calibration": {k: v for k, v in attrs.items() if k.startswith(_CALIBRATION_PREFIXES)},
        "blank_sensels": int(blank.sum()), "never_loaded_sensels": int(never_loaded.sum()),
        "max_value": max_value, **_max_raw(max_value, attrs), "saturation_rule": rule,
        "saturated_frames": None if saturated is None else int(saturated.sum()),
        "saturated_frame_numbers": (None if saturated is None
                                    else frames[saturated].tolist()),
    }


def _max_raw(max_value, attrs):
    """Return the largest value as a raw reading and how it was found (see :func:`describe`).

    A calibrated export is inverted through the law its header states
    (:func:`tactilecal.io.header_law`: no fit, so no SciPy to import), and the reading
    rounded to the whole number the sensor gave.
    """
    units = attrs.get("units")
    if max_value is None or units == "raw":
        return {"max_raw": max_value, "max_raw_source": "file" if max_value is not None else None}
    if units is None or unit_kind(units) != "pressure":
        return {"max_raw": None, "max_raw_source": None}
    try:
        law = header_law(attrs)
    except TactilecalError:  # no calibration in the header: no raw reading to give
        return {"max_raw": None, "max_raw_source": None}
    force_N = pressure_to_kPa(max_value, units) * law.sensel_area_mm2 / N_PER_MM2_TO_KPA
    with np.errstate(over="ignore"):
        raw = law.raw_of_force_N(force_N) if force_N >= 0 else np.nan
    if not np.isfinite(raw):  # below zero, or beyond any reading the law gives
        return {"max_raw": None, "max_raw_source": None}
    return {"max_raw": int(np.rint(raw)),
            "max_raw_source": f"inverted header calibration ({law.method})"}


def frame_table(recording, *, calibration=None, threshold_kPa=0.0):
    """Return the recording's per-frame summary as a DataFrame, one row per frame.

    Parameters
    ----------
    recording : xarray.DataArray or xarray.Dataset
        Recording in the data model (raw needs ``calibration``), or its :func:`summary`
        already computed (then ``calibration`` and ``threshold_kPa`` are not used).
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.
    threshold_kPa : float, default 0
        Loaded-sensel threshold for contact area and mean pressure.

    Returns
    -------
    pandas.DataFrame
        Columns ``frame``, ``time_s`` (NaN without a time coordinate), then
        :data:`FRAME_COLUMNS`, then ``saturated_sensels`` when the recording says what
        saturation is (:func:`saturated_sensels`).

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[0.0, 100.0]], [[50.0, 50.0]]]),
    ...                    dims=("frame", "row", "col"),
    ...                    coords={"frame": [1, 2], "time": ("frame", [0.0, 0.1])},
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 10.0,
    ...                           "row_spacing_mm": 1.0, "col_spacing_mm": 1.0})
    >>> table = rec.tactile.frame_table()
    >>> table[["frame", "time_s", "force_N", "contact_area_mm2"]].values.tolist()
    [[1.0, 0.0, 1.0, 10.0], [2.0, 0.1, 1.0, 20.0]]
    """
    ds = recording if isinstance(recording, xr.Dataset) else summary(
        recording, calibration=calibration, threshold_kPa=threshold_kPa)
    ds = ds.compute()
    table = ds.to_dataframe().reset_index()
    if "frame" not in table:
        table["frame"] = np.arange(1, len(table) + 1)
    table["time_s"] = table["time"] if "time" in table else np.nan
    extra = ["saturated_sensels"] if "saturated_sensels" in table else []
    return table[["frame", "time_s", *FRAME_COLUMNS, *extra]]


def overview(table, *, source=None):
    """Return the headline numbers of a per-frame table as a JSON-ready dict.

    Parameters
    ----------
    table : pandas.DataFrame or xarray.Dataset
        ``recording.tactile.frame_table()``, or ``recording.tactile.frame_summary()`` (whose
        table it then makes).
    source : str, optional
        The recording's name, stored under ``file``.

    Returns
    -------
    dict
        ``file, frames, duration_s, peak_force_N, peak_force_frame, peak_force_time_s,
        mean_force_N, max_contact_area_mm2, max_pressure_kPa, saturated_frames,
        peak_force_is_lower_bound, max_pressure_is_lower_bound`` (the last three None when
        saturation is unknown). A frame with saturated sensels has an unknown force above
        its reading, so as soon as one frame is saturated the recording's peak force and
        largest pressure are lower bounds, whichever frame they were read in.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[0.0, 100.0]], [[50.0, 250.0]]]),
    ...                    dims=("frame", "row", "col"),
    ...                    coords={"frame": [1, 2], "time": ("frame", [0.0, 0.1])},
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 10.0,
    ...                           "row_spacing_mm": 1.0, "col_spacing_mm": 1.0})
    >>> o = overview(rec.tactile.frame_table(), source="press.csv")
    >>> o["peak_force_N"], o["peak_force_frame"], o["max_pressure_kPa"]
    (3.0, 2, 250.0)
    """
    if isinstance(table, xr.Dataset):
        table = frame_table(table)
    force = table["force_N"].to_numpy(float)
    i = int(np.nanargmax(force)) if np.isfinite(force).any() else 0
    return {
        "file": source, "frames": len(table),
        "duration_s": float(table["time_s"].iloc[-1] - table["time_s"].iloc[0])
        if len(table) else None,
        "peak_force_N": float(force[i]), "peak_force_frame": int(table["frame"].iloc[i]),
        "peak_force_time_s": float(table["time_s"].iloc[i]),
        "mean_force_N": float(np.nanmean(force)),
        "max_contact_area_mm2": float(table["contact_area_mm2"].max()),
        "max_pressure_kPa": float(table["peak_kPa"].max()),
        **_saturation(table),
    }


def _saturation(table):
    """Saturated frames, and whether the peak force is a lower bound (None: unknown)."""
    if "saturated_sensels" not in table:
        return {"saturated_frames": None, "peak_force_is_lower_bound": None,
                "max_pressure_is_lower_bound": None}
    saturated = int((table["saturated_sensels"].to_numpy() > 0).sum())
    return {"saturated_frames": saturated, "peak_force_is_lower_bound": saturated > 0,
            "max_pressure_is_lower_bound": saturated > 0}
