"""Units, defined once: exact factors, spellings of exports and CSVs, conversions.

Conversions go to mm, mm2, N, kPa and s.

Sources: NIST SP 811 (2008), appendix B: 1 lb = 0.45359237 kg, standard gravity
g = 9.80665 m/s2 (CGPM 1901), 1 lbf = 1 lb x g, 1 kgf = 1 kg x g, 1 in = 25.4 mm
(1 in2 = 645.16 mm2), 1 psi = 1 lbf/in2, 1 mmHg = 133.322387415 Pa, 1 bar = 100 kPa.
Pressure times area: 1 kPa x 1 mm2 = 1e3 Pa x 1e-6 m2 = 1e-3 N, so a force per sensel in N
is ``pressure_kPa * sensel_area_mm2 * KPA_MM2_TO_N`` and a pressure in kPa is
``force_N / sensel_area_mm2 * N_PER_MM2_TO_KPA`` (1 N/mm2 = 1 MPa = 1000 kPa).

Sensor constants (pitch, sensel area, capacity) are not here: they come from the sensor
catalogue, :mod:`tactilecal.sensors`.
"""

import math
import re

from tactilecal._errors import TactilecalError
from tactilecal._validate import shorten

__all__ = ["G_STANDARD", "LB_KG", "LBF_N", "PSI_TO_KPA", "KPA_MM2_TO_N", "N_PER_MM2_TO_KPA",
           "normalise_unit", "length_to_mm", "area_to_mm2", "force_to_N", "mass_to_N",
           "pressure_to_kPa", "time_to_s", "unit_kind", "unit_from_column", "display_pressure"]

G_STANDARD = 9.80665
"""Standard acceleration of gravity in m/s2 (exact, CGPM 1901)."""

LB_KG = 0.45359237
"""Kilograms per avoirdupois pound (exact)."""

LBF_N = LB_KG * G_STANDARD
"""Newtons per pound-force, 4.4482216152605 N (1 lbf = 1 lb x g)."""

PSI_TO_KPA = LBF_N / 645.16 * 1000.0
"""Kilopascals per psi, 6.894757... kPa (1 lbf / 645.16 mm2, in kPa)."""

KPA_MM2_TO_N = 1e-3
"""Newtons per kPa x mm2: ``force_N = pressure_kPa * area_mm2 * KPA_MM2_TO_N``."""

N_PER_MM2_TO_KPA = 1e3
"""Kilopascals per N/mm2 (1 N/mm2 = 1 MPa = 1000 kPa): ``1 / KPA_MM2_TO_N``."""

# canonical unit -> (kind, factor to the kind's internal unit)
_UNITS = {
    "raw": ("raw", 1.0),
    "kPa": ("pressure", 1.0), "MPa": ("pressure", 1000.0), "Pa": ("pressure", 1e-3),
    "psi": ("pressure", PSI_TO_KPA), "bar": ("pressure", 100.0),
    "mmHg": ("pressure", 0.133322387415), "kgf/cm2": ("pressure", G_STANDARD * 10.0),
    "N/cm2": ("pressure", 10.0), "g/cm2": ("pressure", G_STANDARD * 1e-2),
    "N": ("force", 1.0), "kN": ("force", 1000.0), "kgf": ("force", G_STANDARD),
    "lbf": ("force", LBF_N),
    "kg": ("mass", G_STANDARD), "g": ("mass", G_STANDARD * 1e-3), "lb": ("mass", LBF_N),
    "mm": ("length", 1.0), "cm": ("length", 10.0), "m": ("length", 1000.0),
    "in": ("length", 25.4),
    "mm2": ("area", 1.0), "cm2": ("area", 100.0), "m2": ("area", 1e6), "in2": ("area", 645.16),
    "s": ("time", 1.0), "ms": ("time", 1e-3), "us": ("time", 1e-6), "min": ("time", 60.0),
}

