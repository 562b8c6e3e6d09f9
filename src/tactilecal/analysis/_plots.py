"""Figures of an analysed recording: force/time, pressure map, centre of force, profiles.

matplotlib is imported inside each function (figures are built on
:class:`matplotlib.figure.Figure`, never through pyplot's global state).
"""

import numpy as np

from tactilecal.analysis._regions import column_profile, row_profile
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
    """Index (0-based position) of the frame with the largest total force.

    Examples
    --------
    >>> import xarray as xr
    >>> peak_frame(xr.Dataset({"force_N": ("frame", [1.0, 5.0, 2.0])}))
    1
    """
    force = np.asarray(summary["force_N"].values, dtype=float)
    if not np.isfinite(force).any():
        return 0
    return int(np.nanargmax(force))


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
    i = peak_frame(summary)
    ax.axvline(t[i], color="0.5", ls=":", lw=1)
    ax.set_title(f"peak {float(summary['force_N'][i]):.4g} N at {label.split()[0]} {t[i]:.4g}")
    return ax


def plot_pressure_map(recording, frame, *, calibration=None, ax=None):
    """Pressure map [kPa] of one frame (0-based position), NaN sensels left blank.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax, figsize=(5, 5))
    pressure = pressure_map_kPa(recording.isel(frame=[frame]), calibration=calibration)[0]
    row_mm, col_mm = spacing_mm(recording)
    rows, cols = pressure.shape
    extent = (-col_mm / 2, (cols - 0.5) * col_mm, (rows - 0.5) * row_mm, -row_mm / 2)
    image = ax.imshow(np.asarray(pressure.values, dtype=float), extent=extent,
                      cmap="viridis", interpolation="nearest")
    ax.figure.colorbar(image, ax=ax, label="pressure [kPa]")
    ax.set_xlabel("column [mm]")
    ax.set_ylabel("row [mm]")
    ax.set_title(f"frame {recording['frame'].values[frame]}")
    return ax


def plot_cof_path(summary, *, ax=None):
    """Centre-of-force path (column mm across, row mm down), coloured by time.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax, figsize=(5, 5))
    t, label = _time(summary)
    x = summary["cof_col_mm"].values
    y = summary["cof_row_mm"].values
    ax.plot(x, y, color="0.7", lw=0.8)
    points = ax.scatter(x, y, c=t, s=10, cmap="plasma")
    ax.figure.colorbar(points, ax=ax, label=label)
    ax.set_xlabel("centre of force, column [mm]")
    ax.set_ylabel("centre of force, row [mm]")
    ax.invert_yaxis()
    ax.set_aspect("equal", adjustable="datalim")
    return ax


def plot_profiles(recording, frame, *, nonworking=None, calibration=None, axes=None):
    """Row and column profiles (means skipping blank/non-working sensels) of one frame.

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes
        The row-profile and the column-profile axes.
    """
    if axes is None:
        from matplotlib.figure import Figure

        axes = Figure(figsize=(9, 3.5), layout="constrained").subplots(1, 2)
    one = recording.isel(frame=[frame])
    rows = row_profile(one, nonworking=nonworking, calibration=calibration)[0]
    cols = column_profile(one, nonworking=nonworking, calibration=calibration)[0]
    axes[0].plot(rows.values, rows["row_mm"].values, "o-", ms=3)
    axes[0].invert_yaxis()
    axes[0].set_xlabel("mean row pressure [kPa]")
    axes[0].set_ylabel("row [mm]")
    axes[1].plot(cols["col_mm"].values, cols.values, "o-", ms=3)
    axes[1].set_xlabel("column [mm]")
    axes[1].set_ylabel("mean column pressure [kPa]")
    return axes


