"""Figures of an analysed recording: force/time, pressure map, centre of force, profiles.

matplotlib is imported inside each function (figures are built on
:class:`matplotlib.figure.Figure`, never through pyplot's global state). Every map marks its
saturated sensels and shows the centre of force over the map at the sensor's own scale;
pressures are shown in the recording's own pressure unit or the one asked for (``units=``).
"""

import numpy as np

from tactilecal._contact import CONTACT_FORCE_SHARE
from tactilecal._errors import TactilecalError
from tactilecal.analysis._regions import profile
from tactilecal.analysis._units import (
    display_unit,
    force_map_N,
    pressure_map_kPa,
    saturation_mask,
    spacing_mm,
)

__all__ = ["plot_force_time", "plot_pressure_map", "plot_cof_path", "plot_profiles",
           "plot_cof_time", "plot_step_paths", "plot_region_forces", "plot_region_centres",
           "peak_frame", "map_figsize", "draw_map"]

SATURATED_STYLE = {"marker": "x", "color": "red", "s": 14, "linewidths": 0.9}
"""How saturated sensels are marked on every map."""


def _axes(ax, figsize=(6, 4), layout="constrained"):
    """Return ``ax``, or new axes; maps use the "compressed" layout (for fixed aspects)."""
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=figsize, layout=layout).subplots()
    return ax


def _time(ds):
    if "time" in ds.coords:
        return np.asarray(ds["time"].values, dtype=float), "time [s]"
    return np.arange(ds.sizes["frame"], dtype=float), "frame index"


def map_figsize(recording, width=5.0):
    """Return a figure size that fits the sensor's aspect (a colour bar as tall as the map).

    Examples
    --------
    >>> import xarray as xr
    >>> rec = xr.DataArray(np.zeros((1, 60, 21)), dims=("frame", "row", "col"),
    ...                    attrs={"row_spacing_mm": 5.08, "col_spacing_mm": 5.08})
    >>> map_figsize(rec)
    (3.4, 6.5)
    """
    row_mm, col_mm = spacing_mm(recording)
    aspect = recording.sizes["row"] * row_mm / (recording.sizes["col"] * col_mm)
    map_w = min(width - 1.5, 5.5 / max(aspect, 1e-3))
    height = float(np.clip(map_w * aspect + 1.0, 2.5, 6.5))
    return (round(float(map_w + 1.5), 1), round(height, 1))


def peak_frame(summary):
    """Frame number (the file's numbering) of the frame with the largest total force.

    Examples
    --------
    >>> import xarray as xr
    >>> peak_frame(xr.Dataset({"force_N": ("frame", [1.0, 5.0, 2.0])},
    ...                       coords={"frame": [7, 8, 9]}))
    8
    """
    return int(summary["frame"].values[peak_position(summary)])


def peak_position(summary):
    """0-based position of the frame with the largest total force (0 if none is finite)."""
    force = np.asarray(summary["force_N"].values, dtype=float)
    if not np.isfinite(force).any():
        return 0
    return int(np.nanargmax(force))


def frame_position(recording, frame, position, *, required):
    """Return the 0-based position of frame number ``frame`` or of ``position`` (or None)."""
    if frame is not None and position is not None:
        raise TactilecalError(f"frame={frame} and position={position}; expected one of them")
    numbers = recording["frame"].values
    if position is not None:
        if not -len(numbers) <= position < len(numbers):
            raise TactilecalError(f"position={position} is outside the recording's "
                                  f"{len(numbers)} frames; expected 0..{len(numbers) - 1}")
        return int(position) % len(numbers)
    if frame is None:
        if required:
            raise TactilecalError("no frame given; expected frame= (the file's frame number) "
                                  "or position= (0-based)")
        return None
    if frame not in numbers:
        raise TactilecalError(f"frame={frame} is not a frame of the recording (frames "
                              f"{numbers[0]}..{numbers[-1]}); expected one of its frame numbers "
                              "(position= takes a 0-based position)")
    return int(np.flatnonzero(numbers == frame)[0])


