"""describe, frame_table, overview: the library behind ``tactilecal info`` and ``analyze``."""

import numpy as np
import pytest
import xarray as xr

from tactilecal import analysis


def _rec(values, **attrs):
    n = values.shape[0]
    return xr.DataArray(values, dims=("frame", "row", "col"),
                        coords={"frame": np.arange(3, 3 + n),
                                "time": ("frame", np.arange(n) * 0.5)},
                        attrs={"source": "x.csv", **attrs})


def test_describe_counts_blank_never_loaded_and_saturated():
    raw = np.zeros((4, 3, 5))
    raw[:, 0, 0] = np.nan                   # blank: outside the sensor
    raw[1, 1, 1], raw[3, 2, 4] = 255, 255   # frames 4 and 6 saturate
    raw[2, 1, 2] = 40                       # 15 - 1 blank - 3 loaded = 11 never loaded
    d = _rec(raw, units="raw").tactile.describe()
    assert (d["rows"], d["cols"], d["sensels"], d["frames"]) == (3, 5, 15, 4)
    assert (d["first_frame"], d["last_frame"], d["duration_s"]) == (3, 6, 1.5)
    assert (d["blank_sensels"], d["never_loaded_sensels"]) == (1, 11)
    assert d["max_raw"] == 255.0 and d["max_raw_source"] == "file"
    assert d["saturated_frames"] == 2 and d["saturated_frame_numbers"] == [4, 6]
    assert d["calibration"] == {}


def test_describe_inverts_the_header_power_law():
    scale, exponent = 0.9, 1.164  # p = scale * raw ** exponent (kPa)
    p = np.zeros((2, 2, 2))
    p[1, 0, 0] = scale * 200.0 ** exponent
    d = _rec(p, units="kPa", scale_factor=scale, exponent=exponent,
             sensel_area_mm2=1.6129).tactile.describe()
    assert d["max_raw"] == 200  # a whole reading, through the header's own calibration
    assert d["max_raw_source"] == "inverted header calibration (header-power-2pt)"
    assert d["calibration"] == {"scale_factor": scale, "exponent": exponent}
    no_area = _rec(p, units="kPa", scale_factor=scale, exponent=exponent).tactile.describe()
    assert no_area["max_raw"] is None  # a header without SENSEL_AREA states no law per sensel
    assert d["saturated_frames"] is None  # no saturation pressure: unknown


@pytest.mark.parametrize("largest", [-5.0, 1e308])
def test_a_largest_value_no_reading_gives_has_no_raw_reading(largest):
    """Below 0 (an offset removed), or beyond any finite reading of FrasP01L's 1-point
    calibration (75 kg over a raw sum of 4798): None, not a crash."""
    p = np.full((2, 2, 2), -10.0)
    p[1, 0, 0] = largest
    d = _rec(p, units="kPa", sensel_area_mm2=25.8064, calibration_point_1_load_N=735.5,
             calibration_point_1_raw_sum=4798.0).tactile.describe()
    assert d["max_value"] == largest
    assert d["max_raw"] is None and d["max_raw_source"] is None


def test_frame_table_and_overview_on_a_known_patch():
    p = np.zeros((3, 6, 6))
    for k in range(3):  # 2 x 2 patch at 100 (k + 1) kPa; 4 mm2 sensels
        p[k, k:k + 2, 1:3] = 100.0 * (k + 1)
    rec = _rec(p, units="kPa", sensel_area_mm2=4.0, row_spacing_mm=2.0, col_spacing_mm=2.0)
    table = rec.tactile.frame_table()
    assert list(table.columns[:2]) == ["frame", "time_s"]
    assert tuple(table.columns[2:8]) == ("force_N", "contact_area_mm2", "cof_row_mm", "cof_col_mm",
                                         "peak_kPa", "mean_kPa")
    # 4 sensels x 4 mm2 x 100 (k + 1) kPa x 1e-3 N per kPa mm2
    np.testing.assert_allclose(table["force_N"], 1.6 * np.arange(1, 4), rtol=1e-12)
    head = analysis.overview(table, source="x.csv")
    # a summary already computed gives the same headline numbers (the report passes its own)
    assert analysis.overview(rec.tactile.frame_summary(), source="x.csv") == head
    assert head["file"] == "x.csv" and head["frames"] == 3
    assert (head["peak_force_frame"], head["peak_force_time_s"]) == (5, 1.0)
    assert head["peak_force_N"] == pytest.approx(4.8, rel=1e-12)
    assert head["mean_force_N"] == pytest.approx(3.2, rel=1e-12)
    assert head["max_contact_area_mm2"] == pytest.approx(16.0)
    assert head["max_pressure_kPa"] == pytest.approx(300.0)
    assert head["saturated_frames"] is None and head["peak_force_is_lower_bound"] is None


def test_frame_table_of_a_raw_recording_needs_a_calibration():
    with pytest.raises(ValueError, match="x.csv: units are 'raw'; give a calibration"):
        _rec(np.zeros((1, 2, 2)), units="raw").tactile.frame_table()


def test_one_saturated_frame_makes_the_peaks_lower_bounds():
    # the first frame carries the largest force; the second has one sensel at the saturation
    # pressure: its true force is unknown above what it reads, so the peak is a lower bound
    p = np.zeros((2, 3, 3))
    p[0] = 400.0
    p[1, 1, 1] = 1000.0
    geometry = {"sensel_area_mm2": 1.0, "row_spacing_mm": 1.0, "col_spacing_mm": 1.0}
    rec = _rec(p, units="kPa", saturation_pressure_kPa=1000.0, **geometry)
    head = analysis.overview(rec.tactile.frame_table())
    assert head["peak_force_frame"] == 3 and head["saturated_frames"] == 1  # frames 3, 4
    assert head["peak_force_is_lower_bound"] is True
    assert head["max_pressure_is_lower_bound"] is True
    below = _rec(p * 0.99, units="kPa", saturation_pressure_kPa=1000.0, **geometry)
    head = analysis.overview(below.tactile.frame_table())
    assert head["saturated_frames"] == 0 and head["peak_force_is_lower_bound"] is False
