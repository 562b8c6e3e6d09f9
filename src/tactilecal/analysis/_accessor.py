"""The ``.tactile`` accessor: the analysis functions as methods of a recording.

Registered on :class:`xarray.DataArray` with :func:`xarray.register_dataarray_accessor`
(the xarray documentation's "Extending xarray using accessors") when
:mod:`tactilecal.analysis` is imported. Every method delegates to the function of
:mod:`tactilecal.analysis` it names, with the recording as first argument, so
``rec.tactile.force()`` is ``total_force(rec)``, number for number. The figures of a
recording are methods too (``rec.tactile.plot_pressure_map()``, ...), drawn on
:class:`matplotlib.figure.Figure` without pyplot state.
"""

import xarray as xr

from tactilecal.analysis import _plots
from tactilecal.analysis._maps import (
    centre_of_force,
    contact_area,
    mean_pressure,
    peak_pressure,
    summary,
    total_force,
)
from tactilecal.analysis._units import force_map_N, pressure_map_kPa

__all__ = ["TactileAccessor"]


@xr.register_dataarray_accessor("tactile")
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
            The calibration, or the path of its JSON (:func:`load_calibration`).
        units : str
            Output unit, a pressure (kPa, MPa, psi...) or a force per sensel (N, lbf...).

        Returns
        -------
        xarray.DataArray
        """
        if not hasattr(calibration, "apply"):
            from tactilecal.calibration import load_calibration

            calibration = load_calibration(calibration)
        return calibration.apply(self._rec, units=units)

    def force(self, *, calibration=None):
        """Total force per frame [N]: :func:`tactilecal.analysis.total_force`."""
        return total_force(self._rec, calibration=calibration)

    def area(self, *, threshold_kPa=0.0, calibration=None):
        """Contact area per frame [mm2]: :func:`tactilecal.analysis.contact_area`."""
        return contact_area(self._rec, threshold_kPa=threshold_kPa, calibration=calibration)

    def centre(self, *, calibration=None):
        """Centre of force per frame [mm]: :func:`tactilecal.analysis.centre_of_force`."""
        return centre_of_force(self._rec, calibration=calibration)

    def peak(self, *, calibration=None):
        """Peak pressure per frame [kPa]: :func:`tactilecal.analysis.peak_pressure`."""
        return peak_pressure(self._rec, calibration=calibration)

    def mean_pressure(self, *, threshold_kPa=0.0, calibration=None):
        """Mean loaded pressure per frame [kPa]: :func:`tactilecal.analysis.mean_pressure`."""
        return mean_pressure(self._rec, threshold_kPa=threshold_kPa, calibration=calibration)

    def pressure_map(self, *, calibration=None):
        """Pressure per sensel [kPa]: :func:`tactilecal.analysis.pressure_map_kPa`."""
        return pressure_map_kPa(self._rec, calibration=calibration)

    def force_map(self, *, calibration=None):
        """Force per sensel [N]: :func:`tactilecal.analysis.force_map_N`."""
        return force_map_N(self._rec, calibration=calibration)

    def summary(self, *, threshold_kPa=0.0, calibration=None):
        """Every per-frame quantity in one Dataset: :func:`tactilecal.analysis.summary`."""
        return summary(self._rec, threshold_kPa=threshold_kPa, calibration=calibration)

    # ---------------------------------------------------------------- figures
    def plot_pressure_map(self, frame=None, *, calibration=None, ax=None):
        """Pressure map [kPa] of one frame, or each sensel's peak over the recording.

        ``frame`` is a 0-based frame position (default: the peak-pressure map); a raw
        recording without ``calibration`` is drawn in raw readings (0..255). Returns the
        matplotlib Axes.
        """
        return _plots.plot_pressure_map(self._rec, frame, calibration=calibration, ax=ax)

    def plot_profiles(self, frame, *, nonworking=None, calibration=None, axes=None):
        """Row and column profiles [kPa] of one frame (means skipping blank sensels).

        ``nonworking``: a mask of non-working sensels to skip too. Returns the row-profile
        and the column-profile Axes.
        """
        return _plots.plot_profiles(self._rec, frame, nonworking=nonworking,
                                    calibration=calibration, axes=axes)

    def plot_force_time(self, *, calibration=None, summary=None, ax=None):
        """Total force [N] and contact area [mm2] against time, the peak frame marked.

        ``summary``: the recording's :meth:`summary` if already computed (else computed
        here). Returns the matplotlib Axes.
        """
        if summary is None:
            summary = self.summary(calibration=calibration)
        return _plots.plot_force_time(summary, ax=ax)

    def plot_cof_path(self, *, calibration=None, summary=None, min_force_N=None, ax=None):
        """Centre-of-force path [mm], coloured by time.

        Frames with a total force below ``min_force_N`` (default 5 % of the peak) are not
        drawn: with almost no load the centre is noise. ``summary``: the recording's
        :meth:`summary` if already computed. Returns the matplotlib Axes.
        """
        if summary is None:
            summary = self.summary(calibration=calibration)
        return _plots.plot_cof_path(summary, min_force_N=min_force_N, ax=ax)
