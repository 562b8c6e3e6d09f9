"""read_tekscan on the real exports and on small simulated files."""

import numpy as np
import pytest

from tactilecal.io import read_tekscan


def test_real_iscan_movie(iscan_csv):
    data = read_tekscan(iscan_csv)
    assert data.dims == ("frame", "row", "col")
    assert data.shape == (309, 28, 28) and data.dtype == np.float64
    assert data.attrs["units"] == "raw" and data.attrs["sensor_type"] == "6900"
    assert data.attrs["row_spacing_mm"] == pytest.approx(1.27)
    assert data.attrs["col_spacing_mm"] == pytest.approx(1.27)
    assert data.attrs["sensel_area_mm2"] == pytest.approx(1.6129)
    assert data.attrs["seconds_per_frame"] == 0.1 and data.attrs["noise_threshold"] == 3
    assert data.attrs["sensitivity"] == "S-21" and data.attrs["source"] == str(iscan_csv)
    assert data.attrs["tekscan_ROW_SPACING"] == "0.127 centimeters"
    assert data.frame.values.tolist() == list(range(1, 310))
    assert data.frame.dtype == np.int64 and data.row.dtype == np.int64
    assert data.time.values[[0, 1, -1]] == pytest.approx([0.0, 0.1, 31.1])
    # first frame header says Raw Sum 310; B cells are NaN and a fixed shape
    assert float(data.isel(frame=0).sum()) == 310
    assert np.isnan(data.values[:, 0, :]).all() and data.values[0, 2, 2] == 5
    assert np.array_equal(np.isnan(data.values[0]), np.isnan(data.values[-1]))


def test_real_fscan_movie(fscan_asf):
    data = read_tekscan(fscan_asf)
    assert data.shape == (205, 60, 21)
    assert data.attrs["units"] == "kPa" and data.attrs["sensor_type"] == "FSCAN"
    assert data.attrs["row_spacing_mm"] == 5.08 and data.attrs["col_spacing_mm"] == 5.08
    assert data.attrs["sensel_area_mm2"] == pytest.approx(25.8064)
    assert data.attrs["saturation_pressure_kPa"] == pytest.approx(1514.73)
    assert data.attrs["calibration_point_1_load"] == 75.0001
    assert data.attrs["calibration_point_1_load_unit"] == "kg"
    assert data.attrs["calibration_point_1_load_N"] == pytest.approx(75.0001 * 9.80665)
    assert data.attrs["calibration_point_1_raw_sum"] == 4798
    assert data.attrs["calibration_point_1_loaded_cells"] == 240
    assert data.attrs["calibration_mode_1"] == "Walk"
    assert data.attrs["tekscan_COMMENTS"] == "overground walk p10"
    # F-Scan frame lines carry no time: index x SECONDS_PER_FRAME
    assert data.time.values == pytest.approx(np.arange(205) * 0.032)
    # README: kPa values are multiples of 75.0001 kg x g / (4798 x sensel area) ~ 5.94 kPa
    k_kPa = 75.0001 * 9.80665 / (4798 * 25.8064e-6) / 1000
    counts = data.values[np.isfinite(data.values)] / k_kPa
    assert np.abs(counts - np.round(counts)).max() < 0.1 and counts.max() > 10


def test_attrs_serialise_to_netcdf(iscan_csv, fscan_asf, tmp_path):
    import importlib.util

    import xarray as xr

    # plain to_netcdf() picks h5netcdf, which needs h5py; without it, NetCDF3 via scipy
    usable = any(importlib.util.find_spec(m) for m in ("h5py", "netCDF4"))
    engine = None if usable else "scipy"
    for path in (iscan_csv, fscan_asf):
        data = read_tekscan(path)
        assert all(isinstance(v, str | int | float) for v in data.attrs.values())
        out = tmp_path / f"{path.stem}.nc"
        data.to_netcdf(out, engine=engine)
        back = xr.load_dataarray(out)
        assert back.identical(data)


def _write(tmp_path, text, name="x.csv", newline="\n"):
    path = tmp_path / name
    path.write_bytes(text.replace("\n", newline).encode())
    return path


TINY = ("DATA_TYPE MOVIE\nROWS 2\nCOLS 3\nROW_SPACING 2 mm\nCOL_SPACING 3 mm\nUNITS raw\n"
        "SECONDS_PER_FRAME 0.25\nASCII_DATA @@\n\n"
        "Frame 7, 1.5,, 1/1/2020 1:00:00.00PM,,,Raw Sum=,,8\n0,5,B\n1,2,0\n\n"
        "Frame 8, 2.0,, 1/1/2020 1:00:00.50PM,,,Raw Sum=,,255\n255,0,B\n0,0,0\n@@\n")


@pytest.mark.parametrize("newline", ["\n", "\r\n"])
def test_tiny_file_lf_and_crlf(tmp_path, newline):
    data = read_tekscan(_write(tmp_path, TINY, newline=newline))
    assert data.frame.values.tolist() == [7, 8]
    assert data.time.values.tolist() == [1.5, 2.0]
    assert data.attrs["sensel_area_mm2"] == 6.0  # derived from the spacings
    np.testing.assert_array_equal(
        data.values, [[[0, 5, np.nan], [1, 2, 0]], [[255, 0, np.nan], [0, 0, 0]]])


def test_single_frame_without_frame_line(tmp_path):
    text = "ROWS 2\nCOLS 2\nUNITS KPa\nSTART_FRAME 4\nASCII_DATA @@\n1.5,2\n3,B\n@@\n"
    data = read_tekscan(_write(tmp_path, text, name="single.txt"))
    assert data.shape == (1, 2, 2) and data.frame.values.tolist() == [4]
    assert data.attrs["units"] == "kPa" and data.time.values.tolist() == [0.0]


def test_spaces_after_commas(tmp_path):
    text = "ROWS 2\nCOLS 3\nUNITS raw\nASCII_DATA @@\nFrame 1, 0.5\n1, 2, B\n3, 4, 5\n@@\n"
    data = read_tekscan(_write(tmp_path, text))
    np.testing.assert_array_equal(data.values, [[[1, 2, np.nan], [3, 4, 5]]])


def test_top_level_lazy_exports():
    import tactilecal

    assert tactilecal.read_tekscan is read_tekscan
    assert tactilecal.io.read_tekscan is read_tekscan


def test_header_with_blank_lines_and_comment_like_lines(tmp_path):
    text = ("FILENAME F:\\data\\x.fsx\n\nROWS 2\nCOLS 2\n"
            "COMMENTS:\nFrame 9 was bad\n\"quoted, text\n\nUNITS raw\nASCII_DATA @@\n\n"
            "Frame 1\n1,2\nB,4\n@@\n")
    data = read_tekscan(_write(tmp_path, text))
    np.testing.assert_array_equal(data.values, [[[1, 2], [np.nan, 4]]])
    assert data.attrs["tekscan_COMMENTS"] == 'Frame 9 was bad\n"quoted, text'
