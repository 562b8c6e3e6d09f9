"""The calibration a Tekscan header carries: I-Scan's 2-point power law (built files)."""

import numpy as np
import pytest

from tactilecal.calibration import header_calibration
from tactilecal.io import read_tekscan

# the header I-Scan 5.90I / 6.10I write after a 2-point (power-law) calibration
POWER_HEADER = """\
VERSION 6.10I
SENSOR_TYPE 9500
ROWS 2
COLS 3
ROW_SPACING 0.2 centimeters
COL_SPACING 0.2 centimeters
SENSEL_AREA 0.0399999 cm2
NOISE_THRESHOLD 3
SECONDS_PER_FRAME 0.01
SCALE_FACTOR 0.00660538
EXPONENT 1.25278
SATURATION_PRESSURE 6.83538 MPa
CALIBRATION_POINT_1 5 (Kgs) 2000 (Raw Sum) 20 (Number of Loaded Cells)
CALIBRATION_POINT_2 20 (Kgs) 6000 (Raw Sum) 30 (Number of Loaded Cells)
UNITS {units}
ASCII_DATA @@

Frame 1
0,4,B
100,200,255
@@
"""


def _write(tmp_path, units="MPa"):
    path = tmp_path / "power.csv"
    path.write_text(POWER_HEADER.format(units=units))
    return path


def test_power_law_header_gives_scale_times_raw_to_the_exponent(tmp_path):
    cal = header_calibration(read_tekscan(_write(tmp_path)))
    raw = np.arange(256.0)
    expected_kPa = 1000.0 * 0.00660538 * raw ** 1.25278  # MPa -> kPa
    pressure_kPa = cal.force_table() / cal.sensel_area_mm2 * 1000.0
    np.testing.assert_allclose(pressure_kPa, expected_kPa, rtol=1e-9)
    assert cal.method == "header-power-2pt"
    assert cal.sensel_area_mm2 == pytest.approx(3.99999)


def test_power_law_header_reaches_its_saturation_pressure_at_255(tmp_path):
    cal = header_calibration(read_tekscan(_write(tmp_path)))
    assert cal.saturation_pressure_kPa == pytest.approx(6835.38, rel=1e-3)


def test_power_law_header_has_no_points_to_score_and_says_so(tmp_path):
    cal = header_calibration(read_tekscan(_write(tmp_path)))
    assert cal.metrics["n"] == 0 and np.isnan(cal.metrics["r2"])


def test_power_law_header_without_a_pressure_unit_is_an_error(tmp_path):
    rec = read_tekscan(_write(tmp_path, units="MPa"))
    attrs = {**rec.attrs, "units": "raw"}
    del attrs["saturation_pressure_unit"]
    with pytest.raises(ValueError, match="power.csv: SCALE_FACTOR/EXPONENT without a pressure"):
        header_calibration(attrs)


@pytest.mark.parametrize("key", ["scale_factor", "exponent"])
@pytest.mark.parametrize("value", [0.0, -1.0, float("nan")])
def test_power_law_header_with_impossible_parameters_is_an_error(tmp_path, key, value):
    attrs = {**read_tekscan(_write(tmp_path)).attrs, key: value}
    with pytest.raises(ValueError, match=f"{key.upper()} of .*power.csv"):
        header_calibration(attrs)


def test_one_point_header_with_a_raw_sum_above_255_per_cell_is_an_error():
    attrs = {"source": "x.csv", "sensel_area_mm2": 4.0, "calibration_point_1_load_N": 10.0,
             "calibration_point_1_raw_sum": 256.0 * 3, "calibration_point_1_loaded_cells": 3}
    with pytest.raises(ValueError, match="x.csv: CALIBRATION_POINT_1 has a raw sum of 768"):
        header_calibration(attrs)
