"""``tactilecal apply`` writes compressed float32 NetCDF, its values the calibration's."""

import numpy as np
import pytest

from tactilecal.calibration import calibrate, points_from_frames
from tactilecal.cli import main
from tactilecal.io import read_netcdf, read_tekscan, write_netcdf, write_tekscan
from tactilecal.simulate import deadweight_session, make_sensor, ramp_hold


def test_apply_writes_compressed_float32_of_the_float64_values(tmp_path):
    sensor = make_sensor("5051", seed=1)
    session = deadweight_session(sensor, n_patches=20, seed=3)
    cal = calibrate(points_from_frames(session.raw, session.load_N), method="power")
    cal.to_json(tmp_path / "cal.json")
    raw = ramp_hold(sensor, hold_s=0.5, ramp_s=0.5, frame_rate_hz=50.0, seed=1).raw
    write_tekscan(raw, tmp_path / "rec.csv")
    out = tmp_path / "rec.nc"
    assert main(["-q", "apply", str(tmp_path / "cal.json"), str(tmp_path / "rec.csv"),
                 "--out", str(out)]) == 0
    stored = read_netcdf(out)
    assert stored.dtype == np.float32 and stored.attrs["stored_dtype"] == "float32"
    exact = cal.apply(read_tekscan(tmp_path / "rec.csv"))
    loaded = exact.values > 0
    # float32 keeps 24 bits: each value within half a unit in the last place (6e-8)
    np.testing.assert_allclose(stored.values[loaded], exact.values[loaded], rtol=6e-8)
    assert np.array_equal(np.isnan(stored.values), np.isnan(exact.values))
    write_netcdf(exact, tmp_path / "plain.nc")
    ratio = (tmp_path / "plain.nc").stat().st_size / out.stat().st_size
    assert ratio > 4  # measured 11 on a 2400-frame ramp-and-hold (37 MB -> 3.3 MB)


def test_write_netcdf_refuses_other_dtypes(tmp_path):
    with pytest.raises(ValueError, match=r"dtype='int8'; expected 'float64' or 'float32'"):
        write_netcdf(_tiny(), tmp_path / "x.nc", dtype="int8")


def _tiny():
    import xarray as xr

    return xr.DataArray(np.zeros((1, 2, 2)), dims=("frame", "row", "col"),
                        attrs={"units": "raw"})
