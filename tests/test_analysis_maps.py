"""Per-frame force, area, centre of force and pressures on maps with a known truth."""

import numpy as np
import pytest
import xarray as xr

import tactilecal.analysis  # noqa: F401 - registers recording.tactile
from tactilecal.simulate import deadweight_session, make_sensor

ROW_MM, COL_MM, AREA_MM2 = 2.0, 3.0, 6.0


def moving_patch(unit="kPa", factor=1.0):
    """Frames 0..4: a 3 x 4 patch at rows k..k+2, cols 2..5, pressure 50 (k + 1) kPa.

    Frame 5 is unloaded. Two corner sensels are blank (NaN, outside the sensor).
    """
    p = np.zeros((6, 16, 12))
    for k in range(5):
        p[k, k:k + 3, 2:6] = 50.0 * (k + 1)
    p[:, 0, 11] = p[:, 15, 0] = np.nan
    return xr.DataArray(
        p * factor, dims=("frame", "row", "col"),
        coords={"frame": np.arange(1, 7), "time": ("frame", np.arange(6) * 0.01),
                "row": np.arange(16), "col": np.arange(12)},
        attrs={"units": unit, "sensel_area_mm2": AREA_MM2, "row_spacing_mm": ROW_MM,
               "col_spacing_mm": COL_MM, "source": "moving_patch"},
    )


def test_known_patch_summary():
    s = moving_patch().tactile.frame_summary()
    k = np.arange(5)
    # 12 loaded sensels of 6 mm2 at 50 (k + 1) kPa -> 50 (k + 1) * 72e-3 N
    np.testing.assert_allclose(s.force_N[:5], 50 * (k + 1) * 72e-3, rtol=1e-12)
    np.testing.assert_allclose(s.contact_area_mm2[:5], 72.0)
    np.testing.assert_allclose(s.cof_row_mm[:5], (k + 1) * ROW_MM, rtol=1e-12)
    np.testing.assert_allclose(s.cof_col_mm[:5], 3.5 * COL_MM, rtol=1e-12)
    np.testing.assert_allclose(s.peak_kPa[:5], 50 * (k + 1))
    np.testing.assert_allclose(s.mean_kPa[:5], 50 * (k + 1))
    # the unloaded frame: no force, no area, no centre, no mean
    assert s.force_N[5] == 0 and s.contact_area_mm2[5] == 0 and s.peak_kPa[5] == 0
    assert np.isnan(s.cof_row_mm[5]) and np.isnan(s.mean_kPa[5])
    assert list(s.data_vars) == ["force_N", "contact_area_mm2", "cof_row_mm", "cof_col_mm",
                                 "peak_kPa", "mean_kPa"]
    np.testing.assert_allclose(s["time"], np.arange(6) * 0.01)
    assert s.attrs["source"] == "moving_patch"


def test_threshold_changes_area_and_mean():
    rec = moving_patch()
    rec[0, 10, 10] = 5.0  # a lone light sensel in frame 1
    assert float(rec.tactile.area()[0]) == 13 * AREA_MM2
    assert float(rec.tactile.area(threshold_kPa=10.0)[0]) == 12 * AREA_MM2
    assert float(rec.tactile.mean_pressure()[0]) == pytest.approx((12 * 50 + 5) / 13)
    assert float(rec.tactile.mean_pressure(threshold_kPa=10.0)[0]) == 50.0


@pytest.mark.parametrize(("unit", "per_kPa"), [
    ("MPa", 1e-3), ("psi", 1 / 6.894757293168361), ("PSI", 1 / 6.894757293168361),
    ("N", AREA_MM2 * 1e-3), ("kgf", AREA_MM2 * 1e-3 / 9.80665),
])
def test_units_give_the_same_numbers(unit, per_kPa):
    ref = moving_patch().tactile.frame_summary()
    other = moving_patch(unit, per_kPa).tactile.frame_summary()
    for name in ref.data_vars:
        np.testing.assert_allclose(other[name], ref[name], rtol=1e-12, equal_nan=True)


