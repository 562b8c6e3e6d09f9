"""Centrifuge scaling of records: model to prototype (Gillis 2013, section 4.4.2).

A model at ``N`` g reproduces a prototype ``N`` times larger: time and length scale by
``N``, frequency by ``1 / N``, stress and pressure are unchanged.
"""

import numpy as np

from tactilecal._errors import TactilecalError

__all__ = ["to_prototype", "prototype_frequency_hz"]


def prototype_frequency_hz(f_model_hz, g_level):
    """Prototype frequency ``f / N`` of a model frequency (centrifuge scaling).

    Examples
    --------
    >>> prototype_frequency_hz(1400.0, 70.0)
    20.0
    """
    return np.asarray(f_model_hz, float) / g_level if np.ndim(f_model_hz) else (
        float(f_model_hz) / g_level)


def to_prototype(record, g_level):
    """Convert a model-scale record to prototype scale: time x N (pressures unchanged).

    Parameters
    ----------
    record : xarray.DataArray
        With a ``time`` coordinate (s).
    g_level : float
        ``N``.

    Returns
    -------
    xarray.DataArray
        Same values, ``time`` multiplied by ``N``, attrs ``g_level`` and
        ``scale = "prototype"``.

    Examples
    --------
    >>> import xarray as xr
    >>> rec = xr.DataArray([1.0, 2.0], dims="time", coords={"time": [0.0, 0.01]})
    >>> to_prototype(rec, 50).time.values.tolist()
    [0.0, 0.5]
    """
    if g_level <= 0:
        raise TactilecalError(f"g_level={g_level}; expected > 0")
    out = record.assign_coords(time=record["time"] * float(g_level))
    out.attrs = {**record.attrs, "g_level": float(g_level), "scale": "prototype"}
    return out
