"""Figures of an analysed recording: force/time, pressure map, centre of force, profiles.

matplotlib is imported inside each function (figures are built on
:class:`matplotlib.figure.Figure`, never through pyplot's global state).
"""

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal.analysis._regions import profile
from tactilecal.analysis._units import pressure_map_kPa, spacing_mm

__all__ = ["plot_force_time", "plot_pressure_map", "plot_cof_path", "plot_profiles",
           "peak_frame"]


def _axes(ax, figsize=(6, 4)):
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=figsize, layout="constrained").subplots()
    return ax


def _time(ds):
    if "time" in ds.coords:
        return np.asarray(ds["time"].values, dtype=float), "time [s]"
    return np.arange(ds.sizes["frame"], dtype=float), "frame index"


def peak_frame(summary):
    """Frame number (the file's numbering) of the frame with the largest total force.

    Examples
    --------
    >>> import xarray as xr
    >>> peak_frame(xr.Dataset({"force_N": ("frame", [1.0, 5.0, 2.0])},
    ...                       coords={"frame": [7, 8, 9]}))
    8
    """
    return int(summary["frame"].values[_peak_position(summary)])


def _peak_position(summary):
    """0-based position of the frame with the largest total force (0 if none is finite)."""
    force = np.asarray(summary["force_N"].values, dtype=float)
    if not np.isfinite(force).any():
        return 0
    return int(np.nanargmax(force))


def _one_frame(recording, frame, position, *, required):
    """Return the recording at frame number ``frame`` or 0-based ``position`` (one at most)."""
    if frame is not None and position is not None:
        raise TactilecalError(f"frame={frame} and position={position}; expected one of them")
    if position is not None:
        return recording.isel(frame=[position])
    if frame is None:
        if required:
            raise TactilecalError("no frame given; expected frame= (the file's frame number) "
                                  "or position= (0-based)")
        return None
    numbers = recording["frame"].values
    if frame not in numbers:
        raise TactilecalError(f"frame={frame} is not a frame of the recording (frames "
                              f"{numbers[0]}..{numbers[-1]}); expected one of its frame numbers "
                              "(position= takes a 0-based position)")
    return recording.sel(frame=[frame])


def plot_force_time(summary, *, ax=None):
    """Total force [N] and contact area [mm2] against time, from :func:`summary`.

    Returns
    -------
    matplotlib.axes.Axes
        The force axes (contact area is on a twin axis on the right).
    """
    ax = _axes(ax)
    t, label = _time(summary)
    ax.plot(t, summary["force_N"].values, color="C0", label="total force")
    ax.set_xlabel(label)
    ax.set_ylabel("total force [N]", color="C0")
    twin = ax.twinx()
    twin.plot(t, summary["contact_area_mm2"].values, color="C1", lw=1, alpha=0.8)
    twin.set_ylabel("contact area [mm2]", color="C1")
    i = _peak_position(summary)
    ax.axvline(t[i], color="0.5", ls=":", lw=1)
    ax.set_title(f"peak {float(summary['force_N'][i]):.4g} N at {label.split()[0]} {t[i]:.4g}")
    return ax


def plot_pressure_map(recording, frame=None, *, position=None, calibration=None, ax=None):
    """Pressure map [kPa] of one frame, or the peak pressure of every sensel over the recording.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model. A raw recording without ``calibration`` is drawn in
        raw readings (0..255).
    frame : int, optional
        The file's frame number (``recording.frame``); default: the peak-pressure map
        (each sensel's largest value over all frames).
    position : int, optional
        The frame's 0-based position instead of its number.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    matplotlib.axes.Axes
    """
    one = _one_frame(recording, frame, position, required=False)
    ax = _axes(ax, figsize=(5, 5))
    one = recording if one is None else one
    raw = recording.attrs.get("units") == "raw" and calibration is None
    values = one if raw else pressure_map_kPa(one, calibration=calibration)
    values = values.max("frame", skipna=True)
    row_mm, col_mm = spacing_mm(recording)
    rows, cols = values.shape
    extent = (-col_mm / 2, (cols - 0.5) * col_mm, (rows - 0.5) * row_mm, -row_mm / 2)
    image = ax.imshow(np.asarray(values.values, dtype=float), extent=extent,
                      cmap="viridis", interpolation="nearest")
    ax.figure.colorbar(image, ax=ax, label="raw reading" if raw else "pressure [kPa]")
    ax.set_xlabel("column [mm]")
    ax.set_ylabel("row [mm]")
    ax.set_title("peak over all frames" if one is recording
                 else f"frame {one['frame'].values[0]}")
    return ax


def plot_cof_path(summary, *, min_force_N=None, ax=None):
    """Centre-of-force path (column mm across, row mm down), coloured by time.

    Parameters
    ----------
    summary : xarray.Dataset
        From :func:`summary`.
    min_force_N : float, optional
        Frames with a total force below this are not drawn (the line breaks there): with
        almost no load the centre is noise. Default 5 % of the peak force.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax, figsize=(5, 5))
    t, label = _time(summary)
    force = np.asarray(summary["force_N"].values, dtype=float)
    if min_force_N is None:
        min_force_N = 0.05 * float(np.nanmax(force)) if np.isfinite(force).any() else 0.0
    keep = force >= min_force_N
    x = np.where(keep, summary["cof_col_mm"].values, np.nan)
    y = np.where(keep, summary["cof_row_mm"].values, np.nan)
    ax.plot(x, y, color="0.7", lw=0.8)
    points = ax.scatter(x, y, c=t, s=10, cmap="plasma")
    ax.figure.colorbar(points, ax=ax, label=label)
    ax.set_xlabel("centre of force, column [mm]")
    ax.set_ylabel("centre of force, row [mm]")
    ax.set_title(f"{int(np.sum(keep & np.isfinite(x)))} of {force.size} frames with force "
                 f">= {min_force_N:.3g} N")
    ax.invert_yaxis()
    ax.set_aspect("equal", adjustable="datalim")
    return ax


def plot_profiles(recording, frame=None, *, position=None, nonworking=None, calibration=None,
                  axes=None):
    """Row and column profiles (means skipping blank/non-working sensels) of one frame.

    The frame is ``frame``, the file's frame number, or ``position``, its 0-based position.

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes
        The row-profile and the column-profile axes.
    """
    if axes is None:
        from matplotlib.figure import Figure

        axes = Figure(figsize=(9, 3.5), layout="constrained").subplots(1, 2)
    one = _one_frame(recording, frame, position, required=True)
    rows = profile(one, "row", nonworking=nonworking, calibration=calibration)[0]
    cols = profile(one, "col", nonworking=nonworking, calibration=calibration)[0]
    axes[0].plot(rows.values, rows["row_mm"].values, "o-", ms=3)
    axes[0].invert_yaxis()
    axes[0].set_xlabel("mean row pressure [kPa]")
    axes[0].set_ylabel("row [mm]")
    axes[1].plot(cols["col_mm"].values, cols.values, "o-", ms=3)
    axes[1].set_xlabel("column [mm]")
    axes[1].set_ylabel("mean column pressure [kPa]")
    return axes