def plot_force_time(summary, *, ax=None):
    """Total force [N] and contact area [mm2] against time, from :func:`summary`.

    Frames holding saturated sensels (a ``saturated_sensels`` variable above 0) are marked
    with red ticks along the bottom: their force is a lower bound.

    Returns
    -------
    matplotlib.axes.Axes
        The force axes (contact area is on a twin axis on the right).
    """
    from tactilecal._text import number

    ax = _axes(ax)
    t, label = _time(summary)
    ax.plot(t, summary["force_N"].values, color="C0", label="total force")
    ax.set_xlabel(label)
    ax.set_ylabel("total force [N]", color="C0")
    twin = ax.twinx()
    twin.plot(t, summary["contact_area_mm2"].values, color="C1", lw=1, alpha=0.8)
    twin.set_ylabel("contact area [mm2]", color="C1")
    i = peak_position(summary)
    ax.axvline(t[i], color="0.5", ls=":", lw=1)
    _mark_saturated_frames(ax, t, summary)
    ax.set_title(f"peak {number(float(summary['force_N'][i]))} N at {label.split()[0]} "
                 f"{number(t[i])}")
    return ax


def _mark_saturated_frames(ax, t, summary):
    if "saturated_sensels" not in summary:
        return
    hit = np.asarray(summary["saturated_sensels"].values) > 0
    if hit.any():
        ax.plot(t[hit], np.zeros(hit.sum()), "|", color="red", ms=10, mew=1.5,
                transform=ax.get_xaxis_transform(), clip_on=False,
                label=f"saturated frames ({int(hit.sum())})")
        ax.legend(loc="upper right", fontsize="small", frameon=False)


def draw_map(ax, recording, values, *, label, saturated=None, cmap="viridis", vmax=None):
    """Draw a ``(row, col)`` map at the sensor's scale in mm, saturated sensels marked.

    Returns the image (for a colour bar).
    """
    row_mm, col_mm = spacing_mm(recording)
    rows, cols = values.shape
    extent = (-col_mm / 2, (cols - 0.5) * col_mm, (rows - 0.5) * row_mm, -row_mm / 2)
    image = ax.imshow(np.asarray(values, dtype=float), extent=extent, cmap=cmap,
                      interpolation="nearest", vmin=0, vmax=vmax)
    if saturated is not None and np.any(saturated):
        r, c = np.nonzero(saturated)
        ax.scatter(c * col_mm, r * row_mm, label=f"saturated ({r.size} sensels)",
                   **SATURATED_STYLE)
        ax.legend(loc="upper right", fontsize="x-small", frameon=True, framealpha=0.8)
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    ax.set_xlabel("column [mm]")
    ax.set_ylabel("row [mm]")
    ax.figure.colorbar(image, ax=ax, label=label, shrink=1.0, aspect=25)
    return image


def _map_values(recording, frame, calibration, units):
    """Return the map to show (a frame or each sensel's peak), its label, saturated sensels."""
    one = recording if frame is None else recording.isel(frame=[frame])
    raw = recording.attrs.get("units") == "raw" and calibration is None
    if raw:
        values, label = one, "raw reading"
    else:
        unit, factor = display_unit(recording, units)
        values, label = pressure_map_kPa(one, calibration=calibration) / factor, \
            f"pressure [{unit}]"
    mask, _ = saturation_mask(one)
    saturated = None if mask is None else np.asarray(mask.any("frame").values)
    return np.asarray(values.max("frame", skipna=True).values, float), label, saturated


def plot_pressure_map(recording, frame=None, *, position=None, calibration=None, ax=None,
                      units=None, centre=True, summary=None):
    """Pressure map of one frame, or the peak pressure of every sensel over the recording.

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
    units : str, optional
        Pressure unit shown (default: the recording's own pressure unit, else kPa).
    centre : bool, default True
        Draw the centre of force: a white cross at that frame's, or over the peak map the
        path of every frame with at least 5 % of the peak force.
    summary : xarray.Dataset, optional
        The recording's :func:`summary` if already computed: the centre of force is then
        its ``cof_row_mm``, ``cof_col_mm`` (not computed again from the maps).

    Returns
    -------
    matplotlib.axes.Axes
        Saturated sensels (of that frame, or of any frame) are red crosses.
    """
    at = frame_position(recording, frame, position, required=False)
    ax = _axes(ax, figsize=map_figsize(recording), layout="compressed")
    values, label, saturated = _map_values(recording, at, calibration, units)
    draw_map(ax, recording, values, label=label, saturated=saturated)
    ax.set_title("peak over all frames" if at is None
                 else f"frame {recording['frame'].values[at]}")
    if centre:
        x, y = _centre_path(recording, calibration) if summary is None \
            else _kept_centres(summary)
        if at is None:
            ax.plot(x, y, color="white", lw=1.2, label="centre of force")
        elif np.isfinite(x[at]):
            ax.plot(x[at], y[at], "P", color="white", mec="black", ms=9,
                    label="centre of force")
    return ax


