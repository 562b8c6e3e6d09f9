"""The calibration a Tekscan export carries in its header, as a CalibrationResult."""

import numpy as np

from tactilecal.calibration._calibrate import CommonOptions, law_result
from tactilecal.calibration._fit import Fit
from tactilecal.io import header_law

__all__ = ["header_calibration"]


def header_calibration(recording):
    """Rebuild the calibration stored in a Tekscan file's header.

    The law is the header's (:func:`tactilecal.io.header_law`): ``SCALE_FACTOR`` and
    ``EXPONENT`` (I-Scan 2-point power law, pressure = scale x raw**exponent) or
    ``CALIBRATION_POINT_1`` (load, raw sum, loaded cells: I-Scan's 1-point linear calibration
    through zero, pressure = load / (raw sum x sensel area) per count, Gillis 2013,
    sec. 3.5). The 1-point calibration's point becomes the result's one point, its raw sum
    spread evenly over its loaded cells (the header keeps only sums).

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
    law = header_law(recording)
    hist = np.zeros((0 if law.load_N is None else 1, 256))
    cells, raw_sum = law.loaded_cells, law.raw_sum
    if cells:
        lo = min(int(raw_sum // cells), 254)
        hist[0, lo], hist[0, lo + 1] = cells - (raw_sum - lo * cells), raw_sum - lo * cells
    return _result(law, hist)


def _result(law, hist):
    """Return the result of ``law`` with its point (none for the 2-point power law)."""
    point = [] if law.load_N is None else [law.raw_sum, law.loaded_cells]
    load = np.array([law.load_N] if point else [], dtype=float)
    params, area = {"A": law.A, "b": law.b}, law.sensel_area_mm2
    meta = {"file": np.array(["header"] * len(load), dtype=object),
            "frame": np.zeros(len(load), int), "raw_sum": np.array(point[:1] * len(load)),
            "loaded_cells": np.array(point[1:] * len(load), dtype=int),
            "saturated_cells": np.zeros(len(load), int),
            "label": np.array(["CALIBRATION_POINT_1"] * len(load), dtype=object),
            "note": np.array([""] * len(load), dtype=object),
            "sensel_area_mm2": np.full(len(load), area),
            "working_cells": np.zeros(len(load), int), "total_cells": np.zeros(len(load), int)}
    return law_result(hist, load, meta, law.method,
                      Fit("power", params, {"source": "Tekscan file header"}),
                      np.ones(len(load), bool), np.full(len(load), "", dtype=object), area,
                      CommonOptions(sensel_area_mm2=area))
