"""The calibration a Tekscan export carries in its header, as a CalibrationResult."""

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._units import N_PER_MM2_TO_KPA, pressure_to_kPa, unit_kind
from tactilecal._validate import check_number
from tactilecal.calibration._calibrate import CommonOptions, law_result
from tactilecal.calibration._fit import Fit

__all__ = ["header_calibration"]


def header_calibration(recording):
    """Rebuild the calibration stored in a Tekscan file's header.

    ``SCALE_FACTOR`` and ``EXPONENT`` (I-Scan 2-point power law, pressure = scale x
    raw**exponent) give a power model directly; otherwise ``CALIBRATION_POINT_1`` (load,
    raw sum, loaded cells) gives I-Scan's 1-point linear calibration through zero,
    pressure = load / (raw sum x sensel area) per count (Gillis 2013, sec. 3.5).

    Parameters
    ----------
    recording : xarray.DataArray or dict
        A recording from :func:`tactilecal.io.read_tekscan`, or its ``attrs``.

    Returns
    -------
    CalibrationResult
        Method ``"header-power-2pt"`` or ``"header-linear"``, model ``"power"``; one point
        (the header's calibration point) when there is one.

    Raises
    ------
    TactilecalError
        If the header has neither, or no sensel area.

    Examples
    --------
    >>> attrs = {"sensel_area_mm2": 25.8064, "calibration_point_1_load_N": 735.4997,
    ...          "calibration_point_1_raw_sum": 4798.0, "calibration_point_1_loaded_cells": 240}
    >>> cal = header_calibration(attrs)
    >>> round(cal.params["A"] / cal.sensel_area_mm2 * 1000, 2)  # kPa per count
    5.94
    """
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
    hist = np.zeros((1, 256))
    if cells:  # the header keeps only sums: spread the raw sum evenly over the cells
        if not 0 < raw_sum <= 255 * cells:
            raise TactilecalError(f"{name}: CALIBRATION_POINT_1 has a raw sum of {raw_sum:g} over "
                                  f"{cells} loaded cells; expected 1..{255 * cells} (0..255 each)")
        lo = min(int(raw_sum // cells), 254)
        hist[0, lo], hist[0, lo + 1] = cells - (raw_sum - lo * cells), raw_sum - lo * cells
    return _result({"A": load / raw_sum, "b": 1.0}, "header-linear", area, hist,
                   np.array([load]), [raw_sum, cells])


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
    params = {"A": scale_kPa * area / N_PER_MM2_TO_KPA, "b": exponent}
    return _result(params, "header-power-2pt", area, np.zeros((0, 256)), np.zeros(0), [])


def _result(params, method, area, hist, load, point):
    meta = {"file": np.array(["header"] * len(load), dtype=object),
            "frame": np.zeros(len(load), int), "raw_sum": np.array(point[:1] * len(load)),
            "loaded_cells": np.array(point[1:] * len(load), dtype=int),
            "saturated_cells": np.zeros(len(load), int),
            "label": np.array(["CALIBRATION_POINT_1"] * len(load), dtype=object),
            "note": np.array([""] * len(load), dtype=object),
            "sensel_area_mm2": np.full(len(load), area),
            "working_cells": np.zeros(len(load), int), "total_cells": np.zeros(len(load), int)}
    return law_result(hist, load, meta, method,
                      Fit("power", params, {"source": "Tekscan file header"}),
                      np.ones(len(load), bool), np.full(len(load), "", dtype=object), area,
                      CommonOptions(sensel_area_mm2=area))
