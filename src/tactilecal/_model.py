"""The data model's check: whether a DataArray is a recording every part of tactilecal reads.

A recording (``docs/data-model.md``) is one ``xarray.DataArray`` with dims
``("frame", "row", "col")``; coordinates ``frame``, ``time`` (along ``frame``, seconds),
``row`` and ``col`` (the readers write them all; an array made in memory may leave them
out, but one that has them has them along these dims); a ``units`` attribute that
:func:`tactilecal._units.normalise_unit` knows (raw readings, a pressure or a force per
sensel); and, where present, positive ``sensel_area_mm2``, ``row_spacing_mm``,
``col_spacing_mm`` and ``seconds_per_frame``. Raw readings are whole numbers 0..255 (NaN
outside the sensor's shape); calibrated values are finite and not negative.

The readers produce such arrays; the analysis functions and ``CalibrationResult.apply``
check what they are given with :func:`check_recording` and :func:`usable_values`, so a
hand-made array that breaks the model is a one-line error naming the recording and the
part, not a wrong number further on.
"""

import numpy as np

from tactilecal._errors import TactilecalError

__all__ = ["DIMS", "POSITIVE_ATTRS", "recording_name", "recording_units", "check_recording",
           "positive_attr", "usable_values"]

DIMS = ("frame", "row", "col")
#: Attributes that, when present, must be positive numbers (with what each one is).
POSITIVE_ATTRS = {"sensel_area_mm2": "a positive area in mm2",
                  "row_spacing_mm": "a positive spacing in mm",
                  "col_spacing_mm": "a positive spacing in mm",
                  "seconds_per_frame": "a positive frame period in s"}
_KINDS = ("raw", "pressure", "force")
_UNITS_EXPECTED = "expected raw, a pressure (kPa, MPa, psi) or a force per sensel (N, kgf, lbf)"


def recording_name(data):
    """Return what messages call a recording: its ``source`` attribute, name or 'recording'."""
    return data.attrs.get("source", data.name or "recording")


def recording_units(data):
    """Return ``(unit, kind)`` of a recording: the normalised unit; raw, pressure or force.

    Raises
    ------
    ValueError
        The ``units`` attribute is missing, unknown, or of another kind (a length...).
    """
    from tactilecal._units import normalise_unit, unit_kind

    unit = data.attrs.get("units")
    if unit is None:
        raise TactilecalError(f"{recording_name(data)}: attribute 'units' is missing; "
                              f"{_UNITS_EXPECTED}")
    unit = normalise_unit(unit, where=f"attribute 'units' of {recording_name(data)}")
    kind = unit_kind(unit)
    if kind not in _KINDS:
        raise TactilecalError(f"{recording_name(data)}: units {unit!r} are a {kind}; "
                              f"{_UNITS_EXPECTED}")
    return unit, kind


def positive_attr(data, key):
    """Return the attribute ``key`` as a float, checked to be a positive finite number.

    Raises
    ------
    ValueError
        Missing, not a number, not finite or not positive; the message names the recording
        and the attribute.
    """
    value = data.attrs.get(key)
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = float("nan")
    if not (np.isfinite(number) and number > 0):
        raise TactilecalError(f"{recording_name(data)}: attribute {key!r} is {value!r}; expected "
                              f"{POSITIVE_ATTRS.get(key, 'a positive number')}")
    return number


