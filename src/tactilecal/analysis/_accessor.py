"""The ``.tactile`` accessor: pressure-map analysis as methods of a recording.

Registered on :class:`xarray.DataArray` with :func:`xarray.register_dataarray_accessor`
(the xarray documentation's "Extending xarray using accessors") by ``import tactilecal``
(:mod:`tactilecal._accessor`), which imports this module on the first use of ``.tactile``.
This is the public face of the analysis: each method runs one analysis function of this
package with the recording as first argument (``rec.tactile.force()`` is
``_maps.total_force(rec)``, number for number) and carries that function's docstring and
signature, so the definitions are written once. The figures of a recording are methods too
(``rec.tactile.plot_pressure_map()``, ...), drawn on :class:`matplotlib.figure.Figure`
without pyplot state.
"""

import inspect
import re

from tactilecal.analysis import _plots
from tactilecal.analysis._analyze import analyze
from tactilecal.analysis._contacts import region_analysis, split_contacts
from tactilecal.analysis._describe import describe, frame_table
from tactilecal.analysis._figures import save_figures
from tactilecal.analysis._gait import force_time_integral, pressure_time_integral, steps
from tactilecal.analysis._maps import (
    centre_of_force,
    contact_area,
    mean_pressure,
    peak_pressure,
    summary,
    total_force,
)
from tactilecal.analysis._movie import write_movie
from tactilecal.analysis._regions import (
    high_pressure_zones,
    label_zones,
    max_window_load,
    profile,
    select_region,
)
from tactilecal.analysis._units import (
    force_map_N,
    pressure_map_kPa,
    saturated_sensels,
    saturation_mask,
)

__all__ = ["TactileAccessor"]

_RECORDING_ENTRY = re.compile(r"^recording : .*\n(?:(?: {4}.*)?\n)*?(?=\S)", re.M)
"""The ``recording`` entry of a numpydoc Parameters section (the accessor supplies it)."""


def _method(function, name):
    """Return a method ``name`` that runs ``function`` on the accessor's recording.

    It carries ``function``'s docstring (without the ``recording`` entry; its Examples call
    the method, ``rec.tactile.<name>()``) and its signature (without ``recording``).
    """
    def method(self, *args, **kwargs):
        return function(self._rec, *args, **kwargs)

    signature = inspect.signature(function)
    self_ = inspect.Parameter("self", inspect.Parameter.POSITIONAL_OR_KEYWORD)
    method.__signature__ = signature.replace(
        parameters=[self_, *list(signature.parameters.values())[1:]])
    doc = (inspect.getdoc(function) or "").rstrip() + "\n"  # empty under python -OO
    method.__doc__ = _RECORDING_ENTRY.sub("", doc)
    method.__name__, method.__qualname__ = name, f"TactileAccessor.{name}"
    return method


