"""The data model's check (``tactilecal._model``): what the readers write passes it, and an
array that breaks the model is a one-line error naming the recording and the part."""

import functools
import re

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

import tactilecal.analysis  # noqa: F401 - registers recording.tactile
from tactilecal._model import check_recording, usable_values
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


# --------------------------------------------- values a calculation may use (usable_values)
@st.composite
def _placed_value(draw):
    """A recording (in memory or chunked along any dim), a position and a value there."""
    shape = tuple(draw(st.integers(1, 4)) for _ in range(3))
    position = tuple(draw(st.integers(0, n - 1)) for n in shape)
    chunks = draw(st.none() | st.fixed_dictionaries(
        {}, optional={dim: st.integers(1, 3) for dim in ("frame", "row", "col")}))
    first = draw(st.integers(1, 10**6))  # frames are numbered from where the export began
    return shape, position, chunks, first


def _with(shape, position, chunks, first, units, value):
    data = np.full(shape, 7.0)
    data[position] = value
    recording = xr.DataArray(data, dims=("frame", "row", "col"),
                             coords={"frame": np.arange(first, first + shape[0])},
                             attrs={"units": units, "sensel_area_mm2": 1.6129, "source": "m"})
    return recording if chunks is None else recording.chunk(chunks)


@given(_placed_value(), st.sampled_from(["raw", "kPa"]),
       st.floats(allow_nan=False) | st.sampled_from([np.inf, -np.inf, 255.5, -1e-300]))
def test_a_value_no_calculation_may_use_is_named_where_it_is(placed, units, value):
    """Raw readings outside 0..255 and infinite calibrated values are refused by
    ``CalibrationResult.apply`` and the analysis, naming the frame, row and column, also
    when the recording is chunked (the error is raised as it is computed); NaN, fractions
    of raw readings (equilibrated frames) and negative calibrated values (a dynamic
    filter's undershoot) are used."""
    shape, position, chunks, first = placed
    recording = _with(shape, position, chunks, first, units, value)
    usable = 0 <= value <= 255 if units == "raw" else np.isfinite(value)
    kind = "raw" if units == "raw" else "calibrated"
    door = (lambda r: _power_law().apply(r)) if units == "raw" else \
        (lambda r: r.tactile.force())
    if usable:
        assert usable_values(recording, kind).values[position] == value
        assert door(recording).compute().size
        return
    frame, row, col = position
    with pytest.raises(ValueError, match=rf"^m: frame {first + frame}, row {row}, col {col} "
                                         rf"is {re.escape(repr(value))} \(1 such values\)"):
        usable_values(recording, kind).compute()
    with pytest.raises(ValueError, match=rf"frame {first + frame}, row {row}, col {col}"):
        door(recording).compute()


@functools.cache
def _power_law():
    from tactilecal.calibration import calibrate, points_from_frames

    session = deadweight_session(make_sensor("5051", seed=1), n_patches=6, seed=2)
    return calibrate(points_from_frames(session.raw, session.load_N), method="power")
