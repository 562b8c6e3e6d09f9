"""open_recording: one sniffer for every recording format; its users read through it."""

import numpy as np
import pytest
import xarray as xr

from tactilecal.io import (
    convert,
    open_recording,
    recording_format,
    write_netcdf,
    write_tekscan,
)

VALUES = np.arange(24.0).reshape(2, 3, 4)


@pytest.fixture
def recording():
    return xr.DataArray(VALUES.copy(), dims=("frame", "row", "col"),
                        coords={"frame": [1, 2], "time": ("frame", [0.0, 0.01])},
                        attrs={"units": "raw", "sensel_area_mm2": 1.6129})


@pytest.fixture
def files(tmp_path, recording):
    """The same two frames as a Tekscan export (.txt), NetCDF (.nc and no suffix), Zarr."""
    out = {"tekscan": tmp_path / "rec.txt", "netcdf": tmp_path / "rec.nc"}
    write_tekscan(recording, out["tekscan"])
    write_netcdf(recording, out["netcdf"])
    out["netcdf_nosuffix"] = tmp_path / "rec_netcdf"
    out["netcdf_nosuffix"].write_bytes(out["netcdf"].read_bytes())
    out["zarr"] = tmp_path / "rec.zarr"
    convert(out["tekscan"], out["zarr"], chunks=1)
    return out


@pytest.mark.parametrize("name, kind", [("tekscan", "tekscan"), ("netcdf", "netcdf"),
                                        ("netcdf_nosuffix", "netcdf"), ("zarr", "zarr")])
def test_every_format_is_sniffed_and_read(files, name, kind):
    assert recording_format(files[name]) == kind
    data = open_recording(files[name])
    assert data.dims == ("frame", "row", "col")
    np.testing.assert_array_equal(data.values, VALUES)  # integers: exact in every format
    assert data.attrs["units"] == "raw"


def test_zarr_is_lazy_and_chunks_give_lazy_netcdf(files):
    zarr = open_recording(files["zarr"])
    assert zarr.chunks is not None and zarr.chunks[0] == (1, 1)  # the store's own blocks
    lazy = open_recording(files["netcdf"], chunks=1)
    assert lazy.chunks is not None and lazy.chunks[0] == (1, 1)
    np.testing.assert_array_equal(lazy.values, VALUES)
    assert open_recording(files["netcdf"]).chunks is None  # default: in memory
    tek = open_recording(files["tekscan"], chunks=1)
    assert tek.chunks[0] == (1, 1)


def test_unknown_format_is_one_line_naming_the_file(tmp_path):
    load = tmp_path / "load.csv"
    load.write_text("time_s,load_N\n0,1\n0.1,2\n")
    assert recording_format(load) is None
    with pytest.raises(ValueError, match=r"load\.csv: not a recording: no 'ASCII_DATA' line"):
        open_recording(load)
    folder = tmp_path / "plain"
    folder.mkdir()
    assert recording_format(folder) is None
    with pytest.raises(ValueError, match=r"plain is a folder without Zarr metadata") as info:
        open_recording(folder)
    assert "\n" not in str(info.value)


def test_missing_file_and_bad_chunks(tmp_path, files):
    with pytest.raises(FileNotFoundError, match=r"nothing\.csv: no such file"):
        open_recording(tmp_path / "nothing.csv")
    with pytest.raises(TypeError, match="chunks of type str; expected an integer"):
        open_recording(files["tekscan"], chunks="10")


def test_broken_zarr_store_is_one_line(tmp_path):
    store = tmp_path / "bad.zarr"
    store.mkdir()
    (store / ".zgroup").write_text("not json")
    with pytest.raises(ValueError, match=r"bad\.zarr: not a zarr store with one data variable"):
        open_recording(store)


def test_report_and_dynamic_read_through_it(files):
    from tactilecal.dynamic import read_record
    from tactilecal.report import load_input

    for name in ("tekscan", "netcdf_nosuffix", "zarr"):
        kind, data, _ = load_input(files[name])
        assert kind == "recording"
        np.testing.assert_array_equal(data.values, VALUES)
    total = read_record(files["zarr"])
    np.testing.assert_array_equal(total.values, VALUES.sum(axis=(1, 2)))


def test_cli_apply_reads_netcdf_without_suffix(files, tmp_path, capsys):
    from tactilecal.calibration import calibrate, points_from_frames
    from tactilecal.cli import main

    frames = np.stack([np.full((3, 4), r) for r in (10.0, 20.0, 40.0, 80.0)])
    loads = 12 * 0.0035 * np.array([10.0, 20.0, 40.0, 80.0]) ** 1.16
    cal = calibrate(points_from_frames(frames, loads, sensel_area_mm2=1.6129),
                    method="power")
    cal.to_json(tmp_path / "cal.json")
    for name in ("netcdf_nosuffix", "tekscan"):
        out = tmp_path / f"{name}.nc"
        assert main(["-q", "apply", str(tmp_path / "cal.json"), str(files[name]),
                     "--out", str(out)]) == 0
        expected = cal.apply(open_recording(files["tekscan"]))
        # apply stores float32: the float64 values rounded to 24 bits, exactly
        np.testing.assert_allclose(open_recording(out).values,
                                   expected.values.astype(np.float32), rtol=0)


def test_a_device_is_no_recording_and_no_missing_file():
    """A manifest naming /dev/null used to say "/dev/null: no such file" (issue 31)."""
    with pytest.raises(ValueError, match=r"/dev/null is not a regular file \(a device, pipe or "
                                         r"socket\); expected a recording"):
        open_recording("/dev/null")


def test_a_utf16_export_is_sniffed_and_read(tmp_path, files):
    path = tmp_path / "utf16.csv"
    path.write_bytes(files["tekscan"].read_text().encode("utf-16"))
    assert recording_format(path) == "tekscan"
    assert open_recording(path).drop_attrs().identical(
        open_recording(files["tekscan"]).drop_attrs())
