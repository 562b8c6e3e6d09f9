"""Published checks on real Tekscan exports (../shared/realdata)."""

import numpy as np
import pytest

from tactilecal.calibration import calibrate, header_calibration, load_points
from tactilecal.io import read_tekscan


def test_frasp01l_header_one_point_calibration(fscan_asf):
    """75.0001 kg x 9.80665 / (4798 x 25.8064e-6 m2) = 5.94 kPa per count, 1514.7 kPa at 255."""
    rec = read_tekscan(fscan_asf)
    cal = header_calibration(rec)
    kpa_per_count = cal.params["A"] / cal.sensel_area_mm2 * 1000
    assert kpa_per_count == pytest.approx(5.94, abs=0.005)
    assert cal.saturation_pressure_kPa == pytest.approx(rec.attrs["saturation_pressure_kPa"],
                                                        abs=0.05)
    # the exported kPa values are that law on integer raw readings, rounded to 1 kPa
    kpa = rec.values[np.isfinite(rec.values)]
    raw = np.rint(kpa / kpa_per_count)
    assert raw.max() <= 255 and np.abs(kpa - raw * kpa_per_count).max() <= 0.5


def test_frasp01r_header_one_point_calibration(fscan_right_asf):
    """75.0001 kg x 9.80665 / (13127 x 25.8064e-6 m2) = 2.171 kPa per count, 553.6 kPa at 255."""
    rec = read_tekscan(fscan_right_asf)
    cal = header_calibration(rec)
    assert cal.params["A"] / cal.sensel_area_mm2 * 1000 == pytest.approx(2.171, abs=0.0005)
    assert cal.saturation_pressure_kPa == pytest.approx(rec.attrs["saturation_pressure_kPa"],
                                                        abs=0.05)


def test_header_without_calibration(iscan_csv):
    with pytest.raises(ValueError, match="has no CALIBRATION_POINT_1 and no SCALE_FACTOR"):
        header_calibration(read_tekscan(iscan_csv))


def test_manifest_on_real_iscan_movie(iscan_csv, tmp_path):
    (tmp_path / "finger.csv").write_bytes(iscan_csv.read_bytes())
    manifest = tmp_path / "m.csv"
    manifest.write_text("file,frame,load_N\nfinger.csv,,10\nfinger.csv,100,5\n")
    blank, fixed = load_points(manifest)
    rec = read_tekscan(iscan_csv)
    assert blank.note.startswith("frame blank: chose frame")
    i = int(np.flatnonzero(rec["frame"].values == blank.frame)[0])
    assert blank.raw_sum == np.nansum(rec.values[i])
    assert fixed.frame == 100 and fixed.raw_sum == np.nansum(rec.sel(frame=100).values)
    assert fixed.sensel_area_mm2 == pytest.approx(1.6129)
    res = calibrate([blank], method="linear")
    assert res.predict_force(rec.values[i]) == pytest.approx(10.0)