def test_dask_backed_recording_matches_numpy():
    rec = moving_patch()
    lazy = rec.chunk({"frame": 2}).tactile.frame_summary()
    assert lazy.force_N.chunks is not None  # still lazy
    xr.testing.assert_allclose(lazy.compute(), rec.tactile.frame_summary())


class SimulatedCalibration:
    """The simulator's own law, F = A raw^b per sensel: a calibration with known truth."""

    def __init__(self, sensor):
        self.sensor = sensor

    def apply(self, recording, units="kPa"):
        out = recording.copy(data=self.sensor.force_of_raw(recording.values))
        out.attrs = {**recording.attrs, "units": "N"}
        return out.tactile.pressure_map() if units == "kPa" else out


def test_simulated_deadweight_forces_recovered():
    sensor = make_sensor("5051", gain_spread=0.0, read_noise=0.0, n_dead=0, seed=1)
    session = deadweight_session(sensor, n_patches=12, seed=3)
    truth = session.raw.copy(data=session.force_N)
    truth.attrs = {**session.raw.attrs, "units": "N"}
    # the true force maps sum to the applied loads
    np.testing.assert_allclose(truth.tactile.force(), session.load_N, rtol=1e-9)
    # through the raw readings and the sensor's own law: only 8-bit rounding and the
    # noise threshold remain, stated tolerance 3 %
    got = session.raw.tactile.force(calibration=SimulatedCalibration(sensor))
    np.testing.assert_allclose(got, session.load_N, rtol=0.03)
    # centre of force: raw path within one sensel pitch of the truth
    c_true = truth.tactile.centre()
    c_raw = session.raw.tactile.centre(calibration=SimulatedCalibration(sensor))
    assert float(np.abs(c_true.cof_row_mm - c_raw.cof_row_mm).max()) < sensor.row_spacing_mm


def test_contact_area_of_raw_without_calibration():
    rec = moving_patch().fillna(0.0)
    rec.attrs["units"] = "raw"
    np.testing.assert_allclose(rec.tactile.area()[:5], 72.0)


def test_errors():
    rec = moving_patch()
    raw = rec.copy()
    raw.attrs = {**rec.attrs, "units": "raw"}
    with pytest.raises(ValueError, match="moving_patch: units are 'raw'; give a calibration"):
        raw.tactile.force()
    with pytest.raises(ValueError, match="threshold_kPa is 5.0 but the recording is raw"):
        raw.tactile.area(threshold_kPa=5.0)
    with pytest.raises(ValueError, match=r"threshold_kPa is -1.0; expected a finite value >= 0"):
        rec.tactile.area(threshold_kPa=-1.0)
    no_area = rec.copy()
    no_area.attrs = {"units": "kPa", "source": "x.csv"}
    with pytest.raises(ValueError, match="x.csv: attribute 'sensel_area_mm2' is None"):
        no_area.tactile.force()
    with pytest.raises(ValueError, match="x.csv: attribute 'row_spacing_mm' is None"):
        no_area.assign_attrs(units="N").tactile.centre()
    with pytest.raises(ValueError, match=r"dims \('row', 'col', 'frame'\); expected"):
        rec.transpose("row", "col", "frame").tactile.force()
    no_unit = rec.copy()
    no_unit.attrs = {"source": "y.asf"}
    with pytest.raises(ValueError, match="y.asf: attribute 'units' is missing"):
        no_unit.tactile.peak()
    mm = rec.copy()
    mm.attrs = {**rec.attrs, "units": "mm"}
    with pytest.raises(ValueError, match="units 'mm' are a length; expected raw"):
        mm.tactile.peak()


def test_calibration_given_as_json_path(tmp_path):
    from tactilecal.calibration import calibrate, points_from_frames

    sensor = make_sensor("5051", gain_spread=0.0, read_noise=0.0, n_dead=0, seed=1)
    session = deadweight_session(sensor, n_patches=20, seed=3)
    result = calibrate(points_from_frames(session.raw, session.load_N), method="power")
    result.to_json(tmp_path / "cal.json")
    by_path = session.raw.tactile.force(calibration=tmp_path / "cal.json")
    np.testing.assert_allclose(by_path, result.predict_force(session.raw.values), rtol=1e-12)
    np.testing.assert_allclose(by_path, session.load_N, rtol=0.05)  # a fitted law, 5 %