_ALIASES = {
    "raw": "raw", "raw units": "raw", "counts": "raw",
    "kpa": "kPa", "mpa": "MPa", "pa": "Pa", "n/mm2": "MPa", "psi": "psi", "bar": "bar",
    "mmhg": "mmHg", "kg/cm2": "kgf/cm2", "kgf/cm2": "kgf/cm2", "n/cm2": "N/cm2",
    "g/cm2": "g/cm2",
    "n": "N", "newton": "N", "newtons": "N", "kn": "kN", "kgf": "kgf", "kilogram-force": "kgf",
    "lbf": "lbf", "lbsf": "lbf",
    "kg": "kg", "kgs": "kg", "kilogram": "kg", "kilograms": "kg", "g": "g", "grams": "g",
    "lb": "lb", "lbs": "lb", "pound": "lb", "pounds": "lb",
    "mm": "mm", "millimeter": "mm", "millimeters": "mm", "millimetre": "mm",
    "millimetres": "mm", "cm": "cm", "centimeter": "cm", "centimeters": "cm",
    "centimetre": "cm", "centimetres": "cm", "m": "m", "in": "in", "inch": "in",
    "inches": "in",
    "mm2": "mm2", "sq mm": "mm2", "cm2": "cm2", "sq cm": "cm2", "m2": "m2", "in2": "in2",
    "sq in": "in2",
    "s": "s", "sec": "s", "secs": "s", "second": "s", "seconds": "s",
    "ms": "ms", "msec": "ms", "millisecond": "ms", "milliseconds": "ms",
    "us": "us", "µs": "us", "microsecond": "us", "microseconds": "us",
    "min": "min", "minute": "min", "minutes": "min",
}


def normalise_unit(text, *, where="unit"):
    """Return the canonical spelling of a unit written as in a Tekscan or CSV file.

    Matching ignores case, surrounding spaces/brackets, ``^`` and ``²``
    (``"KPa"`` -> ``"kPa"``, ``"centimeters"`` -> ``"cm"``, ``"mm^2"`` -> ``"mm2"``,
    ``"(Kgs)"`` -> ``"kg"``, ``"PSI"`` -> ``"psi"``).

    Parameters
    ----------
    text : str
        The unit as written.
    where : str, keyword-only
        Where the text came from, used in the error message
        (e.g. ``"ROW_SPACING on line 11 of iscan.csv"``).

    Returns
    -------
    str
        One of ``raw kPa MPa Pa psi bar mmHg kgf/cm2 N/cm2 g/cm2 N kN kgf lbf kg g lb
        mm cm m in mm2 cm2 m2 in2 s ms us min``.

    Raises
    ------
    ValueError
        If the unit is not recognised.

    Examples
    --------
    >>> normalise_unit("KPa"), normalise_unit(" centimeters "), normalise_unit("in^2")
    ('kPa', 'cm', 'in2')
    """
    key = str(text).strip().strip("()[]").strip().lower()
    key = re.sub(r"\s+", " ", key.replace("^", "").replace("²", "2"))
    if key not in _ALIASES:
        raise TactilecalError(f"unknown unit {shorten(str(text).strip())} in {where}; expected "
                              "one of "
                              f"{', '.join(_UNITS)}")
    return _ALIASES[key]


def unit_kind(unit):
    """Return the kind of a canonical unit: raw, pressure, force, mass, length, area, time.

    Examples
    --------
    >>> unit_kind("lbf"), unit_kind("kg")
    ('force', 'mass')
    """
    if unit not in _UNITS:
        raise TactilecalError(f"unit {unit!r} is not a canonical unit; pass it through "
                              "normalise_unit first")
    return _UNITS[unit][0]


def _convert(value, unit, kinds, target):
    unit = normalise_unit(unit)
    kind, factor = _UNITS[unit]
    if kind not in kinds:
        raise TactilecalError(f"cannot convert {unit!r} ({kind}) to {target}")
    result = value * factor
    if isinstance(value, float) and math.isfinite(value) and not math.isfinite(result):
        raise TactilecalError(f"{value:g} {unit} is beyond the largest number in {target}")
    return result


