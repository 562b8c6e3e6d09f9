"""``tactilecal analyze``: table, JSON, CSV, exit codes."""

import json
import re

import numpy as np
import pandas as pd
import pytest

from tactilecal.cli import main


def test_analyze_real_fscan_text_and_csv(fscan_asf, tmp_path, capsys):
    out = tmp_path / "summary.csv"
    assert main(["-q", "analyze", str(fscan_asf), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert re.search(r"peak_force_N +924.359\n", text) and re.search(r"peak_force_frame +9\n", text)
    assert re.search(r"saturated_frames +0\n", text)
    table = pd.read_csv(out)
    assert list(table.columns) == ["frame", "time_s", "force_N", "contact_area_mm2",
                                   "cof_row_mm", "cof_col_mm", "peak_kPa", "mean_kPa",
                                   "saturated_sensels"]
    assert len(table) == 205 and table.frame.iloc[0] == 1
    np.testing.assert_allclose(table.time_s.iloc[-1], 204 * 0.032)


def test_analyze_json_with_threshold(fscan_asf, capsys):
    assert main(["-q", "analyze", str(fscan_asf), "--json", "--threshold-kpa", "50"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["threshold_kPa"] == 50.0 and len(data["frames"]) == 205
    full = data["overview"]
    assert full["peak_force_N"] == pytest.approx(924.359, abs=1e-3)
    # a threshold removes light sensels from the area but never the force
    assert full["max_contact_area_mm2"] < 9909.66


def test_analyze_exit_codes(iscan_csv, tmp_path, capsys):
    assert main(["-q", "analyze", str(iscan_csv)]) == 1
    assert "units are 'raw'; give a calibration" in capsys.readouterr().err
    assert main(["-q", "analyze", str(tmp_path / "none.csv")]) == 1
    assert "does not exist" in capsys.readouterr().err
    with pytest.raises(SystemExit) as usage:
        main(["analyze"])
    assert usage.value.code == 2


def test_analyze_cal_on_a_calibrated_recording_is_an_error(fscan_asf, tmp_path, capsys):
    """Issue 31: the calibration was ignored silently (the F-Scan export is in kPa)."""
    from tactilecal.calibration import calibrate, points_from_frames

    frames = np.zeros((3, 4, 4))
    for k, level in enumerate((20, 60, 120)):
        frames[k, 1:3, 1:3] = level
    cal = tmp_path / "cal.json"
    calibrate(points_from_frames(frames, [4 * 0.0035 * v ** 1.2 for v in (20, 60, 120)],
                                 sensel_area_mm2=1.6129), method="power").to_json(cal)
    assert main(["-q", "analyze", str(fscan_asf), "--cal", str(cal)]) == 1
    err = capsys.readouterr().err
    assert "footPress_FrasP01L.asf: units are 'kPa', already calibrated; expected a raw " \
           "recording with a calibration" in err and len(err.strip().splitlines()) == 1
