"""Turn a recording of any supported unit into a force map (N) or a pressure map (kPa).

The data model (``docs/data-model.md``) stores calibrated recordings as pressure (``kPa``,
``MPa``, ``psi``) or force per sensel (``N``, ``kgf``, ``lbf``). Every analysis function
goes through :func:`force_map_N` or :func:`pressure_map_kPa` so that units are converted in
one place.
"""

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._model import (
    check_recording,
    positive_attr,
    recording_name,
    recording_units,
    usable_values,
)
from tactilecal._units import KPA_MM2_TO_N, N_PER_MM2_TO_KPA

__all__ = ["force_map_N", "pressure_map_kPa", "saturated_sensels", "saturation_mask",
           "saturation_threshold",
           "sensel_area_mm2", "spacing_mm", "display_unit"]

SATURATION_TOLERANCE = 1e-3
"""Calibrated files: a value within 0.1 % of the saturation pressure counts as saturated
(exports round pressures, e.g. 1514 kPa for a saturation pressure of 1514.73 kPa)."""


def saturated_sensels(recording):
    """Count the saturated sensels of every frame, and say by which rule.

    A raw reading of 255 is saturated: the load there is at least the calibration's value at
    255, so forces and pressures of such a frame are lower bounds. A calibrated recording in
    a pressure unit is saturated where it is within 0.1 % of its ``saturation_pressure_kPa``
    attribute (the header's, or the calibration's after :meth:`CalibrationResult.apply`).

    Returns
    -------
    (xarray.DataArray or None, str)
        Count per frame (int, dim ``frame``; lazy for a dask-backed recording), or None when
        the recording does not say what saturation is; and the rule as text.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.array([[[255.0, 3.0]], [[40.0, 0.0]]]),
    ...                    dims=("frame", "row", "col"), attrs={"units": "raw"})
    >>> count, rule = rec.tactile.saturated_sensels()
    >>> count.values.tolist(), rule
    ([1, 0], 'raw value 255')
    """
    mask, rule = saturation_mask(recording)
    return (None if mask is None else mask.sum(("row", "col"))), rule


def saturation_mask(recording):
    """Return the saturated sensels of every frame (boolean, like the recording) and the rule.

    The rule of :func:`saturated_sensels`; ``(None, rule)`` when the recording does not say
    what saturation is.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.array([[[255.0, 3.0]]]), dims=("frame", "row", "col"),
    ...                    attrs={"units": "raw"})
    >>> mask, rule = saturation_mask(rec)
    >>> mask.values.tolist(), rule
    ([[[True, False]]], 'raw value 255')
    """
    threshold, rule = saturation_threshold(recording)
    return (None if threshold is None else recording >= threshold), rule


def saturation_threshold(recording):
    """Return the value from which a sensel is saturated (None: unknown) and the rule.

    The rule of :func:`saturated_sensels`, as a number (NumPy callers compare with it).

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.zeros((1, 1, 1)), dims=("frame", "row", "col"),
    ...                    attrs={"units": "MPa", "saturation_pressure_kPa": 500.0})
    >>> saturation_threshold(rec)
    (0.4995, 'value >= 0.4995 MPa (saturation pressure - 0.1 %)')
    """
    from tactilecal._units import pressure_to_kPa

    unit, kind = recording_units(recording)
    if kind == "raw":
        return 255.0, "raw value 255"
    limit_kPa = recording.attrs.get("saturation_pressure_kPa")
    if limit_kPa is None or kind != "pressure" or not np.isfinite(float(limit_kPa)):
        return None, ("unknown (calibrated recording without a saturation pressure in a "
                      "pressure unit)")
    threshold = float(limit_kPa) / pressure_to_kPa(1.0, unit) * (1 - SATURATION_TOLERANCE)
    return threshold, f"value >= {threshold:.6g} {unit} (saturation pressure - 0.1 %)"


def sensel_area_mm2(recording):
    """Return the ``sensel_area_mm2`` attribute, checked to be a positive number.

    Raises
    ------
    ValueError
        If the attribute is missing or not positive.
    """
    return positive_attr(recording, "sensel_area_mm2")


def spacing_mm(recording):
    """Return ``(row_spacing_mm, col_spacing_mm)`` from the attributes, checked positive.

    Raises
    ------
    ValueError
        If either spacing is missing or not positive.
    """
    return tuple(positive_attr(recording, key) for key in ("row_spacing_mm", "col_spacing_mm"))