def length_to_mm(value, unit):
    """Convert a length (``mm``, ``cm``, ``m``, ``in``) to mm.

    Examples
    --------
    >>> length_to_mm(0.127, "centimeters")
    1.27
    """
    return _convert(value, unit, ("length",), "mm")


def area_to_mm2(value, unit):
    """Convert an area (``mm2``, ``cm2``, ``m2``, ``in2``) to mm2.

    Examples
    --------
    >>> round(area_to_mm2(0.016129, "cm2"), 6)
    1.6129
    """
    return _convert(value, unit, ("area",), "mm2")


def force_to_N(value, unit):
    """Convert a force (``N``, ``kN``, ``kgf``, ``lbf``) to newtons (g = 9.80665 m/s2).

    Examples
    --------
    >>> round(force_to_N(1.0, "lbf"), 6)
    4.448222
    """
    return _convert(value, unit, ("force",), "N")


def mass_to_N(value, unit):
    """Convert a dead-weight mass (``kg``, ``g``, ``lb``) to its weight in N (x 9.80665).

    Examples
    --------
    >>> round(mass_to_N(75.0001, "Kgs"), 4)
    735.4997
    """
    return _convert(value, unit, ("mass",), "N")


def pressure_to_kPa(value, unit):
    """Convert a pressure (``kPa``, ``MPa``, ``Pa``, ``psi``, ``bar``, ``mmHg``...) to kPa.

    Examples
    --------
    >>> round(pressure_to_kPa(350, "PSI"), 1)
    2413.2
    """
    return _convert(value, unit, ("pressure",), "kPa")


def time_to_s(value, unit):
    """Convert a duration (``s``, ``ms``, ``us``, ``min``) to seconds.

    Examples
    --------
    >>> time_to_s(250.0, "ms")
    0.25
    """
    return _convert(value, unit, ("time",), "s")


_HINT = re.compile(r"[\(\[]\s*([^\)\]]*?)\s*[\)\]]\s*$")


def unit_from_column(column, *, where="column name"):
    """Return the canonical unit hinted at the end of a column name, or None.

    ``"Load (lbf)"`` -> ``"lbf"``, ``"Force [kN]"`` -> ``"kN"``, ``"Time (ms)"`` -> ``"ms"``,
    ``"force"`` -> None.

    Raises
    ------
    ValueError
        If the brackets hold an unknown unit.

    Examples
    --------
    >>> unit_from_column("Load (lbf)"), unit_from_column("Force [kN]"), unit_from_column("t")
    ('lbf', 'kN', None)
    """
    match = _HINT.search(str(column))
    if match is None:
        return None
    return normalise_unit(match.group(1), where=where)


def display_pressure(own, units=None, *, where="units="):
    """Return ``(unit, factor)`` to show pressures: ``value_kPa / factor`` is in ``unit``.

    ``units`` when given (a pressure unit: kPa, MPa, psi...), else ``own`` (a recording's
    unit) when it is a pressure (an MPa recording is shown in MPa), else kPa. ``where``
    names the option in a message.

    Examples
    --------
    >>> display_pressure("MPa")
    ('MPa', 1000.0)
    >>> display_pressure("raw", "psi")[0], display_pressure("raw")
    ('psi', ('kPa', 1.0))
    """
    if units is None:
        own = normalise_unit(own) if own is not None else None
        units = own if own is not None and unit_kind(own) == "pressure" else "kPa"
    unit = normalise_unit(units, where=where)
    if unit_kind(unit) != "pressure":
        raise TactilecalError(f"{where} {units!r} is a {unit_kind(unit)} unit; expected a "
                              "pressure unit to show pressures in (kPa, MPa, psi...)")
    return unit, float(pressure_to_kPa(1.0, unit))