def _centre_path(recording, calibration):
    """Centre of force of every frame with at least 5 % of the peak (NaN elsewhere), in mm.

    A raw recording without a calibration is weighed by its raw readings.
    """
    import xarray as xr

    if recording.attrs.get("units") == "raw" and calibration is None:
        weight = recording.fillna(0.0)
    else:
        weight = force_map_N(recording, calibration=calibration).fillna(0.0)
    row_mm, col_mm = spacing_mm(recording)
    total = weight.sum(("row", "col"))
    total = total.where((total > 0) & (total >= CONTACT_FORCE_SHARE * float(total.max())))
    rows = xr.DataArray(np.arange(weight.sizes["row"]) * row_mm, dims="row")
    cols = xr.DataArray(np.arange(weight.sizes["col"]) * col_mm, dims="col")
    return (np.asarray(((weight * cols).sum(("row", "col")) / total).values, float),
            np.asarray(((weight * rows).sum(("row", "col")) / total).values, float))


def _min_force(force, min_force_N=None):
    """``min_force_N``, by default 5 % of the largest finite ``force`` (0 if none is)."""
    if min_force_N is not None:
        return min_force_N
    return CONTACT_FORCE_SHARE * float(np.nanmax(force)) if np.isfinite(force).any() else 0.0


def _kept_centres(summary, min_force_N=None):
    """Centre of force ``(column, row)`` [mm] of a :func:`summary` where it is not noise.

    NaN in frames with less force than ``min_force_N`` (default 5 % of the peak force).
    """
    force = np.asarray(summary["force_N"].values, dtype=float)
    keep = force >= _min_force(force, min_force_N)
    return (np.where(keep, summary["cof_col_mm"].values, np.nan),
            np.where(keep, summary["cof_row_mm"].values, np.nan))


