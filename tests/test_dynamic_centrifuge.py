"""Centrifuge water-test helpers (Gillis 2013, 4.4.2) and filter transfer (4.5)."""

import numpy as np
import pytest
import xarray as xr

from tactilecal.dynamic import CorrectionFilter, compare_filters, row_mean, water_head_factor
from tactilecal.geotech import hydrostatic_pressure_kPa, prototype_frequency_hz, to_prototype
from tactilecal.simulate import sine_sweep


def _rec():
    rng = np.random.default_rng(0)
    data = rng.normal(10.0, 1.0, (50, 14, 14))
    data[:, 8, 3] = np.nan  # outside the shape
    data[:, 8, 5] = 0.0  # a non-working sensel reading 0
    return xr.DataArray(data, dims=("frame", "row", "col"),
                        coords={"row": np.arange(14), "col": np.arange(14),
                                "time": ("frame", np.arange(50) / 4000)},
                        attrs={"source": "water.csv"})


def test_row_mean_skips_nan_and_non_working():
    rec = _rec()
    working = np.ones((14, 14), bool)
    working[8, 5] = False
    out = row_mean(rec, 8, working=working)
    keep = [c for c in range(14) if c not in (3, 5)]
    np.testing.assert_allclose(out.values, rec.values[:, 8, keep].mean(axis=1))
    assert out.attrs["sensels_averaged"] == 12 and "time" in out.coords


def test_water_head_static_calibration_thesis_numbers():
    p = hydrostatic_pressure_kPa(0.070, 77.0)
    assert p == pytest.approx(1000 * 9.80665 * 77 * 0.070 / 1000)
    rec = row_mean(_rec(), 2)
    factor = water_head_factor(rec, 0.070, 77.0)
    assert float(rec.mean()) * factor == pytest.approx(p)


def test_prototype_scale():
    rec = xr.DataArray(np.arange(4.0), dims="time", coords={"time": np.arange(4) / 4000})
    proto = to_prototype(rec, 77.0)
    np.testing.assert_allclose(proto.time.values, rec.time.values * 77)
    np.testing.assert_array_equal(proto.values, rec.values)  # pressure scale 1
    assert prototype_frequency_hz(350.0, 70.0) == pytest.approx(5.0)


def test_filter_transfer_between_sensors():
    """Sensor 2 (A = 0.13) corrected with its own filter and with sensor 1's (A = 0.11)."""
    fast = {"step_hz": 5, "cycles_high": 10, "fs_sensor_hz": 1000.0,
            "fs_reference_hz": 1250.0, "sensor_noise_N": 0.1, "reference_noise_N": 0.05}
    sweep2 = sine_sweep(A=0.13, seed=3, **fast)
    own = CorrectionFilter.from_model(("log10", {"A": 0.13}), fs_hz=1000, band_hz=(1, 140))
    other = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000, band_hz=(1, 140))
    out = compare_filters({"own": own, "sensor 1": other}, sweep2.sensor, sweep2.reference)
    ev = out["evaluations"]  # Evaluation objects, scored at one clock
    assert ev["own"].rms_after_N < ev["sensor 1"].rms_after_N < ev["own"].rms_before_N
    assert ev["own"].lag_s == ev["sensor 1"].lag_s
    assert out["max_gain_difference"]["own vs sensor 1"] == pytest.approx(
        0.02 * np.log10(141), rel=1e-3)
    assert out["rms_difference_N"]["own vs sensor 1"] > 0


def test_centrifuge_errors():
    rec = _rec()
    with pytest.raises(ValueError, match="water.csv: row 20 not found"):
        row_mean(rec, 20)
    with pytest.raises(ValueError, match=r"working mask has shape \(2, 2\)"):
        row_mean(rec, 1, working=np.ones((2, 2)))
    all_nan = rec.copy()
    all_nan[:, 4, :] = np.nan
    with pytest.raises(ValueError, match="row 4 has no working, non-NaN sensel"):
        row_mean(all_nan, 4)
    with pytest.raises(ValueError, match="g_level is 0.0; expected finite values > 0"):
        water_head_factor(row_mean(rec, 2), 0.07, 0.0)
    with pytest.raises(ValueError, match="expected a loaded, non-empty stretch"):
        water_head_factor(row_mean(rec, 2), 0.07, 77, window_s=(5.0, 6.0))
    with pytest.raises(ValueError, match="g_level=-1; expected > 0"):
        to_prototype(row_mean(rec, 2), -1)
    with pytest.raises(ValueError, match="filters: 1 given; expected at least 2"):
        compare_filters({"a": None}, None, None)