def _calibrated(recording, calibration, units):
    """Apply ``calibration`` (object with ``apply`` or a JSON path) to a raw recording."""
    if calibration is None:
        raise TactilecalError(f"{recording_name(recording)}: units are 'raw'; give a calibration "
                              "(calibration=... or --cal CAL.json) to get pressure or force")
    if not hasattr(calibration, "apply"):
        from tactilecal.calibration import CalibrationResult

        calibration = CalibrationResult.from_json(calibration)
    return calibration.apply(recording, units=units)


def _per_sensel(recording, calibration, units):
    """Return ``recording`` as force per sensel (``units="N"``) or pressure (``"kPa"``).

    The body of :func:`force_map_N` and :func:`pressure_map_kPa`: a raw recording is
    calibrated to ``units`` first; a pressure [kPa] on a sensel of area ``a`` [mm2] carries
    ``F = p * a * 1e-3`` N, so ``p = F / a * 1e3``.
    """
    from tactilecal._units import force_to_N, pressure_to_kPa

    unit, kind = check_recording(recording)
    if kind == "raw":
        return _per_sensel(_calibrated(recording, calibration, units), None, units)
    if calibration is not None:  # silently ignored, it would look applied
        raise TactilecalError(f"{recording_name(recording)}: units are {unit!r}, already "
                              "calibrated; expected a raw recording with a calibration "
                              "(calibration= or --cal applies to raw readings only), or none")
    if kind == "force":
        factor = force_to_N(1.0, unit)
        if units == "kPa":
            factor = factor * N_PER_MM2_TO_KPA / sensel_area_mm2(recording)
    else:
        factor = pressure_to_kPa(1.0, unit)
        if units == "N":
            factor = factor * sensel_area_mm2(recording) * KPA_MM2_TO_N
    out = usable_values(recording, "calibrated") * factor
    out.attrs = {**recording.attrs, "units": units}
    return out


def force_map_N(recording, *, calibration=None):
    """Return the force on each sensel in newtons, dims ``("frame", "row", "col")``.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model; ``units`` one of raw, any pressure (kPa, MPa, psi...)
        or force per sensel (N, kgf, lbf).
    calibration : CalibrationResult or path, optional
        Needed (and used) only when ``units`` is ``raw``.

    Returns
    -------
    xarray.DataArray
        Force per sensel [N]; NaN where the recording is NaN (outside the sensor).

    Raises
    ------
    ValueError
        On raw input without a calibration, an unknown unit, wrong dims or a missing
        ``sensel_area_mm2`` for a pressure recording.

    Notes
    -----
    A pressure ``p`` [kPa] on a sensel of area ``a`` [mm2] carries
    ``F = p * a * 1e-3`` N (1 kPa x 1 mm2 = 1e3 Pa x 1e-6 m2 = 1e-3 N).

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.full((1, 2, 2), 100.0), dims=("frame", "row", "col"),
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 25.0})
    >>> float(rec.tactile.force_map().sum())
    10.0
    """
    return _per_sensel(recording, calibration, "N")


def pressure_map_kPa(recording, *, calibration=None):
    """Return the pressure on each sensel in kPa, dims ``("frame", "row", "col")``.

    Parameters
    ----------
    recording, calibration
        As :func:`force_map_N`.

    Returns
    -------
    xarray.DataArray
        Pressure per sensel [kPa]; a force map is divided by ``sensel_area_mm2``
        (``p = F / a * 1e3``).

    Raises
    ------
    ValueError
        As :func:`force_map_N`.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tactilecal.analysis  # registers .tactile
    >>> rec = xr.DataArray(np.full((1, 1, 1), 2.0), dims=("frame", "row", "col"),
    ...                    attrs={"units": "MPa"})
    >>> float(rec.tactile.pressure_map()[0, 0, 0])
    2000.0
    """
    return _per_sensel(recording, calibration, "kPa")


def display_unit(recording=None, units=None):
    """Return ``(unit, factor)`` to show pressures: ``value_kPa / factor`` is in ``unit``.

    ``units`` when given (a pressure unit: kPa, MPa, psi...), else the recording's own unit
    when it is a pressure (an MPa recording is shown in MPa), else kPa.

    Examples
    --------
    >>> unit, factor = display_unit(units="MPa")
    >>> unit, 2500.0 / factor
    ('MPa', 2.5)
    """
    from tactilecal._units import display_pressure

    return display_pressure(None if recording is None else recording.attrs.get("units"), units)