def plot_cof_path(summary, *, recording=None, min_force_N=None, ax=None, units=None):
    """Centre-of-force path over the peak-pressure map, at the sensor's scale, by time.

    Parameters
    ----------
    summary : xarray.Dataset
        From :func:`summary`.
    recording : xarray.DataArray, optional
        The recording (calibrated): its peak-pressure map is drawn under the path and sets
        the scale (the whole sensor), so noise never looks like motion. Without it the
        axes span at least 10 sensel pitches... of the summary's own extent.
    min_force_N : float, optional
        Frames with a total force below this are not drawn (the line breaks there): with
        almost no load the centre is noise. Default 5 % of the peak force.
    units : str, optional
        Pressure unit of the map (default: the recording's own, else kPa).

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax, figsize=(5, 5) if recording is None else map_figsize(recording),
               layout="compressed")
    t, label = _time(summary)
    force = np.asarray(summary["force_N"].values, dtype=float)
    min_force_N = _min_force(force, min_force_N)
    x, y = _kept_centres(summary, min_force_N)
    keep = force >= min_force_N
    if recording is not None:
        values, map_label, saturated = _map_values(recording, None, None, units)
        draw_map(ax, recording, values, label=map_label, saturated=saturated, cmap="Greys")
    ax.plot(x, y, color="0.4", lw=0.8)
    points = ax.scatter(x, y, c=t, s=10, cmap="plasma", zorder=3)
    ax.figure.colorbar(points, ax=ax, label=label, location="bottom", aspect=30, shrink=0.9)
    from tactilecal._text import number

    ax.set_title(f"{int(np.sum(keep & np.isfinite(x)))} of {force.size} frames with force "
                 f">= {number(min_force_N)} N", fontsize="small")
    if recording is None:
        ax.set_xlabel("centre of force, column [mm]")
        ax.set_ylabel("centre of force, row [mm]")
        ax.invert_yaxis()
        ax.set_aspect("equal", adjustable="datalim")
    return ax


def plot_cof_time(summary, *, ax=None):
    """Centre of force (row and column, mm) against time."""
    ax = _axes(ax, figsize=(6, 3.2))
    t, label = _time(summary)
    ax.plot(t, summary["cof_row_mm"].values, label="row [mm]")
    ax.plot(t, summary["cof_col_mm"].values, label="column [mm]")
    ax.set(xlabel=label, ylabel="centre of force [mm]")
    ax.legend(frameon=False, fontsize="small")
    return ax


def plot_profiles(recording, frame=None, *, position=None, nonworking=None, calibration=None,
                  axes=None, units=None):
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
    unit, factor = display_unit(recording, units)
    one = recording.isel(frame=[frame_position(recording, frame, position, required=True)])
    rows = profile(one, "row", nonworking=nonworking, calibration=calibration)[0]
    cols = profile(one, "col", nonworking=nonworking, calibration=calibration)[0]
    axes[0].plot(rows.values / factor, rows["row_mm"].values, "o-", ms=3)
    axes[0].invert_yaxis()
    axes[0].set_xlabel(f"mean row pressure [{unit}]")
    axes[0].set_ylabel("row [mm]")
    axes[1].plot(cols["col_mm"].values, cols.values / factor, "o-", ms=3)
    axes[1].set_xlabel("column [mm]")
    axes[1].set_ylabel(f"mean column pressure [{unit}]")
    return axes


def plot_step_paths(steps, *, ax=None, recording=None):
    """Each step's centre-of-pressure path, numbered, over the peak map when given."""
    ax = _axes(ax, figsize=(5, 5) if recording is None else map_figsize(recording),
               layout="compressed")
    if recording is not None:
        values, label, saturated = _map_values(recording, None, None, None)
        draw_map(ax, recording, values, label=label, saturated=saturated, cmap="Greys")
    for k, path in enumerate(steps.paths, 1):
        line, = ax.plot(path["cof_col_mm"], path["cof_row_mm"], lw=1.2, label=f"step {k}")
        if len(path):
            ax.plot(path["cof_col_mm"].iloc[0], path["cof_row_mm"].iloc[0], "o",
                    color=line.get_color(), ms=4)
    if recording is None:
        ax.invert_yaxis()
        ax.set_aspect("equal", adjustable="datalim")
        ax.set(xlabel="column [mm]", ylabel="row [mm]")
    if steps.paths:
        ax.legend(fontsize="x-small", frameon=False, loc="lower left")
    return ax


def plot_region_forces(analysis, *, ax=None):
    """Force of every region against time; their sum dashed when they cover the sensor."""
    ax = _axes(ax, figsize=(6.5, 3.6))
    ds = analysis.summary
    t, label = _time(ds)
    for name in analysis.regions:
        ax.plot(t, ds["force_N"].sel(region=name).values, lw=1.2, label=name)
    if analysis.regions.is_partition() and len(analysis.regions) > 1:
        ax.plot(t, ds["force_N"].sum("region").values, "--", color="0.3", lw=0.9,
                label="sum (= total)")
    ax.set(xlabel=label, ylabel="force [N]")
    ax.legend(fontsize="small", frameon=False)
    return ax


def plot_region_centres(analysis, recording, *, ax=None, units=None, min_force_N=None):
    """Each region's outline and centre-of-force path over the recording's peak map."""
    ax = _axes(ax, figsize=map_figsize(recording), layout="compressed")
    values, label, saturated = _map_values(recording, None, None, units)
    draw_map(ax, recording, values, label=label, saturated=saturated, cmap="Greys")
    row_mm, col_mm = spacing_mm(recording)
    ds = analysis.summary
    for k, (name, mask) in enumerate(analysis.regions.items()):
        colour = f"C{k % 10}"
        ax.contour(np.arange(mask.shape[1]) * col_mm, np.arange(mask.shape[0]) * row_mm,
                   mask.astype(float), levels=[0.5], colors=[colour], linewidths=0.8)
        force = np.asarray(ds["force_N"].sel(region=name).values, float)
        limit = CONTACT_FORCE_SHARE * np.nanmax(force) if min_force_N is None else min_force_N
        keep = force >= limit
        ax.plot(np.where(keep, ds["cof_col_mm"].sel(region=name).values, np.nan),
                np.where(keep, ds["cof_row_mm"].sel(region=name).values, np.nan),
                color=colour, lw=1.5, label=f"{name}: centre of force")
    ax.legend(fontsize="x-small", frameon=True, framealpha=0.8, loc="lower left")
    return ax
