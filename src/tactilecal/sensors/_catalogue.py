"""Catalogue of Tekscan sensor models and custom sensel matrices.

Every number in :data:`CATALOGUE` says where it comes from (``notes``). Sensel area is the
product of the two centre-to-centre spacings, which is how Tekscan's own exports report it
(``SENSEL_AREA 0.016129 cm2`` for a 1.27 mm pitch, ``25.8064 mm2`` for 5.08 mm).
"""

from dataclasses import dataclass
from typing import NamedTuple

from tactilecal._errors import TactilecalError
from tactilecal._units import PSI_TO_KPA

__all__ = ["SensorModel", "CATALOGUE", "get_sensor", "custom_sensor", "match_sensor",
           "SensorMatch"]


@dataclass(frozen=True)
class SensorModel:
    """A matrix tactile sensor: sensel grid, pitch and (where known) capacity.

    Parameters
    ----------
    name : str
        Model name, e.g. ``"5051"`` (Tekscan's ``SENSOR_TYPE``).
    rows, cols : int
        Number of sensel rows and columns.
    row_spacing_mm, col_spacing_mm : float
        Centre-to-centre sensel spacing in mm.
    capacity_kPa : float, optional
        Nominal pressure capacity in kPa, where the model has a fixed one.
    max_rate_hz : float, optional
        Maximum scan rate in Hz, where known.
    notes : str
        Where the numbers come from.

    Examples
    --------
    >>> s = SensorModel("demo", 2, 3, 1.0, 2.0)
    >>> s.sensel_area_mm2, s.width_mm, s.height_mm
    (2.0, 6.0, 2.0)
    """

    name: str
    rows: int
    cols: int
    row_spacing_mm: float
    col_spacing_mm: float
    capacity_kPa: float | None = None
    max_rate_hz: float | None = None
    notes: str = ""

    def __post_init__(self):
        for field in ("rows", "cols"):
            value = getattr(self, field)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise TactilecalError(f"sensor {self.name!r}: {field} must be a positive integer; "
                                      f"got {value!r}")
        for field in ("row_spacing_mm", "col_spacing_mm", "capacity_kPa", "max_rate_hz"):
            value = getattr(self, field)
            if field in ("capacity_kPa", "max_rate_hz") and value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
                raise TactilecalError(f"sensor {self.name!r}: {field} must be a positive number; "
                                      f"got {value!r}")

    @property
    def sensel_area_mm2(self):
        """Area of one sensel in mm2 (row spacing x column spacing)."""
        return self.row_spacing_mm * self.col_spacing_mm

    @property
    def width_mm(self):
        """Width of the sensing matrix in mm (cols x column spacing)."""
        return self.cols * self.col_spacing_mm

    @property
    def height_mm(self):
        """Height of the sensing matrix in mm (rows x row spacing)."""
        return self.rows * self.row_spacing_mm

    def to_attrs(self):
        """Return the data-model attributes describing this sensor (``docs/data-model.md``).

        Examples
        --------
        >>> get_sensor("9500").to_attrs()["row_spacing_mm"]
        5.08
        """
        return {"sensor_type": self.name, "row_spacing_mm": self.row_spacing_mm,
                "col_spacing_mm": self.col_spacing_mm,
                "sensel_area_mm2": self.sensel_area_mm2}


_ZVYAGIN = ("Zvyagin (2022), Sensors 22(19):7290: 44 x 44 sensels of 1.27 x 1.27 mm, "
            "matrix 55.9 mm")

CATALOGUE = {
    "5051": SensorModel(
        "5051", 44, 44, 1.27, 1.27,
        notes=f"{_ZVYAGIN}. Capacity depends on the pressure grade (suffix)."),
    "5051-350": SensorModel(
        "5051-350", 44, 44, 1.27, 1.27, capacity_kPa=350 * PSI_TO_KPA,
        notes=f"{_ZVYAGIN}; nominal 350 psi = 2413 kPa."),
    "5101": SensorModel(
        "5101", 44, 44, 2.54, 2.54,
        notes="44 x 44 sensels, twice the 5051's size (2.54 mm pitch, 111.8 mm matrix) "
              "(Tekscan's catalogue). Capacity depends on the pressure grade."),
    "9500": SensorModel(
        "9500", 14, 14, 5.08, 5.08, max_rate_hz=4000.0,
        notes="Gillis (2013) MS thesis, U. Colorado: 14 x 14 sensels over 71.1 x 71.1 mm "
              "(5.08 mm pitch), 4000 Hz per sensel."),
    "6900": SensorModel(
        "6900", 28, 28, 1.27, 1.27,
        notes="From a real I-Scan 6.10I export (pressuRe iscan_test.csv): SENSOR_TYPE 6900, "
              "ROWS 28, COLS 28, ROW_SPACING 0.127 centimeters, SENSEL_AREA 0.016129 cm2."),
    "FSCAN": SensorModel(
        "FSCAN", 60, 21, 5.08, 5.08,
        notes="F-Scan insole from a real F-Scan 6.33 export (footPress FrasP01L.asf): "
              "ROWS 60, COLS 21, ROW_SPACING 5.08 mm, SENSEL_AREA 25.8064 mm2."),
    "4010N": SensorModel(
        "4010N", 22, 34, 2.0, 2.0,
        notes="I-Scan knee (tibiofemoral) sensor as its ASCII exports describe it (a rebuilt "
              "I-Scan 5.90I export): 22 rows x 34 columns, 2.0 mm spacing, 4 mm2 sensels, the "
              "outline of the two condyle pads written as B cells."),
}
"""Known sensor models by name (upper case)."""

