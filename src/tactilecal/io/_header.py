"""Tekscan ASCII export header: ``KEY value`` lines up to ``ASCII_DATA @@``.

The header is parsed into the attributes of ``docs/data-model.md``: every line verbatim as
``tekscan_<KEY>`` plus parsed numbers in the project's units.
"""

import re

from tactilecal._errors import TactilecalError
from tactilecal._units import (
    area_to_mm2,
    force_to_N,
    length_to_mm,
    mass_to_N,
    normalise_unit,
    pressure_to_kPa,
    unit_kind,
)
from tactilecal._validate import check_number, shorten

_KEY = re.compile(r"([A-Za-z][A-Za-z0-9_]*)(:?)(?:[ \t]+(.*))?$")
_UPPER_KEY = re.compile(r"[A-Z][A-Z0-9_]*:?(?:[ \t]|$)")
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_NUMBER_UNIT = re.compile(rf"\s*({_NUMBER})\s*(.*?)\s*$")
_CAL_POINT = re.compile(
    rf"\s*({_NUMBER})\s*\(([^)]*)\)\s*({_NUMBER})\s*\(\s*Raw Sum\s*\)"
    rf"(?:\s*({_NUMBER})\s*\(\s*Number of Loaded Cells\s*\))?\s*$", re.IGNORECASE)


def parse_header_lines(lines, name):
    """Split header lines into an ordered ``{KEY: (value, line_number)}`` dict.

    A ``KEY:`` line (``COMMENTS:``) takes the free-text lines after it, up to the next line
    starting with an upper-case key, as its value (joined with newlines). Blank lines are
    skipped.

    Parameters
    ----------
    lines : list of str
        Header lines without line endings (line 1 first).
    name : str
        File name for error messages.

    Returns
    -------
    dict
        ``{key: (value, line_number)}`` in file order.

    Examples
    --------
    >>> h = parse_header_lines(["ROWS 2", "COMMENTS:", "walk 1", "COLS 3"], "f.csv")
    >>> h["COMMENTS"], h["COLS"]
    (('walk 1', 2), ('3', 4))
    """
    header, in_text = {}, None
    for number, line in enumerate(lines, start=1):
        text = line.strip()
        if not text:
            continue
        if in_text is not None and not _UPPER_KEY.match(text):
            value, first = header[in_text]
            header[in_text] = (f"{value}\n{text}" if value else text, first)
            continue
        match = _KEY.match(text)
        if match is None:
            raise TactilecalError(f"line {number} of {name}: {shorten(text)} is not a header line; "
                                  "expected 'KEY value' lines up to 'ASCII_DATA @@'")
        key, colon, value = match.groups()
        if key in header:
            raise TactilecalError(f"line {number} of {name}: {key} appears twice in the header "
                                  f"(first on line {header[key][1]}); expected it once")
        header[key] = ((value or "").strip(), number)
        in_text = key if colon else None
    return header


def number_with_unit(header, key, name):
    """Return ``(number, canonical unit or None)`` from a ``KEY 0.127 centimeters`` line."""
    value, line = header[key]
    match = _NUMBER_UNIT.fullmatch(value)
    if match is None:
        raise TactilecalError(f"line {line} of {name}: {key} is {shorten(value)}; expected a "
                              "number "
                              "optionally followed by a unit")
    unit = match.group(2)
    where = f"{key} on line {line} of {name}"
    return float(match.group(1)), (normalise_unit(unit, where=where) if unit else None)


def integer(header, key, name, *, minimum=None):
    """Return the integer value of header ``key``."""
    value, line = header[key]
    try:
        result = int(value)
    except ValueError:
        raise TactilecalError(f"line {line} of {name}: {key} is {shorten(value)}; expected an "
                              "integer"
                              ) from None
    if minimum is not None and result < minimum:
        raise TactilecalError(f"line {line} of {name}: {key} is {result}; expected at least "
                              f"{minimum}")
    return result


def _length_mm(header, key, name):
    number, unit = number_with_unit(header, key, name)
    if unit is None:
        raise TactilecalError(f"line {header[key][1]} of {name}: {key} has no unit; expected "
                              "e.g. '0.127 centimeters' or '5.08 mm'")
    return _converted(length_to_mm, number, unit, header, key, name)


def _converted(convert, number, unit, header, key, name):
    """``convert(number, unit)``; a unit of the wrong kind is an error naming key and line."""
    try:
        return convert(number, unit)
    except ValueError as exc:
        raise TactilecalError(f"line {header[key][1]} of {name}: {key} {shorten(header[key][0])}: "
                              f"{exc}") from None


