"""Every remaining bad-input message of the calibration package, one pytest.raises each."""

import json

import numpy as np
import pytest
import xarray as xr

from tactilecal.calibration import (
    METHODS,
    CalibrationPoint,
    CalibrationResult,
    calibrate,
    calibrate_movie,
    frame_histograms,
    header_calibration,
    points_from_frames,
    validate,
)


def _points(n=6, seed=0, area=None):
    rng = np.random.default_rng(seed)
    raw = np.zeros((n, 6, 6))
    for i in range(n):
        raw[i, 1:4, 1:4] = rng.integers(5, 200, size=(3, 3))
    load = 0.0035 * (raw ** 1.16).sum(axis=(1, 2))
    return points_from_frames(raw, load, sensel_area_mm2=area)


def test_points_errors():
    with pytest.raises(ValueError, match="raw frames have 1 dimensions; expected 3"):
        frame_histograms(np.zeros(4))
    with pytest.raises(ValueError, match="frames has 1 entries; expected 2"):
        points_from_frames(np.zeros((2, 3, 3)), [1.0, 2.0], frames=[1])


def test_method_option_errors():
    pts = _points()
    one = _points(1)
    with pytest.raises(ValueError, match=r"method 'power-2pt' needs at least two different "
                                         r"loads .* the 1 usable points all have load_N"):
        calibrate(one, method="power-2pt")
    with pytest.raises(ValueError, match=r"pair=\[0, 0\] is invalid; expected two different"):
        calibrate(pts, method="power-2pt", pair=(0, 0))
    with pytest.raises(ValueError, match="best exponent b = 1.000 is at the edge of b_bounds"):
        calibrate(pts, method="power", b_bounds=(0.5, 1.0))
    with pytest.raises(ValueError, match="degree=0; expected an integer >= 1"):
        calibrate(pts, method="polynomial", degree=0)
    with pytest.raises(ValueError, match=r"knots=\[1.0, 1.0\] must increase and be > 0"):
        calibrate(pts, method="piecewise", knots=(1, 1))
    with pytest.raises(ValueError, match=r"knots=\[0.0, 100.0\] must increase from 0 to 255"):
        calibrate(pts, method="lut", knots=(0, 100))
    with pytest.raises(ValueError, match="objective='l1' is not an option of linear-offset"):
        calibrate(pts, method="linear-offset", objective="l1")
    with pytest.raises(ValueError, match=r"only [01] out-of-bag errors from 1 resamples "
                                         r"\([01] could not be fitted\); expected at least 20"):
        calibrate(_points(3), method="power-2pt", n_interval_resamples=1)


@pytest.mark.parametrize("method", METHODS)
def test_points_of_two_sensel_areas_are_refused_by_every_method(method):
    mixed = _points(12, area=1.6129) + _points(12, seed=1, area=25.8064)
    with pytest.raises(ValueError, match=r"points have different sensel areas \[1.6129, "
                                         r"25.8064\] mm2; expected one sensor model"):
        calibrate(mixed, method=method)


def test_area_and_validate_errors(tmp_path):
    mixed = _points(3, area=1.6) + _points(3, seed=1, area=2.0)
    with pytest.raises(ValueError, match="points have different sensel areas"):
        calibrate(mixed, method="power")
    res = calibrate(_points(area=1.6129), method="power")
    rec = xr.DataArray(np.zeros((1, 6, 6)), dims=("frame", "row", "col"),
                       attrs={"units": "raw", "sensel_area_mm2": 25.8})
    with pytest.raises(ValueError, match="sensel_area_mm2 = 25.8 differs from the calibration"):
        res.apply(rec)
    with pytest.raises(ValueError, match="sensel_area_mm2 = 25.8 differs from the calibration"):
        res.apply(rec, units="N")  # a force per sensel does not transfer between sizes either
    hist = np.zeros(256, np.int64)
    hist[255] = 1
    sat = CalibrationPoint(histogram=hist, load_N=1.0, raw_sum=255.0, loaded_cells=1,
                           saturated_cells=1)
    with pytest.raises(ValueError, match="none of the 1 validation points"):
        validate(res, [sat])
    path = tmp_path / "list.json"
    path.write_text(json.dumps([1, 2]))
    with pytest.raises(ValueError, match="list.json: JSON list; expected an object"):
        CalibrationResult.from_json(path)


def test_movie_and_header_errors():
    rec = xr.DataArray(np.zeros((4, 3, 3)), dims=("frame", "row", "col"), attrs={"units": "kPa"})
    with pytest.raises(ValueError, match="has units 'kPa'; expected raw readings"):
        calibrate_movie(rec, np.ones(4))
    loads = xr.DataArray(np.ones(5), dims="time", coords={"time": np.arange(5.0)})
    with pytest.raises(ValueError, match="neither a time coordinate nor seconds_per_frame"):
        calibrate_movie(rec.assign_attrs(units="raw"), loads)
    with pytest.raises(ValueError, match="no sensel_area_mm2 in the header"):
        header_calibration({"source": "x.csv"})