GEOMETRY_RTOL = 0.01
"""Relative tolerance on spacings when a file is matched to an entry by its geometry."""


class SensorMatch(NamedTuple):
    """Which catalogue entry a recording matches, and how (see :func:`match_sensor`)."""

    entry: SensorModel | None
    how: str


def match_sensor(sensor_type=None, *, rows=None, cols=None, row_spacing_mm=None,
                 col_spacing_mm=None):
    """Find the catalogue entry of a recording from its ``SENSOR_TYPE`` or its geometry.

    The name is tried first (exactly, then without a pressure-grade suffix: ``5051-350``
    finds ``5051-350``, ``5051-1000`` finds ``5051``); when it names no entry, the entry with
    the same rows, columns and spacings (within :data:`GEOMETRY_RTOL`) is taken, if exactly
    one has them. A name that matches an entry whose geometry differs from the file's is
    still reported, with the difference.

    Parameters
    ----------
    sensor_type : str, optional
        The file's ``SENSOR_TYPE``.
    rows, cols : int, optional
        The file's sensel grid.
    row_spacing_mm, col_spacing_mm : float, optional
        The file's spacings.

    Returns
    -------
    SensorMatch
        ``entry`` (None when nothing matches) and ``how`` it was matched, in words.

    Examples
    --------
    >>> match_sensor("5051-1000").how
    "SENSOR_TYPE '5051-1000' (entry 5051, without the pressure grade)"
    >>> m = match_sensor("KNEE", rows=22, cols=34, row_spacing_mm=2.0, col_spacing_mm=2.0)
    >>> m.entry.name, m.how
    ('4010N', 'geometry 22 x 34 sensels at 2 x 2 mm')
    """
    geometry = (rows, cols, row_spacing_mm, col_spacing_mm)
    entry, how = _match_name(sensor_type)
    if entry is not None:
        differs = _geometry_difference(entry, *geometry)
        return SensorMatch(entry, how + (f"; but the file's {differs}" if differs else ""))
    if None in geometry:
        return SensorMatch(None, f"no entry named {sensor_type!r} and no full geometry to match")
    hits = [e for e in CATALOGUE.values() if not _geometry_difference(e, *geometry)]
    shape = f"{rows} x {cols} sensels at {row_spacing_mm:g} x {col_spacing_mm:g} mm"
    if len(hits) == 1:
        return SensorMatch(hits[0], f"geometry {shape}")
    found = f"several entries ({', '.join(e.name for e in hits)})" if hits else "no entry"
    return SensorMatch(None, f"no entry named {sensor_type!r}; {found} with {shape}")


def _match_name(sensor_type):
    key = str(sensor_type or "").strip().upper()
    if key in CATALOGUE:
        return CATALOGUE[key], f"SENSOR_TYPE {sensor_type!r}"
    base = key.split("-")[0]
    if base and base in CATALOGUE:
        return CATALOGUE[base], (f"SENSOR_TYPE {sensor_type!r} (entry {base}, without the "
                                 "pressure grade)")
    return None, ""


def _geometry_difference(entry, rows, cols, row_spacing_mm, col_spacing_mm):
    """Describe how a file's geometry differs from ``entry`` ('' when it agrees or is unknown)."""
    differences = []
    if rows is not None and cols is not None and (rows, cols) != (entry.rows, entry.cols):
        differences.append(f"grid is {rows} x {cols}, the entry's {entry.rows} x {entry.cols}")
    for value, expected, label in ((row_spacing_mm, entry.row_spacing_mm, "row spacing"),
                                   (col_spacing_mm, entry.col_spacing_mm, "column spacing")):
        if value is not None and abs(value - expected) > GEOMETRY_RTOL * expected:
            differences.append(f"{label} is {value:g} mm, the entry's {expected:g} mm")
    return "; ".join(differences)


def get_sensor(name):
    """Return the catalogue entry for ``name`` (case-insensitive, e.g. ``"5051-350"``).

    Parameters
    ----------
    name : str or int
        Model name as in :data:`CATALOGUE` or in a Tekscan ``SENSOR_TYPE`` line.

    Returns
    -------
    SensorModel

    Raises
    ------
    ValueError
        If the model is not in the catalogue (the message lists the known ones).

    Examples
    --------
    >>> s = get_sensor("5051-350")
    >>> s.rows, s.cols, round(s.capacity_kPa)
    (44, 44, 2413)
    """
    key = str(name).strip().upper()
    if key not in CATALOGUE:
        raise TactilecalError(f"unknown sensor {name!r}; expected one of {sorted(CATALOGUE)} "
                              "or a custom_sensor(rows, cols, spacing_mm)")
    return CATALOGUE[key]


def custom_sensor(rows, cols, spacing_mm, *, col_spacing_mm=None, capacity_kPa=None,
                  max_rate_hz=None, name="custom", notes=""):
    """Describe a sensel matrix that is not in the catalogue.

    Parameters
    ----------
    rows, cols : int
        Sensel rows and columns.
    spacing_mm : float
        Row spacing in mm (also the column spacing unless ``col_spacing_mm`` is given).
    col_spacing_mm, capacity_kPa, max_rate_hz : float, optional
        See :class:`SensorModel`.
    name, notes : str
        Label and provenance.

    Returns
    -------
    SensorModel

    Examples
    --------
    >>> custom_sensor(10, 20, 2.0, col_spacing_mm=3.0).sensel_area_mm2
    6.0
    """
    return SensorModel(name, rows, cols, spacing_mm,
                       spacing_mm if col_spacing_mm is None else col_spacing_mm,
                       capacity_kPa=capacity_kPa, max_rate_hz=max_rate_hz, notes=notes)