def header_attrs(header, name):
    """Translate a parsed header into data-model attributes (``docs/data-model.md``).

    Parameters
    ----------
    header : dict
        Output of :func:`parse_header_lines`.
    name : str
        File name for error messages.

    Returns
    -------
    dict
        Attributes, all ``str``, ``int`` or ``float``.
    """
    attrs = {}
    if "SENSOR_TYPE" in header:
        attrs["sensor_type"] = header["SENSOR_TYPE"][0]
    if "UNITS" in header:
        attrs["units"] = _recording_unit(header, name)
    for key, attr in (("ROW_SPACING", "row_spacing_mm"), ("COL_SPACING", "col_spacing_mm")):
        if key in header:
            attrs[attr] = _length_mm(header, key, name)
    if "SENSEL_AREA" in header:
        number, unit = number_with_unit(header, "SENSEL_AREA", name)
        if unit is None:
            raise TactilecalError(f"line {header['SENSEL_AREA'][1]} of {name}: SENSEL_AREA has "
                                  "no unit; expected e.g. '0.016129 cm2' or '25.8064 mm2'")
        attrs["sensel_area_mm2"] = _converted(area_to_mm2, number, unit, header,
                                              "SENSEL_AREA", name)
    elif "row_spacing_mm" in attrs and "col_spacing_mm" in attrs:
        attrs["sensel_area_mm2"] = attrs["row_spacing_mm"] * attrs["col_spacing_mm"]
    for key, attr in (("SECONDS_PER_FRAME", "seconds_per_frame"),
                      ("NOISE_THRESHOLD", "noise_threshold"),
                      ("SCALE_FACTOR", "scale_factor"), ("EXPONENT", "exponent")):
        if key in header:
            attrs[attr] = number_with_unit(header, key, name)[0]
    if attrs.get("noise_threshold", 0.5).is_integer():
        attrs["noise_threshold"] = int(attrs["noise_threshold"])
    if "SENSITIVITY" in header:
        attrs["sensitivity"] = header["SENSITIVITY"][0]
    attrs.update(_calibration_attrs(header, name))
    _check_ranges(attrs, header, name)
    attrs.update({f"tekscan_{key}": value for key, (value, _) in header.items()})
    return attrs


RECORDING_UNIT_KINDS = ("raw", "pressure", "force")
"""What the values of a recording may be (``docs/data-model.md``, ``units``)."""


def _recording_unit(header, name):
    """Return the normalised ``UNITS`` of the values: raw, a pressure or a force, else an error."""
    value, line = header["UNITS"]
    unit = normalise_unit(value, where=f"UNITS on line {line} of {name}")
    kind = unit_kind(unit)
    if kind not in RECORDING_UNIT_KINDS:
        raise TactilecalError(f"line {line} of {name}: UNITS is {shorten(value)}, a {kind}; "
                              "expected the unit of the values: raw, a pressure (kPa, MPa, psi, "
                              "...) or a force (N, kgf, lbf)")
    return unit


# attribute -> (header key, minimum, minimum allowed?, maximum): what a sensor can have.
# A frame lasts at most a day; readings are 8-bit, so no threshold above 255.
_RANGES = {
    "row_spacing_mm": ("ROW_SPACING", 0.0, False, None),
    "col_spacing_mm": ("COL_SPACING", 0.0, False, None),
    "sensel_area_mm2": ("SENSEL_AREA", 0.0, False, None),
    "seconds_per_frame": ("SECONDS_PER_FRAME", 0.0, False, 86400.0),
    "noise_threshold": ("NOISE_THRESHOLD", 0.0, True, 255.0),
    "scale_factor": ("SCALE_FACTOR", 0.0, False, None),
    "exponent": ("EXPONENT", 0.0, False, None),
    "saturation_pressure": ("SATURATION_PRESSURE", 0.0, False, None),
}


def _check_ranges(attrs, header, name):
    """Header numbers outside what a sensor can have are errors naming key and line."""
    for attr, (key, minimum, inclusive, maximum) in _RANGES.items():
        if attr in attrs and key in header:
            value, line = header[key]
            check_number(attrs[attr], f"line {line} of {name}: {key} ({shorten(value)})",
                         minimum=minimum, min_inclusive=inclusive, maximum=maximum)


def _calibration_attrs(header, name):
    attrs = {}
    if "SATURATION_PRESSURE" in header:
        number, unit = number_with_unit(header, "SATURATION_PRESSURE", name)
        attrs["saturation_pressure"] = number
        if unit is not None:
            attrs["saturation_pressure_unit"] = unit
            if unit_kind(unit) == "pressure":
                attrs["saturation_pressure_kPa"] = pressure_to_kPa(number, unit)
    for key, (value, line) in header.items():
        if key.startswith("CALIBRATION_MODE_"):
            attrs[f"calibration_mode_{key.rsplit('_', 1)[1]}"] = value
        elif key.startswith("CALIBRATION_POINT_"):
            attrs.update(_calibration_point(key, value, line, name))
    return attrs


def _calibration_point(key, value, line, name):
    match = _CAL_POINT.match(value)
    if match is None:
        raise TactilecalError(f"line {line} of {name}: {key} is {shorten(value)}; expected "
                              "'<load> (<unit>) <raw sum> (Raw Sum) [<n> (Number of Loaded "
                              "Cells)]'")
    load, unit_text, raw_sum, cells = match.groups()
    unit = normalise_unit(unit_text, where=f"{key} on line {line} of {name}")
    prefix = f"calibration_point_{key.rsplit('_', 1)[1]}_"
    attrs = {prefix + "load": float(load), prefix + "load_unit": unit,
             prefix + "raw_sum": float(raw_sum)}
    kind = unit_kind(unit)
    if kind in ("mass", "force"):
        convert = mass_to_N if kind == "mass" else force_to_N
        attrs[prefix + "load_N"] = convert(float(load), unit)
    if cells is not None:
        attrs[prefix + "loaded_cells"] = int(float(cells))
    return attrs