def test_summary_matches_the_single_functions():
    rng = np.random.default_rng(5)
    rec = moving_patch().copy(data=rng.gamma(1.0, 20.0, size=(6, 16, 12)))
    rec[:, 3, 4] = np.nan
    rec[2] = 0.0  # an unloaded frame
    s = rec.tactile.frame_summary(threshold_kPa=10.0)
    single = {
        "force_N": rec.tactile.force(),
        "contact_area_mm2": rec.tactile.area(threshold_kPa=10.0),
        **rec.tactile.centre().data_vars,
        "peak_kPa": rec.tactile.peak(),
        "mean_kPa": rec.tactile.mean_pressure(threshold_kPa=10.0),
    }
    for name, values in single.items():
        np.testing.assert_allclose(s[name], values, rtol=1e-12, equal_nan=True, err_msg=name)
    assert np.isnan(s.mean_kPa[2]) and np.isnan(s.cof_row_mm[2])
    with pytest.raises(ValueError, match=r"threshold_kPa is -2.0; expected a finite value >= 0"):
        rec.tactile.frame_summary(threshold_kPa=-2.0)


def test_centre_of_force_leaves_out_frames_below_a_minimum_force():
    rec = moving_patch()
    force = rec.tactile.force().values  # 3.6, 7.2, 10.8, 14.4, 18.0, 0 N
    cof = rec.tactile.centre(min_force_N=10.0)
    kept = np.isfinite(cof.cof_row_mm.values)
    np.testing.assert_array_equal(kept, force > 10.0)
    np.testing.assert_allclose(cof.cof_row_mm[kept], (np.arange(5)[force[:5] > 10] + 1) * ROW_MM)
    s = rec.tactile.frame_summary(cof_min_force_N=10.0)
    np.testing.assert_array_equal(np.isfinite(s.cof_col_mm.values), force > 10.0)
    assert s.attrs["cof_min_force_N"] == 10.0
    with pytest.raises(ValueError, match=r"min_force_N is -1.0; expected a finite value >= 0"):
        rec.tactile.centre(min_force_N=-1.0)
    with pytest.raises(ValueError, match=r"cof_min_force_N is nan; expected a finite value"):
        rec.tactile.frame_summary(cof_min_force_N=float("nan"))


def test_cof_path_and_peak_map_figures():
    rec = moving_patch()
    s = rec.tactile.frame_summary()
    # default threshold 5 % of the 18 N peak: the 5 loaded frames of 6
    ax = rec.tactile.plot_cof_path(summary=s)
    assert ax.get_title() == "5 of 6 frames with force >= 0.9 N"
    assert rec.tactile.plot_cof_path(summary=s, min_force_N=10.0).get_title() == (
        "3 of 6 frames with force >= 10 N")
    peak = rec.tactile.plot_pressure_map()
    shown = peak.images[0].get_array()
    # row r is loaded in frames k = r-2..r at 50 (k + 1) kPa: its peak is 50 (min(r, 4) + 1)
    expected = 50.0 * (np.minimum(np.arange(7), 4) + 1)
    np.testing.assert_allclose(shown[:7, 2:6], np.repeat(expected[:, None], 4, axis=1))
    assert np.nanmax(shown[7:]) == 0.0 and peak.get_title() == "peak over all frames"
    raw = rec.fillna(0.0).clip(max=255).assign_attrs(units="raw")
    raw_map = raw.tactile.plot_pressure_map()
    assert raw_map.images[0].colorbar.ax.get_ylabel() == "raw reading"
    # without a summary the accessor computes it: the same path as from the given one
    np.testing.assert_array_equal(rec.tactile.plot_cof_path().collections[0].get_offsets(),
                                  ax.collections[0].get_offsets())
    forces = rec.tactile.plot_force_time().lines[0].get_ydata()
    np.testing.assert_allclose(forces, s["force_N"].values)