class TactileAccessor:
    """Pressure-map analysis of a recording: ``recording.tactile.<method>()``.

    The recording is a DataArray in the data model (dims ``("frame", "row", "col")``,
    a ``time`` coordinate, the sensor's attributes; ``docs/data-model.md``). A raw
    recording needs ``calibration=`` (a CalibrationResult or the path of its JSON), or
    is converted first with :meth:`calibrate`.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> import tactilecal.analysis
    >>> rec = xr.DataArray(np.full((1, 2, 2), 100.0), dims=("frame", "row", "col"),
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 25.0})
    >>> rec.tactile.force().values
    array([10.])
    """

    def __init__(self, recording):
        self._rec = recording

    def calibrate(self, calibration, *, units="kPa"):
        """Convert a raw recording to pressure or force per sensel.

        :meth:`tactilecal.calibration.CalibrationResult.apply`, with the calibration's
        recorded equilibration gains and non-working-sensel mask applied first.

        Parameters
        ----------
        calibration : CalibrationResult, str or os.PathLike
            The calibration, or the path of its JSON (:meth:`CalibrationResult.from_json`).
        units : str
            Output unit, a pressure (kPa, MPa, psi...) or a force per sensel (N, lbf...).

        Returns
        -------
        xarray.DataArray

        Examples
        --------
        >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
        >>> from tactilecal.calibration import header_calibration
        >>> cal = header_calibration({"sensel_area_mm2": 2.0, "calibration_point_1_load_N": 10.0,
        ...                           "calibration_point_1_raw_sum": 100.0})  # 0.1 N a count
        >>> raw = xr.DataArray(np.array([[[0.0, 30.0], [50.0, np.nan]]]),
        ...                    dims=("frame", "row", "col"),
        ...                    attrs={"units": "raw", "sensel_area_mm2": 2.0})
        >>> raw.tactile.calibrate(cal, units="N").values.tolist()
        [[[0.0, 3.0], [5.0, nan]]]
        >>> float(raw.tactile.calibrate(cal).tactile.force()[0])  # kPa back to N
        8.0
        """
        if not hasattr(calibration, "apply"):
            from tactilecal.calibration import CalibrationResult

            calibration = CalibrationResult.from_json(calibration)
        return calibration.apply(self._rec, units=units)

    force = _method(total_force, "force")
    area = _method(contact_area, "area")
    centre = _method(centre_of_force, "centre")
    peak = _method(peak_pressure, "peak")
    mean_pressure = _method(mean_pressure, "mean_pressure")
    pressure_map = _method(pressure_map_kPa, "pressure_map")
    force_map = _method(force_map_N, "force_map")
    frame_summary = _method(summary, "frame_summary")
    saturated_sensels = _method(saturated_sensels, "saturated_sensels")
    saturation_mask = _method(saturation_mask, "saturation_mask")
    profile = _method(profile, "profile")
    select_region = _method(select_region, "select_region")
    label_zones = _method(label_zones, "label_zones")
    high_pressure_zones = _method(high_pressure_zones, "high_pressure_zones")
    max_window_load = _method(max_window_load, "max_window_load")
    describe = _method(describe, "describe")
    frame_table = _method(frame_table, "frame_table")
    split_contacts = _method(split_contacts, "split_contacts")
    regions = _method(region_analysis, "regions")
    pressure_time_integral = _method(pressure_time_integral, "pressure_time_integral")
    impulse = _method(force_time_integral, "impulse")
    steps = _method(steps, "steps")
    analyze = _method(analyze, "analyze")
    save_figures = _method(save_figures, "save_figures")
    write_movie = _method(write_movie, "write_movie")

    # ---------------------------------------------------------------- figures
    def plot_pressure_map(self, frame=None, *, position=None, calibration=None, ax=None,
                          units=None, centre=True, summary=None):
        """Pressure map of one frame, or each sensel's peak over the recording.

        ``frame`` is the file's frame number (``recording.frame``), ``position`` a 0-based
        position (default: the peak-pressure map); a raw recording without ``calibration``
        is drawn in raw readings (0..255). ``units``: the pressure unit shown (default the
        recording's own pressure unit, else kPa). Saturated sensels are red crosses;
        ``centre`` draws the centre of force (that frame's, or the path of every frame with
        at least 5 % of the peak force); ``summary``: the recording's :meth:`frame_summary`
        if already computed (its centre of force is drawn). Returns the matplotlib Axes.

        Examples
        --------
        >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
        >>> p = np.zeros((3, 4, 5)); p[:, 1:3, 1:4] = [[[100.0]], [[200.0]], [[150.0]]]
        >>> rec = xr.DataArray(p, dims=("frame", "row", "col"),
        ...                    coords={"time": ("frame", [0.0, 0.1, 0.2])},
        ...                    attrs={"units": "kPa", "sensel_area_mm2": 25.0,
        ...                           "row_spacing_mm": 5.0, "col_spacing_mm": 5.0})
        >>> ax = rec.tactile.plot_pressure_map()  # each sensel's peak
        >>> ax.get_title()
        'peak over all frames'
        """
        return _plots.plot_pressure_map(self._rec, frame, position=position,
                                        calibration=calibration, ax=ax, units=units,
                                        centre=centre, summary=summary)

    def plot_profiles(self, frame=None, *, position=None, nonworking=None, calibration=None,
                      axes=None, units=None):
        """Row and column profiles of one frame (means skipping blank sensels).

        ``frame`` is the file's frame number, or ``position`` its 0-based position;
        ``nonworking``: a mask of non-working sensels to skip too. Returns the row-profile
        and the column-profile Axes.

        Examples
        --------
        >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
        >>> p = np.zeros((3, 4, 5)); p[:, 1:3, 1:4] = [[[100.0]], [[200.0]], [[150.0]]]
        >>> rec = xr.DataArray(p, dims=("frame", "row", "col"),
        ...                    coords={"time": ("frame", [0.0, 0.1, 0.2])},
        ...                    attrs={"units": "kPa", "sensel_area_mm2": 25.0,
        ...                           "row_spacing_mm": 5.0, "col_spacing_mm": 5.0})
        >>> rows, cols = rec.tactile.plot_profiles(1)
        >>> rows.figure is cols.figure
        True
        """
        return _plots.plot_profiles(self._rec, frame, position=position, nonworking=nonworking,
                                    calibration=calibration, axes=axes, units=units)

    def plot_force_time(self, *, calibration=None, summary=None, ax=None):
        """Total force [N] and contact area [mm2] against time, the peak frame marked.

        Frames with saturated sensels are red ticks along the time axis. ``summary``: the
        recording's :meth:`frame_summary` if already computed (else computed here).
        Returns the matplotlib Axes.

        Examples
        --------
        >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
        >>> p = np.zeros((3, 4, 5)); p[:, 1:3, 1:4] = [[[100.0]], [[200.0]], [[150.0]]]
        >>> rec = xr.DataArray(p, dims=("frame", "row", "col"),
        ...                    coords={"time": ("frame", [0.0, 0.1, 0.2])},
        ...                    attrs={"units": "kPa", "sensel_area_mm2": 25.0,
        ...                           "row_spacing_mm": 5.0, "col_spacing_mm": 5.0})
        >>> ax = rec.tactile.plot_force_time()
        >>> ax.get_xlabel()
        'time [s]'
        """
        if summary is None:
            summary = self.frame_summary(calibration=calibration)
        return _plots.plot_force_time(summary, ax=ax)

    def plot_cof_path(self, *, calibration=None, summary=None, min_force_N=None, ax=None,
                      units=None):
        """Centre-of-force path over the peak-pressure map, coloured by time.

        Drawn at the sensor's own scale, so noise never looks like motion. Frames with a
        total force below ``min_force_N`` (default 5 % of the peak) are not drawn: with
        almost no load the centre is noise. ``summary``: the recording's
        :meth:`frame_summary` if already computed. Returns the matplotlib Axes.

        Examples
        --------
        >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
        >>> p = np.zeros((3, 4, 5)); p[:, 1:3, 1:4] = [[[100.0]], [[200.0]], [[150.0]]]
        >>> rec = xr.DataArray(p, dims=("frame", "row", "col"),
        ...                    coords={"time": ("frame", [0.0, 0.1, 0.2])},
        ...                    attrs={"units": "kPa", "sensel_area_mm2": 25.0,
        ...                           "row_spacing_mm": 5.0, "col_spacing_mm": 5.0})
        >>> ax = rec.tactile.plot_cof_path(summary=rec.tactile.frame_summary())
        >>> ax.get_xlabel()
        'column [mm]'
        """
        if summary is None:
            summary = self.frame_summary(calibration=calibration)
        rec = self._rec if calibration is None else self.calibrate(calibration)
        return _plots.plot_cof_path(summary, recording=rec, min_force_N=min_force_N, ax=ax,
                                    units=units)
