"""The figures of a recording written as PNG files (``tactilecal plot REC --out DIR``)."""

from pathlib import Path

from tactilecal._png import FIGURE_DPI, write_png
from tactilecal.analysis import _plots

__all__ = ["save_figures"]


def save_figures(recording, folder, *, frame=None, calibration=None, units=None, regions=None,
                 gap_mm=None, dpi=FIGURE_DPI):
    """Write the figures of a recording as PNG files into ``folder``.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model; a raw one without ``calibration`` is drawn in raw
        readings (maps only: force needs a calibration).
    folder : str or os.PathLike
        An existing folder.
    frame : int, optional
        The file's frame number to draw (default the frame of largest total force).
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.
    units : str, optional
        Pressure unit of the maps (default the recording's own pressure unit, else kPa).
    regions : Regions, dict or "contacts", optional
        Also draw each region's force against time and its centre of force over the map.
    gap_mm : float, optional
        For ``regions="contacts"``.
    dpi : int, optional
        Resolution.

    Returns
    -------
    list of pathlib.Path
        ``frame.png`` (that frame's pressure map and centre of force), ``peak_map.png``
        (each sensel's peak, the centre-of-force path), ``force_time.png`` (force and
        contact area), ``cof_time.png`` (centre of force against time), ``cof_path.png``,
        and with regions ``region_forces.png`` and ``region_centres.png``.

    Raises
    ------
    TactilecalError
        A frame number that is not in the recording.

    Examples
    --------
    >>> import tempfile, numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.ones((2, 3, 3)), dims=("frame", "row", "col"),
    ...                    coords={"frame": [1, 2], "time": ("frame", [0.0, 0.1])},
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 1.0,
    ...                           "row_spacing_mm": 1.0, "col_spacing_mm": 1.0})
    >>> [p.name for p in save_figures(rec, tempfile.mkdtemp(), dpi=20)][:3]
    ['frame.png', 'peak_map.png', 'force_time.png']
    """
    from tactilecal.analysis._contacts import region_analysis
    from tactilecal.analysis._maps import summary

    folder = Path(folder)
    raw = recording.attrs.get("units") == "raw" and calibration is None
    rec = recording if raw or calibration is None else recording.tactile.calibrate(calibration)
    figures = {}
    s = None if raw else summary(rec).compute()
    position = _frame_position(rec, frame, s)
    figures["frame"] = _plots.plot_pressure_map(rec, position=position, units=units, summary=s)
    figures["peak_map"] = _plots.plot_pressure_map(rec, units=units, summary=s)
    if s is not None:
        figures["force_time"] = _plots.plot_force_time(s)
        figures["cof_time"] = _plots.plot_cof_time(s)
        figures["cof_path"] = _plots.plot_cof_path(s, recording=rec, units=units)
        if regions is not None:
            found = region_analysis(rec, regions, gap_mm=gap_mm)
            figures["region_forces"] = found.plot_force_time()
            figures["region_centres"] = found.plot_centres(rec, units=units)
    paths = []
    for name, ax in figures.items():
        path = folder / f"{name}.png"
        write_png(ax.figure, path, dpi=dpi)
        paths.append(path)
    return paths


def _frame_position(recording, frame, summary):
    """0-based position of the file's frame number ``frame`` (default: the peak force)."""
    if frame is not None:
        return _plots.frame_position(recording, frame, None, required=True)
    if summary is not None:
        return _plots.peak_position(summary)
    return int(recording.fillna(0.0).sum(("row", "col")).values.argmax())