def check_recording(data, *, values=False):
    """Check that ``data`` follows the data model; return ``(unit, kind)``.

    Parameters
    ----------
    data : xarray.DataArray
    values : bool
        Also check the values (one pass over them; computes a dask-backed recording): raw
        readings whole numbers in 0..255 or NaN, calibrated values finite and >= 0 or NaN.

    Returns
    -------
    tuple of str
        As :func:`recording_units`.

    Raises
    ------
    TypeError
        ``data`` is not a DataArray.
    ValueError
        Wrong dims, a coordinate along another dim, a bad ``units`` or positive attribute, or (with
        ``values``) an impossible value; the message names the recording and the part.
    """
    import xarray as xr

    if not isinstance(data, xr.DataArray):
        raise TypeError(f"recording is a {type(data).__name__}; expected an xarray.DataArray "
                        "with dims ('frame', 'row', 'col') (see tactilecal.io.open_recording)")
    name = recording_name(data)
    if tuple(data.dims) != DIMS:
        raise TactilecalError(f"{name}: dims {tuple(data.dims)}; expected {DIMS}")
    for coord, dim in (("frame", "frame"), ("time", "frame"), ("row", "row"), ("col", "col")):
        if coord in data.coords and data[coord].dims != (dim,):
            raise TactilecalError(f"{name}: coordinate {coord!r} has dims {data[coord].dims}; "
                                  f"expected it along {dim!r}")
    for key in POSITIVE_ATTRS:
        if key in data.attrs:
            positive_attr(data, key)
    unit, kind = recording_units(data)
    if values:
        _check_values(data, name, kind)
    return unit, kind


def _check_values(data, name, kind):
    """Raw: whole numbers 0..255 or NaN; calibrated: finite, >= 0 or NaN (one pass)."""
    v = np.asarray(data.values, dtype=float)
    with np.errstate(invalid="ignore"):
        if kind == "raw":
            bad = ~np.isnan(v) & ((v < 0) | (v > 255) | (v != np.round(v)))
            what = "raw readings are whole numbers 0..255 (NaN outside the sensor)"
        else:
            bad = np.isinf(v) | (v < 0)
            what = f"{kind} values are finite and not negative (NaN outside the sensor)"
    if bad.any():
        raise _first_bad(v, bad, name, np.asarray(data["frame"]), what)


def _first_bad(values, bad, name, frames, what, start=(0, 0, 0)):
    """Return the error naming the first ``bad`` value: its frame, row, column and the count.

    ``values`` may be a block of the recording starting at index ``start``; ``frames`` are
    the recording's frame numbers (None: counted from 1).
    """
    k, i, j = (np.argwhere(bad)[0] + start).tolist()
    frame = frames[k] if frames is not None else k + 1
    return TactilecalError(f"{name}: frame {frame}, row {i}, col {j} is "
                           f"{float(values[bad][0])!r} ({int(bad.sum())} such values); "
                           f"expected {what}")


_USABLE = {"raw": ("raw readings 0..255 (NaN outside the sensor)", 0.0, 255.0),
           "calibrated": ("finite values (NaN outside the sensor)", -np.inf, np.inf)}
"""Per kind: what is expected, and the bounds (NaN aside) a usable value lies within; an
infinite bound excludes infinity itself."""


def usable_values(data, kind):
    """Return ``data`` once its values are checked usable for a calculation on ``kind``.

    Looser than the model's check (:func:`check_recording` with ``values``) where the
    toolkit itself makes such arrays: raw readings (``kind="raw"``) may be fractions
    (equilibrated frames) but lie in 0..255; calibrated values (``"calibrated"``) may be
    negative (a dynamic filter's undershoot) but are finite. NaN is outside the sensor. An
    array in memory is checked now; a dask-backed one block by block as it is computed
    (the error is raised then), so nothing is read twice.

    Raises
    ------
    ValueError
        Naming the recording, the first bad value's frame, row and column, and the count.
    """
    from functools import partial

    check = partial(_usable_block, name=recording_name(data), kind=kind,
                    frames=np.asarray(data["frame"]) if "frame" in data.coords else None)
    if data.chunks is None:
        check(np.asarray(data.values))
        return data
    return data.copy(data=data.data.map_blocks(check, dtype=data.dtype))


def _usable_block(block, block_info=None, *, name, kind, frames):
    what, low, high = _USABLE[kind]
    if block.size == 0:
        return block
    lowest, highest = np.fmin.reduce(block, axis=None), np.fmax.reduce(block, axis=None)
    if not (lowest < low or highest > high or np.isinf([lowest, highest]).any()):
        return block  # (NaN compares false: an all-NaN block is usable)
    bad = (block < low) | (block > high) | np.isinf(block)
    start = [first for first, _ in block_info[0]["array-location"]] if block_info else (0, 0, 0)
    raise _first_bad(block, bad, name, frames, what, start)  # a dask block starts at ``start``
