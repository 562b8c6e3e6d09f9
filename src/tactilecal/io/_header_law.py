"""The calibration law a Tekscan export's header states, as numbers.

Reading it needs no fit (no SciPy): :func:`tactilecal.analysis.describe` inverts it to give
a calibrated export's largest raw reading.
"""

import os
from dataclasses import dataclass

from tactilecal._errors import TactilecalError
from tactilecal._units import N_PER_MM2_TO_KPA, pressure_to_kPa, unit_kind
from tactilecal._validate import check_number

__all__ = ["HeaderLaw", "header_law"]


@dataclass(frozen=True)
class HeaderLaw:
    """A header's law ``f(raw) = A * raw**b`` (newtons on one sensel) and where it came from.

    Attributes
    ----------
    A : float
        N on one sensel at a raw reading of 1.
    b : float
        Exponent (1 for the 1-point linear calibration).
    method : str
        ``"header-power-2pt"`` (``SCALE_FACTOR``/``EXPONENT``) or ``"header-linear"``
        (``CALIBRATION_POINT_1``).
    sensel_area_mm2 : float
    load_N, raw_sum, loaded_cells : float, float, int or None
        The header's calibration point (``"header-linear"`` only; 0 cells: not stated).
    """

    A: float
    b: float
    method: str
    sensel_area_mm2: float
    load_N: float | None = None
    raw_sum: float | None = None
    loaded_cells: int | None = None

    def raw_of_force_N(self, force_N):
        """Raw reading whose force on one sensel is ``force_N``: ``(force_N / A)**(1 / b)``."""
        return (force_N / self.A) ** (1.0 / self.b)


def header_law(recording):
    """Return the calibration law stored in a Tekscan file's header.

    ``SCALE_FACTOR`` and ``EXPONENT`` (I-Scan 2-point power law, pressure = scale x
    raw**exponent in the file's pressure unit) give the power law directly; otherwise
    ``CALIBRATION_POINT_1`` (load, raw sum, loaded cells) gives I-Scan's 1-point linear
    calibration through zero, force per count = load / raw sum (Gillis 2013, sec. 3.5).
    :func:`tactilecal.calibration.header_calibration` builds a full calibration result from
    it.

    Parameters
    ----------
    recording : xarray.DataArray or dict
        A recording from :func:`tactilecal.io.read_tekscan`, or its ``attrs``.

    Returns
    -------
    HeaderLaw

    Raises
    ------
    TactilecalError
        If the header has neither law, no sensel area, a power law without a pressure unit,
        or a raw sum outside 1..255 x the loaded cells.
    TypeError
        If ``recording`` is a path (read the file with :func:`read_tekscan` first).

    Examples
    --------
    >>> law = header_law({"sensel_area_mm2": 25.8064, "calibration_point_1_load_N": 735.4997,
    ...                   "calibration_point_1_raw_sum": 4798.0,
    ...                   "calibration_point_1_loaded_cells": 240})
    >>> law.method, round(law.A / law.sensel_area_mm2 * 1000, 2)  # kPa per count
    ('header-linear', 5.94)
    """
    if isinstance(recording, str | os.PathLike):
        raise TypeError(f"header_law takes a recording or its attrs, not the path {recording}; "
                        "read it with tactilecal.io.read_tekscan first")
    attrs = dict(getattr(recording, "attrs", recording))
    name = attrs.get("source", "recording")
    area = attrs.get("sensel_area_mm2")
    if area is None:
        raise TactilecalError(f"{name}: no sensel_area_mm2 in the header; expected SENSEL_AREA")
    area = float(area)
    if "scale_factor" in attrs and "exponent" in attrs:
        return _power_law(attrs, name, area)
    if "calibration_point_1_load_N" not in attrs:
        raise TactilecalError(f"{name}: the header has no CALIBRATION_POINT_1 and no SCALE_FACTOR/"
                              "EXPONENT; expected a Tekscan calibration in the header")
    load = float(attrs["calibration_point_1_load_N"])
    raw_sum = float(attrs["calibration_point_1_raw_sum"])
    cells = int(attrs.get("calibration_point_1_loaded_cells", 0))
    if cells and not 0 < raw_sum <= 255 * cells:
        raise TactilecalError(f"{name}: CALIBRATION_POINT_1 has a raw sum of {raw_sum:g} over "
                              f"{cells} loaded cells; expected 1..{255 * cells} (0..255 each)")
    return HeaderLaw(A=load / raw_sum, b=1.0, method="header-linear", sensel_area_mm2=area,
                     load_N=load, raw_sum=raw_sum, loaded_cells=cells)


def _power_law(attrs, name, area):
    """Pressure = SCALE_FACTOR x raw**EXPONENT in the file's pressure unit (I-Scan 2-point).

    The unit is the header's ``UNITS`` when it is a pressure, else the unit of its
    ``SATURATION_PRESSURE``; with neither the law has no unit and is an error.
    """
    candidates = (attrs.get("units"), attrs.get("saturation_pressure_unit"))
    unit = next((u for u in candidates if u is not None and unit_kind(u) == "pressure"), None)
    if unit is None:
        raise TactilecalError(f"{name}: SCALE_FACTOR/EXPONENT without a pressure unit (UNITS is "
                              f"{attrs.get('units')!r}, no SATURATION_PRESSURE unit); expected "
                              "UNITS e.g. MPa or kPa")
    scale = check_number(attrs["scale_factor"], f"SCALE_FACTOR of {name}", minimum=0,
                         min_inclusive=False)
    exponent = check_number(attrs["exponent"], f"EXPONENT of {name}", minimum=0,
                            min_inclusive=False)
    scale_kPa = float(pressure_to_kPa(scale, unit))
    return HeaderLaw(A=scale_kPa * area / N_PER_MM2_TO_KPA, b=exponent,
                     method="header-power-2pt", sensel_area_mm2=area)
