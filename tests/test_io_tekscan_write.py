"""write_tekscan / write_netcdf: round trips on the real exports and simulated data."""

import numpy as np
import pytest
import xarray as xr

from tactilecal.io import read_netcdf, read_tekscan, write_netcdf, write_tekscan


def _without_source(data):
    out = data.copy()
    out.attrs.pop("source")
    return out


@pytest.mark.parametrize("newline", ["\n", "\r\n"])
def test_real_files_round_trip(iscan_csv, fscan_asf, tmp_path, newline):
    for path in (iscan_csv, fscan_asf):
        data = read_tekscan(path)
        out = tmp_path / path.name
        write_tekscan(data, out, newline=newline)
        back = read_tekscan(out)
        assert back.attrs["source"] == str(out)
        xr.testing.assert_identical(_without_source(back), _without_source(data))


def test_real_iscan_layout_kept(iscan_csv, tmp_path):
    out = tmp_path / "copy.csv"
    write_tekscan(read_tekscan(iscan_csv), out)
    original = iscan_csv.read_text().splitlines()
    written = out.read_text().splitlines()
    assert written[:26] == original[:26]  # header verbatim, same order, ASCII_DATA @@
    assert written[27] == "Frame 1, 0,,,,,Raw Sum=,,310"  # date field not kept
    same = [a == b for a, b in zip(original, written, strict=True) if not a.startswith("F")]
    assert all(same)  # every data row byte-identical


def _simulated(rng, n_frames=5, rows=6, cols=4, units="raw"):
    values = rng.integers(0, 256, size=(n_frames, rows, cols)).astype(np.float64)
    values[:, 0, 0] = np.nan
    if units != "raw":
        values = values * 5.94 + rng.normal(0, 1e-3, values.shape)  # non-integral floats
    values[:, 1, 1] = 0.0
    return xr.DataArray(
        values, dims=("frame", "row", "col"),
        coords={"frame": np.arange(3, 3 + n_frames, dtype=np.int64),
                "time": ("frame", np.cumsum(rng.uniform(0.01, 0.1, n_frames))),
                "row": np.arange(rows, dtype=np.int64), "col": np.arange(cols, dtype=np.int64)},
        attrs={"sensor_type": "5051", "units": units, "row_spacing_mm": 1.27,
               "col_spacing_mm": 1.27, "sensel_area_mm2": 1.6129, "seconds_per_frame": 0.005,
               "noise_threshold": 3, "sensitivity": "S-29", "saturation_pressure": 1403.0,
               "saturation_pressure_unit": "kPa", "saturation_pressure_kPa": 1403.0,
               "calibration_point_1_load": 2.0, "calibration_point_1_load_unit": "kg",
               "calibration_point_1_load_N": 2.0 * 9.80665,
               "calibration_point_1_raw_sum": 812.0, "calibration_point_1_loaded_cells": 31,
               "calibration_mode_1": "Point", "scale_factor": 0.00358, "exponent": 1.164})


@pytest.mark.parametrize("units", ["raw", "kPa"])
def test_simulated_round_trip_exact(tmp_path, units):
    data = _simulated(np.random.default_rng(7), units=units)
    out = tmp_path / "sim.asf"
    write_tekscan(data, out)
    back = read_tekscan(out)
    np.testing.assert_array_equal(back.values, data.values)  # bit-exact, NaN in place
    np.testing.assert_array_equal(back.time.values, data.time.values)
    np.testing.assert_array_equal(back.frame.values, data.frame.values)
    for key, value in data.attrs.items():
        assert back.attrs[key] == value, key
    body = out.read_text().split("ASCII_DATA @@")[1]
    assert ",0," in body  # integral values without decimals (values[:, 1, 1] == 0 in kPa)
    rows = [line for line in body.splitlines() if line[:1].isdigit() or line[:1] == "B"]
    assert len(rows) == 5 * 6
    if units == "raw":
        assert not any("." in row for row in rows)


def test_changed_attrs_rewrite_the_header(iscan_csv, tmp_path):
    data = read_tekscan(iscan_csv).isel(frame=slice(10, 20), row=slice(2, 13))
    data = (data * 2.0).assign_attrs(units="kPa", row_spacing_mm=2.54)
    out = tmp_path / "cut.csv"
    write_tekscan(data, out)
    back = read_tekscan(out)
    assert back.shape == (10, 11, 28) and back.frame.values[0] == 11
    assert back.attrs["units"] == "kPa" and back.attrs["row_spacing_mm"] == 2.54
    assert back.attrs["tekscan_START_FRAME"] == "11" and back.attrs["tekscan_ROWS"] == "11"
    assert back.attrs["col_spacing_mm"] == pytest.approx(1.27)
    assert "COL_SPACING 0.127 centimeters" in out.read_text()
    # no Raw Sum for calibrated data (it would no longer equal the frame's sum)
    assert "Raw Sum" not in out.read_text()


