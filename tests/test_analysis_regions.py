"""Regions, profiles, window loads and high-pressure zones against hand-worked values."""

import numpy as np
import pytest
import xarray as xr

import tactilecal.analysis  # noqa: F401 - registers recording.tactile


def recording(p, unit="kPa", area=4.0, pitch=2.0):
    return xr.DataArray(
        np.asarray(p, dtype=float), dims=("frame", "row", "col"),
        coords={"time": ("frame", np.arange(len(p)) * 0.5)},
        attrs={"units": unit, "sensel_area_mm2": area, "row_spacing_mm": pitch,
               "col_spacing_mm": pitch, "source": "hand.csv"},
    )


def test_select_region_box_and_mask():
    rec = recording(np.arange(24.0).reshape(2, 3, 4))
    box = rec.tactile.select_region((1, 3, 0, 2))
    # frame 0 keeps 4, 5, 8, 9 -> 26 kPa x 4 mm2 x 1e-3 N
    assert float(box.tactile.force()[0]) == pytest.approx(26 * 4e-3)
    mask = np.zeros((3, 4), dtype=bool)
    mask[0, 3] = True
    assert float(rec.tactile.select_region(mask).tactile.peak()[1]) == 15.0
    with pytest.raises(ValueError, match=r"region box \(0, 4, 0, 2\) is empty or outside"):
        rec.tactile.select_region((0, 4, 0, 2))
    with pytest.raises(ValueError, match=r"region mask has dtype bool and shape \(2, 2\)"):
        rec.tactile.select_region(np.ones((2, 2), dtype=bool))


def test_profiles_skip_blank_and_nonworking_sensels():
    p = np.array([[[10.0, 20.0, 30.0], [0.0, 0.0, 60.0], [np.nan, 8.0, 4.0]]])
    rec = recording(p)
    np.testing.assert_allclose(rec.tactile.profile("row")[0], [20.0, 20.0, 6.0])
    dead = np.zeros((3, 3), dtype=bool)
    dead[1, 0] = dead[1, 1] = True  # working sensels reading 0 stay, dead ones go
    np.testing.assert_allclose(rec.tactile.profile("row", nonworking=dead)[0], [20.0, 60.0, 6.0])
    np.testing.assert_allclose(rec.tactile.profile("col")[0], [5.0, 28 / 3, 94 / 3])
    np.testing.assert_allclose(rec.tactile.profile("row")["row_mm"], [0.0, 2.0, 4.0])
    with pytest.raises(ValueError, match=r"nonworking mask has dtype int64 and shape \(3, 3\)"):
        rec.tactile.profile("row", nonworking=np.zeros((3, 3), dtype=np.int64))
    with pytest.raises(ValueError, match=r"profile dim is 'column'; expected 'row' or 'col'"):
        rec.tactile.profile("column")


def brute_force_windows(force, h, w):
    """Reference: every window summed with explicit loops."""
    best = []
    for frame in force:
        sums = [(frame[r:r + h, c:c + w].sum(), r, c)
                for r in range(frame.shape[0] - h + 1) for c in range(frame.shape[1] - w + 1)]
        best.append(max(sums))
    return np.array(best)


def test_max_window_load_matches_brute_force():
    rng = np.random.default_rng(42)
    p = rng.gamma(2.0, 30.0, size=(7, 11, 9))
    p[:, 0, 0] = np.nan
    rec = recording(p, area=1.6129, pitch=1.27)
    force = np.nan_to_num(p) * 1.6129e-3
    for h, w in [(1, 1), (3, 2), (4, 4), (11, 9)]:
        got = rec.tactile.max_window_load(window=(h, w))
        ref = brute_force_windows(force, h, w)
        np.testing.assert_allclose(got.force_N, ref[:, 0], rtol=1e-10)
        np.testing.assert_array_equal(got.row, ref[:, 1])
        np.testing.assert_array_equal(got.col, ref[:, 2])
        np.testing.assert_allclose(got.mean_kPa, ref[:, 0] / (h * w * 1.6129) * 1e3)
        assert got.attrs["window_area_mm2"] == pytest.approx(h * w * 1.6129)


def test_max_window_load_by_area_and_centre():
    p = np.zeros((1, 10, 10))
    p[0, 6:9, 2:5] = 100.0
    rec = recording(p, area=4.0, pitch=2.0)
    # 36 mm2 -> a 6 mm square -> 3 x 3 sensels of 2 mm
    out = rec.tactile.max_window_load(area_mm2=36.0)
    assert (out.attrs["window_rows"], out.attrs["window_cols"]) == (3, 3)
    assert float(out.force_N[0]) == pytest.approx(9 * 100 * 4e-3)
    assert (float(out.centre_row_mm[0]), float(out.centre_col_mm[0])) == (14.0, 6.0)
    with pytest.raises(ValueError, match="give exactly one of window"):
        rec.tactile.max_window_load(window=(2, 2), area_mm2=4.0)
    with pytest.raises(ValueError, match=r"window of 11 x 1 sensels does not fit the 10 x 10"):
        rec.tactile.max_window_load(window=(11, 1))
    with pytest.raises(ValueError, match=r"area_mm2 is -4.0; expected a positive area"):
        rec.tactile.max_window_load(area_mm2=-4.0)


def test_high_pressure_zones_hand_worked():
    p = np.zeros((2, 6, 6))
    p[0, 0:2, 0:2] = 200.0           # 4 sensels, 800 kPa in all
    p[0, 4, 4] = 500.0               # 1 sensel
    p[0, 5, 5] = 300.0               # touches (4, 4) by a corner only
    p[1, 2, 1:4] = [100.0, 400.0, 100.0]
    p[1, 0, 5] = 20.0                # below the level
    rec = recording(p, area=4.0, pitch=2.0)
    zones = rec.tactile.high_pressure_zones(50.0)
    assert zones[["frame", "zone", "n_sensels"]].values.tolist() == [
        [0, 1, 4], [0, 2, 1], [0, 3, 1], [1, 1, 3]]
    first = zones.iloc[0]
    assert first.force_N == pytest.approx(800 * 4e-3)
    assert (first.area_mm2, first.peak_kPa, first.mean_kPa) == (16.0, 200.0, 200.0)
    assert (first.cof_row_mm, first.cof_col_mm) == (1.0, 1.0)
    last = zones.iloc[3]
    assert last.time_s == 0.5 and last.cof_col_mm == pytest.approx(4.0)
    assert last.force_N == pytest.approx(600 * 4e-3)
    corner = rec.tactile.high_pressure_zones(50.0, connectivity=2)
    assert corner[corner.frame == 0].n_sensels.tolist() == [4, 2]
    assert len(rec.tactile.high_pressure_zones(50.0, min_sensels=2)) == 2
    labels = rec.tactile.label_zones(50.0)
    assert int(labels.max()) == 4 and labels.dims == ("frame", "row", "col")
    with pytest.raises(ValueError, match="connectivity is 3; expected 1"):
        rec.tactile.label_zones(50.0, connectivity=3)


def test_windows_and_profiles_on_dask_backed_recordings():
    rng = np.random.default_rng(3)
    rec = recording(rng.gamma(2.0, 30.0, size=(8, 9, 7)))
    lazy = rec.chunk({"frame": 3})
    win = lazy.tactile.max_window_load(window=(3, 2))
    assert win.force_N.chunks is not None  # stays lazy until computed
    xr.testing.assert_allclose(win.compute(), rec.tactile.max_window_load(window=(3, 2)))
    xr.testing.assert_allclose(lazy.tactile.profile("row").compute(), rec.tactile.profile("row"))
