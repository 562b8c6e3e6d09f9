"""The data model's check (``tactilecal._model``): what the readers write passes it, and an
array that breaks the model is a one-line error naming the recording and the part."""

import numpy as np
import pytest
import xarray as xr

import tactilecal.analysis  # noqa: F401 - registers recording.tactile
from tactilecal._model import check_recording
from tactilecal.io import open_recording, read_netcdf, write_netcdf, write_tekscan
from tactilecal.simulate import deadweight_session, make_sensor


@pytest.fixture(scope="module")
def recording():
    return deadweight_session(make_sensor("5051", seed=1), n_patches=3, seed=2).recording(0)


def test_what_the_readers_write_follows_the_model(recording, tmp_path):
    write_tekscan(recording, tmp_path / "r.csv")
    write_netcdf(recording, tmp_path / "r.nc")
    for read in (open_recording(tmp_path / "r.csv"), read_netcdf(tmp_path / "r.nc")):
        assert check_recording(read, values=True) == ("raw", "raw")


@pytest.mark.parametrize("name", ["iscan_csv", "fscan_asf", "fscan_right_asf"])
def test_the_real_exports_follow_the_model(name, request):
    data = open_recording(request.getfixturevalue(name))
    unit, kind = check_recording(data, values=True)
    assert unit == data.attrs["units"] and kind in ("raw", "pressure")


def _calibrated(recording):
    return recording.assign_attrs(units="kPa", sensel_area_mm2=1.6129, source="p.nc")


@pytest.mark.parametrize("change, message", [
    (lambda r: r.transpose("row", "frame", "col"),
     r"p.nc: dims \('row', 'frame', 'col'\); expected \('frame', 'row', 'col'\)"),
    (lambda r: r.assign_coords(time=("row", np.arange(r.sizes["row"], dtype=float))),
     r"p.nc: coordinate 'time' has dims \('row',\); expected it along 'frame'"),
    (lambda r: r.assign_attrs(units="furlong"),
     r"unknown unit 'furlong' in attribute 'units' of p.nc"),
    (lambda r: r.assign_attrs(units="mm"), r"p.nc: units 'mm' are a length; expected raw"),
    (lambda r: r.assign_attrs(sensel_area_mm2=-1.0),
     r"p.nc: attribute 'sensel_area_mm2' is -1.0; expected a positive area in mm2"),
    (lambda r: r.assign_attrs(row_spacing_mm=float("nan")),
     r"p.nc: attribute 'row_spacing_mm' is nan; expected a positive spacing in mm"),
])
def test_a_broken_model_is_one_line_naming_the_part(recording, change, message):
    broken = change(_calibrated(recording))
    with pytest.raises(ValueError, match=message):
        check_recording(broken)
    with pytest.raises(ValueError, match=message):  # the analysis checks it too
        broken.tactile.force()


def test_missing_units_and_not_a_dataarray(recording):
    bare = _calibrated(recording)
    del bare.attrs["units"]
    with pytest.raises(ValueError, match="p.nc: attribute 'units' is missing; expected raw"):
        check_recording(bare)
    with pytest.raises(TypeError, match="recording is a ndarray; expected an xarray.DataArray"):
        check_recording(np.zeros((2, 3, 4)))


@pytest.mark.parametrize("units, bad, message", [
    ("raw", 256.0, r"p.nc: frame \d+, row 1, col 2 is 256.0 \(1 such values\); expected raw "
                   r"readings are whole numbers 0..255"),
    ("raw", 12.5, r"row 1, col 2 is 12.5 .*whole numbers 0..255"),
    ("raw", -1.0, r"row 1, col 2 is -1.0 .*whole numbers 0..255"),
    ("kPa", -3.0, r"row 1, col 2 is -3.0 .*pressure values are finite and not negative"),
    ("N", np.inf, r"row 1, col 2 is inf .*force values are finite and not negative"),
])
def test_impossible_values_are_found_where_they_are(recording, units, bad, message):
    data = _calibrated(recording).assign_attrs(units=units).copy(deep=True)
    data[0, 1, 2] = bad
    with pytest.raises(ValueError, match=message):
        check_recording(data, values=True)
    data[0, 1, 2] = np.nan  # outside the sensor's shape: allowed
    check_recording(data, values=True)


def test_values_are_checked_only_when_asked(recording):
    """The default check reads attributes only: no pass over a (possibly lazy) array."""
    lazy = xr.DataArray(np.full((2, 3, 4), 300.0), dims=("frame", "row", "col"),
                        attrs={"units": "raw"}).chunk({"frame": 1})
    assert check_recording(lazy) == ("raw", "raw")
    with pytest.raises(ValueError, match="is 300.0 \\(24 such values\\)"):
        check_recording(lazy, values=True)