def test_write_is_atomic_on_error(tmp_path):
    out = tmp_path / "keep.csv"
    good = _simulated(np.random.default_rng(1))
    write_tekscan(good, out)
    old = out.read_bytes()
    bad = good.copy(deep=True)
    bad.values[2, 3, 1] = np.inf
    with pytest.raises(ValueError, match=r"frame 5 holds infinite values; expected finite"):
        write_tekscan(bad, out, overwrite=True)
    assert out.read_bytes() == old and len(list(tmp_path.iterdir())) == 1


def test_an_existing_file_is_replaced_only_if_asked_and_only_an_export(tmp_path):
    data = _simulated(np.random.default_rng(1))
    out = tmp_path / "e.csv"
    out.write_text("time,load\n0,1\n")
    with pytest.raises(ValueError, match=r"e.csv exists; expected a new path \(pass "
                                         r"overwrite=True to replace it\)"):
        write_tekscan(data, out)
    with pytest.raises(ValueError, match=r"e.csv is a text file, not a Tekscan export written "
                                         "before; expected a new path"):
        write_tekscan(data, out, overwrite=True)
    assert out.read_text() == "time,load\n0,1\n"
    out.unlink()
    write_tekscan(data, out)
    write_tekscan(data.isel(frame=slice(0, 2)), out, overwrite=True)
    assert read_tekscan(out).sizes["frame"] == 2


def test_writer_bad_input(tmp_path):
    data = _simulated(np.random.default_rng(2))
    with pytest.raises(ValueError, match=r"dims \('row', 'frame', 'col'\); expected"):
        write_tekscan(data.transpose("row", "frame", "col"), tmp_path / "a.csv")
    with pytest.raises(ValueError, match=r"frame numbers \[3, 3, 5, 6, 7\]...; expected incr"):
        write_tekscan(data.assign_coords(frame=[3, 3, 5, 6, 7]), tmp_path / "a.csv")
    with pytest.raises(ValueError, match=r"would not read back; expected a single line"):
        write_tekscan(data.assign_attrs(tekscan_TIME="a\nb"), tmp_path / "a.csv")
    with pytest.raises(ValueError, match=r"data has no frames; expected at least one"):
        write_tekscan(data.isel(frame=slice(0, 0)), tmp_path / "a.csv")
    with pytest.raises(ValueError, match=r"newline='\\r'; expected"):
        write_tekscan(data, tmp_path / "a.csv", newline="\r")


def test_netcdf_round_trip(iscan_csv, tmp_path):
    data = read_tekscan(iscan_csv)
    out = tmp_path / "a.nc"
    write_netcdf(data, out)
    back = read_netcdf(out)
    xr.testing.assert_identical(back, data)
    assert back.frame.dtype == np.int64
    fitted = data.isel(frame=0).assign_attrs(calibration={"A": 0.1, "b": [1.2, None]},
                                             ok=True)
    write_netcdf(fitted, out, overwrite=True)
    xr.testing.assert_identical(read_netcdf(out), fitted)


def test_blocks_and_wide_integers_round_trip(tmp_path, monkeypatch):
    import tactilecal.io._tekscan_write as writer

    monkeypatch.setattr(writer, "_BLOCK_VALUES", 50)  # 2 frames per block, 3 blocks
    rng = np.random.default_rng(3)
    data = _simulated(rng, n_frames=5, units="kPa")
    data.values[0] = rng.integers(-10**9, 10**9, size=data.shape[1:])  # beyond the lookup
    data.values[1, 2, 2] = 2.0**60  # integral but not exact as int64 text: float repr
    out = tmp_path / "wide.csv"
    write_tekscan(data, out, newline="\r\n")
    back = read_tekscan(out)
    np.testing.assert_array_equal(back.values, data.values)
    assert out.read_bytes().count(b"\r\n") == out.read_bytes().count(b"\n")


def test_fresh_header_in_tekscan_order(tmp_path):
    out = tmp_path / "fresh.csv"
    write_tekscan(_simulated(np.random.default_rng(5)), out)
    keys = [line.split()[0] for line in out.read_text().split("ASCII_DATA")[0].splitlines()]
    assert keys[:4] == ["DATA_TYPE", "SENSOR_TYPE", "ROWS", "COLS"]
    assert keys[-3:] == ["START_FRAME", "END_FRAME", "UNITS"]
    assert keys.index("SATURATION_PRESSURE") < keys.index("CALIBRATION_POINT_1")


def test_netcdf3_limit_is_explained(tmp_path, monkeypatch):
    import tactilecal.io._netcdf as netcdf

    monkeypatch.setattr(netcdf, "_engine", lambda: "scipy")
    big = xr.DataArray(np.array([2**40]), dims="x")
    out = tmp_path / "big.nc"
    with pytest.raises(ValueError, match=r"cannot write .*big.nc as NetCDF3 \(h5py is not "
                                         r"installed.*install h5py or convert to float64"):
        write_netcdf(big, out)
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_read_netcdf_errors_name_the_file(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"missing.nc: no such file"):
        read_netcdf(tmp_path / "missing.nc")
    text = tmp_path / "text.nc"
    text.write_text("time,value\n0,1\n")
    with pytest.raises(ValueError, match=r"text.nc: not a NetCDF file with one data variable"):
        read_netcdf(text)
